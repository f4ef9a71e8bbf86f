//! One node pair's primitive pairs: the vertices, edges and triangles its rings own (the rule of
//! [`crate::mesh::Features`]), each with its box; every vertex-face and edge-edge pair whose
//! boxes come within the test's reach is given to the test, once.

use super::ImpactKind;
use super::boxes::OwnedBoxes;
use crate::geometry::Primitive;
use crate::geometry::aabb::Aabb;
use crate::mesh::{Features, Mesh};

/// Which mesh of a query a primitive belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    A,
    B,
}

/// The order of a result: `(kind, a0, a1, b0, b1)`, with the indices of [`ImpactKind`].
pub(crate) type Key = (ImpactKind, u32, u32, u32, u32);

/// One mesh of a query and what its rings own.
#[derive(Clone, Copy)]
pub(crate) struct Owners<'m> {
    pub mesh: &'m Mesh,
    pub features: &'m Features,
}

impl<'m> Owners<'m> {
    pub fn new(mesh: &'m Mesh) -> Owners<'m> {
        Owners {
            mesh,
            features: mesh.features(),
        }
    }
}

/// What a query computes on a primitive pair, and where its primitives are.
pub(crate) trait PrimitiveTest: Sync {
    /// What a pair that passes gives.
    type Found: Copy + Send;

    /// Grows `b` by vertex `v` of `side` as the test sees it (its sweep, its placed position).
    fn grow(&self, side: Side, v: u32, b: &mut Aabb);

    /// Do the boxes [`PrimitiveTest::grow`] makes stay the same for the whole query? Then
    /// they are computed once per query; otherwise (a test that shrinks them as it finds
    /// results) for each node pair.
    #[inline(always)]
    fn fixed_boxes(&self) -> bool {
        true
    }

    /// How near primitives must come to be tested: their boxes are compared within this
    /// distance ([`Aabb::within`]). Zero by default: boxes that meet.
    #[inline(always)]
    fn reach(&self) -> f64 {
        0.0
    }

    /// The test of the points `pa` of `first` against `pb` of `second` (a vertex and a
    /// triangle's corners, or two edges' ends), to be reported under `key`. Called for every
    /// pair of primitives whose boxes (as [`PrimitiveTest::grow`] makes them) come within
    /// [`PrimitiveTest::reach`] of each other, and only for those or pairs farther by no more
    /// than the rounding of that comparison.
    fn test<const N: usize, const M: usize>(
        &self,
        kind: Primitive,
        first: Side,
        pa: [u32; N],
        second: Side,
        pb: [u32; M],
        key: Key,
    ) -> Option<Self::Found>;

    /// Keeps what a test found. Returns whether the narrow phase must stop: `limit` results
    /// held, or the result cannot grow.
    #[inline]
    fn keep(&self, w: &mut Worker<Self::Found>, found: Self::Found, limit: usize) -> bool {
        w.push(found, limit)
    }
}

/// One node's primitives, each with its box, in the order of the node's rings: the positions
/// `k` of each list are one primitive, its box at `k` of the boxes.
#[derive(Clone, Copy)]
struct Primitives<'p> {
    triangle_boxes: &'p [Aabb],
    triangles: &'p [u32],
    vertex_boxes: &'p [Aabb],
    vertices: &'p [u32],
    edge_boxes: &'p [Aabb],
    edges: &'p [[u32; 2]],
}

/// Some primitives of a [`Primitives`] list: their positions in it, their boxes and their
/// vertices, the first `len` of each list (the lists only grow, so that keeping writes no more
/// than it keeps).
#[derive(Debug, Default)]
struct Subset<I> {
    at: Vec<u32>,
    boxes: Vec<Aabb>,
    vertices: Vec<I>,
    len: usize,
}

impl<I: Copy + Default> Subset<I> {
    /// Keeps the positions `k` of `boxes` whose box comes within `d` of `near` (all, without
    /// `near`; [`Aabb::reach`] may keep a few more, by rounding), in order, with their boxes
    /// and `vertices(k)`. Written without a branch on the box test: about half are kept, in no
    /// pattern a predictor learns on a scanned mesh, and a mispredicted branch cost more than
    /// the test.
    #[inline(always)]
    fn keep(&mut self, boxes: &[Aabb], vertices: impl Fn(usize) -> I, near: Option<&Aabb>, d: f64) {
        let n = boxes.len();
        if self.at.len() < n {
            self.at.resize(n, 0);
            self.boxes.resize(n, Aabb::EMPTY);
            self.vertices.resize(n, I::default());
        }
        // Slices, so that the lists' pointers are not reloaded after every store.
        let (at, kept, of) = (
            &mut self.at[..n],
            &mut self.boxes[..n],
            &mut self.vertices[..n],
        );
        let mut m = 0;
        match near {
            None => {
                for (k, x) in at.iter_mut().enumerate() {
                    *x = k as u32;
                }
                m = n;
            }
            Some(o) => {
                let o = o.reach(d);
                for (k, b) in boxes.iter().enumerate() {
                    at[m] = k as u32;
                    m += b.meets(&o) as usize;
                }
            }
        }
        // Then the boxes and vertices of those kept only.
        for ((&k, b), v) in at[..m].iter().zip(&mut kept[..m]).zip(&mut of[..m]) {
            *b = boxes[k as usize];
            *v = vertices(k as usize);
        }
        self.len = m;
    }

    /// The positions kept.
    #[inline(always)]
    fn at(&self) -> &[u32] {
        &self.at[..self.len]
    }

    /// Their boxes.
    #[inline(always)]
    fn boxes(&self) -> &[Aabb] {
        &self.boxes[..self.len]
    }

    /// Their vertices.
    #[inline(always)]
    fn vertices(&self) -> &[I] {
        &self.vertices[..self.len]
    }

    fn heap_bytes(&self) -> usize {
        use crate::csr::heap_bytes;
        heap_bytes(&self.at) + heap_bytes(&self.boxes) + heap_bytes(&self.vertices)
    }
}

/// What one node keeps of its primitives for a node pair.
#[derive(Debug, Default)]
struct Kept {
    /// With their corners.
    triangles: Subset<[u32; 3]>,
    vertices: Subset<u32>,
    edges: Subset<[u32; 2]>,
}

impl Kept {
    /// Keeps the primitives of `p`, whose triangles' corners are `corners`, whose boxes come
    /// within `d` of `near` (all, without it).
    #[inline(always)]
    fn keep(&mut self, p: &Primitives, corners: &[[u32; 3]], near: Option<&Aabb>, d: f64) {
        self.keep_triangles(p, corners, near, d);
        self.vertices
            .keep(p.vertex_boxes, |k| p.vertices[k], near, d);
        self.edges.keep(p.edge_boxes, |k| p.edges[k], near, d);
    }

    /// [`Kept::keep`]'s triangles alone, with their corners.
    #[inline(always)]
    fn keep_triangles(
        &mut self,
        p: &Primitives,
        corners: &[[u32; 3]],
        near: Option<&Aabb>,
        d: f64,
    ) {
        let of_triangle = |k: usize| corners[p.triangles[k] as usize];
        self.triangles.keep(p.triangle_boxes, of_triangle, near, d);
    }
}

/// Boxes built for one node pair, when the query's boxes change as it goes (no table).
#[derive(Debug, Default)]
struct Built {
    triangles: Vec<Aabb>,
    vertices: Vec<Aabb>,
    edges: Vec<Aabb>,
}

/// A worker's scratch space for one node pair, per side.
#[derive(Debug, Default)]
struct Scratch {
    kept: [Kept; 2],
    built: [Built; 2],
}

impl Scratch {
    fn heap_bytes(&self) -> usize {
        use crate::csr::heap_bytes;
        let kept =
            |k: &Kept| k.triangles.heap_bytes() + k.vertices.heap_bytes() + k.edges.heap_bytes();
        let built =
            |b: &Built| heap_bytes(&b.triangles) + heap_bytes(&b.vertices) + heap_bytes(&b.edges);
        self.kept.iter().map(kept).sum::<usize>() + self.built.iter().map(built).sum::<usize>()
    }
}

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

/// One thread's scratch space and findings.
// Aligned apart, so that two threads' counters and result lengths never share a cache line
// (two lines: some processors fetch lines in pairs).
#[derive(Debug)]
#[repr(align(128))]
pub(crate) struct Worker<F> {
    /// Results, in the order the node pairs were taken.
    pub out: Vec<F>,
    /// For each chunk of node pairs this worker took: (chunk, start, end) in `out`.
    pub done: Vec<(usize, usize, usize)>,
    /// The first worker's: scratch space for sorting the joined results.
    pub counts: Vec<usize>,
    /// Boxed, so that taking it out for a node pair moves a pointer, not the lists.
    scratch: Option<Box<Scratch>>,
    /// The one result kept, when a query keeps only the best.
    pub best: Option<F>,
    pub primitive_tests: u64,
    /// Could `out` not grow? (The bytes it asked for.)
    pub out_of_memory: Option<usize>,
}

impl<F> Default for Worker<F> {
    fn default() -> Worker<F> {
        Worker {
            out: Vec::new(),
            done: Vec::new(),
            counts: Vec::new(),
            scratch: None,
            best: None,
            primitive_tests: 0,
            out_of_memory: None,
        }
    }
}

impl<F> Worker<F> {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        crate::csr::heap_bytes(&self.out)
            + crate::csr::heap_bytes(&self.done)
            + crate::csr::heap_bytes(&self.counts)
            + self
                .scratch
                .as_ref()
                .map_or(0, |s| std::mem::size_of::<Scratch>() + s.heap_bytes())
    }

    /// Starts a query.
    pub fn begin(&mut self) {
        self.out.clear();
        self.done.clear();
        self.best = None;
        self.primitive_tests = 0;
        self.out_of_memory = None;
    }

    /// Appends `found`. Returns whether `out` holds `limit` results, or cannot grow.
    #[inline]
    pub fn push(&mut self, found: F, limit: usize) -> bool {
        if self.out.len() == self.out.capacity() {
            let extra = self.out.capacity().max(256);
            if self.out.try_reserve(extra).is_err() {
                self.out_of_memory = Some((self.out.capacity() + extra) * std::mem::size_of::<F>());
                return true;
            }
        }
        self.out.push(found);
        self.out.len() >= limit
    }
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
/// both sides of a self query).
#[derive(Clone, Copy)]
pub(crate) struct Tables<'b> {
    pub a: &'b OwnedBoxes,
    pub b: &'b OwnedBoxes,
}

impl<T: PrimitiveTest> Narrow<'_, T> {
    /// Tests the primitive pairs of node `na` of `a` and `nb` of `b` (of one mesh, `na <= nb`,
    /// the two equal or with no ring in common) into `w`, stopping once `w.out` holds `limit`
    /// results. Returns whether it stopped. The primitives' boxes come from `tables`, filled
    /// for both nodes, or are built here when the test's boxes change during the query
    /// ([`PrimitiveTest::fixed_boxes`]).
    pub fn node_pair(
        &self,
        tables: Option<Tables>,
        w: &mut Worker<T::Found>,
        na: u32,
        nb: u32,
        limit: usize,
    ) -> bool {
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
                self.run(w, kind, side, [v], other, corners_t[j], key, limit)
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
        self.run(w, Primitive::EdgeEdge, Side::A, e1, Side::B, e2, key, limit)
    }

    /// One test, counted, and its result kept.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn run<const N: usize, const M: usize>(
        &self,
        w: &mut Worker<T::Found>,
        kind: Primitive,
        first: Side,
        pa: [u32; N],
        second: Side,
        pb: [u32; M],
        key: Key,
        limit: usize,
    ) -> bool {
        w.primitive_tests += 1;
        match self.test.test(kind, first, pa, second, pb, key) {
            Some(found) => self.test.keep(w, found, limit),
            None => false,
        }
    }
}
