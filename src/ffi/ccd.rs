//! Continuous collision through the C ABI: the primitive tests, the motion refit, the queries
//! of two meshes, of one and of a whole scene, and their result buffers.

use super::boundary::{
    Failure, choice, guard, guard_value, slice_from, times_three, write_unless_null,
};
use super::calls::{Call, CallOptions};
use super::handles::*;
use super::mesh::refit_guarded;
use super::results;
use super::types::*;
use crate::exact::{Point, edge_edge_impact_with, vertex_face_impact_with};
use crate::{CcdMode, CcdOptions, continuous_collide, self_continuous_collide};

/// The default continuous options: exact, every core, no impact limit, every impact (all
/// fields zero).
///
/// Thread safety: any thread, any time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_ccd_options_default() -> DvhCcdOptions {
    const DEFAULT: DvhCcdOptions = DvhCcdOptions {
        mode: DVH_CCD_MODE_EXACT,
        threads: 0,
        max_impacts: 0,
        earliest_only: false,
    };
    guard_value(DEFAULT, || DEFAULT)
}

impl CallOptions for DvhCcdOptions {
    type Options = CcdOptions;

    unsafe fn read_or_default(o: *const DvhCcdOptions) -> Result<CcdOptions, Failure> {
        // SAFETY: NULL or readable (contract).
        let Some(o) = (unsafe { o.as_ref() }) else {
            return Ok(CcdOptions::default());
        };
        let mode = choice(
            "mode",
            "DVH_CCD_MODE",
            o.mode,
            &[
                (DVH_CCD_MODE_EXACT, CcdMode::Exact),
                (DVH_CCD_MODE_CONSERVATIVE, CcdMode::Conservative),
            ],
        )?;
        let max_impacts =
            (o.max_impacts != 0).then(|| usize::try_from(o.max_impacts).unwrap_or(usize::MAX));
        Ok(CcdOptions::default()
            .with_mode(mode)
            .with_threads(o.threads)
            .with_max_impacts(max_impacts)
            .with_earliest_only(o.earliest_only))
    }
}

/// A continuous primitive test of the Rust API.
type PrimitiveTest = fn(&[Point; 4], &[Point; 4], CcdMode) -> crate::Result<Option<f64>>;

/// A primitive test from C: four points at the start and at the end, checked, tested.
///
/// # Safety
/// As `dvh_ccd_vertex_face`'s.
unsafe fn primitive(
    start: *const f64,
    end: *const f64,
    options: *const DvhCcdOptions,
    hit_out: *mut bool,
    toi_out: *mut f64,
    test: PrimitiveTest,
) -> DvhStatus {
    guard(|| {
        if hit_out.is_null() {
            return Err(Failure::null("hit_out"));
        }
        // SAFETY: 12 readable doubles each (contract); NULL and alignment checked inside.
        let (s, e) = unsafe { (slice_from(start, 12, "start")?, slice_from(end, 12, "end")?) };
        for (values, name) in [(s, "start"), (e, "end")] {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(Failure::new(
                    DVH_STATUS_NON_FINITE_COORDINATE,
                    format!("{name}[{i}] is {}, not a finite number", values[i]),
                ));
            }
        }
        // SAFETY: NULL or readable (contract).
        let mode = unsafe { DvhCcdOptions::read_or_default(options) }?.mode;
        let points = |v: &[f64]| [0, 1, 2, 3].map(|i| [v[3 * i], v[3 * i + 1], v[3 * i + 2]]);
        let toi = test(&points(s), &points(e), mode)?;
        // SAFETY: non-NULL (checked) and writable (contract).
        unsafe { hit_out.write(toi.is_some()) };
        if let Some(t) = toi {
            // SAFETY: NULL or writable (contract).
            unsafe { write_unless_null(toi_out, t) };
        }
        Ok(())
    })
}

/// Does a point moving in a straight line meet a moving triangle during the step t in [0, 1],
/// and when first? `start` and `end` hold 12 doubles each: the point, then the triangle's three
/// corners (`x, y, z` each), at t = 0 and t = 1. The triangle is closed; one of zero area is
/// the segment or point it covers. Writes whether they meet to `*hit_out` and, on a hit, the
/// earliest time of contact rounded down to a double to `*toi_out` unless it is NULL. `options`
/// (NULL: the defaults) gives the mode; its other fields are ignored. Exact for every finite
/// input in `DVH_CCD_MODE_EXACT`.
///
/// Errors: NULL_ARGUMENT (`start`, `end`, `hit_out`); INVALID_ARGUMENT (misaligned, a mode out of
/// range); NON_FINITE_COORDINATE (naming the array and index).
///
/// Thread safety: any thread, any time.
///
/// # Safety
/// `start` and `end` point to 12 readable doubles each; `options` is NULL or readable;
/// `hit_out` is NULL or writable; `toi_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_ccd_vertex_face(
    start: *const f64,
    end: *const f64,
    options: *const DvhCcdOptions,
    hit_out: *mut bool,
    toi_out: *mut f64,
) -> DvhStatus {
    // SAFETY: the caller's contract is this function's.
    unsafe {
        primitive(
            start,
            end,
            options,
            hit_out,
            toi_out,
            vertex_face_impact_with,
        )
    }
}

/// Do two segments moving with their ends in straight lines share a point during the step, and
/// when first? `start` and `end` hold 12 doubles each: edge a's two ends, then edge b's. The
/// segments are closed (a zero-length one is its point); parallel, collinear and overlapping
/// segments are decided like any others. Outputs, errors and thread safety as
/// `dvh_ccd_vertex_face`.
///
/// # Safety
/// As `dvh_ccd_vertex_face`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_ccd_edge_edge(
    start: *const f64,
    end: *const f64,
    options: *const DvhCcdOptions,
    hit_out: *mut bool,
    toi_out: *mut f64,
) -> DvhStatus {
    // SAFETY: the caller's contract is this function's.
    unsafe { primitive(start, end, options, hit_out, toi_out, edge_edge_impact_with) }
}

/// Gives a mesh a motion over one step: every vertex moves in a straight line from its position
/// in `start` (t = 0) to its position in `end` (t = 1), `x, y, z` per vertex, the vertex count
/// of its creation. The volumes are refit to hold every vertex's whole path, for
/// `dvh_continuous_collide` and `dvh_self_continuous_collide`; the mesh's positions become
/// `end` (the discrete queries see the end of the step). A plain `dvh_mesh_refit` makes the
/// mesh stationary again.
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (a different vertex count, misaligned arrays);
/// NON_FINITE_COORDINATE (the message says which array, vertex and axis). On failure the mesh
/// is exactly as it was.
///
/// Thread safety: as `dvh_mesh_refit` (exclusive access; BUSY otherwise).
///
/// # Safety
/// `mesh` is NULL or a live mesh; `start` and `end` each point to `3 * vertex_count` readable
/// doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_refit_motion(
    mesh: *mut DvhMesh,
    start: *const f64,
    end: *const f64,
    vertex_count: usize,
) -> DvhStatus {
    guard(|| {
        refit_guarded(mesh, vertex_count, "dvh_mesh_refit_motion", |m| {
            let n = times_three(vertex_count, "vertex_count")?;
            // SAFETY: readable per the contract; NULL, alignment and size are checked inside.
            let (s, e) = unsafe { (slice_from(start, n, "start")?, slice_from(end, n, "end")?) };
            m.refit_motion(s, e)?;
            Ok(())
        })
    })
}

/// Every vertex-face and edge-edge pair of meshes `a` and `b` that meets while each moves
/// through its last motion (`dvh_mesh_refit_motion`; a mesh refit without one stays still),
/// with the earliest time it does: each vertex of `a` against each triangle of `b`
/// (VERTEX_FACE), each triangle of `a` against each vertex of `b` (FACE_VERTEX), each edge of
/// `a` against each edge of `b` (EDGE_EDGE; an edge is a pair of distinct vertices joined by a
/// triangle side, reported once however many triangles share it). Vertices of no triangle are
/// not tested. `options` NULL means the defaults (exact, every impact, every core).
///
/// On success the impacts replace the contents of `impacts_out`, sorted by
/// `(kind, a0, a1, b0, b1)`, and the counters go to `*stats_out` unless it is NULL; on failure
/// neither changes.
///
/// Errors: NULL_ARGUMENT (`a`, `b`, `impacts_out`); INVALID_ARGUMENT (a mode out of range, a
/// pointer that is not a live handle); BUSY; OUT_OF_MEMORY (set `max_impacts`); INTERNAL_PANIC.
///
/// Thread safety: `a` and `b` are only read: any number of threads may query them at once, each
/// with its own `impacts_out`; no refit of either may run meanwhile (BUSY).
///
/// # Safety
/// `a` and `b` are NULL or live meshes; `options` is NULL or readable; `impacts_out` is NULL or
/// a live buffer; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_continuous_collide(
    a: *const DvhMesh,
    b: *const DvhMesh,
    options: *const DvhCcdOptions,
    impacts_out: *mut DvhImpacts,
    stats_out: *mut DvhCcdStats,
) -> DvhStatus {
    let call = Call::new("dvh_continuous_collide", options, impacts_out, stats_out);
    let unposed = |m| (m, std::ptr::null());
    // SAFETY: the caller's contract is this function's (no poses: NULL is the identity).
    unsafe {
        call.two_meshes(unposed(a), unposed(b), |ma, _, mb, _, o, out| {
            continuous_collide(ma, mb, o, out)
        })
    }
}

/// Every pair of one mesh's primitives that meets during its last motion, with the earliest
/// time: each vertex against each triangle that does not contain it (VERTEX_FACE, the vertex in
/// `a0`), each pair of edges that share no vertex (EDGE_EDGE, `(a0, a1) < (b0, b1)`). No
/// FACE_VERTEX impacts. Otherwise as `dvh_continuous_collide`.
///
/// Errors: NULL_ARGUMENT (`mesh`, `impacts_out`); INVALID_ARGUMENT; BUSY; OUT_OF_MEMORY;
/// INTERNAL_PANIC.
///
/// Thread safety: as `dvh_continuous_collide`.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `options` is NULL or readable; `impacts_out` is NULL or a
/// live buffer; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_self_continuous_collide(
    mesh: *const DvhMesh,
    options: *const DvhCcdOptions,
    impacts_out: *mut DvhImpacts,
    stats_out: *mut DvhCcdStats,
) -> DvhStatus {
    let call = Call::new(
        "dvh_self_continuous_collide",
        options,
        impacts_out,
        stats_out,
    );
    // SAFETY: the caller's contract is this function's.
    unsafe { call.one_mesh(mesh, self_continuous_collide) }
}

/// A new, empty impact buffer, or NULL when memory ran out. Owned by the caller, released with
/// `dvh_impacts_free`. It keeps the scratch space of the queries that use it.
///
/// Thread safety: any thread; a buffer must be used by one thread at a time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_impacts_new() -> *mut DvhImpacts {
    results::new()
}

/// Number of impacts of the last successful query into `impacts` (0 for NULL or a new buffer).
///
/// Thread safety: not alongside a query writing the same buffer (0 then).
///
/// # Safety
/// `impacts` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_impacts_len(impacts: *const DvhImpacts) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::len(impacts, "dvh_impacts_len") }
}

/// The impacts of the last successful query into `impacts`: `dvh_impacts_len(impacts)` entries,
/// sorted by `(kind, a0, a1, b0, b1)`. NULL when there are none. Owned by the buffer; valid until
/// the next query into it or `dvh_impacts_free`.
///
/// Thread safety: as `dvh_impacts_len`.
///
/// # Safety
/// `impacts` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_impacts_data(impacts: *const DvhImpacts) -> *const DvhImpact {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::data(impacts, "dvh_impacts_data") }
}

/// Releases an impact buffer. NULL is a no-op.
///
/// Thread safety: needs exclusive access; the buffer must not be used afterwards. A buffer in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `impacts` is NULL or a live buffer from `dvh_impacts_new`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_impacts_free(impacts: *mut DvhImpacts) {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::free(impacts, "dvh_impacts_free") }
}

/// Every impact of a scene's step: for every two objects that the filters allow (groups and
/// masks, exclusions) and whose boxes over the whole step overlap, exactly what
/// `dvh_continuous_collide` reports for two stand-alone meshes holding the objects' world
/// positions and motions, `object_a`'s first (a deformable object moves as
/// `dvh_scene_set_motion` says, a rigid object's vertices in straight lines between the poses of
/// `dvh_scene_set_pose_motion`; an object given no step stands still); and for every object with
/// self-contact on (`dvh_scene_set_self_contact`), what `dvh_self_continuous_collide` reports
/// for it (`object_a == object_b`). `options` (NULL: the defaults) as for
/// `dvh_continuous_collide`: exact by default, the result the same for every thread count.
///
/// On success the impacts replace the contents of `impacts_out`, sorted by
/// `(object_a, object_b)`, then as each pair's own query sorts them, and the counters go to
/// `*stats_out` unless it is NULL; on failure neither changes. With `earliest_only`, only the
/// earliest impact of the whole scene (of several at that time, the first in that order). With
/// `max_impacts`, each pair's query keeps what its own query with that limit keeps, and the
/// result the first of those in the scene's order, at most the limit (`truncated` says when
/// anything was left out). The counters are sums over the object pairs queried; `impacts` and
/// `earliest_toi` describe the result.
///
/// Deformable objects whose positions or motion changed are refit here, whole, and only those
/// some pair needs. A rigid object that moves or is posed is placed in world coordinates, once
/// per pose or step, into a copy of its mesh that the scene keeps.
///
/// Errors: NULL_ARGUMENT (`scene`, `impacts_out`); INVALID_ARGUMENT (a mode out of range, a
/// pointer that is not a live handle of its kind); BUSY; OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: exclusive access to `scene` (the query refits and places objects) and an
/// `impacts_out` used by no other thread; otherwise refused with BUSY, nothing changed.
///
/// # Safety
/// `scene` is NULL or a live scene; `options` is NULL or readable; `impacts_out` is NULL or a
/// live buffer; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_continuous_collide(
    scene: *mut DvhScene,
    options: *const DvhCcdOptions,
    impacts_out: *mut DvhSceneImpacts,
    stats_out: *mut DvhCcdStats,
) -> DvhStatus {
    let call = Call::new(
        "dvh_scene_continuous_collide",
        options,
        impacts_out,
        stats_out,
    );
    // SAFETY: the caller's contract is this function's.
    unsafe { call.whole_scene(scene, |s, o, out| s.continuous_collide(o, out)) }
}

/// A new, empty buffer for a scene's impacts, or NULL when memory ran out. Owned by the caller,
/// released with `dvh_scene_impacts_free`. It keeps the scratch space of the queries that use
/// it.
///
/// Thread safety: any thread; a buffer must be used by one thread at a time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_scene_impacts_new() -> *mut DvhSceneImpacts {
    results::new()
}

/// Number of impacts of the last successful query into `impacts` (0 for NULL or a new buffer).
///
/// Thread safety: not alongside a query writing the same buffer (0 then).
///
/// # Safety
/// `impacts` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_impacts_len(impacts: *const DvhSceneImpacts) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::len(impacts, "dvh_scene_impacts_len") }
}

/// The impacts of the last successful query into `impacts`: `dvh_scene_impacts_len(impacts)`
/// entries, sorted by `(object_a, object_b)`, then by `(kind, a0, a1, b0, b1)`. NULL when there
/// are none. Owned by the buffer; valid until the next query into it or
/// `dvh_scene_impacts_free`.
///
/// Thread safety: as `dvh_scene_impacts_len`.
///
/// # Safety
/// `impacts` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_impacts_data(
    impacts: *const DvhSceneImpacts,
) -> *const DvhSceneImpact {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::data(impacts, "dvh_scene_impacts_data") }
}

/// Releases a buffer of a scene's impacts. NULL is a no-op.
///
/// Thread safety: needs exclusive access; the buffer must not be used afterwards. A buffer in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `impacts` is NULL or a live buffer from `dvh_scene_impacts_new`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_impacts_free(impacts: *mut DvhSceneImpacts) {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::free(impacts, "dvh_scene_impacts_free") }
}
