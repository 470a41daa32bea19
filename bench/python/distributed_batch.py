"""Sharded batch recognition: sessions per second on 1 and 2 local Dask workers (docs/python.md, "Measured").

Writes evaluation trials as a sessions file (`sva recognize --write-sessions`), recognises them on one machine
(sva.recognize_batch, the reference file), then on LocalClusters of 1 and 2 worker processes: a first, cold run
(each worker loads its map and makes its engine) and warm runs (engines kept), each checked byte for byte against
the reference.

    PYTHONPATH=build-ci/python .venv/bin/python bench/python/distributed_batch.py --map MAP --data TEST [--trials 40]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import sva
import sva.distributed as sd

REPO = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description="sessions/s of sharded batch recognition on 1 and 2 local workers")
    ap.add_argument("--map", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--trials", type=int, default=40)
    ap.add_argument("--readings", type=int, default=10)
    ap.add_argument("--backend", default="cpu")
    ap.add_argument("--workers", default="1,2")
    ap.add_argument("--runs", type=int, default=3, help="warm runs per cluster")
    ap.add_argument("--sva", default=str(REPO / "build" / "sva"))
    a = ap.parse_args()
    from distributed import Client, LocalCluster

    work = Path(tempfile.mkdtemp(prefix="sva-dist-"))
    sessions = work / "sessions.jsonl"
    subprocess.run([a.sva, "recognize", "--write-sessions", str(sessions), "--map", a.map, "--data", a.data,
                    "--trials", str(a.trials), "--max-readings", str(a.readings)], check=True, capture_output=True)
    ref = work / "single.jsonl"
    t0 = time.perf_counter()
    sva.recognize_batch(a.map, sessions, ref, backend=a.backend)
    single = time.perf_counter() - t0
    print(f"{a.trials} sessions of {a.readings} readings; one machine, no Dask (map load included): "
          f"{single:.2f} s, {a.trials / single:.2f} sessions/s", flush=True)
    for n in (int(w) for w in a.workers.split(",")):
        # Each worker's engine gets its share of the cores (the CPU reference's threads).
        threads = max(1, (len(__import__("os").sched_getaffinity(0)) // n))
        with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
                Client(cluster) as client:
            rates = []
            for run in range(a.runs + 1):
                out = work / f"dist{n}-{run}.jsonl"
                t0 = time.perf_counter()
                sd.recognize_batch(a.map, sessions, out, client=client, backend=a.backend, threads=threads)
                s = time.perf_counter() - t0
                assert out.read_bytes() == ref.read_bytes(), "sharded results differ from the single-machine file"
                if run == 0:
                    print(f"{n} worker(s), {threads} thread(s) each: cold (map load per worker) {s:.2f} s, "
                          f"{a.trials / s:.2f} sessions/s", flush=True)
                else:
                    rates.append(a.trials / s)
            print(f"{n} worker(s): warm {statistics.median(rates):.2f} sessions/s (median of {a.runs}); "
                  f"results identical to the single-machine file", flush=True)


if __name__ == "__main__":
    main()
