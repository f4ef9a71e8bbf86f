//! Floating-point intervals that certainly hold an exact value: each bound rounded outwards,
//! exact sums and products by zero kept as points (so exact zeros keep their sign). The
//! filters of the distance test and of the continuous tests compute with them.

use std::ops::{Add, Mul, Sub};

/// A closed interval of reals holding the exact value.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Interval {
    pub lo: f64,
    pub hi: f64,
}

impl Interval {
    pub(crate) const ALL: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    pub(crate) fn point(x: f64) -> Interval {
        Interval { lo: x, hi: x }
    }

    /// `[lo, hi]` widened by one unit in the last place each way (each bound was rounded to
    /// nearest, so the exact value is within half of one), or everything if a bound is NaN.
    pub(crate) fn outward(lo: f64, hi: f64) -> Interval {
        if lo.is_nan() || hi.is_nan() {
            return Interval::ALL;
        }
        Interval {
            lo: lo.next_down(),
            hi: hi.next_up(),
        }
    }
}

/// `a + b` rounded down and rounded up: the rounded sum, moved one unit only where the rounding
/// went the wrong way (the error, exact by Knuth's two-sum, says which). Exact sums stay points,
/// so exact zeros (equal coordinates subtracted) keep their sign.
#[inline(always)]
fn sum_bounds(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    if !s.is_finite() {
        return (s.next_down(), s.next_up());
    }
    let bb = s - a;
    let err = (a - (s - bb)) + (b - bb);
    (
        if err < 0.0 { s.next_down() } else { s },
        if err > 0.0 { s.next_up() } else { s },
    )
}

impl Add for Interval {
    type Output = Interval;
    #[inline(always)]
    fn add(self, o: Interval) -> Interval {
        let (lo, hi) = (self.lo + o.lo, self.hi + o.hi);
        if lo.is_nan() || hi.is_nan() {
            return Interval::ALL;
        }
        Interval {
            lo: sum_bounds(self.lo, o.lo).0,
            hi: sum_bounds(self.hi, o.hi).1,
        }
    }
}

impl Sub for Interval {
    type Output = Interval;
    #[inline(always)]
    fn sub(self, o: Interval) -> Interval {
        self + Interval {
            lo: -o.hi,
            hi: -o.lo,
        }
    }
}

impl Mul for Interval {
    type Output = Interval;
    #[inline(always)]
    fn mul(self, o: Interval) -> Interval {
        // A product with an exact zero stays zero: widening it would hide exact zeros, which are
        // common (coordinates shared by both triangles). (A product that underflowed to zero is
        // not exact, and is widened below.)
        let zero = |i: &Interval| i.lo == 0.0 && i.hi == 0.0;
        if zero(&self) || zero(&o) {
            return Interval { lo: 0.0, hi: 0.0 };
        }
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        // One test for all four: a NaN product (an infinity times zero) makes the sum NaN. So
        // do infinities of both signs, whose answer is everything anyway.
        if (p[0] + p[1] + p[2] + p[3]).is_nan() {
            return Interval::ALL;
        }
        let lo = p[0].min(p[1]).min(p[2].min(p[3]));
        let hi = p[0].max(p[1]).max(p[2].max(p[3]));
        Interval::outward(lo, hi)
    }
}
