//! Scratch space of a query, kept between queries so that steady state allocates nothing.

use super::pairs::{Pair, QueryStats};
use super::sink::Stop;
use crate::csr::heap_bytes;
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::geometry::tri_tri::PreparedTriangle;
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

/// A triangle of a ring prepared in the query frame: its index, its box, and what the exact test
/// keeps of it (used only when its coordinates are `safe` for the fast predicates).
#[derive(Debug, Default)]
pub(crate) struct Prepared {
    pub bounds: Aabb,
    pub index: u32,
    pub safe: bool,
    pub tri: PreparedTriangle,
}

/// Rings' triangles prepared in the query frame, kept in a small direct-mapped cache: ring `r`
/// in slot `r mod SLOTS`. Rings are numbered in leaf order, so the rings a stretch of the
/// traversal meets are near each other in number and fall in different slots; a ring meets
/// several others, at nearby times (on scanned meshes in dense contact, each was gathered 2.7
/// to 5.3 times per query when only the last one was kept). Small enough to stay in the core's
/// cache, unlike one entry per triangle of the mesh.
#[derive(Debug, Default)]
pub(crate) struct RingCache {
    /// Per slot: the query's stamp (high half) and the ring held (low half); zero for none.
    tags: Vec<u64>,
    /// The current query's stamp.
    current: u32,
    /// Triangles per slot.
    slot_len: usize,
    /// Per slot: the box of the ring's triangles.
    pub bounds: Vec<Aabb>,
    /// Per slot: the ring's triangles, from `slot * slot_len`.
    pub tris: Vec<Prepared>,
    /// Indices in a slot of the triangles of the ring being tested whose boxes meet the other
    /// ring's box.
    pub selected: Vec<u32>,
}

impl RingCache {
    /// Slots of the cache.
    const SLOTS: usize = 64;

    /// Starts a query whose rings hold at most `longest` triangles: grows the slots if needed and
    /// empties them.
    pub fn begin(&mut self, longest: usize) {
        if self.tags.len() < Self::SLOTS {
            self.tags.resize(Self::SLOTS, 0);
            self.bounds.resize(Self::SLOTS, Aabb::EMPTY);
        }
        if self.slot_len < longest {
            self.slot_len = longest;
            self.tris.clear();
            self.tris
                .resize_with(Self::SLOTS * longest, Prepared::default);
        }
        if self.current == u32::MAX {
            self.tags.fill(0);
            self.current = 0;
        }
        self.current += 1;
    }

    /// Ring `r`'s slot, and whether it already holds the ring (otherwise the caller fills it,
    /// and it is marked as holding it).
    #[inline(always)]
    pub fn slot(&mut self, r: u32) -> (usize, bool) {
        let s = r as usize % Self::SLOTS;
        let tag = (u64::from(self.current) << 32) | u64::from(r);
        let held = self.tags[s] == tag;
        self.tags[s] = tag;
        (s, held)
    }

    /// Where slot `s`'s triangles start in `tris`.
    #[inline(always)]
    pub fn start(&self, s: usize) -> usize {
        s * self.slot_len
    }
}

/// What a query keeps per mesh between queries.
#[derive(Debug, Default)]
pub(crate) struct SideSpace {
    /// World positions of a posed mesh's vertices.
    pub world: Stamped<Point>,
    /// Boxes of rings' vertices in the query frame.
    pub ring_boxes: Stamped<Aabb>,
    /// Rings' triangles, for the exact modes.
    pub rings: RingCache,
}

impl SideSpace {
    /// Starts a query on a mesh of `vertices` vertices and `rings` rings, whose longest ring holds
    /// `longest` triangles (`None` when the query tests no triangles).
    pub fn begin(&mut self, vertices: usize, rings: usize, longest: Option<usize>, posed: bool) {
        if posed {
            self.world.begin(vertices);
        }
        self.ring_boxes.begin(rings);
        if let Some(longest) = longest {
            self.rings.begin(longest);
        }
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
        let r = &self.rings;
        self.world.heap_bytes()
            + self.ring_boxes.heap_bytes()
            + heap_bytes(&r.tags)
            + heap_bytes(&r.bounds)
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
