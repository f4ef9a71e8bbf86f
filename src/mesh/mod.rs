//! Meshes and their hierarchies: input checks, 1-rings, build, refit, validation.

mod input;
#[allow(clippy::module_inception)]
mod mesh;
mod mesh_build;
mod mesh_refit;
mod mesh_validation;
pub(crate) mod rings;

pub use mesh::{BuildOptions, Mesh, NodeView, RadiusKind, RefitStats, TreeKind, TreeStats};
pub use mesh_validation::InvariantError;
pub use rings::LeftoverPolicy;
