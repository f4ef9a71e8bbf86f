//! Axis-aligned boxes: the bounding volume of the AABB hierarchies, and the exact filter in front
//! of every triangle test.

use super::predicates::Point;

/// A closed axis-aligned box: the points `p` with `lo[k] <= p[k] <= hi[k]` on every axis `k`.
///
/// Boxes of vertex coordinates are exact (minimum and maximum never round), so two such boxes
/// that do not meet prove that nothing inside them meets. [`Aabb::EMPTY`] contains nothing and
/// is the starting point of [`Aabb::grow`] and [`Aabb::merge`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lowest coordinate on each axis.
    pub lo: Point,
    /// Highest coordinate on each axis.
    pub hi: Point,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The empty box (`lo` = +inf, `hi` = -inf): meets nothing, and is the identity of
    /// [`Aabb::merge`].
    pub const EMPTY: Aabb = Aabb {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };

    /// The box of one point.
    #[inline]
    pub fn point(p: &Point) -> Aabb {
        Aabb { lo: *p, hi: *p }
    }

    /// The smallest box holding every point (empty for none).
    pub fn of_points<'p>(points: impl IntoIterator<Item = &'p Point>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.grow(p);
        }
        b
    }

    /// Grows the box to hold `p`.
    #[inline(always)]
    pub fn grow(&mut self, p: &Point) {
        // Comparisons rather than f64::min/max: their NaN rules cost a dependency chain, and
        // coordinates here are never NaN.
        for (k, &x) in p.iter().enumerate() {
            self.lo[k] = if x < self.lo[k] { x } else { self.lo[k] };
            self.hi[k] = if x > self.hi[k] { x } else { self.hi[k] };
        }
    }

    /// Grows the box to hold `other`.
    #[inline(always)]
    pub fn merge(&mut self, other: &Aabb) {
        for k in 0..3 {
            self.lo[k] = if other.lo[k] < self.lo[k] {
                other.lo[k]
            } else {
                self.lo[k]
            };
            self.hi[k] = if other.hi[k] > self.hi[k] {
                other.hi[k]
            } else {
                self.hi[k]
            };
        }
    }

    /// Do the closed boxes share a point? Exact.
    #[inline(always)]
    pub fn meets(&self, other: &Aabb) -> bool {
        // `&` rather than `&&`: six comparisons without branches are cheaper than early exits.
        (self.lo[0] <= other.hi[0])
            & (other.lo[0] <= self.hi[0])
            & (self.lo[1] <= other.hi[1])
            & (other.lo[1] <= self.hi[1])
            & (self.lo[2] <= other.hi[2])
            & (other.lo[2] <= self.hi[2])
    }

    /// Do the boxes come within `d >= 0` of each other along every axis (touching counts)?
    /// Never refuses boxes within `d`: rounding is monotone and `d` is a double, so a gap
    /// rounded to nearest exceeds `d` only if the exact gap does. Cheaper than [`Aabb::meets`]
    /// on a box [`Aabb::widened`], whose outward rounding costs more than the test.
    #[inline(always)]
    pub fn within(&self, other: &Aabb, d: f64) -> bool {
        (other.lo[0] - self.hi[0] <= d)
            & (self.lo[0] - other.hi[0] <= d)
            & (other.lo[1] - self.hi[1] <= d)
            & (self.lo[1] - other.hi[1] <= d)
            & (other.lo[2] - self.hi[2] <= d)
            & (self.lo[2] - other.hi[2] <= d)
    }

    /// The box grown by `d >= 0` on every side, rounded outwards: it holds every point within
    /// distance `d` of this box.
    #[inline]
    pub fn widened(&self, d: f64) -> Aabb {
        Aabb {
            lo: self.lo.map(|x| (x - d).next_down()),
            hi: self.hi.map(|x| (x + d).next_up()),
        }
    }

    /// A box holding every point within distance `d >= 0` of this box, as [`Aabb::widened`]
    /// but cheaper and looser by an ulp or two: each bound moved by `d`, then outwards by at
    /// least one unit in its last place. For a box compared with many: [`Aabb::meets`] against
    /// it tells what [`Aabb::within`] tells (and possibly more, by rounding) with six
    /// subtractions fewer a comparison.
    #[inline(always)]
    pub(crate) fn reach(&self, d: f64) -> Aabb {
        // `s` is within half an ulp of the exact sum; `|s| eps` (at least the least normal
        // double) is at least one ulp of `s`, so adding it rounds to a double past `s`'s
        // neighbour, beyond the exact sum.
        let out = |s: f64| s.abs() * f64::EPSILON + f64::MIN_POSITIVE;
        Aabb {
            lo: self.lo.map(|x| {
                let s = x - d;
                s - out(s)
            }),
            hi: self.hi.map(|x| {
                let s = x + d;
                s + out(s)
            }),
        }
    }

    /// Does the closed box hold `p`?
    #[inline]
    pub fn contains(&self, p: &Point) -> bool {
        (0..3).all(|k| self.lo[k] <= p[k] && p[k] <= self.hi[k])
    }

    /// Does the box hold nothing?
    pub fn is_empty(&self) -> bool {
        (0..3).any(|k| self.lo[k] > self.hi[k])
    }

    /// The midpoint, halves added separately so that huge coordinates cannot overflow.
    #[inline]
    pub fn centre(&self) -> Point {
        [0, 1, 2].map(|k| 0.5 * self.lo[k] + 0.5 * self.hi[k])
    }

    /// Side lengths (rounded; infinite only for boxes wider than `f64::MAX`).
    #[inline]
    pub fn extent(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| self.hi[k] - self.lo[k])
    }

    /// The axis with the longest side (the lowest such axis on ties).
    pub fn longest_axis(&self) -> usize {
        let e = self.extent();
        (0..3)
            .max_by(|&a, &b| e[a].total_cmp(&e[b]).then(b.cmp(&a)))
            .unwrap_or(0)
    }

    /// Square of half the diagonal: a size comparable with a sphere's squared radius (the box
    /// lies in the ball of that radius about its centre).
    #[inline(always)]
    pub fn half_diagonal_squared(&self) -> f64 {
        let (x, y, z) = (
            self.hi[0] - self.lo[0],
            self.hi[1] - self.lo[1],
            self.hi[2] - self.lo[2],
        );
        0.25 * (x * x + y * y + z * z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Any finite double: normal and subnormal, of both signs, and zero.
    fn finite() -> impl proptest::strategy::Strategy<Value = f64> {
        use proptest::num::f64::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
        POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 20_000, ..proptest::prelude::ProptestConfig::default()
        })]

        /// The cheap reach holds the exactly rounded one, at every scale.
        #[test]
        fn reach_holds_the_widened_box(x in finite(), y in finite(), d in finite()) {
            let d = d.abs();
            let b = Aabb::of_points(&[[x, y, 0.0], [y, x, 0.0]]);
            let (fast, exact) = (b.reach(d), b.widened(d));
            for k in 0..3 {
                proptest::prop_assert!(fast.lo[k] <= exact.lo[k], "{:?} {:?}", fast, exact);
                proptest::prop_assert!(fast.hi[k] >= exact.hi[k], "{:?} {:?}", fast, exact);
            }
        }
    }

    #[test]
    fn grows_merges_and_meets_as_closed_boxes() {
        let a = Aabb::of_points(&[[0.0, 0.0, 0.0], [1.0, 2.0, -1.0]]);
        assert_eq!(a.lo, [0.0, 0.0, -1.0]);
        assert_eq!(a.hi, [1.0, 2.0, 0.0]);
        // Touching along a face counts.
        let b = Aabb::of_points(&[[1.0, 0.5, -0.5], [3.0, 1.0, 0.0]]);
        assert!(a.meets(&b) && b.meets(&a));
        let c = Aabb::point(&[1.0 + f64::EPSILON, 0.5, -0.5]);
        assert!(!a.meets(&c) && !c.meets(&a));
        let mut m = Aabb::EMPTY;
        assert!(m.is_empty() && !m.meets(&a));
        m.merge(&a);
        m.merge(&c);
        assert!(m.contains(&c.lo) && m.contains(&a.lo) && m.contains(&a.hi));
        assert_eq!(m.longest_axis(), 1);
        assert_eq!(a.centre(), [0.5, 1.0, -0.5]);
        assert_eq!(a.half_diagonal_squared(), 0.25 * 6.0);
        let huge = Aabb::of_points(&[[-f64::MAX, 0.0, 0.0], [f64::MAX, 0.0, 0.0]]);
        assert_eq!(huge.centre(), [0.0; 3]);
    }

    /// Is `x - y` exactly more than `d`? (The rounded difference and its exact error.)
    fn exceeds(x: f64, y: f64, d: f64) -> bool {
        let s = x - y;
        if s.is_infinite() {
            return s > 0.0;
        }
        let back = s - x;
        let err = (x - (s - back)) + (-y - back);
        s > d || (s == d && err > 0.0)
    }

    #[test]
    fn within_takes_every_pair_of_boxes_within_d() {
        // A gap of exactly `d` counts, the next double beyond it does not.
        let a = Aabb::of_points(&[[0.0; 3], [1.0; 3]]);
        let at = Aabb::point(&[1.5, 0.5, 0.5]);
        let beyond = Aabb::point(&[1.5f64.next_up(), 0.5, 0.5]);
        assert!(a.within(&at, 0.5) && at.within(&a, 0.5));
        assert!(!a.within(&beyond, 0.5) && !beyond.within(&a, 0.5));
        assert!(a.within(&a, 0.0) && !Aabb::EMPTY.within(&a, f64::MAX));
        // Opposite huge coordinates: the gap overflows, and is more than any `d`.
        let far = Aabb::point(&[f64::MAX, 0.0, 0.0]);
        let near_min = Aabb::point(&[-f64::MAX, 0.0, 0.0]);
        assert!(!far.within(&near_min, f64::MAX));
        // Random boxes at every scale, `d` at, next to and around one axis's gap: a pair is
        // refused only if the exact gap along some axis is more than `d`.
        let mut rng = crate::fixtures::Rng::new(11);
        let mut refused = 0;
        for scale in [1e-300, 1e-150, 1.0, 1e150, 1e300] {
            for offset in [0.0, 1e12] {
                if scale * offset > 1e290 {
                    continue;
                }
                for _ in 0..500 {
                    let mut point = || [0; 3].map(|_| (rng.range(-1.0, 1.0) + offset) * scale);
                    let a = Aabb::of_points(&[point(), point()]);
                    let b = Aabb::of_points(&[point(), point()]);
                    let k = rng.below(3) as usize;
                    let gap = (b.lo[k] - a.hi[k]).abs();
                    for d in [gap, gap.next_up(), gap.next_down(), rng.unit() * scale] {
                        let d = d.max(0.0);
                        let within = a.within(&b, d);
                        assert_eq!(within, b.within(&a, d));
                        if !within {
                            refused += 1;
                            assert!(
                                (0..3).any(|k| exceeds(b.lo[k], a.hi[k], d)
                                    || exceeds(a.lo[k], b.hi[k], d)),
                                "{a:?} and {b:?} are within {d:e}"
                            );
                        }
                    }
                }
            }
        }
        assert!(refused > 1000, "{refused} refused");
    }
}
