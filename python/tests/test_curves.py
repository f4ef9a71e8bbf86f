"""Intersection curves from Python: every segment on both of its triangles, curves that chain
bit for bit, the pairs those of collide, closed curves on closed surfaces, OBJ polylines, the
command line's --curves."""

import numpy as np
import pytest
from conftest import exact_pose, soup, uv_sphere

import dvh


def _plane_gap(tri, p):
    """Distance of point p from the plane of triangle tri, relative to its size."""
    n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    scale = max(np.abs(tri).max(), np.abs(p).max(), 1.0)
    return abs(np.dot(n, p - tri[0])) / (np.linalg.norm(n) * scale)


def _check(curves, pa, ta, pb, tb, pairs, closed):
    seg = curves.segments
    assert seg.dtype == dvh.SEGMENT_DTYPE
    got = np.concatenate(
        [
            np.stack([seg["triangle_a"], seg["triangle_b"]], axis=1),
            np.stack([curves.degenerate["triangle_a"], curves.degenerate["triangle_b"]], axis=1),
        ]
    )
    assert sorted(map(tuple, got.tolist())) == sorted(map(tuple, pairs.tolist()))
    # Curves cover the segments in order, each a chain, bit for bit.
    assert curves.ranges[0, 0] == 0 if len(curves) else len(seg) == 0
    assert np.array_equal(curves.ranges[1:, 0], curves.ranges[:-1, 1])
    for i in range(len(curves)):
        c = curves.curve(i)
        assert np.all(c["curve"] == i)
        assert np.array_equal(c["end"][:-1].view(np.uint64), c["start"][1:].view(np.uint64))
        if closed:
            assert curves.closed[i]
            assert np.array_equal(c["end"][-1].view(np.uint64), c["start"][0].view(np.uint64))
    # Every end point lies on the planes of both its triangles (up to rounding).
    for s in seg:
        a, b = pa[ta[s["triangle_a"]]], pb[tb[s["triangle_b"]]]
        for p in (s["start"], s["end"]):
            assert _plane_gap(a, p) < 1e-13 and _plane_gap(b, p) < 1e-13
    assert np.all(curves.lengths > 0)


def test_overlapping_spheres_cross_in_closed_curves():
    pa, ta = uv_sphere(24)
    pb, tb = uv_sphere(17, 0.8, (0.31, 0.22, 0.13))
    a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)
    for threads in (0, 1, 2):
        curves, stats = dvh.intersection_curves(a, b, threads=threads, stats=True)
        pairs = dvh.collide(a, b)
        assert stats.pairs == len(pairs) and not stats.truncated
        assert len(curves) >= 1 and len(curves.degenerate) == 0
        _check(curves, pa, ta, pb, tb, pairs, closed=True)
    # One closed curve around the smaller sphere's cap: its length is about a circle's.
    assert len(curves.polylines()) == len(curves)
    p = curves.polyline(0)
    assert np.array_equal(p[0], p[-1])


def test_posed_meshes_cross_where_their_moved_copies_do():
    pa, ta = uv_sphere(20)
    pb, tb = uv_sphere(15, 0.9)
    pose = exact_pose(3)
    moved = pb @ pose[:3, :3].T + pose[:3, 3]
    a = dvh.Mesh(pa, ta)
    posed = dvh.intersection_curves(a, dvh.Mesh(pb, tb), pose_b=pose)
    placed = dvh.intersection_curves(a, dvh.Mesh(moved, tb))
    assert len(posed.segments) > 0
    assert posed.segments.tobytes() == placed.segments.tobytes()
    assert np.array_equal(posed.ranges, placed.ranges)


def test_self_curves_of_two_spheres_as_one_mesh():
    pa, ta = uv_sphere(20)
    pb, tb = uv_sphere(15, 0.8, (0.4, 0.1, -0.2))
    one = dvh.Mesh(np.vstack([pa, pb]), np.vstack([ta, tb + len(pa)]))
    two = dvh.intersection_curves(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb))
    self_ = dvh.self_intersection_curves(one)
    assert np.array_equal(self_.segments["triangle_a"], two.segments["triangle_a"])
    assert np.array_equal(self_.segments["triangle_b"], two.segments["triangle_b"] + len(ta))
    assert self_.segments["start"].tobytes() == two.segments["start"].tobytes()
    pall = np.vstack([pa, pb])
    tall = np.vstack([ta, tb + len(pa)])
    _check(self_, pall, tall, pall, tall, dvh.self_collide(one), closed=True)


def test_soups_have_open_curves_and_a_limit():
    pa, ta = soup(300, 1)
    pb, tb = soup(300, 2)
    a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)
    curves = dvh.intersection_curves(a, b)
    pairs = dvh.collide(a, b)
    _check(curves, pa, ta, pb, tb, pairs, closed=False)
    assert not curves.closed.any()
    cut, stats = dvh.intersection_curves(a, b, max_pairs=5, stats=True)
    assert len(cut.segments) + len(cut.degenerate) == 5 and stats.truncated


def test_a_copy_gives_coplanar_pairs():
    p, t = uv_sphere(10)
    m = dvh.Mesh(p, t)
    curves = dvh.intersection_curves(m, m)
    # Each triangle with its copy; and, the sphere's quads being flat, each half of a quad with
    # the other's copy.
    d = curves.degenerate
    same = d[d["triangle_a"] == d["triangle_b"]]
    assert len(same) == len(t) and np.all(same["kind"] == dvh.DEGENERATE_COPLANAR)
    assert set(np.unique(curves.degenerate["kind"])) <= {dvh.DEGENERATE_POINT, dvh.DEGENERATE_COPLANAR}


def test_obj_polylines(tmp_path):
    pa, ta = uv_sphere(16)
    pb, tb = uv_sphere(12, 0.7, (0.5, 0.0, 0.1))
    curves = dvh.intersection_curves(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb))
    path = tmp_path / "curves.obj"
    curves.write_obj(path)
    vertices, lines = [], []
    for line in path.read_text().splitlines():
        if line.startswith("v "):
            vertices.append([float(x) for x in line.split()[1:]])
        elif line.startswith("l "):
            lines.append([int(x) - 1 for x in line.split()[1:]])
    vertices = np.array(vertices)
    assert len(lines) == len(curves)
    for i, idx in enumerate(lines):
        assert np.array_equal(vertices[idx], curves.polyline(i))


def test_errors():
    p, t = uv_sphere(8)
    m = dvh.Mesh(p, t)
    with pytest.raises(TypeError, match="a must be a dvh.Mesh"):
        dvh.intersection_curves(p, m)
    with pytest.raises(ValueError, match="pose_b"):
        dvh.intersection_curves(m, m, pose_b=np.eye(3))
    with pytest.raises(dvh.DvhError, match="NON_RIGID_POSE"):
        dvh.intersection_curves(m, m, pose_a=np.diag([2.0, 1.0, 1.0, 1.0]))
    with pytest.raises(ValueError, match="threads"):
        dvh.self_intersection_curves(m, threads=-1)


def test_length_gradient_shortens_the_curves():
    pa, ta = uv_sphere(24)
    pb, tb = uv_sphere(17, 0.8, (0.31, 0.22, 0.13))
    curves = dvh.intersection_curves(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb), gradient=True)
    assert curves.gradient_a.shape == pa.shape and curves.gradient_b.shape == pb.shape
    assert np.abs(curves.gradient_a).sum() > 0
    step = 1e-3
    after = dvh.intersection_curves(
        dvh.Mesh(pa - step * curves.gradient_a, ta), dvh.Mesh(pb - step * curves.gradient_b, tb)
    )
    assert after.lengths.sum() < curves.lengths.sum()
    one = dvh.Mesh(np.vstack([pa, pb]), np.vstack([ta, tb + len(pa)]))
    own = dvh.self_intersection_curves(one, gradient=True)
    assert own.gradient_b is None
    assert np.allclose(own.gradient_a, np.vstack([curves.gradient_a, curves.gradient_b]), atol=1e-12)
    plain = dvh.intersection_curves(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb))
    assert plain.gradient_a is None
