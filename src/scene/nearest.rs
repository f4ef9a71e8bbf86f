//! The scene's stencils: the broad phase over the objects' end boxes grown by the distance,
//! then each object pair's (and each self-contact object's) closest-feature query.

use super::Scene;
use super::select::{Reach, marks};
use super::share::{Shared, append};
use crate::error::{Error, Result};
use crate::query::{
    NearPair, NearPairs, QueryMode, QueryOptions, QueryStats, check_distance, nearest_features,
    result_buffer, self_nearest_features,
};
use crate::threads;

/// A stencil between two objects of a scene, or within one object with self-contact on: `pair`
/// as [`crate::nearest_features`] reports it with object `object_a`'s mesh first and
/// `object_b`'s second (as [`crate::self_nearest_features`] reports it when they are equal).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct SceneNearPair {
    /// The object with the lower id.
    pub object_a: u32,
    /// The object with the higher id (the same, for a stencil of an object with itself).
    pub object_b: u32,
    /// The primitives, their distance and closest points (world coordinates).
    pub pair: NearPair,
}

/// A caller-owned, reusable result buffer for [`Scene::nearest_features`], with the scratch
/// space of the threads that fill it. Use one per calling thread.
#[derive(Debug, Default)]
pub struct SceneNearPairs {
    items: Vec<SceneNearPair>,
    /// Where a query merges its stencils; swapped with `items` when it succeeds.
    spare: Vec<SceneNearPair>,
    shared: Shared<Work, SceneNearPair>,
}

result_buffer!(
    SceneNearPairs,
    SceneNearPair,
    "stencils",
    as_slice: "The stencils of the last successful query, sorted by `(object_a, object_b)`, then \
               as the pair's own query sorts them."
);

impl SceneNearPairs {
    /// Bytes of memory the buffer holds beyond the struct itself: the result, its spare, and
    /// the scratch space of the threads that filled it.
    pub fn memory_bytes(&self) -> usize {
        crate::csr::heap_bytes(&self.items)
            + crate::csr::heap_bytes(&self.spare)
            + self.shared.memory_bytes(|w| w.near.memory_bytes())
    }
}

/// One thread's scratch: the pair queries' result buffer and their counters.
#[derive(Debug, Default)]
struct Work {
    near: NearPairs,
    stats: QueryStats,
}

impl Scene {
    /// Every vertex-face and edge-edge stencil within `distance` between two objects that the
    /// filters allow and whose end boxes come within `distance`, and within each object with
    /// self-contact on, at the objects' current geometry (the end of their steps): for each such
    /// pair, exactly what [`crate::nearest_features`] reports for the two objects' meshes and
    /// poses, and [`crate::self_nearest_features`] for an object with itself (the same as for
    /// stand-alone meshes holding the world positions). The same for every thread count.
    ///
    /// The result replaces the contents of `out`, sorted by `(object_a, object_b)`, then as the
    /// pair's own query sorts its stencils. [`QueryOptions::mode`] applies to each pair
    /// ([`QueryMode::FirstHit`]: at most one stencil per object pair). With
    /// [`QueryOptions::max_pairs`], each pair's query keeps what its own query with that limit
    /// keeps, and the result the first of those in the scene's order, at most the limit
    /// ([`QueryStats::truncated`] says when anything was left out). The counters are sums over
    /// the pairs queried; [`QueryStats::pairs`] counts the stencils reported.
    ///
    /// Deformable objects whose positions changed are refit here, whole, and only those some
    /// pair needs.
    ///
    /// Errors: [`Error::InvalidDistance`] for a negative, NaN or infinite `distance`;
    /// [`Error::ZeroBudget`]; [`Error::OutOfMemory`] when a result cannot grow. On error `out`
    /// still holds the previous result.
    pub fn nearest_features(
        &mut self,
        distance: f64,
        options: &QueryOptions,
        out: &mut SceneNearPairs,
    ) -> Result<QueryStats> {
        check_distance(distance)?;
        if options.mode == QueryMode::Budget(0) {
            return Err(Error::ZeroBudget);
        }
        let mut candidates = std::mem::take(&mut self.candidates);
        self.select(Reach::Within(distance), &mut candidates);
        let mut needed = std::mem::take(&mut self.marks);
        marks(&candidates, self.objects.len(), &mut needed);
        let nodes_refit = self.refit_stale(|id| needed[id] != 0, options.threads, |_| false);
        let result = self.query_stencils(&candidates, distance, options, out);
        self.candidates = candidates;
        self.marks = needed;
        result.map(|stats| QueryStats {
            nodes_refit,
            ..stats
        })
    }

    /// Queries every candidate pair and merges the stencils into `out`.
    fn query_stencils(
        &self,
        candidates: &[(u32, u32)],
        distance: f64,
        options: &QueryOptions,
        out: &mut SceneNearPairs,
    ) -> Result<QueryStats> {
        let mut opts = *options;
        if candidates.len() > 1 {
            // The pairs share the threads; each pair's query runs on the thread that took it.
            opts.threads = 1;
        }
        let objects = &self.objects[..];
        let object = |id: u32| objects[id as usize].as_ref().expect("a candidate is live");
        out.shared.run(
            candidates,
            threads::resolve(options.threads),
            |w| w.stats = QueryStats::default(),
            &|w: &mut Work, (i, j), found: &mut Vec<SceneNearPair>| {
                let (a, b) = (object(i), object(j));
                let s = if i == j {
                    self_nearest_features(&a.mesh, distance, &opts, &mut w.near)?
                } else {
                    nearest_features(
                        &a.mesh,
                        a.pose(),
                        &b.mesh,
                        b.pose(),
                        distance,
                        &opts,
                        &mut w.near,
                    )?
                };
                w.stats.add(&s);
                append(
                    found,
                    w.near.iter().map(|&pair| SceneNearPair {
                        object_a: i,
                        object_b: j,
                        pair,
                    }),
                )?;
                Ok(s.truncated)
            },
        )?;
        let limit = options.max_pairs.unwrap_or(usize::MAX);
        let mut stats = QueryStats {
            truncated: out.shared.merge(limit, &mut out.spare)?,
            ..QueryStats::default()
        };
        for w in out.shared.works() {
            stats.add(&w.stats);
            stats.frontier_pairs += w.stats.frontier_pairs;
        }
        stats.pairs = out.spare.len() as u64;
        std::mem::swap(&mut out.items, &mut out.spare);
        Ok(stats)
    }
}
