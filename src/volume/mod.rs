//! Bounding volumes on a [`Tree`](crate::tree::Tree)'s nodes, one array per kind, and their refit.
//! The shape, the builder and the traversal are shared; only what a node's volume is and how a
//! refit recomputes it differ between the kinds.

mod boxes;
mod dvh_centres;
mod fit;
mod lazy;
mod motion;
mod spheres;

use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::geometry::sphere::Sphere;
use crate::tree::RingTable;
use crate::tree::Tree;
use boxes::FitBoxes;
pub(crate) use dvh_centres::assign_centres;
pub(crate) use fit::REFIT_PARALLEL_MIN_RINGS;
use fit::{NodeSlice, VolumeSlices};
pub(crate) use lazy::{Blocks, Freshness, LazyBoxes};
use spheres::{FitDvh, FitSbv};

/// The bounding volume on every node of a mesh's hierarchy.
///
/// All three share the 1-ring leaves and the tree builders, so comparing them isolates the
/// volume. Measured in `BENCHMARKS.md`: on meshes that deform (refit every frame, queried in
/// their own coordinates) boxes are the fastest on every scene measured, the paper's three and
/// dense contact, so they are the default; on rigid meshes placed by poses and never refit, SBV's
/// spheres are the fastest (boxes must grow to hold their rotated selves), which
/// [`crate::BuildOptions::rigid`] chooses. The paper's DVH comes between the two when rigid and
/// on two of the three paper scenes, last on the many-object one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum VolumeKind {
    /// The paper's DVH: spheres centred on mesh vertices chosen at build (a leaf on its ring's
    /// centre, an inner node on the vertex below it nearest to their mean), so a refit copies
    /// the centres and recomputes radii only. Rotation-invariant: a pose moves a sphere without
    /// loosening it.
    Dvh,
    /// A standard sphere tree (the paper's SBV): every refit recomputes each centre, as the
    /// midpoint of the box of the vertices below the node, and then its radius. The midpoint is
    /// found bottom-up from the children's boxes in constant time per node and, unlike the mean
    /// of the vertices, is not pulled towards densely sampled parts, which would lengthen the
    /// radius to the sparse ones.
    Sbv,
    /// Axis-aligned boxes of the vertices below each node, refit bottom-up (a leaf's box from
    /// its ring's vertices, an inner node's as the union of its children's). Exact and the
    /// tightest of the three on deforming meshes; a pose must widen each box to the axis-aligned
    /// box of the rotated one. The default.
    #[default]
    Aabb,
}

/// How a sphere's radius is computed at each refit ([`VolumeKind::Dvh`] and [`VolumeKind::Sbv`];
/// boxes are always the exact union of their children).
///
/// Measured on the paper's scenes (`BENCHMARKS.md`): with a refit every frame, layered radii
/// give the lower time per frame (the refit about half as dear, the query 10-20% dearer);
/// wrapped radii win when there is no refit to pay for, as for rigid meshes placed by poses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum RadiusKind {
    /// The largest distance from the node's centre to any vertex below it: the tightest sphere
    /// with that centre (the paper's choice).
    Wrapped,
    /// `max(|c - c_child| + r_child)` over the children: cheaper to refit, looser.
    #[default]
    Layered,
}

/// Counters of one refit (the paper's `NU` and the work behind it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct RefitStats {
    /// Nodes whose volume was recomputed (`NU`).
    pub nodes_refit: u64,
    /// Vertex-to-centre distances evaluated (for boxes: vertices folded into leaf boxes).
    pub distance_evaluations: u64,
}

/// The volumes of one mesh, indexed by node.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Volumes {
    /// Node `n`'s sphere is centred on vertex `centre_vertex[n]`.
    Dvh {
        centre_vertex: Vec<u32>,
        spheres: Vec<Sphere>,
    },
    /// `boxes` holds each node's box of vertices from the last refit: the centres' source.
    Sbv {
        spheres: Vec<Sphere>,
        boxes: Vec<Aabb>,
    },
    Aabb {
        boxes: Vec<Aabb>,
    },
}

impl Volumes {
    /// Storage for `node_count` nodes of `kind`, before the first refit. DVH centres are given.
    pub fn new(kind: VolumeKind, node_count: usize, centre_vertex: Vec<u32>) -> Volumes {
        match kind {
            VolumeKind::Dvh => Volumes::Dvh {
                centre_vertex,
                spheres: vec![Sphere::default(); node_count],
            },
            VolumeKind::Sbv => Volumes::Sbv {
                spheres: vec![Sphere::default(); node_count],
                boxes: vec![Aabb::EMPTY; node_count],
            },
            VolumeKind::Aabb => Volumes::Aabb {
                boxes: vec![Aabb::EMPTY; node_count],
            },
        }
    }

    /// Recomputes every volume from `input.positions` on at most `stacks.len()` threads (each with
    /// its scratch stack for the wrapped-radius search, sized at build), the same result
    /// whatever their number. Allocates nothing.
    pub fn refit(&mut self, input: &RefitInput, stacks: &mut [Vec<u32>]) -> RefitStats {
        let nodes = input.tree.len() as u64;
        let evaluations = match self {
            Volumes::Dvh {
                centre_vertex,
                spheres,
            } => {
                let w = VolumeSlices {
                    spheres: NodeSlice::whole(spheres),
                    boxes: NodeSlice::whole(&mut []),
                };
                fit::refit(&FitDvh { centre_vertex }, w, input, stacks)
            }
            Volumes::Sbv { spheres, boxes } => {
                let w = VolumeSlices {
                    spheres: NodeSlice::whole(spheres),
                    boxes: NodeSlice::whole(boxes),
                };
                fit::refit(&FitSbv, w, input, stacks)
            }
            Volumes::Aabb { boxes } => {
                let w = VolumeSlices {
                    spheres: NodeSlice::whole(&mut []),
                    boxes: NodeSlice::whole(boxes),
                };
                fit::refit(&FitBoxes, w, input, stacks)
            }
        };
        RefitStats {
            nodes_refit: nodes,
            distance_evaluations: evaluations,
        }
    }

    /// Which kind these are.
    pub fn kind(&self) -> VolumeKind {
        match self {
            Volumes::Dvh { .. } => VolumeKind::Dvh,
            Volumes::Sbv { .. } => VolumeKind::Sbv,
            Volumes::Aabb { .. } => VolumeKind::Aabb,
        }
    }
}

/// What a refit reads: the shape, the rings, the radius kind, and the positions.
#[derive(Clone, Copy)]
pub(crate) struct RefitInput<'a> {
    pub tree: &'a Tree,
    pub rings: &'a RingTable,
    pub radius: RadiusKind,
    pub positions: &'a [Point],
}
