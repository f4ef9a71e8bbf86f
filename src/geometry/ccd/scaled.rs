//! The sign of the coplanarity determinant at one time, exactly, in integers: every double is
//! an integer times a power of two, so with one common scale the positions at a double time
//! and the determinant are integers (no fractions to reduce, unlike rationals). Used to round
//! a contact time that the interval path has enclosed to a few doubles.

use crate::geometry::Primitive;
use crate::geometry::predicates::Point;
use num_bigint::BigInt;
use num_traits::Signed;
use std::cmp::Ordering;

/// `x = m · 2^e` with `m` an integer (53 bits at most).
fn split(x: f64) -> (i64, i32) {
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp - 1075)
    };
    (if x.is_sign_negative() { -m } else { m }, e)
}

/// The smallest exponent of the non-zero coordinates: scaled by 2 to minus it, every
/// coordinate is an integer.
pub(crate) fn common_scale(start: &[Point; 4], end: &[Point; 4]) -> i32 {
    start
        .iter()
        .chain(end.iter())
        .flatten()
        .filter(|x| **x != 0.0)
        .map(|&x| split(x).1)
        .min()
        .unwrap_or(0)
}

/// `x · 2^-scale`, an integer when `scale` is at most `x`'s exponent.
pub(crate) fn scaled_int(x: f64, scale: i32) -> BigInt {
    if x == 0.0 {
        return BigInt::ZERO;
    }
    let (m, e) = split(x);
    BigInt::from(m) << (e - scale) as usize
}

/// The sign of the coplanarity determinant (as `condition::coplanarity` orders it) at time
/// `t` in [0, 1], for finite coordinates.
pub(crate) fn coplanarity_sign(
    kind: Primitive,
    start: &[Point; 4],
    end: &[Point; 4],
    t: f64,
) -> Ordering {
    let scale = common_scale(start, end);
    let int = |x: f64| scaled_int(x, scale);
    // t in (0, 1] is tm · 2^te with te < 0 (1 is 2^52 · 2^-52). The position at t, times
    // 2^(-scale - te), is x0 · 2^-te + tm · (x1 - x0): an integer.
    let (tm, te) = split(t);
    debug_assert!(t > 0.0 && t <= 1.0 && te < 0);
    let shift = (-te) as usize;
    let at = |i: usize| -> [BigInt; 3] {
        [0, 1, 2].map(|k| {
            let (x0, x1) = (int(start[i][k]), int(end[i][k]));
            let d = &x1 - &x0;
            (x0 << shift) + BigInt::from(tm) * d
        })
    };
    let p = [at(0), at(1), at(2), at(3)];
    let minus = |a: &[BigInt; 3], b: &[BigInt; 3]| [0, 1, 2].map(|k| &a[k] - &b[k]);
    let (u, v, w) = match kind {
        Primitive::VertexFace => (
            minus(&p[2], &p[1]),
            minus(&p[3], &p[1]),
            minus(&p[0], &p[1]),
        ),
        Primitive::EdgeEdge => (
            minus(&p[1], &p[0]),
            minus(&p[2], &p[0]),
            minus(&p[3], &p[0]),
        ),
    };
    let det = &u[0] * (&v[1] * &w[2] - &v[2] * &w[1])
        + &u[1] * (&v[2] * &w[0] - &v[0] * &w[2])
        + &u[2] * (&v[0] * &w[1] - &v[1] * &w[0]);
    if det.is_positive() {
        Ordering::Greater
    } else if det.is_negative() {
        Ordering::Less
    } else {
        Ordering::Equal
    }
}

/// The largest double not above the coplanarity determinant's only root in `(lo, hi)`, where
/// its sign at `lo` is `at_lo` (not zero) and the opposite at `hi`; `0 <= lo < hi <= 1`.
pub(crate) fn floor_root(
    kind: Primitive,
    start: &[Point; 4],
    end: &[Point; 4],
    mut lo: f64,
    mut hi: f64,
    at_lo: Ordering,
) -> f64 {
    // Non-negative doubles are ordered as their bits: bisect on the bits.
    while hi.to_bits() - lo.to_bits() > 1 {
        let mid = f64::from_bits(lo.to_bits() + (hi.to_bits() - lo.to_bits()) / 2);
        match coplanarity_sign(kind, start, end, mid) {
            Ordering::Equal => return mid,
            s if s == at_lo => lo = mid,
            _ => hi = mid,
        }
    }
    lo
}
