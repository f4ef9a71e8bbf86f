#!/usr/bin/env python3
"""dvh's continuous collision detection (CCD) against IPC Toolkit's Tight Inclusion CCD
(``ipctk``), measured in the same run.

1. primitive queries, vertex-face and edge-edge: four sets of 2,000 queries each (random motions
   in the unit cube; motions that certainly meet; degenerate motions on a dyadic grid; near
   misses at 1e-9..1e-4) and a hard set of 2,000 (tangential grazing, coplanar motion in tilted
   planes, contacts on edges and corners at dyadic times, at scales 1e-151 to 1e150, far from
   the origin, and with exponents a thousand binades apart), each call timed alone: time per
   call (median, 99th and 99.9th percentile, max), hits, false positives and negatives against
   dvh's exact mode, and how much earlier (or later) than the exact time of impact each tool
   reports;
2. one mesh's self CCD per step (a cloth folding over itself, the cloth draped and jittered, an
   icosphere under a smooth displacement field, and three steps of a cloth simulation,
   ``cloth_steps.py``, where the sheet rests and slides on itself): dvh's ``refit_motion`` +
   ``self_continuous_collide`` against ``ipctk.compute_collision_free_stepsize``;
3. two meshes (a sheet falling onto a sphere): ``dvh.continuous_collide`` against ipctk on one
   ``CollisionMesh`` holding both;
4. python-fcl's mesh-mesh ``continuousCollide`` on a rigidly translating sphere, checked
   against dvh's exact time of impact.

Prints Markdown tables. Ground truth everywhere is dvh's exact mode (exact for every finite
input: the earliest contact time rounded down to a double). Needs dvh (``pip install
./python``), ``ipctk`` and optionally ``python-fcl``:

    python -m venv .ccd && .ccd/bin/pip install ./python ipctk python-fcl
    .ccd/bin/python python/bench/ccd_peers.py [--quick]
"""

from __future__ import annotations

import argparse
import gc
import hashlib
import os
import platform
import sys
import time
from datetime import datetime, timezone
from fractions import Fraction
from importlib import metadata

import numpy as np

import dvh
from dvh._dvh import ffi, lib

import cloth_steps

# The simulated cloth's steps, and those whose motions are measured: all in resting and sliding
# self-contact (the sheet lands about step 45).
CLOTH_STEPS = 150
CLOTH_BENCH_STEPS = (60, 100, 140)

try:
    import ipctk
except ImportError:
    ipctk = None

try:
    import fcl
except ImportError:
    fcl = None

perf = time.perf_counter
ns = time.perf_counter_ns
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


def us(x_ns: float) -> str:
    x = x_ns / 1e3
    if x != x:
        return "—"
    return f"{x:.2f}" if x < 10 else f"{x:.3g}" if x < 1000 else f"{x:.0f}"


def ms(x: float) -> str:
    if x != x:
        return "—"
    x *= 1e3
    return f"{x:.3g}" if x < 100 else f"{x:.0f}"


def sci(x: float) -> str:
    if x != x:
        return "—"
    return "0" if x == 0 else f"{x:.2e}"


def ratio(x: float, ref: float) -> str:
    return f"{x / ref:.3g}×" if ref > 0 and x == x else "—"


# ---------------------------------------------------------------------------------------------
# 1. Primitive query sets: (N, 4, 3) start and end arrays. Vertex-face rows: the point, then the
# triangle's corners; edge-edge rows: edge a's two ends, then edge b's.


def unit(v):
    return v / np.linalg.norm(v)


def random_set(rng, n):
    """Four points at random in the unit cube at t = 0 and again at t = 1 (mostly misses)."""
    return rng.random((n, 4, 3)), rng.random((n, 4, 3))


def vf_hits(rng, n):
    """A point passing through a moving triangle's interior (barycentrics >= 0.05) at a random
    time t* in [0.02, 0.98]; every corner moves on its own. The exact toi is t* or earlier."""
    S, E = np.empty((n, 4, 3)), np.empty((n, 4, 3))
    i = 0
    while i < n:
        T0 = rng.random((3, 3))
        T1 = T0 + rng.normal(scale=0.3, size=(3, 3))
        ts = rng.uniform(0.02, 0.98)
        Tt = T0 + ts * (T1 - T0)
        if np.linalg.norm(np.cross(Tt[1] - Tt[0], Tt[2] - Tt[0])) < 0.1:
            continue
        b = rng.dirichlet([1.0, 1.0, 1.0])
        if b.min() < 0.05:
            continue
        x = b @ Tt
        v = rng.normal(scale=0.5, size=3)
        p0 = x - ts * v
        S[i] = np.vstack([p0, T0])
        E[i] = np.vstack([p0 + v, T1])
        i += 1
    return S, E


def ee_hits(rng, n):
    """Edge b passing through an interior point (parameter 0.1..0.9) of edge a at a random time;
    all four ends move on their own."""
    S, E = np.empty((n, 4, 3)), np.empty((n, 4, 3))
    i = 0
    while i < n:
        A0 = rng.random((2, 3))
        A1 = A0 + rng.normal(scale=0.3, size=(2, 3))
        ts = rng.uniform(0.02, 0.98)
        At = A0 + ts * (A1 - A0)
        if np.linalg.norm(At[1] - At[0]) < 0.1:
            continue
        q = At[0] + rng.uniform(0.1, 0.9) * (At[1] - At[0])
        d = unit(rng.normal(size=3))
        Bt = np.vstack([q - rng.uniform(0.1, 0.5) * d, q + rng.uniform(0.1, 0.5) * d])
        vb = rng.normal(scale=0.5, size=(2, 3))
        B0 = Bt - ts * vb
        S[i] = np.vstack([A0, B0])
        E[i] = np.vstack([A1, B0 + vb])
        i += 1
    return S, E


# Degenerate sets: every coordinate a multiple of 1/16 (exact in binary), times of contact in
# {0, 1/4, 1/2, 3/4, 1}, velocities multiples of 1/4.

T_STARS = np.array([0.0, 0.25, 0.5, 0.75, 1.0])


def gp(rng, k=3):
    """A grid point: k coordinates in {0, 1/16, ..., 1}."""
    return rng.integers(0, 17, size=k) / 16.0


def gv(rng, nonzero=True):
    """A grid velocity: coordinates in {-1, -3/4, ..., 1}."""
    while True:
        v = rng.integers(-4, 5, size=3) / 4.0
        if not nonzero or v.any():
            return v


def even_step(rng):
    """A grid vector with even sixteenths, so that its midpoint from a grid point is on the grid."""
    while True:
        v = 2 * rng.integers(-4, 5, size=3) / 16.0
        if v.any():
            return v


def through(rng, target0, w, ts):
    """A point that is at target0 + ts w (a feature moving with velocity w) at time ts."""
    v = gv(rng)
    p0 = target0 + ts * (w - v)
    return p0, p0 + v


def vf_degenerate_one(rng, kind):
    tri = np.vstack([gp(rng), gp(rng), gp(rng)])
    w = gv(rng, nonzero=False) if rng.random() < 0.5 else np.zeros(3)
    ts = rng.choice(T_STARS)
    if kind == "coplanar":  # everything in one plane z = c; the triangle slides in it
        z = rng.integers(0, 17) / 16.0
        tri = np.column_stack([rng.integers(0, 17, size=(3, 2)) / 16.0, np.full(3, z)])
        w = np.append(rng.integers(-4, 5, size=2) / 8.0, 0.0)
        p0 = np.append(gp(rng, 2), z)
        p1 = np.append(gp(rng, 2), z)
    elif kind == "corner":  # through a corner exactly
        p0, p1 = through(rng, tri[rng.integers(3)], w, ts)
    elif kind == "edge":  # through an edge's midpoint exactly
        j = rng.integers(3)
        tri[(j + 1) % 3] = tri[j] + even_step(rng)
        p0, p1 = through(rng, 0.5 * (tri[j] + tri[(j + 1) % 3]), w, ts)
    elif kind == "along_edge":  # along an edge's line, through its corner
        j = rng.integers(3)
        d = tri[(j + 1) % 3] - tri[j]
        p0 = tri[j] - rng.integers(1, 3) * d
        p1 = tri[j] + rng.integers(-1, 3) * d
        w = np.zeros(3)
    elif kind == "degenerate_triangle":  # collinear corners, or all three at one point
        c, d = gp(rng), even_step(rng) / 2
        tri = np.vstack([c, c + d, c + 2 * d]) if rng.random() < 0.7 else np.vstack([c, c, c])
        target = tri[1] + (0 if rng.random() < 0.7 else gv(rng) / 4)
        p0, p1 = through(rng, target, w, ts)
    elif kind == "t0_t1":  # touching at t = 0 or at t = 1
        j = rng.integers(3)
        on = [tri[j], 0.5 * (tri[j] + tri[(j + 1) % 3]), 0.25 * (tri[0] + tri[1]) + 0.5 * tri[2]][rng.integers(3)]
        ts = rng.choice([0.0, 1.0])
        p0, p1 = through(rng, on, w, ts)
    else:  # "still": no motion, the point on a corner, on an edge, or off the triangle
        w = np.zeros(3)
        j = rng.integers(3)
        p0 = [tri[j], 0.5 * (tri[j] + tri[(j + 1) % 3]), gp(rng)][rng.integers(3)]
        p1 = p0
    return np.vstack([p0, tri]), np.vstack([p1, tri + w])


def ee_degenerate_one(rng, kind):
    ts = rng.choice(T_STARS)
    if kind == "parallel":  # parallel edges moving into one line (overlapping or not)
        p, d, o = gp(rng), even_step(rng) / 2, even_step(rng) / 2
        a = np.vstack([p, p + d])
        b = np.vstack([p + o + rng.integers(-2, 3) * d, p + o + rng.integers(-2, 3) * d + 2 * d])
        ts = rng.choice([0.25, 0.5, 1.0])  # -o / ts stays on the grid
        m = -o / ts
        sa, ea = a, a
        sb, eb = b, b + m
    elif kind == "collinear":  # on one line, sliding along it; ends meeting or overlapping
        p, d = gp(rng), even_step(rng) / 2
        a = np.vstack([p, p + d])
        k = rng.integers(2, 5)
        b = np.vstack([p + k * d, p + (k + rng.integers(1, 3)) * d])
        sa, ea = a, a
        sb, eb = b, b - rng.integers(0, 5) * d
    elif kind == "zero_length":  # a point-like edge through the other's midpoint or end
        q0 = gp(rng)
        q1 = q0 + even_step(rng)
        b = np.vstack([q0, q1])
        w = gv(rng, nonzero=False) if rng.random() < 0.5 else np.zeros(3)
        target = [0.5 * (q0 + q1), q0][rng.integers(2)]
        p0, p1 = through(rng, target, w, ts)
        sa, ea = np.vstack([p0, p0]), np.vstack([p1, p1])
        sb, eb = b, b + w
    elif kind == "end_to_end":  # an end of a passing exactly through an end of b
        b = np.vstack([gp(rng), gp(rng)])
        w = gv(rng, nonzero=False) if rng.random() < 0.5 else np.zeros(3)
        p0, p1 = through(rng, b[rng.integers(2)], w, ts)
        other = gp(rng)
        sa, ea = np.vstack([p0, other]), np.vstack([p1, other + (p1 - p0)])
        sb, eb = b, b + w
    elif kind == "cross_at":  # b's midpoint sweeping through a's midpoint at t* in {0, .25, .., 1}
        a0 = gp(rng)
        a = np.vstack([a0, a0 + even_step(rng)])
        mid = 0.5 * (a[0] + a[1])
        h = even_step(rng) / 2
        v = gv(rng)
        sb = np.vstack([mid - h, mid + h]) - ts * v
        sa, ea = a, a
        eb = sb + v
    elif kind == "coplanar":  # all four ends in one plane z = c, moving in it
        z = rng.integers(0, 17) / 16.0
        pts = [np.append(gp(rng, 2), z) for _ in range(8)]
        sa, sb = np.vstack(pts[0:2]), np.vstack(pts[2:4])
        ea, eb = np.vstack(pts[4:6]), np.vstack(pts[6:8])
    elif kind == "two_points":  # both edges of zero length, meeting or not
        q = gp(rng)
        v = gv(rng)
        p0, p1 = through(rng, q + (0 if rng.random() < 0.7 else gv(rng) / 4), v, ts)
        sa, ea = np.vstack([p0, p0]), np.vstack([p1, p1])
        sb, eb = np.vstack([q, q]), np.vstack([q + v, q + v])
    else:  # "still_touching": no motion, crossing, touching at an end, or apart
        a0 = gp(rng)
        a = np.vstack([a0, a0 + even_step(rng)])
        mid = 0.5 * (a[0] + a[1])
        r = rng.integers(3)
        if r == 0:
            b = np.vstack([mid - even_step(rng) / 2, mid + 0])
            b[1] = mid + (mid - b[0])
        elif r == 1:
            b = np.vstack([a[1], gp(rng)])
        else:
            b = np.vstack([gp(rng), gp(rng)])
        sa, ea, sb, eb = a, a, b, b
    return np.vstack([sa, sb]), np.vstack([ea, eb])


VF_KINDS = ["coplanar", "corner", "edge", "along_edge", "degenerate_triangle", "t0_t1", "still"]
EE_KINDS = ["parallel", "collinear", "zero_length", "end_to_end", "cross_at", "coplanar",
            "two_points", "still_touching"]


def degenerate_set(rng, n, one, kinds):
    S, E = np.empty((n, 4, 3)), np.empty((n, 4, 3))
    for i in range(n):
        S[i], E[i] = one(rng, kinds[i % len(kinds)])
    return S, E


def vf_near(rng, n):
    """A point crossing a rigidly translating triangle's plane once, at distance delta in
    [1e-9, 1e-4] (log-uniform) outside one of its edges (parameter 0.1..0.9), moving along that
    edge and across the plane: its nearest approach is delta; it never touches."""
    S, E = np.empty((n, 4, 3)), np.empty((n, 4, 3))
    i = 0
    while i < n:
        T = rng.random((3, 3))
        nrm = np.cross(T[1] - T[0], T[2] - T[0])
        if np.linalg.norm(nrm) < 0.2:
            continue
        nrm = unit(nrm)
        j = rng.integers(3)
        a, b, c = T[j], T[(j + 1) % 3], T[(j + 2) % 3]
        ed = unit(b - a)
        out = unit(np.cross(nrm, ed))
        if out @ (c - a) > 0:
            out = -out
        delta = 10 ** rng.uniform(-9, -4)
        x = a + rng.uniform(0.1, 0.9) * (b - a) + delta * out
        w = rng.normal(scale=0.3, size=3)
        rel = rng.choice([-1, 1]) * rng.uniform(0.3, 1.0) * nrm + rng.normal(scale=0.3) * ed
        ts = rng.uniform(0.05, 0.95)
        v = w + rel
        p0 = x + ts * (w - v)  # at ts the triangle has moved by ts w and the point is at x + ts w
        S[i] = np.vstack([p0, T])
        E[i] = np.vstack([p0 + v, T + w])
        i += 1
    return S, E


def ee_near(rng, n):
    """Two translating edges at distance delta in [1e-9, 1e-4] (log-uniform): half of them slide
    past each other in parallel planes delta apart, their projections crossing mid-step; half
    cross with the lines meeting once, the meeting point delta beyond an end of edge a."""
    S, E = np.empty((n, 4, 3)), np.empty((n, 4, 3))
    i = 0
    while i < n:
        da, db = unit(rng.normal(size=3)), unit(rng.normal(size=3))
        nrm = np.cross(da, db)
        if np.linalg.norm(nrm) < 0.3:
            continue
        nrm = unit(nrm)
        delta = 10 ** rng.uniform(-9, -4)
        q = rng.random(3)
        ts = rng.uniform(0.05, 0.95)
        la, lb = rng.uniform(0.2, 0.6, size=2), rng.uniform(0.2, 0.6, size=2)
        va = rng.normal(scale=0.3, size=3)
        if i % 2 == 0:
            # parallel planes: b is delta above a along nrm; relative motion within the plane
            At = np.vstack([q - la[0] * da, q + la[1] * da])
            Bt = np.vstack([q + delta * nrm - lb[0] * db, q + delta * nrm + lb[1] * db])
            rel = rng.normal(scale=0.4) * da + rng.normal(scale=0.4) * db
        else:
            # lines meet once, at ts, delta beyond a's end a1
            At = np.vstack([q - la[0] * da, q])
            cpt = q + delta * da
            Bt = np.vstack([cpt - lb[0] * db, cpt + lb[1] * db])
            rel = rng.choice([-1, 1]) * rng.uniform(0.3, 1.0) * nrm + rng.normal(scale=0.3) * db
        vb = va + rel
        A0, B0 = At - ts * va, Bt - ts * vb
        S[i] = np.vstack([A0, B0])
        E[i] = np.vstack([A0 + va, B0 + vb])
        i += 1
    return S, E


# Hard sets: exact tangencies and contacts at dyadic times strictly inside the step, on a finer
# grid (thirty-seconds, times in sixty-fourths) so that every construction is exact in doubles,
# then placed at one of five scales. Tangential grazing: the coplanarity cubic f has a double
# root at t* (it touches zero there without crossing), the primitives then meeting inside, on an
# edge, at a corner or just apart. The exact path's slowest inputs are of these kinds.

HARD_SCALES = ["unit", "tiny", "huge", "far", "spread"]


def fine(rng, k=3, r=32):
    """k coordinates in {-1, -31/32, ..., 1}."""
    return rng.integers(-r, r + 1, size=k) / 32.0


def fine_v(rng):
    """A velocity in {-1, -15/16, ..., 1}^3."""
    return rng.integers(-16, 17, size=3) / 16.0


def hard_time(rng):
    return rng.integers(1, 64) / 64.0


def is_pow2(x):
    return x != 0 and np.frexp(abs(x))[0] == 0.5


def coplanarity_at(kind, s, e, t):
    """The coplanarity determinant at rational time t, exactly, ordered as dvh orders it."""
    p = [[Fraction(s[i][k]) + t * (Fraction(e[i][k]) - Fraction(s[i][k])) for k in range(3)] for i in range(4)]
    d = lambda i, j: [p[i][k] - p[j][k] for k in range(3)]  # noqa: E731
    u, v, w = (d(2, 1), d(3, 1), d(0, 1)) if kind == "vf" else (d(1, 0), d(2, 0), d(3, 0))
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))


def double_root_at(kind, s, e, ts):
    """Is ts a root of f of multiplicity two or more? f is a cubic: its values at four points
    give its derivative at ts exactly (Lagrange)."""
    ts = Fraction(ts)
    if coplanarity_at(kind, s, e, ts) != 0:
        return False
    xs = [Fraction(0), Fraction(1), Fraction(2), Fraction(3)]
    ys = [coplanarity_at(kind, s, e, x) for x in xs]
    deriv = Fraction(0)
    for i, xi in enumerate(xs):
        den = Fraction(1)
        for j, xj in enumerate(xs):
            if j != i:
                den *= xi - xj
        # d/dt prod_{j != i} (t - xj) at ts
        num = Fraction(0)
        for j in range(4):
            if j == i:
                continue
            term = Fraction(1)
            for k in range(4):
                if k not in (i, j):
                    term *= ts - xs[k]
            num += term
        deriv += ys[i] * num / den
    return deriv == 0


def vf_tangent(rng, where):
    """The point grazes the triangle's turning plane at t* (f has a double root there), meeting
    it inside, on an edge, at a corner, or 1/64 outside an edge."""
    while True:
        ts = hard_time(rng)
        T = np.vstack([fine(rng) for _ in range(3)])  # corners at t*
        W = np.vstack([fine_v(rng) for _ in range(3)])
        n = np.cross(T[1] - T[0], T[2] - T[0])
        if not is_pow2(n[2]):
            continue
        u, v = {"inside": (rng.integers(1, 8) / 16, rng.integers(1, 8) / 16),
                "edge": (rng.integers(1, 16) / 16, 0.0), "corner": (0.0, 0.0),
                "outside": (rng.integers(1, 16) / 16, -1 / 64)}[where]
        X = T[0] + u * (T[1] - T[0]) + v * (T[2] - T[0])
        dn = np.cross(W[1] - W[0], T[2] - T[0]) + np.cross(T[1] - T[0], W[2] - W[0])
        V = fine_v(rng)
        # f'(t*) = n . (V - A') + n' . (X - A*) = 0, solved for V_z (n_z a power of two: exact)
        V[2] = W[0][2] - (dn @ (X - T[0]) + n[0] * (V[0] - W[0][0]) + n[1] * (V[1] - W[0][1])) / n[2]
        s = np.vstack([X - ts * V, T - ts * W])
        e = s + np.vstack([V, W])
        if double_root_at("vf", s, e, ts):
            return s, e


def ee_tangent(rng, where):
    """The edges' lines graze coplanarity at t* (f has a double root there), the edges then
    crossing inside, an end of one on the other, end to end, or 1/64 apart."""
    while True:
        ts = hard_time(rng)
        a0, e1, e2 = fine(rng), fine(rng), fine(rng)
        q = lambda x, y: a0 + x * e1 + y * e2  # noqa: E731  the plane at t*, in its own coordinates
        if where == "cross":
            b = [q(rng.integers(1, 16) / 16, -rng.integers(1, 9) / 8), None]
            b[1] = q(rng.integers(1, 16) / 16, rng.integers(1, 9) / 8)
        elif where == "end_on":
            b = [q(rng.integers(1, 16) / 16, 0.0), q(rng.integers(-8, 9) / 8, rng.integers(1, 9) / 8)]
        elif where == "end_end":
            b = [q(1.0, 0.0), q(rng.integers(-8, 17) / 8, rng.integers(-8, 9) / 8)]
        else:  # "apart": b's line crosses a's 1/64 beyond its end
            y0, y1 = -rng.integers(1, 9) / 8, rng.integers(1, 9) / 8
            x = 1 + 1 / 64
            b = [q(x - y0 / 4, y0), q(x - y1 / 4, y1)]
        P = np.vstack([a0, a0 + e1, b[0], b[1]])  # at t*
        W = np.vstack([fine_v(rng) for _ in range(4)])
        u, v, w = P[1] - P[0], P[2] - P[0], P[3] - P[0]
        # f'(t*) = u'.(v x w) + v'.(w x u) + w'.(u x v) = 0, solved for one z velocity whose
        # coefficient is a power of two (exact)
        crosses = [(1, np.cross(v, w)), (2, np.cross(w, u)), (3, np.cross(u, v))]
        pick = [(i, c) for i, c in crosses if is_pow2(c[2])]
        if not pick:
            continue
        i, c = pick[rng.integers(len(pick))]
        W[i][2] = 0.0
        du, dv, dw = W[1] - W[0], W[2] - W[0], W[3] - W[0]
        rest = du @ crosses[0][1] + dv @ crosses[1][1] + dw @ crosses[2][1]
        W[i][2] = -rest / c[2]  # it enters f'(t*) only as W[i]_z c_z
        s = P - ts * W
        e = s + W
        if double_root_at("ee", s, e, ts):
            return s, e


def vf_hard_one(rng, kind):
    if kind.startswith("tangent_"):
        return vf_tangent(rng, kind[len("tangent_"):])
    ts = hard_time(rng)
    if kind == "coplanar_tilted":  # all four points in one tilted plane moving in it
        o, e1, e2 = fine(rng), fine(rng), fine(rng)
        flat = lambda xy: o + xy[0] * e1 + xy[1] * e2  # noqa: E731
        tri = [rng.integers(-16, 17, size=2) / 16 for _ in range(3)]
        vel = [rng.integers(-8, 9, size=2) / 16 for _ in range(3)]
        at = [tri[j] + ts * vel[j] for j in range(3)]
        j = rng.integers(3)
        target = [at[j], 0.5 * (at[j] + at[(j + 1) % 3])][rng.integers(2)]
        pv = rng.integers(-8, 9, size=2) / 16
        p0 = target - ts * pv
        s = np.vstack([flat(p0)] + [flat(c) for c in tri])
        e = np.vstack([flat(p0 + pv)] + [flat(c + w) for c, w in zip(tri, vel)])
        return s, e
    # "land_edge" / "land_corner": the point reaches a point of an edge, or a corner, at t*
    T = np.vstack([fine(rng) for _ in range(3)])
    W = np.vstack([fine_v(rng) for _ in range(3)])
    j = rng.integers(3)
    u = rng.integers(1, 16) / 16 if kind == "land_edge" else 0.0
    X = T[j] + u * (T[(j + 1) % 3] - T[j])
    V = fine_v(rng)
    s = np.vstack([X - ts * V, T - ts * W])
    return s, s + np.vstack([V, W])


def ee_hard_one(rng, kind):
    if kind.startswith("tangent_"):
        return ee_tangent(rng, kind[len("tangent_"):])
    ts = hard_time(rng)
    if kind == "coplanar_tilted":  # both edges in one tilted plane moving in it, meeting at t*
        o, e1, e2 = fine(rng), fine(rng), fine(rng)
        flat = lambda xy: o + xy[0] * e1 + xy[1] * e2  # noqa: E731
        a = [rng.integers(-16, 17, size=2) / 16 for _ in range(2)]
        va = [rng.integers(-8, 9, size=2) / 16 for _ in range(2)]
        at = [a[j] + ts * va[j] for j in range(2)]
        x = at[0] + rng.integers(0, 5) / 4 * (at[1] - at[0])
        d = rng.integers(-8, 9, size=2) / 16
        sb = rng.integers(0, 3) / 2
        b = [x - sb * d, x - sb * d + d]
        vb = [rng.integers(-8, 9, size=2) / 16 for _ in range(2)]
        s = np.vstack([flat(a[0]), flat(a[1]), flat(b[0] - ts * vb[0]), flat(b[1] - ts * vb[1])])
        e = np.vstack([flat(a[0] + va[0]), flat(a[1] + va[1]), flat(b[0] + (1 - ts) * vb[0]),
                       flat(b[1] + (1 - ts) * vb[1])])
        return s, e
    if kind == "collinear_touch":  # all four ends on one line at t* (a double root of f)
        p, d = fine(rng), fine(rng) / 2
        k = rng.integers(1, 4)
        P = np.vstack([p, p + 2 * d, p + k * d, p + (k + rng.integers(1, 3)) * d])
        W = np.vstack([fine_v(rng) for _ in range(4)])
        s = P - ts * W
        return s, s + W
    # "cross_at": an interior point or an end of a meets one of b at t*, moving generically
    A = np.vstack([fine(rng), fine(rng)])
    X = A[0] + rng.integers(0, 5) / 4 * (A[1] - A[0])
    d = fine(rng)
    sb = rng.integers(0, 3) / 2
    P = np.vstack([A, X - sb * d, X - sb * d + d])
    W = np.vstack([fine_v(rng) for _ in range(4)])
    s = P - ts * W
    return s, s + W


def place(rng, s, e, scale):
    """The query at a scale: as built, times 2^-500 (about 3e-151), times 2^500 (about 3e150),
    times 2^-10 and moved to 1e6 (small motion far from the origin), or with one coordinate
    moved from 0 to ±2^-1000 (exponents spread over a thousand binades)."""
    if scale == "tiny":
        return s * 2.0 ** -500, e * 2.0 ** -500
    if scale == "huge":
        return s * 2.0 ** 500, e * 2.0 ** 500
    if scale == "far":
        return s * 2.0 ** -10 + 1e6, e * 2.0 ** -10 + 1e6
    if scale == "spread":
        i, k = rng.integers(4), rng.integers(3)
        c = s[i, k]
        s, e = s - np.eye(3)[k] * c, e - np.eye(3)[k] * c  # exact on the grid: s[i, k] is now 0
        s[i, k] = rng.choice([-1.0, 1.0]) * 2.0 ** -1000
        return s, e
    return s, e


VF_HARD = ["tangent_inside", "tangent_edge", "tangent_corner", "tangent_outside", "coplanar_tilted",
           "land_edge", "land_corner"]
EE_HARD = ["tangent_cross", "tangent_end_on", "tangent_end_end", "tangent_apart", "coplanar_tilted",
           "collinear_touch", "cross_at"]


def hard_set(rng, n, one, kinds):
    """Kinds in turn, each at the five scales in turn."""
    S, E = np.empty((n, 4, 3)), np.empty((n, 4, 3))
    for i in range(n):
        s, e = one(rng, kinds[i % len(kinds)])
        S[i], E[i] = place(rng, s, e, HARD_SCALES[(i // len(kinds)) % len(HARD_SCALES)])
    return S, E


# ---------------------------------------------------------------------------------------------
# 1. Primitive queries: the tools


def dvh_tools(kind):
    """[(name, prepare(S, E) -> per-query arguments, call(arguments) -> toi or None)] for dvh,
    run in this process."""
    dvh_fn = dvh.ccd_vertex_face if kind == "vf" else dvh.ccd_edge_edge
    raw_fn = lib.dvh_ccd_vertex_face if kind == "vf" else lib.dvh_ccd_edge_edge

    def dvh_args(S, E):
        return [(np.ascontiguousarray(S[i]), np.ascontiguousarray(E[i])) for i in range(len(S))]

    def exact(a):
        return dvh_fn(a[0], a[1], mode="exact")

    def cons(a):
        return dvh_fn(a[0], a[1], mode="conservative")

    opts = ffi.new("DvhCcdOptions *")
    opts[0] = lib.dvh_ccd_options_default()
    opts.mode = lib.DVH_CCD_MODE_EXACT
    hit_p, toi_p = ffi.new("bool *"), ffi.new("double *")
    keep = []

    def raw_args(S, E):
        out = []
        for i in range(len(S)):
            s, e = np.ascontiguousarray(S[i]), np.ascontiguousarray(E[i])
            keep.append((s, e))
            out.append((ffi.cast("const double *", s.ctypes.data), ffi.cast("const double *", e.ctypes.data)))
        return out

    def raw(a):
        raw_fn(a[0], a[1], opts, hit_p, toi_p)
        return toi_p[0] if hit_p[0] else None

    def empty_dvh(a):
        return _empty2(a[0], a[1], mode="exact")

    def empty_ti(a):
        return _empty_n(*a)

    tools = [("dvh exact", dvh_args, exact), ("dvh conservative", dvh_args, cons),
             ("dvh exact, raw cffi call", raw_args, raw)]
    empties = [("empty Python call, dvh's arguments", dvh_args, empty_dvh),
               ("empty Python call, ipctk's arguments", ti_args, empty_ti)]
    return tools, empties


def ti_args(S, E):
    """ipctk's arguments: eight 3-vectors (start then end), min_distance 0, tmax 1."""
    return [tuple(np.array(S[i, k]) for k in range(4)) + tuple(np.array(E[i, k]) for k in range(4))
            + (0.0, 1.0) for i in range(len(S))]


def _empty2(start, end, *, mode="exact"):
    return None


def _empty_n(*args):
    return None


def run_dvh_set(S, E, tools, rounds):
    """{tool: times_ns}, {tool: tois}: each query run by every tool in turn (the order rotated),
    each call timed alone; with rounds > 1 each call's fastest time is kept."""
    n = len(S)
    prepared = {name: prep(S, E) for name, prep, _ in tools}
    calls = {name: call for name, _, call in tools}
    names = list(calls)
    times = {k: np.full(n, np.iinfo(np.int64).max, dtype=np.int64) for k in names}
    tois = {k: [None] * n for k in names}
    for k in names:  # warm up
        for i in range(min(n, 50)):
            calls[k](prepared[k][i])
    gc.collect()
    gc.disable()
    try:
        for r in range(rounds):
            for i in range(n):
                j = (i + r) % len(names)
                for k in names[j:] + names[:j]:
                    f, a = calls[k], prepared[k][i]
                    t0 = ns()
                    out = f(a)
                    t1 = ns()
                    if t1 - t0 < times[k][i]:
                        times[k][i] = t1 - t0
                    tois[k][i] = out
    finally:
        gc.enable()
    return times, tois


KILLED = "killed"
FAILED = "failed"


def _ti_worker(kind, rescaling, args, first, rounds, conn):
    """In a forked child: Tight Inclusion on args[first:], one (index, ns, toi or None, error)
    message per query. Memory is capped so that a runaway search fails instead of swapping."""
    try:
        import resource

        cap = 4 << 30
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    except (ImportError, ValueError, OSError):
        pass
    ccd = ipctk.TightInclusionCCD(tolerance=1e-6, max_iterations=10_000_000, conservative_rescaling=rescaling)
    fn = ccd.point_triangle_ccd if kind == "vf" else ccd.edge_edge_ccd
    gc.disable()
    if first == 0:  # warm up on a plain miss: a point far above a still triangle
        tri = [np.array(c, dtype=np.float64) for c in ((0, 0, 0), (1, 0, 0), (0, 1, 0))]
        p = np.array([0.2, 0.2, 1.0])
        q = p + [0.0, 0.0, -0.5]
        warm = ((p, *tri, q, *tri, 0.0, 1.0) if kind == "vf"
                else (p, p + 0.1, tri[0], tri[1], q, q + 0.1, tri[0], tri[1], 0.0, 1.0))
        for _ in range(20):
            fn(*warm)
    conn.send(("ready",))
    for i in range(first, len(args)):
        a = args[i]
        best, toi, err = None, None, None
        for _ in range(rounds):
            try:
                t0 = ns()
                hit, t = fn(*a)
                t1 = ns()
            except Exception as e:  # std::bad_alloc comes back as MemoryError
                err = f"{type(e).__name__}: {e}"
                break
            best = t1 - t0 if best is None else min(best, t1 - t0)
            toi = float(t) if hit else None
        conn.send((i, best, toi, err))
    conn.close()


def run_ti_set(kind, rescaling, args, rounds, timeout):
    """Tight Inclusion on every query, each call timed alone in a child process; a call that has
    not returned after `timeout` seconds is killed (the child restarted at the next query) and
    recorded as KILLED, one that raised (out of memory) as FAILED. Returns (times_ns with -1 for
    those, tois with KILLED/FAILED markers)."""
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    n = len(args)
    times = np.full(n, -1, dtype=np.int64)
    tois: list = [None] * n
    i = 0
    while i < n:
        recv, send = ctx.Pipe(duplex=False)
        p = ctx.Process(target=_ti_worker, args=(kind, rescaling, args, i, rounds, send), daemon=True)
        p.start()
        send.close()
        if not recv.poll(60):
            raise RuntimeError("the Tight Inclusion worker did not start")
        recv.recv()
        while i < n:
            if not recv.poll(timeout * rounds):
                p.kill()
                tois[i] = KILLED
                i += 1
                break
            try:
                j, t, toi, err = recv.recv()
            except EOFError:  # the child died (abort in the C++ code)
                tois[i] = FAILED
                i += 1
                break
            if err is not None:
                tois[j] = FAILED
            else:
                times[j], tois[j] = t, toi
            i = j + 1
        p.join()
        recv.close()
    return times, tois


def accuracy(exact, tool):
    """hits, false positives, false negatives, max(exact - tool) over both-hit, count tool later,
    max(tool - exact), unfinished; unfinished queries count as none of the others."""
    hits = fp = fn = later = unfinished = 0
    early = 0.0
    late = 0.0
    for x, y in zip(exact, tool):
        if y is KILLED or y is FAILED:
            unfinished += 1
        elif y is not None:
            hits += 1
            if x is None:
                fp += 1
            else:
                early = max(early, x - y)
                if y > x:
                    later += 1
                    late = max(late, y - x)
        elif x is not None:
            fn += 1
    return hits, fp, fn, early, later, late, unfinished


TI_TOOLS = [("TI, ipctk defaults (tol 1e-6, rescaling 0.8)", 0.8), ("TI, tol 1e-6, rescaling 1.0", 1.0)]


def pct(t, timeout):
    """Median, 99th, 99.9th percentile and max of per-call times (ns), killed calls (-1) counted
    as slower than every finished one: a percentile that falls on them prints as "> timeout"."""
    x = np.where(t < 0, np.inf, t.astype(np.float64))
    out = []
    for v in list(np.percentile(x, [50, 99, 99.9], method="higher")) + [x.max()]:
        out.append(f"> {timeout * 1e6:.0f}" if v == np.inf else us(v))
    return out


def describe(kind, s, e):
    """A query as text: start and end rows."""
    f = lambda a: "[" + ", ".join("(" + ", ".join(f"{c:.17g}" for c in r) + ")" for r in a) + "]"  # noqa: E731
    return f"start {f(s)}, end {f(e)}"


def query_kind(label, kind, q):
    """The kind of query q of a constructed set ("" for the random ones); the hard sets' with
    its scale."""
    if "degenerate" in label:
        kinds = VF_KINDS if kind == "vf" else EE_KINDS
        return kinds[q % len(kinds)]
    if "hard" in label:
        kinds = VF_HARD if kind == "vf" else EE_HARD
        return f"{kinds[q % len(kinds)]}, {HARD_SCALES[(q // len(kinds)) % len(HARD_SCALES)]}"
    return ""


def bench_primitives(n, rounds, seed, timeout, hard_n):
    sets = {
        "vf": [("(a) random", lambda r: random_set(r, n)), ("(b) certain hits", lambda r: vf_hits(r, n)),
               ("(c) degenerate", lambda r: degenerate_set(r, n, vf_degenerate_one, VF_KINDS)),
               ("(d) near misses", lambda r: vf_near(r, n)),
               (f"(e) hard ({hard_n})", lambda r: hard_set(r, hard_n, vf_hard_one, VF_HARD))],
        "ee": [("(a) random", lambda r: random_set(r, n)), ("(b) certain hits", lambda r: ee_hits(r, n)),
               ("(c) degenerate", lambda r: degenerate_set(r, n, ee_degenerate_one, EE_KINDS)),
               ("(d) near misses", lambda r: ee_near(r, n)),
               (f"(e) hard ({hard_n})", lambda r: hard_set(r, hard_n, ee_hard_one, EE_HARD))],
    }
    out_md = []
    slow = []
    by_kind = []
    examples = []
    slow_exact = []
    for kind, title in (("vf", "vertex-face"), ("ee", "edge-edge")):
        tools, empties = dvh_tools(kind)
        if ipctk is None:
            empties = empties[:1]
        rows = []
        for si, (label, make) in enumerate(sets[kind]):
            progress(f"primitives: {title} {label}")
            rng = np.random.default_rng(seed + 100 * si + (0 if kind == "vf" else 1000))
            S, E = make(rng)
            t0 = perf()
            times, tois = run_dvh_set(S, E, tools + empties, rounds)
            progress(f"  dvh and the empty calls: {perf() - t0:.1f} s")
            exact = tois["dvh exact"]
            assert exact == tois["dvh exact, raw cffi call"]
            names = [t[0] for t in tools]
            if ipctk is not None:
                targs = ti_args(S, E)
                for name, resc in TI_TOOLS:
                    t0 = perf()
                    times[name], tois[name] = run_ti_set(kind, resc, targs, rounds, timeout)
                    progress(f"  {name}: {perf() - t0:.1f} s")
                    names.append(name)
            for name in names + [t[0] for t in empties]:
                t = times[name]
                p50, p99, p999, mx = pct(t, timeout)
                if name.startswith("empty"):
                    rows.append([label, f"*{name}*", p50, p99, p999, mx, "", "", "", "", "", ""])
                    continue
                hits, fp, fn, early, later, late, unf = accuracy(exact, tois[name])
                ref = name.startswith("dvh exact")
                rows.append([label, name, p50, p99, p999, mx, hits,
                             "—" if ref else fp, "—" if ref else fn,
                             "—" if ref else sci(early),
                             "—" if ref else (f"{later} (max {late:.2e})" if later else "0"),
                             unf])
                k = int(np.argmax(t))
                slow.append((float(t[k]), title, label, name, k, exact[k], tois[name][k]))
                if name == "dvh exact":
                    kk = query_kind(label, kind, k)
                    slow_exact.append(f"{title} {label} #{k}{f' ({kk})' if kk else ''}: {us(t[k])} µs, "
                                      f"exact {exact[k]!r}; {describe(kind, S[k], E[k])}")
                tag = lambda q: f"{title} {label} #{q}" + (f" ({query_kind(label, kind, q)})"  # noqa: E731
                                                            if query_kind(label, kind, q) else "")
                for what, pick in (("false positive", lambda x, y: y not in (None, KILLED, FAILED) and x is None),
                                   ("false negative", lambda x, y: y is None and x is not None),
                                   ("later toi", lambda x, y: x is not None and isinstance(y, float) and y > x),
                                   ("toi 0 where exact > 0.01",
                                    lambda x, y: x is not None and x > 0.01 and isinstance(y, float) and y == 0)):
                    hit = [q for q in range(len(S)) if pick(exact[q], tois[name][q])]
                    if hit and not ref:
                        q = hit[0]
                        examples.append(f"{name}, {what} ({len(hit)}), first: {tag(q)}: exact {exact[q]!r}, "
                                        f"tool {tois[name][q]!r}; {describe(kind, S[q], E[q])}")
                if not name.endswith("raw cffi call"):
                    slow_kinds = {}
                    for q, y in enumerate(tois[name]):
                        if y is KILLED or y is FAILED or t[q] > 1e6:
                            key = query_kind(label, kind, q).split(",")[0] or "all"
                            slow_kinds[key] = slow_kinds.get(key, 0) + 1
                    if slow_kinds:
                        by_kind.append(f"{title} {label}, {name}: {sum(slow_kinds.values())} calls over 1 ms "
                                       "or killed" + ("" if list(slow_kinds) == ["all"] else ": " + ", ".join(
                                           f"{k} {v}" for k, v in sorted(slow_kinds.items()))))
        hdr = ["set", "tool", "median µs", "p99 µs", "p99.9 µs", "max µs", "hits",
               "false pos.", "false neg.", "max (exact − tool) toi", "tool toi later than exact",
               "killed"]
        out_md.append(f"#### {title} ({n} queries per set, {hard_n} in the hard set)\n\n" + table(hdr, rows))
    slow.sort(key=lambda r: -r[0])
    return out_md, slow, by_kind, examples, slow_exact


# ---------------------------------------------------------------------------------------------
# 2./3. Meshes


def sheet(n, size=2.0):
    """An n x n grid of quads (2 n^2 triangles) over [-size/2, size/2]^2 at z = 0."""
    xs = np.linspace(-size / 2, size / 2, n + 1)
    X, Y = np.meshgrid(xs, xs)
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    v = (j * (n + 1) + i).ravel()
    F = np.vstack([np.column_stack([v, v + 1, v + n + 2]), np.column_stack([v, v + n + 2, v + n + 1])])
    return V, F.astype(np.int64)


def icosphere(level, radius=1.0):
    """A subdivided icosahedron: 20 * 4^level triangles on a sphere."""
    t = (1 + 5 ** 0.5) / 2
    V = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t],
         [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    F = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
         [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(level):
        mid = {}

        def m(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                V.append(unit(V[a] + V[b]))
                mid[key] = len(V) - 1
            return mid[key]

        nf = []
        for a, b, c in F:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        F = nf
    return np.array(V) * radius, np.array(F, dtype=np.int64)


def fold(V):
    """The sheet's right half folded over its left in one step: x > 0 goes to
    (-x + 0.02 y, y, 0.03 - 0.04 x); the left half stays."""
    W = V.copy()
    r = V[:, 0] > 0
    x, y = V[r, 0], V[r, 1]
    W[r, 0] = -x + 0.02 * y
    W[r, 2] = 0.03 - 0.04 * x
    return W


def drape(V, seed):
    """The sheet falling and rippling, gathered towards its middle, with per-vertex jitter of
    about one edge length in every coordinate, so that it passes through itself."""
    rng = np.random.default_rng(seed)
    x, y = V[:, 0], V[:, 1]
    edge = 2.0 / (np.sqrt(len(V)) - 1)
    W = np.column_stack([0.8 * x, 0.85 * y, -0.5 + 0.12 * np.sin(3 * np.pi * x) * np.cos(2 * np.pi * y)])
    return W + rng.normal(scale=1.0 * edge, size=V.shape)


def blob(V, seed, amp=0.45, modes=6):
    """A smooth random displacement field (a sum of `modes` plane waves of wavenumber 3..5 and
    amplitude `amp`) applied to the sphere's vertices: bulges and dents that pass through
    other parts of the surface."""
    rng = np.random.default_rng(seed)
    D = np.zeros_like(V)
    for _ in range(modes):
        k = unit(rng.normal(size=3)) * rng.uniform(3, 5)
        a = unit(rng.normal(size=3)) * amp
        D += np.sin(V @ k + rng.uniform(0, 2 * np.pi))[:, None] * a
    return V + D


def fortran(a):
    return np.asfortranarray(np.asarray(a, dtype=np.float64))


class Runner:
    """Methods timed round-robin (the order rotated each round), each returning
    (result, {part: seconds}) or a result.

    Every method runs once first; that run is a warm-up, dropped, when it took under 0.5 s, and
    the first sample otherwise. A method then runs until it has `reps` samples or its share of
    `budget` seconds (budget / methods) is spent, with at least one sample: a slow method is
    timed fewer times than a fast one."""

    def __init__(self):
        self.fns = {}

    def add(self, name, fn):
        self.fns[name] = fn

    @staticmethod
    def _split(out):
        if isinstance(out, tuple) and len(out) == 2 and isinstance(out[1], dict):
            return out
        return out, {}

    def run(self, reps, budget):
        names = list(self.fns)
        results = {}
        times = {n: [] for n in names}
        parts = {n: {} for n in names}
        spent = {n: 0.0 for n in names}

        def once(n, keep):
            t0 = perf()
            out, pt = self._split(self.fns[n]())
            dt = perf() - t0
            spent[n] += dt
            results[n] = out
            if keep:
                times[n].append(dt)
                for p, v in pt.items():
                    parts[n].setdefault(p, []).append(v)
            return dt

        for n in names:
            t0 = perf()
            out, pt = self._split(self.fns[n]())
            dt = perf() - t0
            spent[n] += dt
            results[n] = out
            if dt >= 0.5:
                times[n].append(dt)
                for p, v in pt.items():
                    parts[n].setdefault(p, []).append(v)
        share = budget / len(names)
        r = 0
        while True:
            todo = [n for n in names
                    if len(times[n]) < reps and (not times[n] or spent[n] + float(np.median(times[n])) <= share)]
            if not todo:
                break
            k = r % len(todo)
            for n in todo[k:] + todo[:k]:
                once(n, True)
            r += 1
        med = {n: float(np.median(times[n])) for n in names}
        pmed = {n: {p: float(np.median(v)) for p, v in parts[n].items()} for n in names}
        runs = {n: len(times[n]) for n in names}
        return med, pmed, results, runs


def dvh_self_step(mesh, S, E, **kw):
    def step():
        t0 = perf()
        mesh.refit_motion(S, E)
        t1 = perf()
        imp, st = dvh.self_continuous_collide(mesh, stats=True, **kw)
        t2 = perf()
        return (len(imp), st), {"refit": t1 - t0, "query": t2 - t1}

    return step


def toi_str(x):
    return "none (1)" if x == float("inf") else f"{x:.6g}"


def bench_self(cases, reps, budget):
    rows = []
    checks = []
    for label, V0, V1, F in cases:
        progress(f"self CCD: {label}")
        S, E = np.ascontiguousarray(V0), np.ascontiguousarray(V1)
        mesh = dvh.Mesh(S, F.astype(np.uint32))
        r = Runner()
        r.add("dvh exact, earliest_only (the stepsize)", dvh_self_step(mesh, S, E, earliest_only=True))
        r.add("dvh exact, every impact", dvh_self_step(mesh, S, E))
        r.add("dvh conservative, earliest_only", dvh_self_step(mesh, S, E, mode="conservative", earliest_only=True))
        if ipctk is not None:
            Fi = np.asfortranarray(F.astype(np.int32))
            Ei = np.asfortranarray(ipctk.edges(Fi))
            cm = ipctk.CollisionMesh(fortran(V0), Ei, Fi)
            A, B = fortran(V0), fortran(V1)
            ti = ipctk.TightInclusionCCD()
            r.add("ipctk compute_collision_free_stepsize (TI)",
                  lambda cm=cm, A=A, B=B, ti=ti: ipctk.compute_collision_free_stepsize(cm, A, B, 0.0, None, ti))
            cands = ipctk.Candidates()

            def ipc_split(cm=cm, A=A, B=B, ti=ti, cands=cands):
                t0 = perf()
                cands.build(cm, A, B, 0.0, None)
                t1 = perf()
                s = cands.compute_collision_free_stepsize(cm, A, B, 0.0, ti)
                t2 = perf()
                return (s, len(cands)), {"broad": t1 - t0, "narrow": t2 - t1}

            r.add("ipctk Candidates.build + .compute_collision_free_stepsize", ipc_split)
        med, parts, res, runs = r.run(reps, budget)
        ref = med["dvh exact, earliest_only (the stepsize)"]
        exact_toi = res["dvh exact, earliest_only (the stepsize)"][1].earliest_toi
        full_n, full_st = res["dvh exact, every impact"]
        for name in med:
            p = parts[name]
            out = res[name]
            if name.startswith("dvh"):
                n_imp, st = out
                split = f"refit {ms(p['refit'])} + query {ms(p['query'])}"
                step = toi_str(st.earliest_toi)
                info = f"{st.primitive_tests} primitive tests, {st.impacts} impacts"
            elif name.startswith("ipctk Candidates"):
                s, nc = out
                split = f"broad {ms(p['broad'])} + narrow {ms(p['narrow'])}"
                step = f"{s:.6g}"
                info = f"{nc} candidates"
            else:
                s = out
                split = ""
                step = f"{s:.6g}"
                info = ""
            if name.startswith("ipctk"):
                ss = out if isinstance(out, float) else out[0]
                if exact_toi != float("inf") and ss > exact_toi:
                    checks.append(f"{label}: ipctk's step {ss:.9g} is later than dvh's exact earliest toi {exact_toi:.9g}")
                if exact_toi == float("inf") and ss < 1:
                    checks.append(f"{label}: ipctk's step {ss:.9g} < 1 though dvh finds no impact")
                step += f" ({ss / exact_toi:.3f} of dvh's)" if exact_toi not in (0.0, float("inf")) else ""
            rows.append([label, name, ms(med[name]), runs[name], ratio(med[name], ref), split, step, info])
    hdr = ["scene", "method", "median ms", "runs", "÷ dvh stepsize", "parts (medians, ms)",
           "step / earliest toi", "work"]
    return table(hdr, rows), checks


def bench_pair(V0a, V1a, Fa, V0b, V1b, Fb, reps, budget, label):
    progress(f"two meshes: {label}")
    Sa, Ea, Sb, Eb = map(np.ascontiguousarray, (V0a, V1a, V0b, V1b))
    a = dvh.Mesh(Sa, Fa.astype(np.uint32))
    b = dvh.Mesh(Sb, Fb.astype(np.uint32))

    def refit():
        a.refit_motion(Sa, Ea)
        b.refit_motion(Sb, Eb)

    def pair(**kw):
        def step():
            t0 = perf()
            refit()
            t1 = perf()
            imp, st = dvh.continuous_collide(a, b, stats=True, **kw)
            t2 = perf()
            return (st.earliest_toi, st.impacts), {"refit": t1 - t0, "query": t2 - t1}

        return step

    def all3():
        t0 = perf()
        refit()
        t1 = perf()
        tois = []
        for q in (lambda: dvh.self_continuous_collide(a, earliest_only=True, stats=True),
                  lambda: dvh.self_continuous_collide(b, earliest_only=True, stats=True),
                  lambda: dvh.continuous_collide(a, b, earliest_only=True, stats=True)):
            tois.append(q()[1].earliest_toi)
        t2 = perf()
        return (min(tois), tois), {"refit": t1 - t0, "query": t2 - t1}

    r = Runner()
    r.add("dvh continuous_collide(a, b), earliest_only", pair(earliest_only=True))
    r.add("dvh continuous_collide(a, b), every impact", pair())
    r.add("dvh self(a) + self(b) + pair, earliest_only", all3)
    if ipctk is not None:
        V0 = fortran(np.vstack([V0a, V0b]))
        V1 = fortran(np.vstack([V1a, V1b]))
        F = np.asfortranarray(np.vstack([Fa, Fb + len(V0a)]).astype(np.int32))
        E = np.asfortranarray(ipctk.edges(F))
        cm = ipctk.CollisionMesh(V0, E, F)
        cm_cross = ipctk.CollisionMesh(V0, E, F)
        cm_cross.can_collide = ipctk.make_connected_components_filter(F)
        ti = ipctk.TightInclusionCCD()
        r.add("ipctk, one CollisionMesh (self + pair)",
              lambda: ipctk.compute_collision_free_stepsize(cm, V0, V1, 0.0, None, ti))
        r.add("ipctk, components filter (pair only)",
              lambda: ipctk.compute_collision_free_stepsize(cm_cross, V0, V1, 0.0, None, ti))
    med, parts, res, runs = r.run(reps, budget)
    ref = med["dvh continuous_collide(a, b), earliest_only"]
    ref_all = med["dvh self(a) + self(b) + pair, earliest_only"]
    pair_toi = res["dvh continuous_collide(a, b), earliest_only"][0]
    all_toi = res["dvh self(a) + self(b) + pair, earliest_only"][0]
    rows = []
    checks = []
    for name in med:
        p = parts[name]
        out = res[name]
        if name.startswith("dvh"):
            split = f"refit {ms(p['refit'])} + query {ms(p['query'])}"
            if name.startswith("dvh self"):
                step = f"{toi_str(out[0])} (self a {toi_str(out[1][0])}, self b {toi_str(out[1][1])}, pair {toi_str(out[1][2])})"
            else:
                step = toi_str(out[0]) + ("" if "earliest" in name else f", {out[1]} impacts")
        else:
            split = ""
            truth = pair_toi if "pair only" in name else all_toi
            step = f"{out:.6g}" + (f" ({out / truth:.3f} of dvh's)" if truth not in (0.0, float("inf")) else "")
            if truth != float("inf") and out > truth:
                checks.append(f"{label}: {name} step {out:.9g} later than dvh's exact {truth:.9g}")
        rows.append([name, ms(med[name]), runs[name], ratio(med[name], ref), ratio(med[name], ref_all), split, step])
    hdr = ["method", "median ms", "runs", "÷ dvh pair", "÷ dvh self+self+pair", "parts (medians, ms)",
           "step / earliest toi"]
    return table(hdr, rows), checks


class quiet_stderr:
    """Sends file descriptor 2 to /dev/null for the duration (fcl's C++ warnings)."""

    def __enter__(self):
        sys.stderr.flush()
        self.saved = os.dup(2)
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 2)
        os.close(null)

    def __exit__(self, *exc):
        os.dup2(self.saved, 2)
        os.close(self.saved)


def bench_fcl(reps, budget):
    """A sphere translating rigidly past (and into) another: dvh's exact toi against python-fcl's
    continuousCollide with translational motion and each solver."""
    V, F = icosphere(3)
    t_start, t_end = np.array([-2.6, 0.35, 0.1]), np.array([0.4, 0.35, 0.1])
    start, end = V + t_start, V + t_end
    a = dvh.Mesh(np.ascontiguousarray(start), F.astype(np.uint32))
    b = dvh.Mesh(np.ascontiguousarray(V), F.astype(np.uint32))

    def dvh_step():
        a.refit_motion(start, end)
        return dvh.continuous_collide(a, b, earliest_only=True, stats=True)[1].earliest_toi

    r = Runner()
    r.add("dvh refit_motion + continuous_collide, earliest_only", dvh_step)
    seen = {}
    extra = ""
    if fcl is not None:
        F32 = F.astype(np.int32)

        def model():
            m = fcl.BVHModel()
            m.beginModel(len(V), len(F))
            m.addSubModel(V, F32)
            m.endModel()
            return m

        with quiet_stderr():  # sanity: the end poses overlap, the start poses do not
            end_hit = fcl.collide(fcl.CollisionObject(model(), fcl.Transform(t_end)),
                                  fcl.CollisionObject(model(), fcl.Transform()), fcl.CollisionRequest(),
                                  fcl.CollisionResult())
            start_hit = fcl.collide(fcl.CollisionObject(model(), fcl.Transform(t_start)),
                                    fcl.CollisionObject(model(), fcl.Transform()), fcl.CollisionRequest(),
                                    fcl.CollisionResult())
        extra = (f" Discrete `fcl.collide` on the same models: {start_hit} contacts at the start "
                 f"poses, {end_hit} at the end poses.")
        solvers = [("naive (sampling), 10 samples", fcl.CCDSolverType.CCDC_NAIVE, 10),
                   ("naive (sampling), 1000 samples", fcl.CCDSolverType.CCDC_NAIVE, 1000),
                   ("conservative advancement", fcl.CCDSolverType.CCDC_CONSERVATIVE_ADVANCEMENT, 10),
                   ("polynomial solver", fcl.CCDSolverType.CCDC_POLYNOMIAL_SOLVER, 10)]
        for label, solver, iters in solvers:
            name = f"python-fcl continuousCollide, {label}"

            def run(solver=solver, iters=iters, name=name):
                with quiet_stderr():
                    t0 = perf()
                    # new models for every call: continuousCollide changes a BVHModel it is given
                    oa = fcl.CollisionObject(model(), fcl.Transform(t_start))
                    ob = fcl.CollisionObject(model(), fcl.Transform())
                    t1 = perf()
                    req = fcl.ContinuousCollisionRequest(num_max_iterations=iters,
                                                         ccd_motion_type=fcl.CCDMotionType.CCDM_TRANS,
                                                         ccd_solver_type=solver)
                    res = fcl.ContinuousCollisionResult()
                    fcl.continuousCollide(oa, fcl.Transform(t_end), ob, fcl.Transform(), req, res)
                    t2 = perf()
                out = (bool(res.is_collide), float(res.time_of_contact))
                seen.setdefault(name, set()).add(out)
                return out, {"build": t1 - t0, "ccd": t2 - t1}

            r.add(name, run)
    med, parts, res, runs = r.run(reps, budget)
    truth = res["dvh refit_motion + continuous_collide, earliest_only"]
    ref = med["dvh refit_motion + continuous_collide, earliest_only"]
    rows = []
    for name in med:
        out = res[name]
        if isinstance(out, tuple):
            hit, toc = out
            verdict = ("misses the contact" if not hit else
                       "later than the exact toi (unsafe as a step)" if toc > truth else
                       "contact at t = 0 while apart" if toc == 0 and truth > 0 else "not later than exact")
            val = f"{'hit' if hit else 'no hit'}, toc {toc:.6g}: {verdict}"
            if len(seen.get(name, ())) > 1:
                val += f" (differs between runs: {sorted(seen[name])})"
            split = f"models {ms(parts[name]['build'])} + ccd {ms(parts[name]['ccd'])}" if parts[name] else ""
        else:
            val = f"toi {out:.9g}"
            split = ""
        rows.append([name, ms(med[name]), runs[name], ratio(med[name], ref), split, val])
    if fcl is None:
        note("python-fcl is not installed: its mesh continuousCollide check is skipped")
    hdr = ["method", "median ms", "runs", "÷ dvh", "parts (medians, ms)", "result"]
    return (f"{len(F)} triangles each; sphere a translates from x = -2.6 to x = 0.4 through b at the "
            "origin (offset 0.35, 0.1 in y, z), ending deep inside it; fcl motion type CCDM_TRANS, "
            "two new `BVHModel`s (OBBRSS) per call." + extra + "\n\n" + table(hdr, rows))


# ---------------------------------------------------------------------------------------------


def versions() -> dict:
    with open(os.path.join(os.path.dirname(dvh.__file__), "_api.py"), "rb") as f:
        api = hashlib.sha256(f.read()).hexdigest()[:12]
    out = {"Python": platform.python_version(), "dvh": f"{dvh.version()} (_api.py {api})"}
    for dist in ("numpy", "cffi", "ipctk", "python-fcl"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer queries and repeats, shorter time limit (about 2 minutes)")
    ap.add_argument("--queries", type=int, default=None,
                    help="queries per primitive set (default 2000; 500 with --quick)")
    ap.add_argument("--hard-queries", type=int, default=2000,
                    help="queries in each hard primitive set (default 2000, with --quick too)")
    ap.add_argument("--timeout", type=float, default=None,
                    help="seconds before a Tight Inclusion call is killed (default 0.1; 0.05 with --quick)")
    ap.add_argument("--seed", type=int, default=20240601)
    ap.add_argument("--skip", default="", help="comma-separated parts to skip: prim,self,cloth,pair,fcl")
    args = ap.parse_args()
    q = args.quick
    skip = set(filter(None, args.skip.split(",")))
    started = perf()
    date = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    if ipctk is None:
        note("ipctk is not installed: only dvh is measured")
    else:
        ipctk.set_logger_level(ipctk.LoggerLevel.off)  # its per-query warnings would be timed

    ver = versions()
    threads = f"ipctk TBB threads {ipctk.get_num_threads()}" if ipctk is not None else ""
    head = (f"## dvh CCD against IPC Toolkit's Tight Inclusion ({'quick' if q else 'full'} run)\n\n"
            f"{date}; {os.cpu_count()} cores; {platform.machine()} {platform.system()}; "
            + ", ".join(f"{k} {v}" for k, v in ver.items())
            + f".\n\nThreads: dvh `threads=0` (every core); ipctk's TBB default (every core; {threads}). "
            "ipctk's default broad phase (`broad_phase=None`) is its LBVH (`make_default_broad_phase()` "
            "since v1.5).")
    print(head, flush=True)

    checks = []
    if "prim" not in skip:
        rounds = 1
        timeout = args.timeout if args.timeout is not None else (0.05 if q else 0.1)
        queries = args.queries if args.queries is not None else (500 if q else 2000)
        md, slow, by_kind, examples, slow_exact = bench_primitives(queries, rounds, args.seed, timeout,
                                                                   args.hard_queries)
        print(f"\n### 1. Primitive queries\n\nEach call timed alone with `time.perf_counter_ns`, "
              "garbage collection off. dvh's calls run in this process, the tools taking turns query "
              "by query; Tight Inclusion's run in a forked child process, so that a call still "
              f"running after {timeout:g} s can be killed (and counted in *killed*; the child then "
              "resumes at the next query). Times include each binding's argument conversion: the "
              "*empty Python call* rows are a trivial Python function called with the same "
              "arguments, and *raw cffi call* is dvh's C function called through cffi with prepared "
              "pointers. Hits, false positives and negatives and toi differences are against dvh "
              "exact. TI rows: `ipctk.TightInclusionCCD(...).point_triangle_ccd` / `.edge_edge_ccd` "
              "with `min_distance=0, tmax=1`; with ipctk's default `conservative_rescaling=0.8` it "
              "asks Tight Inclusion for a separation of min(0.2 × initial distance, 1e-4), so it "
              "reports near misses as hits and earlier tois by design; rescaling 1.0 asks for no "
              "separation (Tight Inclusion alone, tolerance 1e-6).\n", flush=True)
        for m in md:
            print(m + "\n", flush=True)
        print("Slowest finished calls: " + "; ".join(
            f"{us(t)} µs, {name}, {title} {label} #{k} (exact {x!r}, tool {y!r})"
            for t, title, label, name, k, x, y in slow[:6]) + "\n", flush=True)
        print("Calls over 1 ms (or killed), by tool and set (degenerate and hard sets by kind of query):\n")
        for line in by_kind:
            print(f"- {line}", flush=True)
        print("\nThe slowest dvh exact call of each set:\n")
        for line in slow_exact:
            print(f"- {line}", flush=True)
        print("\nDisagreements with dvh exact (count, then the first query):\n")
        for line in examples:
            print(f"- {line}", flush=True)
        print()

    reps = 3 if q else 10
    budget = 15.0 if q else 60.0
    grid_n, ico = (32, 3) if q else (64, 4)
    timing = (f"medians of up to {reps} runs each (a method slower than its share of a {budget:g} s "
              "budget per scene runs fewer times, at least once; *runs* says how many)")
    if "self" not in skip:
        Vs, Fs = sheet(grid_n)
        Vi, Fi = icosphere(ico)
        cases = [(f"cloth fold, {len(Fs)} tris", Vs, fold(Vs), Fs),
                 (f"cloth drape + jitter, {len(Fs)} tris", Vs, drape(Vs, args.seed), Fs),
                 (f"icosphere + smooth field, {len(Fi)} tris", Vi, blob(Vi, args.seed), Fi)]
        if "cloth" not in skip:
            progress("simulating the cloth")
            Fc, motions, _, _ = cloth_steps.simulate(grid_n, CLOTH_STEPS)
            for k in CLOTH_BENCH_STEPS:
                S, E = motions[k]
                cases.append((f"cloth simulation, step {k}, {len(Fc)} tris", S, E, Fc.astype(np.int64)))
        md, c = bench_self(cases, reps, budget)
        checks += c
        print(f"\n### 2. Self CCD per step (one mesh), {timing}\n\n"
              f"Cloth: a {grid_n}×{grid_n}-quad sheet over [-1, 1]², flat at z = 0 at the start; "
              "*fold* maps x > 0 to (-x + 0.02 y, y, 0.03 - 0.04 x) in one step; *drape* drops it "
              "to z ≈ -0.5 with a ripple, gathered to 0.8 × 0.85 of its size, plus Gaussian jitter "
              "of one edge length per vertex and axis. Icosphere: radius 1, displaced by six random "
              "plane waves (wavenumber 3–5, amplitude 0.45). *Cloth simulation*: the motion a "
              f"simulator asks about at steps {', '.join(map(str, CLOTH_BENCH_STEPS))} of "
              f"`cloth_steps.py`'s {CLOTH_STEPS} (a {grid_n}×{grid_n}-quad sheet fallen onto a ball "
              "and the floor, folded onto itself, its self-contact kept by dvh's stencils and "
              "CCD): from the last positions to the predicted ones. "
              "dvh times include `refit_motion(start, end)` (a simulator calls it every step); the "
              "parts column splits it. ipctk: `compute_collision_free_stepsize(mesh, V0, V1, "
              "min_distance=0, broad_phase=None, TightInclusionCCD())` on a `CollisionMesh` built "
              "once (not timed); the *Candidates* row runs its two stages separately (LBVH broad "
              "phase, then Tight Inclusion on each candidate with tmax the earliest toi so far). "
              "ipctk's step is the time its narrow phase reaches a separation of min(0.2 × initial "
              "distance, 1e-4) (× 0.8 only when that time is under 1e-6), so it is a little below "
              "the exact earliest toi, not 0.8 of it.\n\n" + md + "\n", flush=True)

    if "pair" not in skip:
        Va, Fa = sheet(grid_n, size=2.4)
        Va = Va + [0.05, -0.03, 1.1]
        Wa = Va.copy()
        Wa[:, 2] = 0.55 + 0.06 * np.sin(4 * Va[:, 0]) * np.cos(3 * Va[:, 1])
        Vb, Fb = icosphere(ico)
        Wb = Vb * 1.02 + [0.0, 0.0, 0.02]
        md, c = bench_pair(Va, Wa, Fa, Vb, Wb, Fb, reps, budget, "sheet onto sphere")
        checks += c
        print(f"\n### 3. Two meshes: a {len(Fa)}-triangle sheet falling from z = 1.1 to a rippled "
              f"z ≈ 0.55 onto a {len(Fb)}-triangle sphere of radius 1 (growing 2 %, rising 0.02); "
              f"{timing}\n\n"
              "dvh `continuous_collide(a, b)` tests only the pairs between the meshes; ipctk on one "
              "`CollisionMesh` holding both also tests each mesh against itself, so the equal-work "
              "dvh row is self(a) + self(b) + pair, and the ipctk *components filter* row "
              "(`make_connected_components_filter`) tests only the pairs between them. dvh rows "
              "include refitting both meshes.\n\n" + md + "\n", flush=True)

    if "fcl" not in skip:
        md = bench_fcl(reps, budget)
        print(f"\n### 4. python-fcl mesh-mesh continuousCollide (rigid motion), {timing}\n\n"
              + md + "\n", flush=True)

    elapsed = perf() - started
    tail = f"Run time {elapsed:.0f} s."
    if checks:
        tail += "".join(f"\n- check: {c}" for c in checks)
    else:
        tail += " Every ipctk step was at or before dvh's exact earliest toi."
    tail += "".join(f"\n- note: {n}" for n in notes)
    print("\n" + tail)


if __name__ == "__main__":
    main()
