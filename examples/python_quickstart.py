"""sva from Python in one page: simulate the tiny built-in scene, train a map, recognise an object from a stream of
touches, and plot the belief (a PNG, matplotlib's Agg backend: no display needed).

    .venv/bin/python examples/python_quickstart.py [--out DIR]

Run it after `pip install .` (or with PYTHONPATH=build-ci/python in the ci preset's build tree).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sva  # noqa: E402


def rotation_z(deg: float) -> np.ndarray:
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None, help="where the datasets, map and figure go (default: a temp dir)")
    args = ap.parse_args()
    out = args.out or Path(tempfile.mkdtemp(prefix="sva-quickstart-"))
    out.mkdir(parents=True, exist_ok=True)

    # 1. Simulated touches of the tiny scene's two objects (Embree, docs/sensor-model.md).
    train, test = sva.simulate("tiny", train=20, test=8, seed=1, out=out)
    print(f"simulated {len(train)} training and {len(test)} test readings of {train.scene.object_names}")

    # 2. The SVA map of the training readings.
    m = sva.train(train, out=out / "map.svam")
    print(f"trained {m}")

    # 3. A robot touches the brick, lying rotated by 30 degrees and shifted: test readings of object 1 moved into
    #    the robot frame by that pose (readings are in the object's frame in simulation).
    truth = sva.RigidPose(rotation_z(30.0), [15.0, -10.0, 0.0])
    touches = [s.reading for s in test if s.object == 1 and s.converged]  # unconverged touches are refused
    rec = sva.Recognizer(m, backend="auto")
    probabilities, errors = [], []
    for r in touches:
        moved = sva.Reading(r.pressure, truth.apply(r.position), truth.R @ r.normal, truth.R @ r.x_axis)
        rec.add_reading(moved)
        est = rec.estimate()
        probabilities.append(est.object_probability)
        err = np.linalg.norm(est.pose.T - truth.T) if est.pose_valid else np.nan
        errors.append(err)
        print(f"{est.readings:2d} readings: {est.object_name:6s} p={est.object_probability[est.object]:.3f}"
              f"  translation error {err:6.1f} mm")

    # 4. The belief against the number of touches.
    P = np.array(probabilities)
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.5))
    for k, name in enumerate(m.object_names):
        a.plot(range(1, len(P) + 1), P[:, k], marker="o", label=name)
    a.set(xlabel="readings", ylabel="P(object)", title="object belief (truth: brick)", ylim=(-0.05, 1.05))
    a.legend()
    b.plot(range(1, len(errors) + 1), errors, marker="o", color="C2")
    b.set(xlabel="readings", ylabel="mm", title="translation error of the estimate")
    fig.tight_layout()
    png = out / "quickstart.png"
    fig.savefig(png, dpi=100)
    print(f"final: {est.object_name} ({est.object_probability[est.object]:.3f}); wrote {png}")


if __name__ == "__main__":
    main()
