#!/usr/bin/env python3
"""dvh's Python layer against the Python peers, measured in the same run.

1. self-intersection: dvh.self_collide against libigl's Python routines and CGAL's
   Polygon_mesh_processing::self_intersections (cgal_self.cpp, built here when g++ and CGAL's
   headers are installed), on CGAL's demo meshes;
2. two deforming meshes: dvh.collide against python-fcl, trimesh's CollisionManager and libigl;
3. the per-call overhead of the Python layer over the raw cffi call;
4. the cost of handing a million-pair result to NumPy, each result dropped or all kept.

Prints Markdown tables; with --out DIR also writes DIR/peers.json (every sample) and
DIR/peers.md. A peer that is not installed is skipped with a note. Timings are medians over
repeated runs, the methods interleaved round-robin so that load from other processes falls on
all of them alike; ratios are against dvh measured in the same run.

    python python/bench/peers.py [--quick] [--out DIR] [--cgal-data ARCHIVE_OR_DIR]
"""

from __future__ import annotations

import argparse
import gc
import hashlib
import itertools
import json
import os
import platform
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
from datetime import datetime, timezone
from importlib import metadata

import numpy as np

import dvh
from dvh._dvh import ffi, lib

try:
    import igl
    import igl.predicates  # noqa: F401

    try:
        import igl.copyleft.cgal as igl_cgal
    except ImportError:  # wheels without the CGAL module
        igl_cgal = None
except ImportError:
    igl = igl_cgal = None

try:
    import fcl
except ImportError:
    fcl = None

try:
    import trimesh
    import trimesh.collision
except ImportError:
    trimesh = None

# Debian's libcgal-demo package; its data/meshes/*.off are scanned and modelled surfaces.
CGAL_DATA = "/usr/share/doc/libcgal-demo/data.tar.gz"

perf = time.perf_counter
notes: list[str] = []


def note(msg: str) -> None:
    notes.append(msg)
    print(f"note: {msg}", file=sys.stderr, flush=True)


def progress(msg: str) -> None:
    print(f"... {msg}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# Meshes


def parse_off(text: str, where: str):
    """Vertices and triangles of an OFF text (polygons split into fans, colours ignored)."""
    lines = (ln.split("#", 1)[0].split() for ln in text.splitlines())
    toks = [t for t in lines if t]
    head = toks[0]
    if not head[0].endswith("OFF"):
        raise ValueError(f"{where}: not an OFF file")
    counts, rest = (head[1:], toks[1:]) if len(head) > 1 else (toks[1], toks[2:])
    nv, nf = int(counts[0]), int(counts[1])
    V = np.array([[float(x) for x in t[:3]] for t in rest[:nv]], dtype=np.float64)
    tris = []
    for t in rest[nv : nv + nf]:
        k = int(t[0])
        f = [int(x) for x in t[1 : 1 + k]]
        tris.extend([f[0], f[i], f[i + 1]] for i in range(1, k - 1))
    return V, np.array(tris, dtype=np.int64).reshape(-1, 3)


def load_cgal(source: str, names):
    """{name: (V, F)} for the meshes of `names` found in the archive (or directory) `source`;
    one pass over the archive."""
    found = {}
    if os.path.isdir(source):
        for n in names:
            for sub in ("", "data/meshes", "meshes"):
                p = os.path.join(source, sub, n + ".off")
                if os.path.exists(p):
                    with open(p, encoding="utf-8", errors="replace") as f:
                        found[n] = parse_off(f.read(), p)
                    break
    elif os.path.exists(source):
        wanted = {f"data/meshes/{n}.off": n for n in names}
        with tarfile.open(source) as tar:
            for member in tar:
                n = wanted.get(member.name.lstrip("./"))
                if n is not None:
                    raw = tar.extractfile(member).read().decode("utf-8", "replace")
                    found[n] = parse_off(raw, member.name)
    return found


def uv_sphere(n: int, radius: float = 1.0):
    """A closed sphere of 2 n (n - 1) triangles (the fallback when CGAL's meshes are absent)."""
    th = np.pi * np.arange(1, n)[:, None] / n
    ph = 2 * np.pi * np.arange(n)[None, :] / n
    ring = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th) + 0 * ph], -1)
    V = np.vstack([[0, 0, 1], ring.reshape(-1, 3), [0, 0, -1]]) * radius
    south = len(V) - 1
    idx = lambda i, j: 1 + (i - 1) * n + (j % n)  # noqa: E731
    j = np.arange(n)
    tris = [np.column_stack([np.zeros(n, int), idx(1, j), idx(1, j + 1)]),
            np.column_stack([np.full(n, south), idx(n - 1, j + 1), idx(n - 1, j)])]
    for i in range(1, n - 1):
        a, b, c, d = idx(i, j), idx(i, j + 1), idx(i + 1, j), idx(i + 1, j + 1)
        tris += [np.column_stack([a, c, d]), np.column_stack([a, d, b])]
    return V, np.vstack(tris).astype(np.int64)


def grid(n: int, size: float = 1.0):
    """A flat n x n sheet of 2 n^2 triangles in z = 0."""
    xs = np.linspace(0.0, size, n + 1)
    X, Y = np.meshgrid(xs, xs)
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    v = (j * (n + 1) + i).ravel()
    F = np.vstack([np.column_stack([v, v + 1, v + n + 2]), np.column_stack([v, v + n + 2, v + n + 1])])
    return V, F.astype(np.int64)


def with_noise(V, F, fraction=0.02, scale=2.0, seed=1):
    """`V` with `fraction` of its vertices moved by Gaussian noise of `scale` mean edge lengths,
    so that triangles fold through their neighbours and cross."""
    rng = np.random.default_rng(seed)
    edge = np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean()
    W = V.copy()
    idx = rng.choice(len(V), max(1, int(len(V) * fraction)), replace=False)
    W[idx] += rng.normal(size=(len(idx), 3)) * scale * edge
    return W


def raw_mesh(V, F):
    """A DvhMesh made through the raw C ABI, for the calls that bypass the Python layer."""
    P = np.ascontiguousarray(V, dtype=np.float64)
    T = np.ascontiguousarray(F, dtype=np.uint32)
    opts = ffi.new("DvhBuildOptions *")
    opts[0] = lib.dvh_build_options_default()
    out = ffi.new("DvhMesh **")
    status = lib.dvh_mesh_create(
        ffi.cast("const double *", P.ctypes.data), len(P),
        ffi.cast("const uint32_t *", T.ctypes.data), len(T), opts, out)
    assert status == lib.DVH_STATUS_OK, status
    return ffi.gc(out[0], lib.dvh_mesh_free)


# ---------------------------------------------------------------------------------------------
# Timing


def interleaved(fns: dict, reps: int, warmup: int = 1) -> dict:
    """{name: [seconds] * reps}: each round runs every function once, the order rotated so that
    none always runs first (right after a warm cache or a neighbour's garbage)."""
    names = list(fns)
    for n in names:
        for _ in range(warmup):
            fns[n]()
    times = {n: [] for n in names}
    for r in range(reps):
        k = r % len(names)
        for n in names[k:] + names[:k]:
            t0 = perf()
            fns[n]()
            times[n].append(perf() - t0)
    return times


def med(xs) -> float:
    return float(np.median(xs)) if len(xs) else float("nan")


def ms(x: float) -> str:
    if x != x:
        return "—"
    return f"{x * 1e3:.3g}" if x < 0.1 else f"{x * 1e3:.0f}"


def ratio(x: float, ref: float) -> str:
    return f"{x / ref:.3g}×" if ref > 0 and x == x else "—"


def pair_keys(p) -> np.ndarray:
    """Triangle pairs as sorted unique int64 keys, to compare result sets."""
    p = np.asarray(p, dtype=np.int64).reshape(-1, 2)
    return np.unique(p[:, 0] * (1 << 32) + p[:, 1])


def sym_diff(p, q) -> tuple[int, int]:
    a, b = pair_keys(p), pair_keys(q)
    return len(np.setdiff1d(a, b, assume_unique=True)), len(np.setdiff1d(b, a, assume_unique=True))


def table(header, rows) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# 1. Self-intersection


CGAL_SELF = "CGAL PMP::self_intersections"


def build_cgal_self():
    """cgal_self.cpp compiled (once per source version, into the temporary directory), or None
    with a note when g++ or CGAL's headers are missing."""
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cgal_self.cpp")
    if shutil.which("g++") is None or not os.path.isdir("/usr/include/CGAL"):
        note("g++ or CGAL's headers (libcgal-dev) missing: CGAL's self_intersections is skipped")
        return None
    with open(src, "rb") as f:
        tag = hashlib.sha256(f.read()).hexdigest()[:12]
    binary = os.path.join(tempfile.gettempdir(), f"dvh-bench-cgal-self-{tag}")
    if not os.path.exists(binary):
        progress("  building cgal_self.cpp (CGAL's headers: about 15 s)")
        r = subprocess.run(["g++", "-O2", "-std=c++17", src, "-o", binary, "-lgmp", "-lmpfr"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            note(f"cgal_self.cpp did not build: CGAL's self_intersections is skipped\n{r.stderr[-2000:]}")
            return None
    return binary


def cgal_self(binary, V, F, reps: int):
    """(pairs, median seconds) of CGAL's self_intersections on the mesh, timed inside the
    program around the call alone (no file reading), or None when CGAL cannot read the mesh."""
    with tempfile.NamedTemporaryFile("w", suffix=".off", delete=False) as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        np.savetxt(f, V, fmt="%.17g")
        np.savetxt(f, np.column_stack([np.full(len(F), 3), F]), fmt="%d")
        path = f.name
    try:
        r = subprocess.run([binary, path, str(reps)], capture_output=True, text=True)
    finally:
        os.unlink(path)
    if r.returncode != 0:
        note(f"CGAL's self_intersections: {r.stderr.strip()}")
        return None
    _faces, pairs, median_ms = r.stdout.split()
    return int(pairs), float(median_ms) / 1e3


IGL_FIND = "igl.predicates.find_self_intersections"
IGL_CGAL = "igl.copyleft.cgal.remesh_self_intersections(detect_only=True)"


def bench_self(meshes: dict, reps: int):
    progress("self-intersection")
    if igl is None:
        note("libigl is not installed (pip install libigl): the self-intersection peers are skipped")
    elif igl_cgal is None:
        note("this libigl has no igl.copyleft.cgal module: remesh_self_intersections is skipped")
    cgal_binary = build_cgal_self()
    raw, rows = {}, []
    for label, (V, F) in meshes.items():
        progress(f"  {label}: {len(F)} triangles")
        V = np.ascontiguousarray(V, dtype=np.float64)
        F = np.ascontiguousarray(F, dtype=np.int64)
        m = dvh.Mesh(V, F)
        diag = float(np.linalg.norm(V.max(0) - V.min(0)))
        frames = itertools.cycle([deform(V, 0.0, 1e-4 * diag, 4 * np.pi / diag), V])
        fns = {
            "dvh Mesh()": lambda: dvh.Mesh(V, F),
            # Like for like with libigl, which builds its AABB tree inside every call; includes
            # what the first self-query of a new mesh finds once per shape.
            "dvh build+query": lambda: dvh.self_collide(dvh.Mesh(V, F)),
            # The deforming-mesh frame: the tree exists and is refit, to positions that
            # alternate between the mesh and a slightly waved copy so every frame moves.
            "dvh refit+query": lambda: (m.refit(next(frames)), dvh.self_collide(m)),
            "dvh query": lambda: dvh.self_collide(m),
        }
        results = {"dvh": dvh.self_collide(m)}
        if igl is not None:
            fns[IGL_FIND] = lambda: igl.predicates.find_self_intersections(V, F)
            results[IGL_FIND] = igl.predicates.find_self_intersections(V, F)[1]
        if igl_cgal is not None:
            fns[IGL_CGAL] = lambda: igl_cgal.remesh_self_intersections(V, F, detect_only=True)
            results[IGL_CGAL] = igl_cgal.remesh_self_intersections(V, F, detect_only=True)[2]
        times = interleaved(fns, reps)
        cgal = cgal_self(cgal_binary, V, F, reps) if cgal_binary else None
        # Both libigl routines report each pair once as (lower, higher) after sorting the row;
        # they skip the shared vertex/edge of neighbours as dvh does, so the sets compare.
        agree = {}
        for name, p in results.items():
            if name != "dvh":
                extra, missing = sym_diff(np.sort(np.asarray(p), axis=1), results["dvh"])
                agree[name] = {"pairs": int(len(pair_keys(np.sort(np.asarray(p), axis=1)))),
                               "not_in_dvh": extra, "missing_from_peer": missing}
        raw[label] = {"triangles": int(len(F)), "dvh_pairs": int(len(results["dvh"])),
                      "agreement": agree, "seconds": times,
                      "cgal": None if cgal is None else {"pairs": cgal[0], "median_seconds": cgal[1]}}
        ref = med(times["dvh build+query"])
        row = [label, len(F), len(results["dvh"])]
        for name in (IGL_FIND, IGL_CGAL):
            if name in agree:
                a = agree[name]
                same = a["not_in_dvh"] == 0 and a["missing_from_peer"] == 0
                row.append(f"{a['pairs']} ({'same' if same else '+%d/−%d' % (a['not_in_dvh'], a['missing_from_peer'])})")
            else:
                row.append("not installed")
        row += [ms(med(times["dvh Mesh()"])), ms(ref), ms(med(times["dvh refit+query"])),
                ms(med(times["dvh query"]))]
        for name in (IGL_FIND, IGL_CGAL):
            t = med(times[name]) if name in times else float("nan")
            row.append(f"{ms(t)} ({ratio(t, ref)} / {ratio(t, med(times['dvh refit+query']))})"
                       if name in times else "—")
        if cgal is None:
            row += ["—", "—"]
        else:
            same = "same count" if cgal[0] == len(results["dvh"]) else "differs"
            row += [f"{cgal[0]} ({same})",
                    f"{ms(cgal[1])} ({ratio(cgal[1], ref)} / {ratio(cgal[1], med(times['dvh refit+query']))})"]
        rows.append(row)
    header = ["mesh", "triangles", "dvh pairs", f"`{IGL_FIND}` pairs", f"`{IGL_CGAL}` pairs",
              "dvh `Mesh()` ms", "dvh build+query ms", "dvh refit+query ms", "dvh query ms",
              f"`{IGL_FIND}` ms (× build+query / × refit+query)",
              f"`{IGL_CGAL}` ms (× build+query / × refit+query)",
              f"{CGAL_SELF} pairs", f"{CGAL_SELF} ms (× build+query / × refit+query)"]
    md = (f"### 1. Self-intersection (`dvh.self_collide`), median of {reps}\n\n"
          + table(header, rows)
          + "\n\nPeer pairs: the count, then `same` when the set equals dvh's, else +(pairs only the "
          "peer reports)/−(pairs only dvh reports). build+query: a new `dvh.Mesh` and its first "
          "`self_collide` (which also analyses the mesh's shape once), the like for like with "
          "libigl, whose calls build their tree each time. refit+query: the frame of a deforming "
          "mesh, whose tree and shape analysis persist. query: `self_collide` again, same positions. "
          f"{CGAL_SELF}: Epick, sequential, on a Surface_mesh, timed in C++ around the call alone "
          "(its boxes are built inside the call, like build+query without the mesh's build); its "
          "pairs are compared by count.")
    return md, raw


# ---------------------------------------------------------------------------------------------
# 2. Two deforming meshes


def deform(P, phase, amp, k):
    """A smooth travelling wave: every vertex moves by at most `amp`, neighbours alike."""
    x, y, z = P[:, 0], P[:, 1], P[:, 2]
    return P + amp * np.column_stack(
        [np.sin(k * y + phase), np.sin(k * z + 1.3 * phase), np.sin(k * x + 0.7 * phase)])


def bench_collide(label, V, F, frames: int, passes: int):
    progress(f"two-mesh collision: {label}, {frames} frames x {passes} passes")
    V = np.ascontiguousarray(V, dtype=np.float64)
    F = np.ascontiguousarray(F, dtype=np.int64)
    lo, hi = V.min(0), V.max(0)
    diag = float(np.linalg.norm(hi - lo))
    # The second copy is shifted by a fifth of the width so the surfaces cross along a band.
    W = V + np.array([0.2 * (hi - lo)[0], 0.0, 0.0])
    amp, k = 0.01 * diag, 4 * np.pi / diag
    seq = [(deform(V, 2 * np.pi * f / frames, amp, k), deform(W, 2 * np.pi * f / frames + 1.0, amp, k))
           for f in range(frames)]

    methods = {}

    def dvh_method(threads):
        a = dvh.Mesh(seq[0][0], F, refit_threads=threads)
        b = dvh.Mesh(seq[0][1], F, refit_threads=threads)

        def run(i):
            PA, PB = seq[i]
            t0 = perf()
            a.refit(PA)
            b.refit(PB)
            t1 = perf()
            p = dvh.collide(a, b, threads=threads)
            t2 = perf()
            return t1 - t0, t2 - t1, len(p), p
        return run

    methods["dvh (refit + collide)"] = dvh_method(0)
    methods["dvh, 1 thread"] = dvh_method(1)

    if fcl is not None:
        def fcl_method(enable_contact):
            # python-fcl exposes no update/refit of a BVHModel: a new one per frame.
            req = fcl.CollisionRequest(num_max_contacts=10**9, enable_contact=enable_contact)

            def build(P):
                m = fcl.BVHModel()
                m.beginModel(len(F), len(P))
                m.addSubModel(P, F)
                m.endModel()
                return fcl.CollisionObject(m, fcl.Transform())

            def run(i):
                PA, PB = seq[i]
                t0 = perf()
                oa, ob = build(PA), build(PB)
                t1 = perf()
                res = fcl.CollisionResult()
                fcl.collide(oa, ob, req, res)
                ids = [(c.b1, c.b2) for c in res.contacts]
                t2 = perf()
                return t1 - t0, t2 - t1, len(res.contacts), ids
            return run

        methods["python-fcl (rebuild + `fcl.collide`, enable_contact=True)"] = fcl_method(True)
        methods["python-fcl (rebuild + `fcl.collide`, enable_contact=False)"] = fcl_method(False)
    else:
        note("python-fcl is not installed (pip install python-fcl): its rows are skipped")

    if trimesh is not None and fcl is not None:
        mgr = trimesh.collision.CollisionManager()
        added = set()

        def run_trimesh(i):
            # A new Trimesh and BVH per frame; remove_object first, as add_object under an
            # existing name leaves the old object registered in the fcl manager (trimesh 5.2).
            PA, PB = seq[i]
            t0 = perf()
            for name, P in (("a", PA), ("b", PB)):
                if name in added:
                    mgr.remove_object(name)
                mgr.add_object(name, trimesh.Trimesh(P, F, process=False))
                added.add(name)
            t1 = perf()
            _, _, data = mgr.in_collision_internal(return_names=True, return_data=True)
            ids = [(d.index("a"), d.index("b")) for d in data]
            t2 = perf()
            return t1 - t0, t2 - t1, len(data), ids
        methods["trimesh `CollisionManager` (add_object + in_collision_internal)"] = run_trimesh
    elif trimesh is None:
        note("trimesh is not installed (pip install trimesh): its row is skipped")
    else:
        note("trimesh's CollisionManager needs python-fcl: its row is skipped")

    if igl is not None:
        def run_igl(i):
            PA, PB = seq[i]
            t0 = perf()
            _, IF, _ = igl.predicates.find_intersections(PA, F, PB, F)
            t1 = perf()
            return None, t1 - t0, len(IF), IF
        methods["`igl.predicates.find_intersections` (builds its tree per call)"] = run_igl

    # dvh's pairs per frame are the reference every peer is compared with.
    ref_a, ref_b = dvh.Mesh(seq[0][0], F), dvh.Mesh(seq[0][1], F)
    ref = []
    for PA, PB in seq:
        ref_a.refit(PA)
        ref_b.refit(PB)
        ref.append(dvh.collide(ref_a, ref_b))

    names = list(methods)
    for n in names:  # warm-up: first calls, thread pools, allocator
        methods[n](0)
    samples = {n: {"update": [], "query": [], "total": [], "contacts": [], "pairs": [],
                   "not_in_dvh": [], "missing_from_peer": []} for n in names}
    r = 0
    for _ in range(passes):
        for i in range(frames):
            k = r % len(names)
            r += 1
            for n in names[k:] + names[:k]:
                tu, tq, contacts, pairs = methods[n](i)
                s = samples[n]
                # None: the method has no separate update step (its tree is built in the query).
                s["update"].append(tu)
                s["query"].append(tq)
                s["total"].append((tu or 0.0) + tq)
                s["contacts"].append(int(contacts))
                s["pairs"].append(int(len(pair_keys(pairs))))
                extra, missing = sym_diff(pairs, ref[i])
                s["not_in_dvh"].append(extra)
                s["missing_from_peer"].append(missing)

    base, base1 = med(samples[names[0]]["total"]), med(samples[names[1]]["total"])
    rows = []
    for n in names:
        s = samples[n]
        agree = sum(1 for a, b in zip(s["not_in_dvh"], s["missing_from_peer"]) if a == 0 and b == 0)
        rows.append([
            n, "(in query)" if s["update"][0] is None else ms(med(s["update"])),
            ms(med(s["query"])), ms(med(s["total"])), ratio(med(s["total"]), base),
            ratio(med(s["total"]), base1),
            int(np.median(s["contacts"])), int(np.median(s["pairs"])),
            f"{agree}/{len(s['total'])}", f"+{sum(s['not_in_dvh'])}/−{sum(s['missing_from_peer'])}",
        ])
    header = ["method", "update ms", "query ms", "ms/frame", "× dvh", "× dvh 1 thread", "contacts/frame",
              "distinct pairs/frame", "frames equal to dvh", "pairs +peer/−dvh (all frames)"]
    md = (f"### 2. Two deforming copies of {label} ({len(F)} triangles each), {frames} frames × "
          f"{passes} passes, medians per frame\n\n" + table(header, rows)
          + "\n\nupdate: what the method needs before the query each frame (dvh: two `Mesh.refit`; "
          "python-fcl: two new `BVHModel`s; trimesh: two `add_object` of new `Trimesh`es). "
          "query: the call and reading the triangle ids of its result into Python. "
          "Columns are medians each, so update + query need not equal ms/frame.")
    raw = {"mesh": label, "triangles": int(len(F)), "frames": frames, "passes": passes,
           "amplitude_over_diagonal": 0.01, "shift_over_width": 0.2, "methods": samples}
    return md, raw


# ---------------------------------------------------------------------------------------------
# 3. Per-call overhead


def bench_overhead(calls: int, batches: int):
    progress(f"per-call overhead: {batches} batches x {calls} calls")
    T = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    F = np.array([[0, 1, 2]])
    a, b = dvh.Mesh(T, F), dvh.Mesh(T + 100.0, F)
    ra, rb = raw_mesh(T, F), raw_mesh(T + 100.0, F)
    opts = ffi.new("DvhQueryOptions *")
    opts[0] = lib.dvh_query_options_default()
    stats = ffi.new("DvhQueryStats *")
    buf = ffi.gc(lib.dvh_pairs_new(), lib.dvh_pairs_free)
    NULL = ffi.NULL
    assert len(dvh.collide(a, b)) == 0
    assert lib.dvh_collide(ra, NULL, rb, NULL, opts, buf, stats) == lib.DVH_STATUS_OK

    def loop_empty():
        for _ in range(calls):
            pass

    def loop_floor():
        f = lib.dvh_pairs_len
        for _ in range(calls):
            f(buf)

    def loop_raw():
        f = lib.dvh_collide
        for _ in range(calls):
            f(ra, NULL, rb, NULL, opts, buf, stats)

    def loop_layer():
        f = dvh.collide
        for _ in range(calls):
            f(a, b)

    fns = {"empty": loop_empty, "floor": loop_floor, "raw": loop_raw, "layer": loop_layer}
    # As timeit does: the cyclic collector would add pauses unrelated to either path.
    gc.disable()
    try:
        times = interleaved(fns, batches)
    finally:
        gc.enable()
    per = {n: [t / calls for t in ts] for n, ts in times.items()}
    m = {n: med(v) for n, v in per.items()}
    over = m["layer"] - m["raw"]
    ns = lambda x: f"{x * 1e9:.0f}"  # noqa: E731
    rows = [
        ["empty Python `for` iteration (included in every row below)", ns(m["empty"])],
        ["cffi floor: `lib.dvh_pairs_len(buf)`", ns(m["floor"])],
        ["raw cffi: `lib.dvh_collide(a, NULL, b, NULL, opts, buf, stats)`, preallocated", ns(m["raw"])],
        ["`dvh.collide(a, b)`", ns(m["layer"])],
        ["**layer overhead** = `dvh.collide` − raw call", f"**{ns(over)}** "
         f"({'under' if over < 2e-6 else 'over'} the 2 µs goal)"],
    ]
    md = (f"### 3. Per-call overhead: two 1-triangle meshes 100 apart, median of {batches} "
          f"batches × {calls} calls\n\n" + table(["call", "ns/call"], rows))
    raw = {"calls_per_batch": calls, "batches": batches, "seconds_per_call": per,
           "layer_overhead_seconds": over}
    return md, raw


# ---------------------------------------------------------------------------------------------
# 4. A million pairs to NumPy


def bench_million(n: int, reps: int):
    progress(f"million-pair result: two {n}x{n} coplanar grids, {reps} reps")
    V, F = grid(n)
    h = 1.0 / n
    # Shifted by less than a cell: each triangle overlaps about five of the other sheet's.
    W = V + np.array([0.5 * h, 0.3 * h, 0.0])
    a, b = dvh.Mesh(V, F), dvh.Mesh(W, F)
    ra, rb = raw_mesh(V, F), raw_mesh(W, F)
    opts = ffi.new("DvhQueryOptions *")
    opts[0] = lib.dvh_query_options_default()
    stats = ffi.new("DvhQueryStats *")
    buf = ffi.gc(lib.dvh_pairs_new(), lib.dvh_pairs_free)
    NULL = ffi.NULL

    def raw_call():
        assert lib.dvh_collide(ra, NULL, rb, NULL, opts, buf, stats) == lib.DVH_STATUS_OK

    def raw_pairs():
        k = lib.dvh_pairs_len(buf)
        return np.frombuffer(ffi.buffer(lib.dvh_pairs_data(buf), 8 * k), dtype=np.uint32).reshape(k, 2)

    raw_call()
    pairs = dvh.collide(a, b)
    assert np.array_equal(pairs, raw_pairs()), "the layer's result differs from the C buffer"
    k = len(pairs)
    del pairs
    # Dropped: each result is gone before the next call, whose array views the same buffer (a
    # loop that discards each frame's result). Held: every result is kept, so past the two the
    # layer lends at once, each is copied out into fresh pages (a caller that keeps them all).
    times = interleaved({"layer": lambda: dvh.collide(a, b), "raw": raw_call}, reps)
    kept = [dvh.collide(a, b), dvh.collide(a, b)]
    held = 3 * reps
    times["held"] = interleaved({"c": lambda: kept.append(dvh.collide(a, b))}, held, warmup=0)["c"]
    kept.clear()
    m = {n_: med(v) for n_, v in times.items()}
    pct = lambda x: f"{100 * x / m['raw']:.0f}%"  # noqa: E731
    rows = [
        ["raw `lib.dvh_collide` into a preallocated buffer", ms(m["raw"]), "100%"],
        [f"`dvh.collide(a, b)`, each result dropped ({k} pairs, viewed in place)", ms(m["layer"]),
         pct(m["layer"])],
        ["`dvh.collide(a, b)`, every result kept (copied out past two held)", ms(m["held"]),
         pct(m["held"])],
    ]
    mb = 8 * k / 1e6
    md = (f"### 4. Handing {k} pairs to NumPy: two coplanar {n}×{n} grids ({len(F)} triangles "
          f"each) shifted by under a cell; medians of {reps} calls, {held} calls keeping every result\n\n"
          + table(["measurement", "ms", "of the raw call"], rows)
          + f"\n\nThe layer returns a NumPy array that views the library's buffer ({mb:.1f} MB), "
          "which is not queried into again while the array lives; a third result held at once is "
          "copied out of another buffer instead, into new pages whose faults the kernel charges "
          "as for any new array of that size.")
    raw = {"grid": n, "pairs": int(k), "seconds": times}
    return md, raw


# ---------------------------------------------------------------------------------------------


def versions() -> dict:
    # The layer changes between releases of the same version: name the file measured.
    with open(os.path.join(os.path.dirname(dvh.__file__), "_api.py"), "rb") as f:
        api = hashlib.sha256(f.read()).hexdigest()[:12]
    out = {"Python": platform.python_version(), "dvh": f"{dvh.version()} (_api.py {api})"}
    for dist in ("numpy", "cffi", "libigl", "python-fcl", "trimesh"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="smaller meshes, fewer frames and calls (under 2 minutes)")
    ap.add_argument("--out", metavar="DIR", help="write peers.json (every sample) and peers.md there")
    ap.add_argument("--cgal-data", default=CGAL_DATA, metavar="PATH",
                    help="libcgal-demo's data.tar.gz, or a directory holding the .off meshes")
    args = ap.parse_args()
    q = args.quick
    started = perf()
    date = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")

    self_names = ["elephant", "mannequin-devil"] if q else ["elephant", "mannequin-devil", "armadillo", "bunny00"]
    noisy_name = "elephant" if q else "armadillo"
    collide_name = "elephant" if q else "armadillo"
    found = load_cgal(args.cgal_data, set(self_names) | {collide_name})
    if not found:
        note(f"CGAL demo meshes not found at {args.cgal_data} (apt-get install libcgal-demo): "
             "using a UV sphere instead")
    self_meshes = {}
    for n in self_names:
        if n in found:
            self_meshes[n] = found[n]
    if not self_meshes:
        self_meshes["uv sphere"] = uv_sphere(60 if q else 160)
        noisy_name = "uv sphere"
    V0, F0 = self_meshes[noisy_name] if noisy_name in self_meshes else found[noisy_name]
    self_meshes[f"{noisy_name} + noise"] = (with_noise(V0, F0), F0)
    if collide_name in found:
        cV, cF = found[collide_name]
        clabel = collide_name
    else:
        cV, cF = uv_sphere(60 if q else 160)
        clabel = "a UV sphere"
        if trimesh is not None:
            note("the two-mesh scene uses a sphere: trimesh treats a convex mesh as fcl.Convex "
                 "(GJK, one contact), so its row does not compare")

    ver = versions()
    head = (f"## dvh's Python layer against Python peers ({'quick' if q else 'full'} run)\n\n"
            f"{date}; {os.cpu_count()} cores; {platform.machine()} {platform.system()}; "
            + ", ".join(f"{k} {v}" for k, v in ver.items())
            + "\n\nEvery method runs with its default threads (dvh and libigl use every core, "
            "python-fcl one); times are medians of interleaved runs.")
    print(head, flush=True)
    sections, raw = [head], {"date": date, "versions": ver, "quick": q, "cpu_count": os.cpu_count(),
                             "platform": platform.platform()}

    md, raw["self_intersection"] = bench_self(self_meshes, 3 if q else 7)
    print("\n" + md, flush=True)
    sections.append(md)
    md, raw["two_mesh"] = bench_collide(clabel, cV, cF, 8 if q else 20, 1 if q else 2)
    print("\n" + md, flush=True)
    sections.append(md)
    md, raw["overhead"] = bench_overhead(50_000 if q else 200_000, 5)
    print("\n" + md, flush=True)
    sections.append(md)
    md, raw["million_pairs"] = bench_million(320, 3 if q else 7)
    print("\n" + md, flush=True)
    sections.append(md)

    elapsed = perf() - started
    raw["notes"], raw["elapsed_seconds"] = notes, elapsed
    tail = f"Run time {elapsed:.0f} s." + "".join(f"\n- note: {n}" for n in notes)
    print("\n" + tail)
    sections.append(tail)
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        with open(os.path.join(args.out, "peers.json"), "w") as f:
            json.dump(raw, f, indent=1)
        with open(os.path.join(args.out, "peers.md"), "w") as f:
            f.write("\n\n".join(sections) + "\n")
        print(f"wrote {os.path.join(args.out, 'peers.json')} and peers.md", file=sys.stderr)


if __name__ == "__main__":
    main()
