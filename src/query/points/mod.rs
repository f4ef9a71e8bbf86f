//! Queries of many points against one mesh: the closest point of the surface, the winding
//! number about it, the signed distance to it. The points are taken in Morton order and shared
//! out in blocks; each point's walks start from its predecessor's answer.

mod closest;
mod options;
mod order;
mod signed;
#[cfg(test)]
mod tests;
pub(crate) mod walk;
mod winding;

pub use closest::{ClosestPoint, closest_points};
pub use options::DistanceOptions;
pub use signed::signed_distances;
pub use winding::{WINDING_ON_SURFACE, winding_numbers};
