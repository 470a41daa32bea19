"""The Python path's overhead per update against C++ on the same sessions (docs/python.md, "Measured").

C++: `sva eval --backend cpu --threads 1` times add_reading + estimate of every step of every trial in C++
(update_ms of its CSV); so does sva.evaluate in this process (the same C++ loop, in the same process as the Python
loop: same memory, same load). Python: the same trials (`sva recognize --write-sessions`, same map, seed and counts: the
same readings), through sva.Recognizer(backend="cpu", threads=1): add_reading + estimate timed around the Python
calls, so the binding's conversions, GIL release and lock are inside. Rounds alternate C++ and Python (the machine
may be shared); the medians at the last reading count and over all steps are printed, with the overhead.

    PYTHONPATH=build-ci/python .venv/bin/python bench/python/overhead.py --map MAP --data TEST [--trials 20]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import sva

REPO = Path(__file__).resolve().parents[2]


def reading_of(r: dict) -> sva.Reading:
    # The normal normalised as the engine's sessions reader does (glm::normalize), so the readings are the same.
    x, y, z = (float(v) for v in r["normal"])
    k = 1.0 / math.sqrt(x * x + y * y + z * z)
    return sva.Reading(np.asarray(r["pressure"], dtype=np.float32), np.array(r["position"]),
                       np.array([x * k, y * k, z * k]), r.get("x_axis", (1.0, 0.0, 0.0)))


def read_eval_csv(out: Path) -> dict[tuple[int, int], tuple[float, int]]:
    with out.open() as f:
        return {(int(r["trial"]), int(r["readings"])): (float(r["update_ms"]), int(r["estimated_object"]))
                for r in csv.DictReader(f)}


def cpp_round(a, work: Path) -> dict[tuple[int, int], tuple[float, int]]:
    """(trial, readings) -> (update_ms, estimated object) from `sva eval`."""
    out = work / "eval.csv"
    subprocess.run([a.sva, "eval", "--map", a.map, "--data", a.data, "--trials", str(a.trials), "--max-readings",
                    str(a.readings), "--seed", str(a.seed), "--backend", "cpu", "--threads", "1", "--csv", str(out)],
                   check=True, capture_output=True)
    return read_eval_csv(out)


def inprocess_round(a, m: sva.Map, test: sva.Dataset, work: Path) -> dict[tuple[int, int], tuple[float, int]]:
    """The same from sva.evaluate: the C++ trial loop timed in C++, in this process."""
    out = work / "inprocess.csv"
    sva.evaluate(m, test, trials=a.trials, max_readings=a.readings, seed=a.seed, backend="cpu", threads=1, csv=out)
    return read_eval_csv(out)


def python_round(m: sva.Map, sessions: list[list[sva.Reading]]) -> dict[tuple[int, int], tuple[float, int]]:
    times = {}
    rec = sva.Recognizer(m, backend="cpu", threads=1)
    for t, readings in enumerate(sessions):
        rec.reset()
        for k, r in enumerate(readings, start=1):
            t0 = time.perf_counter()
            rec.add_reading(r)
            est = rec.estimate()
            times[(t, k)] = ((time.perf_counter() - t0) * 1e3, est.object)
    return times


def binding_costs(m: sva.Map, reading: sva.Reading) -> None:
    """The binding's fixed costs per call, free of the engine's work (upper bounds of the overhead per update)."""
    import timeit

    def per_call(f, n=20000) -> float:
        return min(timeit.repeat(f, number=n, repeat=5)) / n * 1e6

    rec = sva.Recognizer(m, backend="cpu", threads=1)
    p32 = np.asarray(reading.pressure, dtype=np.float32).reshape(6, 6)
    p64 = p32.astype(np.float64)
    pos, nrm = np.array(reading.position), np.array(reading.normal)
    print("binding costs per call (best of 5, microseconds):")
    print(f"  rec.reading_count() (call, lock)               {per_call(rec.reading_count):7.2f}")
    print(f"  rec.estimate(), no reading (+ GIL release,     {per_call(rec.estimate, 2000):7.2f}\n"
          "    the engine's empty estimate, Estimate to Python)")
    print(f"  sva.Reading(float32 image, vectors)            {per_call(lambda: sva.Reading(p32, pos, nrm)):7.2f}")
    print(f"  sva.Reading(float64 image: converted)          {per_call(lambda: sva.Reading(p64, pos, nrm)):7.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description="Python vs C++ time per update on the same sessions")
    ap.add_argument("--map", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--readings", type=int, default=10)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--sva", default=str(REPO / "build" / "sva"))
    ap.add_argument("--costs-only", action="store_true", help="only the binding's fixed costs per call")
    a = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="sva-overhead-"))
    sessions_file = work / "sessions.jsonl"
    subprocess.run([a.sva, "recognize", "--write-sessions", str(sessions_file), "--map", a.map, "--data", a.data,
                    "--trials", str(a.trials), "--max-readings", str(a.readings), "--seed", str(a.seed)],
                   check=True, capture_output=True)
    sessions = [[reading_of(r) for r in json.loads(line)["readings"]] for line in sessions_file.read_text().splitlines()]
    m = sva.Map.load(a.map)
    binding_costs(m, sessions[0][0])
    if a.costs_only:
        return
    test = sva.Dataset.load(a.data)
    runs = {"C++ (sva eval)": lambda: cpp_round(a, work), "C++ in this process (sva.evaluate)":
            lambda: inprocess_round(a, m, test, work), "Python (sva.Recognizer)": lambda: python_round(m, sessions)}
    last: dict[str, list[float]] = {k: [] for k in runs}
    every: dict[str, list[float]] = {k: [] for k in runs}
    for rnd in range(a.rounds):
        got = {name: run() for name, run in runs.items()}
        ref = got["C++ (sva eval)"]
        for name, times in got.items():
            assert all(times[k][1] == ref[k][1] for k in ref), f"{name} estimated other objects than sva eval"
            last[name].append(statistics.median(v[0] for k, v in times.items() if k[1] == a.readings))
            every[name].append(statistics.median(v[0] for v in times.values()))
        print(f"round {rnd + 1}: " + "; ".join(f"{n} {last[n][-1]:.2f} ms at {a.readings}, {every[n][-1]:.2f} ms "
                                               f"over all steps" for n in runs), flush=True)
    print(f"median of {a.rounds} rounds, {a.trials} trials x {a.readings} readings ({m.scene_name}, CPU reference, "
          f"1 thread), ms per update (add_reading + estimate):")
    base = "C++ in this process (sva.evaluate)"
    for n in runs:
        l, e = statistics.median(last[n]), statistics.median(every[n])
        lb, eb = statistics.median(last[base]), statistics.median(every[base])
        print(f"  {n:38s} at {a.readings} readings {l:8.3f} ({100 * (l - lb) / lb:+5.1f}%)   all steps {e:8.3f} "
              f"({100 * (e - eb) / eb:+5.1f}%)")
    py = "Python (sva.Recognizer)"
    ratios = [p / c for p, c in zip(last[py], last[base])]
    print(f"  Python / C++ in this process, round by round at {a.readings} readings: "
          + ", ".join(f"{100 * (r - 1):+.1f}%" for r in ratios) + f" (median {100 * (statistics.median(ratios) - 1):+.1f}%)")
    print("estimated objects identical at every step of every trial")

if __name__ == "__main__":
    main()
