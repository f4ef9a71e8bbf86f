//! Intersection curves through the C ABI: the two queries and the curve buffer's accessors.

use super::access::read;
use super::boundary::{Failure, guard, times_three};
use super::calls::{Call, pose};
use super::handles::*;
use super::results::{self, part};
use super::types::*;
use crate::{intersection_curves, self_intersection_curves};

/// A new, empty curve buffer, or NULL when memory ran out. Owned by the caller, released with
/// `dvh_curves_free`. It keeps the scratch space of the queries that use it, so that once it has
/// grown to a scene's needs queries on one thread allocate nothing.
///
/// Thread safety: any thread; a buffer must be used by one thread at a time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_curves_new() -> *mut DvhCurves {
    results::new()
}

/// Number of segments of the last successful query into `curves` (0 for NULL or a new buffer).
///
/// Thread safety: not alongside a query writing the same buffer (0 then).
///
/// # Safety
/// `curves` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_len(curves: *const DvhCurves) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::len(curves, "dvh_curves_len") }
}

/// The segments of the last successful query into `curves`: `dvh_curves_len(curves)` entries,
/// curve by curve (curve 0's first), each curve's in chain order. NULL when there are none.
/// Owned by the buffer; valid until the next query into it or `dvh_curves_free`.
///
/// Thread safety: as `dvh_curves_len`.
///
/// # Safety
/// `curves` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_data(curves: *const DvhCurves) -> *const DvhCurveSegment {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::data(curves, "dvh_curves_data") }
}

/// Number of curves of the last successful query into `curves` (0 for NULL or a new buffer).
///
/// Thread safety: as `dvh_curves_len`.
///
/// # Safety
/// `curves` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_curve_count(curves: *const DvhCurves) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { part(curves, "dvh_curves_curve_count", 0, |c| c.curves().len()) }
}

/// Curve `curve` of the last successful query into `curves`: its segments are
/// `dvh_curves_data(curves)[*first_out .. *first_out + *count_out]`, in chain order (each
/// starting where the one before ends), and `*closed_out` says whether the last ends where the
/// first starts. An open curve ends on a boundary edge, beside a degenerate pair, or where more
/// than two segments meet. Curves are ordered by their least `(triangle_a, triangle_b)`
/// segment; a closed curve starts at it, and every curve runs along `n_a x n_b` of that
/// segment's pair (`n` a triangle's normal `(t1 - t0) x (t2 - t0)`).
///
/// Errors: NULL_ARGUMENT (`curves`, an out-pointer); INVALID_ARGUMENT (`curve` not below
/// `dvh_curves_curve_count`, an out-pointer not aligned, a pointer that is not a live buffer);
/// BUSY (a query is writing the buffer). On failure nothing is written.
///
/// Thread safety: as `dvh_curves_len`.
///
/// # Safety
/// `curves` is NULL or a live buffer; the out-pointers are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_curve(
    curves: *const DvhCurves,
    curve: usize,
    first_out: *mut usize,
    count_out: *mut usize,
    closed_out: *mut bool,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or a live buffer (contract).
        let c = unsafe { read(curves, "curves", "dvh_curves_curve") }?;
        check_out(first_out, "first_out")?;
        check_out(count_out, "count_out")?;
        check_out(closed_out, "closed_out")?;
        let n = c.curves().len();
        let Some(found) = c.curves().get(curve) else {
            return Err(Failure::invalid(format!(
                "curve {curve} is out of range: the buffer holds {n} curves"
            )));
        };
        // SAFETY: non-NULL, aligned (checked) and writable (contract).
        unsafe {
            first_out.write(found.segments.start);
            count_out.write(found.segments.len());
            closed_out.write(found.closed);
        }
        Ok(())
    })
}

/// An out-pointer `name`, checked: not NULL, aligned.
fn check_out<T>(p: *mut T, name: &str) -> Result<(), Failure> {
    if p.is_null() {
        return Err(Failure::null(name));
    }
    if !p.is_aligned() {
        return Err(Failure::invalid(format!(
            "argument `{name}` is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )));
    }
    Ok(())
}

/// Number of degenerate pairs of the last successful query into `curves` (0 for NULL or a new
/// buffer).
///
/// Thread safety: as `dvh_curves_len`.
///
/// # Safety
/// `curves` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_degenerate_len(curves: *const DvhCurves) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe {
        part(curves, "dvh_curves_degenerate_len", 0, |c| {
            c.degenerate().len()
        })
    }
}

/// The degenerate pairs of the last successful query into `curves`: intersecting triangle pairs
/// whose intersection is not a segment (one point only, or coplanar), sorted by
/// `(triangle_a, triangle_b)`; `dvh_curves_degenerate_len(curves)` entries, NULL when there are
/// none. Owned by the buffer; valid until the next query into it or `dvh_curves_free`.
///
/// Thread safety: as `dvh_curves_len`.
///
/// # Safety
/// `curves` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_degenerate_data(
    curves: *const DvhCurves,
) -> *const DvhDegeneratePair {
    // SAFETY: the caller's contract is this function's.
    unsafe {
        part(
            curves,
            "dvh_curves_degenerate_data",
            std::ptr::null(),
            |c| {
                let d = c.degenerate();
                // `DvhDegeneratePair` has `DegeneratePair`'s layout (checked in `types`).
                if d.is_empty() {
                    std::ptr::null()
                } else {
                    d.as_ptr().cast()
                }
            },
        )
    }
}

/// Releases a curve buffer. NULL is a no-op.
///
/// Thread safety: needs exclusive access; the buffer must not be used afterwards. A buffer in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `curves` is NULL or a live buffer from `dvh_curves_new`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_free(curves: *mut DvhCurves) {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::free(curves, "dvh_curves_free") }
}

/// The curves along which mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b` (NULL:
/// identity) cross. Each triangle pair `dvh_collide` reports gives either a segment (the pair
/// is not coplanar and meets in more than one point) or a degenerate pair
/// (`dvh_curves_degenerate_data`: the pair meets in one point only, or is coplanar). A
/// segment's ends are where an edge of one triangle meets the other triangle (or a vertex lying
/// in it), decided by exact predicates and rounded once to doubles; segments are chained into
/// curves where their ends are the same exact point, decided from the features that meet
/// there, never from rounded coordinates (see `dvh_curves_curve` for the order). Posed vertices
/// are computed as `dvh_collide` computes them, and the points are the exact intersections of
/// the posed triangles.
///
/// `options` (NULL: the defaults): only `DVH_QUERY_MODE_TRIANGLES`; `threads` as for
/// `dvh_collide` (the answer is the same for every count); `max_pairs` bounds the segments plus
/// degenerate pairs (`DvhQueryStats.truncated` says when it cut: it keeps the pairs
/// `dvh_collide` keeps). `DvhQueryStats.pairs` counts segments plus degenerate pairs.
///
/// On success the results replace the contents of `curves_out` and the counters go to
/// `*stats_out` unless it is NULL; on failure neither changes.
///
/// Errors: NULL_ARGUMENT (`a`, `b`, `curves_out`); INVALID_ARGUMENT (a mode other than
/// `DVH_QUERY_MODE_TRIANGLES`, options out of range, a pointer that is not a live handle);
/// BUSY; NON_FINITE_COORDINATE and NON_RIGID_POSE (a pose); POSE_OUT_OF_RANGE; OUT_OF_MEMORY;
/// INTERNAL_PANIC.
///
/// Thread safety: as `dvh_collide`.
///
/// # Safety
/// `a` and `b` are NULL or live meshes; `pose_a`, `pose_b`, `options` are NULL or readable;
/// `curves_out` is NULL or a live buffer used by no other thread; `stats_out` is NULL or
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_intersection_curves(
    a: *const DvhMesh,
    pose_a: *const DvhPose,
    b: *const DvhMesh,
    pose_b: *const DvhPose,
    options: *const DvhQueryOptions,
    curves_out: *mut DvhCurves,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_intersection_curves", options, curves_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe { call.two_meshes((a, pose_a), (b, pose_b), intersection_curves) }
}

/// The curves along which `mesh` crosses itself: those of the pairs `dvh_self_collide` reports
/// (triangles that share vertices count only where they meet beyond what they share). A pair
/// sharing a vertex gives a segment from that vertex to where the two part. Segments are
/// `(lower, higher)` triangle pairs; a curve passes from a pair to its neighbour whichever of
/// the two has the lower index, so a segment may run against its own pair's `n_a x n_b`.
/// Otherwise as `dvh_intersection_curves`.
///
/// Errors: NULL_ARGUMENT (`mesh`, `curves_out`); INVALID_ARGUMENT (a mode other than
/// `DVH_QUERY_MODE_TRIANGLES`, options out of range); BUSY; OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: as `dvh_self_collide`.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `options` is NULL or readable; `curves_out` is NULL or a
/// live buffer used by no other thread; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_self_intersection_curves(
    mesh: *const DvhMesh,
    options: *const DvhQueryOptions,
    curves_out: *mut DvhCurves,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new(
        "dvh_self_intersection_curves",
        options,
        curves_out,
        stats_out,
    );
    // SAFETY: the caller's contract is this function's.
    unsafe { call.one_mesh(mesh, self_intersection_curves) }
}

/// `vertex_count` points (three doubles each) at `ptr`, to write, after checking what can be
/// checked: not NULL, aligned, a size that fits in memory.
///
/// # Safety
/// If `ptr` is non-NULL it must point to `3 * vertex_count` writable doubles used by no one
/// else for `'a`.
unsafe fn points_out<'a>(
    ptr: *mut f64,
    vertex_count: usize,
    name: &str,
) -> Result<&'a mut [[f64; 3]], Failure> {
    if ptr.is_null() {
        return Err(Failure::null(name));
    }
    if !ptr.is_aligned() {
        return Err(Failure::invalid(format!(
            "argument `{name}` is not aligned to {} bytes",
            std::mem::align_of::<f64>()
        )));
    }
    let values = times_three(vertex_count, name)?;
    if values > isize::MAX as usize / std::mem::size_of::<f64>() {
        return Err(Failure::invalid(format!(
            "argument `{name}`: {vertex_count} points do not fit in memory"
        )));
    }
    // SAFETY: non-NULL, aligned, `3 * vertex_count` writable doubles (contract); `[f64; 3]` has
    // the alignment of `f64` and three of them in a row.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr.cast::<[f64; 3]>(), vertex_count) })
}

/// The gradient of the total length of the curves in `curves` with respect to the world
/// positions of the vertices of `a` and `b`: the meshes and poses (NULL: identity) of the
/// `dvh_intersection_curves` call that gave them, unchanged since. Written to `gradient_a`
/// (`3 * vertex_count_a` doubles: x, y, z per vertex of `a`) and `gradient_b`, replacing what
/// they held; vertices no curve passes by get zeros.
///
/// This is the direction of intersection contour minimisation (Volino and Magnenat-Thalmann
/// 2006): moving the vertices a small step against it shortens the curves, and surfaces that
/// cross come apart as their curves shrink to nothing. Each curve point slides along the edge
/// it lies on as that edge and the other triangle's plane move; the gradient is exact to first
/// order at the rounded points, computed in doubles.
///
/// Errors: NULL_ARGUMENT (`curves`, `a`, `b`, a gradient); INVALID_ARGUMENT (a vertex count
/// that is not the mesh's, curves that name vertices or triangles the meshes do not have, a
/// gradient not aligned, a pointer that is not a live handle); BUSY; NON_FINITE_COORDINATE and
/// NON_RIGID_POSE (a pose); INTERNAL_PANIC. On failure nothing is written.
///
/// Thread safety: `curves`, `a` and `b` are only read.
///
/// # Safety
/// `curves` is NULL or a live buffer; `a` and `b` NULL or live meshes; the poses NULL or
/// readable; `gradient_a` and `gradient_b` NULL or `3 * vertex_count_a` and
/// `3 * vertex_count_b` writable doubles, not overlapping.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)] // two placed meshes and two arrays
pub unsafe extern "C" fn dvh_curves_length_gradient(
    curves: *const DvhCurves,
    a: *const DvhMesh,
    pose_a: *const DvhPose,
    b: *const DvhMesh,
    pose_b: *const DvhPose,
    gradient_a: *mut f64,
    vertex_count_a: usize,
    gradient_b: *mut f64,
    vertex_count_b: usize,
) -> DvhStatus {
    let call = "dvh_curves_length_gradient";
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let (c, ma, mb) = unsafe {
            (
                read(curves, "curves", call)?,
                read(a, "a", call)?,
                read(b, "b", call)?,
            )
        };
        // SAFETY: NULL or readable (contract).
        let (pa, pb) = unsafe { (pose_a.as_ref(), pose_b.as_ref()) };
        let pa = pa.map(|p| pose(p, "pose_a")).transpose()?;
        let pb = pb.map(|p| pose(p, "pose_b")).transpose()?;
        // SAFETY: NULL or writable, not overlapping (contract).
        let (ga, gb) = unsafe {
            (
                points_out(gradient_a, vertex_count_a, "gradient_a")?,
                points_out(gradient_b, vertex_count_b, "gradient_b")?,
            )
        };
        c.length_gradient(&ma, pa.as_ref(), &mb, pb.as_ref(), ga, gb)
            .map_err(Failure::from)
    })
}

/// The gradient of the total length of the curves in `curves`, from
/// `dvh_self_intersection_curves` of `mesh` (unchanged since), with respect to its vertices:
/// `3 * vertex_count` doubles written to `gradient`. Otherwise as `dvh_curves_length_gradient`.
///
/// Errors: NULL_ARGUMENT (`curves`, `mesh`, `gradient`); INVALID_ARGUMENT (a vertex count that
/// is not the mesh's, curves that name vertices or triangles the mesh does not have, a gradient
/// not aligned); BUSY; INTERNAL_PANIC. On failure nothing is written.
///
/// Thread safety: `curves` and `mesh` are only read.
///
/// # Safety
/// `curves` is NULL or a live buffer; `mesh` NULL or a live mesh; `gradient` NULL or
/// `3 * vertex_count` writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_curves_self_length_gradient(
    curves: *const DvhCurves,
    mesh: *const DvhMesh,
    gradient: *mut f64,
    vertex_count: usize,
) -> DvhStatus {
    let call = "dvh_curves_self_length_gradient";
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let (c, m) = unsafe { (read(curves, "curves", call)?, read(mesh, "mesh", call)?) };
        // SAFETY: NULL or writable (contract).
        let g = unsafe { points_out(gradient, vertex_count, "gradient")? };
        c.self_length_gradient(&m, g).map_err(Failure::from)
    })
}
