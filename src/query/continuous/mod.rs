//! Continuous collision of moving meshes: which vertex-face and edge-edge pairs meet during a
//! step, and when first.

mod entry;
mod impacts;
mod sweeps;

pub(crate) use entry::impacts_sharing;
pub use entry::{continuous_collide, self_continuous_collide};
pub use impacts::{CcdOptions, CcdStats, Impact, ImpactKind, Impacts};
#[cfg(test)]
mod tests;
