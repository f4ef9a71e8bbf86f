//! Closest-point stencils: the vertex-face and edge-edge pairs of two placed meshes, or of one
//! mesh, within a distance, each with its distance, closest points, barycentric weights and
//! the features the closest points lie on.

mod entry;
mod near_pairs;

pub use entry::{nearest_features, self_nearest_features};
pub use near_pairs::{NearPair, NearPairs};
#[cfg(test)]
mod tests;
