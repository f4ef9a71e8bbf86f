"""The Python package against brute force on small meshes, its thread counts on larger ones, its
errors, its array handling and the GIL."""

import ctypes
import glob
import os
import threading
import time

import numpy as np
import pytest

import dvh
from dvh import _api
from conftest import (
    PARALLEL_MIN_TRIANGLES,
    PARALLEL_SORT_MIN_PAIRS,
    REFIT_PARALLEL_MIN_RINGS,
    brute_collide,
    exact_pose,
    grid,
    posed,
    same_on_threads,
    soup,
    triangle_distance,
    two_cores,
    uv_sphere,
)


def as_set(pairs):
    return {tuple(map(int, p)) for p in pairs}


def sorted_pairs(pairs):
    return pairs.shape == (len(pairs), 2) and (
        len(pairs) < 2 or bool(np.all(np.lexsort((pairs[:, 1], pairs[:, 0])) == np.arange(len(pairs))))
    )


# ---------------------------------------------------------------------------------------------
# Queries against brute force


@pytest.mark.parametrize("volume", ["aabb", "dvh", "sbv"])
@pytest.mark.parametrize("tree", ["octree", "binary"])
def test_collide_matches_brute_force(volume, tree):
    pa, ta = soup(60, seed=1)
    pb, tb = soup(60, seed=2)
    a = dvh.Mesh(pa, ta, volume=volume, tree=tree)
    b = dvh.Mesh(pb, tb, volume=volume, tree=tree)
    for k in range(3):
        pose_a, pose_b = (None, None) if k == 0 else (exact_pose(k), exact_pose(10 + k))
        got = dvh.collide(a, b, pose_a=pose_a, pose_b=pose_b)
        want = brute_collide(dvh, posed(pa, pose_a), ta, posed(pb, pose_b), tb)
        assert got.dtype == np.uint32 and sorted_pairs(got)
        assert as_set(got) == as_set(want)
        assert len(want) > 0


def test_collide_after_refit_matches_brute_force():
    pa, ta = uv_sphere(10)
    pb, tb = uv_sphere(9, centre=(2.5, 0.0, 0.0))
    a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)
    assert len(dvh.collide(a, b)) == 0
    rng = np.random.default_rng(3)
    for step in range(1, 4):
        moved = pa * (1 + 0.2 * step) + rng.normal(0, 0.02, pa.shape)
        a.refit(moved)
        got = dvh.collide(a, b)
        assert as_set(got) == as_set(brute_collide(dvh, moved, ta, pb, tb))
    assert len(got) > 0


def test_self_collide_matches_brute_force_on_pairs_sharing_no_vertex():
    p, t = soup(80, seed=4)
    m = dvh.Mesh(p, t)
    got = dvh.self_collide(m)
    want = {(i, j) for i, j in as_set(brute_collide(dvh, p, t, p, t)) if i < j}
    assert sorted_pairs(got) and as_set(got) == want and want


def test_self_collide_of_a_closed_sphere_and_a_folded_one():
    p, t = uv_sphere(12)
    m = dvh.Mesh(p, t)
    assert len(dvh.self_collide(m)) == 0
    folded = p.copy()
    folded[:, 2] = np.abs(folded[:, 2]) * -1.5 + 0.2  # the north half pushed through the south
    m.refit(folded)
    got = dvh.self_collide(m)
    shares = lambda i, j: len(set(t[i]) & set(t[j])) > 0  # noqa: E731
    far = {(i, j) for i, j in as_set(brute_collide(dvh, folded, t, folded, t)) if i < j and not shares(i, j)}
    assert far and far <= as_set(got)


def test_proximity_matches_brute_force():
    pa, ta = soup(40, seed=5)
    pb, tb = soup(40, seed=6)
    pb = pb + [0.9, 0.0, 0.0]
    a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)
    for d in (0.0, 0.05, 0.2):
        got = as_set(dvh.proximity(a, b, d))
        for i in range(len(ta)):
            for j in range(len(tb)):
                dist = triangle_distance(dvh, pa[ta[i]], pb[tb[j]])
                # The library decides exactly; the float oracle is trusted away from the boundary.
                if dist < d - 1e-9 or (d == 0 and dist == 0):
                    assert (i, j) in got, (i, j, dist)
                elif dist > d + 1e-9:
                    assert (i, j) not in got, (i, j, dist)
    assert len(dvh.proximity(a, b, 0.2)) > len(dvh.proximity(a, b, 0.05))


def test_self_proximity_matches_brute_force():
    p, t = grid(6)
    q = p.copy()
    q[:, 2] = 0.08 * np.sin(6 * q[:, 0])
    sheet = np.vstack([q, q + [0.0, 0.0, 0.1]])
    tris = np.vstack([t, t + len(q)])
    m = dvh.Mesh(sheet, tris)
    d = 0.12
    got = as_set(dvh.self_proximity(m, d))
    for i in range(len(tris)):
        for j in range(i + 1, len(tris)):
            if set(tris[i]) & set(tris[j]):
                assert (i, j) not in got
                continue
            dist = triangle_distance(dvh, sheet[tris[i]], sheet[tris[j]])
            if dist < d - 1e-9:
                assert (i, j) in got
            elif dist > d + 1e-9:
                assert (i, j) not in got
    assert got


def test_modes_and_limits():
    pa, ta = soup(100, seed=7)
    pb, tb = soup(100, seed=8)
    a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)
    full, st = dvh.collide(a, b, stats=True)
    assert st.pairs == len(full) and not st.truncated and st.bv_tests > 0
    first = dvh.collide(a, b, mode="first_hit")
    assert len(first) == 1 and as_set(first) <= as_set(full)
    cut, st = dvh.collide(a, b, max_pairs=3, stats=True)
    assert len(cut) == 3 and st.truncated and as_set(cut) <= as_set(full)
    for mode, extra in (("leaves", {}), ("depth", {"max_depth": 1}), ("budget", {"budget": 20})):
        nodes = dvh.collide(a, b, mode=mode, **extra)
        covered = {
            (int(i), int(j))
            for na, nb in nodes
            for i in a.node_triangles(na)
            for j in b.node_triangles(nb)
        }
        assert as_set(full) <= covered, mode


def wavy_sheets(n):
    """A flat n x n sheet and a waved copy through it (2 n^2 triangles each): their
    intersections run along many curves."""
    p, t = grid(n)
    q = p.copy()
    q[:, 2] = 0.02 * np.sin(40 * q[:, 0]) * np.cos(40 * q[:, 1])
    return (p, t), (q, t)


def test_threads_give_the_same_answer():
    (pa, ta), (pb, tb) = wavy_sheets(48)
    a, b = dvh.Mesh(pa, ta), dvh.Mesh(pb, tb)
    assert a.triangle_count + b.triangle_count >= PARALLEL_MIN_TRIANGLES
    assert len(same_on_threads(lambda k: dvh.collide(a, b, threads=k))) > 1000
    pose = exact_pose(4)
    pose[:3, 3] = 0.0  # turned about the origin: still through the other sheet
    assert len(same_on_threads(lambda k: dvh.collide(a, b, pose_b=pose, threads=k))) > 100
    assert len(same_on_threads(lambda k: dvh.proximity(a, b, 0.003, threads=k))) > 10_000
    both = dvh.Mesh(np.vstack([pa, pb]), np.vstack([ta, tb + len(pa)]))
    assert len(same_on_threads(lambda k: dvh.self_collide(both, threads=k))) > 1000
    assert len(same_on_threads(lambda k: dvh.self_proximity(both, 0.003, threads=k))) > 10_000
    # A sheet against itself: each triangle touches the triangles around it, enough pairs for
    # the sort to be shared too.
    m = dvh.Mesh(*grid(100))
    assert len(same_on_threads(lambda k: dvh.collide(m, m, threads=k))) >= PARALLEL_SORT_MIN_PAIRS


def test_refit_threads_give_the_same_volumes():
    p, t = grid(180)
    q = p.copy()
    q[:, 2] = 0.01 * np.sin(30 * q[:, 0])
    one, every = dvh.Mesh(p, t, refit_threads=1), dvh.Mesh(p, t)
    assert one.tree_stats().rings >= REFIT_PARALLEL_MIN_RINGS
    other = dvh.Mesh(*wavy_sheets(16)[1])
    shares = []
    for step in range(3):
        moved = q * [1.0, 1.0, 1.0 + step]
        one.refit(moved)
        p0, t0 = time.process_time(), time.thread_time()
        every.refit(moved)
        calling = time.thread_time() - t0
        shares.append(1 - calling / max(time.process_time() - p0, 1e-9))
        assert one.last_refit_stats() == every.last_refit_stats()
        # Equal volumes: the same volume tests, one by one, in a query on one thread.
        got = [dvh.collide(m, other, threads=1, stats=True) for m in (one, every)]
        assert np.array_equal(got[0][0], got[1][0]) and got[0][1] == got[1][1]
        assert len(got[0][0]) > 0 and got[0][1].bv_tests > 1000
    if two_cores():
        assert max(shares) > 0.2, f"no second thread took part in the refits: {shares}"


def test_mesh_introspection():
    p, t = uv_sphere(8)
    m = dvh.Mesh(p, t, volume="dvh", tree="binary", radius="wrapped", leftovers="extra_rings")
    assert (m.vertex_count, m.triangle_count) == (len(p), len(t))
    ts = m.tree_stats()
    assert ts.triangles == len(t) and ts.rings >= 1 and ts.levels >= 2
    assert m.node_count == ts.rings + ts.inner_nodes
    assert sorted(m.node_triangles(0).tolist()) == list(range(len(t)))
    m.refit(p * 1.1)
    assert m.last_refit_stats().nodes_refit == m.node_count
    m.validate()
    r = dvh.Mesh(p, t, rigid=True)
    assert r.tree_stats().triangles == len(t)


# ---------------------------------------------------------------------------------------------
# Scenes


def test_scene_matches_pairwise_queries():
    shapes = [uv_sphere(8), uv_sphere(7, radius=0.8), grid(5, size=2.0)]
    meshes = [dvh.Mesh(p, t) for p, t in shapes]
    scene = dvh.Scene()
    poses = [exact_pose(s) for s in range(3)]
    ids = [scene.add_rigid(meshes[0], poses[0]), scene.add_rigid(meshes[1], poses[1])]
    ids.append(scene.add_deformable(meshes[2]))
    contacts, st = scene.collide(stats=True)
    assert contacts.dtype == dvh.CONTACT_DTYPE and st.objects == 3
    want = set()
    placed = [poses[0], poses[1], None]
    for x in range(3):
        for y in range(x + 1, 3):
            for i, j in dvh.collide(meshes[x], meshes[y], pose_a=placed[x], pose_b=placed[y]):
                want.add((ids[x], ids[y], int(i), int(j)))
    assert {tuple(map(int, c)) for c in contacts} == want and want
    # Move the sheet away and the second sphere; exclude a pair.
    p, t = shapes[2]
    scene.set_positions(ids[2], (p + [10.0, 0.0, 0.0]).astype(np.float32))
    scene.set_pose(ids[1], None)
    scene.exclude_pair(ids[0], ids[1])
    assert len(scene.collide()) == 0
    scene.remove(ids[2])
    with pytest.raises(dvh.DvhError):
        scene.set_positions(ids[2], p)
    scene.set_lazy_refit(True)
    assert len(scene.collide(threads=1)) == 0


def test_scene_threads_give_the_same_contacts():
    # Deformable sheets, each waved through the others: the refits and the object pairs are
    # shared among the threads; then one pair alone, large enough to be split itself.
    (p, t), (q, _) = wavy_sheets(34)
    scene = dvh.Scene()
    ids = [scene.add_deformable(dvh.Mesh(p, t)) for _ in range(4)]

    def frame(k, threads):
        for i, obj in enumerate(ids):
            scene.set_positions(obj, q * [1.0, 1.0, 1.0 + 0.5 * i] + [0.0, 0.0, 0.004 * (i - k)])
        return scene.collide(threads=threads)

    for k in range(2):
        contacts = same_on_threads(lambda threads: frame(k, threads))
        assert {(int(x), int(y)) for x, y, _, _ in contacts} == {(i, j) for i in ids for j in ids if i < j}
    for obj in ids[2:]:
        scene.remove(obj)
    del ids[2:]
    assert 2 * len(t) >= PARALLEL_MIN_TRIANGLES
    assert len(same_on_threads(lambda threads: frame(0, threads))) > 1000


# ---------------------------------------------------------------------------------------------
# Results held


def _fields(x):
    """An array's values, field by field (a structured array's padding bytes are not values)."""
    names = x.dtype.names or (None,)
    return [x if n is None else x[n] for n in names]


def _same(x, y):
    return x.dtype == y.dtype and all(np.array_equal(u, v) for u, v in zip(_fields(x), _fields(y)))


KINDS = ["pairs", "stencils", "impacts", "contacts"]


def querying(kind):
    """A query of this kind of result, ``query(k)``, and the library-buffer set it uses. Two
    sheets, the top one tilted through the bottom one, lower at each step ``k``: every query finds
    something, and something different."""
    p, t = grid(8)
    top = lambda k: p * [1.0, 1.0, 0.0] + np.c_[0 * p[:, :2], 0.06 - 0.01 * k - 0.12 * p[:, 0]]  # noqa: E731
    m = dvh.Mesh(np.vstack([p, p + [0.0, 0.0, 0.05]]), np.vstack([t, t + len(p)]))
    scene = dvh.Scene()
    ids = [scene.add_deformable(dvh.Mesh(p, t)), scene.add_deformable(dvh.Mesh(p, t))]

    def query(k):
        if kind == "contacts":
            scene.set_positions(ids[1], top(k))
            return scene.collide()
        if kind == "impacts":
            m.refit(np.vstack([p, p + [0.0, 0.0, 0.05]]))
        m.refit(np.vstack([p, top(k)]))
        if kind == "pairs":
            return dvh.self_proximity(m, 0.01)
        if kind == "stencils":
            return dvh.self_nearest_features(m, 0.01)
        return dvh.self_continuous_collide(m)

    buffers = {
        "pairs": lambda: _api._buffers.pairs,
        "stencils": lambda: _api._buffers.near_pairs,
        "impacts": lambda: _api._buffers.impacts,
        "contacts": lambda: scene._contacts,
    }[kind]
    return query, buffers


@pytest.mark.parametrize("kind", KINDS)
def test_results_held_while_later_queries_run_keep_their_values(kind):
    # Results are views of the library's buffers, a buffer reused only once no array views it,
    # and copied out once two are held: six results held at once cover both ways.
    query, _ = querying(kind)
    held, copies = [], []
    for k in range(6):
        r = query(k)
        assert len(r) > 0 and r.flags.writeable
        held.append(r)
        copies.append(r.copy())
        # A result dropped at once gives its buffer back for the next query.
        query(k)
    assert len({b"".join(f.tobytes() for f in _fields(c)) for c in copies}) == len(copies)
    assert all(_same(r, c) for r, c in zip(held, copies))
    # Each is the same result as a query asked for alone.
    for k in range(6):
        assert _same(query(k), copies[k])
        assert _same(held[k], copies[k])


def _library_memory(results):
    """Byte arrays over the items of each of a result kind's library buffers (the lendable ones,
    then the one copied out of), made without a copy and holding no reference to them."""
    bufs = [slot[0] for slot in results._lendable]
    if results._copying is not None:
        bufs.append(results._copying[0])
    out = []
    for buf in bufs:
        n = results._len(buf) * results._itemsize
        data = _api.ffi.buffer(results._data(buf), n) if n else b""
        out.append(np.frombuffer(data, dtype=np.uint8))
    return out


def _lender(x):
    """The object at the end of an array's chain of bases."""
    while isinstance(x, np.ndarray) and x.base is not None:
        x = x.base
    return x


def _viewed(result, memory):
    """The index of the library buffer whose items the result views, whole; None if it views
    none of them."""
    hits = [i for i, mem in enumerate(memory) if np.shares_memory(result, mem)]
    if not hits:
        return None
    (i,) = hits
    assert result.ctypes.data == memory[i].ctypes.data and result.nbytes == memory[i].nbytes
    return i


def _bytes(x):
    return x.reshape(-1).view(np.uint8)


def _on_a_new_thread(f):
    """Runs `f` on a thread of its own, which starts with no result buffers (they are per
    thread), and raises what it raised."""
    raised = []

    def run():
        try:
            f()
        except BaseException as e:  # re-raised on the test's thread
            raised.append(e)

    t = threading.Thread(target=run)
    t.start()
    t.join()
    if raised:
        raise raised[0]


@pytest.mark.parametrize("kind", KINDS)
def test_two_held_results_view_the_library_buffers_and_a_third_is_copied(kind):
    _on_a_new_thread(lambda: _two_lent_then_copied(kind))


def _two_lent_then_copied(kind):
    query, buffers = querying(kind)
    first, second = query(0), query(1)
    memory = _library_memory(buffers())
    assert isinstance(_lender(first), _api._Lent) and isinstance(_lender(second), _api._Lent)
    assert {_viewed(first, memory), _viewed(second, memory)} == {0, 1}
    third = query(2)
    memory = _library_memory(buffers())
    assert len(memory) == 3  # two lent, one copied out of
    assert _viewed(third, memory) is None and isinstance(_lender(third), np.ndarray)
    assert np.array_equal(_bytes(third), memory[2])
    assert _same(third, query(2)) and not _same(third, second)
    # A buffer is queried into again once nothing views it, and not before: a view of a part
    # of a result holds the whole buffer.
    first_at, second_at = _viewed(first, memory), _viewed(second, memory)
    part = second[1:]
    del first, second, third
    again = query(3)
    memory = _library_memory(buffers())
    assert _viewed(again, memory) == first_at and isinstance(_lender(again), _api._Lent)
    assert np.shares_memory(part, memory[second_at])
    held = query(4)  # both lent buffers are viewed: copied
    assert _viewed(held, _library_memory(buffers())) is None
    assert isinstance(_lender(held), np.ndarray)


# ---------------------------------------------------------------------------------------------
# Arrays in and errors


def test_float32_strided_and_uint16_inputs_give_the_same_answers():
    pa, ta = soup(50, seed=9)
    pb, tb = soup(50, seed=10)
    # Coordinates that float32 holds exactly, so both precisions describe the same meshes.
    pa, pb = np.round(pa * 1024) / 1024, np.round(pb * 1024) / 1024
    want = dvh.collide(dvh.Mesh(pa, ta), dvh.Mesh(pb, tb))
    wide = np.zeros((len(pa), 4), dtype=np.float32)
    wide[:, :3] = pa
    a32 = dvh.Mesh(wide[:, :3], ta.astype(np.uint32))  # a strided view, read in place
    b16 = dvh.Mesh(pb, tb.astype(np.uint16))
    bf = dvh.Mesh(np.asfortranarray(pb), tb.tolist())  # Fortran order and lists are copied
    assert np.array_equal(dvh.collide(a32, b16), want)
    assert np.array_equal(dvh.collide(a32, bf), want)
    a32.refit(wide[:, :3])
    assert np.array_equal(dvh.collide(a32, b16), want)


def test_bad_arrays_are_python_errors_before_any_call():
    p, t = uv_sphere(6)
    with pytest.raises(ValueError, match=r"positions must have shape \(n, 3\)"):
        dvh.Mesh(p[:, :2], t)
    with pytest.raises(ValueError, match=r"triangles must have shape \(m, 3\)"):
        dvh.Mesh(p, t[:, :2])
    with pytest.raises(TypeError, match="triangles must hold integers"):
        dvh.Mesh(p, t.astype(float))
    with pytest.raises(TypeError, match="positions must hold float64 or float32"):
        dvh.Mesh(p.astype(complex), t)
    bad = t.copy()
    bad[5, 1] = -1
    with pytest.raises(ValueError, match=r"triangle 5 has a negative vertex index"):
        dvh.Mesh(p, bad)
    with pytest.raises(ValueError, match="must be one of"):
        dvh.Mesh(p, t, volume="obb")
    m = dvh.Mesh(p, t)
    with pytest.raises(ValueError, match=f"has {len(p) - 1} vertices; the mesh has {len(p)}"):
        m.refit(p[:-1])
    with pytest.raises(TypeError, match="must be a dvh.Mesh"):
        dvh.collide(m, p)
    with pytest.raises(ValueError, match="4x4 or 3x4"):
        dvh.collide(m, m, pose_a=np.eye(3))
    with pytest.raises(ValueError, match="mode must be one of"):
        dvh.collide(m, m, mode="fast")
    with pytest.raises(ValueError, match="max_pairs must be in"):
        dvh.collide(m, m, max_pairs=-1)
    # Option sets are checked once and kept; look-alike values must still be checked.
    assert np.array_equal(dvh.collide(m, m, threads=1), dvh.collide(m, m, threads=np.int64(1)))
    with pytest.raises(TypeError, match="threads must be an integer"):
        dvh.collide(m, m, threads=True)
    with pytest.raises(TypeError, match="threads must be an integer"):
        dvh.collide(m, m, threads=1.0)
    with pytest.raises(TypeError):
        dvh.collide(m, m, mode=["triangles"])


def test_library_errors_carry_status_and_message_and_change_nothing():
    p, t = uv_sphere(6)
    bad = t.copy()
    bad[3, 2] = len(p) + 7
    with pytest.raises(dvh.DvhError) as e:
        dvh.Mesh(p, bad)
    assert e.value.status == 4 and e.value.name == "DVH_STATUS_INDEX_OUT_OF_RANGE"
    assert "triangle 3" in e.value.message and str(len(p) + 7) in e.value.message
    a = dvh.Mesh(p, t)
    b = dvh.Mesh(p + [1.5, 0, 0], t)
    before = dvh.collide(a, b)
    nan = p * 2.0
    nan[4, 1] = np.nan
    with pytest.raises(dvh.DvhError) as e:
        a.refit(nan)
    assert e.value.name == "DVH_STATUS_NON_FINITE_COORDINATE" and "vertex 4" in e.value.message
    assert np.array_equal(dvh.collide(a, b), before)  # the failed refit left the mesh as it was
    shear = np.eye(4)
    shear[0, 1] = 0.5
    with pytest.raises(dvh.DvhError) as e:
        dvh.collide(a, b, pose_a=shear)
    assert e.value.name == "DVH_STATUS_NON_RIGID_POSE"
    with pytest.raises(dvh.DvhError) as e:
        dvh.proximity(a, b, -1.0)
    assert e.value.name == "DVH_STATUS_INVALID_ARGUMENT"
    with pytest.raises(dvh.DvhError):
        a.node_triangles(a.node_count)


def _turns(seconds):
    """A pure-Python loop, which needs the GIL to turn, run for `seconds`: its turns, and the
    share of the time it stood still in stretches of over 20 ms (another thread keeping the GIL;
    a busy machine's scheduler seldom stops a thread that long)."""
    turns, stalled = 0, 0.0
    now = start = time.perf_counter()
    end = start + seconds
    while now < end:
        last, now = now, time.perf_counter()
        if now - last > 0.02:
            stalled += now - last
        turns += 1
    return turns, stalled / (now - start)


def _turns_beside(work, seconds):
    """`_turns` while another thread calls `work` over and over."""
    started, stop = threading.Event(), threading.Event()

    def loop():
        started.set()
        while not stop.is_set():
            work()

    worker = threading.Thread(target=loop)
    worker.start()
    started.wait()
    try:
        return _turns(seconds)
    finally:
        stop.set()
        worker.join()


def spinning_beside(works, rounds=3, seconds=0.2):
    """For each of `works`, the loop's rate beside it over its rate alone, and the share of the
    time it stood still beside it: medians over `rounds`. A round takes its windows back to back,
    so that they see about the same load on the machine."""
    rates, stalls = [[] for _ in works], [[] for _ in works]
    for _ in range(rounds):
        alone, _ = _turns(seconds)
        for rate, stall, work in zip(rates, stalls, works):
            turns, stalled = _turns_beside(work, seconds)
            rate.append(turns / max(alone, 1))
            stall.append(stalled)
    median = lambda x: sorted(x)[len(x) // 2]  # noqa: E731
    return [(median(r), median(s)) for r, s in zip(rates, stalls)]


def _holding_the_gil(name, argtypes):
    """The library's C function `name` called through ctypes.PyDLL, which keeps the GIL for the
    call: the control of what a layer that held it would do to the loop."""
    folder = os.path.dirname(dvh._dvh.__file__)
    (path,) = [f for f in glob.glob(os.path.join(folder, "*")) if f.endswith((".so", ".dylib", ".dll"))]
    f = getattr(ctypes.PyDLL(path), name)
    f.argtypes, f.restype = argtypes, ctypes.c_int
    return f


def test_queries_release_the_gil():
    # Calls of 60 ms or more, against the 20 ms stand-still the loop is watched for: a sheet
    # falling onto a waved one, as one mesh, continuous collision (its time grows evenly with
    # the triangles), as fine as this machine needs.
    n = 16
    while True:
        p, t = grid(n)
        still = p.copy()
        still[:, 2] = 0.02 * np.sin(20 * p[:, 0])
        start, end = p + [0.003, 0.002, 0.05], p + [0.003, 0.002, 0.01]
        m = dvh.Mesh(np.vstack([still, start]), np.vstack([t, t + len(p)]))
        m.refit_motion(np.vstack([still, start]), np.vstack([still, end]))
        assert len(dvh.self_continuous_collide(m, threads=1)) > 100
        begun = time.perf_counter()  # the second call: the first also grows the buffers
        dvh.self_continuous_collide(m, threads=1)
        if time.perf_counter() - begun > 0.06 or n >= 100:
            break
        n = int(n * 1.2) + 1
    # Beside calls that release the GIL, the loop keeps a good part of its rate (about half
    # where the two threads share a core) and never stands still for long; beside calls that
    # keep it, it turns only between them. The same calls made through ctypes.PyDLL, which keeps
    # the GIL, are the control that the measure tells the two apart on this machine.
    held = _holding_the_gil("dvh_self_continuous_collide", [ctypes.c_void_p] * 4)
    address = lambda c: int(_api.ffi.cast("uintptr_t", c))  # noqa: E731
    options = _api._ccd_options("exact", 1, None, False)
    impacts = _api.ffi.gc(_api.lib.dvh_impacts_new(), _api.lib.dvh_impacts_free)
    args = (address(m._ptr), address(options), address(impacts), None)
    (rate, stalled), (kept_rate, kept_stalled) = spinning_beside(
        [lambda: dvh.self_continuous_collide(m, threads=1), lambda: held(*args)]
    )
    assert _api.lib.dvh_impacts_len(impacts) > 100  # the control did the same work
    assert kept_stalled > 0.6, (kept_rate, kept_stalled)
    assert rate > 0.25 and stalled < 0.4, (rate, stalled)


def test_version_and_package_metadata():
    assert dvh.version() == dvh.__version__ and dvh.__version__.count(".") == 2


def test_scene_groups_and_masks_filter_pairs():
    p, t = uv_sphere(6)
    m = dvh.Mesh(p, t)
    scene = dvh.Scene()
    a = scene.add_deformable(m)  # group 1, every group in its mask
    b = scene.add_rigid(m, exact_pose(1), group=2, mask=2)  # ignores group 1
    c = scene.add_rigid(m, exact_pose(2), group=4)
    objects = {(int(x), int(y)) for x, y, _, _ in scene.collide()}
    # a-b: b's mask ignores group 1; b-c: b's mask ignores group 4; a-c: both allow, and touch.
    assert objects == {(a, c)}
    # Without the filters every pair touches: the masks are what kept a-b and b-c out.
    every = dvh.Scene()
    ids = [every.add_deformable(m), every.add_rigid(m, exact_pose(1)), every.add_rigid(m, exact_pose(2))]
    assert ids == [a, b, c]
    assert {(int(x), int(y)) for x, y, _, _ in every.collide()} == {(a, b), (a, c), (b, c)}
