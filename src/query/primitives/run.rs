//! The narrow phase over a traversal's node pairs: on the calling thread, or cut into chunks
//! taken in order by several, the results joined in the order of the chunks.

use super::ImpactKind;
use super::narrow::{Key, Narrow, PrimitiveTest, Worker};
use crate::error::{Error, Result};
use crate::query::pairs::Pair;
use crate::threads;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Below this many node pairs, the narrow phase runs on the calling thread.
const PARALLEL_MIN_PAIRS: usize = 256;
/// Chunks of node pairs per thread: enough to balance uneven contact.
const CHUNKS_PER_THREAD: usize = 64;
/// Below this many results, they are sorted on the calling thread.
const PARALLEL_SORT_MIN: usize = 1 << 14;

/// A result's place in the order: its packed key ([`packed`]), its worker (the top bit set for
/// the edge-edge run) and its index there.
type Entry = (u128, u32, usize);

/// The bit of [`Entry`]'s worker that marks the edge-edge run.
const EDGE_RUN: u32 = 1 << 31;

/// `key` as an integer that orders keys of its run as `key` does, and whether it is of the
/// edge-edge run (which follows the other). Vertex-face and face-vertex keys have `a1 = b1 = 0`.
#[inline]
fn packed(key: Key) -> (u128, bool) {
    let (kind, a0, a1, b0, b1) = key;
    if kind == ImpactKind::EdgeEdge {
        let k = (a0 as u128) << 96 | (a1 as u128) << 64 | (b0 as u128) << 32 | b1 as u128;
        (k, true)
    } else {
        debug_assert!(a1 == 0 && b1 == 0, "a vertex-face key has two indices");
        (
            (kind as u128) << 64 | (a0 as u128) << 32 | b0 as u128,
            false,
        )
    }
}

/// What the workers found, joined.
pub(crate) struct Joined {
    /// Primitive pairs tested.
    pub primitive_tests: u64,
    /// Did the limit stop the narrow phase?
    pub truncated: bool,
}

/// Runs the narrow phase of `narrow` over the node pairs `pairs` on up to `threads` threads
/// ([`crate::QueryOptions::threads`]), with `workers` grown to the threads used. Unless the
/// test keeps only a best result ([`Worker::best`]), the first `limit` results in the order of
/// `pairs` (so the same whatever the thread count) are appended to `out`, which must be empty,
/// sorted by `key` (unique per result).
///
/// Errors: [`Error::OutOfMemory`] when a result cannot grow.
pub(crate) fn run<T: PrimitiveTest>(
    narrow: &Narrow<T>,
    pairs: &[Pair],
    threads: u32,
    limit: usize,
    workers: &mut Vec<Worker<T::Found>>,
    out: &mut Vec<T::Found>,
    key: impl Fn(&T::Found) -> Key,
) -> Result<Joined> {
    // The sort of a large result is shared out when the query may use every thread of the pool.
    let pool = rayon::current_num_threads();
    let parallel_sort = pool > 1 && threads::resolve(threads) == pool;
    let threads = if pairs.len() < PARALLEL_MIN_PAIRS {
        1
    } else {
        threads::resolve(threads)
    };
    if workers.len() < threads {
        workers.resize_with(threads, Worker::default);
    }
    let workers = &mut workers[..threads];
    let chunks = if threads == 1 {
        1
    } else {
        pairs.len().min(threads * CHUNKS_PER_THREAD)
    };
    in_chunks(narrow, pairs, chunks, limit, workers);
    let mut joined = Joined {
        primitive_tests: 0,
        truncated: false,
    };
    for w in workers.iter() {
        if let Some(bytes) = w.out_of_memory {
            return Err(Error::OutOfMemory { bytes });
        }
        joined.primitive_tests += w.primitive_tests;
    }
    // The first `limit` results in the chunks' order (so the same whatever the thread count),
    // then sorted by `key`: the order is sorted as small (key, worker, index) entries and the
    // results gathered once into `out`, rather than the (large) results themselves moved about.
    // The keys are packed into integers, in two runs that follow each other in key order:
    // vertex-face and face-vertex keys (kind, a0, b0), then edge-edge keys (a0, a1, b0, b1).
    let total: usize = workers
        .iter()
        .map(|w| w.done.iter().map(|d| d.2 - d.1).sum::<usize>())
        .sum();
    let wanted = total.min(limit);
    let mut order: Vec<Entry> = Vec::new();
    let mut chunks: Vec<(usize, usize, usize, usize)> = Vec::new();
    if out.try_reserve(wanted).is_err()
        || order.try_reserve(wanted).is_err()
        || chunks
            .try_reserve(workers.iter().map(|w| w.done.len()).sum())
            .is_err()
    {
        return Err(Error::OutOfMemory {
            bytes: wanted * (std::mem::size_of::<T::Found>() + std::mem::size_of::<Entry>()),
        });
    }
    for (wi, w) in workers.iter().enumerate() {
        chunks.extend(w.done.iter().map(|&(c, s, e)| (c, wi, s, e)));
    }
    chunks.sort_unstable();
    debug_assert!(workers.len() < EDGE_RUN as usize);
    for &(_, wi, s, e) in &chunks {
        if order.len() >= limit {
            break;
        }
        let take = (e - s).min(limit - order.len());
        let found = &workers[wi].out[s..s + take];
        order.extend(found.iter().enumerate().map(|(i, f)| {
            let (k, edge) = packed(key(f));
            (k, wi as u32 | if edge { EDGE_RUN } else { 0 }, s + i)
        }));
    }
    // The edge-edge entries moved to the end, in place: they sort after every other kind.
    let mut split = order.len();
    let mut i = 0;
    while i < split {
        if order[i].1 & EDGE_RUN != 0 {
            split -= 1;
            order.swap(i, split);
        } else {
            i += 1;
        }
    }
    let (vertex_face, edge_edge) = order.split_at_mut(split);
    for part in [vertex_face, edge_edge] {
        if parallel_sort && part.len() >= PARALLEL_SORT_MIN {
            use rayon::slice::ParallelSliceMut;
            part.par_sort_unstable_by_key(|e| e.0);
        } else {
            part.sort_unstable_by_key(|e| e.0);
        }
    }
    out.extend(
        order
            .iter()
            .map(|&(_, wi, i)| workers[(wi & !EDGE_RUN) as usize].out[i]),
    );
    // As the discrete queries: the limit reached stops the query.
    joined.truncated = limit != usize::MAX && out.len() >= limit;
    Ok(joined)
}

/// The narrow phase over `pairs`, cut into `chunks` chunks taken in order by the workers.
fn in_chunks<T: PrimitiveTest>(
    narrow: &Narrow<T>,
    pairs: &[Pair],
    chunks: usize,
    limit: usize,
    workers: &mut [Worker<T::Found>],
) {
    let chunk = |c: usize| &pairs[c * pairs.len() / chunks..(c + 1) * pairs.len() / chunks];
    // The whole of one chunk, its results appended to `w.out` up to `limit` of its own; returns
    // whether it stopped at the limit (or out of memory).
    let run_chunk = |w: &mut Worker<T::Found>, c: usize| -> bool {
        let start = w.out.len();
        let mut stopped = false;
        for p in chunk(c) {
            if narrow.node_pair(w, p.a, p.b, start.saturating_add(limit)) {
                stopped = true;
                break;
            }
        }
        w.done.push((c, start, w.out.len()));
        stopped
    };
    if workers.len() == 1 {
        let w = &mut workers[0];
        w.begin();
        for c in 0..chunks {
            if run_chunk(w, c) {
                break;
            }
        }
        return;
    }
    let next = AtomicUsize::new(0);
    let halt = AtomicBool::new(false);
    let counts: Vec<AtomicUsize> = (0..chunks).map(|_| AtomicUsize::new(usize::MAX)).collect();
    let settled = threads::Settled::new(&counts, limit);
    threads::on_each(workers, &|w: &mut Worker<T::Found>, _| {
        w.begin();
        while !halt.load(Ordering::Relaxed) {
            let c = next.fetch_add(1, Ordering::Relaxed);
            if c >= chunks {
                break;
            }
            let before = w.out.len();
            run_chunk(w, c);
            if w.out_of_memory.is_some() {
                halt.store(true, Ordering::Relaxed);
                break;
            }
            if settled.finish(c, w.out.len() - before) {
                halt.store(true, Ordering::Relaxed);
            }
        }
    });
}
