"""Continuous collision from Python: the primitive tests, motions, the mesh queries against a
brute force over every primitive pair (by the library's own primitive tests), the options, the
result arrays and the errors."""

import threading

import numpy as np
import pytest

import dvh
from conftest import PARALLEL_MIN_TRIANGLES, grid, same_on_threads, uv_sphere

TRIANGLE = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def falling_point(x=0.25, y=0.25, z0=1.0, z1=-3.0):
    """A point moving from (x, y, z0) to (x, y, z1) and the still triangle TRIANGLE (z = 0)."""
    return np.vstack([[x, y, z0], TRIANGLE]), np.vstack([[x, y, z1], TRIANGLE])


def edges_of(triangles):
    """The unique edges (lo, hi) of a triangle list, sorted."""
    out = set()
    for t in np.asarray(triangles).tolist():
        for i in range(3):
            u, v = t[i], t[(i + 1) % 3]
            if u != v:
                out.add((min(u, v), max(u, v)))
    return sorted(out)


def impacts_of(rows):
    return np.array(sorted(rows), dtype=dvh.IMPACT_DTYPE)


def rows(impacts):
    """Impacts as a set of plain tuples (kind, a0, a1, b0, b1, toi)."""
    return {tuple(x.item() for x in r) for r in impacts}


def keyed(impacts):
    """Impacts as a dict (kind, a0, a1, b0, b1) -> toi."""
    return {tuple(int(r[f]) for f in ("kind", "a0", "a1", "b0", "b1")): float(r["toi"]) for r in impacts}


def brute_continuous(sa, ea, ta, sb, eb, tb, mode="exact"):
    """Every impact of two moving meshes, pair by pair, with the library's primitive tests."""
    out = []
    va = sorted(set(np.asarray(ta).ravel().tolist()))
    vb = sorted(set(np.asarray(tb).ravel().tolist()))
    for v in va:
        for j, t in enumerate(tb):
            toi = dvh.ccd_vertex_face(np.vstack([sa[v], sb[t]]), np.vstack([ea[v], eb[t]]), mode=mode)
            if toi is not None:
                out.append((dvh.IMPACT_VERTEX_FACE, v, 0, j, 0, toi))
    for i, t in enumerate(ta):
        for v in vb:
            toi = dvh.ccd_vertex_face(np.vstack([sb[v], sa[t]]), np.vstack([eb[v], ea[t]]), mode=mode)
            if toi is not None:
                out.append((dvh.IMPACT_FACE_VERTEX, i, 0, v, 0, toi))
    for a0, a1 in edges_of(ta):
        for b0, b1 in edges_of(tb):
            s = np.vstack([sa[[a0, a1]], sb[[b0, b1]]])
            e = np.vstack([ea[[a0, a1]], eb[[b0, b1]]])
            toi = dvh.ccd_edge_edge(s, e, mode=mode)
            if toi is not None:
                out.append((dvh.IMPACT_EDGE_EDGE, a0, a1, b0, b1, toi))
    return impacts_of(out)


def brute_self_continuous(s, e, t):
    """Every impact of one moving mesh with itself: vertices against the triangles not holding
    them, edges against the later edges they share no vertex with."""
    out = []
    for v in sorted(set(np.asarray(t).ravel().tolist())):
        for j, tri in enumerate(t):
            if v in tri:
                continue
            toi = dvh.ccd_vertex_face(np.vstack([s[v], s[tri]]), np.vstack([e[v], e[tri]]))
            if toi is not None:
                out.append((dvh.IMPACT_VERTEX_FACE, v, 0, j, 0, toi))
    edges = edges_of(t)
    for i, (a0, a1) in enumerate(edges):
        for b0, b1 in edges[i + 1:]:
            if {a0, a1} & {b0, b1}:
                continue
            toi = dvh.ccd_edge_edge(s[[a0, a1, b0, b1]], e[[a0, a1, b0, b1]])
            if toi is not None:
                out.append((dvh.IMPACT_EDGE_EDGE, a0, a1, b0, b1, toi))
    return impacts_of(out)


def is_sorted(impacts):
    keys = [tuple(int(r[f]) for f in ("kind", "a0", "a1", "b0", "b1")) for r in impacts]
    return keys == sorted(keys) and len(set(keys)) == len(keys)


def passing_spheres():
    """A small sphere crossing a larger, slightly growing one during the step, apart at both
    ends of it."""
    pa, ta = uv_sphere(6, radius=0.3, centre=(-1.5, 0.1, 0.05))
    pb, tb = uv_sphere(8)
    sa, ea = pa, pa + [3.0, 0.0, 0.0]
    sb, eb = pb, pb * 1.05
    return (sa, ea, ta), (sb, eb, tb)


@pytest.fixture
def moving():
    (sa, ea, ta), (sb, eb, tb) = passing_spheres()
    a, b = dvh.Mesh(sa, ta), dvh.Mesh(sb, tb)
    a.refit_motion(sa, ea)
    b.refit_motion(sb, eb)
    return a, b, (sa, ea, ta), (sb, eb, tb)


def folding_sphere():
    """A sphere whose north cap is pushed, shrunk and shifted, through its south half during
    the step (the equator and the south half stay)."""
    p, t = uv_sphere(6)
    folded = p.copy()
    north = p[:, 2] > 0.1
    folded[north] = p[north] * [0.8, 0.8, -1.0] + [0.1, 0.05, -0.4]
    return p, folded, t


# ---------------------------------------------------------------------------------------------
# Primitive tests


def test_point_falling_through_a_triangle():
    s, e = falling_point()
    assert dvh.ccd_vertex_face(s, e) == 0.25
    assert dvh.ccd_vertex_face(s.tolist(), e.tolist(), mode="exact") == 0.25
    assert dvh.ccd_vertex_face(s.astype(np.float32), e.astype(np.int64) * 1.0) == 0.25
    cons = dvh.ccd_vertex_face(s, e, mode="conservative")
    assert cons is not None and 0.0 <= cons <= 0.25
    # Misses: beside the triangle, moving away from it, stopping short of it.
    for miss in (falling_point(x=2.0, y=2.0), falling_point(z0=1.0, z1=2.0),
                 falling_point(z0=1.0, z1=0.5)):
        assert dvh.ccd_vertex_face(*miss) is None
        assert dvh.ccd_vertex_face(*miss, mode="conservative") is None
    # Touching counts: a point ending on the triangle's edge, one starting on it.
    assert dvh.ccd_vertex_face(*falling_point(x=0.5, y=0.5, z1=0.0)) == 1.0
    assert dvh.ccd_vertex_face(*falling_point(z0=0.0)) == 0.0


def test_edges_crossing():
    a0, a1 = [0.0, 0.5, 1.0], [1.0, 0.5, 1.0]
    b = [[0.5, 0.0, 0.0], [0.5, 1.0, 0.0]]
    start = np.array([a0, a1] + b)
    end = start.copy()
    end[:2, 2] = -1.0  # edge a drops from z = 1 to z = -1 across edge b at z = 0
    assert dvh.ccd_edge_edge(start, end) == 0.5
    cons = dvh.ccd_edge_edge(start, end, mode="conservative")
    assert cons is not None and cons <= 0.5
    far = start + [[0, 0, 0], [0, 0, 0], [2, 0, 0], [2, 0, 0]]
    assert dvh.ccd_edge_edge(far, end + [[0, 0, 0], [0, 0, 0], [2, 0, 0], [2, 0, 0]]) is None


def random_primitive(rng, kind):
    """A random start and end of 4 points: general ones, ones on a coarse dyadic grid (touching,
    coplanar, parallel and collinear cases), and constructed crossings."""
    if kind == 0:
        s = rng.random((4, 3))
        return s, s + rng.normal(0.0, 0.6, (4, 3))
    if kind == 1:
        return rng.integers(0, 3, (4, 3)) / 2.0, rng.integers(0, 3, (4, 3)) / 2.0
    # A point or edge passing through the other primitive at a random place.
    s = rng.random((4, 3))
    w = rng.dirichlet([1.0, 1.0, 1.0])
    target = w @ s[1:]
    d = rng.normal(0.0, 1.0, 3)
    s[0] = target + d
    e = s + rng.normal(0.0, 0.05, (4, 3))
    e[0] = target - d
    return s, e


@pytest.mark.parametrize("test", [dvh.ccd_vertex_face, dvh.ccd_edge_edge])
def test_conservative_never_misses_and_is_never_later(test):
    rng = np.random.default_rng(11)
    hits = 0
    for i in range(900):
        s, e = random_primitive(rng, i % 3)
        exact = test(s, e)
        cons = test(s, e, mode="conservative")
        if exact is not None:
            hits += 1
            assert 0.0 <= exact <= 1.0
            assert cons is not None and cons <= exact, (s, e, exact, cons)
        if cons is not None:
            assert 0.0 <= cons <= 1.0
    assert hits > 100


def test_primitive_errors():
    s, e = falling_point()
    with pytest.raises(ValueError, match=r"start must have shape \(4, 3\); got \(3, 3\)"):
        dvh.ccd_vertex_face(s[:3], e)
    with pytest.raises(ValueError, match=r"end must have shape \(4, 3\)"):
        dvh.ccd_edge_edge(s, e.ravel())
    with pytest.raises(TypeError, match="start must hold float64 or float32"):
        dvh.ccd_vertex_face(s.astype(complex), e)
    with pytest.raises(ValueError, match="mode must be one of"):
        dvh.ccd_vertex_face(s, e, mode="fast")
    with pytest.raises(TypeError, match="mode must be a string"):
        dvh.ccd_edge_edge(s, e, mode=0)
    bad = e.copy()
    bad[2, 1] = np.inf
    with pytest.raises(dvh.DvhError) as err:
        dvh.ccd_vertex_face(s, bad)
    assert err.value.name == "DVH_STATUS_NON_FINITE_COORDINATE" and "end" in err.value.message
    bad = s.copy()
    bad[0, 0] = np.nan
    with pytest.raises(dvh.DvhError) as err:
        dvh.ccd_edge_edge(bad, e)
    assert err.value.name == "DVH_STATUS_NON_FINITE_COORDINATE" and "start" in err.value.message


# ---------------------------------------------------------------------------------------------
# Meshes against brute force


def test_continuous_collide_matches_brute_force(moving):
    a, b, (sa, ea, ta), (sb, eb, tb) = moving
    # Apart at both ends of the step: the discrete queries find nothing.
    assert len(dvh.collide(a, b)) == 0  # the meshes are at the end positions
    assert len(dvh.collide(dvh.Mesh(sa, ta), dvh.Mesh(sb, tb))) == 0
    got, st = dvh.continuous_collide(a, b, stats=True)
    assert got.dtype == dvh.IMPACT_DTYPE and is_sorted(got)
    want = brute_continuous(sa, ea, ta, sb, eb, tb)
    assert len(got) > 0 and np.array_equal(got, want)
    assert {int(k) for k in got["kind"]} == {0, 1, 2}
    assert st.impacts == len(got) and not st.truncated
    assert st.primitive_tests >= len(got) and st.bv_tests > 0
    assert st.earliest_toi == got["toi"].min() and 0.0 < st.earliest_toi < 1.0
    # Swapping the meshes swaps the roles: vertex-face becomes face-vertex.
    swapped = dvh.continuous_collide(b, a)
    flip = {0: 1, 1: 0, 2: 2}
    want_swapped = {
        (flip[k], b0, b1, a0, a1): toi for (k, a0, a1, b0, b1), toi in keyed(got).items()
    }
    assert keyed(swapped) == want_swapped


def test_a_mesh_without_a_motion_stays_still():
    (sa, ea, ta), (sb, _, tb) = passing_spheres()
    a, b = dvh.Mesh(sa, ta), dvh.Mesh(sb, tb)
    empty, st = dvh.continuous_collide(a, b, stats=True)
    assert empty.shape == (0,) and empty.dtype == dvh.IMPACT_DTYPE
    assert st.impacts == 0 and st.earliest_toi == np.inf and not st.truncated
    a.refit_motion(sa, ea)  # b never moves
    got = dvh.continuous_collide(a, b)
    assert len(got) > 0 and np.array_equal(got, brute_continuous(sa, ea, ta, sb, sb, tb))
    a.refit(ea)  # a plain refit: still again, at the end positions
    assert len(dvh.continuous_collide(a, b)) == 0


def test_conservative_mode_on_meshes(moving):
    a, b = moving[:2]
    exact = keyed(dvh.continuous_collide(a, b))
    cons = keyed(dvh.continuous_collide(a, b, mode="conservative"))
    assert exact and set(exact) <= set(cons)
    assert all(cons[k] <= toi for k, toi in exact.items())


def test_self_continuous_collide_matches_brute_force():
    s, e, t = folding_sphere()
    m = dvh.Mesh(s, t)
    assert len(dvh.self_continuous_collide(m)) == 0  # not moving
    m.refit_motion(s, e)
    got, st = dvh.self_continuous_collide(m, stats=True)
    assert got.dtype == dvh.IMPACT_DTYPE and is_sorted(got)
    assert dvh.IMPACT_FACE_VERTEX not in got["kind"]
    want = brute_self_continuous(s, e, t)
    assert len(got) > 0 and np.array_equal(got, want)
    assert st.impacts == len(got) and st.earliest_toi == got["toi"].min()
    cons = keyed(dvh.self_continuous_collide(m, mode="conservative"))
    assert all(k in cons and cons[k] <= toi for k, toi in keyed(got).items())


def test_a_step_cut_before_the_first_contact_is_free():
    # A sheet above a ball of radius 1 falls 3 units in one step, ending below it.
    p, t = grid(8, 2.0)
    start = p + [-1.0, -1.0, 1.5]
    end = start + [0.0, 0.0, -3.0]
    sphere, st = uv_sphere(8)
    cloth, ball = dvh.Mesh(start, t), dvh.Mesh(sphere, st)
    cloth.refit_motion(start, end)
    assert len(dvh.collide(cloth, ball)) == 0  # a discrete query misses the pass-through
    first, stats = dvh.continuous_collide(cloth, ball, earliest_only=True, stats=True)
    # The first contact: the ball's north pole (0, 0, 1) meets the sheet's vertex above it.
    assert len(first) == 1 and stats.earliest_toi == first["toi"][0]
    assert 1 / 6 - 1e-12 < stats.earliest_toi <= 1 / 6
    cut = start + 0.9 * stats.earliest_toi * (end - start)
    cloth.refit_motion(start, cut)
    assert len(dvh.continuous_collide(cloth, ball)) == 0


# ---------------------------------------------------------------------------------------------
# Options


def test_earliest_only_returns_the_single_earliest(moving):
    a, b = moving[:2]
    full = dvh.continuous_collide(a, b)
    first, st = dvh.continuous_collide(a, b, earliest_only=True, stats=True)
    earliest = full["toi"].min()
    assert len(first) == 1 and first["toi"][0] == earliest == st.earliest_toi
    # Of several impacts at that time, the first in the result's order.
    assert first[0] == full[full["toi"] == earliest][0]
    s, e, t = folding_sphere()
    m = dvh.Mesh(s, t)
    m.refit_motion(s, e)
    full = dvh.self_continuous_collide(m)
    first = dvh.self_continuous_collide(m, earliest_only=True, threads=1)
    assert len(first) == 1 and first[0] == full[full["toi"] == full["toi"].min()][0]


def test_max_impacts_truncates(moving):
    a, b = moving[:2]
    full = dvh.continuous_collide(a, b)
    assert len(full) > 3
    cut, st = dvh.continuous_collide(a, b, max_impacts=3, stats=True)
    assert len(cut) == 3 and st.truncated and st.impacts == 3
    assert is_sorted(cut) and rows(cut) <= rows(full)
    whole, st = dvh.continuous_collide(a, b, max_impacts=len(full) + 1, stats=True)
    assert not st.truncated and np.array_equal(whole, full)


def test_threads_give_the_same_answer():
    # A sheet falling through the crests of a waved one, and the two as one mesh: each above
    # the triangle count below which a query stays on the calling thread.
    p, t = grid(33)
    still = p.copy()
    still[:, 2] = 0.02 * np.sin(20 * p[:, 0])
    start, end = p + [0.003, 0.002, 0.05], p + [0.003, 0.002, 0.01]
    a, b = dvh.Mesh(still, t), dvh.Mesh(start, t)
    b.refit_motion(start, end)
    assert a.triangle_count + b.triangle_count >= PARALLEL_MIN_TRIANGLES
    impacts = same_on_threads(lambda k: dvh.continuous_collide(a, b, threads=k))
    assert len(impacts) > 1000 and {int(k) for k in impacts["kind"]} == {0, 1, 2}
    m = dvh.Mesh(np.vstack([still, start]), np.vstack([t, t + len(p)]))
    m.refit_motion(np.vstack([still, start]), np.vstack([still, end]))
    assert m.triangle_count >= PARALLEL_MIN_TRIANGLES
    assert len(same_on_threads(lambda k: dvh.self_continuous_collide(m, threads=k))) > 1000


def test_queries_from_several_threads_use_their_own_buffers(moving):
    a, b = moving[:2]
    want = dvh.continuous_collide(a, b)
    results = [None] * 4

    def work(i):
        for _ in range(5):
            results[i] = dvh.continuous_collide(a, b, threads=1)

    workers = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert all(np.array_equal(r, want) for r in results)


def test_result_layout_and_constants():
    assert (dvh.IMPACT_VERTEX_FACE, dvh.IMPACT_FACE_VERTEX, dvh.IMPACT_EDGE_EDGE) == (0, 1, 2)
    d = dvh.IMPACT_DTYPE
    assert d.names == ("kind", "a0", "a1", "b0", "b1", "toi") and d.itemsize == 32
    assert [d.fields[n][1] for n in d.names] == [0, 4, 8, 12, 16, 24]
    assert d["toi"] == np.float64 and all(d[n] == np.uint32 for n in d.names[:5])
    for name in ("IMPACT_DTYPE", "IMPACT_VERTEX_FACE", "IMPACT_FACE_VERTEX", "IMPACT_EDGE_EDGE"):
        assert name in dvh.__all__
    for item in (dvh.continuous_collide, dvh.self_continuous_collide, dvh.ccd_vertex_face,
                 dvh.ccd_edge_edge, dvh.CcdStats, dvh.Mesh.refit_motion):
        assert item.__name__ in dvh.__all__ + ["refit_motion"] and item.__doc__


# ---------------------------------------------------------------------------------------------
# Errors


def test_refit_motion_errors_name_the_argument_and_change_nothing(moving):
    a, b, (sa, ea, ta), _ = moving
    before = dvh.continuous_collide(a, b)
    discrete = dvh.collide(a, dvh.Mesh(sa, ta))
    with pytest.raises(ValueError, match=r"start must have shape \(n, 3\)"):
        a.refit_motion(sa[:, :2], ea)
    with pytest.raises(ValueError, match=f"end has {len(ea) - 1} vertices; the mesh has {len(ea)}"):
        a.refit_motion(sa, ea[:-1])
    with pytest.raises(TypeError, match="end must hold float64 or float32"):
        a.refit_motion(sa, ea.astype(complex))
    nan = sa * 0.5
    nan[3, 1] = np.nan
    with pytest.raises(dvh.DvhError) as e:
        a.refit_motion(nan, ea * 0.5)
    assert e.value.name == "DVH_STATUS_NON_FINITE_COORDINATE"
    assert "start positions" in e.value.message and "vertex 3" in e.value.message
    inf = ea * 0.5
    inf[5, 2] = -np.inf
    with pytest.raises(dvh.DvhError) as e:
        a.refit_motion(sa * 0.5, inf)
    assert e.value.name == "DVH_STATUS_NON_FINITE_COORDINATE" and "end positions" in e.value.message
    # The failed calls left the motion, the positions and the volumes as they were.
    assert np.array_equal(dvh.continuous_collide(a, b), before)
    assert np.array_equal(dvh.collide(a, dvh.Mesh(sa, ta)), discrete)
    a.validate()


def test_float32_motion_is_widened_exactly():
    (sa, ea, ta), (sb, eb, tb) = passing_spheres()
    sa, ea = np.round(sa * 1024) / 1024, np.round(ea * 1024) / 1024
    a64, a32, b = dvh.Mesh(sa, ta), dvh.Mesh(sa, ta), dvh.Mesh(sb, tb)
    a64.refit_motion(sa, ea)
    a32.refit_motion(sa.astype(np.float32), np.asfortranarray(ea).astype(np.float32))
    b.refit_motion(sb, eb)
    assert np.array_equal(dvh.continuous_collide(a64, b), dvh.continuous_collide(a32, b))


def test_bad_options_are_python_errors(moving):
    a, b = moving[:2]
    with pytest.raises(ValueError, match="mode must be one of"):
        dvh.continuous_collide(a, b, mode="triangles")
    with pytest.raises(ValueError, match="mode must be one of"):
        dvh.self_continuous_collide(a, mode="EXACT")
    with pytest.raises(TypeError, match="mode must be a string"):
        dvh.continuous_collide(a, b, mode=1)
    with pytest.raises(ValueError, match="threads must be in"):
        dvh.continuous_collide(a, b, threads=-1)
    with pytest.raises(TypeError, match="threads must be an integer"):
        dvh.continuous_collide(a, b, threads=True)
    with pytest.raises(ValueError, match="max_impacts must be None"):
        dvh.continuous_collide(a, b, max_impacts=0)
    with pytest.raises(ValueError, match="max_impacts must be None"):
        dvh.self_continuous_collide(a, max_impacts=-2)
    with pytest.raises(TypeError, match="max_impacts must be None or an integer"):
        dvh.continuous_collide(a, b, max_impacts=2.0)
    with pytest.raises(TypeError, match="earliest_only must be a bool"):
        dvh.continuous_collide(a, b, earliest_only=1)
    with pytest.raises(TypeError, match="must be a dvh.Mesh"):
        dvh.continuous_collide(a, np.zeros((3, 3)))
    with pytest.raises(TypeError):
        dvh.continuous_collide(a, b, "exact")  # the options are keyword-only
    # Checked option sets are kept; look-alike values must still be checked, and numpy
    # integers and bools accepted.
    want = dvh.continuous_collide(a, b, max_impacts=2)
    assert np.array_equal(dvh.continuous_collide(a, b, max_impacts=np.uint64(2)), want)
    assert len(dvh.continuous_collide(a, b, earliest_only=np.bool_(True))) == 1
