"""Small meshes and brute-force oracles for the tests."""

import itertools
import os
import time

import numpy as np
import pytest

# The library's cut-offs below which work stays on the calling thread
# (src/query/engine/dispatch.rs, src/query/primitives/leaf_pairs.rs, src/query/nearest/entry.rs,
# src/query/engine/sort.rs, src/volume/fit.rs): a comparison of thread counts tests threads only
# above them.
PARALLEL_MIN_TRIANGLES = 4096  # both meshes together
PARALLEL_MIN_NODE_PAIRS = 256  # leaf pairs handed to the primitive tests
PARALLEL_MIN_STENCIL_VALUES = 4096
PARALLEL_SORT_MIN_PAIRS = 2 * 65536  # a share of 65,536 pairs per sorting thread
REFIT_PARALLEL_MIN_RINGS = 8192


def uv_sphere(n: int, radius: float = 1.0, centre=(0.0, 0.0, 0.0)):
    """A closed sphere of 2 n (n - 1) triangles: n meridians, poles as single vertices."""
    rows = []
    for i in range(1, n):
        th = np.pi * i / n
        for j in range(n):
            ph = 2 * np.pi * j / n
            rows.append([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
    pos = np.array([[0.0, 0.0, 1.0]] + rows + [[0.0, 0.0, -1.0]]) * radius + centre
    south = len(pos) - 1
    ring = lambda i, j: 1 + (i - 1) * n + (j % n)  # noqa: E731
    tris = []
    for j in range(n):
        tris.append([0, ring(1, j), ring(1, j + 1)])
        tris.append([south, ring(n - 1, j + 1), ring(n - 1, j)])
    for i in range(1, n - 1):
        for j in range(n):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            tris += [[a, c, d], [a, d, b]]
    return pos, np.array(tris, dtype=np.int64)


def grid(n: int, size: float = 1.0):
    """A flat n x n sheet in z = 0."""
    xs = np.linspace(0.0, size, n + 1)
    pos = np.array([[x, y, 0.0] for y in xs for x in xs])
    idx = lambda i, j: j * (n + 1) + i  # noqa: E731
    tris = []
    for j in range(n):
        for i in range(n):
            tris += [[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)],
                     [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]]
    return pos, np.array(tris, dtype=np.int64)


def soup(count: int, seed: int, scale: float = 1.0):
    """`count` random triangles in the unit cube, sides about `scale` / 4: many intersections,
    no shared vertices."""
    rng = np.random.default_rng(seed)
    centres = rng.random((count, 1, 3))
    pos = (centres + (rng.random((count, 3, 3)) - 0.5) * scale / 2).reshape(-1, 3)
    return pos, np.arange(3 * count, dtype=np.int64).reshape(count, 3)


def exact_pose(seed: int):
    """A rigid pose whose arithmetic is exact: a signed permutation and a dyadic translation, so
    that posed coordinates are the same in NumPy and in the library."""
    rng = np.random.default_rng(seed)
    while True:
        perm = rng.permutation(3)
        signs = rng.choice([-1.0, 1.0], 3)
        r = np.zeros((3, 3))
        r[np.arange(3), perm] = signs
        if np.linalg.det(r) > 0:
            break
    m = np.eye(4)
    m[:3, :3] = r
    m[:3, 3] = rng.integers(-8, 8, 3) / 16.0
    return m


def posed(pos, pose):
    if pose is None:
        return pos
    return pos @ pose[:3, :3].T + pose[:3, 3]


def brute_collide(dvh, pa, ta, pb, tb):
    """Every intersecting pair by the library's exact triangle test, pair by pair."""
    out = [
        (i, j)
        for i, j in itertools.product(range(len(ta)), range(len(tb)))
        if dvh.triangles_intersect(pa[ta[i]], pb[tb[j]])
    ]
    return np.array(out, dtype=np.uint32).reshape(-1, 2)


def _point_triangle(p, t):
    """Distance from point p to the closed triangle t (floating point)."""
    a, b, c = t
    ab, ac, ap = b - a, c - a, p - a
    n = np.cross(ab, ac)
    nn = n @ n
    best = np.inf
    if nn > 0:
        q = p - (ap @ n) / nn * n
        # Barycentric coordinates of the projection.
        v0, v1, v2 = ab, ac, q - a
        d00, d01, d11 = v0 @ v0, v0 @ v1, v1 @ v1
        d20, d21 = v2 @ v0, v2 @ v1
        den = d00 * d11 - d01 * d01
        if den > 0:
            v = (d11 * d20 - d01 * d21) / den
            w = (d00 * d21 - d01 * d20) / den
            if v >= 0 and w >= 0 and v + w <= 1:
                best = abs(ap @ n) / np.sqrt(nn)
    for s, e in ((a, b), (b, c), (c, a)):
        best = min(best, _point_segment(p, s, e))
    return best


def _point_segment(p, s, e):
    d = e - s
    dd = d @ d
    u = 0.0 if dd == 0 else min(1.0, max(0.0, ((p - s) @ d) / dd))
    return np.linalg.norm(p - (s + u * d))


def _segment_segment(p1, q1, p2, q2):
    """Distance between two closed segments: sampled by their closest-point parameters, with
    the end-point distances as the fallback for parallel or degenerate segments."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = d1 @ d1, d2 @ d2, d2 @ r
    best = min(
        _point_segment(p1, p2, q2), _point_segment(q1, p2, q2),
        _point_segment(p2, p1, q1), _point_segment(q2, p1, q1),
    )
    if a > 0 and e > 0:
        b, c = d1 @ d2, d1 @ r
        den = a * e - b * b
        if den > 1e-300:
            s = min(1.0, max(0.0, (b * f - c * e) / den))
            t = (b * s + f) / e
            if 0 <= t <= 1:
                best = min(best, np.linalg.norm(p1 + s * d1 - (p2 + t * d2)))
    return best


def triangle_distance(dvh, t1, t2):
    """Distance between two closed triangles, floating point (0 when they intersect)."""
    if dvh.triangles_intersect(t1, t2):
        return 0.0
    best = min(min(_point_triangle(p, t2) for p in t1), min(_point_triangle(p, t1) for p in t2))
    for i in range(3):
        for j in range(3):
            best = min(best, _segment_segment(t1[i], t1[(i + 1) % 3], t2[j], t2[(j + 1) % 3]))
    return best


def two_cores() -> bool:
    """Can the library's thread pool (sized to the cores, or to RAYON_NUM_THREADS) run two?"""
    if os.environ.get("RAYON_NUM_THREADS", "").strip() == "1":
        return False
    try:
        return len(os.sched_getaffinity(0)) >= 2
    except AttributeError:
        return (os.cpu_count() or 1) >= 2


def same_on_threads(query, same=None):
    """``query(threads)`` for 1, 2 and 0 (every core) threads, asserting one answer; returns it.

    On two or more cores, also asserts that a second thread did a real part of the work of a
    ``threads=2`` call (CPU time of the process's other threads while it ran), so that a
    comparison on work too small to be shared, or a layer that dropped ``threads``, fails. The
    library's calling thread works too and may take back an unstarted share, so a busy machine
    gets a few tries."""
    same = same or (lambda x, y: np.array_equal(x, y))
    want = query(1)
    assert len(want) > 0
    shares = []
    for _ in range(6):
        p0, t0 = time.process_time(), time.thread_time()
        got = query(2)
        calling = time.thread_time() - t0
        others = time.process_time() - p0 - calling
        assert same(got, want)
        shares.append(others / max(calling + others, 1e-9))
        if max(shares) > 0.2:
            break
    assert same(query(0), want)
    if two_cores():
        assert max(shares) > 0.2, f"no second thread took part: shares {shares}"
    return want


@pytest.fixture
def meshes():
    return {"uv_sphere": uv_sphere, "grid": grid, "soup": soup}
