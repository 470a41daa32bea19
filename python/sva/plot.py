"""The command line's figures, drawn by matplotlib for notebooks (docs/python.md, "Figures").

Each function takes what ``sva eval`` writes (the JSON summary as a dict, e.g. from :func:`sva.evaluate`, or the path
of its ``--json`` / ``--confusion`` file) and returns a :class:`matplotlib.figure.Figure`, to show inline or to save
as PNG, SVG or PDF (``fig.savefig("fig.svg")``)::

    import sva, sva.plot
    summary = sva.evaluate("map.svam", "test.svad", trials=4, max_readings=5)
    fig = sva.plot.curves(summary)            # accuracy and the three pose errors against the readings
    fig = sva.plot.reliability(summary)       # the calibration's reliability diagram
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Optional, Sequence, Union

Summary = Union[dict, str, "os.PathLike[str]"]

# The panels of the paper's Fig. 4/5, as `sva eval --plot` draws them: (curve key, title, axis label, scale).
_PANELS = [
    ("accuracy", "(a) classification accuracy", "accuracy (%)", 100.0),
    ("inertial_error_mm", "(b) inertial error", "median inertial distance (mm)", 1.0),
    ("translation_error_mm", "(c) translational error", "median |T_hat - T| (mm)", 1.0),
    ("angular_error_deg", "(d) angular error", "median angle (deg)", 1.0),
]


def _load(summary: Summary) -> dict:
    if isinstance(summary, dict):
        return summary
    path = Path(summary)
    try:
        return json.loads(path.read_text())
    except OSError as e:
        raise ValueError(f"{path}: cannot read: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}: not JSON: {e}") from None


def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError("sva.plot needs matplotlib (pip install 'sva[examples]')") from e
    return plt


def _label(s: dict) -> str:
    return f"{s.get('method', 'sva')} ({s.get('trials', '?')} trials)"


def curves(summary: Summary, *compare: Summary, labels: Optional[Sequence[str]] = None) -> Any:
    """Accuracy and the median inertial, translational and angular errors against the number of readings: the
    four panels of ``sva eval --plot``, with each of ``compare`` (other runs' summaries of the same scene) on the
    same axes."""
    plt = _pyplot()
    runs = [_load(summary)] + [_load(c) for c in compare]
    if labels is not None and len(labels) != len(runs):
        raise ValueError(f"sva.plot.curves: {len(labels)} labels for {len(runs)} runs")
    for r in runs:
        if not isinstance(r.get("curve"), list):
            raise ValueError("sva.plot.curves: a summary without a 'curve' (the JSON of sva eval --json)")
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5), constrained_layout=True)
    fig.suptitle(f"{runs[0].get('scene', '')}: {_label(runs[0])}")
    for ax, (key, title, ylabel, scale) in zip(axes.ravel(), _PANELS):
        for i, r in enumerate(runs):
            pts = [(p["readings"], p[key] * scale) for p in r["curve"] if p.get(key) is not None]
            if not pts:
                continue  # the appearance-only method has no pose errors
            x, y = zip(*pts)
            ax.plot(x, y, marker="o", markersize=3, label=labels[i] if labels else _label(r))
        ax.set_title(title)
        ax.set_xlabel("number of readings")
        ax.set_ylabel(ylabel)
        ax.set_ylim(0, 100 if key == "accuracy" else None)
        ax.grid(True, color="0.88")
        if ax.lines:
            ax.legend(loc="best")
    return fig


def reliability(summary: Summary) -> Any:
    """The reliability diagram of ``sva eval --reliability``: per bin of the top object's probability, the share of
    trial-readings that were right against the bin's mean probability, with the bins' counts and the ECE."""
    plt = _pyplot()
    s = _load(summary)
    cal = s.get("calibration")
    if not isinstance(cal, dict) or not isinstance(cal.get("reliability"), list):
        raise ValueError("sva.plot.reliability: a summary without calibration.reliability (sva eval --json)")
    bins = cal["reliability"]
    n = len(bins)
    fig, (ax, counts) = plt.subplots(2, 1, figsize=(6, 7), height_ratios=[3, 1], sharex=True,
                                     constrained_layout=True)
    centres = [(i + 0.5) / n for i in range(n)]
    used = [b["count"] > 0 for b in bins]
    ax.bar([c for c, u in zip(centres, used) if u], [b["accuracy"] for b, u in zip(bins, used) if u],
           width=1.0 / n, edgecolor="black", color="#1f77b4", alpha=0.8, label="share right")
    ax.plot([0, 1], [0, 1], color="0.4", linestyle="--", label="calibrated")
    ax.plot([b["confidence"] for b, u in zip(bins, used) if u], [b["accuracy"] for b, u in zip(bins, used) if u],
            "o", color="#ff7f0e", label="mean probability")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_ylabel("share right")
    ax.set_title(f"{s.get('scene', '')}: ECE {cal.get('ece', float('nan')):.4f}, "
                 f"confidently wrong {100 * cal.get('confidently_wrong', 0):.2f}%")
    ax.legend(loc="upper left")
    counts.bar(centres, [b["count"] for b in bins], width=1.0 / n, color="0.6", edgecolor="black")
    counts.set_xlabel("top object's probability")
    counts.set_ylabel("trial-readings")
    return fig


def confusion(matrices: Summary, readings: Optional[int] = None) -> Any:
    """The confusion matrix of ``sva eval --confusion`` (its JSON), rows the touched objects and columns the
    estimates in family order, each cell its share of the row's trials; ``readings`` picks one of the reading
    counts (default the last)."""
    plt = _pyplot()
    data = _load(matrices)
    all_ = data.get("confusion")
    if not isinstance(all_, list) or not all_:
        raise ValueError("sva.plot.confusion: no 'confusion' matrices (the JSON of sva eval --confusion)")
    if readings is None:
        m = all_[-1]
    else:
        picked = [c for c in all_ if c.get("readings") == readings]
        if not picked:
            have = [c.get("readings") for c in all_]
            raise ValueError(f"sva.plot.confusion: no matrix at {readings} readings (there are {have})")
        m = picked[0]
    counts = m["counts"]
    shares = [[c / max(sum(row), 1) for c in row] for row in counts]
    size = max(4.0, 0.18 * len(m["estimates"]) + 2)
    fig, ax = plt.subplots(figsize=(size + 1, size), constrained_layout=True)
    image = ax.imshow(shares, cmap="viridis", vmin=0, vmax=1, interpolation="nearest")
    ax.set_xticks(range(len(m["estimates"])), m["estimates"], rotation=90, fontsize=7)
    ax.set_yticks(range(len(m["truths"])), m["truths"], fontsize=7)
    ax.set_xlabel("estimate")
    ax.set_ylabel("touched object")
    right = sum(counts[i][m["estimates"].index(t)] for i, t in enumerate(m["truths"]) if t in m["estimates"])
    total = sum(sum(row) for row in counts)
    ax.set_title(f"confusion at {m['readings']} readings ({total} trials, {100 * right / max(total, 1):.1f}% right)")
    fig.colorbar(image, ax=ax, label="share of the row's trials")
    return fig
