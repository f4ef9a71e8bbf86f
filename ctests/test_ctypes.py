"""Calls dvh from Python through ctypes, with nothing but the header's contract: builds two
meshes, collides them, reads the pairs and counters, refits, queries a scene of them, and checks
error paths.

The library path comes from DVH_LIBRARY (default: target/release/libdvh.so)."""

import ctypes
import math
import os
import sys

lib = ctypes.CDLL(os.environ.get("DVH_LIBRARY", os.path.join(os.path.dirname(__file__), "..", "target", "release", "libdvh.so")))

DvhStatus = ctypes.c_uint32
DVH_STATUS_OK, DVH_STATUS_NULL_ARGUMENT, DVH_STATUS_INVALID_ARGUMENT = 0, 1, 2
DVH_STATUS_INDEX_OUT_OF_RANGE, DVH_STATUS_NON_RIGID_POSE = 4, 5
DVH_STATUS_NON_FINITE_COORDINATE = 3
DVH_STATUS_NOT_CLOSED = 11
DVH_QUERY_MODE_LEAVES, DVH_QUERY_MODE_BUDGET = 2, 4
DVH_VOLUME_KIND_DVH, DVH_VOLUME_KIND_SBV, DVH_VOLUME_KIND_AABB = 0, 1, 2
DVH_PAIR_KIND_NODES = 1


class DvhPair(ctypes.Structure):
    _fields_ = [("a", ctypes.c_uint32), ("b", ctypes.c_uint32)]


class DvhPose(ctypes.Structure):
    _fields_ = [("rotation", ctypes.c_double * 9), ("translation", ctypes.c_double * 3)]


class DvhBuildOptions(ctypes.Structure):
    _fields_ = [("tree", ctypes.c_uint32), ("radius", ctypes.c_uint32), ("leftovers", ctypes.c_uint32), ("volume", ctypes.c_uint32),
                ("refit_threads", ctypes.c_uint32)]


class DvhQueryOptions(ctypes.Structure):
    _fields_ = [("mode", ctypes.c_uint32), ("max_depth", ctypes.c_uint32), ("max_pairs", ctypes.c_uint64), ("budget", ctypes.c_uint64),
                ("threads", ctypes.c_uint32)]


class DvhQueryStats(ctypes.Structure):
    _fields_ = [
        ("bv_tests", ctypes.c_uint64),
        ("triangle_tests", ctypes.c_uint64),
        ("triangle_candidates", ctypes.c_uint64),
        ("leaf_pairs", ctypes.c_uint64),
        ("pairs", ctypes.c_uint64),
        ("nodes_refit", ctypes.c_uint64),
        ("truncated", ctypes.c_bool),
        ("frontier_pairs", ctypes.c_uint64),
    ]


class DvhContact(ctypes.Structure):
    _fields_ = [("object_a", ctypes.c_uint32), ("object_b", ctypes.c_uint32), ("a", ctypes.c_uint32), ("b", ctypes.c_uint32)]


class DvhSceneStats(ctypes.Structure):
    _fields_ = [
        ("objects", ctypes.c_uint64),
        ("object_pairs_tested", ctypes.c_uint64),
        ("object_pairs_colliding", ctypes.c_uint64),
        ("bv_tests", ctypes.c_uint64),
        ("triangle_tests", ctypes.c_uint64),
        ("nodes_refit", ctypes.c_uint64),
        ("contacts", ctypes.c_uint64),
        ("truncated", ctypes.c_bool),
    ]


MeshPtr = ctypes.c_void_p
PairsPtr = ctypes.c_void_p
ScenePtr = ctypes.c_void_p
ContactsPtr = ctypes.c_void_p
lib.dvh_version.restype = ctypes.c_char_p
lib.dvh_status_name.restype = ctypes.c_char_p
lib.dvh_status_name.argtypes = [DvhStatus]
lib.dvh_last_error_message.restype = ctypes.c_size_t
lib.dvh_last_error_message.argtypes = [ctypes.c_char_p, ctypes.c_size_t]
lib.dvh_mesh_create.restype = DvhStatus
lib.dvh_mesh_create.argtypes = [
    ctypes.POINTER(ctypes.c_double), ctypes.c_size_t, ctypes.POINTER(ctypes.c_uint32), ctypes.c_size_t,
    ctypes.POINTER(DvhBuildOptions), ctypes.POINTER(MeshPtr),
]
lib.dvh_build_options_default.restype = DvhBuildOptions
lib.dvh_build_options_rigid.restype = DvhBuildOptions
lib.dvh_query_options_default.restype = DvhQueryOptions
lib.dvh_mesh_refit.restype = DvhStatus
lib.dvh_mesh_refit.argtypes = [MeshPtr, ctypes.POINTER(ctypes.c_double), ctypes.c_size_t]
lib.dvh_mesh_free.argtypes = [MeshPtr]
lib.dvh_mesh_node_triangles.restype = DvhStatus
lib.dvh_mesh_node_triangles.argtypes = [MeshPtr, ctypes.c_uint32, ctypes.POINTER(ctypes.POINTER(ctypes.c_uint32)), ctypes.POINTER(ctypes.c_size_t)]
lib.dvh_pairs_new.restype = PairsPtr
lib.dvh_pairs_len.restype = ctypes.c_size_t
lib.dvh_pairs_len.argtypes = [PairsPtr]
lib.dvh_pairs_data.restype = ctypes.POINTER(DvhPair)
lib.dvh_pairs_data.argtypes = [PairsPtr]
lib.dvh_pairs_kind.restype = ctypes.c_uint32
lib.dvh_pairs_kind.argtypes = [PairsPtr]
lib.dvh_pairs_free.argtypes = [PairsPtr]
lib.dvh_collide.restype = DvhStatus
lib.dvh_collide.argtypes = [
    MeshPtr, ctypes.POINTER(DvhPose), MeshPtr, ctypes.POINTER(DvhPose), ctypes.POINTER(DvhQueryOptions), PairsPtr,
    ctypes.POINTER(DvhQueryStats),
]

lib.dvh_self_collide.restype = DvhStatus
lib.dvh_self_collide.argtypes = [MeshPtr, ctypes.POINTER(DvhQueryOptions), PairsPtr, ctypes.POINTER(DvhQueryStats)]
lib.dvh_proximity.restype = DvhStatus
lib.dvh_proximity.argtypes = [
    MeshPtr, ctypes.POINTER(DvhPose), MeshPtr, ctypes.POINTER(DvhPose), ctypes.c_double, ctypes.POINTER(DvhQueryOptions),
    PairsPtr, ctypes.POINTER(DvhQueryStats),
]
lib.dvh_self_proximity.restype = DvhStatus
lib.dvh_self_proximity.argtypes = [MeshPtr, ctypes.c_double, ctypes.POINTER(DvhQueryOptions), PairsPtr, ctypes.POINTER(DvhQueryStats)]

lib.dvh_scene_create.restype = DvhStatus
lib.dvh_scene_create.argtypes = [ctypes.POINTER(ScenePtr)]
lib.dvh_scene_free.argtypes = [ScenePtr]
lib.dvh_scene_add_rigid.restype = DvhStatus
lib.dvh_scene_add_rigid.argtypes = [ScenePtr, MeshPtr, ctypes.POINTER(DvhPose), ctypes.c_uint32, ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32)]
lib.dvh_scene_add_deformable.restype = DvhStatus
lib.dvh_scene_add_deformable.argtypes = [ScenePtr, MeshPtr, ctypes.c_uint32, ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32)]
lib.dvh_scene_set_pose.restype = DvhStatus
lib.dvh_scene_set_pose.argtypes = [ScenePtr, ctypes.c_uint32, ctypes.POINTER(DvhPose)]
lib.dvh_scene_set_positions.restype = DvhStatus
lib.dvh_scene_set_positions.argtypes = [ScenePtr, ctypes.c_uint32, ctypes.POINTER(ctypes.c_double), ctypes.c_size_t]
lib.dvh_scene_remove.restype = DvhStatus
lib.dvh_scene_remove.argtypes = [ScenePtr, ctypes.c_uint32]
lib.dvh_scene_exclude_pair.restype = DvhStatus
lib.dvh_scene_exclude_pair.argtypes = [ScenePtr, ctypes.c_uint32, ctypes.c_uint32]
lib.dvh_scene_set_lazy_refit.restype = DvhStatus
lib.dvh_scene_set_lazy_refit.argtypes = [ScenePtr, ctypes.c_bool]
lib.dvh_scene_collide.restype = DvhStatus
lib.dvh_scene_collide.argtypes = [ScenePtr, ctypes.POINTER(DvhQueryOptions), ContactsPtr, ctypes.POINTER(DvhSceneStats)]
lib.dvh_contacts_new.restype = ContactsPtr
lib.dvh_contacts_len.restype = ctypes.c_size_t
lib.dvh_contacts_len.argtypes = [ContactsPtr]
lib.dvh_contacts_data.restype = ctypes.POINTER(DvhContact)
lib.dvh_contacts_data.argtypes = [ContactsPtr]
lib.dvh_contacts_free.argtypes = [ContactsPtr]


def last_error():
    n = lib.dvh_last_error_message(None, 0)
    buf = ctypes.create_string_buffer(n + 1)
    lib.dvh_last_error_message(buf, n + 1)
    return buf.value.decode()


def grid(n, z):
    """An n x n square sheet at height z, two triangles per cell."""
    pos = [c for j in range(n + 1) for i in range(n + 1) for c in (float(i), float(j), z)]
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [a, a + 1, a + n + 2, a, a + n + 2, a + n + 1]
    return pos, tris


def create(pos, tris, options=None):
    mesh = MeshPtr()
    status = lib.dvh_mesh_create((ctypes.c_double * len(pos))(*pos), len(pos) // 3, (ctypes.c_uint32 * len(tris))(*tris), len(tris) // 3,
                                 ctypes.byref(options) if options is not None else None, ctypes.byref(mesh))
    return status, mesh


def pairs_of(pairs):
    data = lib.dvh_pairs_data(pairs)
    return [(data[i].a, data[i].b) for i in range(lib.dvh_pairs_len(pairs))]


def main():
    failures = []

    def check(cond, what):
        if not cond:
            failures.append(what)

    check(lib.dvh_version().decode().count(".") == 2, "version")
    # A flat sheet and a tent standing through it along x = 2: its ridge edge runs from (2, 1, -1) up to (2, 3, 1).
    sheet_pos, sheet_tris = grid(4, 0.0)
    tent_pos = [2.0, 1.0, -1.0, 2.0, 3.0, 1.0, 1.0, 2.0, 1.0, 3.0, 2.0, 1.0]
    tent_tris = [0, 1, 2, 0, 3, 1]
    status, sheet = create(sheet_pos, sheet_tris)
    check(status == DVH_STATUS_OK, "sheet created")
    status, tent = create(tent_pos, tent_tris)
    check(status == DVH_STATUS_OK, "tent created")

    pairs = lib.dvh_pairs_new()
    stats = DvhQueryStats()
    status = lib.dvh_collide(sheet, None, tent, None, None, pairs, ctypes.byref(stats))
    found = pairs_of(pairs)
    check(status == DVH_STATUS_OK and len(found) > 0 and stats.pairs == len(found), "collide finds pairs")
    check(found == sorted(set(found)), "pairs sorted and distinct")
    check({b for _, b in found} == {0, 1}, "both tent triangles cross the sheet")

    # The tent moved 10 up by a pose: nothing.
    pose = DvhPose((ctypes.c_double * 9)(1, 0, 0, 0, 1, 0, 0, 0, 1), (ctypes.c_double * 3)(0, 0, 10))
    status = lib.dvh_collide(sheet, None, tent, ctypes.byref(pose), None, pairs, None)
    check(status == DVH_STATUS_OK and lib.dvh_pairs_len(pairs) == 0, "posed away: no pairs")

    # Leaves mode reports nodes that cover the exact pairs.
    lib.dvh_collide(sheet, None, tent, None, None, pairs, None)
    exact = pairs_of(pairs)

    def covered_by(a, b):
        covered = set()
        for na, nb in pairs_of(pairs):
            ta, ca, tb, cb = ctypes.POINTER(ctypes.c_uint32)(), ctypes.c_size_t(), ctypes.POINTER(ctypes.c_uint32)(), ctypes.c_size_t()
            lib.dvh_mesh_node_triangles(a, na, ctypes.byref(ta), ctypes.byref(ca))
            lib.dvh_mesh_node_triangles(b, nb, ctypes.byref(tb), ctypes.byref(cb))
            covered |= {(ta[i], tb[j]) for i in range(ca.value) for j in range(cb.value)}
        return covered

    options = lib.dvh_query_options_default()
    check(options.mode == 0 and options.budget == 0 and options.threads == 0, "default query options")
    options.mode = DVH_QUERY_MODE_LEAVES
    check(lib.dvh_collide(sheet, None, tent, None, ctypes.byref(options), pairs, None) == DVH_STATUS_OK, "leaves mode")
    check(lib.dvh_pairs_kind(pairs) == DVH_PAIR_KIND_NODES, "leaves mode reports nodes")
    check(set(exact) <= covered_by(sheet, tent), "leaves cover the exact pairs")

    # A budget of 2 volume tests: the frontier covers the exact pairs too; 0 is refused.
    options.mode, options.budget = DVH_QUERY_MODE_BUDGET, 2
    check(lib.dvh_collide(sheet, None, tent, None, ctypes.byref(options), pairs, ctypes.byref(stats)) == DVH_STATUS_OK, "budget mode")
    check(stats.bv_tests <= 2 + 64 and set(exact) <= covered_by(sheet, tent), "budget frontier covers the exact pairs")
    options.budget = 0
    check(lib.dvh_collide(sheet, None, tent, None, ctypes.byref(options), pairs, None) == DVH_STATUS_INVALID_ARGUMENT, "zero budget refused")
    check("budget = 0" in last_error(), "zero budget message: " + last_error())

    # Box, SBV and DVH volumes give the same exact pairs, against each other too.
    build = lib.dvh_build_options_default()
    check(build.volume == DVH_VOLUME_KIND_AABB, "default volume kind")
    rigid = lib.dvh_build_options_rigid()
    check(rigid.volume == DVH_VOLUME_KIND_SBV and rigid.radius == 1, "rigid options")
    build.volume = DVH_VOLUME_KIND_AABB
    status, sheet_boxes = create(sheet_pos, sheet_tris, build)
    build.volume = DVH_VOLUME_KIND_SBV
    status2, tent_sbv = create(tent_pos, tent_tris, build)
    check(status == status2 == DVH_STATUS_OK, "box and SBV meshes created")
    lib.dvh_collide(sheet_boxes, None, tent_sbv, None, None, pairs, None)
    check(pairs_of(pairs) == exact, "boxes against SBV spheres: the same exact pairs")
    build.volume = DVH_VOLUME_KIND_DVH
    status, tent_dvh = create(tent_pos, tent_tris, build)
    lib.dvh_collide(sheet_boxes, None, tent_dvh, None, None, pairs, None)
    check(status == DVH_STATUS_OK and pairs_of(pairs) == exact, "boxes against DVH spheres: the same exact pairs")
    lib.dvh_mesh_free(tent_dvh)
    build.volume = 9
    status, bad = create(tent_pos, tent_tris, build)
    check(status == DVH_STATUS_INVALID_ARGUMENT and "options->volume = 9" in last_error(), "volume kind out of range: " + last_error())
    lib.dvh_mesh_free(sheet_boxes)
    lib.dvh_mesh_free(tent_sbv)

    # Refit: the tent lifted out of the sheet, then an error that changes nothing.
    lifted = [c + (3.0 if k % 3 == 2 else 0.0) for k, c in enumerate(tent_pos)]
    check(lib.dvh_mesh_refit(tent, (ctypes.c_double * 12)(*lifted), 4) == DVH_STATUS_OK, "refit")
    lib.dvh_collide(sheet, None, tent, None, None, pairs, None)
    check(lib.dvh_pairs_len(pairs) == 0, "lifted tent misses the sheet")
    lifted[4] = math.nan
    check(lib.dvh_mesh_refit(tent, (ctypes.c_double * 12)(*lifted), 4) != DVH_STATUS_OK, "NaN refit refused")
    check("vertex 1: coordinate y is NaN" in last_error(), "NaN refit message: " + last_error())

    # Error paths: an index out of range, a NULL, a non-rigid pose.
    status, bad = create(tent_pos, [0, 1, 7])
    check(status == DVH_STATUS_INDEX_OUT_OF_RANGE and not bad.value, "index out of range refused")
    check(last_error() == "triangle 0, corner 2: vertex index 7 is out of range (the mesh has 4 vertices)", "index message: " + last_error())
    check(lib.dvh_collide(None, None, tent, None, None, pairs, None) == DVH_STATUS_NULL_ARGUMENT, "NULL mesh refused")
    check(lib.dvh_status_name(DVH_STATUS_NULL_ARGUMENT) == b"DVH_STATUS_NULL_ARGUMENT", "status name")
    squash = DvhPose((ctypes.c_double * 9)(1, 0, 0, 0, 1, 0, 0, 0, 0.5), (ctypes.c_double * 3)(0, 0, 0))
    check(lib.dvh_collide(sheet, ctypes.byref(squash), tent, None, None, pairs, None) == DVH_STATUS_NON_RIGID_POSE, "scaled pose refused")

    # One query and one refit on the library's threads: the calling thread's answer. Sheets of
    # 33,800 triangles, one folded in waves through the other, are large enough to be shared out.
    n = 130
    flat_pos, flat_tris = grid(n, 0.0)
    wave_pos = [c if k % 3 != 2 else float((k // 3) % 7 - 3) for k, c in enumerate(flat_pos)]
    answers = {}
    for refit_threads in (1, 0):
        build = lib.dvh_build_options_default()
        check(build.refit_threads == 0, "default refit threads")
        build.refit_threads = refit_threads
        status, big_a = create(flat_pos, flat_tris, build)
        status2, big_b = create(flat_pos, flat_tris, build)
        check(status == status2 == DVH_STATUS_OK, "large sheets created")
        check(lib.dvh_mesh_refit(big_b, (ctypes.c_double * len(wave_pos))(*wave_pos), len(wave_pos) // 3) == DVH_STATUS_OK, "large refit")
        for threads in (1, 0, 2):
            for max_pairs in (0, 500):
                options = lib.dvh_query_options_default()
                options.threads, options.max_pairs = threads, max_pairs
                check(lib.dvh_collide(big_a, None, big_b, None, ctypes.byref(options), pairs, None) == DVH_STATUS_OK, "threaded query")
                answers[(refit_threads, threads, max_pairs)] = pairs_of(pairs)
        lib.dvh_mesh_free(big_a)
        lib.dvh_mesh_free(big_b)
    for max_pairs in (0, 500):
        reference = answers[(1, 1, max_pairs)]
        check(len(reference) >= 500, "the large sheets are in dense contact")
        for key, found in answers.items():
            check(key[2] != max_pairs or found == reference, f"threads {key}: the single-threaded answer")

    # A scene: the sheet (deformable) and two tents sharing one mesh (rigid), one through the
    # sheet and one far away; its contacts are the pairwise queries' with object ids.
    lib.dvh_mesh_refit(tent, (ctypes.c_double * 12)(*tent_pos), 4)
    scene = ScenePtr()
    check(lib.dvh_scene_create(ctypes.byref(scene)) == DVH_STATUS_OK, "scene created")
    ids = [ctypes.c_uint32() for _ in range(3)]
    far = DvhPose((ctypes.c_double * 9)(1, 0, 0, 0, 1, 0, 0, 0, 1), (ctypes.c_double * 3)(50, 0, 0))
    check(lib.dvh_scene_add_deformable(scene, sheet, 1, 0xFFFFFFFF, ctypes.byref(ids[0])) == DVH_STATUS_OK, "deformable added")
    check(lib.dvh_scene_add_rigid(scene, tent, None, 1, 0xFFFFFFFF, ctypes.byref(ids[1])) == DVH_STATUS_OK, "rigid added")
    check(lib.dvh_scene_add_rigid(scene, tent, ctypes.byref(far), 1, 0xFFFFFFFF, ctypes.byref(ids[2])) == DVH_STATUS_OK, "far rigid added")
    check([i.value for i in ids] == [0, 1, 2], "object ids")
    contacts = lib.dvh_contacts_new()
    scene_stats = DvhSceneStats()

    def contacts_of():
        data = lib.dvh_contacts_data(contacts)
        return [(data[i].object_a, data[i].object_b, data[i].a, data[i].b) for i in range(lib.dvh_contacts_len(contacts))]

    check(lib.dvh_scene_collide(scene, None, contacts, ctypes.byref(scene_stats)) == DVH_STATUS_OK, "scene collide")
    lib.dvh_collide(sheet, None, tent, None, None, pairs, None)
    check(contacts_of() == [(0, 1, a, b) for a, b in pairs_of(pairs)] and len(contacts_of()) > 0, "scene contacts are the pairwise ones")
    check(scene_stats.objects == 3 and scene_stats.object_pairs_tested == 1 and scene_stats.contacts == len(contacts_of()), "scene counters")
    # The sheet lifted by 5 through new positions: no contact; back down by a pose on the tent.
    lifted_sheet = [c + (5.0 if k % 3 == 2 else 0.0) for k, c in enumerate(sheet_pos)]
    n = len(lifted_sheet) // 3
    check(lib.dvh_scene_set_positions(scene, 0, (ctypes.c_double * len(lifted_sheet))(*lifted_sheet), n) == DVH_STATUS_OK, "set positions")
    lib.dvh_scene_collide(scene, None, contacts, None)
    check(contacts_of() == [], "lifted sheet: no contact")
    up = DvhPose((ctypes.c_double * 9)(1, 0, 0, 0, 1, 0, 0, 0, 1), (ctypes.c_double * 3)(0, 0, 5))
    check(lib.dvh_scene_set_pose(scene, 1, ctypes.byref(up)) == DVH_STATUS_OK, "set pose")
    lib.dvh_scene_collide(scene, None, contacts, None)
    check(contacts_of() == [(0, 1, a, b) for a, b in pairs_of(pairs)], "tent moved up with the sheet: the same contacts")
    # Eager refit: the same contacts.
    check(lib.dvh_scene_set_lazy_refit(None, False) == DVH_STATUS_NULL_ARGUMENT, "lazy refit: NULL scene refused")
    check(lib.dvh_scene_set_lazy_refit(scene, False) == DVH_STATUS_OK, "eager refit chosen")
    lib.dvh_scene_collide(scene, None, contacts, None)
    check(contacts_of() == [(0, 1, a, b) for a, b in pairs_of(pairs)], "eager refit: the same contacts")
    check(lib.dvh_scene_set_lazy_refit(scene, True) == DVH_STATUS_OK, "lazy refit chosen")
    check(lib.dvh_scene_exclude_pair(scene, 1, 0) == DVH_STATUS_OK, "pair excluded")
    lib.dvh_scene_collide(scene, None, contacts, None)
    check(contacts_of() == [], "excluded pair: no contact")
    check(lib.dvh_scene_set_pose(scene, 0, ctypes.byref(up)) == DVH_STATUS_INVALID_ARGUMENT, "pose of a deformable refused")
    check("object 0 is deformable" in last_error(), "deformable message: " + last_error())
    check(lib.dvh_scene_remove(scene, 2) == DVH_STATUS_OK and lib.dvh_scene_remove(scene, 2) == DVH_STATUS_INVALID_ARGUMENT, "remove once")
    check("object 2 is not in the scene" in last_error(), "removed object message: " + last_error())
    # Over a step: self-contact, motions, the scene's continuous collision and stencils.
    for name, args in (("dvh_scene_set_self_contact", [ScenePtr, ctypes.c_uint32, ctypes.c_bool]),
                       ("dvh_scene_set_motion", [ScenePtr, ctypes.c_uint32, ctypes.POINTER(ctypes.c_double),
                                                 ctypes.POINTER(ctypes.c_double), ctypes.c_size_t]),
                       ("dvh_scene_set_motion_f32", [ScenePtr, ctypes.c_uint32, ctypes.POINTER(ctypes.c_float),
                                                     ctypes.POINTER(ctypes.c_float), ctypes.c_size_t, ctypes.c_size_t]),
                       ("dvh_scene_set_pose_motion", [ScenePtr, ctypes.c_uint32, ctypes.POINTER(DvhPose), ctypes.POINTER(DvhPose)]),
                       ("dvh_scene_continuous_collide", [ScenePtr, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]),
                       ("dvh_scene_nearest_features", [ScenePtr, ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p,
                                                       ctypes.POINTER(DvhQueryStats)])):
        getattr(lib, name).restype = DvhStatus
        getattr(lib, name).argtypes = args
    for name in ("dvh_scene_impacts_new", "dvh_scene_near_pairs_new"):
        getattr(lib, name).restype = ctypes.c_void_p
    for name in ("dvh_scene_impacts_len", "dvh_scene_near_pairs_len"):
        getattr(lib, name).restype = ctypes.c_size_t
        getattr(lib, name).argtypes = [ctypes.c_void_p]
    for name in ("dvh_scene_impacts_free", "dvh_scene_near_pairs_free"):
        getattr(lib, name).argtypes = [ctypes.c_void_p]
    check(lib.dvh_scene_set_self_contact(scene, 1, True) == DVH_STATUS_INVALID_ARGUMENT, "self-contact of a rigid refused")
    check("rigid" in last_error(), "rigid self-contact message: " + last_error())
    check(lib.dvh_scene_set_self_contact(scene, 1, False) == DVH_STATUS_OK
          and lib.dvh_scene_set_self_contact(scene, 0, True) == DVH_STATUS_OK, "self-contact set")
    down = (ctypes.c_double * len(sheet_pos))(*sheet_pos)
    up_sheet = (ctypes.c_double * len(lifted_sheet))(*lifted_sheet)
    check(lib.dvh_scene_set_motion(scene, 1, up_sheet, down, n) == DVH_STATUS_INVALID_ARGUMENT, "motion of a rigid refused")
    check(lib.dvh_scene_set_motion_f32(scene, 0, None, None, 12, n) == DVH_STATUS_NULL_ARGUMENT, "NULL motion refused")
    check(lib.dvh_scene_set_pose_motion(scene, 0, None, None) == DVH_STATUS_INVALID_ARGUMENT, "pose motion of a deformable refused")
    check(lib.dvh_scene_set_pose_motion(scene, 1, ctypes.byref(up), ctypes.byref(up)) == DVH_STATUS_OK, "pose motion")
    check(lib.dvh_scene_set_motion(scene, 0, up_sheet, down, n) == DVH_STATUS_OK, "motion")
    scene_impacts = lib.dvh_scene_impacts_new()
    check(lib.dvh_scene_continuous_collide(scene, None, scene_impacts, None) == DVH_STATUS_OK, "scene continuous collide")
    # The pair is excluded and the flat sheet does not meet itself while it moves down.
    check(lib.dvh_scene_impacts_len(scene_impacts) == 0, "no impact of an excluded pair")
    scene_near = lib.dvh_scene_near_pairs_new()
    near_stats = DvhQueryStats()
    check(lib.dvh_scene_nearest_features(scene, -1.0, None, scene_near, None) == DVH_STATUS_INVALID_ARGUMENT,
          "negative distance refused")
    check(lib.dvh_scene_nearest_features(scene, 0.5, None, scene_near, ctypes.byref(near_stats)) == DVH_STATUS_OK
          and near_stats.pairs == lib.dvh_scene_near_pairs_len(scene_near), "scene stencils")
    lib.dvh_scene_impacts_free(scene_impacts)
    lib.dvh_scene_near_pairs_free(scene_near)
    lib.dvh_contacts_free(contacts)
    lib.dvh_scene_free(scene)

    # Self-collision: the sheet and the tent as one mesh (the tent's vertices renumbered after the
    # sheet's) report exactly their crossings; the intact sheet alone reports nothing.
    lib.dvh_collide(sheet, None, tent, None, None, pairs, None)
    crossings = pairs_of(pairs)
    offset = len(sheet_tris) // 3
    status, both = create(sheet_pos + tent_pos, sheet_tris + [v + len(sheet_pos) // 3 for v in tent_tris])
    check(status == DVH_STATUS_OK, "one mesh of both")
    check(lib.dvh_self_collide(both, None, pairs, ctypes.byref(stats)) == DVH_STATUS_OK, "self-collide")
    check(pairs_of(pairs) == [(a, b + offset) for a, b in crossings] and stats.pairs == len(crossings), "self-collide: the crossings")
    check(lib.dvh_self_collide(sheet, None, pairs, None) == DVH_STATUS_OK and pairs_of(pairs) == [], "an intact sheet: nothing")
    check(lib.dvh_self_collide(None, None, pairs, None) == DVH_STATUS_NULL_ARGUMENT, "self-collide: NULL mesh refused")

    # Proximity: the sheet and its copy lifted by exactly 1, within 1 and just below.
    lift = DvhPose((ctypes.c_double * 9)(1, 0, 0, 0, 1, 0, 0, 0, 1), (ctypes.c_double * 3)(0, 0, 1))
    check(lib.dvh_proximity(sheet, None, sheet, ctypes.byref(lift), 1.0, None, pairs, None) == DVH_STATUS_OK, "proximity")
    near = pairs_of(pairs)
    check(all((t, t) in near for t in range(offset)), "proximity: every triangle faces its copy")
    check(lib.dvh_proximity(sheet, None, sheet, ctypes.byref(lift), math.nextafter(1.0, 0.0), None, pairs, None) == DVH_STATUS_OK
          and pairs_of(pairs) == [], "proximity: nothing closer than 1")
    check(lib.dvh_proximity(sheet, None, tent, None, 0.0, None, pairs, None) == DVH_STATUS_OK and pairs_of(pairs) == crossings,
          "proximity at 0 is collide")
    check(lib.dvh_proximity(sheet, None, tent, None, -1.0, None, pairs, None) == DVH_STATUS_INVALID_ARGUMENT
          and "distance" in last_error(), "negative distance refused: " + last_error())
    check(pairs_of(pairs) == crossings, "a refused query keeps the result")

    # Self-proximity: pairs sharing no vertex; every such pair far enough.
    tris = [tuple(sheet_tris[3 * t:3 * t + 3]) for t in range(offset)]
    apart = [(a, b) for a in range(offset) for b in range(a + 1, offset) if not set(tris[a]) & set(tris[b])]
    check(lib.dvh_self_proximity(sheet, 100.0, None, pairs, None) == DVH_STATUS_OK and pairs_of(pairs) == apart,
          "self-proximity: every pair apart")
    check(lib.dvh_self_proximity(sheet, 0.0, None, pairs, None) == DVH_STATUS_OK and pairs_of(pairs) == [],
          "self-proximity at 0 on an intact sheet")
    check(lib.dvh_self_proximity(sheet, float("nan"), None, pairs, None) == DVH_STATUS_INVALID_ARGUMENT, "NaN distance refused")
    lib.dvh_mesh_free(both)

    # Continuous collision: the tent moved from 10 above the sheet to 10 below it passes through
    # it, though it meets it at neither end.
    class DvhCcdOptions(ctypes.Structure):
        _fields_ = [("mode", ctypes.c_uint32), ("threads", ctypes.c_uint32),
                    ("max_impacts", ctypes.c_uint64), ("earliest_only", ctypes.c_bool)]

    class DvhImpact(ctypes.Structure):
        _fields_ = [("kind", ctypes.c_uint32), ("a0", ctypes.c_uint32), ("a1", ctypes.c_uint32),
                    ("b0", ctypes.c_uint32), ("b1", ctypes.c_uint32), ("toi", ctypes.c_double)]

    class DvhCcdStats(ctypes.Structure):
        _fields_ = [("bv_tests", ctypes.c_uint64), ("primitive_tests", ctypes.c_uint64),
                    ("impacts", ctypes.c_uint64), ("earliest_toi", ctypes.c_double), ("truncated", ctypes.c_bool)]

    Doubles = ctypes.POINTER(ctypes.c_double)
    lib.dvh_ccd_options_default.restype = DvhCcdOptions
    lib.dvh_ccd_vertex_face.restype = DvhStatus
    lib.dvh_ccd_vertex_face.argtypes = [Doubles, Doubles, ctypes.POINTER(DvhCcdOptions),
                                        ctypes.POINTER(ctypes.c_bool), Doubles]
    lib.dvh_mesh_refit_motion.restype = DvhStatus
    lib.dvh_mesh_refit_motion.argtypes = [MeshPtr, Doubles, Doubles, ctypes.c_size_t]
    lib.dvh_impacts_new.restype = ctypes.c_void_p
    lib.dvh_impacts_len.restype = ctypes.c_size_t
    lib.dvh_impacts_len.argtypes = [ctypes.c_void_p]
    lib.dvh_impacts_data.restype = ctypes.POINTER(DvhImpact)
    lib.dvh_impacts_data.argtypes = [ctypes.c_void_p]
    lib.dvh_impacts_free.argtypes = [ctypes.c_void_p]
    lib.dvh_continuous_collide.restype = DvhStatus
    lib.dvh_continuous_collide.argtypes = [MeshPtr, MeshPtr, ctypes.POINTER(DvhCcdOptions), ctypes.c_void_p,
                                           ctypes.POINTER(DvhCcdStats)]

    def doubles(values):
        return (ctypes.c_double * len(values))(*values)

    falling_start = doubles([0.25, 0.25, 1.0, 0, 0, 0, 1, 0, 0, 0, 1, 0])
    falling_end = doubles([0.25, 0.25, -3.0, 0, 0, 0, 1, 0, 0, 0, 1, 0])
    hit, toi = ctypes.c_bool(False), ctypes.c_double(-1.0)
    check(lib.dvh_ccd_vertex_face(falling_start, falling_end, None, ctypes.byref(hit), ctypes.byref(toi)) == DVH_STATUS_OK
          and hit.value and toi.value == 0.25, "ccd: a point falling through a triangle at t = 0.25")
    bad = doubles([0.25, 0.25, float("nan")] + [0.0] * 9)
    check(lib.dvh_ccd_vertex_face(bad, falling_end, None, ctypes.byref(hit), ctypes.byref(toi)) == DVH_STATUS_NON_FINITE_COORDINATE
          and "start[2]" in last_error() and toi.value == 0.25, "ccd: NaN named, outputs untouched: " + last_error())
    up = doubles([x + (10.0 if i % 3 == 2 else 0.0) for i, x in enumerate(tent_pos)])
    down = doubles([x - (10.0 if i % 3 == 2 else 0.0) for i, x in enumerate(tent_pos)])
    check(lib.dvh_mesh_refit_motion(tent, up, down, 4) == DVH_STATUS_OK, "refit_motion")
    check(lib.dvh_mesh_refit_motion(tent, up, down, 3) == DVH_STATUS_INVALID_ARGUMENT, "refit_motion: wrong count refused")
    impacts = lib.dvh_impacts_new()
    ccd_stats = DvhCcdStats()
    options = lib.dvh_ccd_options_default()
    check(lib.dvh_continuous_collide(sheet, tent, ctypes.byref(options), impacts, ctypes.byref(ccd_stats)) == DVH_STATUS_OK
          and lib.dvh_impacts_len(impacts) > 0 and ccd_stats.impacts == lib.dvh_impacts_len(impacts),
          "continuous collision finds the pass-through")
    data = lib.dvh_impacts_data(impacts)
    keys = [(data[i].kind, data[i].a0, data[i].a1, data[i].b0, data[i].b1) for i in range(lib.dvh_impacts_len(impacts))]
    check(keys == sorted(keys) and all(0.0 <= data[i].toi <= 1.0 for i in range(len(keys))), "impacts sorted, times in the step")
    options.mode = 9
    check(lib.dvh_continuous_collide(sheet, tent, ctypes.byref(options), impacts, None) == DVH_STATUS_INVALID_ARGUMENT
          and lib.dvh_impacts_len(impacts) == len(keys), "bad mode refused, impacts kept")
    lib.dvh_impacts_free(impacts)

    # Closest-point stencils: the sheet against its copy lifted by exactly 1.
    class DvhNearPair(ctypes.Structure):
        _fields_ = [(n, ctypes.c_uint32) for n in ("kind", "a0", "a1", "b0", "b1", "feature_a", "feature_b")] + [
            ("distance", ctypes.c_double)] + [(n, ctypes.c_double * 3) for n in
                                              ("closest_a", "closest_b", "weights_a", "weights_b")]

    check(ctypes.sizeof(DvhNearPair) == 136 and DvhNearPair.distance.offset == 32, "DvhNearPair's layout")
    lib.dvh_near_pairs_new.restype = ctypes.c_void_p
    lib.dvh_near_pairs_len.restype = ctypes.c_size_t
    lib.dvh_near_pairs_len.argtypes = [ctypes.c_void_p]
    lib.dvh_near_pairs_data.restype = ctypes.POINTER(DvhNearPair)
    lib.dvh_near_pairs_data.argtypes = [ctypes.c_void_p]
    lib.dvh_near_pairs_free.argtypes = [ctypes.c_void_p]
    lib.dvh_nearest_features.restype = DvhStatus
    lib.dvh_nearest_features.argtypes = [MeshPtr, ctypes.POINTER(DvhPose), MeshPtr, ctypes.POINTER(DvhPose), ctypes.c_double,
                                         ctypes.POINTER(DvhQueryOptions), ctypes.c_void_p, ctypes.POINTER(DvhQueryStats)]
    lib.dvh_self_nearest_features.restype = DvhStatus
    lib.dvh_self_nearest_features.argtypes = [MeshPtr, ctypes.c_double, ctypes.POINTER(DvhQueryOptions), ctypes.c_void_p,
                                              ctypes.POINTER(DvhQueryStats)]
    near = lib.dvh_near_pairs_new()
    check(lib.dvh_nearest_features(sheet, None, sheet, ctypes.byref(lift), 1.0, None, near, None) == DVH_STATUS_OK
          and lib.dvh_near_pairs_len(near) > 0, "stencils of the sheet and its lifted copy")
    data = lib.dvh_near_pairs_data(near)
    n = lib.dvh_near_pairs_len(near)
    keys = [(data[i].kind, data[i].a0, data[i].a1, data[i].b0, data[i].b1) for i in range(n)]
    check(keys == sorted(keys) and all(data[i].distance == 1.0 for i in range(n))
          and all(abs(sum(data[i].weights_a) - 1.0) < 1e-12 for i in range(n)), "stencils sorted, all exactly 1 apart")
    check(lib.dvh_nearest_features(sheet, None, sheet, ctypes.byref(lift), -1.0, None, near, None) == DVH_STATUS_INVALID_ARGUMENT
          and "distance" in last_error() and lib.dvh_near_pairs_len(near) == n, "negative distance refused, stencils kept")
    check(lib.dvh_nearest_features(sheet, None, sheet, ctypes.byref(lift), math.nextafter(1.0, 0.0), None, near, None)
          == DVH_STATUS_OK and lib.dvh_near_pairs_len(near) == 0, "stencils: nothing closer than 1")
    check(lib.dvh_self_nearest_features(sheet, 0.0, None, near, None) == DVH_STATUS_OK and lib.dvh_near_pairs_len(near) == 0,
          "self stencils at 0 on an intact sheet")
    check(lib.dvh_self_nearest_features(None, 1.0, None, near, None) == DVH_STATUS_NULL_ARGUMENT, "NULL mesh refused")
    lib.dvh_near_pairs_free(near)

    # Intersection curves: a flat sheet and one tilted through it cross along one open curve.
    class DvhCurveSegment(ctypes.Structure):
        _fields_ = [("triangle_a", ctypes.c_uint32), ("triangle_b", ctypes.c_uint32), ("curve", ctypes.c_uint32),
                    ("reserved", ctypes.c_uint32), ("start", ctypes.c_double * 3), ("end", ctypes.c_double * 3)]

    check(ctypes.sizeof(DvhCurveSegment) == 64, "DvhCurveSegment is 64 bytes")
    CurvesPtr = ctypes.c_void_p
    lib.dvh_curves_new.restype = CurvesPtr
    lib.dvh_curves_len.restype = ctypes.c_size_t
    lib.dvh_curves_len.argtypes = [CurvesPtr]
    lib.dvh_curves_data.restype = ctypes.POINTER(DvhCurveSegment)
    lib.dvh_curves_data.argtypes = [CurvesPtr]
    lib.dvh_curves_curve_count.restype = ctypes.c_size_t
    lib.dvh_curves_curve_count.argtypes = [CurvesPtr]
    lib.dvh_curves_curve.argtypes = [CurvesPtr, ctypes.c_size_t, ctypes.POINTER(ctypes.c_size_t),
                                     ctypes.POINTER(ctypes.c_size_t), ctypes.POINTER(ctypes.c_bool)]
    lib.dvh_curves_degenerate_len.restype = ctypes.c_size_t
    lib.dvh_curves_degenerate_len.argtypes = [CurvesPtr]
    lib.dvh_curves_free.argtypes = [CurvesPtr]
    lib.dvh_intersection_curves.argtypes = [MeshPtr, ctypes.POINTER(DvhPose), MeshPtr, ctypes.POINTER(DvhPose),
                                            ctypes.POINTER(DvhQueryOptions), CurvesPtr, ctypes.POINTER(DvhQueryStats)]
    lib.dvh_curves_length_gradient.argtypes = [CurvesPtr, MeshPtr, ctypes.POINTER(DvhPose), MeshPtr,
                                               ctypes.POINTER(DvhPose), ctypes.POINTER(ctypes.c_double), ctypes.c_size_t,
                                               ctypes.POINTER(ctypes.c_double), ctypes.c_size_t]
    flat_pos, flat_tris = grid(4, 0.0)
    tilted_pos = list(flat_pos)
    for v in range(len(tilted_pos) // 3):
        tilted_pos[3 * v + 2] = 0.5 * tilted_pos[3 * v + 1] - 1.03  # crosses z = 0 at y = 2.06
    status_f, flat = create(flat_pos, flat_tris)
    status_t, tilted = create(tilted_pos, flat_tris)
    check(status_f == DVH_STATUS_OK and status_t == DVH_STATUS_OK, "curve meshes created")
    curves = lib.dvh_curves_new()
    stats = DvhQueryStats()
    check(lib.dvh_intersection_curves(flat, None, tilted, None, None, curves, ctypes.byref(stats)) == DVH_STATUS_OK,
          "intersection curves")
    n = lib.dvh_curves_len(curves)
    data = lib.dvh_curves_data(curves)
    first, count, closed = ctypes.c_size_t(), ctypes.c_size_t(), ctypes.c_bool()
    check(n > 0 and stats.pairs == n + lib.dvh_curves_degenerate_len(curves) and lib.dvh_curves_curve_count(curves) == 1
          and lib.dvh_curves_curve(curves, 0, ctypes.byref(first), ctypes.byref(count), ctypes.byref(closed)) == DVH_STATUS_OK
          and first.value == 0 and count.value == n and not closed.value, "one open curve across the sheet")
    check(all(abs(data[i].start[1] - 2.06) < 1e-12 and abs(data[i].start[2]) == 0.0 for i in range(n))
          and all(tuple(data[i].end) == tuple(data[i + 1].start) for i in range(n - 1)), "a chain along y = 2.06 in z = 0")
    check(lib.dvh_curves_curve(curves, 1, ctypes.byref(first), ctypes.byref(count), ctypes.byref(closed))
          == DVH_STATUS_INVALID_ARGUMENT and "out of range" in last_error(), "curve index out of range refused")
    check(lib.dvh_curves_curve(curves, 0, None, ctypes.byref(count), ctypes.byref(closed)) == DVH_STATUS_NULL_ARGUMENT,
          "NULL out-pointer refused")
    leaves = DvhQueryOptions(mode=2)
    check(lib.dvh_intersection_curves(flat, None, tilted, None, ctypes.byref(leaves), curves, None)
          == DVH_STATUS_INVALID_ARGUMENT and lib.dvh_curves_len(curves) == n, "a coarse mode refused, curves kept")
    nv = len(flat_pos) // 3
    ga, gb = (ctypes.c_double * (3 * nv))(), (ctypes.c_double * (3 * nv))()
    check(lib.dvh_curves_length_gradient(curves, flat, None, tilted, None, ga, nv, gb, nv) == DVH_STATUS_OK
          and any(x != 0.0 for x in ga), "length gradient")
    check(lib.dvh_curves_length_gradient(curves, flat, None, tilted, None, ga, nv - 1, gb, nv) == DVH_STATUS_INVALID_ARGUMENT,
          "a gradient of the wrong length refused")
    lib.dvh_curves_free(curves)
    lib.dvh_mesh_free(flat)
    lib.dvh_mesh_free(tilted)

    # Distances: the sheet and the tent lifted by 10 (its lowest corner 9 above the sheet); the
    # winding numbers and signed distances of a closed tetrahedron.
    class DvhDistanceOptions(ctypes.Structure):
        _fields_ = [("max_distance", ctypes.c_double), ("rel_err", ctypes.c_double), ("abs_err", ctypes.c_double),
                    ("threads", ctypes.c_uint32), ("reserved", ctypes.c_uint32)]

    class DvhDistance(ctypes.Structure):
        _fields_ = [(n, ctypes.c_uint32) for n in ("found", "intersecting", "triangle_a", "triangle_b")] + [
            ("distance", ctypes.c_double), ("closest_a", ctypes.c_double * 3), ("closest_b", ctypes.c_double * 3),
            ("stencil", DvhNearPair)]

    check(ctypes.sizeof(DvhDistanceOptions) == 32 and ctypes.sizeof(DvhDistance) == 208, "distance layouts")
    lib.dvh_distance_options_default.restype = DvhDistanceOptions
    lib.dvh_distance.restype = DvhStatus
    lib.dvh_distance.argtypes = [MeshPtr, ctypes.POINTER(DvhPose), MeshPtr, ctypes.POINTER(DvhPose),
                                 ctypes.POINTER(DvhDistanceOptions), ctypes.POINTER(DvhDistance), ctypes.POINTER(DvhQueryStats)]
    lib.dvh_mesh_is_closed.restype = DvhStatus
    lib.dvh_mesh_is_closed.argtypes = [MeshPtr, ctypes.POINTER(ctypes.c_bool)]
    lib.dvh_winding_numbers.restype = DvhStatus
    lib.dvh_winding_numbers.argtypes = [MeshPtr, ctypes.POINTER(DvhPose), ctypes.POINTER(ctypes.c_double), ctypes.c_size_t,
                                        ctypes.c_uint32, ctypes.POINTER(ctypes.c_int32)]
    lib.dvh_signed_distances.restype = DvhStatus
    lib.dvh_signed_distances.argtypes = [MeshPtr, ctypes.POINTER(DvhPose), ctypes.POINTER(ctypes.c_double), ctypes.c_size_t,
                                         ctypes.POINTER(DvhDistanceOptions), ctypes.POINTER(ctypes.c_double),
                                         ctypes.POINTER(DvhQueryStats)]
    options = lib.dvh_distance_options_default()
    check(options.max_distance == float("inf") and options.rel_err == 0.0, "distance defaults")
    # (The continuous tests above left the tent at the end of its motion.)
    check(lib.dvh_mesh_refit(tent, (ctypes.c_double * 12)(*tent_pos), 4) == DVH_STATUS_OK, "tent back")
    d = DvhDistance()
    check(lib.dvh_distance(sheet, None, tent, ctypes.byref(pose), ctypes.byref(options), ctypes.byref(d), None)
          == DVH_STATUS_OK and d.found == 1 and d.intersecting == 0 and d.distance == 9.0, "distance of sheet and lifted tent")
    check(lib.dvh_distance(sheet, None, tent, None, None, ctypes.byref(d), None) == DVH_STATUS_OK
          and d.intersecting == 1 and d.distance == 0.0, "the tent through the sheet intersects it")
    options.max_distance = -1.0
    check(lib.dvh_distance(sheet, None, tent, None, ctypes.byref(options), ctypes.byref(d), None)
          == DVH_STATUS_INVALID_ARGUMENT and "max_distance" in last_error(), "a negative bound refused")
    status, tet = create([0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 4.0], [0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3])
    closed = ctypes.c_bool(False)
    check(status == DVH_STATUS_OK and lib.dvh_mesh_is_closed(tet, ctypes.byref(closed)) == DVH_STATUS_OK and closed.value,
          "the tetrahedron is closed")
    check(lib.dvh_mesh_is_closed(sheet, ctypes.byref(closed)) == DVH_STATUS_OK and not closed.value, "the sheet is open")
    points = (ctypes.c_double * 9)(1, 1, 1, 5, 5, 5, 0, 0, 0)
    winding = (ctypes.c_int32 * 3)()
    check(lib.dvh_winding_numbers(tet, None, points, 3, 0, winding) == DVH_STATUS_OK
          and list(winding) == [1, 0, -2**31], "winding numbers: inside, outside, on a corner")
    signed = (ctypes.c_double * 3)()
    check(lib.dvh_signed_distances(tet, None, points, 3, None, signed, None) == DVH_STATUS_OK
          and signed[0] < 0 and signed[1] > 0 and signed[2] == 0.0, "signed distances")
    check(lib.dvh_winding_numbers(sheet, None, points, 3, 0, winding) == DVH_STATUS_NOT_CLOSED
          and "not closed" in last_error(), "an open mesh refused")
    lib.dvh_mesh_free(tet)

    lib.dvh_pairs_free(pairs)
    lib.dvh_mesh_free(sheet)
    lib.dvh_mesh_free(tent)
    if failures:
        print("test_ctypes: failed:", *failures, sep="\n  ")
        return 1
    print("test_ctypes: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
