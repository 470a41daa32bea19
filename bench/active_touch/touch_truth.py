#!/usr/bin/env python3
"""Does the touch planner rank candidate touches as their true effect does? (issues 22 and 23, "The next touch")

After the first K readings of each trial of a random run, every candidate touch of the true object is scored twice:
by the planner (sva.plan_next_touch, as `sva eval --policy active` calls it: the trial's estimate(8), the visited
touches, the true object's unused test contacts in its true pose) and by its truth, the true object's probability
once that very reading is added. Prints, per planner setting, the mean rank correlation between the two over the
trials, and where the planner's best candidate lies among the truths.

With --dense DENSE.svad (a second test set of the same scene, many readings per object: `sva simulate --train 1
--test 400 --seed 5`) it also asks how much of the truth a planner could know at all: the candidates are then the
dense set's readings of the true object, and the truth of near-identical places (within 3 mm and 15 degrees) is
compared. The share of the truth's variance (in logits) that neighbours share is the place's, a property of the
surface a perfect model could predict; the rest is the reading's own draw (its image, its errors), which no policy
choosing before it touches can know, though the greedy oracle of bench/active_touch/active_touch_oracle.py sees it.

With --train TRAIN.svad (the map's training set) it also scores the candidates with the recognizer itself as the
outcome model: each object holding at least 1% predicts at the candidate its nearest training reading facing the same
way (pressure image and all), placed at the object's best pose; the filter runs on the trial's readings plus that
one, and the score is the expected gain in log2 of the predicting object's probability. Costs an update per
candidate and object.

  usage: PYTHONPATH=build-ci/python .venv/bin/python bench/active_touch/touch_truth.py --map MAP --data TEST.svad \
             --random-csv RANDOM.csv [--readings K] [--trials N] [--objects a,b] [--dense DENSE.svad] \
             [--train TRAIN.svad]
RANDOM.csv is `sva eval --policy random --csv` of the same map, data and seed (its readings and poses).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

import sva

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))  # bench/lib: the helpers the scripts share
from sva_bench import Surface, converged_rows, logit, placed, random_trials, session  # noqa: E402

# Planner settings compared with the defaults (TouchPlanOptions; docs/api.md, "Choosing the next touch").
SETTINGS = [("defaults", {}), ("position_sigma_mm 5", {"position_sigma_mm": 5.0}),
            ("position_sigma_mm 20", {"position_sigma_mm": 20.0}), ("pose_gain off", {"pose_gain": False}),
            ("max_hypotheses 4", {"max_hypotheses": 4}), ("normal_sigma_deg 40", {"normal_sigma_deg": 40.0}),
            ("confusion 0.2", {"confusion": 0.2})]


def rank(a):
    return np.argsort(np.argsort(a, kind="stable"), kind="stable")


def rank_correlation(a, b):
    return float(np.corrcoef(rank(a), rank(b))[0, 1]) if np.std(a) > 0 and np.std(b) > 0 else 0.0


def truths(rec, shown, candidates, obj):
    """The true object's probability after `shown` and each candidate reading."""
    return np.array([float(session(rec, shown + [c], top_k=8).object_probability[obj]) for c in candidates])


def planner_scores(planner, est, shown, candidates, settings):
    touches = [sva.CandidateTouch(c.position, -np.array(c.normal), True) for c in candidates]
    plan = sva.plan_next_touch(planner, est, touches, best=len(touches), visited=np.array([r.position for r in shown]),
                               visited_normals=np.array([r.normal for r in shown]), **settings)
    score = np.zeros(len(touches))
    for b in plan.best:
        score[b.candidate] = b.score
    return score


def predict(surface, obj, R, T, reading):
    """The training reading of `obj` nearest to `reading` (robot frame) facing within 60 degrees of it, placed at
    (R, T); None when the object has none."""
    q, n = R.T @ (np.array(reading.position) - T), R.T @ np.array(reading.normal)
    row = surface.nearest(obj, q, n, max_deg=60.0)
    return placed(surface.data[row[0]], R, T) if row else None


def predicted_reading_scores(rec, surface, est, shown, candidates):
    """The recognizer as the outcome model (see --train): sum_o p_o log2(p'_o / p_o) over objects holding >= 1%."""
    objects = [(h.object, np.array(h.pose.R), np.array(h.pose.T), float(est.object_probability[h.object]))
               for h in est.object_hypotheses if h.valid and est.object_probability[h.object] >= 0.01]
    total = sum(o[3] for o in objects)
    score = np.zeros(len(candidates))
    for i, c in enumerate(candidates):
        for obj, R, T, p in objects:
            predicted = predict(surface, obj, R, T, c)
            if predicted is not None:
                after = float(session(rec, shown + [predicted], top_k=8).object_probability[obj])
                score[i] += (p / total) * np.log2(max(after, 1e-9) / (p / total))
    return score


def report(name, cases, scores):
    rho, lift, above = [], [], []
    for (shown, candidates, truth, est), score in zip(cases, scores):
        best = int(np.argmax(score))
        rho.append(rank_correlation(score, truth))
        lift.append(truth[best] - np.median(truth))
        above.append(float((truth > truth[best]).mean()))
    print(f"  {name:22s} rank correlation {np.mean(rho):+.3f}   chosen less median {np.mean(lift):+.3f}   "
          f"candidates better than the chosen {100 * np.mean(above):.0f}%")


def rank_study(rec, planner, test, trials, k, surface=None):
    """Per setting: mean rank correlation, the chosen candidate's truth less the median, the share above it."""
    cases = []
    for t, rows, obj, R, T, pool in trials:
        samples = [int(r["sample"]) for r in rows[:k]]
        shown = [placed(test[s], R, T) for s in samples]
        candidates = [placed(test[i], R, T) for i in pool if i not in samples]
        if len(candidates) < 2:
            continue
        cases.append((shown, candidates, truths(rec, shown, candidates, obj), session(rec, shown, top_k=8)))
    print(f"{len(cases)} trials after {k} readings; the truth: the true object's probability with each candidate added")
    for name, settings in SETTINGS:
        report(name, cases, [planner_scores(planner, c[3], c[0], c[1], settings) for c in cases])
    if surface is not None:
        report("predicted readings", cases, [predicted_reading_scores(rec, surface, c[3], c[0], c[1]) for c in cases])
    if cases:
        print(f"  {'(the best candidate)':22s} chosen less median "
              f"{np.mean([c[2].max() - np.median(c[2]) for c in cases]):+.3f}")


def place_study(rec, test, dense, trials, k, near_mm=3.0, near_deg=15.0):
    """The share of the truth's variance (logits) that near-identical places share."""
    variance, half_sq_diff, pairs = [], [], 0
    for t, rows, obj, R, T, pool in trials:
        shown = [placed(test[int(r["sample"])], R, T) for r in rows[:k]]
        idx = converged_rows(dense).get(obj, [])
        y = logit(truths(rec, shown, [placed(dense[i], R, T) for i in idx], obj), eps=1e-4)
        P = np.array([dense[i].reading.position for i in idx])
        N = np.array([dense[i].reading.normal for i in idx])
        iu = np.triu_indices(len(idx), 1)
        dist = np.linalg.norm(P[iu[0]] - P[iu[1]], axis=1)
        angle = np.degrees(np.arccos(np.clip(np.sum(N[iu[0]] * N[iu[1]], axis=1), -1, 1)))
        near = (dist < near_mm) & (angle < near_deg)
        if near.sum() < 2:
            continue
        a, b = y[iu[0][near]], y[iu[1][near]]
        variance.append(y.var())
        half_sq_diff.append(0.5 * np.mean((a - b) ** 2))
        pairs += int(near.sum())
    if not variance:
        print("no near-identical places in the dense set: give it more readings per object")
        return
    share = 1.0 - np.mean(half_sq_diff) / np.mean(variance)
    print(f"the place's share of the truth's variance: {share:.2f} ({len(variance)} trials, {pairs} pairs of places "
          f"within {near_mm:g} mm and {near_deg:g} deg; variance {np.mean(variance):.2f}, between neighbours "
          f"{np.mean(half_sq_diff):.2f})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--map", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--random-csv", required=True)
    ap.add_argument("--readings", type=int, default=3, help="readings of the trial before the touch scored (K)")
    ap.add_argument("--trials", type=int, default=0, help="the first N trials of the CSV (default all)")
    ap.add_argument("--objects", default="", help="only trials of these objects (comma-separated names)")
    ap.add_argument("--dense", help="a second, dense test set of the scene: the place's share of the truth")
    ap.add_argument("--train", help="the map's training set: the recognizer on predicted readings as a planner")
    a = ap.parse_args()
    if a.readings < 1:
        ap.error(f"--readings must be at least 1, got {a.readings}")
    try:
        m, test = sva.Map.load(a.map), sva.Dataset.load(a.data)
        dense = sva.Dataset.load(a.dense) if a.dense else None
        train = sva.Dataset.load(a.train) if a.train else None
    except sva.Error as e:  # names the file and the fault
        ap.error(str(e))
    names = list(m.object_names)
    wanted = [s for s in a.objects.split(",") if s]
    unknown = [s for s in wanted if s not in names]
    if unknown:
        ap.error(f"--objects: {', '.join(unknown)} not in the map {a.map}")
    try:
        trials = [t for t in random_trials(a.random_csv, a.trials, test) if not wanted or names[t[2]] in wanted]
    except (OSError, KeyError, ValueError, IndexError) as e:
        ap.error(f"{a.random_csv}: not a CSV of `sva eval --csv` on this map and test set ({type(e).__name__}: {e})")
    if not trials:
        ap.error(f"no trial of {a.random_csv} is left to study")
    if any(len(t[1]) < a.readings for t in trials):
        ap.error(f"--readings {a.readings}: {a.random_csv} holds fewer readings per trial")
    if dense is not None and (
            dense.scene.name != test.scene.name or list(dense.scene.object_names) != list(test.scene.object_names)):
        ap.error(f"--dense {a.dense}: scene \"{dense.scene.name}\", not the test set's \"{test.scene.name}\" "
                 "with the same objects")
    rec = sva.Recognizer(m, backend="cpu")
    if train is not None and train.scene.name != test.scene.name:
        ap.error(f"--train {a.train}: scene \"{train.scene.name}\", not the test set's \"{test.scene.name}\"")
    rank_study(rec, sva.TouchPlanner(m), test, trials, a.readings, Surface(train) if train else None)
    if dense is not None:
        place_study(rec, test, dense, trials, a.readings)


if __name__ == "__main__":
    sys.exit(main())
