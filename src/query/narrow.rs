//! What becomes of the terminal node pairs of a traversal: reported as they are (the coarse
//! modes), or their rings' triangles tested exactly (the exact modes).

use super::pairs::{Pair, QueryStats};
use super::side::QuerySide;
use super::sink::Sink;
use super::traverse::NarrowPhase;
use super::workspace::{Gathered, GatheredRing};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::is_safe_point;
use crate::geometry::tri_tri::{triangles_intersect, triangles_intersect_safe};

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
    pub ring_a: &'s mut GatheredRing,
    pub ring_b: &'s mut GatheredRing,
    /// Must each triangle check that its coordinates suit the fast predicates?
    pub check_domain: bool,
}

impl<'m, A: QuerySide<'m>, B: QuerySide<'m>> NarrowPhase<'m, A, B> for TrianglePairs<'_, '_> {
    fn visit(&mut self, a: &mut A, b: &mut B, na: u32, nb: u32, stats: &mut QueryStats) -> bool {
        let (ma, mb) = (a.mesh(), b.mesh());
        let ra = ma.tree.nodes[na as usize].ring_start;
        let rb = mb.tree.nodes[nb as usize].ring_start;
        stats.triangle_candidates += (ma.rings.triangles.row_len(ra as usize)
            * mb.rings.triangles.row_len(rb as usize)) as u64;
        // Most overlapping leaf volumes hold rings whose boxes are apart (about 70% of the
        // spheres on scanned meshes): ring boxes, computed once per ring and query, settle them
        // before any triangle is gathered.
        if !a.ring_box(na).meets(&b.ring_box(nb)) {
            return false;
        }
        gather(a, ra, self.ring_a, self.check_domain);
        gather(b, rb, self.ring_b, self.check_domain);
        let (ga, gb) = (&mut *self.ring_a, &mut *self.ring_b);
        if !ga.bounds.meets(&gb.bounds) {
            return false;
        }
        select(ga, &gb.bounds);
        select(gb, &ga.bounds);
        for &i in &ga.selected {
            let ta = &ga.tris[i as usize];
            for &j in &gb.selected {
                let tb = &gb.tris[j as usize];
                if !ta.bounds.meets(&tb.bounds) {
                    continue;
                }
                stats.triangle_tests += 1;
                let hit = if ta.safe && tb.safe {
                    triangles_intersect_safe(&ta.corners, &tb.corners)
                } else {
                    triangles_intersect(&ta.corners, &tb.corners)
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

/// Collects ring `r`'s triangles in the side's frame, with their boxes, unless already held.
fn gather<'m, S: QuerySide<'m>>(side: &mut S, r: u32, into: &mut GatheredRing, check_domain: bool) {
    if into.ring == r {
        return;
    }
    into.ring = r;
    into.tris.clear();
    into.bounds = Aabb::EMPTY;
    let rings = &side.mesh().rings;
    let span = rings.triangles.span(r as usize..r as usize + 1);
    for (&t, &[i, j, k]) in rings.triangles.items()[span.clone()]
        .iter()
        .zip(&rings.corners[span])
    {
        let corners = [side.vertex(i), side.vertex(j), side.vertex(k)];
        let bounds = Aabb::of_points(&corners);
        into.bounds.merge(&bounds);
        let safe = !check_domain || corners.iter().all(is_safe_point);
        into.tris.push(Gathered {
            index: t,
            corners,
            bounds,
            safe,
        });
    }
}

/// Marks the triangles of `ring` whose boxes meet `other`.
fn select(ring: &mut GatheredRing, other: &Aabb) {
    ring.selected.clear();
    for (i, t) in ring.tris.iter().enumerate() {
        if t.bounds.meets(other) {
            ring.selected.push(i as u32);
        }
    }
}
