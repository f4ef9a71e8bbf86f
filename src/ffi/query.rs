//! Queries through the C ABI: result buffers, collide, self-collision, proximity, the exact
//! triangle test.

use super::boundary::{Failure, choice, guard, guard_value, slice_from};
use super::calls::{Call, CallOptions};
use super::handles::*;
use super::results;
use super::types::*;
use crate::exact::triangles_intersect;
use crate::{QueryMode, QueryOptions, collide, proximity, self_collide, self_proximity};

/// The default query options: every intersecting triangle pair, no pair limit, every core (all
/// fields zero).
///
/// Thread safety: any thread, any time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_query_options_default() -> DvhQueryOptions {
    const DEFAULT: DvhQueryOptions = DvhQueryOptions {
        mode: DVH_QUERY_MODE_TRIANGLES,
        max_depth: 0,
        max_pairs: 0,
        budget: 0,
        threads: 0,
    };
    guard_value(DEFAULT, || DEFAULT)
}

fn query_options(o: &DvhQueryOptions) -> Result<QueryOptions, Failure> {
    let mode = choice(
        "mode",
        "DVH_QUERY_MODE",
        o.mode,
        &[
            (DVH_QUERY_MODE_TRIANGLES, QueryMode::Triangles),
            (DVH_QUERY_MODE_FIRST_HIT, QueryMode::FirstHit),
            (DVH_QUERY_MODE_LEAVES, QueryMode::Leaves),
            (DVH_QUERY_MODE_DEPTH, QueryMode::Depth(o.max_depth)),
            (DVH_QUERY_MODE_BUDGET, QueryMode::Budget(o.budget)),
        ],
    )?;
    if mode == QueryMode::Budget(0) {
        return Err(Failure::invalid(
            "options->budget = 0 in DVH_QUERY_MODE_BUDGET: at least 1 volume test is needed",
        ));
    }
    let max_pairs = (o.max_pairs != 0).then(|| usize::try_from(o.max_pairs).unwrap_or(usize::MAX));
    Ok(QueryOptions {
        mode,
        max_pairs,
        threads: o.threads,
    })
}

/// A new, empty result buffer, or NULL when memory ran out. Owned by the caller, released with
/// `dvh_pairs_free`. It keeps the scratch space of the queries that use it, so that once it has
/// grown to a scene's needs queries on one thread allocate nothing (on more, one small job per
/// extra thread and step shared out).
///
/// Thread safety: any thread; a buffer must be used by one thread at a time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_pairs_new() -> *mut DvhPairs {
    results::new()
}

/// Number of pairs of the last successful query into `pairs` (0 for NULL or a new buffer).
///
/// Thread safety: not alongside a query writing the same buffer (0 then).
///
/// # Safety
/// `pairs` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_pairs_len(pairs: *const DvhPairs) -> usize {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::len(pairs, "dvh_pairs_len") }
}

/// The pairs of the last successful query into `pairs`: `dvh_pairs_len(pairs)` entries, sorted
/// by `a` then `b`, without duplicates. NULL when there are none. Owned by the buffer; valid
/// until the next query into it or `dvh_pairs_free`.
///
/// Thread safety: as `dvh_pairs_len`.
///
/// # Safety
/// `pairs` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_pairs_data(pairs: *const DvhPairs) -> *const DvhPair {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::data(pairs, "dvh_pairs_data") }
}

/// What the indices in `pairs` refer to: `DVH_PAIR_KIND_TRIANGLES` or `DVH_PAIR_KIND_NODES`
/// (triangles for NULL or a new buffer).
///
/// Thread safety: as `dvh_pairs_len`.
///
/// # Safety
/// `pairs` is NULL or a live buffer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_pairs_kind(pairs: *const DvhPairs) -> DvhPairKind {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::kind(pairs, "dvh_pairs_kind") }
}

/// Releases a result buffer. NULL is a no-op.
///
/// Thread safety: needs exclusive access; the buffer must not be used afterwards. A buffer in
/// use by another call is not released (the last error message says so).
///
/// # Safety
/// `pairs` is NULL or a live buffer from `dvh_pairs_new`, not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_pairs_free(pairs: *mut DvhPairs) {
    // SAFETY: the caller's contract is this function's.
    unsafe { results::free(pairs, "dvh_pairs_free") }
}

/// Finds what intersects between mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b`
/// (NULL: identity, the mesh's coordinates are world coordinates), as `options` asks (NULL: the
/// defaults, every intersecting triangle pair).
///
/// On success the results replace the contents of `pairs_out`: pairs `(index in a, index in b)`,
/// sorted, without duplicates, triangles or nodes as `dvh_pairs_kind` says; and the counters are
/// written to `*stats_out` unless it is NULL. Triangles are tested exactly at the world
/// coordinates `R * p + t` computed in double precision (as `((R0 x + R1 y) + R2 z) + t`), and
/// touching counts as intersecting. On failure neither `pairs_out` nor `*stats_out` changes.
///
/// Errors: NULL_ARGUMENT (`a`, `b`, `pairs_out`); INVALID_ARGUMENT (options out of range, a
/// budget of 0 in `DVH_QUERY_MODE_BUDGET`, a pointer that is not a live handle); BUSY;
/// NON_FINITE_COORDINATE and NON_RIGID_POSE (a pose); POSE_OUT_OF_RANGE; OUT_OF_MEMORY (the
/// result could not grow: set `max_pairs`); INTERNAL_PANIC.
///
/// Thread safety: `a` and `b` are only read: any number of threads may query the same meshes at
/// once, each with its own `pairs_out`. No refit of `a` or `b` may run meanwhile. A query that
/// would break this (a refit running, `pairs_out` in use by another call) is refused with BUSY
/// and changes nothing.
///
/// # Safety
/// `a` and `b` are NULL or live meshes; `pose_a`, `pose_b`, `options` are NULL or readable;
/// `pairs_out` is NULL or a live buffer used by no other thread; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_collide(
    a: *const DvhMesh,
    pose_a: *const DvhPose,
    b: *const DvhMesh,
    pose_b: *const DvhPose,
    options: *const DvhQueryOptions,
    pairs_out: *mut DvhPairs,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_collide", options, pairs_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe { call.two_meshes((a, pose_a), (b, pose_b), collide) }
}

impl CallOptions for DvhQueryOptions {
    type Options = QueryOptions;

    unsafe fn read_or_default(o: *const DvhQueryOptions) -> Result<QueryOptions, Failure> {
        // SAFETY: NULL or readable (contract).
        let o = unsafe { o.as_ref() };
        Ok(o.map(query_options).transpose()?.unwrap_or_default())
    }
}

/// The pairs `(a, b)`, `a < b`, of triangles of one mesh that intersect. Two triangles that
/// share vertices (by index) count only where they meet somewhere other than their shared
/// vertices and shared edge (a fold through, a crossing, a coplanar overlap), so an intact
/// surface reports nothing however it bends, and a surface folded through itself reports every
/// crossing. Exact, like `dvh_collide`; `options` (NULL: the defaults) as in `dvh_collide`: the
/// coarse modes report node pairs `(lower, higher)`, a node with itself included, whose
/// triangle pairs include every intersecting pair.
///
/// On success the pairs replace the contents of `pairs_out`, sorted, and the counters go to
/// `*stats_out` unless it is NULL; on failure neither changes.
///
/// Errors: NULL_ARGUMENT (`mesh`, `pairs_out`); INVALID_ARGUMENT (options out of range, a budget
/// of 0); OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: `mesh` is only read: any number of threads may query it at once, each with
/// its own `pairs_out`. No refit of `mesh` may run meanwhile.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `options` is NULL or readable; `pairs_out` is NULL or a live
/// buffer used by no other thread; `stats_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_self_collide(
    mesh: *const DvhMesh,
    options: *const DvhQueryOptions,
    pairs_out: *mut DvhPairs,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_self_collide", options, pairs_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe { call.one_mesh(mesh, self_collide) }
}

/// Every pair `(triangle of a, triangle of b)` of closed triangles at Euclidean distance
/// `<= distance` between mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b` (NULL:
/// identity). Exact for the given doubles: the decision "distance <= d" is made without rounding
/// error (a floating-point filter first, exact arithmetic when it cannot decide), so
/// `distance = 0` gives exactly `dvh_collide`'s pairs and a pair exactly `distance` apart is
/// reported. Poses and `options` (NULL: the defaults) as in `dvh_collide`; the coarse modes
/// report node pairs whose volumes come within `distance`.
///
/// On success the pairs replace the contents of `pairs_out`, sorted, and the counters go to
/// `*stats_out` unless it is NULL; on failure neither changes.
///
/// Errors: NULL_ARGUMENT (`a`, `b`, `pairs_out`); INVALID_ARGUMENT (a negative, NaN or infinite
/// `distance`; options out of range); NON_FINITE_COORDINATE and NON_RIGID_POSE (a pose);
/// POSE_OUT_OF_RANGE; OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: as `dvh_collide`.
///
/// # Safety
/// As `dvh_collide`.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)] // the C signature the issue fixes
pub unsafe extern "C" fn dvh_proximity(
    a: *const DvhMesh,
    pose_a: *const DvhPose,
    b: *const DvhMesh,
    pose_b: *const DvhPose,
    distance: f64,
    options: *const DvhQueryOptions,
    pairs_out: *mut DvhPairs,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_proximity", options, pairs_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe {
        call.two_meshes((a, pose_a), (b, pose_b), |ma, pa, mb, pb, o, out| {
            proximity(ma, pa, mb, pb, distance, o, out)
        })
    }
}

/// The pairs `(a, b)`, `a < b`, of one mesh's triangles that share no vertex (by index) and lie
/// at Euclidean distance `<= distance`: what keeps a cloth or a soft body a thickness apart from
/// itself. Exact like `dvh_proximity`; `options` (NULL: the defaults) as in `dvh_self_collide`.
///
/// On success the pairs replace the contents of `pairs_out`, sorted, and the counters go to
/// `*stats_out` unless it is NULL; on failure neither changes.
///
/// Errors: NULL_ARGUMENT (`mesh`, `pairs_out`); INVALID_ARGUMENT (a negative, NaN or infinite
/// `distance`; options out of range); OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: as `dvh_self_collide`.
///
/// # Safety
/// As `dvh_self_collide`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_self_proximity(
    mesh: *const DvhMesh,
    distance: f64,
    options: *const DvhQueryOptions,
    pairs_out: *mut DvhPairs,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = Call::new("dvh_self_proximity", options, pairs_out, stats_out);
    // SAFETY: the caller's contract is this function's.
    unsafe { call.one_mesh(mesh, |m, o, out| self_proximity(m, distance, o, out)) }
}

/// The exact triangle test the queries use: do the closed triangles `t1` and `t2` (9 doubles
/// each: three corners, `x, y, z`) share a point? Touching counts; zero-area triangles are the
/// segments or points they cover; the answer is exact for every finite input. The answer goes to
/// `*result_out` (1 or 0).
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (misaligned); NON_FINITE_COORDINATE.
/// Thread safety: any thread, any time.
///
/// # Safety
/// `t1` and `t2` point to 9 readable doubles each; `result_out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_triangles_intersect(
    t1: *const f64,
    t2: *const f64,
    result_out: *mut bool,
) -> DvhStatus {
    guard(|| {
        if result_out.is_null() {
            return Err(Failure::null("result_out"));
        }
        // SAFETY: 9 readable doubles each (contract); NULL and alignment checked inside.
        let (s1, s2) = unsafe { (slice_from(t1, 9, "t1")?, slice_from(t2, 9, "t2")?) };
        for (s, name) in [(s1, "t1"), (s2, "t2")] {
            if let Some(i) = s.iter().position(|v| !v.is_finite()) {
                return Err(Failure::new(
                    DVH_STATUS_NON_FINITE_COORDINATE,
                    format!("{name}[{i}] is {}, not a finite number", s[i]),
                ));
            }
        }
        let tri = |s: &[f64]| [0, 1, 2].map(|c| [s[3 * c], s[3 * c + 1], s[3 * c + 2]]);
        let hit = triangles_intersect(&tri(s1), &tri(s2));
        // SAFETY: non-NULL (checked) and writable (contract).
        unsafe { result_out.write(hit) };
        Ok(())
    })
}
