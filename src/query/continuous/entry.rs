//! The continuous queries: the traversal over the meshes' motion finds the leaf pairs whose
//! volumes overlap, and the narrow phase tests their primitive pairs, on one thread or shared
//! out in chunks whose results are joined in order (so the answer does not depend on the
//! thread count).

use super::impacts::{CcdOptions, CcdStats, Impact, Impacts};
use super::narrow::{Job, Moving, Worker};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::query::engine::{NodeVolumes, OneMesh, PairTest, Prepared, query, query_one};
use crate::query::options::{QueryMode, QueryOptions};
use crate::query::pairs::Pair;
use crate::threads;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

/// Every vertex-face and edge-edge pair of meshes `a` and `b` that meets while each moves
/// through its last motion ([`Mesh::refit_motion`]; a mesh refit without one stays still), with
/// the earliest time it does: every vertex of `a` against every triangle of `b`
/// ([`crate::ImpactKind::VertexFace`]), every triangle of `a` against every vertex of `b`
/// ([`crate::ImpactKind::FaceVertex`]), every edge of `a` against every edge of `b` (an edge is
/// a pair of distinct vertices joined by a triangle side, counted once however many triangles
/// share it). Vertices that belong to no triangle are not tested.
///
/// Exact with the default [`crate::CcdMode::Exact`]: the answer is that of
/// [`crate::exact::vertex_face_impact`] and [`crate::exact::edge_edge_impact`] over every
/// primitive pair. The result replaces the contents of `out`, sorted by
/// `(kind, a0, a1, b0, b1)`; the counters are returned.
///
/// Errors: [`Error::OutOfMemory`] when the result cannot grow (set
/// [`CcdOptions::max_impacts`] to bound it). On error `out` still holds the previous result.
pub fn continuous_collide(
    a: &Mesh,
    b: &Mesh,
    options: &CcdOptions,
    out: &mut Impacts,
) -> Result<CcdStats> {
    run(a, Some(b), options, out)
}

/// Every pair of one mesh's primitives that meets during its last motion, with the earliest
/// time: every vertex against every triangle that does not contain it (reported as
/// [`crate::ImpactKind::VertexFace`], the vertex in `a0`), every pair of edges that share no
/// vertex (`(a0, a1) < (b0, b1)`). Otherwise as [`continuous_collide`].
pub fn self_continuous_collide(
    mesh: &Mesh,
    options: &CcdOptions,
    out: &mut Impacts,
) -> Result<CcdStats> {
    run(mesh, None, options, out)
}

/// The traversal over the motion: leaf pairs whose volumes overlap (the volumes of a moving
/// mesh hold its whole motion). Only the coarse mode is run, so the triangle test is never
/// asked.
#[derive(Clone, Copy)]
struct Sweeps {
    one_mesh: bool,
}

impl<'m> PairTest<'m> for Sweeps {
    type SideA<K: NodeVolumes<'m>> = K;
    const CHECKS_DOMAIN: bool = false;

    fn side_a<K: NodeVolumes<'m>>(&self, kind: K) -> K {
        kind
    }

    fn own(&self) -> Option<OneMesh<'m>> {
        // No patch skips: a patch free of self-intersection at the end may still pass through
        // itself during the step.
        self.one_mesh.then_some(OneMesh { patches: None })
    }

    fn test(&self, _mesh: &Mesh, _ta: &Prepared, _tb: &Prepared) -> bool {
        unreachable!("the traversal over the motion reports leaf pairs only")
    }
}

/// Below this many leaf pairs, the narrow phase runs on the calling thread.
const PARALLEL_MIN_LEAF_PAIRS: usize = 256;
/// Chunks of leaf pairs per thread: enough to balance uneven contact.
const CHUNKS_PER_THREAD: usize = 64;

fn run(a: &Mesh, b: Option<&Mesh>, options: &CcdOptions, out: &mut Impacts) -> Result<CcdStats> {
    let one_mesh = b.is_none();
    let b = b.unwrap_or(a);
    let broad_options = QueryOptions::with_mode(QueryMode::Leaves).with_threads(options.threads);
    let test = Sweeps { one_mesh };
    let broad = if one_mesh {
        query_one(a, test, &broad_options, &mut out.leaves)?
    } else {
        query(
            (a, None, None),
            (b, None, None),
            test,
            &broad_options,
            &mut out.leaves,
        )?
    };
    let mut stats = CcdStats {
        bv_tests: broad.bv_tests,
        ..CcdStats::default()
    };
    let limit = if options.earliest_only {
        options.max_impacts.unwrap_or(usize::MAX).min(1)
    } else {
        options.max_impacts.unwrap_or(usize::MAX)
    };
    let Impacts {
        items,
        spare,
        leaves,
        workers,
    } = out;
    let leaves = leaves.as_slice();
    spare.clear();
    if limit == 0 {
        stats.truncated = true;
        std::mem::swap(items, spare);
        return Ok(stats);
    }
    let best = AtomicU64::new(1.0f64.to_bits());
    let job = Job {
        a: Moving::new(a),
        b: Moving::new(b),
        one_mesh,
        mode: options.mode,
        earliest_only: options.earliest_only,
        best: &best,
    };
    let threads = if leaves.len() < PARALLEL_MIN_LEAF_PAIRS {
        1
    } else {
        threads::resolve(options.threads)
    };
    if workers.len() < threads {
        workers.resize_with(threads, Worker::default);
    }
    let workers = &mut workers[..threads];
    let chunks = if threads == 1 {
        1
    } else {
        leaves.len().min(threads * CHUNKS_PER_THREAD)
    };
    narrow(&job, leaves, chunks, limit, workers);
    for w in workers.iter() {
        if let Some(bytes) = w.out_of_memory {
            return Err(Error::OutOfMemory { bytes });
        }
        stats.primitive_tests += w.primitive_tests;
    }
    if options.earliest_only {
        let first = workers
            .iter()
            .filter_map(|w| w.best)
            .min_by(|x, y| (x.toi, x.key()).partial_cmp(&(y.toi, y.key())).unwrap());
        spare.extend(first);
    } else {
        // Join the chunks in order, up to the limit.
        let mut order: Vec<(usize, usize, usize, usize)> = Vec::new();
        let total: usize = workers
            .iter()
            .map(|w| w.done.iter().map(|d| d.2 - d.1).sum::<usize>())
            .sum();
        let wanted = total.min(limit);
        if spare.try_reserve(wanted).is_err()
            || order
                .try_reserve(workers.iter().map(|w| w.done.len()).sum())
                .is_err()
        {
            return Err(Error::OutOfMemory {
                bytes: wanted * std::mem::size_of::<Impact>(),
            });
        }
        for (wi, w) in workers.iter().enumerate() {
            order.extend(w.done.iter().map(|&(c, s, e)| (c, wi, s, e)));
        }
        order.sort_unstable();
        for &(_, wi, s, e) in &order {
            if spare.len() >= limit {
                break;
            }
            let found = &workers[wi].out[s..e];
            let take = found.len().min(limit - spare.len());
            spare.extend_from_slice(&found[..take]);
        }
        // As the discrete queries: the limit reached stops the query.
        stats.truncated = limit != usize::MAX && spare.len() >= limit;
        spare.sort_unstable_by_key(Impact::key);
    }
    stats.impacts = spare.len() as u64;
    stats.earliest_toi = spare.iter().map(|i| i.toi).fold(f64::INFINITY, f64::min);
    std::mem::swap(items, spare);
    Ok(stats)
}

/// The narrow phase over `leaves`, cut into `chunks` chunks taken in order by the workers.
fn narrow(job: &Job, leaves: &[Pair], chunks: usize, limit: usize, workers: &mut [Worker]) {
    let chunk = |c: usize| &leaves[c * leaves.len() / chunks..(c + 1) * leaves.len() / chunks];
    // The whole of one chunk, its impacts appended to `w.out` up to `limit` of its own; returns
    // whether it stopped at the limit (or out of memory).
    let run_chunk = |w: &mut Worker, c: usize| -> bool {
        let start = w.out.len();
        let mut stopped = false;
        for p in chunk(c) {
            if job.leaf_pair(w, p.a, p.b, start.saturating_add(limit)) {
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
    threads::on_each(workers, &|w: &mut Worker, _| {
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
