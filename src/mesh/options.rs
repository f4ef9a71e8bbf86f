//! [`BuildOptions`]: how a mesh's hierarchy is built and refit.

use super::rings::LeftoverPolicy;
use crate::tree::TreeKind;
use crate::volume::{RadiusKind, VolumeKind};

/// Options for [`crate::Mesh::new`]. The defaults (octree, boxes) are the fastest measured for
/// meshes that deform; [`BuildOptions::rigid`] for meshes that only move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
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
