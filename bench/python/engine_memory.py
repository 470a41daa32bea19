"""Memory of recognizers sharing one sva.Engine against recognizers with engines of their own (docs/python.md,
"Measured"): the process's resident set (VmRSS) after loading the map, after making the engine(s), and after each
recognizer has taken the same readings, on the CPU reference (the host map is what an engine holds there; on Vulkan
the device copy is measured by `ctest -R "GPU engine" -V`, docs/api.md). Each configuration runs in a fresh process
so that one's freed memory does not hide the other's.

    PYTHONPATH=build-ci/python .venv/bin/python bench/python/engine_memory.py --map MAP --data TEST [--readings 10]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

import sva


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise RuntimeError("no VmRSS in /proc/self/status")


def readings_of(data: sva.Dataset, count: int) -> list[sva.Reading]:
    """The first `count` converged readings of the dataset's first object with that many. Not bench/lib/sva_bench.py's
    converged_rows: that module imports NumPy, which would add ~12 MiB to every resident set measured here."""
    by_object: dict[int, list[sva.Reading]] = {}
    for s in data:
        if s.converged:
            by_object.setdefault(s.object, []).append(s.reading)
    for rs in by_object.values():
        if len(rs) >= count:
            return rs[:count]
    raise SystemExit(f"no object has {count} converged readings")


def one_configuration(a) -> dict:
    out = {"start": rss_mb()}
    m = sva.Map.load(a.map)
    readings = readings_of(sva.Dataset.load(a.data), a.readings)
    out["map_loaded"] = rss_mb()
    if a.shared:
        engine = sva.Engine(m, backend="cpu")
        recs = [sva.Recognizer(engine, threads=1) for _ in range(2)]
    else:
        recs = [sva.Recognizer(m, backend="cpu", threads=1) for _ in range(2)]
    out["recognizers_made"] = rss_mb()
    for i, rec in enumerate(recs):
        for r in readings:
            rec.add_reading(r)
        rec.estimate()
        out[f"after_recognizer_{i + 1}"] = rss_mb()
    out["map_bytes"] = m.bytes
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--map", required=True)
    p.add_argument("--data", required=True)
    p.add_argument("--readings", type=int, default=10)
    p.add_argument("--shared", action="store_true", help=argparse.SUPPRESS)  # one configuration (child process)
    p.add_argument("--own", action="store_true", help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.shared or a.own:
        print(json.dumps(one_configuration(a)))
        return
    rows = {}
    for flag, name in (("--shared", "two recognizers, one sva.Engine"), ("--own", "two recognizers, own engines")):
        r = subprocess.run([sys.executable, __file__, "--map", a.map, "--data", a.data, "--readings",
                            str(a.readings), flag], check=True, capture_output=True, text=True)
        rows[name] = json.loads(r.stdout)
    first = next(iter(rows.values()))
    print(f"map arrays: {first['map_bytes'] / 2**20:.1f} MiB; {a.readings} readings per recognizer; CPU reference")
    print("| configuration | map loaded | recognizers made | after recognizer 1 | after recognizer 2 | added by the "
          "second |")
    print("|---|---|---|---|---|---|")
    for name, r in rows.items():
        print(f"| {name} | {r['map_loaded']:.0f} MiB | {r['recognizers_made']:.0f} MiB | {r['after_recognizer_1']:.0f} "
              f"MiB | {r['after_recognizer_2']:.0f} MiB | {r['after_recognizer_2'] - r['after_recognizer_1']:.0f} MiB |")


if __name__ == "__main__":
    main()
