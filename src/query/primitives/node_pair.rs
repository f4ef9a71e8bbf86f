//! One node pair's primitive pairs: the vertices, edges and triangles its rings own (the rule of
//! [`crate::mesh::Features`]), each with its box; every vertex-face and edge-edge pair whose
//! boxes come within the test's reach is given to the test, once.

use super::ImpactKind;
use super::boxes::OwnedBoxes;
use super::subsets::{Built, Kept, Primitives, Scratch, Subset};
use super::vocabulary::{Owners, PrimitivePair, PrimitiveTest, Side, Worker};
use crate::geometry::Primitive;
use crate::geometry::aabb::Aabb;

/// Calls `f` with each position `k` of `boxes`, in order, whose box comes within `d` of `b`
/// (by [`Aabb::reach`]) and whose vertices `vertices[k]` are not `excluded`, until `f` returns
/// true (then returns true). The tests of up to 64 positions are made first, without a branch,
/// into a mask: on a self query most pairs whose boxes meet share a vertex, and which do
/// follows no pattern a predictor learns on a scanned mesh. (On a regular grid it does: there
/// branches were about a tenth faster.)
#[inline(always)]
fn each_near<I>(
    b: &Aabb,
    d: f64,
    (boxes, vertices): (&[Aabb], &[I]),
    excluded: impl Fn(&I) -> bool,
    mut f: impl FnMut(usize) -> bool,
) -> bool {
    let b = b.reach(d);
    let mut start = 0;
    while start < boxes.len() {
        let end = boxes.len().min(start + 64);
        let mut mask = 0u64;
        for (k, (x, v)) in boxes[start..end]
            .iter()
            .zip(&vertices[start..end])
            .enumerate()
        {
            mask |= ((b.meets(x) & !excluded(v)) as u64) << k;
        }
        while mask != 0 {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if f(start + k) {
                return true;
            }
        }
        start = end;
    }
    false
}

/// Do edges `a` and `b` share a vertex? (Without a branch.)
#[inline(always)]
fn share(a: [u32; 2], b: &[u32; 2]) -> bool {
    (a[0] == b[0]) | (a[0] == b[1]) | (a[1] == b[0]) | (a[1] == b[1])
}

/// A query's two meshes (one mesh twice for a self query) and its test.
pub(crate) struct Narrow<'m, T> {
    pub a: Owners<'m>,
    pub b: Owners<'m>,
    /// Both sides are one mesh.
    pub one_mesh: bool,
    pub test: T,
}

/// Each side's boxes of its owned primitives, computed once for the query (one table for
/// both sides of a self query), as the test made them at [`PrimitiveTest::box_epoch`] `epoch`.
#[derive(Clone, Copy)]
pub(crate) struct Tables<'b> {
    pub a: &'b OwnedBoxes,
    pub b: &'b OwnedBoxes,
    pub epoch: u64,
}

impl<T: PrimitiveTest> Narrow<'_, T> {
    /// Tests the primitive pairs of node `na` of `a` and `nb` of `b` (of one mesh, `na <= nb`,
    /// the two equal or with no ring in common) into `w`, stopping once `w.out` holds `limit`
    /// results. Returns whether it stopped. The primitives' boxes come from `tables`, filled
    /// for both nodes, or are built here once the test's boxes have become tighter than the
    /// tables' ([`PrimitiveTest::box_epoch`]).
    pub fn node_pair(
        &self,
        tables: Tables,
        w: &mut Worker<T::Found>,
        na: u32,
        nb: u32,
        limit: usize,
    ) -> bool {
        let tables = Some(tables).filter(|t| t.epoch == self.test.box_epoch());
        let mut scratch = w.scratch.take().unwrap_or_default();
        let stopped = self.node_pair_in(tables, w, &mut scratch, na, nb, limit);
        w.scratch = Some(scratch);
        stopped
    }

    /// [`Narrow::node_pair`] with the worker's scratch space taken out of it.
    fn node_pair_in(
        &self,
        tables: Option<Tables>,
        w: &mut Worker<T::Found>,
        scratch: &mut Scratch,
        na: u32,
        nb: u32,
        limit: usize,
    ) -> bool {
        let d = self.test.reach();
        let Scratch {
            kept: [kept_a, kept_b],
            built: [built_a, built_b],
        } = scratch;
        if self.one_mesh && na == nb {
            let p = match tables {
                Some(t) => self.primitives_in_table(Side::A, na, t.a),
                None => {
                    self.build_triangles(Side::A, na, built_a);
                    self.build_vertices_and_edges(Side::A, na, built_a);
                    self.primitives_built(Side::A, na, built_a)
                }
            };
            // Every primitive is kept: only the triangles' corners need gathering.
            kept_a.keep_triangles(&p, self.a.mesh.triangles(), None, d);
            return self.own(w, &p, &kept_a.triangles, limit);
        }
        // A leaf's ring owns about 7 triangles and 10 edges: each side keeps what comes near
        // the other node before the pairs are formed (most does not).
        let (pa, pb, box_a, box_b) = match tables {
            Some(t) => {
                let box_a = t.a.of_rings(self.rings(Side::A, na).1);
                let box_b = t.b.of_rings(self.rings(Side::B, nb).1);
                if !box_a.within(&box_b, d) {
                    return false;
                }
                let pa = self.primitives_in_table(Side::A, na, t.a);
                (pa, self.primitives_in_table(Side::B, nb, t.b), box_a, box_b)
            }
            None => {
                // Boxes built here, the triangles' first: they give each node's box.
                let box_a = self.build_triangles(Side::A, na, built_a);
                let box_b = self.build_triangles(Side::B, nb, built_b);
                if !box_a.within(&box_b, d) {
                    return false;
                }
                self.build_vertices_and_edges(Side::A, na, built_a);
                self.build_vertices_and_edges(Side::B, nb, built_b);
                let pa = self.primitives_built(Side::A, na, built_a);
                (
                    pa,
                    self.primitives_built(Side::B, nb, built_b),
                    box_a,
                    box_b,
                )
            }
        };
        kept_a.keep(&pa, self.a.mesh.triangles(), Some(&box_b), d);
        kept_b.keep(&pb, self.b.mesh.triangles(), Some(&box_a), d);
        self.apart(w, (&pa, kept_a), (&pb, kept_b), limit)
    }

    /// The mesh of `side`.
    #[inline(always)]
    fn owners(&self, side: Side) -> &Owners<'_> {
        match side {
            Side::A => &self.a,
            Side::B => &self.b,
        }
    }

    /// The mesh of `side` and the rings below its node `n`.
    #[inline(always)]
    fn rings(&self, side: Side, n: u32) -> (&Owners<'_>, std::ops::Range<usize>) {
        let owners = self.owners(side);
        let node = &owners.mesh.tree().nodes[n as usize];
        (owners, node.ring_start as usize..node.ring_end as usize)
    }

    /// The primitives the rings of node `n` of `side` own, with their boxes from `table`.
    #[inline]
    fn primitives_in_table<'t>(
        &'t self,
        side: Side,
        n: u32,
        table: &'t OwnedBoxes,
    ) -> Primitives<'t> {
        let (owners, rings) = self.rings(side, n);
        let f = owners.features;
        let (t, v, e) = (
            f.triangles.span(rings.clone()),
            f.vertices.span(rings.clone()),
            f.edges.span(rings),
        );
        Primitives {
            triangle_boxes: &table.triangles[t.clone()],
            triangles: &f.triangles.items()[t],
            vertex_boxes: &table.vertices[v.clone()],
            vertices: &f.vertices.items()[v],
            edge_boxes: &table.edges[e.clone()],
            edges: &f.edges.items()[e],
        }
    }

    /// The primitives the rings of node `n` of `side` own, with the boxes `built` for them.
    #[inline]
    fn primitives_built<'t>(&'t self, side: Side, n: u32, built: &'t Built) -> Primitives<'t> {
        let (owners, rings) = self.rings(side, n);
        let f = owners.features;
        Primitives {
            triangle_boxes: &built.triangles,
            triangles: &f.triangles.items()[f.triangles.span(rings.clone())],
            vertex_boxes: &built.vertices,
            vertices: &f.vertices.items()[f.vertices.span(rings.clone())],
            edge_boxes: &built.edges,
            edges: &f.edges.items()[f.edges.span(rings)],
        }
    }

    /// Builds the boxes of the triangles the rings of node `n` of `side` own into `built`;
    /// returns the box of them all.
    fn build_triangles(&self, side: Side, n: u32, built: &mut Built) -> Aabb {
        let (owners, rings) = self.rings(side, n);
        let f = owners.features;
        let corners = owners.mesh.triangles();
        let mut all = Aabb::EMPTY;
        built.triangles.clear();
        for &t in &f.triangles.items()[f.triangles.span(rings)] {
            let b = self.boxed(side, &corners[t as usize]);
            all.merge(&b);
            built.triangles.push(b);
        }
        all
    }

    /// Builds the boxes of the vertices and edges the rings of node `n` of `side` own into
    /// `built`.
    fn build_vertices_and_edges(&self, side: Side, n: u32, built: &mut Built) {
        let (owners, rings) = self.rings(side, n);
        let f = owners.features;
        built.vertices.clear();
        for &v in &f.vertices.items()[f.vertices.span(rings.clone())] {
            built.vertices.push(self.boxed(side, &[v]));
        }
        built.edges.clear();
        for e in &f.edges.items()[f.edges.span(rings)] {
            built.edges.push(self.boxed(side, e));
        }
    }

    /// The box of `vertices` of `side` as the test sees them.
    #[inline(always)]
    fn boxed(&self, side: Side, vertices: &[u32]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for &v in vertices {
            self.test.grow(side, v, &mut b);
        }
        b
    }

    /// The primitive pairs of a node of one mesh with itself, `triangles` holding all of `p`'s
    /// with their corners.
    fn own(
        &self,
        w: &mut Worker<T::Found>,
        p: &Primitives,
        triangles: &Subset<[u32; 3]>,
        limit: usize,
    ) -> bool {
        let vertices = (p.vertex_boxes, p.vertices);
        if self.vertex_faces(w, Side::A, vertices, (p, triangles), limit) {
            return true;
        }
        let d = self.test.reach();
        let (boxes, ends) = (p.edge_boxes, p.edges);
        for n in 0..ends.len() {
            let ea = ends[n];
            let later = (&boxes[n + 1..], &ends[n + 1..]);
            if each_near(
                &boxes[n],
                d,
                later,
                |eb| share(ea, eb),
                |j| self.edge_pair(w, ea, ends[n + 1 + j], limit),
            ) {
                return true;
            }
        }
        false
    }

    /// The primitive pairs of two nodes, of two meshes or of one mesh with no ring in common,
    /// from those each keeps.
    fn apart(
        &self,
        w: &mut Worker<T::Found>,
        (pa, ka): (&Primitives, &Kept),
        (pb, kb): (&Primitives, &Kept),
        limit: usize,
    ) -> bool {
        let (va, vb) = (&ka.vertices, &kb.vertices);
        if self.vertex_faces(
            w,
            Side::A,
            (va.boxes(), va.vertices()),
            (pb, &kb.triangles),
            limit,
        ) || self.vertex_faces(
            w,
            Side::B,
            (vb.boxes(), vb.vertices()),
            (pa, &ka.triangles),
            limit,
        ) {
            return true;
        }
        let (d, one) = (self.test.reach(), self.one_mesh);
        let ends_b = kb.edges.vertices();
        let b_side = (kb.edges.boxes(), ends_b);
        for (&ea, boxed) in ka.edges.vertices().iter().zip(ka.edges.boxes()) {
            if each_near(
                boxed,
                d,
                b_side,
                |eb| one & share(ea, eb),
                |j| self.edge_pair(w, ea, ends_b[j], limit),
            ) {
                return true;
            }
        }
        false
    }

    /// The vertices `vertices` of `side` (their boxes and indices) against the triangles
    /// `triangles` of `pt`, of the other side (of one mesh, those that do not contain the
    /// vertex), each pair whose boxes come within the reach.
    fn vertex_faces(
        &self,
        w: &mut Worker<T::Found>,
        side: Side,
        (v_boxes, v_ids): (&[Aabb], &[u32]),
        (pt, triangles): (&Primitives, &Subset<[u32; 3]>),
        limit: usize,
    ) -> bool {
        let (d, one) = (self.test.reach(), self.one_mesh);
        let other = match side {
            Side::A => Side::B,
            Side::B => Side::A,
        };
        let (at_t, corners_t) = (triangles.at(), triangles.vertices());
        let t_side = (triangles.boxes(), corners_t);
        for (&v, boxed) in v_ids.iter().zip(v_boxes) {
            let contains = |c: &[u32; 3]| one & ((c[0] == v) | (c[1] == v) | (c[2] == v));
            if each_near(boxed, d, t_side, contains, |j| {
                let index = pt.triangles[at_t[j] as usize];
                let key = if one || side == Side::A {
                    (ImpactKind::VertexFace, v, 0, index, 0)
                } else {
                    (ImpactKind::FaceVertex, index, 0, v, 0)
                };
                let kind = Primitive::VertexFace;
                self.run(
                    w,
                    PrimitivePair {
                        kind,
                        first: side,
                        pa: [v],
                        second: other,
                        pb: corners_t[j],
                        key,
                    },
                    limit,
                )
            }) {
                return true;
            }
        }
        false
    }

    /// Edge `ea` of `a` against edge `eb` of `b` (of one mesh, sharing no vertex).
    #[inline]
    fn edge_pair(
        &self,
        w: &mut Worker<T::Found>,
        ea: [u32; 2],
        eb: [u32; 2],
        limit: usize,
    ) -> bool {
        let one = self.one_mesh;
        // Tested in the order reported, so that a test's rounding does not depend on which
        // node came first.
        let (e1, e2) = if one && eb < ea { (eb, ea) } else { (ea, eb) };
        let key = (ImpactKind::EdgeEdge, e1[0], e1[1], e2[0], e2[1]);
        let pair = PrimitivePair {
            kind: Primitive::EdgeEdge,
            first: Side::A,
            pa: e1,
            second: Side::B,
            pb: e2,
            key,
        };
        self.run(w, pair, limit)
    }

    /// One test, counted, and its result kept.
    #[inline]
    fn run<const N: usize, const M: usize>(
        &self,
        w: &mut Worker<T::Found>,
        pair: PrimitivePair<N, M>,
        limit: usize,
    ) -> bool {
        w.primitive_tests += 1;
        match self.test.test(pair, w.best.as_ref()) {
            Some(found) => self.test.keep(w, found, limit),
            None => false,
        }
    }
}
