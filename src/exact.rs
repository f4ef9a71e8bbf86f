//! The exact predicates the queries decide with, for use on their own: do two triangles meet,
//! are they within a distance, on which side of a plane does a point lie.
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

use crate::geometry::{distance, predicates, tri_tri};

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
