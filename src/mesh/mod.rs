//! Meshes and their hierarchies: input checks, 1-rings, build, refit, validation.

mod input;
#[allow(clippy::module_inception)]
mod mesh;
mod mesh_build;
mod mesh_refit;
mod mesh_validation;
mod options;
mod ring_table;
pub(crate) mod rings;

pub use mesh::{BoundingVolume, Mesh, NodeView, RefitStats, TreeStats};
pub use mesh_validation::InvariantError;
pub use options::{BuildOptions, RadiusKind};
pub(crate) use ring_table::RingTable;
pub use rings::LeftoverPolicy;
