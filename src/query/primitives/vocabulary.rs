//! What the queries on primitive pairs share: which side a primitive is on, the order of their
//! results, each mesh's owners of primitives, the test a query makes of a primitive pair, and a
//! thread's findings.

use super::ImpactKind;
use super::subsets::Scratch;
use crate::geometry::Primitive;
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
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

    /// Which boxes [`PrimitiveTest::grow`] makes now: a number that changes whenever they
    /// become tighter (a test that shrinks them as it finds results), never looser. The boxes
    /// are computed once per query, marked with this; a node pair whose test has moved on
    /// builds its own, tighter boxes (the older ones still hold what it needs, but keep
    /// more).
    #[inline(always)]
    fn box_epoch(&self) -> u64 {
        0
    }

    /// How near primitives must come to be tested: their boxes are compared within this
    /// distance ([`Aabb::within`]). Zero by default: boxes that meet.
    #[inline(always)]
    fn reach(&self) -> f64 {
        0.0
    }

    /// The test of `pair`. Called for every pair of primitives whose boxes (as
    /// [`PrimitiveTest::grow`] makes them) come within [`PrimitiveTest::reach`] of each other,
    /// and only for those or pairs farther by no more than the rounding of that comparison.
    /// `best` is this thread's [`Worker::best`].
    fn test<const N: usize, const M: usize>(
        &self,
        pair: PrimitivePair<N, M>,
        best: Option<&Self::Found>,
    ) -> Option<Self::Found>;

    /// Keeps what a test found. Returns whether the narrow phase must stop: `limit` results
    /// held, or the result cannot grow.
    #[inline]
    fn keep(&self, w: &mut Worker<Self::Found>, found: Self::Found, limit: usize) -> bool {
        w.push(found, limit)
    }
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
    pub(super) scratch: Option<Box<Scratch>>,
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

/// A pair of primitives to test: the vertices `pa` of side `first` against `pb` of side
/// `second` (a vertex and a triangle's corners, or two edges' ends), reported under `key`.
#[derive(Clone, Copy)]
pub(crate) struct PrimitivePair<const N: usize, const M: usize> {
    pub kind: Primitive,
    pub first: Side,
    pub pa: [u32; N],
    pub second: Side,
    pub pb: [u32; M],
    pub key: Key,
}

impl<const N: usize, const M: usize> PrimitivePair<N, M> {
    /// The pair's points in one array, as the geometric tests take them: `pa` of `first`'s
    /// positions `a`, then `pb` of `second`'s positions `b`.
    #[inline(always)]
    pub fn points(&self, a: &[Point], b: &[Point]) -> [Point; 4] {
        let mut p = [[0.0; 3]; 4];
        for (i, &v) in self.pa.iter().enumerate() {
            p[i] = a[v as usize];
        }
        for (i, &v) in self.pb.iter().enumerate() {
            p[N + i] = b[v as usize];
        }
        p
    }
}
