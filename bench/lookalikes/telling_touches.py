#!/usr/bin/env python3
"""Would touches where near-twins differ help the recognizer? (docs/evaluation.md, "Touches where the twins differ")

    PYTHONPATH=build-ci/python python3 bench/lookalikes/telling_touches.py MAP TEST.svad SCENE [--gap 1] [--telling 3,5]
        [--trials 8] [--families a,b] [--seed 11]

bench/lookalikes/family_ceiling.py marks each test reading of a family's member that *tells* it from a sibling: the two
surfaces lie more than GAP mm apart somewhere under the sensor's pad. Random touches rarely land there on the families
that differ in one small region, which bounds any recognizer under random touches. This asks the question a touch
planner depends on: if the touches did land there, would the recognizer use them? For every member, TRIALS sessions of
30 of its test readings: "random", the member's trials of `sva eval --seed SEED --max-readings 30` as eval runs them,
and, for each K of --telling, K telling readings at random places among the first 15 and every other reading one that
tells nothing, at the pose of the same eval trial. Prints the share of sessions whose estimate names the member at 15
and at 30 readings, per family and variant. A variant needs K telling readings and 30 - K others; a member short of them
skips it (the counts are printed).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import sva
from family_ceiling import family_gaps, readings_by_object

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))  # bench/lib: the helpers the scripts share
from sva_bench import placed  # noqa: E402

READINGS = 30  # per session; the telling readings land among the first EARLY
EARLY = 15


def eval_trial(test, m, member: int, k: int, seed: int):
    """The k-th trial of `member` as `sva eval --seed SEED --max-readings 30` runs it: its readings (the random
    variant) and its pose (rotation, translation), which the other variants share. The translation matters: at the
    origin every centred object sits on a bin edge of the translation grid, and the screwdriver tips were right in
    25% of eval's own trials moved there against 37.5% where eval put them."""
    s = sva.trial_session(test, m, member + len(m.object_names) * k, seed=seed, max_readings=READINGS)
    return s.readings, (np.array(s.truth["R"], float), np.array(s.truth["T"], float))


def session_right(rec, readings, member: int) -> tuple[bool, bool]:
    """Adds `readings` to a fresh session: whether the estimate names `member` at 15 and at 30 readings."""
    rec.reset()
    right = {}
    for k, r in enumerate(readings, 1):
        rec.add_reading(r)
        if k in (EARLY, READINGS):
            right[k] = rec.estimate().object == member
    return right[EARLY], right[READINGS]


def draw(variant: int, telling: np.ndarray, rng: np.random.Generator) -> np.ndarray | None:
    """Positions (into the member's readings) of one session's readings with `variant` telling ones among the first
    EARLY, or None when the member has too few of either kind."""
    told, other = np.flatnonzero(telling), np.flatnonzero(~telling)
    if len(told) < variant or len(other) < READINGS - variant:
        return None
    rows = np.concatenate([rng.choice(told, variant, replace=False), rng.choice(other, READINGS - variant,
                                                                                replace=False)])
    early = rows[:EARLY].copy()
    rng.shuffle(early)
    rows[:EARLY] = early
    return rows


def parse_args() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("map", help="a map (.svam) of the scene")
    ap.add_argument("test", help="a test dataset (.svad) of the scene")
    ap.add_argument("scene", help="the scene (built-in name or JSON file) whose objects name their family")
    ap.add_argument("--gap", type=float, default=1.0, help="mm between the surfaces that tells them apart")
    ap.add_argument("--telling", default="3,5", help="telling readings among the first 15 (comma-separated)")
    ap.add_argument("--trials", type=int, default=8, help="sessions per member and variant")
    ap.add_argument("--families", default="", help="only these families (comma-separated; default every one)")
    ap.add_argument("--seed", type=int, default=11, help="seed of eval's trials (sva eval --seed) and of the draws")
    ap.add_argument("--points", type=int, default=40000, help="surface points per mesh (family_ceiling.py)")
    a = ap.parse_args()
    try:
        a.telling = [int(x) for x in a.telling.split(",")] if a.telling else []
    except ValueError:
        ap.error(f"--telling {a.telling!r}: expected whole numbers, comma-separated")
    if any(k < 1 or k > EARLY for k in a.telling):
        ap.error(f"--telling: each count must lie in 1-{EARLY}")
    if not a.gap > 0 or a.trials < 1 or a.points < 100:
        ap.error("--gap must be positive, --trials at least 1, --points at least 100")
    return a


def main() -> None:
    a = parse_args()
    try:
        m = sva.Map.load(a.map)
        test = sva.Dataset.load(a.test)
        scene = sva.load_scene(a.scene)
    except Exception as e:  # the package's errors name the file and the fault
        sys.exit(f"telling_touches.py: {e}")
    if list(test.scene.object_names) != list(scene.object_names) or list(m.object_names) != list(scene.object_names):
        sys.exit(f"telling_touches.py: {a.map} and {a.test} must both be of scene {a.scene!r} (their objects differ)")
    families: dict[str, list[int]] = {}
    for i, o in enumerate(json.loads(scene.to_json())["objects"]):
        if o.get("family"):
            families.setdefault(o["family"], []).append(i)
    wanted = [f for f in a.families.split(",") if f]
    unknown = [f for f in wanted if f not in families]
    if unknown:
        sys.exit(f"telling_touches.py: --families: {', '.join(unknown)} not a family of {a.scene!r}")
    position, normal, rows_of = readings_by_object(test)
    half_width = 0.5 * max(scene.sensor.rows, scene.sensor.cols) * scene.sensor.pitch_mm
    rng = np.random.default_rng(a.seed)
    rec = sva.Recognizer(m, backend="cpu")
    variants: list[int | None] = [None, *a.telling]
    label = {None: "random", **{k: f"{k} telling" for k in a.telling}}
    print(f"gap {a.gap} mm; per family and variant: right at {EARLY} / {READINGS} readings (sessions)")
    for family in wanted or list(families):
        members = families[family]
        if len(members) < 2 or any(o not in position for o in members):
            print(f"{family:<20} skipped: fewer than two members with converged test readings")
            continue
        gaps = family_gaps(scene, members, position, normal, half_width, a.points, rng)
        right: dict = {v: [] for v in variants}
        for o in members:
            telling = (gaps[o] > a.gap).any(1)
            for k in range(a.trials):
                readings, pose = eval_trial(test, m, o, k, a.seed)
                if len(readings) == READINGS:  # eval's trial repeats readings past the count; a session here does not
                    right[None].append(session_right(rec, readings, o))
                for v in a.telling:
                    rows = draw(v, telling, rng)
                    if rows is not None:
                        right[v].append(session_right(rec, [placed(test[int(i)], *pose) for i in rows_of[o][rows]], o))
        shares = " ".join(f"{(gaps[o] > a.gap).any(1).mean():.2f}" for o in members)
        cells = [f"{label[v]} " + (f"{100 * np.mean([x[0] for x in right[v]]):3.0f} / "
                                   f"{100 * np.mean([x[1] for x in right[v]]):3.0f}% ({len(right[v])})"
                                   if right[v] else "- (too few readings)") for v in variants]
        print(f"{family:<20} telling {shares:<20} " + "   ".join(cells), flush=True)


if __name__ == "__main__":
    main()
