//! Midpoint-radius intervals of doubles: a value is `mid` give or take `rad`. The closest-point
//! decisions make their signs with them first: an operation costs one rounded result and a
//! few operations on the radius, against four products and outward roundings of both ends in
//! [`super::interval::Interval`], and the signs are as certain.
//!
//! Each rounding of a result is within 2^-52 of it (RN is within 2^-53; the bound is itself
//! rounded); radii are computed in round-to-nearest from non-negative terms and then scaled up
//! by far more than their own roundings. Products add [`TINY`] for what underflow can lose. An
//! overflow makes the radius infinite or NaN, and the sign unknown.

use super::distance::Num;
use super::predicates::Sign;
use std::ops::{Add, Mul, Sub};

const fn pow2(e: i64) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

const REL: f64 = pow2(-52);
const SLACK: f64 = 1.0 + pow2(-45);
/// 2^-1050: more than underflow can lose in one product (a few roundings of 2^-1075).
const TINY: f64 = f64::from_bits(1 << 24);

/// The closed interval `[mid - rad, mid + rad]`, certainly holding the exact value.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ball {
    pub mid: f64,
    pub rad: f64,
}

impl Ball {
    pub(crate) fn point(x: f64) -> Ball {
        Ball { mid: x, rad: 0.0 }
    }

    fn is_zero(&self) -> bool {
        self.mid == 0.0 && self.rad == 0.0
    }
}

impl Add for Ball {
    type Output = Ball;
    #[inline(always)]
    fn add(self, o: Ball) -> Ball {
        let mid = self.mid + o.mid;
        // Sums are exact below the normal range, and a zero sum is exact: exact zeros (equal
        // coordinates subtracted) stay exact.
        Ball {
            mid,
            rad: (self.rad + o.rad + mid.abs() * REL) * SLACK,
        }
    }
}

impl Sub for Ball {
    type Output = Ball;
    #[inline(always)]
    fn sub(self, o: Ball) -> Ball {
        self + Ball {
            mid: -o.mid,
            rad: o.rad,
        }
    }
}

impl Mul for Ball {
    type Output = Ball;
    #[inline(always)]
    fn mul(self, o: Ball) -> Ball {
        // A product with an exact zero is an exact zero, whatever the other factor.
        if self.is_zero() || o.is_zero() {
            return Ball::point(0.0);
        }
        let mid = self.mid * o.mid;
        let spread = self.mid.abs() * o.rad + o.mid.abs() * self.rad + self.rad * o.rad;
        Ball {
            mid,
            rad: (spread + mid.abs() * REL) * SLACK + TINY,
        }
    }
}

impl Num for Ball {
    #[inline(always)]
    fn sign(&self) -> Option<Sign> {
        // A NaN part fails every comparison: unknown.
        if self.mid > self.rad {
            Some(1)
        } else if -self.mid > self.rad {
            Some(-1)
        } else if self.is_zero() {
            Some(0)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::Rng;
    use num_rational::BigRational;
    use num_traits::{Signed, Zero};

    type Q = BigRational;

    fn q(x: f64) -> Q {
        Q::from_float(x).unwrap()
    }

    #[test]
    fn balls_hold_exact_results_and_their_signs_are_exact() {
        let mut rng = Rng::new(0xba11);
        let mut known = 0;
        for case in 0..4000 {
            let span = [4, 40, 600, 1100][case % 4];
            let mut xs: Vec<(Ball, Q)> = (0..6)
                .map(|_| {
                    let x = match rng.below(8) {
                        0 => 0.0,
                        1 => rng.below(8) as f64,
                        _ => {
                            let e = rng.below((span + span.min(1000)) as u64 + 1) as i64 - span;
                            rng.range(1.0, 2.0) * pow2(e / 2) * pow2(e - e / 2)
                        }
                    };
                    let x = if rng.below(2) == 0 { x } else { -x };
                    (Ball::point(x), q(x))
                })
                .collect();
            for _ in 0..24 {
                let i = rng.below(6) as usize;
                let j = rng.below(6) as usize;
                let ((a, qa), (b, qb)) = (xs[i].clone(), xs[j].clone());
                let (x, v) = match rng.below(3) {
                    0 => (a + b, &qa + &qb),
                    1 => (a - b, &qa - &qb),
                    _ => (a * b, &qa * &qb),
                };
                if let Some(s) = x.sign() {
                    let want = if v.is_zero() {
                        0
                    } else if v.is_positive() {
                        1
                    } else {
                        -1
                    };
                    assert_eq!(s, want, "{a:?} {b:?} -> {x:?}");
                    known += 1;
                }
                if x.mid.is_finite() && x.rad.is_finite() {
                    assert!((&v - q(x.mid)).abs() <= q(x.rad), "{a:?} {b:?} -> {x:?}");
                }
                let k = rng.below(6) as usize;
                xs[k] = (x, v);
            }
        }
        assert!(known > 40_000, "{known}");
    }
}
