#!/usr/bin/env python3
"""dvh's point queries (``dvh.closest_points``, ``dvh.signed_distances``,
``dvh.winding_numbers``) against the Python peers that answer the same questions, in one run, on
a scanned mesh that deforms every frame:

- pysdf (``SDF``: ``update()`` after the vertices move, ``sdf`` for signed distances, positive
  inside, and ``contains``),
- Open3D (``RaycastingScene``: no refit, so rebuilt every frame; ``compute_signed_distance`` and
  ``compute_closest_points``, float32),
- fcpw (``scene_3D`` with its vectorized BVH: ``update_object_vertices`` + ``refit``, then
  ``find_closest_points`` and ``contains``, float32; ``contains`` through its list overload,
  since the NumPy one leaves its result unwritten),
- libigl (``igl.signed_distance``, which builds its tree inside every call; the first frame
  only: it is the slowest by far).

The mesh is CGAL's refined elephant (Debian's libcgal-demo, 88,928 triangles, closed), every
vertex moved each frame by a travelling wave along its direction from the centroid (up to 2 %
of the bounding box's diagonal). The points, 1 million (``--points``), are of two kinds: *box*,
uniform in the mesh's bounding box grown by 10 % on every side (an SDF grid's points: most far
from the surface), and *near*, points of the surface moved off it by up to 1 % of the diagonal
(a solver's particles, a cloth's vertices). Every method uses both cores where it can (dvh,
pysdf with ``n_threads=2``, Open3D, fcpw); times are medians over frames of wall time per frame,
the peers' rebuilds and refits included as their users pay them.

Signs are compared with dvh's, which are exact (the winding number decided by exact
predicates; the Rust tests judge it against exact brute force): a peer's *wrong signs* are the
points it puts on the other side. Distances: the largest difference from dvh's (exact, within
an ulp), over the bounding box's diagonal.

Prints Markdown tables to stdout, progress to stderr; ``--out DIR`` also writes
``points.json``. Needs dvh (``pip install ./python``), NumPy and the peers from PyPI (a missing
peer is skipped with a note):

    python -m venv .pts && .pts/bin/pip install ./python pysdf open3d fcpw libigl
    .pts/bin/python python/bench/points_peers.py [--quick] [--points N] [--frames K]

pysdf builds from source (it needs Eigen: ``apt-get install libeigen3-dev``, and
``CPATH=/usr/include/eigen3``); Open3D needs ``libusb-1.0-0``. On 2 cores the full run takes
about 3 minutes; --quick (100,000 points, the elephant of 5,558 triangles) about 10 seconds.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tarfile
import tempfile
import time
from datetime import datetime, timezone
from importlib import metadata

import numpy as np

import dvh

CGAL_DATA = os.environ.get("DVH_CGAL_DATA", "/usr/share/doc/libcgal-demo/data.tar.gz")
perf = time.perf_counter
notes: list[str] = []


def note(msg: str) -> None:
    notes.append(msg)
    print(f"note: {msg}", file=sys.stderr, flush=True)


def progress(msg: str) -> None:
    print(f"... {msg}", file=sys.stderr, flush=True)


def optional(name: str):
    try:
        return __import__(name)
    except Exception as e:  # a peer that fails to load (a missing system library) is skipped
        note(f"{name} not available ({type(e).__name__}: {e}); skipped")
        return None


def read_cgal_mesh(name: str):
    """A mesh of CGAL's demo data as (positions, triangles), read by dvh's own OFF reader."""
    with tarfile.open(CGAL_DATA) as tar, tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, f"{name}.off")
        with open(path, "wb") as f:
            f.write(tar.extractfile(f"data/meshes/{name}.off").read())
        positions, triangles = dvh.read_mesh(path)
    return positions, triangles.astype(np.uint32)


def uv_sphere(n: int):
    """A closed UV sphere of n rings and 2n segments: (positions, triangles)."""
    rings = [[0, 0, 1.0]]
    for i in range(1, n):
        th = np.pi * i / n
        for j in range(2 * n):
            ph = np.pi * j / n
            rings.append([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
    rings.append([0, 0, -1.0])
    tris = []
    ring = lambda i, j: 1 + (i - 1) * 2 * n + j % (2 * n)
    for j in range(2 * n):
        tris.append([0, ring(1, j), ring(1, j + 1)])
        tris.append([len(rings) - 1, ring(n - 1, j + 1), ring(n - 1, j)])
        for i in range(1, n - 1):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            tris += [[a, c, b], [b, c, d]]
    return np.array(rings), np.array(tris, dtype=np.uint32)


def wave(rest: np.ndarray, t: float, amplitude: float) -> np.ndarray:
    """The rest positions moved by a travelling wave along their direction from the centroid."""
    c = rest.mean(axis=0)
    r = rest - c
    u = r / np.maximum(np.linalg.norm(r, axis=1, keepdims=True), 1e-300)
    k = 2 * np.pi / np.ptp(rest, axis=0).max()
    s = np.sin(3 * k * rest[:, 0] + t) * np.cos(2 * k * rest[:, 1] - 0.5 * t)
    return rest + amplitude * s[:, None] * u


def sample_points(positions, triangles, n: int, kind: str, diag: float, rng):
    if kind == "box":
        lo, hi = positions.min(axis=0), positions.max(axis=0)
        grow = 0.1 * (hi - lo)
        return lo - grow + rng.random((n, 3)) * (hi - lo + 2 * grow)
    tri = positions[triangles]
    area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    pick = rng.choice(len(triangles), size=n, p=area / area.sum())
    a, b = rng.random(n), rng.random(n)
    flip = a + b > 1
    a[flip], b[flip] = 1 - a[flip], 1 - b[flip]
    t = tri[pick]
    on = t[:, 0] + a[:, None] * (t[:, 1] - t[:, 0]) + b[:, None] * (t[:, 2] - t[:, 0])
    off = rng.normal(size=(n, 3))
    off *= (rng.random(n) * 0.01 * diag / np.linalg.norm(off, axis=1))[:, None]
    return on + off


def timed(f):
    start = perf()
    out = f()
    return perf() - start, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--points", type=int)
    ap.add_argument("--frames", type=int)
    ap.add_argument("--mesh")
    ap.add_argument("--out")
    args = ap.parse_args()
    n = args.points or (100_000 if args.quick else 1_000_000)
    frames = args.frames or (2 if args.quick else 3)
    name = args.mesh or ("elephant" if args.quick else "refined_elephant")
    pysdf, o3d, fcpw, igl = (optional(m) for m in ("pysdf", "open3d", "fcpw", "igl"))

    if os.path.exists(CGAL_DATA):
        rest, triangles = read_cgal_mesh(name)
    else:
        note(f"CGAL's demo meshes not found ({CGAL_DATA}: apt-get install libcgal-demo); "
             "a UV sphere stands in")
        name = "UV sphere"
        rest, triangles = uv_sphere(64 if args.quick else 224)
    diag = float(np.linalg.norm(np.ptp(rest, axis=0)))
    mesh = dvh.Mesh(rest, triangles)
    if not mesh.is_closed:
        sys.exit(f"{name} is not closed: signed distances need a closed mesh")
    rng = np.random.default_rng(7)
    sets = {kind: sample_points(rest, triangles, n, kind, diag, rng) for kind in ("box", "near")}
    f32 = np.float32
    tri_i32 = triangles.astype(np.int32)

    sdf = pysdf.SDF(rest.astype(f32), triangles.copy()) if pysdf else None
    scene = None
    if fcpw:
        scene = fcpw.scene_3D()
        scene.set_object_count(1)
        scene.set_object_vertices(rest.astype(f32), 0)
        scene.set_object_triangles(tri_i32, 0)
        scene.build(fcpw.aggregate_type.bvh_surface_area, True)

    rows: dict = {}
    fcpw_lists: dict = {}

    def record(kind, method, seconds, wrong=None, err=None):
        r = rows.setdefault((kind, method), {"times": [], "wrong": [], "err": []})
        r["times"].append(seconds)
        if wrong is not None:
            r["wrong"].append(int(wrong))
        if err is not None:
            r["err"].append(float(err))

    for frame in range(frames):
        positions = wave(rest, 0.7 * frame + 0.3, 0.02 * diag)
        p32 = positions.astype(f32)
        for kind, points in sets.items():
            progress(f"frame {frame}, {kind} points")
            t_refit, _ = timed(lambda: mesh.refit(positions))
            t, closest = timed(lambda: dvh.closest_points(mesh, points))
            record(kind, "dvh refit + closest points", t_refit + t)
            t, winding = timed(lambda: dvh.winding_numbers(mesh, points))
            record(kind, "dvh winding numbers", t)
            t, signed = timed(lambda: dvh.signed_distances(mesh, points))
            record(kind, "dvh refit + signed distances", t_refit + t)
            record(kind, "dvh refit", t_refit)
            inside = signed < 0
            assert np.array_equal(inside, winding != 0)
            dist = np.abs(signed)
            # One exact distance, whichever query gave it.
            # (off the surface a signed distance is never 0, even where the distance rounds to 0)
            assert np.all(np.abs(dist - closest["distance"]) <= 5e-324)

            def rel(d):
                # Against the diagonal: float32 peers are off by their rounding of the
                # coordinates, which relative to a distance near 0 says little.
                d = np.abs(np.asarray(d, dtype=float).reshape(-1))
                return float(np.max(np.abs(d - dist)) / diag)

            q32 = points.astype(f32)
            if sdf is not None:
                def pysdf_frame():
                    sdf.vertices_mutable[:] = p32
                    sdf.update()
                    return sdf(q32, n_threads=2)
                t, s = timed(pysdf_frame)
                s = s.reshape(-1)
                record(kind, "pysdf update + sdf", t, np.sum((s > 0) != inside), rel(s))
                t, c = timed(lambda: sdf.contains(q32, n_threads=2))
                record(kind, "pysdf contains", t, np.sum(c.reshape(-1) != inside))
            if o3d is not None:
                def o3d_scene():
                    sc = o3d.t.geometry.RaycastingScene()
                    sc.add_triangles(o3d.core.Tensor(p32), o3d.core.Tensor(triangles))
                    return sc
                t, s = timed(lambda: o3d_scene().compute_signed_distance(o3d.core.Tensor(q32)).numpy())
                record(kind, "Open3D rebuild + signed distance", t, np.sum((s < 0) != inside), rel(s))
                t, c = timed(lambda: o3d_scene().compute_closest_points(o3d.core.Tensor(q32)))
                record(kind, "Open3D rebuild + closest points", t)
            if scene is not None:
                qf = np.asfortranarray(q32)
                def fcpw_closest():
                    scene.update_object_vertices(p32, 0)
                    scene.refit()
                    found = fcpw.interaction_3D_list()
                    scene.find_closest_points(qf, np.full(len(q32), np.inf, f32), found)
                    return found
                try:
                    t, found = timed(fcpw_closest)
                    d = np.fromiter((i.d for i in found), dtype=float, count=len(q32))
                    record(kind, "fcpw refit + closest points", t, None, rel(d))
                    # The NumPy overload of `contains` leaves its result array unwritten (fcpw
                    # 1.2.0: every point reads 0); the list overload answers, so it is timed,
                    # the lists made beforehand.
                    if kind not in fcpw_lists:
                        fcpw_lists[kind] = fcpw.float_3D_list(list(q32))
                    result = fcpw.uint32_list([0] * len(q32))
                    t, _ = timed(lambda: scene.contains(fcpw_lists[kind], result))
                    record(kind, "fcpw contains", t, np.sum((np.array(result) != 0) != inside))
                except Exception as e:
                    note(f"fcpw failed ({type(e).__name__}: {e}); skipped")
                    scene = None
            if igl is not None and frame == 0:
                t, s = timed(lambda: igl.signed_distance(points, positions, triangles.astype(np.int64))[0])
                record(kind, "libigl signed_distance (tree built inside)", t, np.sum((s < 0) != inside), rel(s))

    versions = {}
    for pkg in ("dvh", "numpy", "pysdf", "open3d", "fcpw", "libigl"):
        try:
            versions[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            pass
    print(f"{name}, {len(triangles):,} triangles, {n:,} points a set, {frames} frames; "
          f"{datetime.now(timezone.utc):%Y-%m-%d}; " + ", ".join(f"{k} {v}" for k, v in versions.items()))
    print()
    print("| points | method | median per frame | points a second | ÷ dvh's like | wrong signs | worst distance error ÷ diagonal |")
    print("|---|---|---|---|---|---|---|")
    for kind in sets:
        ref = {
            "signed": np.median(rows[(kind, "dvh refit + signed distances")]["times"]),
            "closest": np.median(rows[(kind, "dvh refit + closest points")]["times"]),
            "inside": np.median(rows[(kind, "dvh winding numbers")]["times"]),
        }
        for (k, method), r in rows.items():
            if k != kind:
                continue
            m = float(np.median(r["times"]))
            like = ("inside" if ("contains" in method or "winding" in method) else
                    "closest" if "closest" in method else "signed")
            ratio = "" if method.startswith("dvh") or "refit" == method[-5:] else f"{m / ref[like]:.2f}×"
            rate = "" if method == "dvh refit" else f"{n / m / 1e6:.2f} M"
            wrong = f"{max(r['wrong']):,}" if r["wrong"] else ("0 (exact)" if method.startswith("dvh") and method != "dvh refit" else "")
            err = f"{max(r['err']):.1e}" if r["err"] else ""
            shown = f"{m * 1e3:.1f} ms" if m < 10 else f"{m:.2f} s"
            print(f"| {kind} | {method} | {shown} | {rate} | {ratio} | {wrong} | {err} |")
    for msg in notes:
        print(f"\nnote: {msg}")
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        with open(os.path.join(args.out, "points.json"), "w") as f:
            json.dump({f"{k}|{m}": r for (k, m), r in rows.items()}, f, indent=1)


if __name__ == "__main__":
    main()
