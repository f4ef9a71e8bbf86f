"""Scenes over a step from Python: self-contact, motions, continuous collision and stencils, each
equal to the pairwise and self queries on stand-alone meshes holding the same world positions."""

import numpy as np
import pytest

import dvh


def icosphere(level=2):
    t = (1 + 5 ** 0.5) / 2
    V = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t],
         [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    F = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(level):
        mid = {}

        def m(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                v = V[a] + V[b]
                V.append(v / np.linalg.norm(v))
                mid[key] = len(V) - 1
            return mid[key]

        nf = []
        for a, b, c in F:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        F = nf
    return np.array(V), np.array(F, dtype=np.uint32)


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def pose(R, t):
    P = np.eye(4)
    P[:3, :3], P[:3, 3] = R, t
    return P


def placed(V, P):
    """`V` placed by `P`, as the library places a vertex: ((R0 x + R1 y) + R2 z) + t, row by row."""
    R, t = P[:3, :3], P[:3, 3]
    out = np.empty_like(V)
    for i in range(3):
        out[:, i] = ((R[i, 0] * V[:, 0] + R[i, 1] * V[:, 1]) + R[i, 2] * V[:, 2]) + t[i]
    return out


def dent(V, amount, seed):
    """A smooth bump pushed into the sphere, so that it passes through itself."""
    rng = np.random.default_rng(seed)
    k = rng.normal(size=3)
    k /= np.linalg.norm(k)
    w = np.exp(-8.0 * (1.0 - V @ k)) * amount
    return V - w[:, None] * k


@pytest.fixture(scope="module")
def world():
    """A scene of four objects over one step: a rigid ball turning a little, a rigid ball
    standing still, and two soft balls (one denting itself, self-contact on) moving through
    the others; and the same objects as stand-alone meshes."""
    V, F = icosphere(2)
    mesh = dvh.Mesh(V, F)
    scene = dvh.Scene()
    p0 = pose(rotation([1, 2, 3], 0.4), [0.0, 0.0, 0.0])
    p1 = pose(rotation([1, 2, 3], 0.5), [0.1, 0.05, 0.0])
    turning = scene.add_rigid(mesh, p0)
    scene.set_pose_motion(turning, p0, p1)
    still_pose = pose(rotation([0, 1, 1], 1.0), [1.7, 0.3, 0.2])
    still = scene.add_rigid(mesh, still_pose)
    s0 = V + [2.2, -0.4, 0.1]
    s1 = dent(V, 2.5, 5) + [0.9, -0.1, 0.0]
    soft = scene.add_deformable(dvh.Mesh(s0, F))
    scene.set_motion(soft, s0, s1)
    scene.set_self_contact(soft, True)
    g0 = V * 0.8 + [-1.5, 0.2, 0.0]
    g1 = V * 0.8 + [-0.6, 0.1, 0.05]
    glide = scene.add_deformable(dvh.Mesh(g0, F))
    scene.set_motion(glide, g0, g1)
    # Stand-alone meshes holding the world positions and motions.
    alone = {}
    for obj, (a, b) in {
        turning: (placed(V, p0), placed(V, p1)),
        still: (placed(V, still_pose), placed(V, still_pose)),
        soft: (s0, s1),
        glide: (g0, g1),
    }.items():
        m = dvh.Mesh(b, F)
        if not np.array_equal(a, b):
            m.refit_motion(a, b)
        alone[obj] = m
    return scene, alone, {soft}


def pairwise(alone, selfish, query_pair, query_self, dtype):
    """What the pairwise and self queries give, in the scene's order."""
    rows = []
    ids = sorted(alone)
    for i in ids:
        if i in selfish:
            r = query_self(alone[i])
            rows += [(i, i, r)]
        for j in ids:
            if j > i:
                rows += [(i, j, query_pair(alone[i], alone[j]))]
    out = np.zeros(sum(len(r) for _, _, r in rows), dtype=dtype)
    k = 0
    for i, j, r in rows:
        out["object_a"][k:k + len(r)] = i
        out["object_b"][k:k + len(r)] = j
        for name in r.dtype.names:
            out[name][k:k + len(r)] = r[name]
        k += len(r)
    return out


@pytest.mark.parametrize("threads", [0, 1])
def test_scene_impacts_equal_pairwise_and_self_impacts(world, threads):
    scene, alone, selfish = world
    expected = pairwise(
        alone, selfish,
        lambda a, b: dvh.continuous_collide(a, b, threads=threads),
        lambda a: dvh.self_continuous_collide(a, threads=threads),
        dvh.SCENE_IMPACT_DTYPE,
    )
    got, st = scene.continuous_collide(threads=threads, stats=True)
    assert got.dtype == dvh.SCENE_IMPACT_DTYPE
    assert np.array_equal(got, expected)
    assert st.impacts == len(expected)
    # Not vacuous: impacts between objects and within the self-contact object.
    assert (got["object_a"] != got["object_b"]).any() and (got["object_a"] == got["object_b"]).any()
    first = scene.continuous_collide(threads=threads, earliest_only=True)
    assert len(first) == 1
    k = int(np.argmin(expected["toi"]))  # the first of the earliest in order
    assert first[0] == expected[k]


@pytest.mark.parametrize("distance", [0.0, 0.02, 0.1])
def test_scene_stencils_equal_pairwise_and_self_stencils(world, distance):
    scene, alone, selfish = world
    expected = pairwise(
        alone, selfish,
        lambda a, b: dvh.nearest_features(a, b, distance),
        lambda a: dvh.self_nearest_features(a, distance),
        dvh.SCENE_NEAR_PAIR_DTYPE,
    )
    got, st = scene.nearest_features(distance, stats=True)
    assert got.dtype == dvh.SCENE_NEAR_PAIR_DTYPE
    # Byte for byte (the stencils' padding is written as zero).
    assert got.tobytes() == expected.tobytes()
    assert st.pairs == len(expected)
    if distance > 0.05:
        assert len(got) > 0


def test_self_contact_adds_the_object_with_itself(world):
    scene, alone, selfish = world
    (soft,) = selfish
    contacts = scene.collide()
    mine = contacts[(contacts["object_a"] == soft) & (contacts["object_b"] == soft)]
    assert len(mine) > 0, "the dented ball passes through itself"
    assert np.array_equal(np.column_stack([mine["a"], mine["b"]]), dvh.self_collide(alone[soft]))
    scene.set_self_contact(soft, False)
    try:
        contacts = scene.collide()
        assert not ((contacts["object_a"] == soft) & (contacts["object_b"] == soft)).any()
    finally:
        scene.set_self_contact(soft, True)


def test_errors_name_what_was_wrong_and_change_nothing(world):
    scene, alone, selfish = world
    before = (scene.continuous_collide(), scene.nearest_features(0.1), scene.collide())
    V, _ = icosphere(2)
    (soft,) = selfish
    with pytest.raises(dvh.DvhError, match="rigid"):
        scene.set_self_contact(0, True)
    scene.set_self_contact(0, False)
    with pytest.raises(dvh.DvhError, match="object 0"):
        scene.set_motion(0, V, V)
    with pytest.raises(dvh.DvhError, match=f"object {soft}"):
        scene.set_pose_motion(soft, np.eye(4), np.eye(4))
    bad = V.copy()
    bad[3, 1] = np.nan
    with pytest.raises(dvh.DvhError, match="vertex 3"):
        scene.set_motion(soft, V, bad)
    with pytest.raises(ValueError, match="start"):
        scene.set_motion(soft, V[:-1], V)
    with pytest.raises(dvh.DvhError):
        scene.set_pose_motion(0, None, pose(np.eye(3), [1e301, 0, 0]))
    with pytest.raises(dvh.DvhError):
        scene.nearest_features(-1.0)
    after = (scene.continuous_collide(), scene.nearest_features(0.1), scene.collide())
    for x, y in zip(before, after):
        assert np.array_equal(x, y)
