//! The scene's stencils: the broad phase over the objects' end boxes grown by the distance,
//! then each object pair's (and each self-contact object's) closest-feature query.

use super::Scene;
use super::select::{Reach, marks};
use super::share::{append, scene_results};
use crate::error::{Error, Result};
use crate::query::{
    NearPair, NearPairs, QueryMode, QueryOptions, QueryStats, check_distance, nearest_features,
    self_nearest_features,
};

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

scene_results!(
    /// A caller-owned, reusable result buffer for [`Scene::nearest_features`], with the
    /// scratch space of the threads that fill it. Use one per calling thread.
    SceneNearPairs,
    SceneNearPair,
    NearPairs,
    QueryStats,
    "stencils",
    as_slice: "The stencils of the last successful query, sorted by `(object_a, object_b)`, then \
               as the pair's own query sorts them."
);

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
        out.shared
            .run(candidates, options.threads, &|w, (i, j), threads, found| {
                let (a, b) = (self.candidate(i), self.candidate(j));
                let opts = options.with_threads(threads);
                let s = if i == j {
                    self_nearest_features(&a.mesh, distance, &opts, &mut w.buffer)?
                } else {
                    nearest_features(
                        &a.mesh,
                        a.pose(),
                        &b.mesh,
                        b.pose(),
                        distance,
                        &opts,
                        &mut w.buffer,
                    )?
                };
                w.stats.add(&s);
                append(
                    found,
                    w.buffer.iter().map(|&pair| SceneNearPair {
                        object_a: i,
                        object_b: j,
                        pair,
                    }),
                )?;
                Ok(s.truncated)
            })?;
        let limit = options.max_pairs.unwrap_or(usize::MAX);
        let mut stats = QueryStats {
            truncated: out.shared.merge(limit)?,
            ..QueryStats::default()
        };
        for w in out.shared.works() {
            stats.add(&w.stats);
            stats.frontier_pairs += w.stats.frontier_pairs;
        }
        out.shared.publish(&mut out.items);
        stats.pairs = out.items.len() as u64;
        Ok(stats)
    }
}
