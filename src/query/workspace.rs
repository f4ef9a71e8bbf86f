//! Scratch space of a query, kept between queries so that steady state allocates nothing.

use super::pairs::{Pair, QueryStats};
use super::sink::Stop;
use crate::csr::heap_bytes;
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

/// What one thread of a query works with: its traversal stack, its caches of each side, and
/// (when several threads share the query) the pairs it found.
#[derive(Debug, Default)]
pub(crate) struct Worker {
    /// Node pairs still to open, depth first.
    pub stack: Vec<(u32, u32)>,
    pub a: SideSpace,
    pub b: SideSpace,
    /// The pairs this thread found, item after item (threaded queries only).
    pub out: Vec<Pair>,
    /// The items this thread took: `(item, start, end)` of its pairs in `out`.
    pub done: Vec<(usize, usize, usize)>,
    /// `out` distributed into buckets for the result's sort, and where each bucket starts.
    pub bucketed: Vec<Pair>,
    pub bucket_starts: Vec<u32>,
    pub stats: QueryStats,
    pub stop: Option<Stop>,
}

/// Everything a query needs besides its inputs and output.
#[derive(Debug, Default)]
pub(crate) struct Workspace {
    /// One per thread that has worked through this buffer; the first is the calling thread's.
    pub workers: Vec<Worker>,
    /// Node pairs still to open, largest first ([`crate::QueryMode::Budget`]).
    pub queue: BinaryHeap<Queued>,
    /// The counters of the result's sort.
    pub sort_counts: Vec<u32>,
    /// A threaded query's items: the node pairs whose subtrees the threads share out, in the
    /// order the single-threaded traversal reaches them, and the next level being split.
    pub items: Vec<(u32, u32)>,
    pub next_items: Vec<(u32, u32)>,
    /// Per item: the pairs it found (`usize::MAX` while pending), to cut at the pair limit.
    pub item_counts: Vec<std::sync::atomic::AtomicUsize>,
    /// Per item: `(worker, start, end)` of its pairs.
    pub item_pairs: Vec<(usize, usize, usize)>,
}

impl<T> Stamped<T> {
    fn heap_bytes(&self) -> usize {
        heap_bytes(&self.values) + heap_bytes(&self.stamp)
    }
}

impl SideSpace {
    fn heap_bytes(&self) -> usize {
        let r = &self.ring;
        self.world.heap_bytes()
            + self.ring_boxes.heap_bytes()
            + heap_bytes(&r.tris)
            + heap_bytes(&r.selected)
    }
}

impl Worker {
    fn heap_bytes(&self) -> usize {
        heap_bytes(&self.stack)
            + self.a.heap_bytes()
            + self.b.heap_bytes()
            + heap_bytes(&self.out)
            + heap_bytes(&self.done)
            + heap_bytes(&self.bucketed)
            + heap_bytes(&self.bucket_starts)
    }
}

impl Workspace {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        heap_bytes(&self.workers)
            + self.workers.iter().map(Worker::heap_bytes).sum::<usize>()
            + self.queue.capacity() * std::mem::size_of::<Queued>()
            + heap_bytes(&self.sort_counts)
            + heap_bytes(&self.items)
            + heap_bytes(&self.next_items)
            + heap_bytes(&self.item_counts)
            + heap_bytes(&self.item_pairs)
    }
}

/// A node pair waiting in the budgeted traversal, ordered by the size of its larger volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Queued {
    /// The bits of the larger squared size: non-negative doubles order as their bits do.
    pub key: u64,
    pub a: u32,
    pub b: u32,
}
