//! Doubles with a forward error bound: the rounded value of a polynomial with its permanent (the
//! same polynomial evaluated on the inputs' magnitudes, every subtraction an addition). The
//! closest-point decisions try their signs with these before [`super::ball::Ball`]: an
//! operation costs two rounded results, against a radius's half-dozen operations and a zero
//! test, and most signs are far from their bound.
//!
//! The bound is the classical one for straight-line programs (Higham, *Accuracy and Stability of
//! Numerical Algorithms*, 3.1): a value with `k` roundings on its longest path, where a product
//! counts both factors' roundings and its own, differs from the exact one by at most
//! `gamma_k = k u / (1 - k u)` times the exact permanent, `u = 2^-53`. The permanent is itself
//! computed in round-to-nearest from non-negative terms, so it is low by at most the same
//! relative amount, covered by [`SLACK`].
//!
//! Nothing is counted per value (counting roundings and watching for underflow in every
//! operation cost as much as the arithmetic itself). Instead, what the bound needs is required
//! of the polynomials and the inputs:
//! - at most [`MOST_ROUNDINGS`] roundings on a polynomial's longest path and degree at most
//!   [`MOST_DEGREE`] (the closest-point decisions' test checks both with a tracing arithmetic);
//! - inputs whose nonzero magnitudes lie within `2^±150` ([`Permanent::inputs`]). Then every
//!   nonzero permanent lies between `2^-900` and `2^1000`: none underflows or overflows. A value
//!   may still underflow after cancellation, losing at most `2^-1075` per rounding, carried
//!   through later products by at most their factors' permanents: below `2^-170` of the final
//!   permanent, also covered by [`SLACK`].

use super::distance::{Num, sign_within};
use super::predicates::Sign;
use std::ops::{Add, Mul, Sub};

const fn pow2(e: i64) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

/// The unit roundoff of round-to-nearest.
const U: f64 = pow2(-53);
/// Covers `gamma_k` against `k u`, the permanent's own roundings, those of the bound's
/// evaluation and what underflow can lose.
const SLACK: f64 = 1.0 + pow2(-28);
/// Roundings on the longest path of any polynomial signed with these.
pub(crate) const MOST_ROUNDINGS: u32 = 32;
/// The largest degree of a polynomial signed with these, in the inputs (constants of degree 0).
pub(crate) const MOST_DEGREE: u32 = 6;
/// Nonzero inputs are at least this and at most its inverse in magnitude.
const LEAST: f64 = pow2(-150);
// A product of `MOST_DEGREE` inputs in the range stays above 2^-900 (and far below overflow).
const _: () = assert!(150 * MOST_DEGREE <= 900);

/// The rounded value of a polynomial in doubles, with what bounds its error.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Permanent {
    /// The value as computed.
    pub value: f64,
    /// The permanent as computed.
    pub permanent: f64,
}

impl Permanent {
    /// A constant, or an input within the range [`Permanent::inputs`] checks: exact.
    #[inline(always)]
    pub(crate) fn point(x: f64) -> Permanent {
        Permanent {
            value: x,
            permanent: x.abs(),
        }
    }

    /// The inputs `x` as values, when every nonzero magnitude lies within `2^±150`; `None`
    /// otherwise (then the bound could be lost to underflow or overflow).
    #[inline(always)]
    pub(crate) fn inputs<const N: usize>(x: &[f64; N]) -> Option<[Permanent; N]> {
        // Every input tested without branches (`&`, `|`): this runs once per pair tested, and
        // the inputs are nearly always in range.
        let fits = x.iter().fold(true, |ok, v| {
            let m = v.abs();
            ok & ((m == 0.0) | (LEAST..=1.0 / LEAST).contains(&m))
        });
        fits.then(|| x.map(Permanent::point))
    }

    /// The bound on `|value - exact|`: `gamma_k` is at most `k u (1 + 2 k u)`, within
    /// [`SLACK`] of `k u`.
    #[inline(always)]
    pub(crate) fn error(&self) -> f64 {
        MOST_ROUNDINGS as f64 * U * self.permanent * SLACK
    }
}

impl Add for Permanent {
    type Output = Permanent;
    #[inline(always)]
    fn add(self, o: Permanent) -> Permanent {
        Permanent {
            value: self.value + o.value,
            permanent: self.permanent + o.permanent,
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
        }
    }
}

impl Mul for Permanent {
    type Output = Permanent;
    #[inline(always)]
    fn mul(self, o: Permanent) -> Permanent {
        Permanent {
            value: self.value * o.value,
            permanent: self.permanent * o.permanent,
        }
    }
}

impl Num for Permanent {
    #[inline(always)]
    fn sign(&self) -> Option<Sign> {
        // A zero permanent: every term is an exact zero.
        sign_within(self.value, self.error(), self.permanent == 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::chains::{Traced, check};
    use super::*;

    /// Random chains over inputs within the range, near-cancellations included: every sign the
    /// bound claims for a polynomial within the limits on roundings and degree is the exact
    /// one, and the error bound holds for each.
    #[test]
    fn claimed_signs_are_exact_and_errors_within_the_bound() {
        let within =
            |x: &Traced<Permanent>| x.roundings <= MOST_ROUNDINGS && x.degree <= MOST_DEGREE;
        let (known, zeros) = check(
            0x9e44,
            [4, 40, 100, 150],
            |x| Traced::input(Permanent::point(x)),
            |x| {
                if within(x) {
                    (x.x.value, x.x.error())
                } else {
                    (f64::NAN, f64::NAN)
                }
            },
            |x| if within(x) { x.x.sign() } else { None },
        );
        assert!(known > 20_000 && zeros > 1000, "{known} {zeros}");
    }

    /// Cancellation the bound cannot see through is left to the next arithmetic; inputs out of
    /// the range are refused.
    #[test]
    fn unknown_where_the_bound_cannot_tell() {
        let p = Permanent::point;
        // (1 + 2^-52) - 1 - 2^-52 is exactly zero, but computed with roundings.
        let x = p(1.0 + pow2(-52)) * p(1.0) - p(1.0) - p(pow2(-52));
        assert_eq!(x.sign(), None);
        assert_eq!((p(0.0) * p(pow2(-100))).sign(), Some(0));
        assert_eq!((p(3.0) * p(-2.0) + p(5.0)).sign(), Some(-1));
        assert!(Permanent::inputs(&[1.0, 0.0, -pow2(150), pow2(-150)]).is_some());
        assert!(Permanent::inputs(&[1.0, pow2(-151)]).is_none());
        assert!(Permanent::inputs(&[pow2(151), 1.0]).is_none());
    }
}
