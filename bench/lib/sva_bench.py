"""The helpers the bench scripts share (bench/README.md): one home each, so that two studies never differ by a copy.

A script in bench/<folder>/ imports it with

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))
    import sva_bench

and finds the sva package itself on PYTHONPATH (build-ci/python, or an installed one) where a helper needs it.

- logit: the log-odds, clipped
- object_families: each object's family in a scene (its own name when it has none)
- converged_rows, Surface: a dataset's converged readings by object, and the nearest of them to a place
- rotation, placed: a `sva eval` trial's true pose, and a reading moved by it
- random_trials, replay, session: the trials of a `sva eval --csv` run, replayed through a recognizer
- decision, score: when a session decides at a threshold, and how much it gives the true object
"""

from __future__ import annotations

import csv
import json
from collections import defaultdict

import numpy as np


def logit(p, eps: float = 1e-9):
    """log(p / (1 - p)), p clipped to [eps, 1 - eps] so that a certain 0 or 1 stays finite."""
    p = np.clip(p, eps, 1 - eps)
    return np.log(p / (1 - p))


def object_families(scene) -> dict[str, str]:
    """Each object's family by name in a loaded scene (`sva.load_scene`); an object without one is its own."""
    return {o["name"]: o.get("family") or o["name"] for o in json.loads(scene.to_json())["objects"]}


def converged_rows(data) -> dict[int, list[int]]:
    """The rows of the dataset's converged readings, by object (objects in the order they first appear)."""
    rows: dict[int, list[int]] = {}
    for i in range(len(data)):
        s = data[i]
        if s.converged:
            rows.setdefault(s.object, []).append(i)
    return rows


class Surface:
    """Each object's converged readings of a dataset, by contact and normal (object frame): where an object's
    surface was touched, for the reading a hypothesis predicts at a place."""

    def __init__(self, data):
        self.data, self.index = data, converged_rows(data)
        self.position = {o: np.array([data[i].reading.position for i in ix]) for o, ix in self.index.items()}
        self.normal = {o: np.array([data[i].reading.normal for i in ix]) for o, ix in self.index.items()}

    def nearest(self, obj, position, normal, max_mm=np.inf, max_deg=60.0):
        """The row of obj's reading nearest to a place in obj's frame, facing within max_deg of it, if within max_mm
        (a list of one row, or empty)."""
        if obj not in self.position:
            return []
        d = np.linalg.norm(self.position[obj] - position, axis=1)
        d[self.normal[obj] @ normal <= np.cos(np.radians(max_deg))] = np.inf
        j = int(np.argmin(d))
        return [self.index[obj][j]] if np.isfinite(d[j]) and d[j] <= max_mm else []

    def near(self, obj, position, normal, near_mm, near_deg):
        """The rows of obj's readings within near_mm and near_deg of a place given in obj's frame."""
        if obj not in self.position:
            return []
        ok = (np.linalg.norm(self.position[obj] - position, axis=1) < near_mm) & (
            self.normal[obj] @ normal > np.cos(np.radians(near_deg)))
        return [self.index[obj][j] for j in np.flatnonzero(ok)]


def rotation(rv):
    """Rodrigues vector -> 3x3 rotation (the CSV's true_rx, true_ry, true_rz)."""
    th = float(np.linalg.norm(rv))
    if th < 1e-12:
        return np.eye(3)
    k = rv / th
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * K @ K


def placed(sample, R, T):
    """The sample's reading (object frame, as a dataset stores it) moved to the pose (R, T)."""
    import sva  # here, not at the top: calibration_study.py imports this module on NumPy alone, without the package

    r = sample.reading
    return sva.Reading(np.array(r.pressure), R @ np.array(r.position) + T, R @ np.array(r.normal),
                       R @ np.array(r.x_axis))


def random_trials(random_csv, count, test):
    """The random run's trials, first `count` (0: all): (trial, rows by reading, object, R, T, the rows of the
    object's converged test readings)."""
    trials = defaultdict(list)
    with open(random_csv) as f:
        for row in csv.DictReader(f):
            trials[int(row["trial"])].append(row)
    converged = converged_rows(test)
    out = []
    for t in sorted(trials)[: count or None]:
        rows = sorted(trials[t], key=lambda r: int(r["readings"]))
        obj = int(rows[0]["object"])
        R = rotation(np.array([float(rows[0][k]) for k in ("true_rx", "true_ry", "true_rz")]))
        T = np.array([float(rows[0][k]) for k in ("true_tx", "true_ty", "true_tz")])
        out.append((t, rows, obj, R, T, list(converged.get(obj, []))))
    return out


def session(rec, readings, top_k=1):
    """A fresh session of the (placed) readings; its estimate (top_k 8: every object's best mode too)."""
    rec.reset()
    for r in readings:
        rec.add_reading(r)
    return rec.estimate(top_k)


def replay(rec, samples, test, R, T):
    """A fresh session of the test readings `samples`, placed at (R, T); its estimate."""
    return session(rec, [placed(test[s], R, T) for s in samples])


def decision(est, threshold):
    """None, "unknown" or the decided object's id."""
    if est.p_unknown >= threshold:
        return "unknown"
    top = int(np.argmax(est.object_probability))
    if (1.0 - est.p_unknown) * float(est.object_probability[top]) >= threshold:
        return top
    return None


def score(est, obj):
    """The probability the estimate gives obj, "none of these" included."""
    return (1.0 - est.p_unknown) * float(est.object_probability[obj])
