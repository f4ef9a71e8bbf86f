//! Scenes through the C ABI: objects, filters, self-contact, steps (motions and pose motions),
//! the frame's query and its contact buffer. The queries over a step are beside the mesh
//! queries they extend: `dvh_scene_continuous_collide` in `ccd.rs`,
//! `dvh_scene_nearest_features` in `nearest.rs`.

use super::access::{SCENE_TAG, Write, read, release, write};
use super::boundary::{Failure, guard, guard_value, slice_from, times_three, try_box};
use super::calls::{Call, pose};
use super::handles::*;
use super::mesh::StridedF32;
use super::results;
use super::types::*;
use crate::{Mesh, Pose, Scene};

/// Creates an empty scene and writes it to `*scene_out`. Release it with `dvh_scene_free`.
///
/// Errors: NULL_ARGUMENT; OUT_OF_MEMORY.
///
/// Thread safety: any thread, any time.
///
/// # Safety
/// `scene_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_create(scene_out: *mut *mut DvhScene) -> DvhStatus {
    guard(|| {
        if scene_out.is_null() {
            return Err(Failure::null("scene_out"));
        }
        let ptr = try_box(DvhScene(Body::new(SCENE_TAG, Scene::new())))?;
        // SAFETY: non-NULL (checked) and writable per the contract.
        unsafe { scene_out.write(ptr) };
        Ok(())
    })
}

/// Releases a scene and its objects (not the meshes they were made from). NULL is a no-op.
///
/// Thread safety: needs exclusive access to `scene`; it must not be used afterwards.
///
/// # Safety
/// `scene` is NULL or a live scene from `dvh_scene_create`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_free(scene: *mut DvhScene) {
    // SAFETY: allocated by `try_box` and owned by the caller (contract).
    guard_value((), || unsafe { release(scene, "scene", "dvh_scene_free") })
}

/// The scene behind `scene`, for entry point `call`, which changes it.
///
/// # Safety
/// `scene` is NULL or a live scene.
unsafe fn scene_mut<'a>(scene: *mut DvhScene, call: &str) -> Result<Write<'a, Scene>, Failure> {
    // SAFETY: per the contract.
    unsafe { write(scene, "scene", call) }
}

/// Adds an object made from `mesh` with `make` and writes its id to `*object_out`.
///
/// # Safety
/// `scene` is NULL or a live scene used by no other thread; `mesh` is NULL or a live mesh not
/// being refit; `object_out` is NULL or writable.
unsafe fn add(
    scene: *mut DvhScene,
    mesh: *const DvhMesh,
    object_out: *mut u32,
    call: &str,
    make: impl FnOnce(&mut Scene, &Mesh) -> Result<u32, Failure>,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let (mut s, m) = unsafe { (scene_mut(scene, call)?, read(mesh, "mesh", call)?) };
        if object_out.is_null() {
            return Err(Failure::null("object_out"));
        }
        let id = make(&mut s, &m)?;
        // SAFETY: non-NULL (checked), writable (contract).
        unsafe { object_out.write(id) };
        Ok(())
    })
}

/// Adds a rigid object: `mesh`'s current positions as local coordinates, placed by `pose` (NULL:
/// the identity). The object shares the mesh's topology, rings and tree, and keeps its own copy
/// of the positions and volumes: the mesh may be refit or freed afterwards without affecting
/// it. Objects `i` and `j` are tested when `group_i & mask_j` and `group_j & mask_i` are both
/// non-zero. The new object's id goes to `*object_out`: a small integer, stable until the
/// object is removed (a removed id may be given to a later object).
///
/// Errors: NULL_ARGUMENT (`scene`, `mesh`, `object_out`); NON_FINITE_COORDINATE and
/// NON_RIGID_POSE (the pose); POSE_OUT_OF_RANGE; OUT_OF_MEMORY; INTERNAL_PANIC (a mesh whose
/// refit panicked). On failure the scene is unchanged.
///
/// Thread safety: exclusive access to `scene`; `mesh` is only read (no refit of it meanwhile).
///
/// # Safety
/// `scene` is NULL or a live scene; `mesh` is NULL or a live mesh; `pose` is NULL or readable;
/// `object_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_add_rigid(
    scene: *mut DvhScene,
    mesh: *const DvhMesh,
    pose: *const DvhPose,
    group: u32,
    mask: u32,
    object_out: *mut u32,
) -> DvhStatus {
    // SAFETY: NULL or readable (contract); read inside the guard below.
    let pose = unsafe { pose.as_ref() };
    // SAFETY: the caller's contract is `add`'s.
    unsafe {
        add(scene, mesh, object_out, "dvh_scene_add_rigid", |s, m| {
            let p = pose.map(|p| self::pose(p, "pose")).transpose()?;
            Ok(s.add_rigid(m, p.as_ref(), group, mask)?)
        })
    }
}

/// Adds a deformable object: `mesh`'s current positions as world coordinates, changed by
/// `dvh_scene_set_positions`. It shares the mesh's topology, rings and tree and keeps its own
/// positions and volumes; filters and ids as for `dvh_scene_add_rigid`.
///
/// Errors: NULL_ARGUMENT; OUT_OF_MEMORY; INTERNAL_PANIC (a mesh whose refit panicked). On
/// failure the scene is unchanged.
///
/// Thread safety: as `dvh_scene_add_rigid`.
///
/// # Safety
/// `scene` is NULL or a live scene; `mesh` is NULL or a live mesh; `object_out` is NULL or
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_add_deformable(
    scene: *mut DvhScene,
    mesh: *const DvhMesh,
    group: u32,
    mask: u32,
    object_out: *mut u32,
) -> DvhStatus {
    // SAFETY: the caller's contract is `add`'s.
    unsafe {
        add(
            scene,
            mesh,
            object_out,
            "dvh_scene_add_deformable",
            |s, m| Ok(s.add_deformable(m, group, mask)?),
        )
    }
}

/// Places rigid object `object` by `pose` (NULL: the identity), standing still there: its step
/// (`dvh_scene_set_pose_motion`), if it had one, ends.
///
/// Errors: NULL_ARGUMENT (`scene`); INVALID_ARGUMENT (an unknown or removed id, a deformable
/// object); NON_FINITE_COORDINATE and NON_RIGID_POSE (the pose); POSE_OUT_OF_RANGE. On failure
/// the scene is unchanged.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene; `pose` is NULL or readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_pose(
    scene: *mut DvhScene,
    object: u32,
    pose: *const DvhPose,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let mut s = unsafe { scene_mut(scene, "dvh_scene_set_pose")? };
        // SAFETY: NULL or readable (contract).
        let p: Option<Pose> = unsafe { pose.as_ref() }
            .map(|p| self::pose(p, "pose"))
            .transpose()?;
        s.set_pose(object, p.as_ref())?;
        Ok(())
    })
}

/// Checks an object's vertex count before its positions are read.
fn check_vertex_count(s: &Scene, object: u32, vertex_count: usize) -> Result<(), Failure> {
    let n = s.vertex_count(object)?;
    if vertex_count != n {
        return Err(Failure::invalid(format!(
            "vertex_count = {vertex_count}, but object {object} has {n} vertices"
        )));
    }
    Ok(())
}

/// Gives deformable object `object` new world positions (`x, y, z` per vertex, as many vertices
/// as its mesh), standing still there: its step (`dvh_scene_set_motion`), if it had one, ends.
/// They are checked and stored now; its volumes are recomputed by the next query that needs
/// them.
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (an unknown or removed id, a rigid object, a
/// different vertex count, a misaligned array); NON_FINITE_COORDINATE. On failure the scene is
/// unchanged.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene; `positions` points to `3 * vertex_count` readable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_positions(
    scene: *mut DvhScene,
    object: u32,
    positions: *const f64,
    vertex_count: usize,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let mut s = unsafe { scene_mut(scene, "dvh_scene_set_positions")? };
        check_vertex_count(&s, object, vertex_count)?;
        let len = times_three(vertex_count, "vertex_count")?;
        // SAFETY: readable per the contract; NULL, alignment and size are checked inside.
        let positions = unsafe { slice_from(positions, len, "positions")? };
        s.set_positions(object, positions)?;
        Ok(())
    })
}

/// `dvh_scene_set_positions` with `float` positions at a byte stride (see
/// `dvh_mesh_create_f32`).
///
/// Errors: as `dvh_scene_set_positions`, plus INVALID_ARGUMENT for a stride below 12 bytes. On
/// failure the scene is unchanged.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene; for each `i < vertex_count`, 12 bytes at
/// `positions + i * stride_bytes` are readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_positions_f32(
    scene: *mut DvhScene,
    object: u32,
    positions: *const f32,
    stride_bytes: usize,
    vertex_count: usize,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let mut s = unsafe { scene_mut(scene, "dvh_scene_set_positions_f32")? };
        check_vertex_count(&s, object, vertex_count)?;
        // SAFETY: readable per the contract; NULL, stride and span are checked inside.
        let reader =
            unsafe { StridedF32::new(positions, "positions", stride_bytes, vertex_count)? };
        s.set_positions_with(object, vertex_count, |i| reader.get(i))?;
        Ok(())
    })
}

/// Turns the self-contact of object `object` on or off (off when added). When on,
/// `dvh_scene_collide` also reports the object's self-intersecting triangle pairs as
/// `dvh_self_collide` does (contacts with `object_a == object_b`), `dvh_scene_continuous_collide`
/// its self impacts and `dvh_scene_nearest_features` its self stencils. Groups, masks and
/// exclusions do not gate self-contact; this switch does. Only a deformable object can touch
/// itself: turning it on for a rigid object is refused, turning it off accepted.
///
/// Errors: NULL_ARGUMENT (`scene`); INVALID_ARGUMENT (an unknown or removed id; `on` for a rigid
/// object). On failure the scene is unchanged.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_self_contact(
    scene: *mut DvhScene,
    object: u32,
    on: bool,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        unsafe { scene_mut(scene, "dvh_scene_set_self_contact")? }.set_self_contact(object, on)?;
        Ok(())
    })
}

/// Gives deformable object `object` a step: every vertex moves in a straight line from its
/// position in `start` (t = 0) to its position in `end` (t = 1), `x, y, z` per vertex, as many
/// vertices as its mesh (as `dvh_mesh_refit_motion` takes them). `dvh_scene_collide` and
/// `dvh_scene_nearest_features` see the object at `end`; `dvh_scene_continuous_collide` sees the
/// whole step. The step lasts until the next `dvh_scene_set_motion` or
/// `dvh_scene_set_positions`. Checked and stored now; the volumes are refit by the next query
/// that needs the object.
///
/// Errors: NULL_ARGUMENT (`scene`, `start`, `end`); INVALID_ARGUMENT (an unknown or removed id,
/// a rigid object, a different vertex count, a misaligned array); NON_FINITE_COORDINATE (the
/// message names the object, the array, the vertex and the axis). On failure the scene is
/// unchanged (the object keeps its step, or its stillness).
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene; `start` and `end` each point to `3 * vertex_count` readable
/// doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_motion(
    scene: *mut DvhScene,
    object: u32,
    start: *const f64,
    end: *const f64,
    vertex_count: usize,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let mut s = unsafe { scene_mut(scene, "dvh_scene_set_motion")? };
        check_vertex_count(&s, object, vertex_count)?;
        let len = times_three(vertex_count, "vertex_count")?;
        // SAFETY: readable per the contract; NULL, alignment and size are checked inside.
        let (start, end) = unsafe {
            (
                slice_from(start, len, "start")?,
                slice_from(end, len, "end")?,
            )
        };
        s.set_motion(object, start, end)?;
        Ok(())
    })
}

/// `dvh_scene_set_motion` with `float` positions at a byte stride, the same stride for `start`
/// and `end` (see `dvh_mesh_create_f32`).
///
/// Errors: as `dvh_scene_set_motion`, plus INVALID_ARGUMENT for a stride below 12 bytes. On
/// failure the scene is unchanged.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene; for each `i < vertex_count`, 12 bytes at
/// `start + i * stride_bytes` and at `end + i * stride_bytes` are readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_motion_f32(
    scene: *mut DvhScene,
    object: u32,
    start: *const f32,
    end: *const f32,
    stride_bytes: usize,
    vertex_count: usize,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let mut s = unsafe { scene_mut(scene, "dvh_scene_set_motion_f32")? };
        check_vertex_count(&s, object, vertex_count)?;
        // SAFETY: readable per the contract; NULL, stride and span are checked inside.
        let (first, last) = unsafe {
            (
                StridedF32::new(start, "start", stride_bytes, vertex_count)?,
                StridedF32::new(end, "end", stride_bytes, vertex_count)?,
            )
        };
        s.set_motion_with(object, vertex_count, |i| first.get(i), |i| last.get(i))?;
        Ok(())
    })
}

/// Gives rigid object `object` a step: from pose `start` to pose `end` (NULL: the identity),
/// each vertex moving in a straight line from where `start` places it to where `end` does.
/// `dvh_scene_collide` and `dvh_scene_nearest_features` see the object at `end`;
/// `dvh_scene_continuous_collide` sees the whole step. The step lasts until the next
/// `dvh_scene_set_pose` or `dvh_scene_set_pose_motion`. Straight paths are not the turn itself:
/// a large rotation in one step shortens the object midway, so steps should turn little.
///
/// Errors: NULL_ARGUMENT (`scene`); INVALID_ARGUMENT (an unknown or removed id, a deformable
/// object); NON_FINITE_COORDINATE and NON_RIGID_POSE (either pose, named `start` or `end`);
/// POSE_OUT_OF_RANGE. On failure the scene is unchanged.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene; `start` and `end` are NULL or readable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_pose_motion(
    scene: *mut DvhScene,
    object: u32,
    start: *const DvhPose,
    end: *const DvhPose,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        let mut s = unsafe { scene_mut(scene, "dvh_scene_set_pose_motion")? };
        // SAFETY: NULL or readable (contract).
        let (start, end) = unsafe { (start.as_ref(), end.as_ref()) };
        let first: Option<Pose> = start.map(|p| pose(p, "start")).transpose()?;
        let last: Option<Pose> = end.map(|p| pose(p, "end")).transpose()?;
        s.set_pose_motion(object, first.as_ref(), last.as_ref())?;
        Ok(())
    })
}

/// Removes object `object` and its pair exclusions; its id may be given to a later object.
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (an unknown or removed id).
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_remove(scene: *mut DvhScene, object: u32) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        unsafe { scene_mut(scene, "dvh_scene_remove")? }.remove(object)?;
        Ok(())
    })
}

/// Never tests objects `object_a` and `object_b` against each other (until one is removed).
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (an unknown or removed id, the same object twice).
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_exclude_pair(
    scene: *mut DvhScene,
    object_a: u32,
    object_b: u32,
) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        unsafe { scene_mut(scene, "dvh_scene_exclude_pair")? }.exclude_pair(object_a, object_b)?;
        Ok(())
    })
}

/// Whether `dvh_scene_collide` refits box volumes lazily (`true`, the default: each block of
/// about 32 rings of a deformable object's tree when a traversal first reaches it, so the parts
/// no other object comes near are never refit) or every deformable object it needs whole
/// (`false`). The contacts are the same either way; `BENCHMARKS.md` measures both.
///
/// Errors: NULL_ARGUMENT.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_set_lazy_refit(scene: *mut DvhScene, lazy: bool) -> DvhStatus {
    guard(|| {
        // SAFETY: per the contract.
        unsafe { scene_mut(scene, "dvh_scene_set_lazy_refit")? }.set_lazy_refit(lazy);
        Ok(())
    })
}

/// Every contact of the frame: for every two objects that the filters allow (groups and masks,
/// exclusions) and whose world boxes overlap, exactly what `dvh_collide` reports for the two
/// objects' current geometry and poses, and for every object with self-contact on
/// (`dvh_scene_set_self_contact`) what `dvh_self_collide` reports for it (contacts with
/// `object_a == object_b`), in the mode `options` asks (NULL: the defaults; in
/// `DVH_QUERY_MODE_FIRST_HIT` at most one contact per object pair). Objects given a step are seen
/// at its end. The contacts replace those in `contacts_out`, sorted by
/// `(object_a, object_b, a, b)`; `max_pairs` bounds the whole result. The counters go to
/// `*stats_out` unless it is NULL. Deformable objects whose positions changed are refit here, only
/// those a pair needs (every one in the coarse modes); with box volumes (the default), in the modes
/// that report triangles, only the blocks of their trees that a traversal reaches (the boxes, and
/// so the result, are the eager refit's; objects with self-contact on are refit whole). Object
/// pairs are shared among `options->threads` threads; the result does not depend on the count
/// (threads reaching one object refit each of its blocks once, under a lock per object). On failure
/// neither `contacts_out` nor `*stats_out` changes.
///
/// Errors: NULL_ARGUMENT (`scene`, `contacts_out`); INVALID_ARGUMENT (options out of range, a
/// budget of 0); OUT_OF_MEMORY (set `max_pairs`).
///
/// Thread safety: exclusive access to `scene` (the query refits objects), and a `contacts_out`
/// used by no other thread; otherwise refused with BUSY, nothing changed (as every
/// `dvh_scene_*` call that needs exclusive access).
///
/// # Safety
/// `scene` is NULL or a live scene; `options` is NULL or readable; `contacts_out` is NULL or a
/// live buffer; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_collide(
    scene: *mut DvhScene,
    options: *const DvhQueryOptions,
    contacts_out: *mut DvhContacts,
    stats_out: *mut DvhSceneStats,
) -> DvhStatus {
    let call = Call::new("dvh_scene_collide", options, contacts_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe { call.whole_scene(scene, |s, o, out| s.collide(o, out)) }
}

/// A new, empty contact buffer, or NULL when memory ran out. Owned by the caller, released with
/// `dvh_contacts_free`. It keeps the scratch space of the queries that use it, so that once it
/// has grown to a scene's needs queries allocate nothing.
///
/// Thread safety: any thread; a buffer must be used by one thread at a time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_contacts_new() -> *mut DvhContacts {
    results::new()
}

/// Number of contacts of the last successful query into `contacts` (0 for NULL or a new
/// buffer).
///
/// Thread safety: not alongside a query writing the same buffer (0 then).
///
/// # Safety
/// `contacts` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_contacts_len(contacts: *const DvhContacts) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::len(contacts, "dvh_contacts_len") }
}

/// The contacts of the last successful query into `contacts`: `dvh_contacts_len(contacts)`
/// entries, sorted by `(object_a, object_b, a, b)`, without duplicates. NULL when there are
/// none. Owned by the buffer; valid until the next query into it or `dvh_contacts_free`.
///
/// Thread safety: as `dvh_contacts_len`.
///
/// # Safety
/// `contacts` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_contacts_data(contacts: *const DvhContacts) -> *const DvhContact {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::data(contacts, "dvh_contacts_data") }
}

/// What the indices `a` and `b` of the contacts in `contacts` refer to:
/// `DVH_PAIR_KIND_TRIANGLES` or `DVH_PAIR_KIND_NODES` (triangles for NULL or a new buffer).
///
/// Thread safety: as `dvh_contacts_len`.
///
/// # Safety
/// `contacts` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_contacts_kind(contacts: *const DvhContacts) -> DvhPairKind {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::kind(contacts, "dvh_contacts_kind") }
}

/// Releases a contact buffer. NULL is a no-op.
///
/// Thread safety: needs exclusive access; the buffer must not be used afterwards. A buffer in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `contacts` is NULL or a live buffer from `dvh_contacts_new`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_contacts_free(contacts: *mut DvhContacts) {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::free(contacts, "dvh_contacts_free") }
}
