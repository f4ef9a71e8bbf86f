//! Midpoint-radius intervals of doubles: a value is `mid` give or take `rad`. The closest-point
//! decisions make their signs with them first: an operation costs one rounded result and a
//! few operations on the radius, against four products and outward roundings of both ends in
//! [`super::interval::Interval`], and the signs are as certain.
//!
//! Each rounding of a result is within 2^-52 of it (RN is within 2^-53; the bound is itself
//! rounded); radii are computed in round-to-nearest from non-negative terms and then scaled up
//! by far more than their own roundings. Products add [`TINY`] for what underflow can lose. An
//! overflow makes the radius infinite or NaN, and the sign unknown.

use super::distance::{Num, sign_within};
use super::predicates::Sign;
use std::ops::{Add, Mul, Neg, Sub};

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

impl Neg for Ball {
    type Output = Ball;
    #[inline(always)]
    fn neg(self) -> Ball {
        Ball {
            mid: -self.mid,
            rad: self.rad,
        }
    }
}

impl Sub for Ball {
    type Output = Ball;
    #[inline(always)]
    fn sub(self, o: Ball) -> Ball {
        self + -o
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
        sign_within(self.mid, self.rad, self.is_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balls_hold_exact_results_and_their_signs_are_exact() {
        let (known, _) = super::super::chains::check(
            0xba11,
            [4, 40, 600, 1100],
            Ball::point,
            |x| (x.mid, x.rad),
            Ball::sign,
        );
        assert!(known > 40_000, "{known}");
    }
}
