"""Batch recognition of a sessions file (docs/batch-format.md) on this machine: what ``sva recognize`` does.

The file is split into shards of consecutive sessions (whole lines); each shard is recognised by the engine
(``_recognize_shard_in_flight`` here, ``BatchRecognizer._recognize_shard`` on a Dask worker) and yields the result lines of its sessions, so the results file is the
shards' lines concatenated in input order. :mod:`sva.distributed` runs the same shards on a Dask cluster.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Optional, Union

from ._files import atomic_output
from ._sva_core import Engine, Error, Map, _recognize_shard_in_flight

PathLike = Union[str, "os.PathLike[str]"]


@dataclass(frozen=True)
class Shard:
    """Whole lines of a sessions file: ``text`` starts at line ``first_line`` (from 1) and is preceded in the
    file by ``first_session`` sessions; it holds ``sessions`` sessions."""

    text: bytes
    first_line: int
    first_session: int
    sessions: int


def _is_session(line: bytes) -> bool:
    # As the engine's reader: a line of only spaces, tabs and carriage returns is skipped.
    return line.strip(b" \t\r") != b""


class SessionsFile:
    """A sessions file's lines, cut into shards on line boundaries only: every field is checked by the engine when
    a shard is recognised, and errors name FILE:LINE as for the whole file."""

    def __init__(self, file: PathLike):
        self.name = os.fspath(file)
        try:
            data = Path(file).read_bytes()
        except OSError:
            raise Error(f"{self.name}: cannot read the sessions file") from None
        self._lines = data.split(b"\n")
        if self._lines and self._lines[-1] == b"":
            self._lines.pop()  # the newline that ends the last line
        self._starts = [i for i, line in enumerate(self._lines) if _is_session(line)]
        if not self._starts:
            raise Error(f"{self.name}: no sessions (empty file)")

    @property
    def sessions(self) -> int:
        return len(self._starts)

    def shards(self, sessions_per_shard: int) -> list[Shard]:
        """Consecutive shards of ``sessions_per_shard`` sessions (the last may have fewer), in file order."""
        if sessions_per_shard < 1:
            raise Error(f"sessions per shard must be >= 1, got {sessions_per_shard}")
        out = []
        for first in range(0, self.sessions, sessions_per_shard):
            last = min(first + sessions_per_shard, self.sessions)
            begin = 0 if first == 0 else self._starts[first]
            end = self._starts[last] if last < self.sessions else len(self._lines)
            text = b"\n".join(self._lines[begin:end]) + b"\n"
            out.append(Shard(text, begin + 1, first, last - first))
        return out


def check_writable(file: PathLike) -> None:
    """Refuses an output path whose folder is missing before any recognition runs (as the commands do)."""
    parent = Path(file).parent
    if not parent.is_dir():
        raise Error(f"{os.fspath(file)}: cannot write: folder {os.fspath(parent)} does not exist")


def write_atomically(file: PathLike, chunks: Iterator[bytes]) -> None:
    """Writes the chunks to a temporary file beside ``file`` and renames it into place (no partial results file
    that looks complete, as the engine writes its files), with the mode the user's umask gives (sva._files)."""
    with atomic_output(file) as out:
        for chunk in chunks:
            out.write(chunk)


def recognize_batch(
    map: Union[Map, PathLike],
    sessions: PathLike,
    out: Optional[PathLike] = None,
    *,
    sessions_per_submission: Optional[int] = None,
    in_flight: Optional[int] = None,
    top: int = 3,
    depth: str = "full",
    **options,
) -> list[str]:
    """Recognises every session of a sessions file, as ``sva recognize --batch SESSIONS --out OUT`` does: the
    results (one JSON line per session, in input order; docs/batch-format.md) are returned as strings and, with
    ``out``, written there (byte for byte the command's file). ``options`` are the Recognizer's (backend="auto",
    refine_pose, vulkan_device, ...). ``sessions_per_submission`` defaults to the engine's
    (``Engine.sessions_per_submission``: on a GPU as many as half its memory holds, 64 on the CPU), and
    ``in_flight``, the groups recognised at once (one recognizer each, so that the host prepares one group's update
    while the device runs another's), to the engine's (``Engine.submissions_in_flight``: 2 on a GPU, 1 on the CPU).
    The results do not depend on either. ``depth``: each session's estimate at its end, "full" or "light" (the
    belief's answer without the host's fits, as ``--estimate light``; docs/recognition.md)."""
    if not isinstance(map, Map):
        map = Map.load(map)
    if sessions_per_submission is not None and sessions_per_submission < 1:
        raise Error(f"sessions_per_submission must be >= 1, got {sessions_per_submission}")
    if in_flight is not None and in_flight < 1:
        raise Error(f"in_flight must be >= 1, got {in_flight}")
    if out is not None:
        check_writable(out)
    file = SessionsFile(sessions)
    engine = Engine(map, options.get("backend", "auto"), options.get("vulkan_device", ""))
    if sessions_per_submission is None:
        sessions_per_submission = engine.sessions_per_submission(**options)
    if in_flight is None:
        in_flight = engine.submissions_in_flight()
    (whole,) = file.shards(file.sessions)
    results = _recognize_shard_in_flight(
        engine, whole.text, file.name, whole.first_line, whole.first_session, top, depth, whole.sessions,
        sessions_per_submission, in_flight, **options
    )
    if out is not None:
        write_atomically(out, iter([results]))
    return results.decode("utf-8").splitlines()


@dataclass(frozen=True)
class Session:
    """One session of a sessions file: its id (the file's, else its number from 0), its readings and its truth
    (any JSON, None when absent)."""

    id: str
    readings: list
    truth: object


def read_sessions(path: PathLike, map: Map) -> list:
    """The sessions of a sessions file (docs/batch-format.md) for ``map``'s sensor, read by the engine's own reader:
    what ``sva recognize`` accepts; :class:`sva.Error` names the line and the field of a bad one."""
    import json

    from ._sva_core import _read_sessions

    return [Session(id_, readings, json.loads(truth) if truth else None)
            for id_, readings, truth in _read_sessions(os.fspath(path), map.sensor.elements)]


def trial_session(data, map: Map, trial: int, *, seed: int = 1, max_readings: int = 30) -> Session:
    """Evaluation trial ``trial`` of the test set ``data`` (a :class:`sva.Dataset` or a ``.svad`` path) as a session:
    exactly the readings ``sva eval --seed SEED --max-readings M`` presents in that trial, with the truth as
    ``sva recognize --write-sessions`` writes it (``object``, ``R`` row by row, ``T`` in mm)."""
    import numpy as np

    from ._sva_core import Dataset
    from ._sva_eval import _eval_trial  # the tools' module, imported on first use

    if trial < 0 or max_readings < 1 or seed < 0:
        raise Error(f"trial_session: trial {trial} and seed {seed} must be >= 0, max_readings {max_readings} >= 1")
    source = os.fspath(data) if not isinstance(data, Dataset) else "test set"
    test = data if isinstance(data, Dataset) else Dataset.load(source)
    readings, name, pose = _eval_trial(test, map, trial, seed, max_readings, source)
    truth = {"object": name, "R": np.asarray(pose.R).tolist(), "T": np.asarray(pose.T).tolist()}
    return Session(f"trial-{trial}", readings, truth)
