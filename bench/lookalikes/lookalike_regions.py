#!/usr/bin/env python3
"""Share of each look-alike's surface that differs from its family twins (docs/evaluation.md, "Look-alikes").

Reads the meshes in assets/objects; needs, outside the project's set-up, a Python
environment with numpy, scipy, trimesh and libigl:
    python3 -m venv /tmp/regions && /tmp/regions/bin/pip install numpy scipy trimesh libigl
    /tmp/regions/bin/python bench/lookalikes/lookalike_regions.py --samples 200000 --frames file --out regions.md
(about 17 minutes on one core for both frames).

For every family in assets/scenes/lookalikes.json and every member A:
sample N points uniformly by area on A's touchable (exterior) surface; for each
point, the distance to the nearest point of the exterior surface of every other
member B. Then

  f_A(t)   share of A's samples farther than t mm from at least one other member
  f_all    share farther than 0.5 mm from every other member
  P15/P30  1 - (1 - f_A(0.5))^k: chance that at least one of k touches placed
           uniformly on A's surface lands in the differing region.

Geometry notes
* Distances are exact point-triangle distances (libigl AABB tree), cross-checked
  against trimesh.proximity.closest_point on a subset of every pair.
* The generator builds objects as unions of closed parts without booleans, so
  some triangles are buried inside other parts (ribbon over a box, blades over
  each other, a handle's ends inside a mug wall). A point is "buried" when the
  generalized winding number of its own mesh, 0.05 mm to both sides of the
  surface, is >= 0.5 on both sides. A's samples are kept only where exposed
  (the raw all-triangle figure is also given), and where A's nearest point on B
  is buried, the distance is recomputed against B's exterior: exact against B's
  faces that are not fully buried if that nearest point is exposed; otherwise
  U = min(exact distance to B's fully exposed faces, nearest of a dense sample
  (0.05 mm spacing, capped at 4M points) of the exposed part of B's partially
  buried faces). U overestimates by at most about the sample spacing; the share
  of points with 0.5 < U <= 0.5 + spacing (and lower bound <= 0.5) is reported
  as "ambiguous".
* Frames: "file" = meshes as stored (scaled about the origin to size_mm, a no-op
  here); "sim" = as sim/src/mesh.cpp fit_mesh loads them: scale to size_mm and
  move the bounding-box centre to the origin (SceneObject::center defaults to
  true and lookalikes.json doesn't set it).

Usage: venv/bin/python differ.py [--samples 200000] [--seed 1] [--frames file,sim] [--out table.md]
"""
import argparse
import json
import os
import sys
import time

import igl
import numpy as np
import trimesh
from scipy.spatial import cKDTree

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "scenes", "lookalikes.json")
THRESHOLDS = (0.5, 1.0, 2.0)
EPS = 0.05  # mm, offset for the winding-number exposure test
DENSITY = 400.0  # samples per mm^2 on partially buried faces (0.05 mm spacing)
DENSE_CAP = 4_000_000


def load_raw(obj, scene_dir):
    path = os.path.normpath(os.path.join(scene_dir, obj["mesh"]))
    m = trimesh.load(path, force="mesh", process=False)  # node transforms applied
    return np.asarray(m.vertices, dtype=np.float64), np.asarray(m.faces, dtype=np.int64)


def frame_transform(V, obj, frame):
    lo, hi = V.min(0), V.max(0)
    largest = (hi - lo).max()
    scale = obj["size_mm"] / largest if obj.get("size_mm", 0) > 0 else 1.0
    shift = 0.5 * (lo + hi) if (frame == "sim" and obj.get("center", True)) else np.zeros(3)
    return shift, scale  # x_frame = (x - shift) * scale


class Obj:
    """One member: its mesh in the file frame plus exposure data (frame-invariant)."""

    def __init__(self, obj, scene_dir):
        self.o = obj
        self.name = obj["name"]
        self.V, self.F = load_raw(obj, scene_dir)
        self.mesh = trimesh.Trimesh(self.V, self.F, process=False)
        self.N = self.mesh.face_normals
        self._dense = None
        # per-face exposure: 10 interior test points per face
        bary = np.array([[1, 1, 1], [4, 1, 1], [1, 4, 1], [1, 1, 4], [2, 2, 1], [2, 1, 2], [1, 2, 2],
                         [8, 1, 1], [1, 8, 1], [1, 1, 8]], float)
        bary /= bary.sum(1, keepdims=True)
        T = self.V[self.F]  # f x 3 x 3
        P = np.einsum("kj,fjd->fkd", bary, T).reshape(-1, 3)
        fi = np.repeat(np.arange(len(self.F)), len(bary))
        b = self.buried(P, fi).reshape(len(self.F), len(bary))
        self.face_all_buried = b.all(1)
        self.face_all_exposed = ~b.any(1)

    def buried(self, P, fi):
        n = self.N[fi]
        wo = igl.fast_winding_number(self.V, self.F, P + EPS * n)
        wi = igl.fast_winding_number(self.V, self.F, P - EPS * n)
        return np.minimum(np.abs(wo), np.abs(wi)) >= 0.5

    def dense_exposed(self, seed):
        """Exposed points on B's partially buried faces, ~DENSITY per mm^2 (capped)."""
        if self._dense is None:
            part = np.nonzero(~self.face_all_buried & ~self.face_all_exposed)[0]
            sub = trimesh.Trimesh(self.V, self.F[part], process=False)
            area = sub.area
            n = int(np.clip(area * DENSITY, 10_000, DENSE_CAP))
            P, fi = trimesh.sample.sample_surface(sub, n, seed=seed + 7)
            P = np.asarray(P, float)
            ok = ~self.buried(P, part[fi])
            self._dense = P[ok]
            self.dense_spacing = float(np.sqrt(area / n))
        return self._dense


def dist(P, V, F):
    d2, I, C = igl.point_mesh_squared_distance(P, V, F)
    return np.sqrt(np.maximum(d2, 0)), I, C


def exterior_distance(P, B, shift, scale, seed):
    """Distance from points P (frame coords) to B's exterior surface (B placed by shift/scale)."""
    Vb = (B.V - shift) * scale
    d, I, C = dist(P, Vb, B.F)
    C_file = C / scale + shift
    flag = B.buried(C_file, I)
    stats = {"flagged": flag.mean(), "ambiguous": 0.0}
    if flag.any():
        idx = np.nonzero(flag)[0]
        Q = P[idx]
        keepF = B.F[~B.face_all_buried]
        L, I2, C2 = dist(Q, Vb, keepF)
        fidx2 = np.nonzero(~B.face_all_buried)[0][I2]
        ok = ~B.buried(C2 / scale + shift, fidx2)
        res = L.copy()
        bad = np.nonzero(~ok)[0]
        if len(bad):
            expF = B.F[B.face_all_exposed]
            U1, _, _ = dist(Q[bad], Vb, expF) if len(expF) else (np.full(len(bad), np.inf), 0, 0)
            dense = (B.dense_exposed(seed) - shift) * scale
            U2, _ = cKDTree(dense).query(Q[bad])
            U = np.minimum(U1, U2)
            res[bad] = U
            h = B.dense_spacing * scale  # U overestimates by at most ~h
            stats["ambiguous"] = ((L[bad] <= 0.5) & (U > 0.5) & (U <= 0.5 + h)).sum() / len(P)
            stats["spacing"] = h
        d[idx] = res
    return d, stats


def run(frame, objs, members_by_fam, n, seed, check_n):
    results, maxerr, notes = {}, 0.0, []
    for fam, names in members_by_fam.items():
        rows = []
        for an in names:
            A = objs[an]
            sA, kA = frame_transform(A.V, A.o, frame)
            # pilot for the exposed share, then sample enough to keep ~n exposed points
            P, fi = trimesh.sample.sample_surface(A.mesh, n, seed=seed)
            P = np.asarray(P, float)
            expo = ~A.buried(P, fi)
            raw_P, raw_exp = P, expo
            if expo.mean() < 0.999:
                m = int(np.ceil(n / max(expo.mean(), 0.05) * 1.02))
                P2, fi2 = trimesh.sample.sample_surface(A.mesh, m, seed=seed + 1)
                P2 = np.asarray(P2, float)
                e2 = ~A.buried(P2, fi2)
                P = P2[e2][:n]
            else:
                P = P[expo]
            P = (P - sA) * kA
            raw_P = (raw_P - sA) * kA
            area = A.mesh.area * kA ** 2
            dists, raw_dists, pair_stats = {}, {}, {}
            for bn in names:
                if bn == an:
                    continue
                B = objs[bn]
                sB, kB = frame_transform(B.V, B.o, frame)
                d, st = exterior_distance(P, B, sB, kB, seed)
                dists[bn] = d
                pair_stats[bn] = st
                # raw: all of A's triangles, plain distance to all of B's triangles (no exposure logic)
                raw_dists[bn], _, _ = dist(raw_P, (B.V - sB) * kB, B.F)
                if check_n:
                    Bm = trimesh.Trimesh((B.V - sB) * kB, B.F, process=False)
                    _, dt, _ = trimesh.proximity.closest_point(Bm, raw_P[:check_n])
                    maxerr = max(maxerr, float(np.abs(dt - raw_dists[bn][:check_n]).max()))
            D = np.stack(list(dists.values()), 1)
            dmax, dmin = D.max(1), D.min(1)
            Rd = np.stack(list(raw_dists.values()), 1)
            f = (dmax > 0.5).mean()
            row = {
                "name": an, "area": area, "exposed": raw_exp.mean(), "n": len(P),
                **{f"f{t}": (dmax > t).mean() for t in THRESHOLDS},
                "f_all": (dmin > 0.5).mean(),
                "P15": 1 - (1 - f) ** 15, "P30": 1 - (1 - f) ** 30,
                "f_raw": (Rd.max(1) > 0.5).mean(), "f_all_raw": (Rd.min(1) > 0.5).mean(),
                "pair": {bn: (dv > 0.5).mean() for bn, dv in dists.items()},
                "amb": max(s["ambiguous"] for s in pair_stats.values()),
                "flag": max(s["flagged"] for s in pair_stats.values()),
            }
            rows.append(row)
            print(f"[{frame}] {fam}/{an}: n={len(P)} f0.5={f:.4f} f_all={row['f_all']:.4f} "
                  f"exposed={row['exposed']:.3f} flagged<= {row['flag']:.3f} ambiguous<= {row['amb']:.4f}",
                  file=sys.stderr, flush=True)
        results[fam] = rows
    return results, maxerr


def pct(x):
    return "n/a" if (isinstance(x, float) and np.isnan(x)) else f"{100 * x:.1f}%"


KEYS = ["f0.5", "f1.0", "f2.0", "f_all", "P15", "P30", "exposed", "f_raw", "f_all_raw"]
COLS = ["f@0.5", "f@1.0", "f@2.0", "f_all@0.5", "P15", "P30",
        "exposed share of mesh area", "f@0.5 raw", "f_all raw"]


def table(results, frame, n):
    out = [f"### Frame: {frame}", "",
           "| family | member | " + " | ".join(COLS) + " | f@0.5 vs each other member |",
           "|" + "---|" * (len(COLS) + 3)]
    fam_means = []
    for fam, rows in results.items():
        for r in rows:
            pair = ", ".join(f"{bn} {pct(v)}" for bn, v in r["pair"].items())
            out.append(f"| {fam} | {r['name']} | " + " | ".join(pct(r[k]) for k in KEYS) + f" | {pair} |")
        mean = {k: float(np.mean([r[k] for r in rows])) for k in KEYS}
        fam_means.append(mean)
        out.append(f"| **{fam}** | **mean** | " + " | ".join(f"**{pct(mean[k])}**" for k in KEYS) + " |  |")
    allrows = [r for rows in results.values() for r in rows]
    mean = {k: float(np.mean([r[k] for r in allrows])) for k in KEYS}
    out.append(f"| **all {len(allrows)} objects** | **mean** | " + " | ".join(f"**{pct(mean[k])}**" for k in KEYS) + " |  |")
    amb = max(r["amb"] for r in allrows)
    out += ["", f"Max share of any member's samples whose exterior distance to a twin is ambiguous "
                f"about 0.5 mm (0.5 < upper bound <= 0.5 + dense-sample spacing): {100 * amb:.2f}%.", ""]
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=200000, help="exposed samples per member")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--frames", default="file,sim")
    ap.add_argument("--check", type=int, default=2000, help="points per pair cross-checked with trimesh")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "table.md"))
    args = ap.parse_args()
    scene = json.load(open(SCENE))
    scene_dir = os.path.dirname(SCENE)
    olist = [o for o in scene["objects"] if o.get("family")]
    t0 = time.time()
    objs = {o["name"]: Obj(o, scene_dir) for o in olist}
    fams = {}
    for o in olist:
        fams.setdefault(o["family"], []).append(o["name"])

    lines = ["## Units and frames (bounding boxes as stored in the .glb)", "",
             "| family | member | size_mm | largest bbox extent | scale to size_mm | bbox min | bbox max | sim-frame shift (bbox centre) |",
             "|---|---|---|---|---|---|---|---|"]
    for o in olist:
        V = objs[o["name"]].V
        lo, hi = V.min(0), V.max(0)
        sh, sc = frame_transform(V, o, "sim")
        lines.append(f"| {o['family']} | {o['name']} | {o['size_mm']} | {(hi - lo).max():.3f} | {sc:.5f} | "
                     f"{np.round(lo, 2).tolist()} | {np.round(hi, 2).tolist()} | {np.round(sh, 2).tolist()} |")
    lines.append("")

    parts = [f"# Differing surface share per look-alike", "",
             f"N = {args.samples} uniform-by-area samples per member on its exposed (touchable) surface, seed {args.seed}; "
             "f@t = share farther than t mm from at least one twin's exterior; f_all = farther than 0.5 mm from every twin; "
             "P_k = 1-(1-f@0.5)^k. 'raw' columns: uniform over all triangles (buried ones too), "
             "plain distance to all of the twin's triangles.", ""]
    errs = []
    for frame in args.frames.split(","):
        res, err = run(frame, objs, fams, args.samples, args.seed, args.check)
        errs.append(f"{frame}: {err:.1e} mm")
        parts.append(table(res, frame, args.samples))
    parts.append(f"Cross-check, max |libigl - trimesh.proximity.closest_point| over {args.check} points per pair: "
                 + "; ".join(errs) + ".")
    parts.append(f"\nCompute time: {time.time() - t0:.0f} s (wall).\n")
    parts += lines
    text = "\n".join(parts)
    open(args.out, "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
