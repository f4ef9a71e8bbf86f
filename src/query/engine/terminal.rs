//! What becomes of the terminal node pairs of a traversal: reported as they are (the coarse
//! modes, [`Coarse`]), or their rings' triangles tested exactly (the exact modes, [`Exact`]) by
//! the one leaf narrow phase, [`LeafPairs`], which asks a [`TriangleTest`] only what differs
//! between queries.

use super::query_traits::TriangleTest;
use super::side::QuerySide;
use super::sink::Sink;
use super::traverse::{Least, NarrowPhase, OneMesh, Walk, depth_first, pair_key};
use super::workspace::{Prepared, RingCache};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::is_safe_point;
use crate::geometry::tri_tri::PreparedTriangle;
use crate::mesh::Mesh;
use crate::query::pairs::{Pair, QueryStats};
use std::ops::Range;

/// What a query does with the terminal node pairs of its traversal: reports them
/// ([`Coarse`]), or tests their rings' triangles ([`Exact`]). Chosen before the sides are
/// typed, so that each is compiled only for the queries that use it, and the coarse traversal
/// once for all queries whose sides have the same types.
pub(crate) trait Terminal<'m>: Copy + Sync {
    /// Are triangles prepared (so that each thread's caches must hold rings)?
    const TRIANGLES: bool;

    /// `Some` when both sides are one mesh. Known when the code is compiled for the exact
    /// modes of a query of two meshes (always `None`), where it lets the traversal drop its
    /// checks of one mesh's pairs: a tenth of a small query's time.
    fn own(&self) -> Option<OneMesh<'m>>;

    /// Every terminal pair of the traversal `walk` from the roots (`None`) or below `start`,
    /// handled; the pairs found go to `sink`. Returns whether the traversal stopped early.
    #[allow(clippy::too_many_arguments)]
    fn descend<A: QuerySide<'m>, B: QuerySide<'m>>(
        &self,
        a: &mut A,
        b: &mut B,
        start: Option<(u32, u32)>,
        walk: &Walk<'m>,
        worker: Scratch<'_>,
        stats: &mut QueryStats,
        sink: &mut Sink,
    ) -> bool;
}

/// What of a thread's scratch space a traversal uses besides the sides' views.
pub(crate) struct Scratch<'w> {
    pub stack: &'w mut Vec<(u32, u32)>,
    pub rings_a: &'w mut RingCache,
    pub rings_b: &'w mut RingCache,
}

/// The coarse modes: every terminal node pair is reported. Compiled once for every query whose
/// sides have the same types, so whether they are one mesh is known only when it runs.
#[derive(Clone, Copy)]
pub(crate) struct Coarse<'m> {
    pub own: Option<OneMesh<'m>>,
}

impl<'m> Terminal<'m> for Coarse<'m> {
    const TRIANGLES: bool = false;

    #[inline(always)]
    fn own(&self) -> Option<OneMesh<'m>> {
        self.own
    }

    fn descend<A: QuerySide<'m>, B: QuerySide<'m>>(
        &self,
        a: &mut A,
        b: &mut B,
        start: Option<(u32, u32)>,
        walk: &Walk<'m>,
        worker: Scratch<'_>,
        stats: &mut QueryStats,
        sink: &mut Sink,
    ) -> bool {
        let mut narrow = NodePairs {
            sink,
            one_mesh: walk.own.is_some(),
        };
        depth_first(a, b, start, walk, worker.stack, stats, &mut narrow)
    }
}

/// The exact modes: the triangles of each terminal leaf pair's rings are tested with `test`.
#[derive(Clone, Copy)]
pub(crate) struct Exact<T> {
    pub test: T,
    /// May the query's coordinates leave the range of the fast predicates?
    pub check_domain: bool,
}

impl<'m, T: TriangleTest<'m>> Terminal<'m> for Exact<T> {
    const TRIANGLES: bool = true;

    #[inline(always)]
    fn own(&self) -> Option<OneMesh<'m>> {
        self.test.own()
    }

    fn descend<A: QuerySide<'m>, B: QuerySide<'m>>(
        &self,
        a: &mut A,
        b: &mut B,
        start: Option<(u32, u32)>,
        walk: &Walk<'m>,
        worker: Scratch<'_>,
        stats: &mut QueryStats,
        sink: &mut Sink,
    ) -> bool {
        let mut narrow = LeafPairs {
            test: self.test,
            sink,
            rings_a: worker.rings_a,
            rings_b: worker.rings_b,
            check_domain: self.check_domain,
        };
        depth_first(a, b, start, walk, worker.stack, stats, &mut narrow)
    }
}

/// Reports every terminal node pair; of one mesh, as `(lower, higher)`.
pub(crate) struct NodePairs<'s, 'w> {
    pub sink: &'s mut Sink<'w>,
    pub one_mesh: bool,
}

impl<'m, A: QuerySide<'m>, B: QuerySide<'m>> NarrowPhase<'m, A, B> for NodePairs<'_, '_> {
    #[inline]
    fn visit(&mut self, _: &mut A, _: &mut B, na: u32, nb: u32, _: &mut QueryStats) -> bool {
        self.sink.report(ordered(self.one_mesh, na, nb))
    }
}

/// The pair `(a, b)`; of one mesh, `(lower, higher)`.
#[inline(always)]
fn ordered(one_mesh: bool, a: u32, b: u32) -> Pair {
    if one_mesh {
        Pair {
            a: a.min(b),
            b: a.max(b),
        }
    } else {
        Pair { a, b }
    }
}

/// Tests the triangles of two leaves' rings with the pair test `T` and reports the pairs it
/// accepts. Boxes of exact coordinates, grown by the test's margin, are an exact filter in front
/// of the test: the rings' boxes first, then each triangle against the other ring's box, then
/// pair by pair.
pub(crate) struct LeafPairs<'s, 'w, T> {
    pub test: T,
    pub sink: &'s mut Sink<'w>,
    pub rings_a: &'s mut RingCache,
    pub rings_b: &'s mut RingCache,
    /// May the query's coordinates leave the range of the fast predicates?
    pub check_domain: bool,
}

impl<'m, T: TriangleTest<'m>> LeafPairs<'_, '_, T> {
    /// Must each prepared triangle check its coordinates?
    #[inline(always)]
    fn check_domain(&self) -> bool {
        T::CHECKS_DOMAIN && self.check_domain
    }

    /// A leaf of one mesh against itself: each pair of its ring's triangles once.
    fn own<A: QuerySide<'m>>(&mut self, a: &mut A, n: u32, stats: &mut QueryStats) -> bool {
        let mesh = a.mesh();
        let r = mesh.tree().nodes[n as usize].ring_start;
        let (span, _) = prepare(a, r, self.rings_a, self.check_domain());
        let count = span.len() as u64;
        stats.triangle_candidates += count * count.saturating_sub(1) / 2;
        let tris = &self.rings_a.tris;
        for i in span.clone() {
            let grown = self.test.widen(&tris[i].bounds);
            for tb in &tris[i + 1..span.end] {
                if try_pair(&self.test, self.sink, mesh, &grown, &tris[i], tb, stats) {
                    return true;
                }
            }
        }
        false
    }
}

/// Tests `ta` against `tb` (`grown`: `ta`'s box grown by the margin) and reports the pair if
/// the test accepts it; returns whether the traversal must stop.
#[inline(always)]
fn try_pair<'m, T: TriangleTest<'m>>(
    test: &T,
    sink: &mut Sink,
    mesh: &Mesh,
    grown: &Aabb,
    ta: &Prepared,
    tb: &Prepared,
    stats: &mut QueryStats,
) -> bool {
    if !grown.meets(&tb.bounds) || test.skips(mesh, ta, tb) {
        return false;
    }
    stats.triangle_tests += 1;
    test.test(mesh, ta, tb) && sink.report(ordered(test.own().is_some(), ta.index, tb.index))
}

impl<'m, A, B, T> NarrowPhase<'m, A, B> for LeafPairs<'_, '_, T>
where
    A: QuerySide<'m>,
    B: QuerySide<'m>,
    T: TriangleTest<'m>,
{
    fn visit(&mut self, a: &mut A, b: &mut B, na: u32, nb: u32, stats: &mut QueryStats) -> bool {
        if na == nb && self.test.own().is_some() {
            return self.own(a, na, stats);
        }
        let (ma, mb) = (a.mesh(), b.mesh());
        let ra = ma.tree().nodes[na as usize].ring_start;
        let rb = mb.tree().nodes[nb as usize].ring_start;
        stats.triangle_candidates += (ma.rings().triangles.row_len(ra as usize)
            * mb.rings().triangles.row_len(rb as usize))
            as u64;
        // Most overlapping leaf volumes hold rings whose boxes are apart (about 70% of the
        // spheres on scanned meshes): ring boxes, computed once per ring and query, settle them
        // before any triangle is prepared.
        if !self.test.widen(&a.ring_box(na)).meets(&b.ring_box(nb)) {
            return false;
        }
        let check_domain = self.check_domain();
        let (span_a, bounds_a) = prepare(a, ra, self.rings_a, check_domain);
        let (span_b, bounds_b) = prepare(b, rb, self.rings_b, check_domain);
        let (near_a, near_b) = (self.test.widen(&bounds_a), self.test.widen(&bounds_b));
        if !near_a.meets(&bounds_b) {
            return false;
        }
        let (ca, cb) = (&mut *self.rings_a, &mut *self.rings_b);
        select(&ca.tris[span_a.clone()], &near_b, &mut ca.selected);
        select(&cb.tris[span_b.clone()], &near_a, &mut cb.selected);
        let (tris_a, tris_b) = (&ca.tris[span_a], &cb.tris[span_b]);
        for &i in &ca.selected {
            let ta = &tris_a[i as usize];
            let grown = self.test.widen(&ta.bounds);
            for &j in &cb.selected {
                let tb = &tris_b[j as usize];
                if try_pair(&self.test, self.sink, ma, &grown, ta, tb, stats) {
                    return true;
                }
            }
        }
        false
    }
}

/// [`LeafPairs`] keeping only the least pair it finds, in `(a, b)` order, for
/// [`super::traverse::least_first`]; starts from a bound (a pair known to be accepted, or
/// `u64::MAX`) that only a lesser pair replaces.
pub(crate) struct LeastPairs<'s, 'w, T> {
    pub leaves: LeafPairs<'s, 'w, T>,
    /// The least pair yet, as its [`pair_key`].
    pub least: u64,
}

impl<T> Least for LeastPairs<'_, '_, T> {
    #[inline]
    fn least(&self) -> u64 {
        self.least
    }
}

impl<'m, A, B, T> NarrowPhase<'m, A, B> for LeastPairs<'_, '_, T>
where
    A: QuerySide<'m>,
    B: QuerySide<'m>,
    T: TriangleTest<'m>,
{
    fn visit(&mut self, a: &mut A, b: &mut B, na: u32, nb: u32, stats: &mut QueryStats) -> bool {
        let stop = self.leaves.visit(a, b, na, nb, stats);
        for p in self.leaves.sink.out.drain(..) {
            self.least = self.least.min(pair_key(p));
        }
        stop
    }
}

/// Ring `r`'s triangles in the side's frame, prepared unless the cache holds them: where they
/// are in the cache's arena, and the box around them all.
#[inline]
pub(super) fn prepare<'m, S: QuerySide<'m>>(
    side: &mut S,
    r: u32,
    cache: &mut RingCache,
    check_domain: bool,
) -> (Range<usize>, Aabb) {
    let rings = &side.mesh().rings();
    let items = rings.triangles.span(r as usize..r as usize + 1);
    if let Some((start, bounds)) = cache.held(r) {
        return (start..start + items.len(), bounds);
    }
    let start = cache.place(r, items.len());
    let span = start..start + items.len();
    let mut bounds = Aabb::EMPTY;
    for ((&t, &[i, j, k]), into) in rings.triangles.items()[items.clone()]
        .iter()
        .zip(&rings.corners[items])
        .zip(&mut cache.tris[span.clone()])
    {
        let corners = [side.vertex(i), side.vertex(j), side.vertex(k)];
        let b = Aabb::of_points(&corners);
        bounds.merge(&b);
        *into = Prepared {
            bounds: b,
            index: t,
            in_fast_range: !check_domain || corners.iter().all(is_safe_point),
            tri: PreparedTriangle::new(corners),
        };
    }
    cache.filled(r, bounds);
    (span, bounds)
}

/// Lists in `selected` the triangles of `tris` whose boxes meet `other`.
#[inline]
pub(super) fn select(tris: &[Prepared], other: &Aabb, selected: &mut Vec<u32>) {
    selected.clear();
    for (i, t) in tris.iter().enumerate() {
        if t.bounds.meets(other) {
            selected.push(i as u32);
        }
    }
}
