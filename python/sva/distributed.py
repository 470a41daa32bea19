"""Batch recognition of a sessions file sharded over a Dask cluster (docs/python.md, "Beyond one machine").

The driver cuts the sessions file into shards of consecutive sessions and sends them to the workers; each worker
process holds one engine (a BatchRecognizer and its map, loaded once and kept for every shard it gets) and returns
its shard's result lines; the driver joins them in input order. Each session's estimate depends only on its own
readings, so the results file is byte for byte the one ``sva recognize`` (or :func:`sva.recognize_batch`) writes on
one machine.

On a lab's cluster (sva installed on every machine, the map on a path every worker can read)::

    # illustration: shell commands on a lab's machines; python/tests/test_distributed.py runs them on 127.0.0.1
    dask scheduler                                         # on the head node: tcp://HEAD:8786
    dask worker tcp://HEAD:8786 --nworkers 1 --nthreads 1  # on each machine (one engine per machine)
    python -m sva.distributed --scheduler tcp://HEAD:8786 \\
        --map /shared/map.svam --batch sessions.jsonl --out results.jsonl

On this machine: ``python -m sva.distributed --local 2 --map ... --batch ... --out ...``.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import threading
import time
from pathlib import Path
from typing import Any, Optional

from ._sva_core import BatchRecognizer, Error, Map
from .batch import PathLike, SessionsFile, Shard, check_writable, write_atomically

# This worker process's engines, by (map file, its size and mtime, options): normally exactly one.
_engines: dict[tuple, tuple[Map, BatchRecognizer]] = {}
_engines_lock = threading.Lock()


def _engine(map_file: str, sessions_per_submission: int, options: tuple) -> tuple[Map, BatchRecognizer]:
    st = os.stat(map_file)
    key = (map_file, st.st_size, st.st_mtime_ns, sessions_per_submission, options)
    with _engines_lock:
        if key not in _engines:
            _engines.clear()  # a new map or options: let the old engine go first
            m = Map.load(map_file)
            _engines[key] = (m, BatchRecognizer(m, sessions_per_submission, **dict(options)))
        return _engines[key]


def _recognize_shard(
    map_file: str, sessions_per_submission: int, options: tuple, shard: Shard, source: str, top: int,
    depth: str = "full",
) -> bytes:
    """Runs on a worker: the result lines of one shard, on this worker's engine."""
    m, rec = _engine(map_file, sessions_per_submission, options)
    return rec._recognize_shard(m, shard.text, source, shard.first_line, shard.first_session, top, depth)


def default_sessions_per_shard(sessions: int, workers: int, sessions_per_submission: int) -> int:
    """At most one submission's worth of sessions (a GPU stays as busy as on one machine), and at least four shards
    per worker while there are enough sessions (the faster workers take more)."""
    return max(1, min(sessions_per_submission, math.ceil(sessions / (4 * max(1, workers)))))


def recognize_batch(
    map: PathLike,
    sessions: PathLike,
    out: Optional[PathLike] = None,
    *,
    client: Any = None,
    sessions_per_shard: Optional[int] = None,
    sessions_per_submission: int = 64,
    top: int = 3,
    depth: str = "full",
    **options,
) -> list[str]:
    """:func:`sva.recognize_batch` sharded over the Dask cluster of ``client`` (a ``distributed.Client``; default:
    the current one). ``map`` is the path of the map file, which every worker must be able to read (a shared
    filesystem); the sessions file is read here and sent to the workers in shards. Returns the result lines in
    input order and, with ``out``, writes them there only when every shard succeeded. An error in a shard is
    raised as the engine reported it (sva.Error naming FILE:LINE); of several, the one earliest in the file."""
    from distributed import wait

    if client is None:
        from distributed import get_client

        client = get_client()
    if sessions_per_submission < 1:
        raise Error(f"sessions_per_submission must be >= 1, got {sessions_per_submission}")
    map_file = os.path.abspath(os.fspath(map))
    if not os.path.isfile(map_file):
        raise Error(f"{map_file}: no such map file (it must be readable at this path on every worker)")
    if out is not None:
        check_writable(out)
    file = SessionsFile(sessions)
    workers = len(client.scheduler_info().get("workers", {})) or 1
    per_shard = sessions_per_shard or default_sessions_per_shard(file.sessions, workers, sessions_per_submission)
    shards = file.shards(per_shard)
    opts = tuple(sorted(options.items()))
    futures = [
        client.submit(_recognize_shard, map_file, sessions_per_submission, opts, s, file.name, top, depth, pure=False)
        for s in shards
    ]
    wait(futures)
    for f in futures:  # the earliest failing shard's error
        if f.status == "error":
            error = f.exception()
            client.cancel(futures)
            raise error
    results = client.gather(futures)
    if out is not None:
        write_atomically(out, iter(results))
    return b"".join(results).decode("utf-8").splitlines()


def main(argv: Optional[list[str]] = None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m sva.distributed",
        description="Batch recognition of a sessions file (docs/batch-format.md) sharded over a Dask cluster; "
        "the results file is the one `sva recognize` writes.",
    )
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--scheduler", metavar="ADDRESS", help="the cluster's scheduler, e.g. tcp://head:8786")
    where.add_argument("--local", metavar="N", type=int, help="start a local cluster of N worker processes")
    p.add_argument("--map", required=True, help="map file (readable at this path on every worker)")
    p.add_argument("--batch", required=True, metavar="SESSIONS.jsonl", help="the sessions to recognise")
    p.add_argument("--out", required=True, metavar="RESULTS.jsonl", help="where the estimates go")
    p.add_argument("--backend", default="auto", choices=["auto", "cpu", "vulkan"])
    p.add_argument("--threads", type=int, default=0, help="CPU backend threads per worker (0: all cores)")
    p.add_argument("--sessions-per-submission", type=int, default=64)
    p.add_argument("--sessions-per-shard", type=int, default=None)
    p.add_argument("--top", type=int, default=3, help="hypotheses reported per session")
    p.add_argument("--refine", choices=["on", "off"], default="on", help="fine pose (default on)")
    p.add_argument("--estimate", choices=["full", "light"], default="full",
                   help="each session's estimate at its end (light: no host fits; default full)")
    a = p.parse_args(argv)
    from distributed import Client, LocalCluster

    if a.local is not None and a.local < 1:
        p.error("--local expects at least 1 worker")
    cluster = None
    if a.local:
        cluster = LocalCluster(n_workers=a.local, threads_per_worker=1, processes=True, dashboard_address=":0")
    try:
        with Client(cluster if cluster else a.scheduler) as client:
            start = time.perf_counter()
            lines = recognize_batch(
                a.map, a.batch, a.out, client=client, sessions_per_shard=a.sessions_per_shard,
                sessions_per_submission=a.sessions_per_submission, top=a.top, depth=a.estimate, backend=a.backend,
                threads=a.threads, refine_pose=a.refine == "on",
            )
            seconds = time.perf_counter() - start
            workers = len(client.scheduler_info()["workers"])
        print(f"recognised {len(lines)} sessions on {workers} workers in {seconds:.2f} s "
              f"({len(lines) / seconds:.2f} sessions/s); wrote {a.out}", file=sys.stderr)
    except Error as e:
        print(f"python -m sva.distributed: {e}", file=sys.stderr)
        return 1
    finally:
        if cluster:
            cluster.close()
    return 0


if __name__ == "__main__":
    # Run as a script (`python -m sva.distributed`), this file is the module `__main__`, and pickle would send its
    # functions to the workers by value, with the module's lock (which cannot be pickled). The importable module's
    # own main submits `sva.distributed._recognize_shard`, which workers import by name.
    from sva.distributed import main as _main

    sys.exit(_main())
