//! Scratch space of a query, kept between queries so that steady state allocates nothing.

use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::geometry::tri_tri::Triangle;
use std::collections::BinaryHeap;

/// Values computed when first needed in a query (world positions of a posed mesh's vertices,
/// boxes of rings): an entry is current when its stamp equals the query's, so starting a query
/// invalidates everything without touching the entries.
#[derive(Debug, Default)]
pub(crate) struct Stamped<T> {
    pub values: Vec<T>,
    pub stamp: Vec<u32>,
    pub current: u32,
}

impl<T: Copy + Default> Stamped<T> {
    /// Starts a query over `count` entries: grows the arrays if needed and invalidates every
    /// entry.
    pub fn begin(&mut self, count: usize) {
        if self.values.len() < count {
            self.values.resize(count, T::default());
            self.stamp.resize(count, 0);
        }
        if self.current == u32::MAX {
            self.stamp.fill(0);
            self.current = 0;
        }
        self.current += 1;
    }

    /// Entry `i`, computed by `make` unless already current.
    #[inline(always)]
    pub fn get_or(&mut self, i: usize, make: impl FnOnce() -> T) -> T {
        if self.stamp[i] != self.current {
            self.values[i] = make();
            self.stamp[i] = self.current;
        }
        self.values[i]
    }
}

/// A triangle gathered for ring-against-ring tests: its index, corners, box, and whether its
/// coordinates are in the fast predicates' safe range.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Gathered {
    pub index: u32,
    pub corners: Triangle,
    pub bounds: Aabb,
    pub safe: bool,
}

/// One ring's triangles gathered in the query frame, with the box around them all. Kept while
/// the traversal stays on the same ring (consecutive leaf pairs often share one side).
#[derive(Debug, Default)]
pub(crate) struct GatheredRing {
    /// The ring held, or `u32::MAX` for none.
    pub ring: u32,
    pub tris: Vec<Gathered>,
    pub bounds: Aabb,
    /// Indices into `tris` of the triangles whose boxes meet the other ring's box.
    pub selected: Vec<u32>,
}

/// What a query keeps per mesh between queries.
#[derive(Debug, Default)]
pub(crate) struct SideSpace {
    /// World positions of a posed mesh's vertices.
    pub world: Stamped<Point>,
    /// Boxes of rings' vertices in the query frame.
    pub ring_boxes: Stamped<Aabb>,
    pub ring: GatheredRing,
}

impl SideSpace {
    /// Starts a query on a mesh of `vertices` vertices and `rings` rings.
    pub fn begin(&mut self, vertices: usize, rings: usize, posed: bool) {
        if posed {
            self.world.begin(vertices);
        }
        self.ring_boxes.begin(rings);
        self.ring.ring = u32::MAX;
    }
}

/// Everything a query needs besides its inputs and output.
#[derive(Debug, Default)]
pub(crate) struct Workspace {
    /// Node pairs still to open, depth first.
    pub stack: Vec<(u32, u32)>,
    /// Node pairs still to open, largest first ([`crate::QueryMode::Budget`]).
    pub queue: BinaryHeap<Queued>,
    pub a: SideSpace,
    pub b: SideSpace,
    /// The counters of the result's sort.
    pub sort_counts: Vec<usize>,
}

/// A node pair waiting in the budgeted traversal, ordered by the size of its larger volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Queued {
    /// The bits of the larger squared size: non-negative doubles order as their bits do.
    pub key: u64,
    pub a: u32,
    pub b: u32,
}
