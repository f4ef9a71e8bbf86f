//! Scratch space of a query, kept between queries so that steady state allocates nothing.

use super::sink::Stop;
use crate::csr::heap_bytes;
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::geometry::tri_tri::{
    PreparedTriangle, prepared_triangles_intersect, triangles_intersect,
};
use crate::query::pairs::{Pair, QueryStats};
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
/// keeps of it (used only when its coordinates are `in_fast_range` of the fast predicates).
#[derive(Debug, Default)]
pub(crate) struct Prepared {
    pub bounds: Aabb,
    pub index: u32,
    pub in_fast_range: bool,
    pub tri: PreparedTriangle,
}

impl Prepared {
    /// Do the two closed triangles share a point? Exact: with the fast predicates where both
    /// are in their range, otherwise from the corners.
    #[inline]
    pub fn intersects(&self, other: &Prepared) -> bool {
        if self.in_fast_range && other.in_fast_range {
            prepared_triangles_intersect(&self.tri, &other.tri)
        } else {
            triangles_intersect(&self.tri.corners, &other.tri.corners)
        }
    }
}

/// Rings' triangles prepared in the query frame, kept while the traversal is near them: a ring
/// meets several others at nearby times (on scanned meshes in dense contact, each was gathered
/// 2.7 to 5.3 times per query when only the last one was kept).
///
/// Ring `r` is looked up in slot `r mod SLOTS` (rings are numbered in leaf order, so the rings a
/// stretch of the traversal meets fall in different slots); its triangles are written one after
/// the other into an arena used as a ring buffer, and a slot holds as long as the arena has not
/// come round over its triangles. The arena holds [`RingCache::ARENA`] triangles, or the longest
/// ring if that is longer: a fixed size that stays in the core's cache, whatever the mesh's
/// valences.
#[derive(Debug, Default)]
pub(crate) struct RingCache {
    /// Per slot: the query's stamp (high half) and the ring held (low half); zero for none.
    tags: Vec<u64>,
    /// Per slot: where the ring's triangles start, counted in triangles written since the arena
    /// was sized, and the box around them.
    slots: Vec<(u64, Aabb)>,
    /// The current query's stamp.
    current: u32,
    /// Triangles written into the arena since it was sized (a ring that would cross its end
    /// starts over at its beginning; the skipped tail counts as written).
    written: u64,
    /// The arena of prepared triangles.
    pub tris: Vec<Prepared>,
    /// Indices of the triangles of the ring being tested whose boxes meet the other ring's box,
    /// from the ring's start in `tris`.
    pub selected: Vec<u32>,
}

impl RingCache {
    /// Slots of the cache.
    const SLOTS: usize = 64;
    /// Triangles of the arena, at least: 64 rings of 16 (scanned meshes average about 7).
    pub const ARENA: usize = 1024;

    /// Starts a query whose rings hold at most `longest` triangles: grows the arena if needed
    /// and forgets every ring. On failure to allocate, the bytes that were wanted.
    pub fn begin(&mut self, longest: usize) -> Result<(), usize> {
        if self.tags.len() < Self::SLOTS {
            self.tags.resize(Self::SLOTS, 0);
            self.slots.resize(Self::SLOTS, (0, Aabb::EMPTY));
        }
        let size = longest.max(Self::ARENA);
        if self.tris.len() < size {
            let more = size - self.tris.len();
            let bytes = more * std::mem::size_of::<Prepared>();
            self.tris.try_reserve_exact(more).map_err(|_| bytes)?;
            self.tris.resize_with(size, Prepared::default);
            self.written = 0;
        }
        self.selected.clear();
        self.selected
            .try_reserve(longest)
            .map_err(|_| longest * std::mem::size_of::<u32>())?;
        if self.current == u32::MAX {
            self.tags.fill(0);
            self.current = 0;
        }
        self.current += 1;
        Ok(())
    }

    #[inline(always)]
    fn tag(&self, r: u32) -> u64 {
        (u64::from(self.current) << 32) | u64::from(r)
    }

    /// Ring `r`'s triangles (from where they start in `tris`) and their box, if still held.
    #[inline(always)]
    pub fn held(&self, r: u32) -> Option<(usize, Aabb)> {
        let s = r as usize % Self::SLOTS;
        let (start, bounds) = self.slots[s];
        let size = self.tris.len() as u64;
        (self.tags[s] == self.tag(r) && self.written <= start + size)
            .then_some(((start % size) as usize, bounds))
    }

    /// Room for ring `r`'s `len` triangles (at most the arena's size): where they start in
    /// `tris`. The ring is held once [`RingCache::filled`] gives its box.
    #[inline]
    pub fn place(&mut self, r: u32, len: usize) -> usize {
        let size = self.tris.len() as u64;
        debug_assert!(len as u64 <= size);
        let at = self.written % size;
        if at + len as u64 > size {
            self.written += size - at;
        }
        let start = self.written;
        self.written += len as u64;
        let s = r as usize % Self::SLOTS;
        self.tags[s] = self.tag(r);
        self.slots[s].0 = start;
        (start % size) as usize
    }

    /// Ring `r`, just placed and filled, has the box `bounds`.
    #[inline]
    pub fn filled(&mut self, r: u32, bounds: Aabb) {
        self.slots[r as usize % Self::SLOTS].1 = bounds;
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
    /// `longest` triangles (`None` when the query tests no triangles). On failure to allocate the
    /// ring cache, the bytes that were wanted.
    pub fn begin(
        &mut self,
        vertices: usize,
        rings: usize,
        longest: Option<usize>,
        posed: bool,
    ) -> Result<(), usize> {
        if posed {
            self.world.begin(vertices);
        }
        self.ring_boxes.begin(rings);
        match longest {
            Some(longest) => self.rings.begin(longest),
            None => Ok(()),
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

/// A threaded query's items: the node pairs whose subtrees the threads share out, in the order
/// the single-threaded traversal reaches them, and the next level while the top is split.
#[derive(Debug, Default)]
pub(crate) struct Split {
    pub items: Vec<(u32, u32)>,
    pub next: Vec<(u32, u32)>,
}

/// Everything a query needs besides its inputs and output.
#[derive(Debug, Default)]
pub(crate) struct Workspace {
    /// One per thread that has worked through this buffer; the first is the calling thread's.
    pub workers: Vec<Worker>,
    /// Node pairs still to open: largest first ([`crate::QueryMode::Budget`]), or least pair
    /// first (the least intersecting pair).
    pub queue: BinaryHeap<Queued>,
    /// The counters of the result's sort.
    pub sort_counts: Vec<u32>,
    /// A threaded query's items.
    pub split: Split,
    /// Per item: the pairs it found (`usize::MAX` while pending), to cut at the pair limit.
    pub item_counts: Vec<std::sync::atomic::AtomicUsize>,
    /// Per item: `(worker, start, end)` of its pairs.
    pub item_pairs: Vec<(usize, usize, usize)>,
}

impl<T> Stamped<T> {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        heap_bytes(&self.values) + heap_bytes(&self.stamp)
    }
}

impl SideSpace {
    fn heap_bytes(&self) -> usize {
        let r = &self.rings;
        self.world.heap_bytes()
            + self.ring_boxes.heap_bytes()
            + heap_bytes(&r.tags)
            + heap_bytes(&r.slots)
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
            + heap_bytes(&self.split.items)
            + heap_bytes(&self.split.next)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring is held until the arena comes round over its triangles or another ring takes its
    /// slot, and never after; a new query forgets every ring.
    #[test]
    fn ring_cache_holds_only_intact_rings() {
        let mut cache = RingCache::default();
        cache.begin(10).unwrap();
        let size = cache.tris.len();
        assert_eq!(size, RingCache::ARENA);
        // Ring r has r % 13 + 1 triangles; remember where each went and mark its triangles.
        let mut placed: Vec<Option<(usize, usize)>> = vec![None; 4000];
        for r in 0..4000u32 {
            let len = r as usize % 13 + 1;
            let start = cache.place(r, len);
            assert!(start + len <= size);
            for t in &mut cache.tris[start..start + len] {
                t.index = r;
            }
            cache.filled(r, Aabb::point(&[f64::from(r), 0.0, 0.0]));
            placed[r as usize] = Some((start, len));
            // Every ring the cache claims to hold is intact, with its own box.
            for q in r.saturating_sub(200)..=r {
                if let Some((start, bounds)) = cache.held(q) {
                    let (s, len) = placed[q as usize].unwrap();
                    assert_eq!(start, s);
                    assert!(cache.tris[s..s + len].iter().all(|t| t.index == q));
                    assert_eq!(bounds.lo[0], f64::from(q));
                }
            }
            // The last ring placed is always held.
            assert!(cache.held(r).is_some());
        }
        cache.begin(10).unwrap();
        assert!((0..4000).all(|r| cache.held(r).is_none()));
        // A ring longer than the arena grows it.
        cache.begin(5000).unwrap();
        assert_eq!(cache.tris.len(), 5000);
        let start = cache.place(1, 5000);
        assert_eq!(start, 0);
    }
}
