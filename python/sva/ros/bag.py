"""MCAP files of ROS 2 messages (mcap, mcap-ros2-support: no ROS installation needed)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Optional, Sequence, Union

from .. import _sva_core as _core
from .._files import atomic_output
from . import TOPICS, ObjectMesh, session_messages
from .msgdefs import definition

PathLike = Union[str, "os.PathLike[str]"]


def _mcap_ros2():
    try:
        from mcap.reader import make_reader
        from mcap_ros2.decoder import DecoderFactory
        from mcap_ros2.writer import Writer
    except ImportError as e:  # an optional dependency of the package
        raise _core.Error("sva.ros: writing and reading bags needs the Python packages mcap and mcap-ros2-support "
                          "(pip install 'sva[ros]', or bash scripts/setup.sh for the development environment)") from e
    return Writer, make_reader, DecoderFactory


def export_session(recognizer: "_core.Recognizer", readings: Sequence["_core.Reading"], out: PathLike, *,
                   frame_id: str = "world", start_ns: int = 0, period_ns: int = 500_000_000, top_k: int = 5,
                   detection_id: str = "", meshes: Optional[Sequence[Optional[ObjectMesh]]] = None,
                   stamps_ns: Optional[Sequence[int]] = None) -> dict:
    """Replays ``readings`` through ``recognizer`` and writes every update's messages (sva.ros.session_messages)
    to the MCAP file ``out``, which appears whole or not at all. Returns counts: messages per topic, readings and
    the file's bytes."""
    Writer, _, _ = _mcap_ros2()
    out = Path(out)
    if not out.parent.is_dir():
        raise _core.Error(f"{out}: cannot write: the folder {out.parent} does not exist")
    counts = {topic: 0 for topic in TOPICS}
    # Whole or not at all, with the mode of the user's other files (a bag is meant to be shared: not mkstemp's 0600).
    with atomic_output(out) as f:
        writer = Writer(f)
        schemas = {topic: writer.register_msgdef(kind, definition(kind))
                   for topic, kind in TOPICS.items()}
        for topic, stamp, message in session_messages(recognizer, readings, frame_id=frame_id,
                                                      start_ns=start_ns, period_ns=period_ns, top_k=top_k,
                                                      detection_id=detection_id, meshes=meshes,
                                                      stamps_ns=stamps_ns):
            writer.write_message(topic, schemas[topic], message, log_time=stamp, publish_time=stamp,
                                 sequence=counts[topic])
            counts[topic] += 1
        writer.finish()
    return {"messages": {t: c for t, c in counts.items() if c}, "readings": len(readings),
            "bytes": out.stat().st_size}


def read_bag(path: PathLike, topics: Optional[Sequence[str]] = None) -> list[tuple[str, int, Any]]:
    """Every message of an MCAP file of ROS 2 messages, decoded: ``(topic, log_time_ns, message)`` in log time
    order (the messages are objects with the fields as attributes)."""
    _, make_reader, DecoderFactory = _mcap_ros2()
    if not Path(path).is_file():
        raise _core.Error(f"{path}: no such bag")
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        return [(channel.topic, message.log_time, decoded)
                for _, channel, message, decoded in reader.iter_decoded_messages(topics=topics)]
