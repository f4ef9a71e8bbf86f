//! The [`Mesh`] type: topology, current positions, 1-rings and the sphere hierarchy over them.

use super::rings::LeftoverPolicy;
use crate::geometry::predicates::Point;

/// How the hierarchy above the 1-rings is split.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TreeKind {
    /// Each node's box of ring centres is cut at its midpoint on all three axes: up to 8
    /// children, shallow trees.
    #[default]
    Octree,
    /// Each node's box is cut at the midpoint of its longest axis: 2 children, deeper trees.
    Binary,
}

/// How a node's radius is computed at each refit.
///
/// Measured on two deforming 52K-triangle meshes with one query per refit (see
/// `examples/frame_timing.rs`), layered radii give the lower time per frame with the octree,
/// whether contact is heavy or light and deformation small or large: the refit is about half as
/// dear and the query only 10-15% dearer. Wrapped radii win when queries dominate (many queries
/// per refit).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RadiusKind {
    /// The largest distance from the node's centre to any vertex below it: the tightest sphere
    /// with that centre (the paper's choice).
    Wrapped,
    /// `max(|c - c_child| + r_child)` over the children: cheaper to refit, looser.
    #[default]
    Layered,
}

/// Options for [`Mesh::new`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct BuildOptions {
    /// Octree or binary tree.
    pub tree: TreeKind,
    /// Wrapped or layered radii.
    pub radius: RadiusKind,
    /// How triangles that touch no ring centre are covered.
    pub leftovers: LeftoverPolicy,
}

impl BuildOptions {
    /// Every combination of the options, for measuring them against each other.
    pub fn all() -> impl Iterator<Item = BuildOptions> {
        [TreeKind::Octree, TreeKind::Binary]
            .into_iter()
            .flat_map(|tree| {
                [RadiusKind::Layered, RadiusKind::Wrapped]
                    .into_iter()
                    .flat_map(move |radius| {
                        [LeftoverPolicy::JoinAdjacent, LeftoverPolicy::ExtraRings]
                            .into_iter()
                            .map(move |leftovers| BuildOptions {
                                tree,
                                radius,
                                leftovers,
                            })
                    })
            })
    }
}

/// A node: its sphere and its place in the tree, in one cache line because the traversal reads
/// both on every visit. Children of a node are contiguous and numbered after it; the rings below
/// a node are the contiguous range `ring_start..ring_end` (rings are stored in leaf order), so are
/// their triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Node {
    /// Current position of the centre vertex (copied at each refit).
    pub centre: Point,
    /// Radius after the last refit, rounded up.
    pub radius: f64,
    /// The mesh vertex the sphere is centred on.
    pub centre_vertex: u32,
    /// First child; for a leaf, unused (equal to `ring_start`).
    pub first_child: u32,
    /// Number of children; 0 for a leaf.
    pub child_count: u32,
    pub ring_start: u32,
    pub ring_end: u32,
    /// Distance from the root, which has depth 0.
    pub depth: u32,
}

impl Node {
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.child_count == 0
    }

    #[inline(always)]
    pub fn children(&self) -> std::ops::Range<u32> {
        self.first_child..self.first_child + self.child_count
    }
}

/// Counters of one refit (the paper's `NU` and the work behind it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RefitStats {
    /// Nodes whose radius was recomputed (`NU`).
    pub nodes_refit: u64,
    /// Vertex-to-centre distances evaluated.
    pub distance_evaluations: u64,
}

/// Shape of a built hierarchy, for comparison with the paper's Tables 1 and 2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
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

/// One node of the hierarchy, as seen from outside.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeView {
    /// The mesh vertex the sphere is centred on.
    pub centre_vertex: u32,
    /// The sphere's centre: the current position of `centre_vertex`.
    pub centre: Point,
    /// The sphere's radius after the last refit (an upper bound, rounded up).
    pub radius: f64,
    /// Distance from the root.
    pub depth: u32,
    /// Child node indices; empty for a leaf.
    pub children: std::ops::Range<u32>,
}

/// A deformable triangle mesh with its DVH hierarchy.
///
/// Built once with [`Mesh::new`]; each frame, [`Mesh::refit`] takes the new vertex positions and
/// recomputes radii only (centres are mesh vertices and move with them). Queries take `&Mesh`, so
/// any number of threads may query one mesh at once; a refit needs `&mut`.
#[derive(Clone, Debug)]
pub struct Mesh {
    pub(crate) positions: Vec<Point>,
    pub(crate) triangles: Vec<[u32; 3]>,
    pub(crate) options: BuildOptions,
    /// Ring `r` (in leaf order) is centred on `ring_centre[r]`.
    pub(crate) ring_centre: Vec<u32>,
    /// Triangles of ring `r`: `ring_tris[ring_tri_start[r]..ring_tri_start[r + 1]]`.
    pub(crate) ring_tri_start: Vec<u32>,
    pub(crate) ring_tris: Vec<u32>,
    /// Corners of `ring_tris[i]`, stored alongside so that the query reads a ring's triangles
    /// from one contiguous run instead of jumping through the triangle array.
    pub(crate) ring_corners: Vec<[u32; 3]>,
    /// Distinct vertices of ring `r`'s triangles other than its centre.
    pub(crate) ring_vert_start: Vec<u32>,
    pub(crate) ring_verts: Vec<u32>,
    pub(crate) nodes: Vec<Node>,
    /// Largest coordinate magnitude of the current positions.
    pub(crate) max_abs: f64,
    /// Are all current coordinates in the range where the fast exact predicates apply?
    pub(crate) safe: bool,
    pub(crate) last_refit: RefitStats,
    /// Stack for the wrapped-radius search, sized at build so refits never allocate.
    pub(crate) scratch: Vec<u32>,
}

impl Mesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Current vertex positions.
    pub fn positions(&self) -> &[Point] {
        &self.positions
    }

    /// The triangles, as vertex index triples.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The options the mesh was built with.
    pub fn options(&self) -> BuildOptions {
        self.options
    }

    /// Number of 1-rings (leaves).
    pub fn ring_count(&self) -> usize {
        self.ring_centre.len()
    }

    /// Number of nodes, leaves included. Node 0 is the root.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// One node. Panics if `node >= node_count()`.
    pub fn node(&self, node: u32) -> NodeView {
        let n = &self.nodes[node as usize];
        NodeView {
            centre_vertex: n.centre_vertex,
            centre: n.centre,
            radius: n.radius,
            depth: n.depth,
            children: n.children(),
        }
    }

    /// The triangles below a node (for a leaf, its ring's triangles). Node pairs reported by the
    /// coarse query modes expand to triangle pairs through this. Panics if `node` is out of range.
    pub fn node_triangles(&self, node: u32) -> &[u32] {
        let n = &self.nodes[node as usize];
        let start = self.ring_tri_start[n.ring_start as usize] as usize;
        let end = self.ring_tri_start[n.ring_end as usize] as usize;
        &self.ring_tris[start..end]
    }

    /// The centre vertex of each 1-ring, in leaf order.
    pub fn ring_centres(&self) -> &[u32] {
        &self.ring_centre
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
            inner_nodes: self.nodes.len() - leaves,
            levels: self
                .nodes
                .iter()
                .map(|n| n.depth as usize + 1)
                .max()
                .unwrap_or(0),
            max_ring_triangles: (0..leaves)
                .map(|r| (self.ring_tri_start[r + 1] - self.ring_tri_start[r]) as usize)
                .max()
                .unwrap_or(0),
        }
    }

    /// Largest coordinate magnitude of the current positions.
    pub fn max_abs_coordinate(&self) -> f64 {
        self.max_abs
    }
}
