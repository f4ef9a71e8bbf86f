//! Doubles with a forward error bound: the rounded value of a polynomial, with its permanent
//! (the same polynomial evaluated on the inputs' magnitudes, every subtraction an addition)
//! and the number of roundings on its longest path. The closest-point decisions try their signs
//! with these before [`super::ball::Ball`]: an operation costs two rounded results and a count,
//! against a radius's half-dozen operations and a zero test, and most signs are far from their
//! bound.
//!
//! The bound is the classical one for straight-line programs (Higham, *Accuracy and Stability of
//! Numerical Algorithms*, 3.1): a value with `k` roundings on its longest path, where a product
//! counts both factors' roundings and its own, differs from the exact one by at most
//! `gamma_k = k u / (1 - k u)` times the exact permanent, `u = 2^-53`, for `k u < 1`. The
//! permanent is itself computed in round-to-nearest from non-negative terms, so it is low by at
//! most the same relative amount, covered by [`SLACK`].
//!
//! The bound assumes no underflow: a product whose permanent is below [`SMALL`] (and not an
//! exact zero) poisons the result, whose sign is then unknown. Above it, what underflow can lose
//! in a rounding (2^-1075) is far below `u` times the permanent. An overflow makes the permanent
//! infinite or NaN, and the sign unknown too.

use super::distance::Num;
use super::predicates::Sign;
use std::ops::{Add, Mul, Sub};

const fn pow2(e: i64) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

/// The unit roundoff of round-to-nearest.
const U: f64 = pow2(-53);
/// Covers `gamma_k` against `k u`, the permanent's own roundings and those of the bound's
/// evaluation, for up to [`MOST_ROUNDINGS`] roundings on a path.
const SLACK: f64 = 1.0 + pow2(-28);
/// 2^20 roundings (the decisions here make fewer than a hundred): `k u` is at most 2^-33.
const MOST_ROUNDINGS: f64 = pow2(20);
/// Permanents of products below this (and above zero) may have lost digits to underflow.
const SMALL: f64 = pow2(-960);

/// The rounded value of a polynomial in doubles, with what bounds its error.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Permanent {
    /// The value as computed.
    pub value: f64,
    /// The permanent as computed; NaN once an operation may have underflowed.
    pub permanent: f64,
    /// Roundings on the longest path, products counting both factors'.
    pub roundings: f64,
}

impl Permanent {
    /// An input: exact.
    #[inline(always)]
    pub(crate) fn point(x: f64) -> Permanent {
        Permanent {
            value: x,
            permanent: x.abs(),
            roundings: 0.0,
        }
    }

    /// The bound on `|value - exact|`: `gamma_k` is at most `k u (1 + 2 k u)`, within
    /// [`SLACK`] of `k u` while `k` is at most [`MOST_ROUNDINGS`]; beyond, unbounded.
    #[inline(always)]
    fn error(&self) -> f64 {
        if self.roundings > MOST_ROUNDINGS {
            return f64::INFINITY;
        }
        self.roundings * U * self.permanent * SLACK
    }
}

impl Add for Permanent {
    type Output = Permanent;
    #[inline(always)]
    fn add(self, o: Permanent) -> Permanent {
        Permanent {
            value: self.value + o.value,
            permanent: self.permanent + o.permanent,
            roundings: self.roundings.max(o.roundings) + 1.0,
        }
    }
}

impl Sub for Permanent {
    type Output = Permanent;
    #[inline(always)]
    fn sub(self, o: Permanent) -> Permanent {
        Permanent {
            value: self.value - o.value,
            permanent: self.permanent + o.permanent,
            roundings: self.roundings.max(o.roundings) + 1.0,
        }
    }
}

impl Mul for Permanent {
    type Output = Permanent;
    #[inline(always)]
    fn mul(self, o: Permanent) -> Permanent {
        let permanent = self.permanent * o.permanent;
        // A zero factor's permanent is an exact zero, and so is the product; a small product of
        // nonzero factors may have underflowed.
        let lost = permanent < SMALL && self.permanent != 0.0 && o.permanent != 0.0;
        Permanent {
            value: self.value * o.value,
            permanent: if lost { f64::NAN } else { permanent },
            roundings: self.roundings + o.roundings + 1.0,
        }
    }
}

impl Num for Permanent {
    #[inline(always)]
    fn sign(&self) -> Option<Sign> {
        // NaN anywhere fails every comparison: unknown.
        let error = self.error();
        if self.value > error {
            Some(1)
        } else if -self.value > error {
            Some(-1)
        } else if self.permanent == 0.0 {
            // Every term is an exact zero.
            Some(0)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random chains over doubles of every magnitude, near-cancellations included: every sign
    /// the bound claims is the exact one, and the error bound holds wherever it is finite.
    #[test]
    fn claimed_signs_are_exact_and_errors_within_the_bound() {
        let (known, zeros) =
            super::super::chains::check(0x9e44, Permanent::point, |x| (x.value, x.error()));
        assert!(known > 40_000 && zeros > 1000, "{known} {zeros}");
    }

    /// Cancellation the bound cannot see through is left to the next arithmetic; a product that
    /// underflows is never trusted.
    #[test]
    fn unknown_where_the_bound_cannot_tell() {
        let p = Permanent::point;
        // (1 + 2^-52) - 1 - 2^-52 is exactly zero, but computed with roundings.
        let x = p(1.0 + pow2(-52)) * p(1.0) - p(1.0) - p(pow2(-52));
        assert_eq!(x.sign(), None);
        let tiny = p(pow2(-600)) * p(pow2(-600));
        assert_eq!(tiny.sign(), None);
        assert_eq!((p(0.0) * p(pow2(-600))).sign(), Some(0));
        assert_eq!((p(3.0) * p(-2.0) + p(5.0)).sign(), Some(-1));
    }
}
