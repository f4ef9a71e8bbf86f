"""Closest-point stencils from Python: hand-worked values, the whole set and its values against
a floating-point brute force built on IPC Toolkit's distance functions (a second, independent
reference), the classification against ipctk's distance types where the case is well
conditioned, the options, the result array and the errors."""

import os

import numpy as np
import pytest

import dvh
from conftest import (
    PARALLEL_MIN_NODE_PAIRS,
    PARALLEL_MIN_STENCIL_VALUES,
    PARALLEL_MIN_TRIANGLES,
    exact_pose,
    grid,
    posed,
    same_on_threads,
    uv_sphere,
)

from test_ccd import edges_of

if os.environ.get("DVH_REQUIRE_IPCTK"):
    import ipctk
else:
    ipctk = pytest.importorskip("ipctk")

TRIANGLE = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
ONE = np.array([[0, 1, 2]])


def test_hand_worked_stencils():
    # A vertex 1/2 above a right triangle's interior; an edge 1/4 above two of its edges.
    b = np.array([[0.25, 0.25, 0.5], [0.25, -1.0, 0.25], [0.25, 2.0, 0.25]])
    near = dvh.nearest_features(dvh.Mesh(TRIANGLE, ONE), dvh.Mesh(b, ONE), 0.25)
    assert near.dtype == dvh.NEAR_PAIR_DTYPE and near.dtype.itemsize == 136
    assert [tuple(int(x) for x in r[["kind", "a0", "a1", "b0", "b1"]]) for r in near] == [
        (dvh.IMPACT_EDGE_EDGE, 0, 1, 1, 2),
        (dvh.IMPACT_EDGE_EDGE, 1, 2, 1, 2),
    ]
    first = near[0]
    assert first["distance"] == 0.25
    assert first["feature_a"] == dvh.FEATURE_EDGE_01 and first["feature_b"] == dvh.FEATURE_EDGE_01
    assert first["closest_a"].tolist() == [0.25, 0.0, 0.0]
    assert first["closest_b"].tolist() == [0.25, 0.0, 0.25]
    assert first["weights_a"].tolist() == [0.75, 0.25, 0.0]
    assert first["weights_b"].tolist() == [2 / 3, 1 / 3, 0.0]
    near = dvh.nearest_features(dvh.Mesh(TRIANGLE, ONE), dvh.Mesh(b, ONE), 0.5)
    (fv,) = near[(near["kind"] == dvh.IMPACT_FACE_VERTEX) & (near["b0"] == 0)]
    assert fv["distance"] == 0.5 and fv["a0"] == 0
    assert (fv["feature_a"], fv["feature_b"]) == (dvh.FEATURE_INTERIOR, dvh.FEATURE_VERTEX_0)
    assert fv["closest_a"].tolist() == [0.25, 0.25, 0.0]
    assert fv["weights_a"].tolist() == [0.5, 0.25, 0.25]
    assert fv["weights_b"].tolist() == [1.0, 0.0, 0.0]


# ipctk's distance types, as dvh's features (on the vertex, then the triangle; on edge a, then b).
def _pt_types():
    t = ipctk.PointTriangleDistanceType
    v0, v1, v2, e01, e12, e20, inside = range(7)
    return {
        t.P_T0: v0,
        t.P_T1: v1,
        t.P_T2: v2,
        t.P_E0: e01,
        t.P_E1: e12,
        t.P_E2: e20,
        t.P_T: inside,
    }


def _ee_types():
    t = ipctk.EdgeEdgeDistanceType
    v0, v1, e = dvh.FEATURE_VERTEX_0, dvh.FEATURE_VERTEX_1, dvh.FEATURE_EDGE_01
    return {
        t.EA0_EB0: (v0, v0),
        t.EA0_EB1: (v0, v1),
        t.EA1_EB0: (v1, v0),
        t.EA1_EB1: (v1, v1),
        t.EA_EB0: (e, v0),
        t.EA_EB1: (e, v1),
        t.EA0_EB: (v0, e),
        t.EA1_EB: (v1, e),
        t.EA_EB: (e, e),
    }


def _reference(pa, ta, pb, tb, d, one_mesh):
    """Every stencil by brute force with ipctk's (floating-point) squared distances: key ->
    (distance, ipctk's feature pair). Pairs within a relative 1e-9 of ``d`` are left out (there
    floating point may decide either way), returned apart."""
    out, borderline = {}, set()
    pt, ee = _pt_types(), _ee_types()
    pt_of = {v: k for k, v in pt.items()}
    ee_of = {v: k for k, v in ee.items()}

    def add(key, squared, features, distance_as):
        dist = float(np.sqrt(squared))
        if abs(dist - d) <= 1e-9 * max(d, 1e-300):
            borderline.add(key)
        elif dist <= d:
            out[key] = (dist, features, distance_as)

    used_a = sorted(set(np.asarray(ta).ravel().tolist()))
    used_b = sorted(set(np.asarray(tb).ravel().tolist()))
    for v in used_a:
        for t, tri in enumerate(np.asarray(tb).tolist()):
            if one_mesh and v in tri:
                continue
            c = [pb[i] for i in tri]
            kind = ipctk.point_triangle_distance_type(pa[v], *c)
            add((dvh.IMPACT_VERTEX_FACE, v, 0, t, 0), ipctk.point_triangle_distance(pa[v], *c),
                (dvh.FEATURE_VERTEX_0, pt[kind]),
                lambda f, p=pa[v], c=c: ipctk.point_triangle_distance(p, *c, pt_of[f[1]]))
    if not one_mesh:
        for t, tri in enumerate(np.asarray(ta).tolist()):
            c = [pa[i] for i in tri]
            for v in used_b:
                kind = ipctk.point_triangle_distance_type(pb[v], *c)
                add((dvh.IMPACT_FACE_VERTEX, t, 0, v, 0), ipctk.point_triangle_distance(pb[v], *c),
                    (pt[kind], dvh.FEATURE_VERTEX_0),
                    lambda f, p=pb[v], c=c: ipctk.point_triangle_distance(p, *c, pt_of[f[0]]))
    ea, eb = edges_of(ta), edges_of(tb)
    for i, x in enumerate(ea):
        for y in eb[i + 1:] if one_mesh else eb:
            if one_mesh and (set(x) & set(y)):
                continue
            q = [pa[x[0]], pa[x[1]], pb[y[0]], pb[y[1]]]
            kind = ipctk.edge_edge_distance_type(*q)
            add((dvh.IMPACT_EDGE_EDGE, x[0], x[1], y[0], y[1]), ipctk.edge_edge_distance(*q), ee[kind],
                lambda f, q=q: ipctk.edge_edge_distance(*q, ee_of[f]))
    return out, borderline


def same(x, y):
    """Equal stencils in the same order. (Not ``tobytes``: NumPy does not copy the padding.)"""
    return x.dtype == y.dtype and len(x) == len(y) and bool(np.all(x == y))


def _check(near, pa, ta, pb, tb, d, one_mesh):
    expected, borderline = _reference(pa, ta, pb, tb, d, one_mesh)
    got = {tuple(int(x) for x in r[["kind", "a0", "a1", "b0", "b1"]]): r for r in near}
    assert set(expected) <= set(got), sorted(set(expected) - set(got))[:5]
    assert set(got) <= set(expected) | borderline, sorted(set(got) - set(expected) - borderline)[:5]
    agree = 0
    for key, r in got.items():
        assert r["distance"] <= d
        if key not in expected:
            continue
        dist, features, distance_as = expected[key]
        assert r["distance"] == pytest.approx(dist, rel=1e-9, abs=1e-12)
        gap = np.linalg.norm(r["closest_a"] - r["closest_b"])
        assert gap == pytest.approx(r["distance"], rel=1e-9, abs=1e-12)
        for side in ("a", "b"):
            w = r["weights_" + side]
            assert np.all((w >= 0) & (w <= 1)) and abs(w.sum() - 1) < 1e-12
        ours = (int(r["feature_a"]), int(r["feature_b"]))
        if ours == features:
            agree += 1
        else:
            # Floating point put the closest point on a neighbouring feature: then the two
            # classifications must give the same distance (a point on their common boundary).
            assert np.sqrt(distance_as(ours)) == pytest.approx(dist, rel=1e-9, abs=1e-12), (key, ours, features)
    return len(got), agree


def test_two_meshes_against_ipctk():
    pa, ta = uv_sphere(10, 0.5, (0.0, 0.0, 0.0))
    pb, tb = grid(8, 2.0)
    pb = pb - [1.0, 1.0, 0.55]
    pose = exact_pose(3)
    found = compared = 0
    for d in [0.0, 0.03, 0.08, 0.2]:
        for pose_b in [None, pose]:
            a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)
            near = dvh.nearest_features(a, b, d, pose_b=pose_b)
            n, c = _check(near, pa, ta, posed(pb, pose_b), tb, d, False)
            found, compared = found + n, compared + c
            again = dvh.nearest_features(a, b, d, pose_b=pose_b, mode="depth", max_depth=2)
            assert same(again, near)
    assert found > 200 and compared > 100, (found, compared)


def test_threads_give_the_same_stencils():
    # Sizes above the library's cut-offs for sharing work: the triangles of the query, the
    # leaf pairs given to the primitive tests and the stencils whose values are computed.
    pa, ta = uv_sphere(48, 0.5)
    pb, tb = grid(48, 2.0)
    a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb - [1.0, 1.0, 0.5], tb)
    assert a.triangle_count + b.triangle_count >= PARALLEL_MIN_TRIANGLES
    _, st = dvh.nearest_features(a, b, 0.03, stats=True)
    assert st.leaf_pairs >= PARALLEL_MIN_NODE_PAIRS
    near = same_on_threads(lambda k: dvh.nearest_features(a, b, 0.03, threads=k), same)
    assert len(near) >= PARALLEL_MIN_STENCIL_VALUES
    for mode, extra in [("depth", {"max_depth": 2}), ("leaves", {})]:
        coarse = same_on_threads(lambda k: dvh.nearest_features(a, b, 0.03, mode=mode, threads=k, **extra), same)
        assert same(coarse, near)
    # Two layers of a sheet, a little apart, as one mesh.
    p, t = grid(32)
    sheets = dvh.Mesh(np.vstack([p, p + [0.004, 0.003, 0.01]]), np.vstack([t, t + len(p)]))
    _, st = dvh.self_nearest_features(sheets, 0.012, stats=True)
    assert st.leaf_pairs >= PARALLEL_MIN_NODE_PAIRS
    near = same_on_threads(lambda k: dvh.self_nearest_features(sheets, 0.012, threads=k), same)
    assert len(near) >= PARALLEL_MIN_STENCIL_VALUES


def test_one_mesh_against_ipctk():
    p, t = grid(8, 1.0)
    rng = np.random.default_rng(7)
    # A sheet folded over itself, a little uneven.
    folded = p.copy()
    right = p[:, 0] > 0.5
    folded[right, 0] = 1.0 - p[right, 0]
    folded[right, 2] = 0.02 + 0.01 * p[right, 1]
    folded += rng.uniform(-0.003, 0.003, folded.shape)
    found = compared = 0
    for d in [0.0, 0.02, 0.05, 0.15]:
        near = dvh.self_nearest_features(dvh.Mesh(folded, t), d)
        assert not np.any(near["kind"] == dvh.IMPACT_FACE_VERTEX)
        n, c = _check(near, folded, t, folded, t, d, True)
        found, compared = found + n, compared + c
    assert found > 500 and compared > 200, (found, compared)


def test_options_statistics_and_errors():
    p, t = grid(12, 1.0)
    m = dvh.Mesh(p, t)
    whole, stats = dvh.self_nearest_features(m, 0.1, stats=True)
    assert stats.pairs == len(whole) > 100 and stats.triangle_tests >= len(whole)
    assert not stats.truncated
    order = list(zip(whole["kind"], whole["a0"], whole["a1"], whole["b0"], whole["b1"]))
    assert order == sorted(order)
    part, stats = dvh.self_nearest_features(m, 0.1, max_pairs=5, stats=True)
    assert len(part) == 5 and stats.truncated
    assert np.isin(part, whole).all()
    first = dvh.self_nearest_features(m, 0.1, mode="first_hit")
    assert len(first) == 1 and np.isin(first, whole).all()
    for mode, extra in [("leaves", {}), ("depth", {"max_depth": 1}), ("budget", {"budget": 3})]:
        assert same(dvh.self_nearest_features(m, 0.1, mode=mode, **extra), whole)
    assert len(dvh.self_nearest_features(m, 0.0)) == 0
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(dvh.DvhError, match="distance"):
            dvh.self_nearest_features(m, bad)
        with pytest.raises(dvh.DvhError, match="distance"):
            dvh.nearest_features(m, m, bad)
    with pytest.raises(TypeError, match="distance"):
        dvh.nearest_features(m, m, "0.1")
    with pytest.raises(dvh.DvhError, match="budget"):
        dvh.self_nearest_features(m, 0.1, mode="budget")
    with pytest.raises(ValueError):
        dvh.self_nearest_features(m, 0.1, mode="nearest")
    far = np.eye(4)
    far[0, 3] = 1e301
    with pytest.raises(dvh.DvhError, match="POSE_OUT_OF_RANGE"):
        dvh.nearest_features(m, m, 0.1, pose_a=far)
    # A failed call leaves the next result unaffected.
    assert same(dvh.self_nearest_features(m, 0.1), whole)
