//! Meshes and their hierarchies: input checks, 1-rings, build, refit, validation.

mod features;
pub(crate) use features::Features;
mod input;
#[allow(clippy::module_inception)]
mod mesh;
mod mesh_build;
mod mesh_refit;
mod mesh_validation;
mod motion;
mod options;
mod patches;
pub(crate) mod rings;
mod surface;

pub use crate::volume::{RadiusKind, RefitStats};
pub use mesh::{BoundingVolume, Mesh, NodeView, TreeStats};
pub use mesh_validation::InvariantError;
pub use options::BuildOptions;
pub(crate) use patches::Patches;
pub use patches::scratch_growths;
pub use rings::LeftoverPolicy;
