#!/usr/bin/env python3
"""Intersection curves of deforming meshes, frame by frame, from Python: dvh against trueform
(``pip install trueform``: exact arrangements of static meshes) and libigl's CGAL-backed
``intersect_other`` / ``remesh_self_intersections``, on Debian's CGAL demo meshes.

Scenes (each mesh scaled to unit size; a smooth displacement field that changes every frame):

- **two meshes**: the mannequin (25,888 triangles) through the lion (14,859), and the refined
  elephant (88,928) through the armadillo (52,000);
- **one mesh**: the refined elephant folded through itself (its far half turned back through
  its near half), for the self-intersection curves.

Per frame, each repeated ``--reps`` times and the fastest kept, medians over the frames:

- dvh: ``Mesh.refit`` of the meshes and ``intersection_curves`` (or
  ``self_intersection_curves``), the meshes built once before the first frame, as a simulation
  does; also ``collide`` (``self_collide``) on the same frame, the query the curves start from;
- trueform: ``trueform.Mesh`` of each frame's arrays and ``trueform.intersection_curves`` (or
  ``self_intersection_curves``): its meshes are static, so a user rebuilds them every frame;
- libigl: ``igl.copyleft.cgal.intersect_other`` (``remesh_self_intersections`` for one mesh),
  which computes the intersection points exactly and remeshes around them; slower by far, so it
  runs on the first ``--igl-frames`` frames only.

Each frame checks that trueform's curve points are dvh's segment ends (the same points within
1e-9 of the scene's size), but for the points where trueform splits its self curves where three
sheets meet, which must lie inside dvh's segments.

    python python/bench/curves_peers.py [--frames N] [--reps R] [--quick] [--cgal-data ARCHIVE]
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from datetime import datetime, timezone
from importlib import metadata

import numpy as np

import dvh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peers import CGAL_DATA, load_cgal, med, ms, note, progress, ratio, table  # noqa: E402

try:
    import trueform as tf
except ImportError:
    tf = None
try:
    import igl.copyleft.cgal as igl_cgal
except ImportError:
    igl_cgal = None


def unit(V: np.ndarray) -> np.ndarray:
    lo, hi = V.min(axis=0), V.max(axis=0)
    return (V - (lo + hi) / 2) / (hi - lo).max()


def frames(V: np.ndarray, count: int, seed: int, amplitude: float = 0.02):
    """``count`` frames of ``V`` under a smooth displacement field that turns with time."""
    rng = np.random.default_rng(seed)
    k = rng.normal(size=(4, 3)) * 4.0
    d = rng.normal(size=(4, 3))
    phase = rng.uniform(0, 2 * np.pi, 4)
    out = []
    for f in range(count):
        t = 2 * np.pi * f / max(count, 1)
        field = sum(np.sin(V @ k[i] + phase[i] + t)[:, None] * d[i] for i in range(4))
        out.append(np.ascontiguousarray(V + amplitude * field / 4))
    return out


def folded(V: np.ndarray) -> np.ndarray:
    """The far half (x beyond the middle) turned 150 degrees about the vertical axis through
    the middle, back through the near half."""
    V = V.copy()
    far = V[:, 0] > 0
    c, s = np.cos(np.radians(150)), np.sin(np.radians(150))
    x, z = V[far, 0].copy(), V[far, 2].copy()
    V[far, 0], V[far, 2] = c * x - s * z, s * x + c * z
    return V


def fastest(fn, reps: int) -> float:
    best = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def same_points(curves, tf_points, scale: float):
    """(dvh's distinct segment ends, trueform's distinct points, do they match within 1e-9 of
    the scale?) Every dvh end must be one of trueform's points, and every trueform point a dvh
    end or a point inside a dvh segment: trueform's curves of one mesh are an arrangement, split
    where three sheets meet (a point where two of dvh's segments, of different pairs, cross)."""
    ends = np.unique(np.vstack([curves.segments["start"], curves.segments["end"]]), axis=0)
    theirs = np.unique(np.asarray(tf_points, dtype=np.float64).reshape(-1, 3), axis=0)
    tol = 1e-9 * scale

    def nearest(P, Q):
        """For each point of P, the distance to the nearest of Q (by sorted x, then a scan)."""
        order = np.argsort(Q[:, 0])
        Qs = Q[order]
        out = np.empty(len(P))
        for k, p in enumerate(P):
            lo = np.searchsorted(Qs[:, 0], p[0] - tol)
            hi = np.searchsorted(Qs[:, 0], p[0] + tol, side="right")
            out[k] = np.abs(Qs[lo:hi] - p).max(axis=1).min() if hi > lo else np.inf
        return out

    if len(ends) == 0 or len(theirs) == 0:
        return len(ends), len(theirs), len(ends) == len(theirs)
    ours_found = bool((nearest(ends, theirs) <= tol).all())
    extra = theirs[nearest(theirs, ends) > tol]
    if len(extra):
        a, b = curves.segments["start"], curves.segments["end"]
        d = b - a
        for p in extra:
            t = np.clip(((p - a) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-300), 0, 1)
            if np.abs(a + t[:, None] * d - p).max(axis=1).min() > tol:
                return len(ends), len(theirs), False
    return len(ends), len(theirs), ours_found


def timed_frames(name, args, steps):
    """Times each frame's calls: ``steps(f)`` gives the frame's dvh curves and collide calls
    (each refits first), its trueform call (or None) and its libigl call (or None)."""
    rows = {"dvh refit + curves": [], "dvh refit + collide": [], "trueform": [], "libigl": []}
    mismatches, segments = 0, []
    for f in range(args.frames):
        progress(f"  {name}: frame {f + 1}/{args.frames}")
        curves, pairs, trueform, libigl = steps(f)
        rows["dvh refit + curves"].append(fastest(curves, args.reps))
        rows["dvh refit + collide"].append(fastest(pairs, args.reps))
        c = curves()
        segments.append(len(c.segments))
        if trueform is not None:
            rows["trueform"].append(fastest(trueform, args.reps))
            _, points = trueform()
            mismatches += not same_points(c, points, 1.0)[2]
        if libigl is not None and f < args.igl_frames:
            rows["libigl"].append(fastest(libigl, 1))
    return rows, mismatches, segments


def two_meshes(name, A, B, args):
    (VA, FA), (VB, FB) = A, B
    fa, fb = frames(VA, args.frames, 1), frames(VB, args.frames, 2)
    ma, mb = dvh.Mesh(fa[0], FA), dvh.Mesh(fb[0], FB)

    def steps(f):
        def refit():
            ma.refit(fa[f])
            mb.refit(fb[f])

        return (
            lambda: (refit(), dvh.intersection_curves(ma, mb))[1],
            lambda: (refit(), dvh.collide(ma, mb))[1],
            None if tf is None
            else lambda: tf.intersection_curves(tf.Mesh(FA, fa[f]), tf.Mesh(FB, fb[f])),
            None if igl_cgal is None
            else lambda: igl_cgal.intersect_other(fa[f], FA, fb[f], FB),
        )

    return timed_frames(name, args, steps)


def one_mesh(name, M, args):
    V, F = M
    fv = frames(folded(V), args.frames, 3, 0.01)
    m = dvh.Mesh(fv[0], F)

    def steps(f):
        return (
            lambda: (m.refit(fv[f]), dvh.self_intersection_curves(m))[1],
            lambda: (m.refit(fv[f]), dvh.self_collide(m))[1],
            None if tf is None else lambda: tf.self_intersection_curves(tf.Mesh(F, fv[f])),
            None if igl_cgal is None
            else lambda: igl_cgal.remesh_self_intersections(fv[f], F),
        )

    return timed_frames(name, args, steps)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--igl-frames", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="2 frames, 2 reps, the smaller scene")
    ap.add_argument("--cgal-data", default=CGAL_DATA)
    args = ap.parse_args()
    if args.quick:
        args.frames, args.reps, args.igl_frames = 2, 2, 1
    if tf is None:
        note("trueform is not installed (pip install trueform): its rows are skipped")
    if igl_cgal is None:
        note("libigl with igl.copyleft.cgal is not installed (pip install libigl): skipped")
    names = ["mannequin-devil", "lion"] + ([] if args.quick else ["refined_elephant", "armadillo"])
    meshes = load_cgal(args.cgal_data, names)
    missing = [n for n in names if n not in meshes]
    if missing:
        note(f"CGAL demo meshes not found ({', '.join(missing)}): install libcgal-demo")
        return 0
    shifted = lambda VF, d: (unit(VF[0]) + np.array(d), VF[1])  # noqa: E731
    scenes = [
        (
            "mannequin through lion",
            lambda: two_meshes(
                "mannequin through lion",
                shifted(meshes["mannequin-devil"], (0, 0, 0)),
                shifted(meshes["lion"], (0.2, 0.05, 0)),
                args,
            ),
        ),
    ]
    if not args.quick:
        scenes += [
            (
                "refined elephant through armadillo",
                lambda: two_meshes(
                    "refined elephant through armadillo",
                    shifted(meshes["refined_elephant"], (0, 0, 0)),
                    shifted(meshes["armadillo"], (0.2, 0.05, 0)),
                    args,
                ),
            ),
            (
                "refined elephant folded (self)",
                lambda: one_mesh("refined elephant folded", shifted(meshes["refined_elephant"], (0, 0, 0)), args),
            ),
        ]
    versions = {"dvh": dvh.version()}
    for p in ("trueform", "libigl", "numpy"):
        try:
            versions[p] = metadata.version(p)
        except metadata.PackageNotFoundError:
            pass
    print(f"curves_peers.py, {datetime.now(timezone.utc):%Y-%m-%d}, {platform.machine()}, "
          f"{os.cpu_count()} cores; " + ", ".join(f"{k} {v}" for k, v in versions.items()))
    print(f"{args.frames} frames, each call's fastest of {args.reps}, medians over the frames "
          f"(libigl: {args.igl_frames} frames, one call each); both libraries on every core\n")
    out = []
    failed = False
    for title, run in scenes:
        rows, mismatches, segments = run()
        dvh_t = med(rows["dvh refit + curves"])
        line = [title, f"{int(np.median(segments))}", ms(dvh_t),
                f"{med(rows['dvh refit + curves']) / med(rows['dvh refit + collide']):.2f}"]
        for peer in ("trueform", "libigl"):
            t = med(rows[peer])
            line += [ms(t), ratio(t, dvh_t)]
        line.append(str(mismatches))
        failed |= mismatches > 0
        out.append(line)
    print()
    print(table(["scene", "segments", "dvh ms", "dvh curves / collide", "trueform ms", "trueform / dvh",
                 "libigl ms", "libigl / dvh", "frames whose points differ from trueform's"], out))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
