#!/usr/bin/env python3
"""How far random touches can tell look-alikes apart at all: the ceiling of any recognizer (docs/evaluation.md,
"What random touches can tell under the sensor's pad").

    PYTHONPATH=build-ci/python python3 bench/lookalikes/family_ceiling.py TEST.svad SCENE [--gaps 1,2] [--draws 300]

For every test reading of a family's member (its contact in the object's frame, as the dataset stores it), the
largest gap between the member's surface and each sibling's under the sensor's pad: the member's surface points
within the pad's half-width of the contact (in its tangent plane) and within 1 mm of the contact plane (what the pad
can press), their distance to the sibling's mesh, and the sibling's points there to the member's (the meshes as the
simulator places them). A reading tells the member from a sibling when that gap exceeds GAP mm. The ceiling at n
readings is E[1 / members left] over random draws of n of the member's test readings (a sibling is left while no
drawn reading tells them apart): what a recognizer that used every such difference perfectly, with perfect poses,
would score by guessing among what is left. It ignores appearance-only differences finer than GAP (the pressure
image's own detail) and lets a sibling move only by the translation that lays its surface onto the member's (the
simulator centres each mesh's bounding box: shift_onto), never turn, so it is optimistic in pose and pessimistic only
in what the image alone might show. Objects without siblings count as told apart.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import sva

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "lib"))  # bench/lib: the helpers the scripts share
from sva_bench import converged_rows, object_families  # noqa: E402

DEPTH_MM = 1.0  # how far off the contact plane the pad still presses (the skin's indentation is 0.2 mm at 20 kPa)


def closest_distance(p: np.ndarray, v: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Distance from each point of p (n, 3) to the triangle mesh (v, t): Ericson's closest point, vectorised."""
    a, b, c = (v[t[:, k]].astype(float) for k in range(3))
    ab, ac, bc = b - a, c - a, c - b
    out = np.empty(len(p))
    for s in range(0, len(p), 64):
        x = p[s:s + 64, None, :]
        ap, bp, cp = x - a, x - b, x - c
        d1, d2 = (ab * ap).sum(-1), (ac * ap).sum(-1)
        d3, d4 = (ab * bp).sum(-1), (ac * bp).sum(-1)
        d5, d6 = (ab * cp).sum(-1), (ac * cp).sum(-1)
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        with np.errstate(divide="ignore", invalid="ignore"):
            denom = va + vb + vc
            q = a + ab * (vb / denom)[..., None] + ac * (vc / denom)[..., None]
            q_ab = a + ab * (d1 / (d1 - d3))[..., None]
            q_ac = a + ac * (d2 / (d2 - d6))[..., None]
            q_bc = b + bc * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[..., None]
        for cond, y in (((va <= 0) & (d4 >= d3) & (d5 >= d6), q_bc), ((vb <= 0) & (d2 >= 0) & (d6 <= 0), q_ac),
                        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), q_ab), ((d6 >= 0) & (d5 <= d6), c),
                        ((d3 >= 0) & (d4 <= d3), b), ((d1 <= 0) & (d2 <= 0), a)):
            q = np.where(cond[..., None], y, q)
        out[s:s + 64] = np.sqrt(((x - q) ** 2).sum(-1)).min(1)
    return out


def surface_points(v: np.ndarray, t: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """n points uniform over the mesh's area."""
    a, b, c = (v[t[:, k]].astype(float) for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    k = rng.choice(len(t), size=n, p=area / area.sum())
    u, w = rng.random(n), rng.random(n)
    flip = u + w > 1
    u[flip], w[flip] = 1 - u[flip], 1 - w[flip]
    return a[k] + (b[k] - a[k]) * u[:, None] + (c[k] - a[k]) * w[:, None]


REACH_MM = 10.0  # gaps are measured up to this (a surface farther than that from the pad counts as this far)


def near_triangles(mesh, centre: np.ndarray, radius: float):
    """The mesh's triangles with a vertex within `radius` of `centre` (the pad's neighbourhood: far ones cannot be
    the closest to a point under the pad when a near one exists within REACH_MM)."""
    v, t = mesh
    near = np.linalg.norm(v - centre, axis=1) <= radius
    return v, t[near[t].any(1)]


def pad_gap(p, n, half_width, own_points, other_points, own_mesh, other_mesh) -> np.ndarray:
    """Per reading (p, n): the largest gap between the two surfaces under the pad, at most REACH_MM."""
    out = np.zeros(len(p))
    for i in range(len(p)):
        for points, mesh in ((own_points, other_mesh), (other_points, own_mesh)):
            d = points - p[i]
            h = d @ n[i]
            lateral = np.linalg.norm(d - h[:, None] * n[i], axis=1)
            under = points[(lateral <= half_width) & (np.abs(h) <= DEPTH_MM)]
            if not len(under):
                continue
            v, t = near_triangles(mesh, p[i], half_width + DEPTH_MM + REACH_MM)
            gap = np.minimum(closest_distance(under, v, t), REACH_MM) if len(t) else np.full(len(under), REACH_MM)
            out[i] = max(out[i], gap.max())
    return out


def shift_onto(own_points: np.ndarray, other_points: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The translation that lays the sibling's surface onto the member's: translation-only ICP from 1,000 of the
    member's points to 10,000 of the sibling's, each step the median of the nearest offsets, so that the region where
    they differ does not pull it. The simulator centres each mesh's bounding box, so siblings whose boxes differ (a
    longer handle, a taller cap) sit shifted against each other, a shift the pose estimate absorbs."""
    probe = own_points[rng.choice(len(own_points), size=min(1000, len(own_points)), replace=False)]
    target = other_points[rng.choice(len(other_points), size=min(10000, len(other_points)), replace=False)]
    shift = np.zeros(3)
    for _ in range(20):
        moved = target - shift
        nearest = np.empty_like(probe)
        for s in range(0, len(probe), 200):
            d = ((probe[s:s + 200, None, :] - moved[None, :, :]) ** 2).sum(-1)
            nearest[s:s + 200] = moved[d.argmin(1)]
        step = np.median(nearest - probe, axis=0)
        shift += step
        if np.linalg.norm(step) < 0.01:
            break
    return shift


def ceiling(tells: np.ndarray, n: int, draws: int, rng: np.random.Generator) -> float:
    """E[1 / members left] after n of the member's readings (tells: readings x siblings)."""
    left = [1 + (~tells[rng.choice(len(tells), size=min(n, len(tells)), replace=False)].any(0)).sum()
            for _ in range(draws)]
    return float(np.mean(1.0 / np.array(left)))


def readings_by_object(test) -> tuple[dict, dict, dict]:
    """The converged test readings' contacts and normals per object (object frame), and their rows in the dataset
    (in the same order)."""
    rows = converged_rows(test)
    return ({o: np.array([test[i].reading.position for i in v], float) for o, v in rows.items()},
            {o: np.array([test[i].reading.normal for i in v], float) for o, v in rows.items()},
            {o: np.array(v) for o, v in rows.items()})


def family_gaps(scene, members, position, normal, half_width, n_points, rng) -> dict:
    """Per member: the pad gap of each of its readings to each sibling (readings x siblings)."""
    mesh = {o: scene.object_mesh(o) for o in members}
    points = {o: surface_points(*mesh[o], n_points, rng) for o in members}
    gap = {}
    for o in members:
        columns = []
        for s in members:
            if s == o:
                continue
            shift = shift_onto(points[o], points[s], rng)
            moved = (mesh[s][0] - shift, mesh[s][1])
            columns.append(pad_gap(position[o], normal[o], half_width, points[o], points[s] - shift, mesh[o], moved))
        gap[o] = np.stack(columns, 1)
    return gap


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("test", help="a test dataset (.svad) of the scene")
    ap.add_argument("scene", help="the scene (built-in name or JSON file) whose objects name their family")
    ap.add_argument("--gaps", default="1,2", help="gaps in mm that tell two surfaces apart (comma-separated)")
    ap.add_argument("--draws", type=int, default=300, help="random draws of readings per member and count")
    ap.add_argument("--points", type=int, default=40000, help="surface points per mesh")
    a = ap.parse_args()
    try:
        gaps = [float(x) for x in a.gaps.split(",")]
    except ValueError:
        sys.exit(f"family_ceiling.py: --gaps {a.gaps!r}: expected numbers in mm, comma-separated")
    if not gaps or min(gaps) <= 0 or a.draws < 1 or a.points < 100:
        sys.exit("family_ceiling.py: --gaps must be positive, --draws at least 1, --points at least 100")
    try:
        test = sva.Dataset.load(a.test)
        scene = sva.load_scene(a.scene)
    except Exception as e:  # the package's errors name the file and the fault
        sys.exit(f"family_ceiling.py: {e}")
    families: dict[str, list[int]] = {}
    for i, family in enumerate(object_families(scene).values()):
        families.setdefault(family, []).append(i)
    if list(test.scene.object_names) != list(scene.object_names):
        sys.exit(f"family_ceiling.py: {a.test} is not a dataset of scene {a.scene!r} (its objects differ)")
    position, normal, _ = readings_by_object(test)
    half_width = 0.5 * max(scene.sensor.rows, scene.sensor.cols) * scene.sensor.pitch_mm
    rng = np.random.default_rng(1)
    counts = (5, 10, 15, 30)
    total = {(g, n): 0.0 for g in gaps for n in counts}
    objects = len(scene.object_names)
    print(f"pad half-width {half_width:.1f} mm; per gap: the share of each member's readings that tell it from a "
          f"sibling, and the ceiling at {' / '.join(map(str, counts))} readings")
    for family, members in families.items():
        if len(members) < 2:
            for g in gaps:
                for n in counts:
                    total[(g, n)] += 1.0
            continue
        if any(o not in position for o in members):
            sys.exit(f"family_ceiling.py: a member of {family!r} has no converged test reading in {a.test}")
        gap = family_gaps(scene, members, position, normal, half_width, a.points, rng)
        for g in gaps:
            shares = " ".join(f"{(gap[o] > g).any(1).mean():.2f}" for o in members)
            row = []
            for n in counts:
                c = np.mean([ceiling(gap[o] > g, n, a.draws, rng) for o in members])
                total[(g, n)] += c * len(members)
                row.append(c)
            print(f"{family:<20} gap {g:>4} mm  telling {shares:<24} ceiling " + " / ".join(f"{x:.2f}" for x in row),
                  flush=True)
    for g in gaps:
        ceilings = " / ".join(f"{total[(g, n)] / objects:.3f}" for n in counts)
        print(f"scene {scene.name}, gap {g} mm: ceiling {ceilings} at {' / '.join(map(str, counts))} readings")


if __name__ == "__main__":
    main()
