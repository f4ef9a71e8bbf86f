//! The scene's intersection query: the broad phase and the filters choose the object pairs,
//! the deformable objects among them are refit, and the pairs are queried on the threads
//! allowed, their contacts merged in order.

use super::select::{Reach, WITH_ITSELF, marks};
use super::share::{Shared, Work, append};
use super::{Apart, Body, Object, Scene, volume_box};
use crate::error::{Error, Result};
use crate::geometry::aabb::Aabb;
use crate::mesh::Mesh;
use crate::query::{
    PairKind, Pairs, QueryMode, QueryOptions, QueryStats, collide_lazy, result_buffer, self_collide,
};
use crate::volume::LazyBoxes;
use std::sync::Arc;

/// A contact between two objects of a scene, or of one object with itself: `a` of object
/// `object_a` meets `b` of object `object_b`, with `object_a <= object_b` (equal for an object
/// with self-contact on, `a < b` then, as [`crate::self_collide`] reports them). Triangle
/// indices, or node indices in the coarse modes ([`Contacts::kind`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(C)]
pub struct Contact {
    /// The object with the lower id.
    pub object_a: u32,
    /// The object with the higher id (the same, for a contact of an object with itself).
    pub object_b: u32,
    /// Index in `object_a`'s mesh.
    pub a: u32,
    /// Index in `object_b`'s mesh.
    pub b: u32,
}

impl Contact {
    /// The contacts of objects `object_a` and `object_b` whose meshes' query found `pairs`.
    pub(crate) fn of_pairs(
        object_a: u32,
        object_b: u32,
        pairs: &Pairs,
    ) -> impl ExactSizeIterator<Item = Contact> + '_ {
        pairs.iter().map(move |p| Contact {
            object_a,
            object_b,
            a: p.a,
            b: p.b,
        })
    }
}

/// Counters of one scene query.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct SceneStats {
    /// Objects in the scene.
    pub objects: u64,
    /// Object pairs that passed the broad phase and the filters, and were queried, each object
    /// with self-contact on counted as a pair with itself. A pair that an earlier query found
    /// without contact is not queried again while neither object has changed (nor the
    /// options): it is not counted.
    pub object_pairs_tested: u64,
    /// Object pairs with at least one contact.
    pub object_pairs_colliding: u64,
    /// Volume pairs tested, over every object pair.
    pub bv_tests: u64,
    /// Triangle pairs given to the exact test, over every object pair.
    pub triangle_tests: u64,
    /// Nodes recomputed by the refits the query made (`NU`): only in deformable objects some
    /// pair needed whose positions had changed and, with box volumes in the modes that report
    /// triangles, only the blocks of their trees that a traversal reached.
    pub nodes_refit: u64,
    /// Contacts reported.
    pub contacts: u64,
    /// Did [`QueryOptions::max_pairs`] cut the result short?
    pub truncated: bool,
}

/// A caller-owned, reusable result buffer for [`Scene::collide`], with the scratch space of the
/// threads that fill it. Use one per calling thread.
#[derive(Debug, Default)]
pub struct Contacts {
    items: Vec<Contact>,
    kind: PairKind,
    shared: Shared<Work<Pairs, QueryStats>, Contact>,
}

result_buffer!(
    Contacts,
    Contact,
    "contacts",
    as_slice: "The contacts of the last successful query, sorted by `(object_a, object_b, a, b)`.",
    kind: "What `a` and `b` of each contact index: triangles, or nodes in the coarse modes."
);

/// Object pair `(i, j)`'s contacts, appended to `found` (an object with itself when `i == j`).
fn query_pair(
    work: &mut Work<Pairs, QueryStats>,
    objects: &[Option<Object>],
    lazy: &[Option<LazyBoxes>],
    (i, j): (u32, u32),
    opts: &QueryOptions,
    found: &mut Vec<Contact>,
) -> Result<bool> {
    let (oa, ob) = (
        objects[i as usize].as_ref().expect("a candidate is live"),
        objects[j as usize].as_ref().expect("a candidate is live"),
    );
    let stats = if i == j {
        // Refit whole before the query (see `Scene::collide`): no lazy view.
        self_collide(&oa.mesh, opts, &mut work.buffer)?
    } else {
        collide_lazy(
            (
                &oa.mesh,
                oa.pose(),
                lazy.get(i as usize).and_then(Option::as_ref),
            ),
            (
                &ob.mesh,
                ob.pose(),
                lazy.get(j as usize).and_then(Option::as_ref),
            ),
            opts,
            &mut work.buffer,
        )?
    };
    work.stats.add(&stats);
    append(found, Contact::of_pairs(i, j, &work.buffer))?;
    Ok(stats.truncated)
}

impl Scene {
    /// Every contact between two objects that the filters allow (groups and masks, exclusions)
    /// and whose world boxes overlap, as [`QueryOptions::mode`] asks: for each such pair, exactly
    /// what [`collide`](crate::collide) reports for the two objects' current geometry and poses
    /// ([`QueryMode::FirstHit`]: at most one contact per object pair); and for each object with
    /// self-contact on ([`Scene::set_self_contact`]), what [`crate::self_collide`] reports for
    /// it. Objects given a step are seen at its end. The result replaces the contents of `out`,
    /// sorted by `(object_a, object_b, a, b)`; [`QueryOptions::max_pairs`] bounds the whole
    /// result (the first contacts in that order, and [`SceneStats::truncated`]).
    ///
    /// Deformable objects whose positions changed are refit here, and only those that some
    /// object pair needs. With box volumes (the default) and a mode that reports triangles the
    /// refit is lazy: the nodes above a cut through the tree come from one pass over the
    /// positions, and each block below the cut (about 32 rings) is refit when a traversal first
    /// opens its root, so the parts of an object no other one comes near are never refit. The
    /// boxes are exactly the eager refit's, so is the result. The other volume kinds, the
    /// coarse modes (which report nodes wherever volumes overlap), and objects with
    /// self-contact on are refit whole.
    ///
    /// Object pairs are shared among [`QueryOptions::threads`] threads (the result does not
    /// depend on the count); a single pair gets all of them. Two threads may reach one object's
    /// block at once: each block is refit once, under the object's lock, and read only after
    /// (see the `volume::lazy` module). A query takes `&mut self`, so no other call, and no
    /// other query, runs on the scene meanwhile.
    ///
    /// Errors: [`Error::ZeroBudget`]; [`Error::OutOfMemory`] when a result cannot grow. On error
    /// `out` still holds the previous result.
    pub fn collide(&mut self, options: &QueryOptions, out: &mut Contacts) -> Result<SceneStats> {
        if options.mode == QueryMode::Budget(0) {
            return Err(Error::ZeroBudget);
        }
        let mut stats = SceneStats {
            objects: self.len() as u64,
            ..SceneStats::default()
        };
        let mut candidates = std::mem::take(&mut self.candidates);
        if options.mode.reports_nodes() {
            // Node pairs are reported wherever the volumes overlap, the roots' included, and
            // the volumes are known only once refit: every object is refit, and the broad phase
            // compares boxes around the root volumes.
            stats.nodes_refit = self.refit_stale(|_| true, options.threads, |_| false);
            let boxes: Vec<_> = self
                .objects
                .iter()
                .map(|o| o.as_ref().map_or(Aabb::EMPTY, volume_box))
                .collect();
            self.broad.overlapping(&boxes, &mut candidates);
            self.filter_and_add_self(&mut candidates);
        } else {
            self.select(Reach::End, &mut candidates);
        }
        // Pairs found apart before, unchanged since, are not queried again.
        let key = QueryOptions {
            threads: 0,
            ..*options
        };
        let mut apart_next = std::mem::take(&mut self.apart_next);
        apart_next.clear();
        candidates.retain(|&(i, j)| {
            let now = Apart {
                stamps: (stamp(&self.objects, i), stamp(&self.objects, j)),
                options: key,
            };
            let unchanged = self.apart.get(&(i, j)) == Some(&now);
            if unchanged {
                apart_next.insert((i, j), now);
            }
            !unchanged
        });
        let mut needed = std::mem::take(&mut self.marks);
        marks(&candidates, self.objects.len(), &mut needed);
        let result = if options.mode.reports_nodes() {
            self.query_pairs(&candidates, &[], options, out, &mut stats)
        } else {
            // An object with itself is refit whole (`self_collide` reads no lazy view).
            let lazy = !self.eager;
            stats.nodes_refit = self.refit_stale(
                |id| needed[id] != 0,
                options.threads,
                |id| lazy && needed[id] & WITH_ITSELF == 0,
            );
            let boxes = self.lazy_boxes(&needed);
            // SAFETY: nothing but the views reads those boxes until they are dropped below.
            let lazy = unsafe { self.lazy_views(&boxes) };
            let result = self.query_pairs(&candidates, &lazy, options, out, &mut stats);
            drop(lazy);
            for o in self.objects.iter_mut().flatten() {
                if let Body::Deformable { fresh } = &mut o.body {
                    stats.nodes_refit += fresh.take_nodes();
                    fresh.settle();
                }
            }
            result
        };
        if result.is_ok() {
            for (&(i, j), span) in candidates.iter().zip(out.shared.spans()) {
                if span.len == 0 && !span.truncated {
                    let now = Apart {
                        stamps: (stamp(&self.objects, i), stamp(&self.objects, j)),
                        options: key,
                    };
                    apart_next.insert((i, j), now);
                }
            }
            std::mem::swap(&mut self.apart, &mut apart_next);
        }
        self.apart_next = apart_next;
        self.candidates = candidates;
        self.marks = needed;
        result.map(|()| stats)
    }

    /// Per object: the boxes a query reads lazily, for the objects `needed` whose top is current
    /// and some block not (each such mesh made this scene's own first).
    fn lazy_boxes(&mut self, needed: &[u8]) -> Vec<Option<*mut [Aabb]>> {
        self.objects
            .iter_mut()
            .zip(needed)
            .map(|(o, &needed)| {
                let o = o.as_mut().filter(|_| needed != 0)?;
                match &o.body {
                    Body::Deformable { fresh } if fresh.is_partial() => {}
                    _ => return None,
                }
                Arc::make_mut(&mut o.mesh)
                    .boxes_mut()
                    .map(|boxes| boxes as *mut [Aabb])
            })
            .collect()
    }

    /// The lazy views of the objects `boxes` names.
    ///
    /// # Safety
    /// While the views live, the boxes they name must be reached only through them.
    unsafe fn lazy_views<'s>(
        &'s self,
        boxes: &[Option<*mut [Aabb]>],
    ) -> Vec<Option<LazyBoxes<'s>>> {
        self.objects
            .iter()
            .zip(boxes)
            .map(|(o, &b)| {
                let (o, b) = (o.as_ref()?, b?);
                let Body::Deformable { fresh } = &o.body else {
                    return None;
                };
                let mesh: &Mesh = &o.mesh;
                let blocks = mesh.blocks()?;
                // SAFETY: `b` is this mesh's boxes (made unique by `lazy_boxes`, so no other
                // object reads them), and the query reads them only through the view.
                Some(unsafe { LazyBoxes::new(b, blocks, fresh, mesh.refit_input()) })
            })
            .collect()
    }

    /// Queries every candidate pair and merges the contacts into `out`. `lazy`: per object, its
    /// boxes when they are refit lazily (may be empty: none is).
    fn query_pairs(
        &self,
        candidates: &[(u32, u32)],
        lazy: &[Option<LazyBoxes>],
        options: &QueryOptions,
        out: &mut Contacts,
        stats: &mut SceneStats,
    ) -> Result<()> {
        let objects = &self.objects[..];
        out.shared
            .run(candidates, options.threads, &|w, pair, threads, found| {
                let opts = options.with_threads(threads);
                query_pair(w, objects, lazy, pair, &opts, found)
            })?;
        let limit = options.max_pairs.unwrap_or(usize::MAX);
        stats.truncated |= out.shared.merge(limit)?;
        for s in out.shared.spans() {
            stats.object_pairs_colliding += u64::from(s.len > 0);
        }
        for w in out.shared.works() {
            stats.bv_tests += w.stats.bv_tests;
            stats.triangle_tests += w.stats.triangle_tests;
        }
        stats.object_pairs_tested = candidates.len() as u64;
        out.shared.publish(&mut out.items);
        stats.contacts = out.items.len() as u64;
        out.kind = if options.mode.reports_nodes() {
            PairKind::Nodes
        } else {
            PairKind::Triangles
        };
        Ok(())
    }
}

/// Object `id`'s stamp (0 for none).
fn stamp(objects: &[Option<Object>], id: u32) -> u64 {
    objects[id as usize].as_ref().map_or(0, |o| o.stamp)
}
