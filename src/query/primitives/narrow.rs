//! One node pair's primitive pairs: the triangles its rings own, filtered by box, then every
//! vertex-face and edge-edge pair those triangles own, each given to the test once.

use super::ImpactKind;
use crate::geometry::Primitive;
use crate::geometry::aabb::Aabb;
use crate::mesh::Mesh;

/// Which mesh of a query a primitive belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    A,
    B,
}

/// The order of a result: `(kind, a0, a1, b0, b1)`, with the indices of [`ImpactKind`].
pub(crate) type Key = (ImpactKind, u32, u32, u32, u32);

/// One mesh of a query and its ownership tables.
#[derive(Clone, Copy)]
pub(crate) struct Owners<'m> {
    pub mesh: &'m Mesh,
    pub owner_ring: &'m [u32],
    pub owned: &'m [u8],
}

impl<'m> Owners<'m> {
    pub fn new(mesh: &'m Mesh) -> Owners<'m> {
        let f = mesh.features();
        Owners {
            mesh,
            owner_ring: &f.owner_ring,
            owned: &f.owned,
        }
    }
}

/// What a query computes on a primitive pair, and where its primitives are.
pub(crate) trait PrimitiveTest: Sync {
    /// What a pair that passes gives.
    type Found: Copy + Send;

    /// Grows `b` by vertex `v` of `side` as the test sees it (its sweep, its placed position).
    fn grow(&self, side: Side, v: u32, b: &mut Aabb);

    /// The box of a triangle of side `a` as it is compared with side `b`'s boxes (widened by a
    /// distance, say): pairs whose boxes so compared are apart are not tested.
    #[inline(always)]
    fn reach(&self, b: Aabb) -> Aabb {
        b
    }

    /// The test of the points `pa` of `first` against `pb` of `second` (a vertex and a
    /// triangle's corners, or two edges' ends), to be reported under `key`.
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

/// A triangle owned by a ring, with its box.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Boxed {
    pub triangle: u32,
    pub bounds: Aabb,
}

/// One thread's scratch space and findings.
#[derive(Debug)]
pub(crate) struct Worker<F> {
    /// Results, in the order the node pairs were taken.
    pub out: Vec<F>,
    /// For each chunk of node pairs this worker took: (chunk, start, end) in `out`.
    pub done: Vec<(usize, usize, usize)>,
    ring_a: Vec<Boxed>,
    ring_b: Vec<Boxed>,
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
            ring_a: Vec::new(),
            ring_b: Vec::new(),
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
            + crate::csr::heap_bytes(&self.ring_a)
            + crate::csr::heap_bytes(&self.ring_b)
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

impl<T: PrimitiveTest> Narrow<'_, T> {
    /// Tests the primitive pairs of node `na` of `a` and `nb` of `b` (of one mesh, `na <= nb`,
    /// the two equal or with no ring in common) into `w`, stopping once `w.out` holds `limit`
    /// results. Returns whether it stopped.
    pub fn node_pair(&self, w: &mut Worker<T::Found>, na: u32, nb: u32, limit: usize) -> bool {
        let mut ring_a = std::mem::take(&mut w.ring_a);
        let mut ring_b = std::mem::take(&mut w.ring_b);
        let box_a = self.boxes(Side::A, na, &mut ring_a);
        let mut stopped = false;
        if self.one_mesh && na == nb {
            'pairs: for (i, ta) in ring_a.iter().enumerate() {
                let reach = self.test.reach(ta.bounds);
                for tb in &ring_a[i + 1..] {
                    if reach.meets(&tb.bounds)
                        && self.triangle_pair(w, ta.triangle, tb.triangle, limit)
                    {
                        stopped = true;
                        break 'pairs;
                    }
                }
            }
        } else {
            let box_b = self.boxes(Side::B, nb, &mut ring_b);
            let box_a = self.test.reach(box_a);
            if box_a.meets(&box_b) {
                'pairs: for ta in &ring_a {
                    let reach = self.test.reach(ta.bounds);
                    if !reach.meets(&box_b) {
                        continue;
                    }
                    for tb in &ring_b {
                        if reach.meets(&tb.bounds)
                            && self.triangle_pair(w, ta.triangle, tb.triangle, limit)
                        {
                            stopped = true;
                            break 'pairs;
                        }
                    }
                }
            }
        }
        w.ring_a = ring_a;
        w.ring_b = ring_b;
        stopped
    }

    /// The triangles the rings of node `n` of `side` own, each with its box, into `out`;
    /// returns the box of them all.
    fn boxes(&self, side: Side, n: u32, out: &mut Vec<Boxed>) -> Aabb {
        let owners = match side {
            Side::A => &self.a,
            Side::B => &self.b,
        };
        let node = &owners.mesh.tree().nodes[n as usize];
        let (rings, tris) = (owners.mesh.rings(), owners.mesh.triangles());
        out.clear();
        let mut all = Aabb::EMPTY;
        for r in node.ring_start..node.ring_end {
            for &t in rings.triangles.row(r as usize) {
                if owners.owner_ring[t as usize] != r {
                    continue;
                }
                let mut b = Aabb::EMPTY;
                for &v in &tris[t as usize] {
                    self.test.grow(side, v, &mut b);
                }
                all.merge(&b);
                out.push(Boxed {
                    triangle: t,
                    bounds: b,
                });
            }
        }
        all
    }

    /// The primitive pairs of triangle `ta` of `a` and `tb` of `b` that these triangles own.
    fn triangle_pair(&self, w: &mut Worker<T::Found>, ta: u32, tb: u32, limit: usize) -> bool {
        let (a, b, one) = (&self.a, &self.b, self.one_mesh);
        let (ca, cb) = (
            a.mesh.triangles()[ta as usize],
            b.mesh.triangles()[tb as usize],
        );
        let (oa, ob) = (a.owned[ta as usize], b.owned[tb as usize]);
        for (k, &v) in ca.iter().enumerate() {
            if oa & (1 << k) != 0 && !(one && cb.contains(&v)) {
                let key = (ImpactKind::VertexFace, v, 0, tb, 0);
                if self.run(
                    w,
                    Primitive::VertexFace,
                    Side::A,
                    [v],
                    Side::B,
                    cb,
                    key,
                    limit,
                ) {
                    return true;
                }
            }
        }
        for (k, &v) in cb.iter().enumerate() {
            if ob & (1 << k) != 0 && !(one && ca.contains(&v)) {
                let key = if one {
                    (ImpactKind::VertexFace, v, 0, ta, 0)
                } else {
                    (ImpactKind::FaceVertex, ta, 0, v, 0)
                };
                if self.run(
                    w,
                    Primitive::VertexFace,
                    Side::B,
                    [v],
                    Side::A,
                    ca,
                    key,
                    limit,
                ) {
                    return true;
                }
            }
        }
        for i in 0..3 {
            if oa & (1 << (3 + i)) == 0 {
                continue;
            }
            let ea = ordered(ca[i], ca[(i + 1) % 3]);
            for j in 0..3 {
                if ob & (1 << (3 + j)) == 0 {
                    continue;
                }
                let eb = ordered(cb[j], cb[(j + 1) % 3]);
                if one && (eb.contains(&ea[0]) || eb.contains(&ea[1])) {
                    continue;
                }
                // Tested in the order reported, so that a test's rounding does not depend on
                // which triangle came first.
                let (e1, e2) = if one && eb < ea { (eb, ea) } else { (ea, eb) };
                let key = (ImpactKind::EdgeEdge, e1[0], e1[1], e2[0], e2[1]);
                if self.run(w, Primitive::EdgeEdge, Side::A, e1, Side::B, e2, key, limit) {
                    return true;
                }
            }
        }
        false
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

/// An edge's ends, lower first.
#[inline]
fn ordered(u: u32, v: u32) -> [u32; 2] {
    [u.min(v), u.max(v)]
}
