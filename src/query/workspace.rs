//! Scratch space of a query, kept between queries so that steady state allocates nothing.

use crate::geometry::predicates::Point;
use crate::geometry::tri_tri::Triangle;

/// World positions of a posed mesh's vertices, computed when first needed in a query. A vertex
/// is current when its stamp equals the query's.
#[derive(Debug, Default)]
pub(crate) struct VertexCache {
    pub world: Vec<Point>,
    pub stamp: Vec<u32>,
    pub current: u32,
}

impl VertexCache {
    /// Starts a query over `vertex_count` vertices: grows the arrays if needed and invalidates
    /// every cached position.
    pub fn begin(&mut self, vertex_count: usize) {
        if self.world.len() < vertex_count {
            self.world.resize(vertex_count, [0.0; 3]);
            self.stamp.resize(vertex_count, 0);
        }
        if self.current == u32::MAX {
            self.stamp.fill(0);
            self.current = 0;
        }
        self.current += 1;
    }
}

/// A triangle gathered for ring-against-ring tests: its index, corners, box, and whether its
/// coordinates are in the fast predicates' safe range.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Gathered {
    pub index: u32,
    pub corners: Triangle,
    pub lo: Point,
    pub hi: Point,
    pub safe: bool,
}

/// One ring's triangles gathered in the query frame, with the box around them all. Kept while
/// the traversal stays on the same ring (consecutive leaf pairs often share one side).
#[derive(Debug, Default)]
pub(crate) struct GatheredRing {
    /// The ring held, or `u32::MAX` for none.
    pub ring: u32,
    pub tris: Vec<Gathered>,
    pub lo: Point,
    pub hi: Point,
    /// Indices into `tris` of the triangles whose boxes meet the other ring's box.
    pub selected: Vec<u32>,
}

/// Everything a query needs besides its inputs and output.
#[derive(Debug, Default)]
pub(crate) struct Workspace {
    pub stack: Vec<(u32, u32)>,
    pub cache_a: VertexCache,
    pub cache_b: VertexCache,
    pub ring_a: GatheredRing,
    pub ring_b: GatheredRing,
}
