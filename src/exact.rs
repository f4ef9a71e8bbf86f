//! The exact predicates the queries decide with, for use on their own: do two triangles meet,
//! are they within a distance, on which side of a plane does a point lie.
//!
//! Continuous tests follow points moving in straight lines over a step, t from 0 to 1:
//! [`vertex_face_impact`] and [`edge_edge_impact`] say whether, and first when, the moving
//! primitives meet.
//!
//! [`vertex_face_nearest`] and [`edge_edge_nearest`] give the closest points of a point and a
//! triangle, or of two segments, within a distance: where each lies (a corner, an edge, the
//! interior), the distance and the barycentric weights a simulator builds its contact forces
//! from.
//!
//! Every answer is exact for the given `f64` coordinates (finite ones): it is the sign of a
//! determinant or a polynomial, evaluated with a floating-point filter first and, when the
//! filter cannot tell, with Shewchuk's adaptive arithmetic or big integers; never a tolerance.
//! The queries call these very functions, so [`collide`](crate::collide) in
//! [`QueryMode::Triangles`](crate::QueryMode::Triangles) reports exactly the pairs for which
//! [`triangles_intersect`] holds, and [`proximity`](crate::proximity) those for which
//! [`triangles_within`] does.
//!
//! ```
//! use dvh::exact::{orient3d, triangles_intersect, triangles_within};
//!
//! let floor = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
//! // A triangle standing on the floor's edge: touching counts.
//! let wall = [[0.5, 0.0, 0.0], [0.5, 0.0, 1.0], [0.5, -1.0, 0.0]];
//! assert!(triangles_intersect(&floor, &wall));
//! // The floor lifted by 0.25: apart, and exactly 0.25 away.
//! let lifted = floor.map(|[x, y, z]| [x, y, z + 0.25]);
//! assert!(!triangles_intersect(&floor, &lifted));
//! assert!(triangles_within(&floor, &lifted, 0.25));
//! assert!(!triangles_within(&floor, &lifted, 0.2499));
//! // Below the counter-clockwise floor: positive.
//! assert_eq!(orient3d(&floor[0], &floor[1], &floor[2], &[0.2, 0.2, -1.0]), 1);
//! ```

use crate::geometry::Primitive;
use crate::geometry::ccd::{CcdMode, time_of_impact};
use crate::geometry::nearest;
use crate::geometry::{distance, predicates, tri_tri};
use crate::{Error, Result};

pub use crate::geometry::nearest::{Feature, Nearest};

pub use crate::geometry::predicates::Point;
pub use crate::geometry::tri_tri::Triangle;

/// Do the closed triangles `t1` and `t2` share at least one point?
///
/// Touching counts: a shared vertex, a vertex on the other's edge or face, crossing edges,
/// coplanar overlap. A triangle of zero area is the segment or the point it covers, and is
/// tested as such. The answer does not depend on the order of the triangles or of their corners.
#[inline]
pub fn triangles_intersect(t1: &Triangle, t2: &Triangle) -> bool {
    tri_tri::triangles_intersect(t1, t2)
}

/// Is the Euclidean distance between the closed triangles `t1` and `t2` at most `d`? `d = 0`
/// is [`triangles_intersect`]; a pair exactly `d` apart is within `d`. Degenerate triangles as
/// for [`triangles_intersect`].
///
/// # Panics
/// When `d` is negative, NaN or infinite.
pub fn triangles_within(t1: &Triangle, t2: &Triangle, d: f64) -> bool {
    assert!(
        d >= 0.0 && d.is_finite(),
        "triangles_within: the distance must be finite and not negative, not {d}"
    );
    distance::triangles_within(t1, t2, d)
}

/// The sign (-1, 0 or 1) of `det[a - d; b - d; c - d]`: positive when `d` lies below the plane
/// through `a, b, c` (below as seen from the side where `a, b, c` turn counter-clockwise),
/// negative above, zero when the four points are coplanar.
#[inline]
pub fn orient3d(a: &Point, b: &Point, c: &Point, d: &Point) -> i8 {
    predicates::orient3d(a, b, c, d)
}

/// Does a point moving in a straight line meet a moving triangle during the step, and when
/// first? `start` and `end` hold the point then the triangle's three corners, at t = 0 and
/// t = 1; every point moves linearly between them. The triangle is closed (its edges and
/// corners count), and one of zero area is the segment or the point it covers at that time.
///
/// Returns the earliest time of contact rounded down to a double (the largest double not
/// above it; 0 when they touch at the start), or `None` when they never meet. Exact for every
/// finite input: coplanar motion, grazing contact, double roots and collapsing triangles
/// included.
///
/// Errors: [`Error::NonFiniteCoordinate`] for a NaN or infinite coordinate (`vertex` 0 to 3 in
/// `start`, 4 to 7 in `end`).
///
/// ```
/// use dvh::exact::vertex_face_impact;
///
/// let floor = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// // A point falling from z = 1 to z = -3 through the floor: contact a quarter into the step.
/// let start = [[0.25, 0.25, 1.0], floor[0], floor[1], floor[2]];
/// let end = [[0.25, 0.25, -3.0], floor[0], floor[1], floor[2]];
/// assert_eq!(vertex_face_impact(&start, &end)?, Some(0.25));
/// # Ok::<(), dvh::Error>(())
/// ```
pub fn vertex_face_impact(start: &[Point; 4], end: &[Point; 4]) -> Result<Option<f64>> {
    vertex_face_impact_with(start, end, CcdMode::Exact)
}

/// [`vertex_face_impact`], decided as `mode` says: [`CcdMode::Conservative`] stays in floating
/// point, never misses a contact and never reports a later time, but may report primitives
/// that come within rounding error of contact.
pub fn vertex_face_impact_with(
    start: &[Point; 4],
    end: &[Point; 4],
    mode: CcdMode,
) -> Result<Option<f64>> {
    check_finite(start, end)?;
    Ok(time_of_impact(Primitive::VertexFace, start, end, mode, 1.0))
}

/// Do two segments moving with their ends in straight lines share a point during the step,
/// and when first? `start` and `end` hold edge a's two ends then edge b's, at t = 0 and t = 1.
/// The segments are closed; a zero-length one is its point. Parallel, collinear and
/// overlapping segments are decided exactly like any others.
///
/// Returns and errors as [`vertex_face_impact`].
pub fn edge_edge_impact(start: &[Point; 4], end: &[Point; 4]) -> Result<Option<f64>> {
    edge_edge_impact_with(start, end, CcdMode::Exact)
}

/// [`edge_edge_impact`], decided as `mode` says (see [`vertex_face_impact_with`]).
pub fn edge_edge_impact_with(
    start: &[Point; 4],
    end: &[Point; 4],
    mode: CcdMode,
) -> Result<Option<f64>> {
    check_finite(start, end)?;
    Ok(time_of_impact(Primitive::EdgeEdge, start, end, mode, 1.0))
}

/// The closest points of the point `points[0]` and the closed triangle `points[1..4]` when
/// they are at most `distance` apart (exactly: a pair exactly `distance` apart is reported,
/// and `distance = 0` asks whether they touch), else `None`.
///
/// The closest point on the triangle is unique; its feature is the lowest-dimensional one that
/// holds it (a corner, then an open edge, then the interior), decided exactly. The distance is
/// within one unit in the last place of the exact distance correctly rounded; the closest points
/// and weights within two units of their exact values. A triangle of zero area is the segment or
/// point it covers; where two of its edges hold the closest point alike, the first in the order
/// 01, 12, 20 is reported.
///
/// Errors: [`Error::NonFiniteCoordinate`] naming the point (0 to 3) and axis;
/// [`Error::InvalidDistance`] for a negative, NaN or infinite `distance`.
///
/// ```
/// use dvh::exact::{vertex_face_nearest, Feature};
///
/// let floor = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// // A point 0.5 above the floor's hypotenuse, beyond it: closest on that edge.
/// let n = vertex_face_nearest(&[[0.5, 0.5, 0.5], floor[0], floor[1], floor[2]], 1.0)?.unwrap();
/// assert_eq!(n.features, [Feature::Vertex0, Feature::Edge12]);
/// assert_eq!(n.distance, 0.5);
/// assert_eq!(n.points[1], [0.5, 0.5, 0.0]);
/// assert_eq!(n.weights[1], [0.0, 0.5, 0.5]);
/// # Ok::<(), dvh::Error>(())
/// ```
pub fn vertex_face_nearest(points: &[Point; 4], distance: f64) -> Result<Option<Nearest>> {
    check_nearest(points, distance)?;
    Ok(nearest::nearest(Primitive::VertexFace, points, distance))
}

/// The closest points of the closed segments `points[0..2]` and `points[2..4]` when they are at
/// most `distance` apart, else `None`; exact as [`vertex_face_nearest`]. Where the closest points
/// are not unique (parallel segments), and the lines' closest points are not both strictly
/// inside the segments, the pair is taken at an end: a0 against b, a1 against b, b0 against a,
/// b1 against a, the first of the closest. An edge's interior is [`Feature::Edge01`]; its
/// weights are `(1 - s, s, 0)`.
///
/// Errors as [`vertex_face_nearest`].
pub fn edge_edge_nearest(points: &[Point; 4], distance: f64) -> Result<Option<Nearest>> {
    check_nearest(points, distance)?;
    Ok(nearest::nearest(Primitive::EdgeEdge, points, distance))
}

fn check_nearest(points: &[Point; 4], distance: f64) -> Result<()> {
    for (vertex, p) in points.iter().enumerate() {
        if let Some(axis) = p.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFiniteCoordinate {
                vertex,
                axis,
                value: p[axis],
            });
        }
    }
    if !(distance >= 0.0 && distance.is_finite()) {
        return Err(Error::InvalidDistance { distance });
    }
    Ok(())
}

fn check_finite(start: &[Point; 4], end: &[Point; 4]) -> Result<()> {
    for (vertex, p) in start.iter().chain(end.iter()).enumerate() {
        if let Some(axis) = p.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFiniteCoordinate {
                vertex,
                axis,
                value: p[axis],
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_non_finite_coordinate_is_named() {
        let p = [[0.0; 3]; 4];
        let mut q = p;
        q[2][1] = f64::NAN;
        let e = edge_edge_impact(&p, &q).unwrap_err();
        assert!(
            matches!(
                e,
                Error::NonFiniteCoordinate {
                    vertex: 6,
                    axis: 1,
                    ..
                }
            ),
            "{e}"
        );
        let e = vertex_face_impact(&q, &p).unwrap_err();
        assert!(
            matches!(
                e,
                Error::NonFiniteCoordinate {
                    vertex: 2,
                    axis: 1,
                    ..
                }
            ),
            "{e}"
        );
        let mut r = p;
        r[0][0] = f64::INFINITY;
        assert!(vertex_face_impact(&p, &r).is_err());
        // All eight points at one place: in contact from the start.
        assert_eq!(vertex_face_impact(&p, &p).unwrap(), Some(0.0));
        assert_eq!(edge_edge_impact(&p, &p).unwrap(), Some(0.0));
    }
}
