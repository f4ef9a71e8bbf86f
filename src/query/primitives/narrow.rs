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
    /// triangle's corners, or two edges' ends), to be reported under `key`. Called only for
    /// primitives whose boxes (as [`PrimitiveTest::grow`] makes them) come within
    /// [`PrimitiveTest::reach`] of each other.
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

/// A primitive of a node's rings (a vertex, a triangle with its corners, or an edge), with
/// its box.
#[derive(Clone, Copy, Debug, Default)]
struct Boxed<I> {
    pub item: I,
    pub bounds: Aabb,
}

/// A triangle and its corners.
#[derive(Clone, Copy, Debug, Default)]
struct Triangle {
    pub index: u32,
    pub corners: [u32; 3],
}

/// The primitives the rings of one node own, each with its box.
#[derive(Debug, Default)]
struct Owned {
    vertices: Vec<Boxed<u32>>,
    triangles: Vec<Boxed<Triangle>>,
    edges: Vec<Boxed<[u32; 2]>>,
}

impl Owned {
    fn heap_bytes(&self) -> usize {
        crate::csr::heap_bytes(&self.vertices)
            + crate::csr::heap_bytes(&self.triangles)
            + crate::csr::heap_bytes(&self.edges)
    }
}

/// One thread's scratch space and findings.
#[derive(Debug)]
pub(crate) struct Worker<F> {
    /// Results, in the order the node pairs were taken.
    pub out: Vec<F>,
    /// For each chunk of node pairs this worker took: (chunk, start, end) in `out`.
    pub done: Vec<(usize, usize, usize)>,
    /// The first worker's: scratch space for sorting the joined results.
    pub counts: Vec<usize>,
    owned_a: Owned,
    owned_b: Owned,
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
            owned_a: Owned::default(),
            owned_b: Owned::default(),
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
            + self.owned_a.heap_bytes()
            + self.owned_b.heap_bytes()
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
        let mut owned_a = std::mem::take(&mut w.owned_a);
        let mut owned_b = std::mem::take(&mut w.owned_b);
        let stopped = if self.one_mesh && na == nb {
            self.gather(Side::A, na, tables.map(|t| t.a), None, &mut owned_a);
            self.own(w, &owned_a, limit)
        } else {
            self.apart(tables, w, na, nb, &mut owned_a, &mut owned_b, limit)
        };
        w.owned_a = owned_a;
        w.owned_b = owned_b;
        stopped
    }

    /// The primitives the rings of node `n` of `side` own, each with its box (from `table`, or
    /// built), into `out`: those whose boxes come within the test's reach of `near`, or all.
    fn gather(
        &self,
        side: Side,
        n: u32,
        table: Option<&OwnedBoxes>,
        near: Option<&Aabb>,
        out: &mut Owned,
    ) {
        self.gather_triangles(side, n, table, near, out);
        self.gather_vertices_and_edges(side, n, table, near, out);
    }

    /// The triangles of [`Narrow::gather`]; returns the box of those kept.
    fn gather_triangles(
        &self,
        side: Side,
        n: u32,
        table: Option<&OwnedBoxes>,
        near: Option<&Aabb>,
        out: &mut Owned,
    ) -> Aabb {
        let (owners, rings) = self.rings(side, n);
        let f = owners.features;
        let d = self.test.reach();
        let tris = owners.mesh.triangles();
        let mut all = Aabb::EMPTY;
        out.triangles.clear();
        for i in f.triangles.span(rings) {
            let index = f.triangles.items()[i];
            let corners = tris[index as usize];
            let bounds = match table {
                Some(t) => t.triangles[i],
                None => self.boxed(side, &corners),
            };
            if near.is_none_or(|o| bounds.within(o, d)) {
                all.merge(&bounds);
                let item = Triangle { index, corners };
                out.triangles.push(Boxed { item, bounds });
            }
        }
        all
    }

    /// The vertices and edges of [`Narrow::gather`].
    fn gather_vertices_and_edges(
        &self,
        side: Side,
        n: u32,
        table: Option<&OwnedBoxes>,
        near: Option<&Aabb>,
        out: &mut Owned,
    ) {
        let (owners, rings) = self.rings(side, n);
        let f = owners.features;
        let d = self.test.reach();
        let keep = |b: &Aabb| near.is_none_or(|o| b.within(o, d));
        out.vertices.clear();
        for i in f.vertices.span(rings.clone()) {
            let item = f.vertices.items()[i];
            let bounds = match table {
                Some(t) => t.vertices[i],
                None => self.boxed(side, &[item]),
            };
            if keep(&bounds) {
                out.vertices.push(Boxed { item, bounds });
            }
        }
        out.edges.clear();
        for i in f.edges.span(rings) {
            let item = f.edges.items()[i];
            let bounds = match table {
                Some(t) => t.edges[i],
                None => self.boxed(side, &item),
            };
            if keep(&bounds) {
                out.edges.push(Boxed { item, bounds });
            }
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

    /// The mesh of `side` and the rings below its node `n`.
    #[inline(always)]
    fn rings(&self, side: Side, n: u32) -> (&Owners<'_>, std::ops::Range<usize>) {
        let owners = match side {
            Side::A => &self.a,
            Side::B => &self.b,
        };
        let node = &owners.mesh.tree().nodes[n as usize];
        (owners, node.ring_start as usize..node.ring_end as usize)
    }

    /// The primitive pairs of a node of one mesh with itself.
    fn own(&self, w: &mut Worker<T::Found>, owned: &Owned, limit: usize) -> bool {
        if self.vertex_faces(w, &owned.vertices, Side::A, &owned.triangles, limit) {
            return true;
        }
        let d = self.test.reach();
        for (i, ea) in owned.edges.iter().enumerate() {
            for eb in &owned.edges[i + 1..] {
                if ea.bounds.within(&eb.bounds, d) && self.edge_pair(w, ea.item, eb.item, limit) {
                    return true;
                }
            }
        }
        false
    }

    /// The primitive pairs of node `na` of `a` and `nb` of `b`, two meshes' or one mesh's
    /// with no ring in common, gathered into `owned_a` and `owned_b`.
    #[allow(clippy::too_many_arguments)]
    fn apart(
        &self,
        tables: Option<Tables>,
        w: &mut Worker<T::Found>,
        na: u32,
        nb: u32,
        owned_a: &mut Owned,
        owned_b: &mut Owned,
        limit: usize,
    ) -> bool {
        let d = self.test.reach();
        // A leaf's ring owns about 7 triangles and 10 edges: each side keeps what comes near
        // the other node before the pairs are formed (most does not).
        if let Some(t) = tables {
            let box_a = t.a.of_rings(self.rings(Side::A, na).1);
            let box_b = t.b.of_rings(self.rings(Side::B, nb).1);
            if !box_a.within(&box_b, d) {
                return false;
            }
            self.gather(Side::A, na, Some(t.a), Some(&box_b), owned_a);
            self.gather(Side::B, nb, Some(t.b), Some(&box_a), owned_b);
        } else {
            // Boxes built here, the triangles' first: they give each node's box.
            let box_a = self.gather_triangles(Side::A, na, None, None, owned_a);
            let box_b = self.gather_triangles(Side::B, nb, None, None, owned_b);
            if !box_a.within(&box_b, d) {
                return false;
            }
            owned_a.triangles.retain(|x| x.bounds.within(&box_b, d));
            owned_b.triangles.retain(|x| x.bounds.within(&box_a, d));
            self.gather_vertices_and_edges(Side::A, na, None, Some(&box_b), owned_a);
            self.gather_vertices_and_edges(Side::B, nb, None, Some(&box_a), owned_b);
        }
        if self.vertex_faces(w, &owned_a.vertices, Side::A, &owned_b.triangles, limit)
            || self.vertex_faces(w, &owned_b.vertices, Side::B, &owned_a.triangles, limit)
        {
            return true;
        }
        for ea in &owned_a.edges {
            for eb in &owned_b.edges {
                if ea.bounds.within(&eb.bounds, d) && self.edge_pair(w, ea.item, eb.item, limit) {
                    return true;
                }
            }
        }
        false
    }

    /// The vertices `vertices` of `side` against the triangles `triangles` of the other side
    /// (of one mesh, those that do not contain the vertex), each pair whose boxes come within
    /// the reach.
    fn vertex_faces(
        &self,
        w: &mut Worker<T::Found>,
        vertices: &[Boxed<u32>],
        side: Side,
        triangles: &[Boxed<Triangle>],
        limit: usize,
    ) -> bool {
        let (d, one) = (self.test.reach(), self.one_mesh);
        let other = match side {
            Side::A => Side::B,
            Side::B => Side::A,
        };
        for v in vertices {
            for t in triangles {
                let Triangle { index, corners } = t.item;
                if v.bounds.within(&t.bounds, d) && !(one && corners.contains(&v.item)) {
                    let key = if one || side == Side::A {
                        (ImpactKind::VertexFace, v.item, 0, index, 0)
                    } else {
                        (ImpactKind::FaceVertex, index, 0, v.item, 0)
                    };
                    let kind = Primitive::VertexFace;
                    if self.run(w, kind, side, [v.item], other, corners, key, limit) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Edge `ea` of `a` against edge `eb` of `b`; of one mesh, unless they share a vertex.
    #[inline]
    fn edge_pair(
        &self,
        w: &mut Worker<T::Found>,
        ea: [u32; 2],
        eb: [u32; 2],
        limit: usize,
    ) -> bool {
        let one = self.one_mesh;
        if one && (eb.contains(&ea[0]) || eb.contains(&ea[1])) {
            return false;
        }
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
