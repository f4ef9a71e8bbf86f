//! The narrow phase over a traversal's node pairs: on the calling thread, or cut into chunks
//! taken in order by several, the results joined in the order of the chunks.

use super::ImpactKind;
use super::boxes::OwnedBoxes;
use super::node_pair::{Narrow, Tables};
use super::vocabulary::{Key, PrimitiveTest, Side, Worker};
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
/// Below this many results, they are sorted as they are, not first put in buckets.
const BUCKETS_MIN_RESULTS: usize = 1 << 10;
/// Results are put in buckets only when the buckets number at most this many per result (so
/// that counting them costs less than sorting).
const BUCKETS_PER_RESULT: usize = 4;
/// Shares of the buckets per thread, for their sorts.
const SHARES_PER_THREAD: usize = 8;

/// `key` as a value that orders keys as `key` does: vertex-face and face-vertex keys
/// `(kind, a0, b0)` packed into an integer (their `a1 = b1 = 0`), then edge-edge keys
/// `(a0, a1, b0, b1)` packed into another, after every other kind.
#[inline]
fn packed(key: Key) -> (bool, u128) {
    let (kind, a0, a1, b0, b1) = key;
    if kind == ImpactKind::EdgeEdge {
        let k = (a0 as u128) << 96 | (a1 as u128) << 64 | (b0 as u128) << 32 | b1 as u128;
        (true, k)
    } else {
        debug_assert!(a1 == 0 && b1 == 0, "a vertex-face key has two indices");
        (
            false,
            (kind as u128) << 64 | (a0 as u128) << 32 | b0 as u128,
        )
    }
}

/// The order of keys that share `(kind, a0)`, as in one bucket of [`Buckets`]: `(a1, b0, b1)`
/// packed into an integer (no branch on the kind, unlike [`packed`]).
#[inline]
fn in_bucket((_, _, a1, b0, b1): Key) -> u128 {
    (a1 as u128) << 64 | (b0 as u128) << 32 | b1 as u128
}

/// What the workers found, joined.
pub(crate) struct Joined {
    /// Primitive pairs tested.
    pub primitive_tests: u64,
    /// Did the limit stop the narrow phase?
    pub truncated: bool,
}

/// The scratch space of [`run`], kept between queries: each thread's, the boxes of the
/// primitives of each side, and the chunks' results in order.
#[derive(Debug)]
pub(crate) struct Workspace<F> {
    pub workers: Vec<Worker<F>>,
    boxes: [OwnedBoxes; 2],
    /// Per chunk finished: (chunk, worker, start, end) of its results in the worker's.
    chunks: Vec<(usize, usize, usize, usize)>,
    /// Per chunk, on several threads: its results once finished.
    chunk_counts: Vec<AtomicUsize>,
}

impl<F> Default for Workspace<F> {
    fn default() -> Workspace<F> {
        Workspace {
            workers: Vec::new(),
            boxes: Default::default(),
            chunks: Vec::new(),
            chunk_counts: Vec::new(),
        }
    }
}

impl<F> Workspace<F> {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        crate::csr::heap_bytes(&self.workers)
            + self.workers.iter().map(Worker::heap_bytes).sum::<usize>()
            + self.boxes.iter().map(OwnedBoxes::heap_bytes).sum::<usize>()
    }
}

/// Runs the narrow phase of `narrow` over the node pairs `pairs` on up to `threads` threads
/// ([`crate::QueryOptions::threads`]), with `space`'s workers grown to the threads used. Unless the
/// test keeps only a best result ([`Worker::best`]), the first `limit` results in the order of
/// `pairs` (so the same whatever the thread count) are appended to `out`, which must be empty,
/// sorted by `key` (unique per result).
///
/// Errors: [`Error::OutOfMemory`] when a result cannot grow.
pub(crate) fn test_leaf_pairs<T: PrimitiveTest>(
    narrow: &Narrow<T>,
    pairs: &[Pair],
    threads: u32,
    limit: usize,
    space: &mut Workspace<T::Found>,
    out: &mut Vec<T::Found>,
    key: impl Fn(&T::Found) -> Key + Sync,
) -> Result<Joined> {
    let Workspace {
        workers,
        boxes,
        chunks: finished,
        chunk_counts,
    } = space;
    let tables: Tables = {
        // Read before the boxes are made: a test that tightens them meanwhile makes them
        // tighter than this says, and its node pairs build their own.
        let epoch = narrow.test.box_epoch();
        let [box_a, box_b] = boxes;
        let (a, b) = (&narrow.a, &narrow.b);
        let filled = if narrow.one_mesh {
            let nodes = pairs.iter().flat_map(|p| [p.a, p.b]);
            box_a.fill(a, Side::A, &narrow.test, nodes)
        } else {
            box_a
                .fill(a, Side::A, &narrow.test, pairs.iter().map(|p| p.a))
                .and_then(|()| box_b.fill(b, Side::B, &narrow.test, pairs.iter().map(|p| p.b)))
        };
        filled.map_err(|bytes| Error::OutOfMemory { bytes })?;
        let b = if narrow.one_mesh { &*box_a } else { &*box_b };
        Tables { a: box_a, b, epoch }
    };
    let sort_threads = threads::resolve(threads);
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
    if threads > 1 && chunk_counts.len() < chunks {
        chunk_counts.resize_with(chunks, || AtomicUsize::new(usize::MAX));
    }
    in_chunks(narrow, tables, pairs, chunks, limit, workers, chunk_counts);
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
    // then sorted by `key`.
    let total: usize = workers
        .iter()
        .map(|w| w.done.iter().map(|d| d.2 - d.1).sum::<usize>())
        .sum();
    let wanted = total.min(limit);
    finished.clear();
    if out.try_reserve(wanted).is_err()
        || finished
            .try_reserve(workers.iter().map(|w| w.done.len()).sum())
            .is_err()
    {
        return Err(Error::OutOfMemory {
            bytes: wanted * std::mem::size_of::<T::Found>(),
        });
    }
    for (wi, w) in workers.iter().enumerate() {
        finished.extend(w.done.iter().map(|&(c, s, e)| (c, wi, s, e)));
    }
    finished.sort_unstable();
    let mut counts = std::mem::take(&mut workers[0].counts);
    // The results taken, in order: the chunks' up to the limit.
    let mut left = wanted;
    finished.retain_mut(|(_, _, s, e)| {
        let take = (*e - *s).min(left);
        left -= take;
        *e = *s + take;
        take > 0
    });
    let taken = finished.iter().map(|&(_, wi, s, e)| &workers[wi].out[s..e]);
    let buckets = Buckets::of(narrow);
    counts.clear();
    let bucketed = wanted >= BUCKETS_MIN_RESULTS
        && buckets.count() <= wanted.saturating_mul(BUCKETS_PER_RESULT)
        && counts.try_reserve(buckets.count() + 1).is_ok();
    if bucketed {
        buckets.sort(taken, &key, &mut counts, sort_threads, out);
    } else {
        for part in taken {
            out.extend_from_slice(part);
        }
        // Few results for the meshes' size: sorted as they are, on the whole pool when the
        // query may use it.
        let pool = rayon::current_num_threads();
        if pool > 1 && sort_threads == pool && out.len() >= PARALLEL_SORT_MIN {
            use rayon::slice::ParallelSliceMut;
            threads::shared_out(threads::Step::Sort);
            out.par_sort_unstable_by_key(|f| packed(key(f)));
        } else {
            out.sort_unstable_by_key(|f| packed(key(f)));
        }
    }
    workers[0].counts = counts;
    // As the discrete queries: the limit reached stops the query.
    joined.truncated = limit != usize::MAX && out.len() >= limit;
    Ok(joined)
}

/// The narrow phase over `pairs`, cut into `chunks` chunks taken in order by the workers
/// (`counts`, on several workers: room for each chunk's count, at least `chunks`).
fn in_chunks<T: PrimitiveTest>(
    narrow: &Narrow<T>,
    tables: Tables,
    pairs: &[Pair],
    chunks: usize,
    limit: usize,
    workers: &mut [Worker<T::Found>],
    counts: &[AtomicUsize],
) {
    let chunk = |c: usize| &pairs[c * pairs.len() / chunks..(c + 1) * pairs.len() / chunks];
    // The whole of one chunk, its results appended to `w.out` up to `limit` of its own; returns
    // whether it stopped at the limit (or out of memory).
    let run_chunk = |w: &mut Worker<T::Found>, c: usize| -> bool {
        let start = w.out.len();
        let mut stopped = false;
        for p in chunk(c) {
            if narrow.node_pair(tables, w, p.a, p.b, start.saturating_add(limit)) {
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
    let settled = threads::Settled::new(&counts[..chunks], limit);
    threads::on_each(
        threads::Step::Pairs,
        workers,
        &|w: &mut Worker<T::Found>, _| {
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
        },
    );
}

/// Results in buckets by the first two parts of their key, `(kind, a0)`: a bucket for each
/// vertex of the first mesh (vertex-face), each triangle (face-vertex), then each vertex again
/// (edge-edge), so that the buckets follow each other in key order. Putting results in buckets
/// is two passes over them; each bucket, a few hundred results at most where many are found, is
/// then sorted in cache, and the buckets on several threads at once.
struct Buckets {
    vertices: usize,
    triangles: usize,
}

impl Buckets {
    fn of<T: PrimitiveTest>(narrow: &Narrow<T>) -> Buckets {
        let mesh = narrow.a.mesh;
        Buckets {
            vertices: mesh.vertex_count(),
            triangles: mesh.triangle_count(),
        }
    }

    fn count(&self) -> usize {
        2 * self.vertices + self.triangles
    }

    #[inline]
    fn of_key(&self, (kind, a0, ..): Key) -> usize {
        a0 as usize
            + match kind {
                ImpactKind::VertexFace => 0,
                ImpactKind::FaceVertex => self.vertices,
                ImpactKind::EdgeEdge => self.vertices + self.triangles,
            }
    }

    /// The results `taken` appended to `out` (empty, with room for them all) in the order of
    /// `key`, with `counts` (room for [`Buckets::count`] + 1) as scratch space, on up to
    /// `threads` threads.
    fn sort<'f, F: Copy + Send + 'f>(
        &self,
        taken: impl Iterator<Item = &'f [F]> + Clone,
        key: &(impl Fn(&F) -> Key + Sync),
        counts: &mut Vec<usize>,
        threads: usize,
        out: &mut Vec<F>,
    ) {
        let n: usize = taken.clone().map(|p| p.len()).sum();
        debug_assert!(out.is_empty() && out.capacity() >= n);
        counts.clear();
        counts.resize(self.count() + 1, 0);
        for f in taken.clone().flatten() {
            counts[self.of_key(key(f)) + 1] += 1;
        }
        // `counts[b]`: where bucket `b` starts; moved along to where it ends as it is filled.
        for b in 1..counts.len() {
            counts[b] += counts[b - 1];
        }
        let room = &mut out.spare_capacity_mut()[..n];
        for f in taken.flatten() {
            let b = self.of_key(key(f));
            room[counts[b]].write(*f);
            counts[b] += 1;
        }
        // SAFETY: the buckets' ranges, counted above, partition the first `n` slots, and each
        // slot was written once as its bucket was filled.
        unsafe { out.set_len(n) };
        // Bucket `b` now runs from `counts[b - 1]` (0 for the first) to `counts[b]`.
        let ends = &counts[..self.count()];
        let sort = |part: &mut [F], start: usize, ends: &[usize]| {
            let mut from = start;
            for &end in ends {
                if end - from > 1 {
                    part[from - start..end - start].sort_unstable_by_key(|f| in_bucket(key(f)));
                }
                from = end;
            }
        };
        if threads <= 1 || n < PARALLEL_SORT_MIN {
            sort(out, 0, ends);
            return;
        }
        // Shares of whole buckets, each about `size` results, taken in turn by the threads.
        let size = n.div_ceil(threads * SHARES_PER_THREAD);
        let mut shares: Vec<(&mut [F], usize, &[usize])> = Vec::new();
        let (mut rest, mut start, mut first) = (&mut out[..], 0, 0);
        for (b, &end) in ends.iter().enumerate() {
            if end - start >= size || b + 1 == ends.len() {
                let (part, tail) = std::mem::take(&mut rest).split_at_mut(end - start);
                shares.push((part, start, &ends[first..=b]));
                (rest, start, first) = (tail, end, b + 1);
            }
        }
        threads::in_turns(threads::Step::Sort, threads, shares, &|(
            part,
            start,
            ends,
        )| {
            sort(part, start, ends)
        });
    }
}
