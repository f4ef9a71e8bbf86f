//! What becomes of the terminal node pairs of a traversal: reported as they are (the coarse
//! modes), or their rings' triangles tested exactly (the exact modes).

use super::pairs::{Pair, QueryStats};
use super::side::{Kind, QuerySide};
use super::sink::Sink;
use super::traverse::{NarrowPhase, OneMesh};
use super::workspace::{Prepared, RingCache};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::is_safe_point;
use crate::geometry::tri_tri::{
    PreparedTriangle, prepared_triangles_intersect, triangles_intersect,
};
use std::ops::Range;

/// What a query asks: intersection or nearness, of two meshes or of one. It says how side `a`'s
/// volumes are read, whether the traversal is of one mesh, and which narrow phase tests the
/// triangles of terminal pairs in the exact modes ([`crate::QueryMode::Triangles`],
/// [`crate::QueryMode::FirstHit`]); the coarse modes report node pairs whatever the question.
pub(crate) trait Question<'m>: Copy + Send + Sync {
    /// Side `a`'s volume kind, given the mesh's own.
    type SideA<K: Kind<'m>>: Kind<'m>;
    /// The narrow phase of the exact modes.
    type Exact<'s, 'w: 's>: NarrowPhase<'m>;

    /// Side `a`'s volume kind, given the mesh's own.
    fn side_a<K: Kind<'m>>(&self, kind: K) -> Self::SideA<K>;
    /// `Some` when both sides are one mesh.
    fn own(&self) -> Option<OneMesh<'m>>;
    /// The narrow phase of the exact modes, writing to `sink` and caching prepared triangles in
    /// `rings_a` and `rings_b`; `check_domain`: must each triangle check that its coordinates
    /// suit the fast predicates?
    fn exact<'s, 'w: 's>(
        &self,
        sink: &'s mut Sink<'w>,
        rings_a: &'s mut RingCache,
        rings_b: &'s mut RingCache,
        check_domain: bool,
    ) -> Self::Exact<'s, 'w>;
}

/// Which triangles of two meshes intersect ([`crate::collide`]).
#[derive(Clone, Copy)]
pub(crate) struct Intersect;

impl<'m> Question<'m> for Intersect {
    type SideA<K: Kind<'m>> = K;
    type Exact<'s, 'w: 's> = TrianglePairs<'s, 'w>;

    fn side_a<K: Kind<'m>>(&self, kind: K) -> K {
        kind
    }

    fn own(&self) -> Option<OneMesh<'m>> {
        None
    }

    fn exact<'s, 'w: 's>(
        &self,
        sink: &'s mut Sink<'w>,
        rings_a: &'s mut RingCache,
        rings_b: &'s mut RingCache,
        check_domain: bool,
    ) -> TrianglePairs<'s, 'w> {
        TrianglePairs {
            sink,
            rings_a,
            rings_b,
            check_domain,
        }
    }
}

/// Reports every terminal node pair; of one mesh, as `(lower, higher)`.
pub(crate) struct NodePairs<'s, 'w> {
    pub sink: &'s mut Sink<'w>,
    pub one_mesh: bool,
}

impl<'m> NarrowPhase<'m> for NodePairs<'_, '_> {
    #[inline]
    fn visit<A, B>(&mut self, _: &mut A, _: &mut B, na: u32, nb: u32, _: &mut QueryStats) -> bool {
        let pair = if self.one_mesh {
            Pair {
                a: na.min(nb),
                b: na.max(nb),
            }
        } else {
            Pair { a: na, b: nb }
        };
        self.sink.report(pair)
    }
}

/// Tests the triangles of two leaves' rings exactly and reports the intersecting pairs. Boxes of
/// exact coordinates are an exact filter in front of the test: the rings' boxes first, then
/// each triangle against the other ring's box, then pair by pair.
pub(crate) struct TrianglePairs<'s, 'w> {
    pub sink: &'s mut Sink<'w>,
    pub rings_a: &'s mut RingCache,
    pub rings_b: &'s mut RingCache,
    /// Must each triangle check that its coordinates suit the fast predicates?
    pub check_domain: bool,
}

impl<'m> NarrowPhase<'m> for TrianglePairs<'_, '_> {
    fn visit<A: QuerySide<'m>, B: QuerySide<'m>>(
        &mut self,
        a: &mut A,
        b: &mut B,
        na: u32,
        nb: u32,
        stats: &mut QueryStats,
    ) -> bool {
        let (ma, mb) = (a.mesh(), b.mesh());
        let ra = ma.shape.tree.nodes[na as usize].ring_start;
        let rb = mb.shape.tree.nodes[nb as usize].ring_start;
        stats.triangle_candidates += (ma.shape.rings.triangles.row_len(ra as usize)
            * mb.shape.rings.triangles.row_len(rb as usize))
            as u64;
        // Most overlapping leaf volumes hold rings whose boxes are apart (about 70% of the
        // spheres on scanned meshes): ring boxes, computed once per ring and query, settle them
        // before any triangle is prepared.
        if !a.ring_box(na).meets(&b.ring_box(nb)) {
            return false;
        }
        let (span_a, bounds_a) = prepare(a, ra, self.rings_a, self.check_domain);
        let (span_b, bounds_b) = prepare(b, rb, self.rings_b, self.check_domain);
        if !bounds_a.meets(&bounds_b) {
            return false;
        }
        let (ca, cb) = (&mut *self.rings_a, &mut *self.rings_b);
        select(&ca.tris[span_a.clone()], &bounds_b, &mut ca.selected);
        select(&cb.tris[span_b.clone()], &bounds_a, &mut cb.selected);
        let (tris_a, tris_b) = (&ca.tris[span_a], &cb.tris[span_b]);
        for &i in &ca.selected {
            let ta = &tris_a[i as usize];
            for &j in &cb.selected {
                let tb = &tris_b[j as usize];
                if !ta.bounds.meets(&tb.bounds) {
                    continue;
                }
                stats.triangle_tests += 1;
                let hit = if ta.safe && tb.safe {
                    prepared_triangles_intersect(&ta.tri, &tb.tri)
                } else {
                    triangles_intersect(&ta.tri.corners, &tb.tri.corners)
                };
                if hit
                    && self.sink.report(Pair {
                        a: ta.index,
                        b: tb.index,
                    })
                {
                    return true;
                }
            }
        }
        false
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
    let rings = &side.mesh().shape.rings;
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
            safe: !check_domain || corners.iter().all(is_safe_point),
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
