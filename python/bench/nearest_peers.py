#!/usr/bin/env python3
"""dvh's closest-point stencils (``dvh.self_nearest_features``) against IPC Toolkit's collision
set (``ipctk.NormalCollisions.build``: its broad phase, then the distance of every candidate),
measured in the same run on the frames of three deforming meshes, the first two as the
benchmark runner's ``self`` command builds them:

1. *sheet*: a grid of n × n cells, 1 wide, rippled, falling while it folds over a crease past
   180 degrees, so that the flap comes down on the rest of the sheet (20,000 triangles;
   3,200, the runner's short size, with --quick);
2. *bent*: CGAL's scanned elephant (Debian's libcgal-demo, 5,558 triangles) bent around a
   cylinder until its ends cross; a UV sphere stands in when the data is not installed.
3. *cloth simulation*: ``cloth_steps.py``'s sheet (2,048 triangles with --quick, 8,192 otherwise)
   fallen onto a ball and the floor and folded onto itself, its self-contact kept by dvh's own
   stencils and CCD: the positions a simulator produces, frames spread over its steps in
   contact.

For each mesh, distance (0.1 %, 1 % and 5 % of the rest mesh's bounding-box diagonal, as the
runner) and frame (t in [0, 1)): ``self_nearest_features`` (every vertex-face and edge-edge pair
sharing no vertex within d, with distances, closest points, weights and features),
``self_proximity`` (the triangle pairs sharing no vertex within d, the same traversal without
the stencils) and ``NormalCollisions.build``, each repeated and the fastest kept; medians over
frames. Counts split by kind; a cross-check maps every ipctk collision to the dvh primitive
pairs it implies and counts those dvh lacks, and the other way round.

Prints Markdown tables to stdout, progress to stderr. Needs dvh (``pip install ./python``),
``ipctk`` and NumPy:

    python -m venv .near && .near/bin/pip install ./python ipctk
    .near/bin/python python/bench/nearest_peers.py [--quick] [--frames N] [--budget S] [--skip sheet,bent,check]

On 2 cores the full run takes about 5 minutes and up to 8 GB of memory (the sheet at 5 %: 16
million stencils in one frame; each distance takes frames until a time budget is spent, at
least one); --quick about 35 seconds and under 1 GB.
"""

from __future__ import annotations

import argparse
import gc
import hashlib
import os
import platform
import resource
import sys
import tarfile
import time
from datetime import datetime, timezone
from importlib import metadata

import numpy as np

import dvh

import cloth_steps

try:
    import ipctk
except ImportError:
    ipctk = None

# Debian's libcgal-demo package; data/meshes/*.off are scanned and modelled surfaces.
CGAL_DATA = os.environ.get("DVH_CGAL_DATA", "/usr/share/doc/libcgal-demo/data.tar.gz")
FRACTIONS = (0.001, 0.01, 0.05)
# The simulated cloth (``cloth_steps.py``): its steps, and the first in self-contact.
CLOTH_STEPS = 150
CLOTH_FROM = 50
# Pairs whose distance is within this relative band of d may be decided either way by a
# floating-point tool (and ipctk keeps distance < d where dvh keeps distance <= d).
TIE = 1e-9

perf = time.perf_counter
cpu = time.process_time  # every thread of the process: cpu / wall is the cores a call used
notes: list[str] = []


def note(msg: str) -> None:
    notes.append(msg)
    print(f"note: {msg}", file=sys.stderr, flush=True)


def progress(msg: str) -> None:
    print(f"... {msg}", file=sys.stderr, flush=True)


def table(header, rows) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def ms(x: float) -> str:
    if x != x:
        return "—"
    x *= 1e3
    return f"{x:.3g}" if x < 100 else f"{x:.0f}"


def ratio(x: float, ref: float) -> str:
    return f"{x / ref:.3g}×" if ref > 0 and x == x else "—"


def count(x: float) -> str:
    return f"{x:,.0f}"


def med(xs) -> float:
    return float(np.median(xs)) if len(xs) else float("nan")


# Memory: Linux resets a process's peak resident size (VmHWM) on writing 5 to
# /proc/self/clear_refs, so the peak of one call is cheap to read. Elsewhere it is not measured.
peak_seen = [0.0]


def vm(key: str) -> float:
    """VmRSS or VmHWM of this process in bytes, or NaN."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    return float("nan")


def reset_peak() -> bool:
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def mb(x: float) -> str:
    return "—" if x != x else f"{x / 2**20:.3g}" if x < 100 * 2**20 else f"{x / 2**20:,.0f}"


# ---------------------------------------------------------------------------------------------
# Meshes, as the runner builds them


def grid(n: int, size: float = 1.0):
    """The runner's grid: (n + 1)² vertices over [0, size]², row by row; two triangles per cell,
    (i, j), (i+1, j), (i+1, j+1) and (i, j), (i+1, j+1), (i, j+1)."""
    c = np.arange(n + 1) * size / n  # i * size / n, as the runner computes it
    X, Y = np.meshgrid(c, c)
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    i, j = (a.ravel() for a in np.meshgrid(np.arange(n), np.arange(n)))
    a, b, cc, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
    F = np.empty((2 * n * n, 3), dtype=np.int64)
    F[0::2] = np.column_stack([a, b, cc])
    F[1::2] = np.column_stack([a, cc, d])
    return V, F


def sheet_at(rest: np.ndarray, t: float) -> np.ndarray:
    """The runner's folding sheet at time t: rippled, the part beyond the crease x = 0.45
    wrapped round a cylinder of radius 0.02 and then straight at the fold angle, which grows to
    200 degrees (more at one side), the whole sheet falling by 0.5 t."""
    x, y = rest[:, 0], rest[:, 1]
    radius, crease = 0.02, 0.45
    ripple = 0.004 * np.sin(23.0 * x) * np.sin(17.0 * y)
    angle = np.pi * 1.12 * t * (0.9 + 0.2 * y)
    arc = radius * angle
    on = (x > crease) & (x <= crease + arc)
    past = x > crease + arc
    a = (x - crease) / radius
    s = x - crease - arc
    sin, cos = np.sin(angle), np.cos(angle)
    cx, cz = crease + radius * sin, radius - radius * cos
    px = np.where(past, cx + s * cos - ripple * sin, np.where(on, crease + (radius - ripple) * np.sin(a), x))
    pz = np.where(past, cz + s * sin + ripple * cos, np.where(on, radius - (radius - ripple) * np.cos(a), ripple))
    return np.column_stack([px, y, pz - 0.5 * t])


def bent_at(rest: np.ndarray, t: float) -> np.ndarray:
    """The runner's bent mesh at time t: bent around a cylinder along x, the bend growing to
    2.3 π, so that its ends meet and cross."""
    lo, hi = rest.min(axis=0), rest.max(axis=0)
    length = hi[0] - lo[0]
    bend = min(1e-6 + 2.3 * np.pi * t, 2.3 * np.pi)
    radius = length / bend
    a = (rest[:, 0] - lo[0]) / length * bend - bend / 2.0
    r = radius - (rest[:, 2] - 0.5 * (lo[2] + hi[2]))
    return np.column_stack([r * np.sin(a), rest[:, 1], radius - r * np.cos(a)])


def parse_off(text: str, where: str):
    """Vertices and triangles of an OFF text (polygons split into fans, colours ignored)."""
    toks = [t for t in (ln.split("#", 1)[0].split() for ln in text.splitlines()) if t]
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


def load_cgal(source: str, name: str):
    """(V, F) of data/meshes/<name>.off in the archive or directory `source`, or None."""
    if os.path.isdir(source):
        for sub in ("", "data/meshes", "meshes"):
            p = os.path.join(source, sub, name + ".off")
            if os.path.exists(p):
                with open(p, encoding="utf-8", errors="replace") as f:
                    return parse_off(f.read(), p)
    elif os.path.exists(source):
        with tarfile.open(source) as tar:
            for member in tar:
                if member.name.lstrip("./") == f"data/meshes/{name}.off":
                    raw = tar.extractfile(member).read().decode("utf-8", "replace")
                    return parse_off(raw, member.name)
    return None


def uv_sphere(n: int, radius: float = 1.0):
    """A closed sphere of 2 n (n - 1) triangles."""
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


def subdivide(V, F):
    """1-to-4 subdivision at shared edge midpoints (the runner's, for meshes below its size)."""
    e = np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(e, axis=0, return_inverse=True)
    mid = len(V) + inv.reshape(3, -1)
    ab, bc, ca = mid
    V2 = np.vstack([V, 0.5 * (V[uniq[:, 0]] + V[uniq[:, 1]])])
    a, b, c = F.T
    F2 = np.stack([np.column_stack(x) for x in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))], 1)
    return V2, F2.reshape(-1, 3)


def normalized(V, size=1.0):
    """Box centred at the origin, largest side `size` (translated, then scaled, as the runner)."""
    lo, hi = V.min(axis=0), V.max(axis=0)
    ext = (hi - lo).max()
    V = V + (-(lo + hi) / 2.0)
    return V * (size / ext) if ext > 0 else V


def bent_rest(source: str):
    """The runner's short `bent` mesh: the elephant (at least 4,000 triangles), size 1."""
    m = load_cgal(source, "elephant")
    if m is None:
        note(f"CGAL's elephant not found ({source}; Debian package libcgal-demo): the bent scene "
             "uses a UV sphere of 5,512 triangles instead")
        V, F, name = *uv_sphere(53), "bent (UV sphere stand-in)"
    else:
        V, F, name = *m, "bent (elephant)"
    while len(F) < 4000:
        V, F = subdivide(V, F)
    return name, normalized(V), F


def diagonal(V) -> float:
    ext = V.max(axis=0) - V.min(axis=0)
    return float(np.sqrt(sum(float(x) ** 2 for x in ext)))


# ---------------------------------------------------------------------------------------------
# Topology for the cross-check


def groups(keys, values, n):
    """CSR grouping: (offsets, values sorted by key) for keys in [0, n)."""
    order = np.argsort(keys, kind="stable")
    offs = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(keys, minlength=n), out=offs[1:])
    return offs, values[order]


def expand(ids, offs, vals):
    """For each ids[i], every value of its group: (row i repeated, values)."""
    cnt = offs[ids + 1] - offs[ids]
    rows = np.repeat(np.arange(len(ids)), cnt)
    start = np.repeat(offs[ids] - (np.cumsum(cnt) - cnt), cnt)
    return rows, vals[start + np.arange(len(rows))]


class Topology:
    """Edges (sorted unique vertex pairs) and the vertex-face, vertex-edge and edge-face
    incidences of a triangle mesh, as CSR groups."""

    def __init__(self, nv: int, F: np.ndarray):
        self.nv, self.F = nv, F
        m = len(F)
        half = np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
        keys = half[:, 0] * nv + half[:, 1]
        self.ekeys, inv = np.unique(keys, return_inverse=True)
        inv = inv.ravel()
        self.E = np.column_stack([self.ekeys // nv, self.ekeys % nv])
        self.ne = len(self.E)
        fe = inv.reshape(3, m).T  # the edge ids of each face
        tri = np.arange(m)
        self.v_faces = groups(F.ravel(), np.repeat(tri, 3), nv)
        self.v_edges = groups(self.E.ravel(), np.repeat(np.arange(self.ne), 2), nv)
        self.e_faces = groups(fe.ravel(), np.repeat(tri, 3), self.ne)

    def edge_id(self, a, b):
        k = np.minimum(a, b).astype(np.int64) * self.nv + np.maximum(a, b)
        i = np.searchsorted(self.ekeys, k)
        assert np.all(self.ekeys[np.minimum(i, self.ne - 1)] == k), "not an edge of the mesh"
        return i

    def vf_key(self, v, f):
        return v.astype(np.int64) * len(self.F) + f

    def ee_key(self, e, g):
        return np.minimum(e, g).astype(np.int64) * self.ne + np.maximum(e, g)

    def faces_without(self, owner, incidence, v):
        """VF keys (v[i], f) for every face f incident (by `incidence`) to owner[i] that does not
        contain v[i]."""
        rows, f = expand(owner, *incidence)
        w = v[rows]
        ok = (self.F[f] != w[:, None]).all(axis=1)
        return self.vf_key(w[ok], f[ok]), rows[ok]

    def edges_apart(self, ea, eb):
        """EE keys of edges ea[i], eb[i] that share no vertex."""
        A, B = self.E[ea], self.E[eb]
        ok = (A[:, :1] != B).all(axis=1) & (A[:, 1:] != B).all(axis=1)
        return self.ee_key(ea[ok], eb[ok]), ok


# Distances, vectorised; the true Euclidean distance between the features, however ipctk
# classified them.


def _dot(a, b):
    return np.einsum("ij,ij->i", a, b)


def point_segment(p, a, b):
    ab = b - a
    t = np.clip(_dot(p - a, ab) / np.maximum(_dot(ab, ab), 1e-300), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


def segment_segment(p1, q1, p2, q2):
    """The least of the four end-to-segment distances and, when the lines' closest points lie
    on both segments, the distance between those points."""
    d = np.minimum.reduce([point_segment(p1, p2, q2), point_segment(q1, p2, q2),
                           point_segment(p2, p1, q1), point_segment(q2, p1, q1)])
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, b = _dot(d1, d1), _dot(d2, d2), _dot(d1, d2)
    c, f = _dot(d1, r), _dot(d2, r)
    den = a * e - b * b
    ok = den > 1e-12 * a * e
    den = np.where(ok, den, 1.0)
    s = (b * f - c * e) / den
    t = (a * f - b * c) / den
    ok &= (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
    inner = np.linalg.norm(p1 + s[:, None] * d1 - (p2 + t[:, None] * d2), axis=1)
    return np.where(ok, np.minimum(d, inner), d)


def point_triangle(p, a, b, c):
    d = np.minimum.reduce([point_segment(p, a, b), point_segment(p, b, c), point_segment(p, c, a)])
    n = np.cross(b - a, c - a)
    inside = ((_dot(np.cross(b - a, p - a), n) >= 0) & (_dot(np.cross(c - b, p - b), n) >= 0)
              & (_dot(np.cross(a - c, p - c), n) >= 0))
    plane = np.abs(_dot(p - a, n)) / np.maximum(np.linalg.norm(n, axis=1), 1e-300)
    return np.where(inside, np.minimum(d, plane), d)


def ipctk_ids(collisions, topo: Topology, ipc_edges: np.ndarray):
    """The collisions' primitives as int64 arrays in `topo`'s numbering: vv (a, b), ev (edge,
    vertex), ee (edge, edge), fv (face, vertex)."""

    def pairs(lst, x, y):
        out = np.fromiter((v for k in lst for v in (getattr(k, x), getattr(k, y))), dtype=np.int64,
                          count=2 * len(lst))
        return out.reshape(-1, 2)

    emap = topo.edge_id(ipc_edges[:, 0], ipc_edges[:, 1])  # ipctk's edge order -> ours
    vv = pairs(collisions.vv_collisions, "vertex0_id", "vertex1_id")
    ev = pairs(collisions.ev_collisions, "edge_id", "vertex_id")
    ee = pairs(collisions.ee_collisions, "edge0_id", "edge1_id")
    fv = pairs(collisions.fv_collisions, "face_id", "vertex_id")
    ev[:, 0], ee = emap[ev[:, 0]], emap[ee]
    return vv, ev, ee, fv


def dvh_keys(near, topo: Topology, d: float) -> dict:
    """dvh's stencils as VF and EE keys in `topo`'s numbering, each with whether its distance is
    a near tie: all the cross-check needs, far smaller than the result."""
    kind = near["kind"]
    is_vf, is_ee = kind == dvh.IMPACT_VERTEX_FACE, kind == dvh.IMPACT_EDGE_EDGE
    tie = np.abs(near["distance"] - d) <= TIE * d
    ee = near[["a0", "a1", "b0", "b1"]][is_ee]
    return {"vf": topo.vf_key(near["a0"][is_vf], near["b0"][is_vf]), "vf tie": tie[is_vf],
            "ee": topo.ee_key(topo.edge_id(ee["a0"], ee["a1"]), topo.edge_id(ee["b0"], ee["b1"])),
            "ee tie": tie[is_ee]}


def cross_check(mine: dict, theirs, P, topo: Topology, d: float) -> dict:
    """ipctk's collisions against dvh's stencils.

    Every ipctk collision stands for a pair of features (vertex-vertex, edge-vertex, edge-edge,
    face-vertex) within d; every vertex-face and edge-edge primitive pair containing those two
    features is then within d too, so dvh must report it. Collisions whose own distance is
    within TIE (relative) of d are left out of that test; those beyond it are counted. The other
    way, every dvh stencil (not at a near tie) should be implied by some ipctk collision, as
    ipctk's collision for that candidate pair contains both primitives' closest features."""
    vv, ev, ee, fv = theirs
    F, E = topo.F, topo.E
    dist = np.concatenate([
        np.linalg.norm(P[vv[:, 0]] - P[vv[:, 1]], axis=1),
        point_segment(P[ev[:, 1]], P[E[ev[:, 0], 0]], P[E[ev[:, 0], 1]]),
        segment_segment(P[E[ee[:, 0], 0]], P[E[ee[:, 0], 1]], P[E[ee[:, 1], 0]], P[E[ee[:, 1], 1]]),
        point_triangle(P[fv[:, 1]], P[F[fv[:, 0], 0]], P[F[fv[:, 0], 1]], P[F[fv[:, 0], 2]]),
    ])
    beyond = int(np.sum(dist > d * (1 + TIE)))
    tie = np.abs(dist - d) <= TIE * d
    o = np.cumsum([0, len(vv), len(ev), len(ee), len(fv)])
    tie_vv, tie_ev, tie_ee, tie_fv = (tie[o[k]:o[k + 1]] for k in range(4))

    # Implied pairs, each with whether its source collision is a near tie.
    vf_keys, vf_tie, ee_keys, ee_tie = [], [], [], []
    a, b = vv[:, 0], vv[:, 1]
    for x, y in ((a, b), (b, a)):  # x against the faces round y
        k, rows = topo.faces_without(y, topo.v_faces, x)
        vf_keys.append(k), vf_tie.append(tie_vv[rows])
    ra, ea = expand(a, *topo.v_edges)
    rows, eb = expand(b[ra], *topo.v_edges)
    k, ok = topo.edges_apart(ea[rows], eb)
    ee_keys.append(k), ee_tie.append(tie_vv[ra[rows]][ok])
    e, v = ev[:, 0], ev[:, 1]
    k, rows = topo.faces_without(e, topo.e_faces, v)
    vf_keys.append(k), vf_tie.append(tie_ev[rows])
    rows, ev_ = expand(v, *topo.v_edges)
    k, ok = topo.edges_apart(e[rows], ev_)
    ee_keys.append(k), ee_tie.append(tie_ev[rows][ok])
    ee_keys.append(topo.ee_key(ee[:, 0], ee[:, 1])), ee_tie.append(tie_ee)
    vf_keys.append(topo.vf_key(fv[:, 1], fv[:, 0])), vf_tie.append(tie_fv)

    out = {"checked": int(len(dist) - tie.sum()), "beyond": beyond, "ties": int(tie.sum()),
           "implied": 0, "missing": 0, "unimplied": 0}
    for keys, ties, kind in ((vf_keys, vf_tie, "vf"), (ee_keys, ee_tie, "ee")):
        keys, ties = np.concatenate(keys), np.concatenate(ties)
        firm, every = unique(keys[~ties]), unique(keys)
        ours, ours_tie = mine[kind], mine[kind + " tie"]
        out["implied"] += len(firm)
        out["missing"] += int(np.sum(~member(firm, unique(ours))))
        out["unimplied"] += int(np.sum(~member(unique(ours[~ours_tie]), every)))
    return out


def unique(x):
    """Sorted distinct values (by sorting: faster here than NumPy's hashing unique)."""
    s = np.sort(x)
    return s[np.concatenate(([True], s[1:] != s[:-1]))] if len(s) else s


def member(x, sorted_set):
    """x[i] in sorted_set, for each i."""
    if len(sorted_set) == 0:
        return np.zeros(len(x), dtype=bool)
    i = np.minimum(np.searchsorted(sorted_set, x), len(sorted_set) - 1)
    return sorted_set[i] == x


# ---------------------------------------------------------------------------------------------
# Timing


def spread(frames: int):
    """Frame indices in an order whose every prefix is spread over [0, 1) (van der Corput),
    starting from the last frame, where the flap (or the ends) have come through the mesh, so
    that a distance cut short by the time budget still sees the contact."""
    order = []
    for k in range(frames):
        x, f, b = 0.0, 0.5, k
        while b:
            x += f * (b & 1)
            b >>= 1
            f /= 2
        i = (int(x * frames) + frames - 1) % frames
        if i not in order:
            order.append(i)
    return order + [i for i in range(frames) if i not in order]


def measure_frame(mesh, cm, P, Pf, d, reps, cap, rot, digest):
    """One frame at one distance: each method up to `reps` times, taking turns (the order rotated
    by `rot`), a method stopping once its runs in this frame took `cap` seconds; the fastest run
    of each. Every run gives the same result: the first is reduced by digest[method] (untimed)
    and the rest dropped at once, so that no large result is held while another method runs.
    Returns {method: (wall s, cpu s, digest, extra)}; extra["grew"]: the largest rise of the
    resident size during one call above the size before it (bytes)."""

    def stencils():
        t0 = perf()
        mesh.refit(P)  # untimed in the query: a query may keep what it found about the positions
        t1, c1 = perf(), cpu()
        out, st = dvh.self_nearest_features(mesh, d, threads=0, stats=True)
        return perf() - t1, cpu() - c1, out, {"refit": t1 - t0, "tests": st.triangle_tests}

    def prox():
        mesh.refit(P)
        t1, c1 = perf(), cpu()
        out = dvh.self_proximity(mesh, d, threads=0)
        return perf() - t1, cpu() - c1, out, {}

    def build():
        c = ipctk.NormalCollisions()
        t1, c1 = perf(), cpu()
        c.build(cm, Pf, d)  # broad_phase None: ipctk's default, LBVH
        return perf() - t1, cpu() - c1, c, {}

    def split():
        cands, c = ipctk.Candidates(), ipctk.NormalCollisions()
        t0 = perf()
        cands.build(cm, Pf, 0.5 * d)  # what build(mesh, V, dhat) does: boxes inflated by dhat / 2
        t1 = perf()
        c.build(cands, cm, Pf, d)
        t2 = perf()
        return t2 - t0, 0.0, None, {"broad": t1 - t0, "narrow": t2 - t1, "candidates": len(cands)}

    methods = {"stencils": stencils, "proximity": prox}
    if ipctk is not None:
        methods.update({"ipctk": build, "ipctk split": split})
    names = list(methods)
    best, spent, runs = {}, {n: 0.0 for n in names}, {n: 0 for n in names}
    extra_best, grew = {}, {}
    for r in range(reps):
        k = (rot + r) % len(names)
        for n in names[k:] + names[:k]:
            if runs[n] and spent[n] >= cap:
                continue
            gc.collect()
            rss = vm("VmRSS") if reset_peak() else float("nan")
            gc.disable()
            try:
                w, c, out, extra = methods[n]()
            finally:
                gc.enable()
            hwm = vm("VmHWM")
            peak_seen[0] = max(peak_seen[0], hwm if hwm == hwm else 0.0)
            rise = hwm - rss
            grew[n] = rise if rise != rise or n not in grew else max(grew[n], rise)
            spent[n] += w
            runs[n] += 1
            if n not in best:
                best[n] = (w, c, digest[n](out) if n in digest else None, extra)
            elif w < best[n][0]:
                best[n] = (w, c, best[n][2], extra)
            for key in ("refit", "broad", "narrow"):  # each part's own fastest
                if key in extra:
                    extra_best[(n, key)] = min(extra_best.get((n, key), float("inf")), extra[key])
            del out
    for (n, key), v in extra_best.items():
        best[n][3][key] = v
    for n, g in grew.items():
        best[n][3]["grew"] = g
    return best, runs


def bench_scene(name, rest, F, at, frames, reps, cap, budget, check):
    """Rows of the three tables for one deforming mesh."""
    diag = diagonal(rest)
    Fu = F.astype(np.uint32)
    mesh = dvh.Mesh(np.ascontiguousarray(rest), Fu)
    cm = ipc_edges = None
    if ipctk is not None:
        Fi = np.asfortranarray(F.astype(np.int32))
        ipc_edges = np.asfortranarray(ipctk.edges(Fi))
        cm = ipctk.CollisionMesh(np.asfortranarray(rest), ipc_edges, Fi)
    topo = Topology(len(rest), F) if check and ipctk is not None else None
    # One untimed query at rest first: the first call also finds what depends on the shape alone.
    dvh.self_nearest_features(mesh, 0.0)
    order = spread(frames)
    timing, counts, checks, memory = [], [], [], []
    for frac in FRACTIONS:
        d = frac * diag
        label = f"{frac * 100:g} % ({d:.3g})"
        progress(f"{name}: d = {label}")
        per = {k: [] for k in ("stencils", "proximity", "ipctk", "refit", "broad", "narrow", "cores dvh",
                               "cores prox", "cores ipctk", "vf", "ee", "pairs", "tests", "vv", "ev", "iee",
                               "fv", "candidates", "bytes", "grew dvh", "grew ipctk")}
        tot = {"checked": 0, "beyond": 0, "ties": 0, "implied": 0, "missing": 0, "unimplied": 0}
        done = []
        started = perf()

        def near_digest(near, d=d):
            out = {"vf": int(np.sum(near["kind"] == dvh.IMPACT_VERTEX_FACE)),
                   "ee": int(np.sum(near["kind"] == dvh.IMPACT_EDGE_EDGE)), "bytes": near.nbytes}
            if topo is not None:
                out["keys"] = dvh_keys(near, topo, d)
            return out

        def ipctk_digest(coll):
            out = {k: len(getattr(coll, k + "_collisions")) for k in ("vv", "ev", "ee", "fv")}
            if topo is not None:
                out["ids"] = ipctk_ids(coll, topo, ipc_edges)
            return out

        digest = {"stencils": near_digest, "proximity": len, "ipctk": ipctk_digest}
        for i, f in enumerate(order):
            t = f / frames
            P = np.ascontiguousarray(at(rest, t))
            Pf = np.asfortranarray(P)
            t0 = perf()
            best, runs = measure_frame(mesh, cm, P, Pf, d, reps, cap, i, digest)
            w, c, near, x = best["stencils"]
            per["stencils"].append(w), per["cores dvh"].append(c / w), per["refit"].append(x["refit"])
            per["tests"].append(x["tests"])
            for k in ("vf", "ee", "bytes"):
                per[k].append(near[k])
            per["grew dvh"].append(x["grew"])
            w, c, pairs, _ = best["proximity"]
            per["proximity"].append(w), per["cores prox"].append(c / w), per["pairs"].append(pairs)
            msg = (f"  t = {t:.3f}: stencils {ms(per['stencils'][-1])} ms ({runs['stencils']} runs), "
                   f"proximity {ms(per['proximity'][-1])} ms")
            if ipctk is not None:
                w, c, coll, _ = best["ipctk"]
                per["ipctk"].append(w), per["cores ipctk"].append(c / w)
                per["grew ipctk"].append(best["ipctk"][3]["grew"])
                for k in ("vv", "ev", "fv"):
                    per[k].append(coll[k])
                per["iee"].append(coll["ee"])
                x = best["ipctk split"][3]
                per["broad"].append(x["broad"]), per["narrow"].append(x["narrow"])
                per["candidates"].append(x["candidates"])
                msg += f", ipctk {ms(per['ipctk'][-1])} ms ({runs['ipctk']} runs)"
                if topo is not None:
                    t1 = perf()
                    res = cross_check(near["keys"], coll["ids"], P, topo, d)
                    for k in tot:
                        tot[k] += res[k]
                    msg += f"; check {perf() - t1:.1f} s, {res['missing']} missing, {res['unimplied']} unimplied"
            del near, best
            done.append(t)
            progress(msg + f"; frame {perf() - t0:.1f} s")
            spent = perf() - started
            if spent + spent / len(done) > budget and len(done) < len(order):
                break
        nf = len(done)
        fr = str(nf) if nf == frames else f"{nf} of {frames} (t = {', '.join(f'{t:.3g}' for t in done)})"
        m = {k: med(v) for k, v in per.items()}
        split = f"{ms(m['ipctk'])} ({ms(m['broad'])} + {ms(m['narrow'])})" if ipctk is not None else "—"
        timing.append([name, f"{len(F):,}", label, fr, ms(m["refit"]), ms(m["stencils"]), ms(m["proximity"]),
                       split, ratio(m["ipctk"], m["stencils"]), ratio(m["stencils"], m["proximity"]),
                       f"{m['cores dvh']:.2f} / {m['cores prox']:.2f} / {m['cores ipctk']:.2f}"])
        dv = med([a + b for a, b in zip(per["vf"], per["ee"])])
        ic = med([a + b + c + e for a, b, c, e in zip(per["vv"], per["ev"], per["iee"], per["fv"])])
        counts.append([name, label, f"{count(dv)} ({count(m['vf'])} + {count(m['ee'])})",
                       f"{m['bytes'] / 2**20:.3g}", count(m["tests"]), count(m["pairs"]),
                       f"{count(ic)} ({count(m['vv'])} / {count(m['ev'])} / {count(m['iee'])} / {count(m['fv'])})"
                       if ipctk is not None else "—",
                       count(m["candidates"]) if ipctk is not None else "—",
                       ratio(ic, dv) if dv > 0 else "—"])
        if topo is not None:
            checks.append([name, label, nf, count(tot["checked"]), tot["beyond"], tot["ties"],
                           count(tot["implied"]), tot["missing"], tot["unimplied"]])
        first_n = per["vf"][0] + per["ee"][0]
        # Per item only where the call's own needs show (dvh's buffers grew past the result) and
        # the items outweigh fixed costs.
        big = first_n >= 10_000 and per["grew dvh"][0] >= max(per["bytes"][0], 2**20)
        per_stencil = f" ({per['grew dvh'][0] / first_n:.0f} B per stencil)" if big else ""
        per_coll = m["grew ipctk"] / ic if ic >= 10_000 and m["grew ipctk"] >= 2**20 else float("nan")
        memory.append([name, label, mb(per["bytes"][0]), mb(per["grew dvh"][0]) + per_stencil,
                       mb(med(per["grew dvh"][1:])) if nf > 1 else "—",
                       (mb(m["grew ipctk"]) + (f" ({per_coll:.0f} B per collision)" if per_coll == per_coll else ""))
                       if ipctk is not None else "—",
                       mb(vm("VmRSS"))])
    return timing, counts, checks, memory


# ---------------------------------------------------------------------------------------------


def versions() -> dict:
    with open(os.path.join(os.path.dirname(dvh.__file__), "_api.py"), "rb") as f:
        api = hashlib.sha256(f.read()).hexdigest()[:12]
    out = {"Python": platform.python_version(), "dvh": f"{dvh.version()} (_api.py {api})"}
    for dist in ("numpy", "cffi", "ipctk"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="the runner's short sheet (3,200 triangles), 6 frames, fewer repeats, a smaller "
                         "time budget (about 1 to 2 minutes)")
    ap.add_argument("--cells", type=int, default=None,
                    help="sheet cells per side (default 100: 20,000 triangles; 40 with --quick)")
    ap.add_argument("--frames", type=int, default=None, help="frames over t in [0, 1) (default 8; 6 with --quick)")
    ap.add_argument("--budget", type=float, default=None,
                    help="seconds per mesh and distance: once the next frame would pass it, the remaining "
                         "frames are skipped (at least one is measured; default 75; 12 with --quick)")
    ap.add_argument("--cgal-data", default=CGAL_DATA, help="libcgal-demo's data.tar.gz, or a directory of .off files")
    ap.add_argument("--seed", type=int, default=20240601,
                    help="unused: every scene here is deterministic (kept for the other scripts' command line)")
    ap.add_argument("--skip", default="", help="comma-separated parts to skip: sheet,bent,cloth,check")
    args = ap.parse_args()
    q = args.quick
    skip = set(filter(None, args.skip.split(",")))
    cells = args.cells or (40 if q else 100)
    frames = args.frames or (6 if q else 8)
    budget = args.budget if args.budget is not None else (12.0 if q else 75.0)
    reps, cap = (2, 0.5) if q else (3, 1.0)
    started = perf()
    date = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    threads = ""
    if ipctk is None:
        note("ipctk is not installed: only dvh is measured")
    else:
        ipctk.set_logger_level(ipctk.LoggerLevel.off)
        ipctk.set_num_threads(os.cpu_count() or 1)
        threads = f"ipctk `set_num_threads({os.cpu_count()})`, `get_num_threads()` {ipctk.get_num_threads()}"

    ver = versions()
    print(f"## dvh closest-point stencils against IPC Toolkit's collision set ({'quick' if q else 'full'} run)\n\n"
          f"{date}; {os.cpu_count()} cores; {platform.machine()} {platform.system()}; "
          + ", ".join(f"{k} {v}" for k, v in ver.items())
          + f".\n\nThreads: dvh `threads=0` (every core); {threads} (TBB). ipctk: "
          "`NormalCollisions().build(mesh, V, dhat=d)` with the default `broad_phase=None` (its LBVH, "
          "`make_default_broad_phase()`), `dmin=0`, the default collision set type (IPC) and no area "
          "weighting; on a `CollisionMesh(rest, edges(F), F)` built once. Its `dhat` is a distance, "
          "not squared: the broad phase inflates every box by dhat / 2 and a candidate is kept when "
          "its squared distance is < dhat² (strictly: a pair at exactly d is dropped, where dvh's "
          "`distance <= d` keeps it).\n", flush=True)

    scenes = []
    if "sheet" not in skip:
        V, F = grid(cells, 1.0)
        scenes.append(("sheet", V, F, sheet_at))
    if "bent" not in skip:
        name, V, F = bent_rest(args.cgal_data)
        scenes.append((name, V, F, bent_at))
    if "cloth" not in skip:
        progress("simulating the cloth")
        Fc, _, states, _ = cloth_steps.simulate(32 if q else 64, CLOTH_STEPS)

        def cloth_at(rest, t, states=states):
            # The frames spread over the steps in self-contact (the sheet lands about step 45).
            return states[CLOTH_FROM + min(int(t * (len(states) - CLOTH_FROM)), len(states) - CLOTH_FROM - 1)]

        scenes.append(("cloth simulation", states[CLOTH_FROM], Fc.astype(np.int64), cloth_at))
    timing, counts, checks, memory = [], [], [], []
    for name, V, F, at in scenes:
        t, c, k, mem = bench_scene(name, V, F, at, frames, reps, cap, budget, "check" not in skip)
        memory += mem
        timing += t
        counts += c
        checks += k

    print(f"### Time per frame (medians over frames of each frame's fastest of up to {reps} runs, ms)\n\n"
          "Frames at t = k / frames, as the runner's; the last frame (past the crossing) first, then "
          "spread over the motion; a distance "
          f"stops taking frames once the next would pass {budget:g} s (*frames* says which were used). "
          "Before every dvh call the mesh is refit to the frame (the *refit* column, not in the query "
          "times; ipctk has nothing to refit: its build makes its broad phase from scratch). The dvh "
          "times include handing the result to NumPy (an array viewing the library's buffer, no copy); "
          "ipctk's result stays in C++. "
          "*broad + narrow*: `Candidates.build(mesh, V, d / 2)` then `NormalCollisions.build(candidates, "
          "mesh, V, d)`, timed apart in separate runs. *cores*: process CPU time ÷ wall time of the "
          "fastest run, so 2 means both cores busy throughout.\n")
    print(table(["mesh", "triangles", "d (% of diagonal)", "frames", "dvh refit", "dvh self_nearest_features",
                 "dvh self_proximity", "ipctk build (broad + narrow)", "ipctk ÷ dvh stencils",
                 "dvh stencils ÷ dvh proximity", "cores: stencils / proximity / ipctk"], timing) + "\n", flush=True)
    print("### Counts per frame (medians over the same frames)\n\n"
          "dvh reports every vertex-face and edge-edge pair (sharing no vertex) within d. ipctk keeps, "
          "for every such candidate within d, the pair of features its closest points lie on "
          "(vertex-vertex, edge-vertex, edge-edge or face-vertex) and merges duplicates, so one ipctk "
          "collision stands for all the dvh stencils with the same closest features (nearly parallel "
          "edge pairs stay edge-edge, for its mollifier): its count is smaller. *MB*: the result array "
          f"at {dvh.NEAR_PAIR_DTYPE.itemsize} bytes (`NEAR_PAIR_DTYPE.itemsize`) per stencil. *primitive "
          "tests*: dvh's exact vertex-face and edge-edge tests (`stats.triangle_tests`).\n")
    print(table(["mesh", "d", "dvh stencils (vertex-face + edge-edge)", "dvh result MB", "dvh primitive tests",
                 "dvh self_proximity triangle pairs",
                 "ipctk collisions (vertex-vertex / edge-vertex / edge-edge / face-vertex)", "ipctk candidates",
                 "ipctk ÷ dvh count"], counts) + "\n", flush=True)
    if checks:
        print("### Cross-check (sums over the frames)\n\n"
              "Each ipctk collision's features are measured again here (the true Euclidean distance, in "
              "floating point): *beyond d* counts those farther than d, *near ties* those within a "
              f"relative {TIE:g} of d (left out below, as floating point may decide them either way). "
              "Every vertex-face and edge-edge primitive pair containing a collision's two features is "
              "within d too, so dvh must report it: *implied* counts those distinct pairs, *missing from "
              "dvh* the ones dvh lacks. *dvh not implied*: dvh stencils (not at a near tie) implied by "
              "no ipctk collision, i.e. pairs within d that ipctk's broad phase or distance test "
              "dropped.\n")
        print(table(["mesh", "d", "frames", "ipctk collisions checked", "beyond d", "near ties",
                     "dvh primitive pairs implied", "missing from dvh", "dvh not implied"], checks) + "\n",
              flush=True)

    if memory:
        print("### Memory (resident size, MB)\n\n"
              "*rise*: the process's peak resident size during one call minus its resident size just "
              "before it (Linux: the peak is reset through /proc/self/clear_refs; — elsewhere), the "
              "largest over a frame's runs. dvh keeps its result buffers between calls, sized to the "
              "largest result so far in the process (any mesh), so a rise is only what a call needs "
              "beyond buffers earlier results left (0 when they suffice); where the first frame's "
              "result is the largest yet, its rise per stencil is what a fresh call needs, the "
              "array included (it views the library's buffer). *after*: the process's "
              "resident size once the distance is done and its results are freed (what stays "
              "allocated: dvh's buffers, the Python heap, freed memory not returned).\n")
        print(table(["mesh", "d", "dvh result (first frame)", "dvh rise, first call", "dvh rise, later frames (median)",
                     "ipctk build rise (median)", "process after"], memory) + "\n", flush=True)

    ru = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0  # kB on Linux
    peak = max(peak_seen[0], ru)
    tail = f"Run time {perf() - started:.0f} s; peak resident memory of the process {peak / 2**20:,.0f} MB."
    tail += "".join(f"\n- note: {n}" for n in notes)
    print(tail)


if __name__ == "__main__":
    main()
