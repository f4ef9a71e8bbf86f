//! Geometry: exact predicates, the exact triangle test, rigid poses, conservative spheres and
//! boxes.

pub mod aabb;
pub mod adjacent;
pub(crate) mod ball;
pub(crate) mod ccd;
#[cfg(test)]
mod chains;
pub(crate) mod crossing;
pub mod distance;
pub(crate) mod double_double;
pub(crate) mod interval;
pub mod nearest;
pub(crate) mod permanent;
pub mod polygon;
pub mod pose;
pub mod predicates;
pub mod sphere;
pub mod tri_tri;
pub(crate) mod winding;

/// The six orders of a triangle's three corners, for the tests that check an answer under each.
#[cfg(test)]
pub(crate) const CORNER_ORDERS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [1, 2, 0],
    [2, 0, 1],
    [0, 2, 1],
    [2, 1, 0],
    [1, 0, 2],
];

/// Which primitive pair a test takes, as four points: a point and a triangle's corners, or two
/// segments' ends.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Primitive {
    /// A point against a triangle.
    VertexFace,
    /// A segment against a segment.
    EdgeEdge,
}

impl Primitive {
    /// How many of the four points are the first primitive's: the rest are the second's.
    #[inline(always)]
    pub(crate) fn split(self) -> usize {
        match self {
            Primitive::VertexFace => 1,
            Primitive::EdgeEdge => 2,
        }
    }
}

pub use crate::limits::MAX_POSED_MAGNITUDE;
