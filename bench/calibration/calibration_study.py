#!/usr/bin/env python3
"""Calibration families compared offline on the sessions bench/calibration/calibration_study.cpp wrote (PREFIX.*.jsonl).

    python3 bench/calibration/calibration_study.py PREFIX [--blocks N] [--weights]

Mirrors host/src/calibration (calibration.cpp, calibration_fit.cpp): the temperature tau(n) = scale (n-1)^-power with
the surface weight on a grid of halvings, fitted by the NLL of the true object; the top label, a logistic regression
of "the top is right" on the logit of the tempered top probability per regime (before the fine pose, from it on),
the second phased in over the fine pose's first five readings, never surer than the temperature past one half (and,
as earlier builds applied it, the second at once); and, tried and left (docs/evaluation.md, "600 trials, and the first
fine poses"), the top label linear in log(n - 1) within each regime and one per band of reading counts. Prints the
ECE of the test sessions (10 bins of the top object's probability, every step from 2 readings on) overall and by
reading range, and the share confidently wrong. --blocks N: also the temperature and top label fitted on each disjoint
block of N known sessions of the map of every object (the fit's noise between draws of `sva train`'s sessions).
--weights: also, for surface weights 1/8 to 1, the test steps' share right by reading range under the fitted
temperature, and the ECE with the weight held there and the temperature and top label fitted again (docs/evaluation.md,
"The surface weight that ranks best is not the one that calibrates best").
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))  # bench/lib: the helpers the scripts share
from sva_bench import logit  # noqa: E402

RANGES = [(2, 5), (6, 10), (11, 20), (21, 30)]
WEIGHTS = [0.0, 1 / 32, 1 / 16, 1 / 8, 1 / 4, 1 / 2, 1.0]


def load(path: str, first: int = 0, last: int | None = None) -> dict:
    """Every step from 2 readings on of the known sessions (those numbered first to last - 1): n, the true object, L and
    G (objects padded)."""
    rows = []
    known = 0
    with open(path) as f:
        for line in f:
            s = json.loads(line)
            if not s["known"]:
                continue
            known += 1
            if known <= first or (last is not None and known > last):
                continue
            fine_from = min([st["n"] for st in s["steps"] if st["share"] >= 0], default=0)
            rows += [(st["n"], s["object"], st["L"], st["G"], st["share"], fine_from) for st in s["steps"]
                     if st["n"] >= 2]
    k = max(len(r[2]) for r in rows)
    d = {"n": np.array([r[0] for r in rows], float), "obj": np.array([r[1] for r in rows]),
         "L": np.full((len(rows), k), -1e6), "G": np.zeros((len(rows), k)),
         "fine": np.array([r[4] >= 0 for r in rows]), "fine_from": np.array([r[5] for r in rows], float)}
    for i, r in enumerate(rows):
        d["L"][i, :len(r[2])] = r[2]
        d["G"][i, :len(r[3])] = r[3]
    return d


def posterior(d, scale, power, weight):
    tau = np.minimum(scale * (d["n"] - 1.0) ** (-power), 4.0)  # Calibration::kMaxTemperature
    q = tau[:, None] * d["L"] + weight * d["G"]
    p = np.exp2(q - q.max(1, keepdims=True))
    return p / p.sum(1, keepdims=True)


def nll(d, scale, power, weight):
    p = posterior(d, scale, power, weight)
    return -np.log(np.maximum(p[np.arange(len(p)), d["obj"]], 1e-300)).sum()


def golden(f, lo, hi, iterations=40):
    phi = 0.6180339887498949
    m1, m2 = hi - phi * (hi - lo), lo + phi * (hi - lo)
    f1, f2 = f(m1), f(m2)
    for _ in range(iterations):
        if f1 < f2:
            hi, m2, f2 = m2, m1, f1
            m1 = hi - phi * (hi - lo)
            f1 = f(m1)
        else:
            lo, m1, f1 = m1, m2, f2
            m2 = lo + phi * (hi - lo)
            f2 = f(m2)
    return (m1, f1) if f1 < f2 else (m2, f2)


def fit_temperature(d, weights=WEIGHTS):
    best = (np.inf, 0.25, 0.8, 0.25)
    for w in weights:
        for power in np.arange(0.0, 2.51, 0.05):
            x, f = golden(lambda ls: nll(d, 2.0 ** ls, power, w), -12.0, 3.0)
            if f < best[0]:
                best = (f, 2.0 ** x, power, w)
    return best[1:]


def top_and_right(d, t):
    p = posterior(d, *t)
    return p.max(1), p.argmax(1) == d["obj"]


def newton(x, y, ridge=1e-3, start=None):
    """Unweighted logistic regression by Newton steps, every weight but the bias held by a small ridge."""
    w = np.zeros(x.shape[1]) if start is None else np.array(start, float)
    r = np.full(x.shape[1], ridge)
    r[0] = 1e-9
    for _ in range(50):
        p = 1 / (1 + np.exp(-np.clip(x @ w, -700, 700)))
        g = x.T @ (p - y) / len(y) + r * w
        h = (x * (p * (1 - p))[:, None]).T @ x / len(y) + np.diag(r)
        w = w - np.linalg.solve(h, g)
    return w


def fit_top_label(d, t):
    top, right = top_and_right(d, t)
    labels = []
    for regime in (False, True):
        m = d["fine"] == regime
        x = np.stack([np.ones(m.sum()), logit(top[m])], 1)
        y = right[m].astype(float)
        labels.append(newton(x, y, start=[0.0, 1.0]) if 0 < y.sum() < len(y) else np.array([0.0, 1.0]))
    return labels


def platt(ab, top):
    """The top label's map of the top probability, never surer than the temperature left it past one half."""
    now = 1 / (1 + np.exp(-np.clip(ab[:, 0] + ab[:, 1] * logit(top), -700, 700)))
    return np.minimum(now, np.maximum(top, 0.5))


def fit_top_label_pooled(d, t):
    """Per regime, a and b linear in log(n - 1): logit p' = a0 + a1 l + (b0 + b1 l) logit p."""
    top, right = top_and_right(d, t)
    labels = []
    for regime in (False, True):
        m = d["fine"] == regime
        z, l = logit(top[m]), np.log(d["n"][m] - 1)
        x = np.stack([np.ones(m.sum()), z, l, l * z], 1)
        y = right[m].astype(float)
        labels.append(newton(x, y, start=[0, 1, 0, 0]) if 0 < y.sum() < len(y) else np.array([0.0, 1, 0, 0]))
    return labels


def relabel_pooled(d, top, labels, n_max):
    w = np.where(d["fine"][:, None], labels[1], labels[0])
    l = np.log(np.minimum(d["n"], n_max) - 1)
    z = logit(top)
    now = 1 / (1 + np.exp(-np.clip(w[:, 0] + w[:, 1] * z + w[:, 2] * l + w[:, 3] * l * z, -700, 700)))
    return np.minimum(now, np.maximum(top, 0.5))


BANDS = [(2, 5), (6, 8), (9, 1000)]


def fit_top_label_bands(d, t):
    """One {a, b} per band of reading counts (the last band open-ended)."""
    top, right = top_and_right(d, t)
    labels = []
    for a, b in BANDS:
        m = (d["n"] >= a) & (d["n"] <= b)
        x = np.stack([np.ones(m.sum()), logit(top[m])], 1)
        y = right[m].astype(float)
        labels.append(newton(x, y, start=[0, 1]) if 0 < y.sum() < len(y) else np.array([0.0, 1]))
    return labels


def relabel_bands(d, top, labels):
    ab = np.zeros((len(top), 2))
    for (a, b), w in zip(BANDS, labels):
        ab[(d["n"] >= a) & (d["n"] <= b)] = w
    return platt(ab, top)


BLEND_READINGS = 5.0  # Calibration::kTopLabelBlendReadings


def relabel(d, top, labels, blend=BLEND_READINGS):
    """This build's top label: the fine-pose regime phased in over its first `blend` readings (0: at once)."""
    w = np.ones(len(top)) if blend == 0 else np.clip((d["n"] - d["fine_from"] + 1) / blend, 0, 1)
    w = np.where(d["fine"], w, 0.0)[:, None]
    return platt((1 - w) * labels[0] + w * labels[1], top)


def ece(top, right):
    b = np.minimum((top * 10).astype(int), 9)
    return sum(abs(top[b == k].sum() - right[b == k].sum()) for k in range(10)) / len(top)


def report(name, d, top, right):
    parts = " ".join(f"{ece(top[(d['n'] >= a) & (d['n'] <= b)], right[(d['n'] >= a) & (d['n'] <= b)]):.3f}"
                     for a, b in RANGES)
    wrong = 100 * ((top >= 0.99) & ~right).mean()
    print(f"{name:<52} ECE {ece(top, right):.4f}   by readings {parts}   confidently wrong {wrong:.2f}%")


def shares_right(test, right) -> str:
    return " / ".join(f"{100 * right[(test['n'] >= a) & (test['n'] <= b)].mean():.1f}" for a, b in RANGES)


def surface_weights(d, test) -> None:
    """Ranking and calibration as the surface weight varies (--weights): each weight's share right under the fitted
    temperature and its ECE with the temperature and top label fitted again at it; then the top object ranked with
    two and four times the fitted weight while its probability stays the calibrated posterior's (the ranked object's
    own, scaled as the top label scaled the rest where it is not the calibrated top)."""
    fitted = fit_temperature(d)
    scale, power, weight = fitted
    for w in (0.125, 0.25, 0.5, 1.0):
        right = posterior(test, scale, power, w).argmax(1) == test["obj"]
        t = fit_temperature(d, [w])
        top, right_refit = top_and_right(test, t)
        report(f"w {w}: right {shares_right(test, right)}%; held, refitted", test,
               relabel(test, top, fit_top_label(d, t)), right_refit)
    p = posterior(test, *fitted)
    top = p.max(1)
    calibrated = relabel(test, top, fit_top_label(d, fitted))
    rest = (1 - calibrated) / np.maximum(1 - top, 1e-12)
    for k in (2, 4):
        ranked = posterior(test, scale, power, k * weight).argmax(1)
        same = ranked == p.argmax(1)
        prob = np.where(same, calibrated, p[np.arange(len(p)), ranked] * rest)
        right = ranked == test["obj"]
        report(f"ranked at w {k * weight:g}, calibrated at {weight:g}: right {shares_right(test, right)}%, "
               f"{100 * (~same).mean():.1f}% of steps name another object", test, prob, right)


def main() -> None:
    ap = argparse.ArgumentParser(description="Calibration families compared offline (calibration_study.sh writes PREFIX.*)")
    ap.add_argument("prefix", help="the sessions' prefix: PREFIX.test.jsonl, PREFIX.every_object.jsonl, ...")
    ap.add_argument("--blocks", type=int, metavar="N", help="also fit each disjoint block of N known sessions")
    ap.add_argument("--weights", action="store_true", help="also the surface weights' ranking and calibration")
    args = ap.parse_args()
    if args.blocks is not None and args.blocks < 1:
        ap.error(f"--blocks {args.blocks}: expected at least 1 session per block")
    prefix = args.prefix
    test = load(prefix + ".test.jsonl")
    print(f"{len(test['n'])} test steps; ECE by readings: " + ", ".join(f"{a}-{b}" for a, b in RANGES))
    for sessions in ("objects_held_out", "every_object"):
        d = load(f"{prefix}.{sessions}.jsonl")
        t = fit_temperature(d)
        top, right = top_and_right(test, t)
        report(f"temperature from {sessions} ({t[0]:.3f} (n-1)^-{t[1]:.2f}, w {t[2]:.3g})", test, top, right)
        labels = fit_top_label(d, t)
        report(f"  + top label {np.round(labels[0], 2)} {np.round(labels[1], 2)}", test, relabel(test, top, labels),
               right)
        report("  + the same, the fine-pose label at once", test, relabel(test, top, labels, 0), right)
        pl = fit_top_label_pooled(d, t)
        report("  + top label linear in log(n-1)", test, relabel_pooled(test, top, pl, d["n"].max()), right)
        bl = fit_top_label_bands(d, t)
        report(f"  + top label per band {BANDS}", test, relabel_bands(test, top, bl), right)
    if args.blocks:
        size = args.blocks
        total = sum(1 for line in open(f"{prefix}.every_object.jsonl") if json.loads(line)["known"])
        for first in range(0, total - size + 1, size):
            d = load(f"{prefix}.every_object.jsonl", first, first + size)
            t = fit_temperature(d)
            top, right = top_and_right(test, t)
            labels = fit_top_label(d, t)
            report(f"sessions {first}-{first + size - 1}: {t[0]:.3f} (n-1)^-{t[1]:.2f}, w {t[2]:.3g}, label "
                   f"{np.round(labels[1], 2)}", test, relabel(test, top, labels), right)
    if args.weights:
        surface_weights(load(f"{prefix}.every_object.jsonl"), test)
    t = fit_temperature(test)
    top, right = top_and_right(test, t)
    report(f"temperature fitted to the test sessions ({t[0]:.3f}, {t[1]:.2f}, {t[2]:.3g})", test, top, right)


if __name__ == "__main__":
    main()
