//! Geometry: exact predicates, the exact triangle test, rigid poses, conservative spheres and
//! boxes.

pub mod aabb;
pub mod adjacent;
pub(crate) mod ccd;
pub mod distance;
pub(crate) mod interval;
pub mod nearest;
pub mod polygon;
pub mod pose;
pub mod predicates;
pub mod sphere;
pub mod tri_tri;

/// Largest magnitude a posed mesh's transformed coordinates may reach. Beyond it, differences of
/// world coordinates could overflow and the sphere tests would no longer be conservative.
pub const MAX_POSED_MAGNITUDE: f64 = 1e300;
