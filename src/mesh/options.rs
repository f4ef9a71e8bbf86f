//! [`BuildOptions`]: how a mesh's hierarchy is built and refit.

use super::rings::LeftoverPolicy;
use crate::tree::TreeKind;
use crate::volume::{RadiusKind, VolumeKind};

/// Options for [`crate::Mesh::new`]. The defaults (octree, boxes) are the fastest measured for
/// meshes that deform; [`BuildOptions::rigid`] for meshes that only move. Start from either and
/// set what you need with the `with_*` methods (or the fields).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct BuildOptions {
    /// Octree or binary tree.
    pub tree: TreeKind,
    /// Wrapped or layered radii (spheres only).
    pub radius: RadiusKind,
    /// How triangles that touch no ring centre are covered.
    pub leftovers: LeftoverPolicy,
    /// The bounding volume on every node: vertex-centred spheres (DVH), spheres recentred at
    /// every refit (SBV), or axis-aligned boxes.
    pub volume: VolumeKind,
    /// Threads each [`crate::Mesh::refit`] may use: 0 (the default) for every core, 1 for the
    /// calling thread only, `n` for at most `n`, from rayon's global pool (no refit creates
    /// threads). The volumes are the same whatever the count. Meshes of fewer than 8,192 rings
    /// (about as many as vertices) refit on the calling thread, where handing subtrees out
    /// costs more than it saves. The build itself runs on the calling thread.
    pub refit_threads: u32,
}

impl BuildOptions {
    /// The options that measured fastest for rigid meshes, moved by poses and never refit:
    /// SBV spheres with wrapped radii on an octree (see [`VolumeKind`]). The defaults are the
    /// fastest for meshes that deform.
    pub fn rigid() -> BuildOptions {
        BuildOptions {
            tree: TreeKind::Octree,
            radius: RadiusKind::Wrapped,
            leftovers: LeftoverPolicy::JoinAdjacent,
            volume: VolumeKind::Sbv,
            refit_threads: 0,
        }
    }

    /// These options with [`BuildOptions::tree`] set.
    pub fn with_tree(self, tree: TreeKind) -> BuildOptions {
        BuildOptions { tree, ..self }
    }

    /// These options with [`BuildOptions::radius`] set.
    pub fn with_radius(self, radius: RadiusKind) -> BuildOptions {
        BuildOptions { radius, ..self }
    }

    /// These options with [`BuildOptions::leftovers`] set.
    pub fn with_leftovers(self, leftovers: LeftoverPolicy) -> BuildOptions {
        BuildOptions { leftovers, ..self }
    }

    /// These options with [`BuildOptions::volume`] set: `BuildOptions::default()
    /// .with_volume(VolumeKind::Dvh)`.
    pub fn with_volume(self, volume: VolumeKind) -> BuildOptions {
        BuildOptions { volume, ..self }
    }

    /// These options with [`BuildOptions::refit_threads`] set.
    pub fn with_refit_threads(self, refit_threads: u32) -> BuildOptions {
        BuildOptions {
            refit_threads,
            ..self
        }
    }

    /// Every distinct combination of the options, for measuring them against each other (the
    /// radius kind only for the sphere volumes: boxes have none).
    pub fn all() -> impl Iterator<Item = BuildOptions> {
        let trees = [TreeKind::Octree, TreeKind::Binary];
        let leftovers = [LeftoverPolicy::JoinAdjacent, LeftoverPolicy::ExtraRings];
        let shapes = [
            (VolumeKind::Dvh, RadiusKind::Layered),
            (VolumeKind::Dvh, RadiusKind::Wrapped),
            (VolumeKind::Sbv, RadiusKind::Layered),
            (VolumeKind::Sbv, RadiusKind::Wrapped),
            (VolumeKind::Aabb, RadiusKind::default()),
        ];
        shapes.into_iter().flat_map(move |(volume, radius)| {
            trees.into_iter().flat_map(move |tree| {
                leftovers.into_iter().map(move |leftovers| BuildOptions {
                    tree,
                    radius,
                    leftovers,
                    volume,
                    refit_threads: 0,
                })
            })
        })
    }
}
