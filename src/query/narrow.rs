//! What becomes of the terminal node pairs of a traversal: reported as they are (the coarse
//! modes), or their rings' triangles tested exactly (the exact modes).

use super::pairs::{Pair, QueryStats};
use super::side::QuerySide;
use super::sink::Sink;
use super::traverse::NarrowPhase;
use super::workspace::{Prepared, RingCache};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::is_safe_point;
use crate::geometry::tri_tri::{
    PreparedTriangle, prepared_triangles_intersect, triangles_intersect,
};
use std::ops::Range;

/// Reports every terminal node pair.
pub(crate) struct NodePairs<'s, 'w> {
    pub sink: &'s mut Sink<'w>,
}

impl<'m, A: QuerySide<'m>, B: QuerySide<'m>> NarrowPhase<'m, A, B> for NodePairs<'_, '_> {
    #[inline]
    fn visit(&mut self, _: &mut A, _: &mut B, na: u32, nb: u32, _: &mut QueryStats) -> bool {
        self.sink.report(Pair { a: na, b: nb })
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

impl<'m, A: QuerySide<'m>, B: QuerySide<'m>> NarrowPhase<'m, A, B> for TrianglePairs<'_, '_> {
    fn visit(&mut self, a: &mut A, b: &mut B, na: u32, nb: u32, stats: &mut QueryStats) -> bool {
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
