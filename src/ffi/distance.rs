//! Distances through the C ABI: of two meshes, of a mesh to many points (closest points,
//! winding numbers, signed distances), and of a scene's objects.

use super::access::{read, write};
use super::boundary::{Failure, guard, guard_value, slice_from, slice_from_mut, write_unless_null};
use super::calls::{Placed, pose};
use super::handles::*;
use super::types::*;
use crate::{
    ClosestPoint, Distance, DistanceOptions, Pose, closest_points, distance, signed_distances,
    winding_numbers,
};

/// The default distance options: no bound, no tolerance, every core.
///
/// Thread safety: any thread, any time.
#[unsafe(no_mangle)]
pub extern "C" fn dvh_distance_options_default() -> DvhDistanceOptions {
    const DEFAULT: DvhDistanceOptions = DvhDistanceOptions {
        max_distance: f64::INFINITY,
        rel_err: 0.0,
        abs_err: 0.0,
        threads: 0,
        reserved: 0,
    };
    guard_value(DEFAULT, || DEFAULT)
}

/// The options behind `o` (NULL: the defaults), checked.
///
/// # Safety
/// `o` is NULL or readable.
unsafe fn distance_options(o: *const DvhDistanceOptions) -> Result<DistanceOptions, Failure> {
    // SAFETY: NULL or readable (contract).
    let Some(o) = (unsafe { o.as_ref() }) else {
        return Ok(DistanceOptions::default());
    };
    if o.reserved != 0 {
        return Err(Failure::invalid(format!(
            "options->reserved = {}: it must be 0",
            o.reserved
        )));
    }
    let options = DistanceOptions {
        max_distance: o.max_distance,
        rel_err: o.rel_err,
        abs_err: o.abs_err,
        threads: o.threads,
    };
    options.check()?;
    Ok(options)
}

/// The pose behind `p` (NULL: none), checked, for argument `name`.
///
/// # Safety
/// `p` is NULL or readable.
unsafe fn optional_pose(p: *const DvhPose, name: &str) -> Result<Option<Pose>, Failure> {
    // SAFETY: NULL or readable (contract).
    unsafe { p.as_ref() }.map(|p| pose(p, name)).transpose()
}

/// `point_count` points (three doubles each) at `points`, checked.
///
/// # Safety
/// `points` is NULL or `3 * point_count` readable doubles.
unsafe fn points_at<'a>(points: *const f64, point_count: usize) -> Result<&'a [[f64; 3]], Failure> {
    // SAFETY: NULL or readable (contract); `[f64; 3]` has the alignment of `f64` and its three
    // doubles in a row.
    unsafe { slice_from(points.cast::<[f64; 3]>(), point_count, "points") }
}

/// The least distance between the surfaces of mesh `a` placed by `pose_a` and mesh `b` placed
/// by `pose_b` (NULL: identity), written to `*distance_out`: the triangles and closest points
/// that attain it, and the vertex-face or edge-edge pair (as `dvh_nearest_features` reports
/// one) that does. Exact: the pair reported attains the exact least distance (candidates
/// ordered by exact comparisons; of several at the least, the first by `(kind, a0, a1, b0,
/// b1)`, whatever the thread count), the distance within one unit in the last place of the
/// exact one correctly rounded, the points within two. `triangle_a`, `triangle_b`: the least
/// triangles holding the pair's vertex, edge or face on each side. Meshes that intersect
/// (touching counts) get distance 0, `intersecting` 1, the least intersecting triangle pair in
/// `dvh_collide`'s order, a point of both triangles (within rounding) as both closest points,
/// and a zero `stencil`.
///
/// `options` (NULL: the defaults): farther apart than `max_distance`, `found` is 0 (every field
/// zero); with `rel_err` or `abs_err`, a pair at distance `d <= (1 + rel_err) m + abs_err` of the
/// least `m` may be reported (which of those may depend on the volume kind, never on the thread
/// count). Counters (the sums of the queries made) go to `*stats_out` unless
/// it is NULL. On failure neither output changes.
///
/// Errors: NULL_ARGUMENT (`a`, `b`, `distance_out`); INVALID_ARGUMENT (options out of range, a
/// pointer that is not a live handle); NON_FINITE_COORDINATE and NON_RIGID_POSE (a pose);
/// POSE_OUT_OF_RANGE; BUSY; OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: `a` and `b` are only read: any number of threads may query them at once; no
/// refit of either may run meanwhile (BUSY).
///
/// # Safety
/// `a` and `b` are NULL or live meshes; the poses and `options` NULL or readable;
/// `distance_out` NULL or writable; `stats_out` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_distance(
    a: *const DvhMesh,
    pose_a: *const DvhPose,
    b: *const DvhMesh,
    pose_b: *const DvhPose,
    options: *const DvhDistanceOptions,
    distance_out: *mut DvhDistance,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    let call = "dvh_distance";
    let (pa, pb): (Placed, Placed) = ((a, pose_a), (b, pose_b));
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let (ma, mb) = unsafe { (read(pa.0, "a", call)?, read(pb.0, "b", call)?) };
        if distance_out.is_null() {
            return Err(Failure::null("distance_out"));
        }
        // SAFETY: NULL or readable (contract).
        let (pose_a, pose_b) = unsafe {
            (
                optional_pose(pa.1, "pose_a")?,
                optional_pose(pb.1, "pose_b")?,
            )
        };
        // SAFETY: NULL or readable (contract).
        let o = unsafe { distance_options(options) }?;
        let mut d = Distance::default();
        let stats = distance(&ma, pose_a.as_ref(), &mb, pose_b.as_ref(), &o, &mut d)?;
        // SAFETY: non-NULL (checked) and writable (contract); `DvhDistance` has `Distance`'s
        // layout (checked in `types`).
        unsafe { distance_out.cast::<Distance>().write(d) };
        // SAFETY: NULL or writable (contract).
        unsafe { write_unless_null(stats_out, DvhQueryStats::from(&stats)) };
        Ok(())
    })
}

/// Is the surface of `mesh` closed: every directed edge `(u, v)` of a triangle side matched by
/// as many sides `(v, u)` (a side of a degenerate triangle from a vertex to itself matching
/// itself)? Winding numbers and signed distances need a closed surface. Found once per mesh's
/// triangles (which never change) and kept; `*closed_out` receives the answer.
///
/// Errors: NULL_ARGUMENT (`mesh`, `closed_out`); INVALID_ARGUMENT (not a live mesh); BUSY;
/// INTERNAL_PANIC.
///
/// Thread safety: `mesh` is only read.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `closed_out` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_mesh_is_closed(
    mesh: *const DvhMesh,
    closed_out: *mut bool,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let m = unsafe { read(mesh, "mesh", "dvh_mesh_is_closed") }?;
        if closed_out.is_null() {
            return Err(Failure::null("closed_out"));
        }
        let closed = m.is_closed();
        // SAFETY: non-NULL (checked) and writable (contract).
        unsafe { closed_out.write(closed) };
        Ok(())
    })
}

/// For each of the `point_count` points at `points` (x, y, z each), the closest point of mesh
/// `mesh` placed by `pose` (NULL: identity), into `results_out[i]`: the triangle it lies on (of
/// several at the same distance, the least index), the feature of that triangle holding it, its
/// barycentric weights, the point and the distance, decided and rounded as in `dvh_distance`.
/// No triangle within `options->max_distance`: `found` 0 and every field zero. Counters go to
/// `*stats_out` unless NULL (`pairs`: the points with a closest point found). On failure
/// nothing is written.
///
/// Errors: NULL_ARGUMENT (`mesh`, `points` or `results_out` with points); INVALID_ARGUMENT
/// (options out of range, an array not aligned, a count too large, not a live mesh);
/// NON_FINITE_COORDINATE (a point: the message names its index and axis; a pose); NON_RIGID_POSE;
/// BUSY; INTERNAL_PANIC.
///
/// Thread safety: `mesh` is only read.
///
/// # Safety
/// `mesh` is NULL or a live mesh; `pose` and `options` NULL or readable; `points` NULL or
/// `3 * point_count` readable doubles; `results_out` NULL or `point_count` writable entries,
/// apart from `points`; `stats_out` NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_closest_points(
    mesh: *const DvhMesh,
    pose: *const DvhPose,
    points: *const f64,
    point_count: usize,
    options: *const DvhDistanceOptions,
    results_out: *mut DvhClosestPoint,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let m = unsafe { read(mesh, "mesh", "dvh_closest_points") }?;
        // SAFETY: as documented (contract).
        let (p, placed, o) = unsafe {
            (
                points_at(points, point_count)?,
                optional_pose(pose, "pose")?,
                distance_options(options)?,
            )
        };
        // SAFETY: NULL or `point_count` writable entries apart from `points` (contract);
        // `DvhClosestPoint` has `ClosestPoint`'s layout (checked in `types`).
        let out = unsafe {
            slice_from_mut(
                results_out.cast::<ClosestPoint>(),
                point_count,
                "results_out",
            )
        }?;
        let stats = closest_points(&m, placed.as_ref(), p, &o, out)?;
        // SAFETY: NULL or writable (contract).
        unsafe { write_unless_null(stats_out, DvhQueryStats::from(&stats)) };
        Ok(())
    })
}

/// For each of the `point_count` points at `points`, its winding number about the closed
/// surface of mesh `mesh` placed by `pose` (NULL: identity), into `winding_out[i]`: how many
/// times the surface winds around the point, with sign (a triangle faces where its normal
/// `(t1 - t0) x (t2 - t0)` points: an outward surface winds +1 around its inside, an inward one
/// -1); 0 outside; 2 where a folded surface wraps twice; `DVH_WINDING_ON_SURFACE` for a point on
/// the surface. Exact for every point: crossings are counted by exact orientation predicates,
/// with a symbolic perturbation where the ray meets an edge or a vertex. `threads` as
/// `DvhQueryOptions.threads`. On failure nothing is written.
///
/// Errors: NOT_CLOSED (the mesh is not closed: the message names an edge with no reverse);
/// NULL_ARGUMENT; INVALID_ARGUMENT; NON_FINITE_COORDINATE (a point, named; a pose);
/// NON_RIGID_POSE; BUSY; INTERNAL_PANIC.
///
/// Thread safety: `mesh` is only read.
///
/// # Safety
/// As `dvh_closest_points`, with `winding_out` NULL or `point_count` writable `int32_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_winding_numbers(
    mesh: *const DvhMesh,
    pose: *const DvhPose,
    points: *const f64,
    point_count: usize,
    threads: u32,
    winding_out: *mut i32,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let m = unsafe { read(mesh, "mesh", "dvh_winding_numbers") }?;
        // SAFETY: as documented (contract).
        let (p, placed) = unsafe {
            (
                points_at(points, point_count)?,
                optional_pose(pose, "pose")?,
            )
        };
        // SAFETY: NULL or `point_count` writable entries apart from `points` (contract).
        let out = unsafe { slice_from_mut(winding_out, point_count, "winding_out") }?;
        winding_numbers(&m, placed.as_ref(), p, threads, out)?;
        Ok(())
    })
}

/// For each of the `point_count` points at `points`, its signed distance to the closed surface
/// of mesh `mesh` placed by `pose` (NULL: identity), into `distances_out[i]`: the distance to
/// the closest point (as `dvh_closest_points`), negative inside (winding number not 0, exact),
/// positive outside, 0 on the surface; beyond `options->max_distance`, an infinity of the
/// point's sign. Counters to `*stats_out` unless NULL (`pairs`: the points within the bound).
/// On failure nothing is written.
///
/// Errors: NOT_CLOSED; NULL_ARGUMENT; INVALID_ARGUMENT; NON_FINITE_COORDINATE; NON_RIGID_POSE;
/// BUSY; INTERNAL_PANIC.
///
/// Thread safety: `mesh` is only read.
///
/// # Safety
/// As `dvh_closest_points`, with `distances_out` NULL or `point_count` writable doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_signed_distances(
    mesh: *const DvhMesh,
    pose: *const DvhPose,
    points: *const f64,
    point_count: usize,
    options: *const DvhDistanceOptions,
    distances_out: *mut f64,
    stats_out: *mut DvhQueryStats,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or live, read-only during the call (contract).
        let m = unsafe { read(mesh, "mesh", "dvh_signed_distances") }?;
        // SAFETY: as documented (contract).
        let (p, placed, o) = unsafe {
            (
                points_at(points, point_count)?,
                optional_pose(pose, "pose")?,
                distance_options(options)?,
            )
        };
        // SAFETY: NULL or `point_count` writable doubles apart from `points` (contract).
        let out = unsafe { slice_from_mut(distances_out, point_count, "distances_out") }?;
        let stats = signed_distances(&m, placed.as_ref(), p, &o, out)?;
        // SAFETY: NULL or writable (contract).
        unsafe { write_unless_null(stats_out, DvhQueryStats::from(&stats)) };
        Ok(())
    })
}

/// The closest pair of distinct objects of `scene` that the filters allow (groups, masks,
/// exclusions, as `dvh_scene_collide`): `*object_a_out < *object_b_out` and `*distance_out` as
/// `dvh_distance` reports it for their meshes and poses (the lower id's first); the least
/// distance over the pairs, decided exactly, ties to the least `(object_a, object_b)`. No
/// allowed pair within `options->max_distance` (or none at all): `distance_out->found` is 0,
/// every field zero, and the object ids are `UINT32_MAX`. Deformable objects whose positions
/// changed are refit, whole, only those some pair needs. On failure nothing is written.
///
/// Errors: NULL_ARGUMENT (`scene`, an out-pointer); INVALID_ARGUMENT; BUSY; OUT_OF_MEMORY;
/// INTERNAL_PANIC.
///
/// Thread safety: exclusive access to `scene` (the query refits objects).
///
/// # Safety
/// `scene` is NULL or a live scene; `options` NULL or readable; the out-pointers NULL or
/// writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_distance(
    scene: *mut DvhScene,
    options: *const DvhDistanceOptions,
    object_a_out: *mut u32,
    object_b_out: *mut u32,
    distance_out: *mut DvhDistance,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or a live scene (contract); BUSY while another call uses it.
        let mut s = unsafe { write(scene, "scene", "dvh_scene_distance")? };
        for (p, name) in [
            (object_a_out, "object_a_out"),
            (object_b_out, "object_b_out"),
        ] {
            if p.is_null() {
                return Err(Failure::null(name));
            }
        }
        if distance_out.is_null() {
            return Err(Failure::null("distance_out"));
        }
        // SAFETY: NULL or readable (contract).
        let o = unsafe { distance_options(options) }?;
        let found = s.distance(&o)?;
        let (i, j, d) = found.map_or((u32::MAX, u32::MAX, Distance::default()), |f| {
            (f.object_a, f.object_b, f.distance)
        });
        // SAFETY: non-NULL (checked) and writable (contract).
        unsafe {
            object_a_out.write(i);
            object_b_out.write(j);
            distance_out.cast::<Distance>().write(d);
        }
        Ok(())
    })
}

/// The object of `scene` closest to `object` among those the filters allow it to meet, as
/// `dvh_scene_distance` chooses (ties to the least id): `*other_out` and `*distance_out` with
/// `object`'s mesh as the first side. None within `options->max_distance`:
/// `distance_out->found` 0 and `*other_out` `UINT32_MAX`. On failure nothing is written.
///
/// Errors: NULL_ARGUMENT; INVALID_ARGUMENT (`object` not in the scene, options out of range);
/// BUSY; OUT_OF_MEMORY; INTERNAL_PANIC.
///
/// Thread safety: exclusive access to `scene`.
///
/// # Safety
/// As `dvh_scene_distance`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn dvh_scene_object_distance(
    scene: *mut DvhScene,
    object: u32,
    options: *const DvhDistanceOptions,
    other_out: *mut u32,
    distance_out: *mut DvhDistance,
) -> DvhStatus {
    guard(|| {
        // SAFETY: NULL or a live scene (contract); BUSY while another call uses it.
        let mut s = unsafe { write(scene, "scene", "dvh_scene_object_distance")? };
        if other_out.is_null() {
            return Err(Failure::null("other_out"));
        }
        if distance_out.is_null() {
            return Err(Failure::null("distance_out"));
        }
        // SAFETY: NULL or readable (contract).
        let o = unsafe { distance_options(options) }?;
        let found = s.object_distance(object, &o)?;
        let (j, d) = found.map_or((u32::MAX, Distance::default()), |f| {
            (f.object_b, f.distance)
        });
        // SAFETY: non-NULL (checked) and writable (contract).
        unsafe {
            other_out.write(j);
            distance_out.cast::<Distance>().write(d);
        }
        Ok(())
    })
}
