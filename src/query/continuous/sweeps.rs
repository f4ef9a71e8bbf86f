//! The continuous test of the shared narrow phase: primitive pairs filtered by the boxes of
//! their sweeps, then the time of impact.

use super::impacts::Impact;
use crate::geometry::aabb::Aabb;
use crate::geometry::ccd::{CcdMode, time_of_impact};
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;
use crate::query::primitives::{PrimitivePair, PrimitiveTest, Side, Worker};
use std::sync::atomic::{AtomicU64, Ordering};

/// Where each vertex of a moving mesh starts and ends.
#[derive(Clone, Copy)]
pub(crate) struct VertexPaths<'m> {
    pub start: &'m [Point],
    pub end: &'m [Point],
}

impl<'m> VertexPaths<'m> {
    pub fn new(mesh: &'m Mesh) -> VertexPaths<'m> {
        VertexPaths {
            start: mesh.start_positions(),
            end: mesh.positions(),
        }
    }
}

/// The continuous test, as every thread of a query shares it.
pub(crate) struct Sweeps<'m, 'q> {
    pub a: VertexPaths<'m>,
    pub b: VertexPaths<'m>,
    pub mode: CcdMode,
    /// Keep only the earliest impact, and skip what cannot come before it.
    pub earliest_only: bool,
    /// The earliest impact time found so far by any thread (the bits of a non-negative double,
    /// ordered as the doubles are), when `earliest_only`.
    pub best: &'q AtomicU64,
}

impl Sweeps<'_, '_> {
    fn side(&self, side: Side) -> &VertexPaths<'_> {
        match side {
            Side::A => &self.a,
            Side::B => &self.b,
        }
    }

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

    /// The time up to which the triangles' sweeps are boxed: [`Sweeps::cut`] when the times
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
}

impl PrimitiveTest for Sweeps<'_, '_> {
    type Found = Impact;

    /// The earliest impact alone, exact: the boxes end at the earliest time found so far,
    /// which only comes earlier.
    #[inline]
    fn box_epoch(&self) -> u64 {
        self.box_cut().to_bits()
    }

    #[inline(always)]
    fn grow(&self, side: Side, v: u32, b: &mut Aabb) {
        let m = self.side(side);
        sweep_point(b, &m.start[v as usize], &m.end[v as usize], self.box_cut());
    }

    #[inline]
    fn test<const N: usize, const M: usize>(
        &self,
        pair: PrimitivePair<N, M>,
        best: Option<&Impact>,
    ) -> Option<Impact> {
        let (a, b) = (self.side(pair.first), self.side(pair.second));
        let start = pair.points(a.start, b.start);
        let end = pair.points(a.end, b.end);
        let (kind_out, a0, a1, b0, b1) = pair.key;
        let mut cut = self.cut();
        // A contact at this thread's best time would lose to it in the result's order (ties
        // are common where a vertex lands exactly on a face: every primitive around it meets
        // then), so only earlier ones are wanted. Which impact wins does not change.
        if self.earliest_only && best.is_some_and(|b| b.toi == cut && b.key() < pair.key) {
            cut = cut.next_down();
        }
        let toi = time_of_impact(pair.kind, &start, &end, self.mode, cut)?;
        Some(Impact {
            kind: kind_out,
            a0,
            a1,
            b0,
            b1,
            toi,
        })
    }

    #[inline]
    fn keep(&self, w: &mut Worker<Impact>, impact: Impact, limit: usize) -> bool {
        if !self.earliest_only {
            return w.push(impact, limit);
        }
        if impact.toi > self.cut() {
            return false;
        }
        let better = w
            .best
            .is_none_or(|b| (impact.toi, impact.key()) < (b.toi, b.key()));
        if better {
            w.best = Some(impact);
            self.best.fetch_min(impact.toi.to_bits(), Ordering::Relaxed);
        }
        false
    }
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
