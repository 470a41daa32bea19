"""Choosing where to touch next, from Python: the planner picks each touch among the places a robot could press
(here the tiny scene's brick as a camera would see it: its surface points, not which object it is), until one
object holds 95% of the belief; the same touches taken in the order they come are counted beside it.

    .venv/bin/python examples/python_active_touch.py [--out DIR]

The tiny scene is a poor showcase: two objects and 12 surface points leave the planner little to choose from, and
over 12 placements it needs about as many touches as the given order (die 6.9 against 6.7, brick 3.4 against 3.2).
On paper3d (10 objects, ~100 points each) it needs 93% of random's touches and halves the pose error at 8 touches
(docs/evaluation.md, "Choosing the next touch").

Run it after `pip install .` (or with PYTHONPATH=build-ci/python in the ci preset's build tree). docs/python.md, "Choosing the next
touch"; docs/api.md for the planner's model.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

import sva


def rotation_z(deg: float) -> np.ndarray:
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def touches_to_decide(m, surface, planner=None, threshold=0.95):
    """Touches until the belief's best object holds `threshold` (first touch: surface[0]); with a planner each next
    touch is its best among the unused surface points, else the next one in order. Returns (touches, estimate)."""
    rec = sva.Recognizer(m, backend="cpu")
    used, touched = [0], [surface[0]]
    rec.add_reading(surface[0])
    est = rec.estimate(top_k=8)
    while est.object_probability.max() < threshold and len(used) < len(surface):
        free = [i for i in range(len(surface)) if i not in used]
        pick = free[0]
        if planner is not None:
            if len(touched) == 1:  # no pair has voted yet: guesses from the first touch's appearance
                guess = planner.contact_estimate(touched[0], per_object=6, seed=1)
                belief, hyps = guess, len(guess.hypotheses)
            else:
                belief, hyps = est, 16
            cands = [sva.CandidateTouch(surface[i].position, -np.asarray(surface[i].normal)) for i in free]
            plan = sva.plan_next_touch(planner, belief, cands, max_hypotheses=hyps,
                                       visited=np.array([r.position for r in touched]),
                                       visited_normals=np.array([r.normal for r in touched]))
            if plan.best and plan.best[0].score > 0.0:
                pick = free[plan.best[0].candidate]
        used.append(pick)
        touched.append(surface[pick])
        rec.add_reading(surface[pick])
        est = rec.estimate(top_k=8)
    return len(used), est


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None, help="where the datasets and map go (default: a temp dir)")
    args = ap.parse_args()
    out = args.out or Path(tempfile.mkdtemp(prefix="sva-active-touch-"))
    out.mkdir(parents=True, exist_ok=True)

    train, test = sva.simulate("tiny", train=20, test=12, seed=1, out=out)
    m = sva.train(train, out=out / "map.svam")
    planner = sva.TouchPlanner(m)  # once per map

    # The brick at a pose the robot does not know; its surface points in the robot frame are the touches it can make.
    truth = sva.RigidPose(rotation_z(30.0), [15.0, -10.0, 0.0])
    surface = [sva.Reading(s.reading.pressure, truth.apply(s.reading.position), truth.R @ s.reading.normal,
                           truth.R @ s.reading.x_axis)
               for s in test if s.object == 1 and s.converged]
    in_order, _ = touches_to_decide(m, surface)
    planned, est = touches_to_decide(m, surface, planner)
    print(f"touches until one object holds 95%: {planned} planned, {in_order} in the order they come")
    print(f"final: {est.object_name} ({est.object_probability[est.object]:.3f}) after {planned} planned touches")


if __name__ == "__main__":
    main()
