#!/usr/bin/env python3
"""Readings to a right decision with an oracle choosing every touch (issue 22, "The next touch").

With the calibrated belief a session decides once the top object (or "none of these") reaches P. The oracle knows
the true object and pose: after the random policy's first reading it tries candidate next readings of the true
object (`--candidates` unused test readings, drawn at random each step; all of them with 0) and keeps the one that
gives the true object the most probability, until the session decides. It is greedy, not an exact optimum, and it
sees only the test readings, as the active policy does; its mean is the yardstick the active policy is measured
against: active closes (random - active) / (random - oracle) of the gap.

  usage: PYTHONPATH=build-ci/python .venv/bin/python bench/active_touch/active_touch_oracle.py --map MAP --data TEST.svad \
             --random-csv RANDOM.csv [--trials N] [--threshold 0.95] [--candidates 40] [--max-readings 20]
RANDOM.csv is `sva eval --policy random --csv` of the same map, data and seed (its first readings and poses).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

import sva

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))  # bench/lib: the helpers the scripts share
from sva_bench import decision, random_trials, replay, score  # noqa: E402


def run_trial(rec, test, pool, first, obj, R, T, a, rng):
    shown = [first]
    est = replay(rec, shown, test, R, T)
    for n in range(1, a.max_readings + 1):
        d = decision(est, a.threshold)
        if d is not None:
            return n if d == obj else a.max_readings + 1
        if n == a.max_readings:
            break
        unused = [i for i in pool if i not in shown]
        if a.candidates and len(unused) > a.candidates:
            unused = list(rng.choice(unused, size=a.candidates, replace=False))
        best, best_est = None, None
        for i in unused:
            e = replay(rec, shown + [i], test, R, T)
            if best is None or score(e, obj) > score(best_est, obj):
                best, best_est = i, e
        shown.append(best)
        est = best_est
    return a.max_readings + 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--map", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--random-csv", required=True)
    ap.add_argument("--trials", type=int, default=0, help="the first N trials of the CSV (default all)")
    ap.add_argument("--threshold", type=float, default=0.95)
    ap.add_argument("--candidates", type=int, default=40, help="candidates tried per step (0: every unused one)")
    ap.add_argument("--max-readings", type=int, default=20)
    a = ap.parse_args()
    m, test = sva.Map.load(a.map), sva.Dataset.load(a.data)
    trials = random_trials(a.random_csv, a.trials, test)
    rec = sva.Recognizer(m, backend="cpu")
    rng = np.random.default_rng(1)
    readings = []
    print("trial object        oracle readings to a right decision")
    for t, rows, obj, R, T, pool in trials:
        readings.append(run_trial(rec, test, pool, int(rows[0]["sample"]), obj, R, T, a, rng))
        print(f"{t:5d} {rows[0]['object_name']:12s} {readings[-1]:5d}", flush=True)
    print(f"trials {len(trials)}: oracle mean readings to a right decision at {a.threshold}: "
          f"{sum(readings) / len(readings):.2f} (no decision within {a.max_readings} counts {a.max_readings + 1})")


if __name__ == "__main__":
    sys.exit(main())
