//! The closest point of a mesh to each of many points, exactly: the least distance decided by
//! exact comparisons, ties to the least triangle index.
//!
//! For each point, one walk (starting from the triangle nearest the point before it) finds the
//! triangle whose floating-point estimate is least and keeps every triangle that certain bounds
//! cannot put beyond that estimate (a little widened); the guess's exact distance, rounded up,
//! then bounds the least, and exact decisions choose among the kept triangles within it
//! (usually those around the nearest vertex or edge). The floating point only chooses where to
//! look: every answer rests on exact decisions, and where the guess's exact distance is beyond
//! what the walk kept (a degenerate triangle's estimate far too low) a second, exact walk to
//! that distance takes over.

use super::options::DistanceOptions;
use super::order::{Walker, answer_points, check_points};
use super::walk::{Frame, mesh_feature};
use crate::error::Result;
use crate::geometry::nearest::{Decided, Feature, Primitive, cmp_distance, decide_near, values};
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;
use crate::query::pairs::QueryStats;
use std::cmp::Ordering;

/// The closest point of a mesh to a query point, in world coordinates. The layout is the C
/// ABI's `DvhClosestPoint`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct ClosestPoint {
    found: u32,
    /// The triangle the closest point lies on (of several at the same distance, the least).
    pub triangle: u32,
    /// Where on the triangle it lies, numbered on the triangle's corners.
    pub feature: Feature,
    reserved: u32,
    /// The distance, within one unit in the last place of the exact one correctly rounded.
    pub distance: f64,
    /// The closest point, each coordinate within two units in the last place of the exact one.
    pub point: Point,
    /// Its barycentric weights on the triangle's corners (summing to one).
    pub weights: [f64; 3],
}

impl ClosestPoint {
    /// Is there a triangle within the query's `max_distance`? When not, the other fields are
    /// zero.
    pub fn found(&self) -> bool {
        self.found != 0
    }
}

/// A triangle of the walk's answer: its index and where its closest point lies.
type Found = (u32, Decided);

/// The points of the pair (query point, triangle `t`) as the exact tests take them.
#[inline]
fn pair_points(frame: &Frame, p: &Point, t: u32) -> [Point; 4] {
    let [a, b, c] = frame.corners(t);
    [*p, a, b, c]
}

/// The mesh feature that holds the closest point of `p` on triangle `t`, as the exact decision
/// found it.
fn face_mesh_feature(frame: &Frame, t: u32, d: Decided) -> [u32; 3] {
    mesh_feature(&frame.triangle(t), t, d.face_feature())
}

/// The closest of `found` to `p`: least exact distance, then least triangle index.
fn least(frame: &Frame, p: &Point, found: &[Found]) -> Option<Found> {
    let mut best: Option<(Found, [Point; 4])> = None;
    for &(t, d) in found {
        let q = pair_points(frame, p, t);
        let closer = match &best {
            None => true,
            Some(((bt, bd), bq)) => {
                // Closest points on one vertex or edge of the mesh: the same point, the same
                // distance (the common tie: the triangles around the nearest vertex).
                let order = if face_mesh_feature(frame, t, d) == face_mesh_feature(frame, *bt, *bd)
                {
                    Ordering::Equal
                } else {
                    cmp_distance(
                        (Primitive::VertexFace, &q, d),
                        (Primitive::VertexFace, bq, *bd),
                    )
                };
                match order {
                    Ordering::Less => true,
                    Ordering::Equal => t < *bt,
                    Ordering::Greater => false,
                }
            }
        };
        if closer {
            best = Some(((t, d), q));
        }
    }
    best.map(|(f, _)| f)
}

/// The exact distance of `p` from triangle `t` (rounded as the results are) with where its
/// closest point lies; `None` for a distance beyond the largest double.
fn exact_distance(frame: &Frame, p: &Point, t: u32, estimate: f64) -> Option<(Decided, f64)> {
    let q = pair_points(frame, p, t);
    let decided = decide_near(Primitive::VertexFace, &q, estimate)?;
    Some((decided, values(Primitive::VertexFace, &q, decided).distance))
}

/// The closest triangle of `frame` to `p` within `options.max_distance` (as
/// [`closest_points`] chooses it), with where its closest point lies.
pub(super) fn closest_triangle(
    frame: &Frame,
    p: &Point,
    options: &DistanceOptions,
    w: &mut Walker,
) -> Option<Found> {
    let max = options.max_distance;
    // Start from the triangle the point before found: near it, its distance prunes most.
    let shrink = |d: f64| options.improving(d);
    let (guess, reach) = frame.nearest_kept(p, max, w.previous, shrink, &mut w.stack, &mut w.kept);
    // Every triangle within `reach` is kept; the exact decisions need those within the
    // guess's exact distance (or the tolerance's radius below it).
    let (radius, guess) =
        match guess.and_then(|(t, e)| exact_distance(frame, p, t, e).map(|x| (t, x))) {
            Some((t, (decided, d))) => {
                // Two units up from a distance within one of the correctly rounded: at least the
                // exact distance.
                let exact_bound = d.next_up().next_up();
                if options.tolerant() && exact_bound <= max {
                    // Accepted unless something is nearer than the tolerance allows.
                    (options.improving(exact_bound), Some((t, decided)))
                } else {
                    // Widened a little: the guess's own triangle and those tying with it (around
                    // its nearest vertex or edge) are then told within by the filters, not in
                    // exact arithmetic at the boundary; the few more it may take in are ordered
                    // exactly.
                    let r = (exact_bound * (1.0 + 1.0 / (1u64 << 30) as f64)).next_up();
                    (r.min(max), None)
                }
            }
            // Nothing within the bound by the estimates (or only beyond the largest double): the
            // exact decisions settle it.
            None => (max.min(f64::MAX), None),
        };
    if radius <= reach {
        frame.kept_within(p, radius, &w.kept, &mut w.stack, &mut w.found);
    } else {
        // The guess's estimate was far below its exact distance (a degenerate triangle): walk
        // again to the radius.
        frame.within(p, radius, &mut w.stack, &mut w.found);
    }
    match guess {
        Some(accepted) if w.found.is_empty() => Some(accepted),
        _ => least(frame, p, &w.found),
    }
}

/// The answer for `p`: its closest point, or not found.
fn answer(frame: &Frame, p: &Point, options: &DistanceOptions, w: &mut Walker) -> ClosestPoint {
    let Some((t, decided)) = closest_triangle(frame, p, options, w) else {
        w.previous = None;
        return ClosestPoint::default();
    };
    w.previous = Some(t);
    let n = values(Primitive::VertexFace, &pair_points(frame, p, t), decided);
    ClosestPoint {
        found: 1,
        triangle: t,
        feature: n.features[1],
        reserved: 0,
        distance: n.distance,
        point: n.points[1],
        weights: n.weights[1],
    }
}

/// For each point of `points`, the closest point of mesh `mesh` placed by `pose` (`None`: the
/// mesh's coordinates are world coordinates), into `out` (one entry per point): the triangle it
/// lies on, where on it, its barycentric weights, the point and the distance. Exact: the least
/// distance is decided by exact comparisons (of several triangles at the same distance, the
/// least index is reported), the distance is within one unit in the last place of the exact one
/// correctly rounded, the point and weights within two; the feature is decided exactly (the
/// lowest-dimensional one holding the point: a corner before an edge before the interior).
///
/// [`DistanceOptions`]: no triangle within `max_distance` gives an entry that is not
/// [`ClosestPoint::found`]; with `rel_err` or `abs_err`, an entry may name a triangle farther
/// than the least by at most what they allow (its values are still its own, exactly);
/// `threads` shares the points out, the answer the same for every count.
///
/// With a pose, the triangles are those of the placed vertices, as [`Pose::transform_point`]
/// computes them (the coordinates every query tests), and the points and results are in world
/// coordinates.
///
/// The counters returned: the volumes and triangles tested, and in `pairs` the points with a
/// closest point found.
///
/// Errors: [`crate::Error::InvalidDistanceOption`]; [`crate::Error::NonFinitePoint`] (the first
/// point with a NaN or infinite coordinate); [`crate::Error::ResultLength`] unless `out` has one
/// entry per point. On error `out` is unchanged.
///
/// Memory: the order of the points, the answers in that order and each thread's walk keep
/// their space for the next call on the same threads; sharing the points out among threads
/// allocates the list of their blocks.
pub fn closest_points(
    mesh: &Mesh,
    pose: Option<&Pose>,
    points: &[Point],
    options: &DistanceOptions,
    out: &mut [ClosestPoint],
) -> Result<QueryStats> {
    options.check()?;
    check_points(points, out.len())?;
    let mut stats = with_frame(mesh, pose, |frame| {
        answer_points(points, options.threads, out, |w, p| {
            answer(frame, p, options, w)
        })
    });
    stats.pairs = out.iter().filter(|c| c.found()).count() as u64;
    Ok(stats)
}

/// Runs `f` with the frame of `mesh` placed by `pose`: the mesh's own, or its placed vertices
/// and boxes (kept in the calling thread's scratch for the next call).
pub(super) fn with_frame<R>(mesh: &Mesh, pose: Option<&Pose>, f: impl FnOnce(&Frame) -> R) -> R {
    match pose.filter(|p| !p.is_identity()) {
        None => f(&Frame::own(mesh)),
        Some(pose) => PLACED.with(|cell| {
            let mut placed = cell.borrow_mut();
            let (vertices, boxes) = &mut *placed;
            f(&Frame::placed(mesh, pose, vertices, boxes))
        }),
    }
}

type Placed = (Vec<Point>, Vec<crate::geometry::aabb::Aabb>);

thread_local! {
    static PLACED: std::cell::RefCell<Placed> = std::cell::RefCell::default();
}
