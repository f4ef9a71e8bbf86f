//! Intersection curves: where two meshes, or one mesh with itself, cross, as chains of exact
//! segments, one per intersecting triangle pair, joined by the mesh features at their ends.

mod chain;
mod entry;
mod measure;
mod result;

pub use entry::{intersection_curves, self_intersection_curves};
pub use result::{Curve, CurvePoint, CurveSegment, Curves, DegenerateKind, DegeneratePair};
#[cfg(test)]
mod tests;
