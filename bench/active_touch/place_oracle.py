#!/usr/bin/env python3
"""Readings to a right decision when every touch goes to the best place: how far any planner could go (issue 22,
"The next touch").

The greedy oracle of bench/active_touch/active_touch_oracle.py sees each candidate reading's own draw (its pressure
image, its errors) before it chooses, which no planner can: a planner chooses a place, then touches. This oracle knows
the true object and pose and, for each candidate place, the place's expected outcome: the mean true-object probability
that the readings of a dense test set within --near-mm and --near-deg of it would give (what a perfect outcome model
would predict). It touches the place of highest expected outcome and takes that place's own reading, whose outcome it
did not see. With --see-draws it chooses among the same candidates by their own readings' outcomes instead (the greedy
oracle's rule on the dense set), so the two differ only in what they know. Both are greedy (one touch ahead).

The candidates of a step are --candidates places drawn from the dense set's readings of the true object that have a
neighbour there; the first reading of every trial is the random run's own (nothing is known before it), as for the
active policy and the greedy oracle.

--value asks who predicts a place's outcome: the truth (the oracle above), the belief's own hypotheses (objects
holding at least 1%, at their best modes, weighed by probability: a planner with a perfect outcome model), the
belief's --modes best modes (several per object: a planner that tells poses apart as well), the true
object at the belief's pose for it, or the true object at its true pose moved by --pose-error (how good a pose a
planner needs; with --pose-samples K, the mean over K poses drawn as far about that one: a planner that knows how far
its pose may be off). --refine fits each predicting pose to the readings so far first; --train predicts from the nearest
reading of the map's training set instead of the dense set's (what a planner holding the map has).

  usage: PYTHONPATH=build-ci/python .venv/bin/python bench/active_touch/place_oracle.py --map MAP --data TEST.svad \
             --dense DENSE.svad --random-csv RANDOM.csv [--candidates 20] [--neighbours 4] [--near-mm 3] \
             [--near-deg 15] [--threshold 0.95] [--max-readings 20] [--trials N] [--jobs 2] [--see-draws]
             [--value truth|hypotheses|modes|true-object|noisy-truth] [--modes 16] [--pose-error MM,DEG]
             [--pose-samples 1] [--refine] [--train TRAIN.svad]
RANDOM.csv is `sva eval --policy random --csv` of the same map, data and seed (its first readings and poses); DENSE
is the same scene simulated with many test readings per object (`sva simulate --scene S --train 1 --test 2000
--seed 5`), so that most places have neighbours.
"""
import argparse
import multiprocessing
import sys
from pathlib import Path

import numpy as np

import sva

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))  # bench/lib: the helpers the scripts share
from sva_bench import Surface, decision, placed, random_trials, rotation, score, session  # noqa: E402


def neighbourhoods(places, obj, near_mm, near_deg):
    """Each converged dense reading of obj that has others within near_mm and near_deg of it: those others."""
    near = {}
    for k, i in enumerate(places.index.get(obj, [])):
        hood = places.near(obj, places.position[obj][k], places.normal[obj][k], near_mm, near_deg)
        hood = [j for j in hood if j != i]
        if hood:
            near[i] = hood
    return near


def predicted_value(rec, surface, shown, predictors, place, a, rng):
    """A place's expected outcome as the predictors see it: each (object, weight, R, T) predicts the dense readings
    of its own surface near the place, placed at its pose (R, T); the value is the mean, over the predictors by
    weight, of the predicting object's probability once its predicted reading is added (a predictor with no surface
    there left out)."""
    total, value = 0.0, 0.0
    for obj, weight, R, T in predictors:
        q, n = R.T @ (np.array(place.position) - T), R.T @ np.array(place.normal)
        hood = surface.nearest(obj, q, n, max_mm=10.0) if a.train else surface.near(obj, q, n, a.near_mm, a.near_deg)
        if not hood:
            continue
        if len(hood) > a.neighbours:
            hood = list(rng.choice(hood, size=a.neighbours, replace=False))
        outcome = np.mean([float(session(rec, shown + [placed(surface.data[j], R, T)]).object_probability[obj])
                           for j in hood])
        total, value = total + weight, value + weight * outcome
    return value / total if total > 0 else 0.0


def predictors(rec, shown, obj, R, T, a, rng):
    """Who predicts a place's outcome (--value): the belief's objects holding at least 1% at their best poses
    (hypotheses), its distinct modes (modes), the true object at the belief's pose for it (true-object), or at the
    true pose moved by --pose-error in a random direction (noisy-truth); each spread over --pose-samples poses."""
    if a.value == "noisy-truth":  # the estimate; --pose-samples > 1: poses drawn as far about it
        return spread([(obj, 1.0, *moved(R, T, a.pose_error, rng))], a, rng)
    if a.value == "modes":
        return spread(mode_predictors(session(rec, shown, top_k=a.modes), a), a, rng)
    est = session(rec, shown, top_k=8)
    out = []
    for h in est.object_hypotheses:
        p = float(est.object_probability[h.object]) if a.value == "hypotheses" else float(h.object == obj)
        if h.valid and p >= 0.01:
            Rh, Th = np.array(h.pose.R), np.array(h.pose.T)
            if a.refine:
                Rh, Th = refine(shown, worker["outcomes"], h.object, Rh, Th)
            out.append((h.object, p, Rh, Th, np.array(h.covariance)))
    return spread(out, a, rng)


def spread(out, a, rng):
    """Each predictor (object, weight, R, T[, covariance]) as it is, or with --pose-samples K > 1 as K predictors of
    a K-th of its weight at poses drawn about its own: --pose-error away (a fixed spread), or from its mode's
    covariance (--spread covariance; ROS order, mm and rad, the rotation applied on the left)."""
    if a.pose_samples == 1:
        return [p[:4] for p in out]
    drawn = []
    for obj, weight, R, T, *cov in out:
        for _ in range(a.pose_samples):
            if a.spread == "covariance":
                vals, vecs = np.linalg.eigh(cov[0])
                d = vecs @ (np.sqrt(np.clip(vals, 0.0, None)) * rng.normal(size=6))
                drawn.append((obj, weight / a.pose_samples, rotation(d[3:]) @ R, T + d[:3]))
            else:
                drawn.append((obj, weight / a.pose_samples, *moved(R, T, a.pose_error, rng)))
    return drawn


def moved(R, T, error, rng):
    """The pose (R, T) turned by error[1] degrees and shifted by error[0] mm, each in a random direction."""
    axis, shift = rng.normal(size=3), rng.normal(size=3)
    turn = rotation(axis / np.linalg.norm(axis) * np.radians(error[1]))
    return R @ turn, T + error[0] * shift / np.linalg.norm(shift)


def mode_predictors(est, a):
    """The belief's distinct modes (up to --modes, several per object where it holds them), each weighed by its
    object's probability times its share of that object's modes' mass: a planner that tells poses apart too."""
    mass = {}
    for h in est.hypotheses:
        mass[h.object] = mass.get(h.object, 0.0) + h.probability
    out = []
    for h in est.hypotheses:
        p = float(est.object_probability[h.object]) * h.probability / mass[h.object] if mass[h.object] > 0 else 0.0
        if p >= 0.01:
            out.append((h.object, p, np.array(h.pose.R), np.array(h.pose.T), np.array(h.covariance)))
    return out


def refine(shown, surface, obj, R, T, iterations=15, normal_mm=3.0, huber_mm=1.0):
    """The pose (R, T) of obj fitted to the shown readings: each contact against its nearest surface reading,
    point to plane, and its normal against that reading's normal (a radian counting as normal_mm), Gauss-Newton
    with Huber weights and a little damping towards the start. A stand-in for the engine's fine pose, run from the
    first readings on (the engine's starts at 6)."""
    if obj not in surface.position:
        return R, T
    P, N = surface.position[obj], surface.normal[obj]
    R0, T0 = R, T
    X, Nx = np.array([r.position for r in shown]), np.array([r.normal for r in shown])
    for _ in range(iterations):
        Y, Ny = (X - T) @ R, Nx @ R  # the contacts in the object's frame
        d = ((Y[:, None, :] - P[None]) ** 2).sum(-1)
        d[Ny @ N.T < 0.5] = np.inf  # a contact pairs with surface facing its way (within 60 degrees)
        if not np.isfinite(d.min(1)).all():
            return R0, T0
        j = d.argmin(1)
        p, n = P[j], N[j]
        r_point = np.einsum("ij,ij->i", n, Y - p)
        w = 1.0 / np.maximum(1.0, np.abs(r_point) / huber_mm)
        # Unknowns: a small turn u and shift t of the contacts in the object's frame (y -> y + u x y + t).
        A = [np.hstack([np.cross(Y, n), n]) * w[:, None]]
        b = [-r_point * w]
        for k in range(len(Y)):  # the normal turned: ny + u x ny = n, i.e. -[ny]x u = n - ny
            skew = np.array([[0, -Ny[k, 2], Ny[k, 1]], [Ny[k, 2], 0, -Ny[k, 0]], [-Ny[k, 1], Ny[k, 0], 0]])
            A.append(np.hstack([-skew, np.zeros((3, 3))]) * normal_mm)
            b.append((n[k] - Ny[k]) * normal_mm)
        A, b = np.vstack(A), np.concatenate(b)
        x = np.linalg.solve(A.T @ A + 1e-3 * np.eye(6), A.T @ b)
        u, t = x[:3], x[3:]
        turn = rotation(u)
        # y' = turn y + t with y = R^T (x - T): R' = R turn^T, T' = T - R' t.
        R = R @ turn.T
        T = T - R @ t
        if np.linalg.norm(u) < 1e-5 and np.linalg.norm(t) < 1e-4:
            break
    return R, T


def run_trial(job):
    """Readings to a right decision for one trial (max_readings + 1 for a wrong or no decision)."""
    a, (t, rows, obj, R, T, _) = job
    rec, test, dense = worker["rec"], worker["test"], worker["dense"]
    near = neighbourhoods(worker["places"], obj, a.near_mm, a.near_deg)
    rng = np.random.default_rng(1000 + t)
    shown = [placed(test[int(rows[0]["sample"])], R, T)]
    used = set()
    est = session(rec, shown)
    for n in range(1, a.max_readings + 1):
        d = decision(est, a.threshold)
        if d is not None:
            return t, obj, (n if d == obj else a.max_readings + 1)
        if n == a.max_readings:
            break
        places = [i for i in near if i not in used]
        if not places:
            raise NoPlace(f"trial {t}: no place of {worker['test'].scene.object_names[obj]} left with a neighbour "
                          f"within {a.near_mm:g} mm and {a.near_deg:g} deg in the dense set: give it more readings")
        if len(places) > a.candidates:
            places = list(rng.choice(places, size=a.candidates, replace=False))
        best, best_value = None, -1.0
        if a.value != "truth":
            who = predictors(rec, shown, obj, R, T, a, rng)
        for i in places:
            if a.value != "truth":
                value = predicted_value(rec, worker["outcomes"], shown, who, placed(dense[i], R, T), a, rng)
            elif a.see_draws:
                value = score(session(rec, shown + [placed(dense[i], R, T)]), obj)
            else:
                hood = near[i] if len(near[i]) <= a.neighbours else list(
                    rng.choice(near[i], size=a.neighbours, replace=False))
                value = np.mean([score(session(rec, shown + [placed(dense[j], R, T)]), obj) for j in hood])
            if value > best_value:
                best, best_value = i, value
        used.add(best)
        shown.append(placed(dense[best], R, T))
        est = session(rec, shown)
    return t, obj, a.max_readings + 1


worker = {}


class NoPlace(ValueError):
    """A trial's object has no candidate place left (raised in a worker, reported by main)."""


def start_worker(map_path, data_path, dense_path, train_path):
    m = sva.Map.load(map_path)
    dense = sva.Dataset.load(dense_path)
    places = Surface(dense)
    outcomes = Surface(sva.Dataset.load(train_path)) if train_path else places
    worker.update(rec=sva.Recognizer(m, backend="cpu", threads=1), test=sva.Dataset.load(data_path), dense=dense,
                  places=places, outcomes=outcomes)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--map", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--dense", required=True, help="the scene simulated with many test readings per object")
    ap.add_argument("--random-csv", required=True)
    ap.add_argument("--trials", type=int, default=0, help="the first N trials of the CSV (default all)")
    ap.add_argument("--threshold", type=float, default=0.95)
    ap.add_argument("--candidates", type=int, default=20, help="places tried per step")
    ap.add_argument("--neighbours", type=int, default=4, help="readings near a place that estimate its outcome")
    ap.add_argument("--near-mm", type=float, default=3.0)
    ap.add_argument("--near-deg", type=float, default=15.0)
    ap.add_argument("--max-readings", type=int, default=20)
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (one recognizer on one thread each)")
    ap.add_argument("--see-draws", action="store_true", help="choose by each candidate's own reading instead")
    ap.add_argument("--value", choices=["truth", "hypotheses", "modes", "true-object", "noisy-truth"], default="truth",
                    help="a place's value: the true object's expected probability at the true pose (the oracle); the "
                         "belief's own expectation from its hypotheses' objects and poses (a planner with a perfect "
                         "outcome model); the same from each of the belief's distinct modes (modes); the true "
                         "object's alone at the belief's pose for it (what the pose costs); or at the true pose moved "
                         "by --pose-error")
    ap.add_argument("--train", help="the map's training set: predicted readings and --refine's surface from it (the "
                                     "nearest reading, as a planner holding the map would), not from the dense set")
    ap.add_argument("--refine", action="store_true",
                    help="fit each predicting object's pose to the readings so far first (hypotheses, true-object)")
    ap.add_argument("--modes", type=int, default=16, help="--value modes: the belief's modes asked (default 16)")
    ap.add_argument("--pose-error", default="2,10", help="MM,DEG: noisy-truth's pose error (default 2,10)")
    ap.add_argument("--pose-samples", type=int, default=1,
                    help="poses drawn about each predicting pose, the value their mean (a planner that knows how far "
                         "its poses may be off; default 1, the pose alone): --pose-error away, or with --spread "
                         "covariance from the mode's covariance (not for noisy-truth)")
    ap.add_argument("--spread", choices=["fixed", "covariance"], default="fixed",
                    help="--pose-samples' spread: --pose-error (fixed) or each mode's covariance")
    a = ap.parse_args()
    for name in ("candidates", "neighbours", "jobs", "modes", "pose_samples"):
        if getattr(a, name) < 1:
            ap.error(f"--{name.replace('_', '-')} must be at least 1, got {getattr(a, name)}")
    if not (a.near_mm > 0 and 0 < a.near_deg <= 180):
        ap.error(f"--near-mm must be positive and --near-deg in (0, 180], got {a.near_mm} and {a.near_deg}")
    try:
        test, dense = sva.Dataset.load(a.data), sva.Dataset.load(a.dense)
        sva.Map.load(a.map)
    except sva.Error as e:  # names the file and the fault
        ap.error(str(e))
    if dense.scene.name != test.scene.name or list(dense.scene.object_names) != list(test.scene.object_names):
        ap.error(f"--dense {a.dense}: scene \"{dense.scene.name}\", not the test set's \"{test.scene.name}\" "
                 "with the same objects")
    trials = random_trials(a.random_csv, a.trials, test)
    try:
        pose_error = [float(x) for x in a.pose_error.split(",")]
        if len(pose_error) != 2 or not all(np.isfinite(pose_error)) or min(pose_error) < 0:
            raise ValueError
    except ValueError:
        ap.error(f"--pose-error: expected MM,DEG (two numbers >= 0), got \"{a.pose_error}\"")
    a.pose_error = pose_error
    if a.see_draws and a.value != "truth":
        ap.error(f"--see-draws and --value {a.value}: choose one")
    if a.pose_samples > 1 and a.value == "truth":
        ap.error("--pose-samples: the place oracle knows the true pose; give another --value")
    if a.spread == "covariance" and a.value in ("truth", "noisy-truth"):
        ap.error(f"--spread covariance: --value {a.value} has no mode covariance; use hypotheses, modes or true-object")
    rule = ("its own reading (sees the draw)" if a.see_draws else
            f"the mean of up to {a.neighbours} readings near it" +
            {"truth": "", "hypotheses": " for each hypothesis (object, pose) of the belief",
             "modes": f" for each of the belief's {a.modes} best modes",
             "true-object": " of the true object at the belief's pose for it",
             "noisy-truth": f" of the true object at the true pose moved by {a.pose_error[0]:g} mm and "
                            f"{a.pose_error[1]:g} deg" + (f", averaged over {a.pose_samples} poses as far about it"
                                                        if a.pose_samples > 1 else "")}[a.value])
    if a.pose_samples > 1 and a.value != "noisy-truth":
        rule += f", each pose spread over {a.pose_samples} drawn " + (
            "from its mode's covariance" if a.spread == "covariance" else
            f"{a.pose_error[0]:g} mm and {a.pose_error[1]:g} deg away")
    print(f"{len(trials)} trials; each step {a.candidates} candidate places, each valued by {rule}", flush=True)
    readings, fault = [], None
    # Workers from a fork server, not forked from this process (a forked copy of the engine's threads may hold a lock),
    # and the pool closed and joined, never terminated: Pool.terminate() hung at 300 s in 1 run of 3 here, after every
    # trial had printed, joining a worker that the pool's own handler had started behind it (py-spy: the main thread
    # in Pool._terminate_pool's join, the worker waiting for a task on the queue's lock).
    pool = multiprocessing.get_context("forkserver").Pool(a.jobs, start_worker, (a.map, a.data, a.dense, a.train))
    try:
        for t, obj, r in pool.imap(run_trial, [(a, tr) for tr in trials]):
            readings.append(r)
            print(f"{t:5d} {test.scene.object_names[obj]:16s} {r:5d}", flush=True)
    except NoPlace as e:
        fault = e
    finally:
        pool.close()  # the trials still queued after a fault run out; each is bounded by --max-readings
        pool.join()
    if fault is not None:
        ap.error(f"--dense {a.dense}: {fault}")
    who = "place oracle (sees the draws)" if a.see_draws else {
        "truth": "place oracle", "hypotheses": "planner (the belief's hypotheses, dense outcomes)",
        "modes": "planner (the belief's modes, dense outcomes)",
        "true-object": "place oracle at the belief's pose", "noisy-truth": "place oracle at a noisy pose"}[a.value]
    print(f"trials {len(readings)}: {who} mean readings to a right "
          f"decision at {a.threshold}: {sum(readings) / len(readings):.2f} (no decision within {a.max_readings} "
          f"counts {a.max_readings + 1})")


if __name__ == "__main__":
    sys.exit(main())
