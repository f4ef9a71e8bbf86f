"""Distances from Python: the least distance of two meshes and the closest points of many
points against floating-point brute force over every primitive pair (the library's answers are
exact; the brute force is within rounding), winding numbers and signs of closed meshes against
their insides, the scene's closest objects, the options and the errors."""

import numpy as np
import pytest

import dvh
from conftest import grid, uv_sphere


def box(x0=0.0, w=2.0):
    """An axis-aligned box [x0, x0 + w] x [0, w] x [0, w] of twelve outward triangles."""
    pos = np.array(
        [[x0 + (i & 1) * w, ((i >> 1) & 1) * w, ((i >> 2) & 1) * w] for i in range(8)], dtype=float
    )
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    tris = [t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])]
    return pos, np.array(tris)


def point_triangle(p, a, b, c):
    """The distance from point p to the closed triangle abc, in floating point (by its plane,
    edges and corners)."""
    n = np.cross(b - a, c - a)
    nn = n @ n
    best = min(np.linalg.norm(p - v) for v in (a, b, c))
    for u, v in ((a, b), (b, c), (c, a)):
        e = v - u
        s = np.clip((p - u) @ e / (e @ e), 0.0, 1.0)
        best = min(best, np.linalg.norm(p - (u + s * e)))
    if nn > 0:
        foot = p - ((p - a) @ n / nn) * n
        inside = all(np.cross(v - u, foot - u) @ n >= 0 for u, v in ((a, b), (b, c), (c, a)))
        if inside:
            best = min(best, abs((p - a) @ n) / np.sqrt(nn))
    return best


def segment_segment(p1, q1, p2, q2):
    """The distance between two closed segments, sampled densely then refined: a floating-point
    reference."""
    s = np.linspace(0.0, 1.0, 41)
    a = p1 + s[:, None] * (q1 - p1)
    b = p2 + s[:, None] * (q2 - p2)
    best = np.min(np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2))
    for x in (p1, q1):
        e = q2 - p2
        t = np.clip((x - p2) @ e / max(e @ e, 1e-300), 0.0, 1.0)
        best = min(best, np.linalg.norm(x - (p2 + t * e)))
    for x in (p2, q2):
        e = q1 - p1
        t = np.clip((x - p1) @ e / max(e @ e, 1e-300), 0.0, 1.0)
        best = min(best, np.linalg.norm(x - (p1 + t * e)))
    return best


def test_box_distances_closest_points_windings_and_signs():
    a = dvh.Mesh(*box(0.0))
    b = dvh.Mesh(*box(5.0))
    assert a.is_closed and b.is_closed
    d = dvh.distance(a, b)
    assert d.distance == 3.0 and not d.intersecting
    assert d.closest_a[0] == 2.0 and d.closest_b[0] == 5.0
    assert d.stencil["distance"] == 3.0 and d.stencil.dtype == dvh.NEAR_PAIR_DTYPE
    assert dvh.distance(a, b, max_distance=2.5) is None
    d, stats = dvh.distance(a, b, stats=True)
    assert stats.bv_tests > 0
    through = dvh.distance(a, dvh.Mesh(*box(1.0)))
    assert through.intersecting and through.distance == 0.0 and through.stencil is None
    # Posed: moved back by 4 along x, the second box overlaps the first.
    back = np.eye(4)
    back[0, 3] = -4.0
    assert dvh.distance(a, b, pose_b=back).intersecting

    points = np.array(
        [[1, 1, 1], [1.5, 0.5, 5], [2, 1, 1], [2, 2, 1], [0, 0, 0], [-1, 0, 0], [1, 0, 2.5], [3, 3, 3]],
        dtype=float,
    )
    c = dvh.closest_points(a, points)
    assert c.dtype == dvh.CLOSEST_POINT_DTYPE and c.dtype.itemsize == 72
    assert c["found"].tolist() == [1] * 8
    assert c["distance"].tolist() == [1, 3, 0, 0, 0, 1, 0.5, np.sqrt(3)]
    assert c["point"][1].tolist() == [1.5, 0.5, 2.0] and c["feature"][1] == dvh.FEATURE_INTERIOR
    w = dvh.winding_numbers(a, points)
    on = dvh.WINDING_ON_SURFACE
    assert w.dtype == np.int32 and w.tolist() == [1, 0, on, on, on, 0, 0, 0]
    s = dvh.signed_distances(a, points)
    assert s.tolist() == [-1, 3, 0, 0, 0, 1, 0.5, np.sqrt(3)]
    s = dvh.signed_distances(a, points, max_distance=0.75)
    assert s[0] == -np.inf and s[1] == np.inf and s[6] == 0.5
    c, stats = dvh.closest_points(a, points, max_distance=0.75, stats=True)
    assert c["found"].tolist() == [0, 0, 1, 1, 1, 0, 1, 0] and stats.pairs == 4
    assert c["distance"][0] == 0.0 and c["triangle"][0] == 0


def test_sphere_and_sheet_against_brute_force():
    rng = np.random.default_rng(5)
    pos, tris = uv_sphere(10, radius=1.0)
    pos = pos + rng.uniform(-0.02, 0.02, pos.shape)
    sphere = dvh.Mesh(pos, tris)
    gp, gt = grid(6, 2.0)
    gp = gp + np.array([-1.0, -1.0, 1.3])
    sheet = dvh.Mesh(gp, gt)
    d = dvh.distance(sphere, sheet)
    reference = min(
        min(point_triangle(pos[v], *gp[t]) for v in range(len(pos)) for t in gt),
        min(point_triangle(gp[v], *pos[t]) for v in range(len(gp)) for t in tris),
    )
    edges_a = {tuple(sorted((t[k], t[(k + 1) % 3]))) for t in tris for k in range(3)}
    edges_b = {tuple(sorted((t[k], t[(k + 1) % 3]))) for t in gt for k in range(3)}
    near_edges = [e for e in edges_a if pos[list(e)][:, 2].max() > 0.8]
    reference = min(
        reference,
        min(segment_segment(pos[u], pos[v], gp[x], gp[y]) for u, v in near_edges for x, y in edges_b),
    )
    assert abs(d.distance - reference) <= 1e-6
    assert not d.intersecting
    # Closest points of random points: each distance is the least over the triangles.
    points = rng.uniform(-1.6, 1.6, (60, 3))
    c = dvh.closest_points(sphere, points)
    for p, r in zip(points, c):
        ref = min(point_triangle(p, *pos[t]) for t in tris)
        assert abs(r["distance"] - ref) <= 1e-12 * max(1.0, ref)
        assert abs(point_triangle(r["point"], *pos[tris[r["triangle"]]])) <= 1e-12
    # Same on one thread as on every core.
    assert np.array_equal(c, dvh.closest_points(sphere, points, threads=1))
    # The sphere winds once (one sign or the other) around its inside.
    w = dvh.winding_numbers(sphere, points)
    inside = np.linalg.norm(points, axis=1) < 0.9
    outside = np.linalg.norm(points, axis=1) > 1.1
    assert set(np.abs(w[inside]).tolist()) <= {1} and set(w[outside].tolist()) <= {0}
    s = dvh.signed_distances(sphere, points)
    assert np.all((s < 0) == (w != 0))
    assert np.allclose(np.abs(s), c["distance"])


def test_errors_name_the_culprit():
    a = dvh.Mesh(*box(0.0))
    sheet = dvh.Mesh(*grid(3, 1.0))
    assert not sheet.is_closed
    with pytest.raises(dvh.DvhError, match="not closed"):
        dvh.winding_numbers(sheet, [[0.0, 0.0, 0.0]])
    with pytest.raises(dvh.DvhError, match="not closed"):
        dvh.signed_distances(sheet, [[0.0, 0.0, 0.0]])
    with pytest.raises(dvh.DvhError, match="point 1 has a non-finite coordinate y"):
        dvh.closest_points(a, [[0.0, 0.0, 0.0], [1.0, np.nan, 0.0]])
    with pytest.raises(dvh.DvhError, match="max_distance"):
        dvh.distance(a, a, max_distance=-1.0)
    with pytest.raises(dvh.DvhError, match="rel_err"):
        dvh.closest_points(a, [[0.0, 0.0, 0.0]], rel_err=np.inf)
    with pytest.raises(ValueError, match=r"shape \(n, 3\)"):
        dvh.closest_points(a, [[0.0, 0.0]])
    with pytest.raises(TypeError):
        dvh.distance(a, "not a mesh")


def test_the_scene_closest_objects():
    scene = dvh.Scene()
    i0 = scene.add_rigid(dvh.Mesh(*box(0.0)))
    i1 = scene.add_rigid(dvh.Mesh(*box(5.0)))
    i2 = scene.add_rigid(dvh.Mesh(*box(1.0)))
    ia, ib, d = scene.distance()
    assert (ia, ib) == (i0, i2) and d.intersecting
    scene.exclude_pair(i0, i2)
    ia, ib, d = scene.distance()
    assert (ia, ib) == (i1, i2) and d.distance == 2.0
    other, d = scene.object_distance(i1)
    assert other == i2 and d.closest_a[0] == 5.0
    assert scene.object_distance(i1, max_distance=1.0) is None
    with pytest.raises(dvh.DvhError, match="object 9"):
        scene.object_distance(9)
