//! The [`Mesh`] type: topology, current positions, 1-rings, the hierarchy's shape and its
//! bounding volumes.

use super::options::BuildOptions;
use super::patches::{PatchCache, Patches};
use crate::csr::heap_bytes;
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::geometry::sphere::Sphere;
use crate::tree::{RingTable, Tree};
use crate::volume::{Blocks, RadiusKind, RefitInput, RefitStats, Volumes};
use std::sync::Arc;

/// Shape of a built hierarchy, for comparison with the paper's Tables 1 and 2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct TreeStats {
    /// Triangles in the mesh.
    pub triangles: usize,
    /// 1-rings, that is leaves.
    pub rings: usize,
    /// Inner nodes ("clusters" in the paper).
    pub inner_nodes: usize,
    /// Levels: the depth of the deepest leaf plus one.
    pub levels: usize,
    /// Most triangles in one ring.
    pub max_ring_triangles: usize,
}

/// A node's bounding volume after the last refit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoundingVolume {
    /// A ball ([`crate::VolumeKind::Dvh`] and [`crate::VolumeKind::Sbv`]).
    Sphere(Sphere),
    /// A box ([`crate::VolumeKind::Aabb`]).
    Box(Aabb),
}

/// One node of the hierarchy, as seen from outside.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeView {
    /// The volume, in the mesh's own coordinates.
    pub volume: BoundingVolume,
    /// The mesh vertex the sphere is centred on ([`crate::VolumeKind::Dvh`] only).
    pub centre_vertex: Option<u32>,
    /// Distance from the root.
    pub depth: u32,
    /// Child node indices; empty for a leaf.
    pub children: std::ops::Range<u32>,
}

/// What a mesh's positions never change: its triangles, 1-rings and tree. Built once; shared.
#[derive(Debug)]
pub(super) struct Topology {
    pub triangles: Vec<[u32; 3]>,
    pub rings: RingTable,
    pub tree: Tree,
    /// How the tree is cut for lazy refit; built on first use (by a scene's deformable object).
    pub blocks: std::sync::OnceLock<Blocks>,
    /// The nodes' patches for self-collision; found on first use.
    pub patches: std::sync::OnceLock<Patches>,
    /// Who owns each vertex, edge and triangle in continuous collision; found on first use.
    pub features: std::sync::OnceLock<super::features::Features>,
    /// Whether the surface is closed, and the triangles of each vertex and edge, for the
    /// distance and inside-outside queries; found on first use.
    pub surface: std::sync::OnceLock<super::surface::Surface>,
    /// The least triangle index in the rings below each node, for finding the least
    /// intersecting pair without finding them all; found on first use.
    pub least_triangles: std::sync::OnceLock<Vec<u32>>,
}

impl Topology {
    /// What a refit of this shape reads, with `radius` and `positions`.
    pub fn refit_input<'a>(&'a self, radius: RadiusKind, positions: &'a [Point]) -> RefitInput<'a> {
        RefitInput {
            tree: &self.tree,
            rings: &self.rings,
            radius,
            positions,
        }
    }
}

/// A deformable triangle mesh with its bounding-volume hierarchy.
///
/// Built once with [`Mesh::new`]; each frame, [`Mesh::refit`] takes the new vertex positions and
/// recomputes the volumes (for the default DVH volumes, radii only: centres are mesh vertices
/// and move with them). Queries take `&Mesh`, so any number of threads may query one mesh at
/// once; a refit needs `&mut`.
#[derive(Clone)]
pub struct Mesh {
    pub(super) positions: Vec<Point>,
    /// Where a refit writes the new positions while it checks them; swapped with `positions`
    /// once they are all valid.
    pub(super) spare: Vec<Point>,
    /// Triangles, rings and the tree: everything positions do not change, shared by the
    /// clones of a mesh (a scene's objects made from one mesh hold one copy).
    pub(super) topology: Arc<Topology>,
    pub(super) options: BuildOptions,
    pub(super) volumes: Volumes,
    /// Largest coordinate magnitude of the current positions.
    pub(super) max_abs: f64,
    /// Are all current coordinates in the range where the fast exact predicates apply?
    pub(super) in_fast_range: bool,
    pub(super) last_refit: RefitStats,
    /// Names the current positions (and the volumes fitted to them): drawn from a counter shared
    /// by every mesh at build and at every change of positions, copied by a clone. Equal states
    /// mean equal contents, which lets a scene's rigid objects share one copy.
    pub(super) state: u64,
    /// What self-collision finds about the nodes at the current positions (which way their
    /// triangles turn, whether their loops project simply); found on first use and forgotten
    /// when the positions change.
    pub(super) patch_cache: PatchCache,
    /// Stacks for the wrapped-radius search, one per refit thread, sized at build so refits
    /// never allocate.
    pub(super) scratch: Vec<Vec<u32>>,
    /// The start of the step, when the mesh was last given a motion.
    pub(super) motion: super::motion::Motion,
}

/// Everything but the scratch space (the spare positions a refit writes before it knows they are
/// valid, the refit's stack), which holds nothing of the mesh's state.
impl std::fmt::Debug for Mesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mesh")
            .field("positions", &self.positions)
            .field("triangles", &self.topology.triangles)
            .field("options", &self.options)
            .field("rings", &self.topology.rings)
            .field("tree", &self.topology.tree)
            .field("volumes", &self.volumes)
            .field("max_abs", &self.max_abs)
            .field("safe", &self.in_fast_range)
            .field("last_refit", &self.last_refit)
            .field("moving", &self.motion.moving)
            .finish_non_exhaustive()
    }
}

impl Mesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.topology.triangles.len()
    }

    /// Current vertex positions.
    #[inline]
    pub fn positions(&self) -> &[Point] {
        &self.positions
    }

    /// The triangles, as vertex index triples.
    #[inline]
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.topology.triangles
    }

    /// The options the mesh was built with.
    pub fn options(&self) -> BuildOptions {
        self.options
    }

    /// Number of 1-rings (leaves).
    pub fn ring_count(&self) -> usize {
        self.topology.rings.len()
    }

    /// Number of nodes, leaves included. Node 0 is the root.
    pub fn node_count(&self) -> usize {
        self.topology.tree.len()
    }

    /// One node. Panics if `node >= node_count()`.
    pub fn node(&self, node: u32) -> NodeView {
        let i = node as usize;
        let n = &self.topology.tree.nodes[i];
        let (volume, centre_vertex) = match &self.volumes {
            Volumes::Dvh {
                centre_vertex,
                spheres,
            } => (BoundingVolume::Sphere(spheres[i]), Some(centre_vertex[i])),
            Volumes::Sbv { spheres, .. } => (BoundingVolume::Sphere(spheres[i]), None),
            Volumes::Aabb { boxes } => (BoundingVolume::Box(boxes[i]), None),
        };
        NodeView {
            volume,
            centre_vertex,
            depth: u32::from(n.depth),
            children: n.children(),
        }
    }

    /// The triangles below a node (for a leaf, its ring's triangles). Node pairs reported by the
    /// coarse query modes expand to triangle pairs through this. Panics if `node` is out of range.
    pub fn node_triangles(&self, node: u32) -> &[u32] {
        let n = &self.topology.tree.nodes[node as usize];
        self.topology
            .rings
            .triangles
            .row_range(n.ring_start as usize..n.ring_end as usize)
    }

    /// What a refit of this mesh reads.
    pub(crate) fn refit_input(&self) -> RefitInput<'_> {
        self.topology
            .refit_input(self.options.radius, &self.positions)
    }

    /// The centre vertex of each 1-ring, in leaf order.
    pub fn ring_centres(&self) -> &[u32] {
        &self.topology.rings.centre
    }

    /// Bytes of memory the mesh holds beyond the struct itself: its copy of the positions and
    /// the spare copy a refit checks new positions into, the triangles, the rings, the tree's
    /// shape and the volumes. Reported per triangle in `BENCHMARKS.md`. A clone shares the
    /// triangles, rings and tree with the mesh it was cloned from; both count them.
    pub fn memory_bytes(&self) -> usize {
        let tree = heap_bytes(&self.topology.tree.nodes)
            + heap_bytes(&self.topology.tree.leaf_of_ring)
            + heap_bytes(&self.topology.tree.subtrees)
            + self.topology.blocks.get().map_or(0, Blocks::heap_bytes)
            + self.topology.patches.get().map_or(0, Patches::heap_bytes)
            + self
                .topology
                .features
                .get()
                .map_or(0, super::features::Features::heap_bytes)
            + self
                .topology
                .surface
                .get()
                .map_or(0, super::surface::Surface::heap_bytes)
            + self.topology.least_triangles.get().map_or(0, heap_bytes);
        self.state_bytes()
            + heap_bytes(&self.topology.triangles)
            + self.topology.rings.heap_bytes()
            + tree
    }

    /// [`Mesh::memory_bytes`] without what clones share: positions, volumes, scratch.
    pub(crate) fn state_bytes(&self) -> usize {
        let volumes = match &self.volumes {
            Volumes::Dvh {
                centre_vertex,
                spheres,
            } => heap_bytes(centre_vertex) + heap_bytes(spheres),
            Volumes::Sbv { spheres, boxes } => heap_bytes(spheres) + heap_bytes(boxes),
            Volumes::Aabb { boxes } => heap_bytes(boxes),
        };
        let scratch: usize =
            heap_bytes(&self.scratch) + self.scratch.iter().map(heap_bytes).sum::<usize>();
        heap_bytes(&self.positions)
            + heap_bytes(&self.spare)
            + volumes
            + scratch
            + self.patch_cache.heap_bytes()
            + self.motion.heap_bytes()
    }

    /// Number of edges: pairs of distinct vertices joined by a side of some triangle, each
    /// counted once (what continuous collision tests edge against edge). Found on first use.
    pub fn edge_count(&self) -> usize {
        self.features().edge_count()
    }

    /// Counters of the last refit (or of the build's initial fit).
    pub fn last_refit(&self) -> RefitStats {
        self.last_refit
    }

    /// Shape of the hierarchy.
    pub fn tree_stats(&self) -> TreeStats {
        let leaves = self.ring_count();
        TreeStats {
            triangles: self.triangle_count(),
            rings: leaves,
            inner_nodes: self.topology.tree.len() - leaves,
            levels: self.topology.tree.levels(),
            max_ring_triangles: (0..leaves)
                .map(|r| self.topology.rings.triangles.row_len(r))
                .max()
                .unwrap_or(0),
        }
    }

    /// Largest coordinate magnitude of the current positions.
    #[inline]
    pub fn max_abs_coordinate(&self) -> f64 {
        self.max_abs
    }
}

/// What the query and the scene read of a mesh beyond its public API: its shape and volumes,
/// read in their inner loops, hence inlined.
impl Mesh {
    /// The hierarchy's shape.
    #[inline(always)]
    pub(crate) fn tree(&self) -> &Tree {
        &self.topology.tree
    }

    /// The 1-rings in leaf order.
    #[inline(always)]
    pub(crate) fn rings(&self) -> &RingTable {
        &self.topology.rings
    }

    /// The volumes after the last refit.
    #[inline(always)]
    pub(crate) fn volumes(&self) -> &Volumes {
        &self.volumes
    }

    /// The box volumes, to be refit lazily by a scene; `None` for spheres.
    pub(crate) fn boxes_mut(&mut self) -> Option<&mut [Aabb]> {
        match &mut self.volumes {
            Volumes::Aabb { boxes } => Some(boxes),
            _ => None,
        }
    }

    /// Are all current coordinates in the range where the fast adaptive predicates are exact?
    #[inline(always)]
    pub(crate) fn in_fast_range(&self) -> bool {
        self.in_fast_range
    }

    /// Names the current positions (see the field).
    pub(crate) fn state(&self) -> u64 {
        self.state
    }

    /// How the tree is cut for lazy refit, if a lazy refit has cut it.
    pub(crate) fn blocks(&self) -> Option<&Blocks> {
        self.topology.blocks.get()
    }

    /// The nodes' patches for self-collision, found on first use.
    pub(crate) fn patches(&self) -> &Patches {
        self.topology.patches.get_or_init(|| Patches::new(self))
    }

    /// Which ring owns each vertex, edge and triangle in the queries on vertex-face and
    /// edge-edge pairs, found on first use.
    pub(crate) fn features(&self) -> &super::features::Features {
        self.topology.features.get_or_init(|| {
            super::features::Features::new(
                &self.topology.triangles,
                &self.topology.rings,
                self.positions.len(),
            )
        })
    }

    /// The least triangle index in the rings below each node (`u32::MAX` below a node whose
    /// rings hold none), found on first use.
    pub(crate) fn least_triangles(&self) -> &[u32] {
        self.topology.least_triangles.get_or_init(|| {
            let (nodes, rings) = (&self.topology.tree.nodes, &self.topology.rings.triangles);
            let mut least = vec![u32::MAX; nodes.len()];
            // Children come after their parents: a reverse sweep sees them first.
            for n in (0..nodes.len()).rev() {
                let node = &nodes[n];
                least[n] = if node.is_leaf() {
                    (node.ring_start..node.ring_end)
                        .flat_map(|r| rings.row(r as usize).iter().copied())
                        .min()
                        .unwrap_or(u32::MAX)
                } else {
                    node.children()
                        .map(|c| least[c as usize])
                        .min()
                        .unwrap_or(u32::MAX)
                };
            }
            least
        })
    }

    /// The surface's closedness and the triangles of each vertex and edge, found on first use.
    pub(crate) fn surface(&self) -> &super::surface::Surface {
        self.topology.surface.get_or_init(|| {
            super::surface::Surface::new(&self.topology.triangles, self.positions.len())
        })
    }

    /// Is the surface closed: is every directed edge `(u, v)` of a triangle side matched by as
    /// many sides `(v, u)` (a side of a degenerate triangle from a vertex to itself matching
    /// itself)? A closed surface bounds a region: winding numbers about points off it are
    /// integers, and [`crate::winding_numbers`] and [`crate::signed_distances`] answer for it.
    /// Self-intersection, non-manifold edges and degenerate triangles are allowed. Found once
    /// for the mesh's triangles (which never change) and kept.
    pub fn is_closed(&self) -> bool {
        self.surface().open_edge.is_none()
    }

    /// The least directed edge `(u, v)` (by its lower vertex, then its higher) whose sides
    /// `(u, v)` outnumber its sides `(v, u)`: what keeps the surface from being closed; `None`
    /// when it is closed.
    pub fn open_edge(&self) -> Option<[u32; 2]> {
        self.surface().open_edge
    }

    /// Fails with [`Error::NotClosed`](crate::Error::NotClosed) unless the surface is closed.
    pub(crate) fn check_closed(&self) -> crate::Result<()> {
        match self.open_edge() {
            Some(edge) => Err(crate::Error::NotClosed { edge }),
            None => Ok(()),
        }
    }

    /// Do the two meshes share one copy of their triangles, rings and tree?
    #[cfg(test)]
    pub(crate) fn shares_shape_with(&self, other: &Mesh) -> bool {
        Arc::ptr_eq(&self.topology, &other.topology)
    }

    /// Frees the room for new positions of a mesh that is never refit.
    pub(crate) fn drop_spare(&mut self) {
        self.spare = Vec::new();
    }

    /// Gives back the room for new positions that [`Mesh::drop_spare`] took, for a copy that is
    /// refit after all.
    pub(crate) fn keep_spare(&mut self) {
        self.spare.resize(self.positions.len(), [0.0; 3]);
    }
}

/// A state never given before (see [`Mesh::state`]).
pub(crate) fn next_state() -> u64 {
    static STATES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    STATES.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}
