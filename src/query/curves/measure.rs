//! Measures of intersection curves.

use crate::geometry::predicates::Point;

/// The Euclidean distance between `p` and `q`, without overflow or underflow in between.
pub(crate) fn distance(p: &Point, q: &Point) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    d[0].hypot(d[1]).hypot(d[2])
}
