//! The scene's continuous collision: the broad phase over the objects' boxes for the whole
//! step, then each object pair's (and each self-contact object's) continuous query on world
//! positions, the earliest impact found so far shared by all of them.

use super::select::{Reach, marks};
use super::share::{append, scene_results};
use super::{Body, Scene, WorldCopy};
use crate::error::{Error, Result};
use crate::query::{CcdOptions, CcdStats, Impact, Impacts, impacts_sharing};
use std::sync::atomic::AtomicU64;

/// An impact between two objects of a scene, or within one object with self-contact on:
/// `impact` as [`crate::continuous_collide`] reports it with object `object_a`'s mesh first and
/// `object_b`'s second (as [`crate::self_continuous_collide`] reports it when they are equal).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct SceneImpact {
    /// The object with the lower id.
    pub object_a: u32,
    /// The object with the higher id (the same, for an impact of an object with itself).
    pub object_b: u32,
    /// The primitives and the time, indices into the two objects' meshes.
    pub impact: Impact,
}

scene_results!(
    /// A caller-owned, reusable result buffer for [`Scene::continuous_collide`], with the
    /// scratch space of the threads that fill it. Use one per calling thread.
    SceneImpacts,
    SceneImpact,
    Impacts,
    CcdStats,
    "impacts",
    as_slice: "The impacts of the last successful query, sorted by `(object_a, object_b)`, then \
               as the pair's own query sorts them."
);

impl Scene {
    /// Every impact during the objects' steps between two objects that the filters allow and
    /// whose boxes over the step overlap, and within each object with self-contact on: for each
    /// such pair, exactly what [`crate::continuous_collide`] reports for two stand-alone meshes
    /// holding the objects' world positions and motions (a deformable object's
    /// [`Scene::set_motion`]; a rigid object's vertices moving in straight lines between their
    /// [`Scene::set_pose_motion`] poses; an object given no step stands still), and
    /// [`crate::self_continuous_collide`] for an object with itself. Exact by default
    /// ([`crate::CcdMode`]); the same for every thread count.
    ///
    /// The result replaces the contents of `out`, sorted by `(object_a, object_b)`, then as the
    /// pair's own query sorts its impacts. With [`CcdOptions::earliest_only`], only the earliest
    /// impact of the whole scene (of several at that time, the first in that order): each
    /// primitive test of every pair searches only up to the earliest impact found so far in any
    /// pair. With [`CcdOptions::max_impacts`], each pair's query keeps what its own query with
    /// that limit keeps, and the result the first of those in the scene's order, at most the
    /// limit ([`CcdStats::truncated`] says when anything was left out). The counters are sums
    /// over the pairs queried.
    ///
    /// Deformable objects whose positions or motion changed are refit here (whole, their
    /// volumes holding the step), and only those some pair needs. A rigid object that moves or
    /// is posed is placed in world coordinates, once per pose or step, into a copy of its mesh
    /// that the scene keeps.
    ///
    /// Errors: [`Error::OutOfMemory`] when a result or an object's world copy cannot grow. On
    /// error `out` still holds the previous result.
    pub fn continuous_collide(
        &mut self,
        options: &CcdOptions,
        out: &mut SceneImpacts,
    ) -> Result<CcdStats> {
        let mut candidates = std::mem::take(&mut self.candidates);
        self.select(Reach::Swept, &mut candidates);
        let mut needed = std::mem::take(&mut self.marks);
        marks(&candidates, self.objects.len(), &mut needed);
        self.refit_stale(|id| needed[id] != 0, options.threads, |_| false);
        let result = self
            .place_rigid(&needed)
            .and_then(|()| self.query_impacts(&candidates, options, out));
        self.candidates = candidates;
        self.marks = needed;
        result
    }

    /// Makes the world copy of every rigid object that `needed` names and that moves or is
    /// posed, where it is not current.
    fn place_rigid(&mut self, needed: &[u8]) -> Result<()> {
        for (id, o) in self.objects.iter_mut().enumerate() {
            let Some(o) = o.as_mut().filter(|_| needed[id] != 0) else {
                continue;
            };
            let Body::Rigid { pose, start, .. } = &o.body else {
                continue;
            };
            if start.is_none() && pose.is_identity()
                || o.world.as_ref().is_some_and(|w| w.stamp == o.stamp)
            {
                continue;
            }
            let (pose, start) = (*pose, *start);
            if o.world.is_none() {
                // A new copy's positions, volumes and the two lists below, asked for fallibly
                // first (Rust aborts on a failed allocation).
                let bytes =
                    2 * o.mesh.state_bytes() + 2 * std::mem::size_of_val(o.mesh.positions());
                let mut probe: Vec<u8> = Vec::new();
                probe
                    .try_reserve_exact(bytes)
                    .map_err(|_| Error::OutOfMemory { bytes })?;
                drop(probe);
                let mut mesh = (*o.mesh).clone();
                mesh.keep_spare();
                o.world = Some(Box::new(WorldCopy {
                    stamp: 0,
                    mesh,
                    start: Vec::new(),
                    end: Vec::new(),
                }));
            }
            let copy = o.world.as_mut().expect("made above");
            let WorldCopy {
                mesh,
                start: at_start,
                end: at_end,
                ..
            } = &mut **copy;
            let local = o.mesh.positions();
            at_end.clear();
            at_end.extend(local.iter().map(|p| pose.transform_point(p)));
            let placed = match start {
                Some(first) => {
                    at_start.clear();
                    at_start.extend(local.iter().map(|p| first.transform_point(p)));
                    mesh.refit_motion_points(at_start, at_end)
                }
                None => mesh.refit_points(at_end),
            };
            // The poses were checked to keep every coordinate in range: finite.
            placed.map_err(|e| Error::Object {
                object: id as u32,
                error: Box::new(e),
            })?;
            copy.stamp = o.stamp;
        }
        Ok(())
    }

    /// Queries every candidate pair and merges the impacts into `out`.
    fn query_impacts(
        &self,
        candidates: &[(u32, u32)],
        options: &CcdOptions,
        out: &mut SceneImpacts,
    ) -> Result<CcdStats> {
        let mut stats = CcdStats::default();
        let limit = if options.earliest_only {
            options.max_impacts.unwrap_or(usize::MAX).min(1)
        } else {
            options.max_impacts.unwrap_or(usize::MAX)
        };
        let best = AtomicU64::new(1.0f64.to_bits());
        out.shared
            .run(candidates, options.threads, &|w, (i, j), threads, found| {
                let a = self.candidate(i).world_mesh();
                let b = (i != j).then(|| self.candidate(j).world_mesh());
                let opts = options.with_threads(threads);
                let s = impacts_sharing(a, b, &opts, &mut w.buffer, &best)?;
                w.stats.bv_tests += s.bv_tests;
                w.stats.primitive_tests += s.primitive_tests;
                append(
                    found,
                    w.buffer.iter().map(|&impact| SceneImpact {
                        object_a: i,
                        object_b: j,
                        impact,
                    }),
                )?;
                Ok(s.truncated)
            })?;
        if options.earliest_only {
            // Each pair reported its earliest at or before the scene's earliest so far; the
            // first of the earliest in the scene's order wins.
            let mut first: Option<SceneImpact> = None;
            for s in out.shared.spans() {
                for x in out.shared.results(s) {
                    if first.is_none_or(|f| x.impact.toi < f.impact.toi) {
                        first = Some(*x);
                    }
                }
            }
            let merged = out.shared.merged();
            merged.clear();
            merged.try_reserve(1).map_err(|_| Error::OutOfMemory {
                bytes: std::mem::size_of::<SceneImpact>(),
            })?;
            merged.extend(first.filter(|_| limit > 0));
            stats.truncated = limit == 0;
        } else {
            stats.truncated = out.shared.merge(limit)?;
        }
        for w in out.shared.works() {
            stats.bv_tests += w.stats.bv_tests;
            stats.primitive_tests += w.stats.primitive_tests;
        }
        out.shared.publish(&mut out.items);
        stats.impacts = out.items.len() as u64;
        stats.earliest_toi = out
            .items
            .iter()
            .map(|x| x.impact.toi)
            .fold(f64::INFINITY, f64::min);
        Ok(stats)
    }
}
