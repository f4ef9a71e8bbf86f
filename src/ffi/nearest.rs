//! Closest-point stencils through the C ABI: the queries of two meshes, of one and of a whole
//! scene, and their result buffers.

use super::calls::Call;
use super::handles::*;
use super::results;
use super::types::*;
use crate::{nearest_features, self_nearest_features};

/// Every vertex-face and edge-edge pair of mesh `a` placed by `pose_a` and mesh `b` placed by
/// `pose_b` (NULL: identity) whose distance is at most `distance`, with the distance, the
/// closest point on each primitive, its barycentric weights and the feature it lies on: the
/// stencils from which repulsion, barrier and constraint forces are built. Each vertex of `a`
/// against each triangle of `b` (VERTEX_FACE), each triangle of `a` against each vertex of `b`
/// (FACE_VERTEX), each edge of `a` against each edge of `b` (EDGE_EDGE; an edge is a pair of
/// distinct vertices joined by a triangle side, reported once). Vertices of no triangle are
/// not tested.
///
/// The decision "distance <= d" is exact for the placed coordinates, so `distance = 0` gives
/// the touching pairs. The distance is within one unit in the last place of the correctly
/// rounded one, points and weights within two units of the exact ones; where the closest
/// points are not unique (parallel edges), the pair is taken at an end, tried in the order
/// a0, a1, b0, b1, the first of the closest kept.
///
/// `options` (NULL: the defaults): TRIANGLES reports every stencil; FIRST_HIT the first found
/// in the traversal's order (the same whatever the thread count), or none; LEAVES, DEPTH and
/// BUDGET stop the traversal where they say and test every primitive pair under the node pairs
/// it reaches, so the stencils are the same as TRIANGLES' (a budget bounds the traversal only).
/// `max_pairs` stops the query once that many stencils are found; `threads` shares the work
/// out, the result the same for every count. In the counters, `triangle_tests` counts the
/// primitive pairs given to the exact test.
///
/// On success the stencils replace the contents of `pairs_out`, sorted by
/// `(kind, a0, a1, b0, b1)`, and the counters go to `*stats_out` unless it is NULL; on failure
/// neither changes.
///
/// Errors: NULL_ARGUMENT (`a`, `b`, `pairs_out`); INVALID_ARGUMENT (a negative, NaN or infinite
/// `distance`; options out of range; a pointer that is not a live handle); NON_FINITE_COORDINATE
/// and NON_RIGID_POSE (a pose); POSE_OUT_OF_RANGE; BUSY; OUT_OF_MEMORY (set `max_pairs`);
/// INTERNAL_PANIC.
///
/// Thread safety: `a` and `b` are only read: any number of threads may query them at once, each
/// with its own `pairs_out`; no refit of either may run meanwhile (BUSY).
///
/// # Safety
/// `a` and `b` are NULL or live meshes; `pose_a`, `pose_b` and `options` are NULL or readable;
/// `pairs_out` is NULL or a live buffer used by no other thread; `stats_out` is NULL or
/// writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)] // the C signature the issue fixes
pub unsafe extern "C" fn dvh_nearest_features(
    a: *const DvhMesh,
    pose_a: *const DvhPose,
    b: *const DvhMesh,
    pose_b: *const DvhPose,
    distance: f64,
    options: *const DvhQueryOptions,
    pairs_out: *mut DvhNearPairs,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_nearest_features", options, pairs_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe {
        call.two_meshes((a, pose_a), (b, pose_b), |ma, pa, mb, pb, o, out| {
            nearest_features(ma, pa, mb, pb, distance, o, out)
        })
    }
}

/// The stencils of one mesh with itself: each vertex against each triangle that does not
/// contain it (VERTEX_FACE, the vertex in `a0`), each pair of edges that share no vertex
/// (EDGE_EDGE, `(a0, a1) < (b0, b1)`), at distance at most `distance`. No FACE_VERTEX pairs.
/// Otherwise as `dvh_nearest_features`.
///
/// Errors: NULL_ARGUMENT (`mesh`, `pairs_out`); INVALID_ARGUMENT; BUSY; OUT_OF_MEMORY;
/// INTERNAL_PANIC.
///
/// Thread safety: as `dvh_nearest_features`.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `options` is NULL or readable; `pairs_out` is NULL or a live
/// buffer used by no other thread; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_self_nearest_features(
    mesh: *const DvhMesh,
    distance: f64,
    options: *const DvhQueryOptions,
    pairs_out: *mut DvhNearPairs,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_self_nearest_features", options, pairs_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe { call.one_mesh(mesh, |m, o, out| self_nearest_features(m, distance, o, out)) }
}

/// A new, empty stencil buffer, or NULL when memory ran out. Owned by the caller, released with
/// `dvh_near_pairs_free`. It keeps the scratch space of the queries that use it.
///
/// Thread safety: any thread; a buffer must be used by one thread at a time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_near_pairs_new() -> *mut DvhNearPairs {
    results::new()
}

/// Number of stencils of the last successful query into `pairs` (0 for NULL or a new buffer).
///
/// Thread safety: not alongside a query writing the same buffer (0 then).
///
/// # Safety
/// `pairs` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_near_pairs_len(pairs: *const DvhNearPairs) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::len(pairs, "dvh_near_pairs_len") }
}

/// The stencils of the last successful query into `pairs`: `dvh_near_pairs_len(pairs)`
/// entries, sorted by `(kind, a0, a1, b0, b1)`. NULL when there are none. Owned by the buffer;
/// valid until the next query into it or `dvh_near_pairs_free`.
///
/// Thread safety: as `dvh_near_pairs_len`.
///
/// # Safety
/// `pairs` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_near_pairs_data(pairs: *const DvhNearPairs) -> *const DvhNearPair {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::data(pairs, "dvh_near_pairs_data") }
}

/// Releases a stencil buffer. NULL is a no-op.
///
/// Thread safety: needs exclusive access; the buffer must not be used afterwards. A buffer in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `pairs` is NULL or a live buffer from `dvh_near_pairs_new`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_near_pairs_free(pairs: *mut DvhNearPairs) {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::free(pairs, "dvh_near_pairs_free") }
}

/// Every stencil of a scene within `distance`: for every two objects that the filters allow
/// (groups and masks, exclusions) and whose boxes come within `distance`, exactly what
/// `dvh_nearest_features` reports for the two objects' meshes and poses, `object_a`'s first;
/// and for every object with self-contact on (`dvh_scene_set_self_contact`), what
/// `dvh_self_nearest_features` reports for it (`object_a == object_b`). Objects given a step
/// are seen at its end. `options` (NULL: the defaults) as for `dvh_nearest_features`, applied
/// to each pair (`DVH_QUERY_MODE_FIRST_HIT`: at most one stencil per object pair); the result
/// is the same for every thread count.
///
/// On success the stencils replace the contents of `pairs_out`, sorted by
/// `(object_a, object_b)`, then as each pair's own query sorts them, and the counters go to
/// `*stats_out` unless it is NULL; on failure neither changes. With `max_pairs`, each pair's
/// query keeps what its own query with that limit keeps, and the result the first of those in
/// the scene's order, at most the limit (`truncated` says when anything was left out). The
/// counters are sums over the object pairs queried; `pairs` counts the stencils reported and
/// `nodes_refit` the nodes the query's refits recomputed.
///
/// Deformable objects whose positions changed are refit here, whole, and only those some pair
/// needs.
///
/// Errors: NULL_ARGUMENT (`scene`, `pairs_out`); INVALID_ARGUMENT (a negative, NaN or infinite
/// `distance`; options out of range; a pointer that is not a live handle of its kind); BUSY;
/// OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: exclusive access to `scene` (the query refits objects) and a `pairs_out` used
/// by no other thread; otherwise refused with BUSY, nothing changed.
///
/// # Safety
/// `scene` is NULL or a live scene; `options` is NULL or readable; `pairs_out` is NULL or a live
/// buffer; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_nearest_features(
    scene: *mut DvhScene,
    distance: f64,
    options: *const DvhQueryOptions,
    pairs_out: *mut DvhSceneNearPairs,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_scene_nearest_features", options, pairs_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe { call.whole_scene(scene, |s, o, out| s.nearest_features(distance, o, out)) }
}

/// A new, empty buffer for a scene's stencils, or NULL when memory ran out. Owned by the caller,
/// released with `dvh_scene_near_pairs_free`. It keeps the scratch space of the queries that use
/// it.
///
/// Thread safety: any thread; a buffer must be used by one thread at a time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_scene_near_pairs_new() -> *mut DvhSceneNearPairs {
    results::new()
}

/// Number of stencils of the last successful query into `pairs` (0 for NULL or a new buffer).
///
/// Thread safety: not alongside a query writing the same buffer (0 then).
///
/// # Safety
/// `pairs` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_near_pairs_len(pairs: *const DvhSceneNearPairs) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::len(pairs, "dvh_scene_near_pairs_len") }
}

/// The stencils of the last successful query into `pairs`: `dvh_scene_near_pairs_len(pairs)`
/// entries, sorted by `(object_a, object_b)`, then by `(kind, a0, a1, b0, b1)`. NULL when there
/// are none. Owned by the buffer; valid until the next query into it or
/// `dvh_scene_near_pairs_free`.
///
/// Thread safety: as `dvh_scene_near_pairs_len`.
///
/// # Safety
/// `pairs` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_near_pairs_data(
    pairs: *const DvhSceneNearPairs,
) -> *const DvhSceneNearPair {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::data(pairs, "dvh_scene_near_pairs_data") }
}

/// Releases a buffer of a scene's stencils. NULL is a no-op.
///
/// Thread safety: needs exclusive access; the buffer must not be used afterwards. A buffer in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `pairs` is NULL or a live buffer from `dvh_scene_near_pairs_new`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_near_pairs_free(pairs: *mut DvhSceneNearPairs) {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::free(pairs, "dvh_scene_near_pairs_free") }
}
