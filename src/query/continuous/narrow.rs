//! The narrow phase of continuous collision: from a pair of leaves whose volumes overlap over
//! the motion, the vertex-face and edge-edge pairs of their rings' triangles, each tested once
//! (the owners' rule of [`crate::mesh::Features`]), after boxes of the triangles' sweeps.

use super::impacts::{Impact, ImpactKind};
use crate::geometry::aabb::Aabb;
use crate::geometry::ccd::exact::Primitive;
use crate::geometry::ccd::{CcdMode, time_of_impact};
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;
use std::sync::atomic::{AtomicU64, Ordering};

/// One mesh of a continuous query: its triangles, its motion, its ownership tables.
#[derive(Clone, Copy)]
pub(crate) struct Moving<'m> {
    pub mesh: &'m Mesh,
    pub start: &'m [Point],
    pub end: &'m [Point],
    pub owner_ring: &'m [u32],
    pub owned: &'m [u8],
}

impl<'m> Moving<'m> {
    pub fn new(mesh: &'m Mesh) -> Moving<'m> {
        let f = mesh.features();
        Moving {
            mesh,
            start: mesh.start_positions(),
            end: mesh.positions(),
            owner_ring: &f.owner_ring,
            owned: &f.owned,
        }
    }
}

/// What every thread of a query shares.
pub(crate) struct Job<'m, 'q> {
    pub a: Moving<'m>,
    pub b: Moving<'m>,
    /// Both sides are one mesh.
    pub one_mesh: bool,
    pub mode: CcdMode,
    /// Keep only the earliest impact, and skip what cannot come before it.
    pub earliest_only: bool,
    /// The earliest impact time found so far by any thread (the bits of a non-negative double,
    /// ordered as the doubles are), when `earliest_only`.
    pub best: &'q AtomicU64,
}

/// A triangle owned by a ring, with the box of its sweep.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Swept {
    pub triangle: u32,
    pub bounds: Aabb,
}

/// One thread's scratch space and findings.
#[derive(Debug, Default)]
pub(crate) struct Worker {
    /// Impacts found, in the order the leaf pairs were taken.
    pub out: Vec<Impact>,
    /// For each chunk of leaf pairs this worker took: (chunk, start, end) in `out`.
    pub done: Vec<(usize, usize, usize)>,
    pub ring_a: Vec<Swept>,
    pub ring_b: Vec<Swept>,
    /// The earliest impact found, when only that is wanted.
    pub best: Option<Impact>,
    pub primitive_tests: u64,
    /// Could `out` not grow? (The bytes it asked for.)
    pub out_of_memory: Option<usize>,
}

impl Worker {
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
}

impl Job<'_, '_> {
    /// The time up to which contacts are still wanted: the whole step, or (earliest only) up to
    /// the earliest found so far.
    #[inline]
    fn cut(&self) -> f64 {
        if self.earliest_only {
            f64::from_bits(self.best.load(Ordering::Relaxed))
        } else {
            1.0
        }
    }

    /// The time up to which the triangles' sweeps are boxed: [`Job::cut`] when the times
    /// reported are exact; the whole step in the conservative mode, whose times may come
    /// before the contact (so a box up to the time may miss the primitives that report it).
    #[inline]
    fn box_cut(&self) -> f64 {
        if self.earliest_only && self.mode == CcdMode::Exact {
            f64::from_bits(self.best.load(Ordering::Relaxed))
        } else {
            1.0
        }
    }

    /// Tests the primitive pairs of leaves `na` of `a` and `nb` of `b` (of one mesh, `na <= nb`)
    /// into `w`, stopping once `w.out` holds `limit` impacts. Returns whether it stopped.
    pub fn leaf_pair(&self, w: &mut Worker, na: u32, nb: u32, limit: usize) -> bool {
        let cut = self.box_cut();
        let ra = self.a.mesh.tree().nodes[na as usize].ring_start;
        let rb = self.b.mesh.tree().nodes[nb as usize].ring_start;
        let mut ring_a = std::mem::take(&mut w.ring_a);
        let mut ring_b = std::mem::take(&mut w.ring_b);
        let box_a = sweep_ring(&self.a, ra, cut, &mut ring_a);
        let stopped = if self.one_mesh && na == nb {
            let mut stopped = false;
            'pairs: for (i, ta) in ring_a.iter().enumerate() {
                for tb in &ring_a[i + 1..] {
                    if ta.bounds.meets(&tb.bounds)
                        && self.triangle_pair(w, ta.triangle, tb.triangle, limit)
                    {
                        stopped = true;
                        break 'pairs;
                    }
                }
            }
            stopped
        } else {
            let box_b = sweep_ring(&self.b, rb, cut, &mut ring_b);
            let mut stopped = false;
            if box_a.meets(&box_b) {
                'pairs: for ta in ring_a.iter().filter(|t| t.bounds.meets(&box_b)) {
                    for tb in &ring_b {
                        if ta.bounds.meets(&tb.bounds)
                            && self.triangle_pair(w, ta.triangle, tb.triangle, limit)
                        {
                            stopped = true;
                            break 'pairs;
                        }
                    }
                }
            }
            stopped
        };
        w.ring_a = ring_a;
        w.ring_b = ring_b;
        stopped
    }

    /// The primitive pairs of triangle `ta` of `a` and `tb` of `b` that these triangles own.
    fn triangle_pair(&self, w: &mut Worker, ta: u32, tb: u32, limit: usize) -> bool {
        let (a, b) = (&self.a, &self.b);
        let (ca, cb) = (
            a.mesh.triangles()[ta as usize],
            b.mesh.triangles()[tb as usize],
        );
        let (oa, ob) = (a.owned[ta as usize], b.owned[tb as usize]);
        for (k, &v) in ca.iter().enumerate() {
            if oa & (1 << k) != 0 && !(self.one_mesh && cb.contains(&v)) {
                let hit = self.test(Primitive::VertexFace, a, [v], b, cb);
                let impact = (ImpactKind::VertexFace, v, 0, tb, 0);
                if self.report(w, hit, impact, limit) {
                    return true;
                }
            }
        }
        for (k, &v) in cb.iter().enumerate() {
            if ob & (1 << k) != 0 && !(self.one_mesh && ca.contains(&v)) {
                let hit = self.test(Primitive::VertexFace, b, [v], a, ca);
                let impact = if self.one_mesh {
                    (ImpactKind::VertexFace, v, 0, ta, 0)
                } else {
                    (ImpactKind::FaceVertex, ta, 0, v, 0)
                };
                if self.report(w, hit, impact, limit) {
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
                if self.one_mesh && (eb.contains(&ea[0]) || eb.contains(&ea[1])) {
                    continue;
                }
                // Tested in the order reported, so that the conservative mode's rounding
                // does not depend on which triangle came first.
                let (e1, e2) = if self.one_mesh && eb < ea {
                    (eb, ea)
                } else {
                    (ea, eb)
                };
                let hit = self.test(Primitive::EdgeEdge, a, e1, b, e2);
                let impact = (ImpactKind::EdgeEdge, e1[0], e1[1], e2[0], e2[1]);
                if self.report(w, hit, impact, limit) {
                    return true;
                }
            }
        }
        false
    }

    /// The continuous test of the points `pa` of `a` against the points `pb` of `b`: a vertex
    /// and a triangle's corners, or two edges' ends.
    #[inline]
    fn test<const N: usize, const M: usize>(
        &self,
        kind: Primitive,
        a: &Moving,
        pa: [u32; N],
        b: &Moving,
        pb: [u32; M],
    ) -> Option<f64> {
        let mut start = [[0.0; 3]; 4];
        let mut end = [[0.0; 3]; 4];
        for (i, &v) in pa.iter().enumerate() {
            start[i] = a.start[v as usize];
            end[i] = a.end[v as usize];
        }
        for (i, &v) in pb.iter().enumerate() {
            start[N + i] = b.start[v as usize];
            end[N + i] = b.end[v as usize];
        }
        time_of_impact(kind, &start, &end, self.mode, self.cut())
    }

    /// Records the test's outcome: an impact if it found one in time. Returns whether `limit`
    /// impacts are held, or the result cannot grow.
    #[inline]
    fn report(
        &self,
        w: &mut Worker,
        hit: Option<f64>,
        (kind, a0, a1, b0, b1): (ImpactKind, u32, u32, u32, u32),
        limit: usize,
    ) -> bool {
        w.primitive_tests += 1;
        let Some(toi) = hit else {
            return false;
        };
        let impact = Impact {
            kind,
            a0,
            a1,
            b0,
            b1,
            toi,
        };
        if self.earliest_only {
            if toi > self.cut() {
                return false;
            }
            let better = w
                .best
                .is_none_or(|b| (toi, impact.key()) < (b.toi, b.key()));
            if better {
                w.best = Some(impact);
                self.best.fetch_min(toi.to_bits(), Ordering::Relaxed);
            }
            return false;
        }
        if w.out.len() == w.out.capacity() {
            let extra = w.out.capacity().max(256);
            if w.out.try_reserve(extra).is_err() {
                w.out_of_memory = Some((w.out.capacity() + extra) * std::mem::size_of::<Impact>());
                return true;
            }
        }
        w.out.push(impact);
        w.out.len() >= limit
    }
}

/// An edge's ends, lower first.
#[inline]
fn ordered(u: u32, v: u32) -> [u32; 2] {
    [u.min(v), u.max(v)]
}

/// The triangles ring `r` of `side` owns, each with the box of its corners over `[0, cut]`,
/// into `out`; returns the box of them all.
fn sweep_ring(side: &Moving, r: u32, cut: f64, out: &mut Vec<Swept>) -> Aabb {
    out.clear();
    let mut all = Aabb::EMPTY;
    let tris = side.mesh.triangles();
    for &t in side.mesh.rings().triangles.row(r as usize) {
        if side.owner_ring[t as usize] != r {
            continue;
        }
        let mut b = Aabb::EMPTY;
        for &v in &tris[t as usize] {
            sweep_point(&mut b, &side.start[v as usize], &side.end[v as usize], cut);
        }
        all.merge(&b);
        out.push(Swept {
            triangle: t,
            bounds: b,
        });
    }
    all
}

/// Grows `b` by the path of a point from `s` (t = 0) to `e` (t = 1) over `[0, cut]`. Below the
/// whole step, the position at a double just above `cut` (so that a contact whose time rounds
/// down to `cut` is inside) is computed in floating point and the box widened by its rounding.
#[inline]
fn sweep_point(b: &mut Aabb, s: &Point, e: &Point, cut: f64) {
    b.grow(s);
    if cut >= 1.0 {
        b.grow(e);
        return;
    }
    let t = cut.next_up();
    for k in 0..3 {
        let x = s[k] + t * (e[k] - s[k]);
        // Three roundings of terms at most |s| + |e|; the subnormal term covers underflow.
        let err = 2.0 * f64::EPSILON * (s[k].abs() + e[k].abs()) + f64::from_bits(4);
        b.lo[k] = b.lo[k].min(x - err);
        b.hi[k] = b.hi[k].max(x + err);
    }
}
