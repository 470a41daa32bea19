#!/usr/bin/env python3
"""Where look-alikes' evidence goes wrong: one eval run's evidence weighed again, and the surface check's margin of
each truth over its best sibling (docs/notes/evaluation-2026-11.md, "where the twins' evidence goes wrong").

    PYTHONPATH=build-ci/python python3 bench/lookalikes/evidence_margins.py EVIDENCE.jsonl MAP SCENE \
        [--readings 30] [--weights 0,1,4]

EVIDENCE is `sva eval --evidence`'s file: per trial and reading, each map object's pairs' bits and surface bits with
the temperature and surface weight that weighed them (docs/evaluation.md, "The evidence behind each answer"). MAP
names the objects by id; SCENE gives each object its family (objects without one are their own).

First table: accuracy at each reading count when the same evidence is weighed as the estimate did (which must
reproduce its answer), with other surface weights, and with the leading family's members decided by their surfaces
alone. A weight that lifts it says the weighing is the limit; none that does says the evidence itself is.
Second table, at --readings: per family with siblings, how often the truth's surface bits fall more than a bit below
its best sibling's, lie within a bit, or rise above, and the median shortfall; and how many wrong trials had the
truth at the floor of the surface bits (not among the objects the check fitted: they all get the fitted ones' worst).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from collections import defaultdict
from pathlib import Path

import sva

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))  # bench/lib: the helpers the scripts share
from sva_bench import object_families  # noqa: E402

PROG = "evidence_margins.py"


def fail(message: str) -> None:
    sys.exit(f"{PROG}: {message}")


def read_rows(path: str, objects: int) -> list[dict]:
    """The evidence file's rows, each checked for the fields and the object count this script reads."""
    rows = []
    try:
        lines = open(path, encoding="utf-8").read().splitlines()
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            r = json.loads(line)
            if r.get("map_object", 0) is None:
                fail(f"{path}, line {number}: trial {r.get('trial')}'s object {r.get('object')!r} is not in the map "
                     "(--unknown-objects); this script reads runs on the map's own objects")
            if len(r["pairs_log2_mass"]) != objects or len(r["surface_log2_fit"]) not in (0, objects):
                fail(f"{path}, line {number}: {len(r['pairs_log2_mass'])} objects' evidence, the map has {objects}")
            float(r["temperature"]), float(r["surface_weight"]), int(r["readings"]), int(r["map_object"])
        except (json.JSONDecodeError, KeyError, TypeError, ValueError) as e:
            fail(f"{path}, line {number}: not a row of sva eval --evidence ({type(e).__name__}: {e})")
        rows.append(r)
    if not rows:
        fail(f"{path}: no rows (sva eval --evidence writes one per trial and reading)")
    return rows


def surface(r: dict) -> list[float]:
    return r["surface_log2_fit"] or [0.0] * len(r["pairs_log2_mass"])


def pick(r: dict, family_of: list[str], weight: float | None = None, surfaces_within: bool = False) -> int:
    """The object the evidence names: temperature x pairs + weight x surface (the run's weight by default); with
    surfaces_within, the leading family's members ranked by their surface bits alone."""
    w = r["surface_weight"] if weight is None else weight
    s = surface(r)
    score = [r["temperature"] * p + w * q for p, q in zip(r["pairs_log2_mass"], s)]
    best = max(range(len(score)), key=score.__getitem__)
    if not surfaces_within:
        return best
    members = [o for o in range(len(score)) if family_of[o] == family_of[best]]
    if len({s[o] for o in members}) == 1:
        return best  # the surfaces say nothing (before the check's first reading count): the weighed best stands
    return max(members, key=lambda o: s[o])


def accuracy_table(rows: list[dict], family_of: list[str], weights: list[float]) -> None:
    counts = sorted({r["readings"] for r in rows})
    shown = [n for n in counts if n in (2, 4, 6, 10, 15, 20, 25, 30) or n == counts[-1]]
    runs = [("as the estimate weighed it", {})] + [(f"surface weight {w:g}", {"weight": w}) for w in weights]
    runs.append(("the leading family by its surfaces alone", {"surfaces_within": True}))
    by_count = defaultdict(list)
    for r in rows:
        by_count[r["readings"]].append(r)
    print(f"accuracy (%) at {' / '.join(map(str, shown))} readings")
    for label, kw in runs:
        cells = []
        for n in shown:
            at = by_count[n]
            cells.append(f"{100.0 * sum(pick(r, family_of, **kw) == r['map_object'] for r in at) / len(at):5.1f}")
        print(f"  {label:42s} {' '.join(cells)}")
    same = sum(pick(r, family_of) == r["estimated_object"] for r in rows)
    print(f"  (the weighing reproduces the estimate's object in {same} of {len(rows)} trial-readings)")


def margin_table(rows: list[dict], family_of: list[str], readings: int) -> None:
    at = [r for r in rows if r["readings"] == readings]
    wrong = [r for r in at if not r["correct"]]
    floor = sum(1 for r in wrong if len(set(surface(r))) > 1 and surface(r)[r["map_object"]] == min(surface(r)))
    print(f"at {readings} readings: {len(wrong)} of {len(at)} trials wrong, {floor} of them with the truth at the floor "
          "of the surface bits (not fitted)")
    per = defaultdict(list)
    for r in at:
        truth, s = r["map_object"], surface(r)
        siblings = [o for o in range(len(s)) if o != truth and family_of[o] == family_of[truth]]
        if siblings:
            per[family_of[truth]].append((bool(r["correct"]), s[truth] - max(s[o] for o in siblings)))
    print(f"  {'family':20s} {'right':>7s} {'below > 1 bit':>14s} {'within 1':>9s} {'above > 1':>10s} {'median shortfall':>17s}")
    for family, v in sorted(per.items(), key=lambda kv: sum(c for c, _ in kv[1]) / len(kv[1])):
        m = [x for _, x in v]
        short = [x for x in m if x < -1.0]
        median = f"{statistics.median(short):+.1f} bits" if short else "-"
        print(f"  {family:20s} {sum(c for c, _ in v):3d}/{len(v):<3d} {len(short):14d} "
              f"{sum(abs(x) <= 1.0 for x in m):9d} {sum(x > 1.0 for x in m):10d} {median:>17s}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("evidence", help="sva eval --evidence's file (JSON lines)")
    ap.add_argument("map", help="the map the run recognised with (.svam): the objects' names by id")
    ap.add_argument("scene", help="the scene (built-in name or JSON file) whose objects name their family")
    ap.add_argument("--readings", type=int, default=30, help="the reading count of the margins' table")
    ap.add_argument("--weights", default="0,1,4", help="other surface weights to weigh with (comma-separated)")
    a = ap.parse_args()
    try:
        weights = [float(x) for x in a.weights.split(",")]
    except ValueError:
        fail(f"--weights {a.weights!r}: expected numbers, comma-separated")
    if any(not (w >= 0.0) or w == float("inf") for w in weights):
        fail(f"--weights {a.weights!r}: each weight must be finite and at least 0")
    try:
        names = list(sva.Map.load(a.map).object_names)
        family_by_name = object_families(sva.load_scene(a.scene))
    except Exception as e:  # the package's errors name the file and the fault
        fail(str(e))
    missing = [n for n in names if n not in family_by_name]
    if missing:
        fail(f"{a.map}: object {missing[0]!r} is not in scene {a.scene!r}")
    family_of = [family_by_name[n] for n in names]
    rows = read_rows(a.evidence, len(names))
    if not any(r["readings"] == a.readings for r in rows):
        fail(f"--readings {a.readings}: {a.evidence} has no trial at that many readings")
    accuracy_table(rows, family_of, weights)
    print()
    margin_table(rows, family_of, a.readings)


if __name__ == "__main__":
    main()
