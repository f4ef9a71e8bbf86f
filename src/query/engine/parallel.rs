//! One query on several threads. The calling thread opens the top of the two hierarchies into
//! items (node pairs, in the order the single-threaded traversal reaches them); the threads
//! take items in that order from a shared counter, each descending with its own stack, caches
//! and result; the results are then joined in item order. Joined so, they are the pairs the
//! single-threaded traversal reports, in its order, so a pair limit cuts them at the same pair
//! and the sorted answer is identical.

use super::side::{Placement, Typed, View, ViewOf};
use super::sink::{Sink, Stop};
use super::sort;
use super::terminal::{Scratch, Terminal};
use super::traverse::{Walk, split};
use super::workspace::{SideSpace, Split, Worker, Workspace};
use crate::query::pairs::{Pair, QueryStats};
use crate::threads;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Items per thread: enough that a thread finishing early finds more to take when contact is
/// unevenly spread, few enough that opening them on one thread stays a small part of the query.
const ITEMS_PER_THREAD: usize = 128;

/// What every thread of a query shares: both sides, typed, how the traversal walks, and what
/// becomes of its terminal pairs.
pub(crate) struct Job<A, B, N> {
    pub a: A,
    pub b: B,
    /// The depth at which nodes are no longer opened.
    pub max_depth: u32,
    pub terminal: N,
    /// Pairs to find before stopping.
    pub limit: usize,
}

impl<'m, A: Typed<'m>, B: Typed<'m>, N: Terminal<'m>> Job<A, B, N> {
    /// How the traversal walks, built where it runs: whether both sides are one mesh is known
    /// there at compile time for most queries (see [`Terminal::own`]).
    #[inline(always)]
    pub fn walk(&self) -> Walk<'m> {
        Walk {
            max_depth: self.max_depth,
            own: self.terminal.own(),
        }
    }

    /// Both sides seen through a thread's caches.
    pub fn views<'w>(
        &self,
        a: &'w mut SideSpace,
        b: &'w mut SideSpace,
    ) -> (ViewOf<'w, 'm, A>, ViewOf<'w, 'm, B>) {
        (
            View::new(self.a, &mut a.world, &mut a.ring_boxes),
            View::new(self.b, &mut b.world, &mut b.ring_boxes),
        )
    }
}

impl<'m, A: Typed<'m>, B: Typed<'m>, N: Terminal<'m>> Descend for Job<A, B, N> {
    fn limit(&self) -> usize {
        self.limit
    }

    fn begin(&self, a: &mut SideSpace, b: &mut SideSpace) -> Option<Stop> {
        let (ma, mb) = (self.a.place().mesh(), self.b.place().mesh());
        let longest = |m: &crate::mesh::Mesh| N::TRIANGLES.then_some(m.rings().longest);
        let (local_a, local_b) = (
            <A::Place as Placement<'m>>::LOCAL,
            <B::Place as Placement<'m>>::LOCAL,
        );
        a.begin(ma.vertex_count(), ma.ring_count(), longest(ma), !local_a)
            .and_then(|()| b.begin(mb.vertex_count(), mb.ring_count(), longest(mb), !local_b))
            .err()
            .map(|bytes| Stop::OutOfMemory { bytes })
    }

    fn split(&self, w: &mut Worker, target: usize, into: &mut Split, stats: &mut QueryStats) {
        let (mut va, mut vb) = self.views(&mut w.a, &mut w.b);
        split(&mut va, &mut vb, &self.walk(), target, into, stats);
    }

    fn traverse(&self, worker: &mut Worker, start: Option<(u32, u32)>, sink: &mut Sink) {
        let Worker {
            stack, a, b, stats, ..
        } = worker;
        let (mut va, mut vb) = (
            View::new(self.a, &mut a.world, &mut a.ring_boxes),
            View::new(self.b, &mut b.world, &mut b.ring_boxes),
        );
        let scratch = Scratch {
            stack,
            rings_a: &mut a.rings,
            rings_b: &mut b.rings,
        };
        self.terminal
            .descend(&mut va, &mut vb, start, &self.walk(), scratch, stats, sink);
    }
}

/// A typed query as the threads see it. Behind a trait object, the sharing out, joining and
/// sorting below are compiled once rather than for every combination of sides and pair test;
/// they call it a few hundred times a query, the traversal it runs millions of times.
pub(crate) trait Descend: Sync {
    /// Pairs to find before stopping.
    fn limit(&self) -> usize;
    /// Starts a thread's caches on this query; out of memory if they cannot grow as needed.
    fn begin(&self, a: &mut SideSpace, b: &mut SideSpace) -> Option<Stop>;
    /// Opens the top of the two hierarchies into about `target` items, in the order the
    /// single-threaded traversal reaches them.
    fn split(&self, w: &mut Worker, target: usize, into: &mut Split, stats: &mut QueryStats);
    /// Every terminal pair below item `start` (from the roots: `None`) to `sink`.
    fn traverse(&self, worker: &mut Worker, start: Option<(u32, u32)>, sink: &mut Sink);
}

/// Runs the job on `threads` threads (at least 2, and `ws.workers` has as many); its counters go
/// to `stats`, its pairs to `finish.out`: sorted when the query ran to the end (the threads
/// share the sort too), otherwise in the single-threaded traversal's order, cut at the limit.
/// Returns why it stopped early, if it did, and whether `out` is sorted.
pub(crate) fn share_out(
    job: &dyn Descend,
    ws: &mut Workspace,
    threads: usize,
    finish: Finish,
    stats: &mut QueryStats,
) -> (Option<Stop>, bool) {
    let Workspace {
        workers,
        split,
        item_counts,
        item_pairs,
        sort_counts,
        ..
    } = ws;
    let Finish {
        out,
        scratch,
        a_count,
        b_count,
    } = finish;
    let workers = &mut workers[..threads];
    for w in workers.iter_mut() {
        w.stats = QueryStats::default();
    }
    {
        let w = &mut workers[0];
        if let Some(stop) = job.begin(&mut w.a, &mut w.b) {
            return (Some(stop), false);
        }
        job.split(w, threads * ITEMS_PER_THREAD, split, stats);
    }
    let items = &split.items;
    let count = items.len();
    if count < threads * ITEMS_PER_THREAD {
        // The overlap ran out before the split did: too little work to share. The calling
        // thread descends the items in order, as the single-threaded traversal would.
        let w = &mut workers[0];
        let mut sink = Sink::new(out, job.limit());
        for &item in items.iter() {
            job.traverse(w, Some(item), &mut sink);
            if sink.stop.is_some() {
                break;
            }
        }
        stats.add(&w.stats);
        return (sink.stop, false);
    }
    if item_counts.len() < count {
        item_counts.resize_with(count, || AtomicUsize::new(usize::MAX));
    }
    let limit = job.limit();
    let settled = threads::Settled::new(&item_counts[..count], limit);
    let items = &items[..];
    let next = AtomicUsize::new(0);
    let halt = AtomicBool::new(false);
    // A query that cannot be cut short is sorted by the threads too: each distributes its
    // pairs into buckets, then the buckets are shared out.
    let buckets = sort::buckets_for(a_count);
    let bucketed = limit == usize::MAX;
    threads::on_each(
        threads::Step::Traversal,
        workers,
        &|w: &mut Worker, index| {
            w.out.clear();
            w.done.clear();
            w.stop = None;
            if index != 0 {
                w.stop = job.begin(&mut w.a, &mut w.b);
                if w.stop.is_some() {
                    halt.store(true, Ordering::Relaxed);
                    return;
                }
            }
            while !halt.load(Ordering::Relaxed) {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= count {
                    break;
                }
                let mut out = std::mem::take(&mut w.out);
                let start = out.len();
                let mut sink = Sink {
                    out: &mut out,
                    limit: start.saturating_add(limit),
                    stop: None,
                };
                job.traverse(w, Some(items[i]), &mut sink);
                let stop = sink.stop;
                w.out = out;
                if let Some(Stop::OutOfMemory { .. }) = stop {
                    w.stop = stop;
                    halt.store(true, Ordering::Relaxed);
                    break;
                }
                let end = w.out.len();
                w.done.push((i, start, end));
                if settled.finish(i, end - start) {
                    halt.store(true, Ordering::Relaxed);
                }
            }
            if bucketed
                && w.stop.is_none()
                && !sort::bucket_part(&w.out, &mut w.bucketed, &mut w.bucket_starts, buckets)
            {
                w.stop = Some(Stop::OutOfMemory {
                    bytes: w.out.len() * std::mem::size_of::<Pair>(),
                });
            }
        },
    );
    for w in workers.iter() {
        if let Some(stop) = w.stop {
            return (Some(stop), false);
        }
        stats.add(&w.stats);
    }
    if bucketed {
        let part = |w: usize| (&workers[w].bucketed[..], &workers[w].bucket_starts[..]);
        let parts = workers.len();
        if sort::sort_parts(
            parts,
            &part,
            buckets,
            b_count,
            out,
            scratch,
            sort_counts,
            threads,
        ) {
            return (None, true);
        }
    }
    // Join in item order, up to the limit.
    out.clear();
    item_pairs.clear();
    item_pairs.resize(count, (usize::MAX, 0, 0));
    let mut total = 0usize;
    for (wi, w) in workers.iter().enumerate() {
        for &(i, start, end) in &w.done {
            item_pairs[i] = (wi, start, end);
            total += end - start;
        }
    }
    let wanted = total.min(limit);
    if out.try_reserve(wanted).is_err() {
        return (
            Some(Stop::OutOfMemory {
                bytes: wanted * std::mem::size_of::<Pair>(),
            }),
            false,
        );
    }
    for &(wi, start, end) in item_pairs.iter() {
        // Items after the cut may not have run.
        if out.len() >= limit || wi == usize::MAX {
            break;
        }
        let found = &workers[wi].out[start..end];
        let take = found.len().min(limit - out.len());
        out.extend_from_slice(&found[..take]);
    }
    ((out.len() >= limit).then_some(Stop::Limit), false)
}

/// How a threaded query's pairs come out.
pub(crate) struct Finish<'o> {
    pub out: &'o mut Vec<Pair>,
    /// Scratch for sorting them (its contents are lost only once the sort is sure to succeed).
    pub scratch: &'o mut Vec<Pair>,
    /// Bounds on the pairs' first and second indices.
    pub a_count: u64,
    pub b_count: u64,
}
