//! Intervals about a double-double centre: a value is `hi + lo` (an unevaluated sum, `lo` at
//! most half a unit in the last place of `hi`) give or take `rad`. Each operation computes the
//! centre with error-free transformations and adds a proven bound on what it rounded off to
//! the radius, so the enclosure is certain. About 106 bits in the centre let values that are
//! rational functions of doubles round correctly from it in all but nearly singular cases,
//! where plain intervals are often a few units too wide.
//!
//! Underflow loses at most 2^-1075 per rounding: every radius that is not exactly zero
//! includes [`TINY`], far more than the few roundings of one operation lose. Overflow makes a
//! part infinite or NaN, which then spreads to the results; [`DdInterval::is_finite`] tells.

use std::ops::{Add, Mul, Neg, Sub};

const fn pow2(e: i64) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

/// Bounds the error of two or three roundings relative to the magnitudes rounded (each at most
/// 2^-53 of its result): 2^-51.
const REL: f64 = pow2(-51);
/// A radius computed in round-to-nearest from non-negative terms, times this, bounds the exact
/// radius: it covers far more roundings (each 2^-53 relative) than any formula here makes.
const SLACK: f64 = 1.0 + pow2(-45);
/// 2^-1050: more than underflow can lose in one operation (its roundings, each 2^-1075).
const TINY: f64 = f64::from_bits(1 << 24);
/// Magnitudes between `SAFE` and `BIG` leave products of two error-free (no underflow in the
/// error term, no overflow in Dekker's split), and neighbours two units away finite.
const SAFE: f64 = pow2(-900);
const BIG: f64 = pow2(900);

/// A closed interval `[hi + lo - rad, hi + lo + rad]` certainly holding the exact value.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DdInterval {
    pub hi: f64,
    pub lo: f64,
    pub rad: f64,
}

/// `a + b` as `s + e` exactly (Knuth), `s` the rounded sum.
#[inline(always)]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// How a product is split into its rounded value and its error. Both ways give the same
/// results: `a b` as `p + e` exactly when neither underflows nor overflows, `p` the rounded
/// product; otherwise `e` is off by underflow's few 2^-1075, or NaN.
pub(crate) trait Split {
    fn two_prod(a: f64, b: f64) -> (f64, f64);
}

/// The split the target is compiled for: the fused multiply-add where every processor of the
/// target has it, else Dekker's (several times the operations).
pub(crate) enum Plain {}

/// The fused multiply-add, for arithmetic inlined into a function compiled with it (see
/// [`crate::geometry::nearest`]'s values, chosen when the processor has it). Called elsewhere,
/// it is the C library's `fma`: as exact, but a call per product.
pub(crate) enum Fused {}

impl Split for Plain {
    #[inline(always)]
    fn two_prod(a: f64, b: f64) -> (f64, f64) {
        if cfg!(any(target_feature = "fma", target_arch = "aarch64")) {
            return Fused::two_prod(a, b);
        }
        let p = a * b;
        // Dekker: each factor split into halves of at most 26 bits, whose products are exact.
        let split = |x: f64| {
            let c = 134_217_729.0 * x;
            let h = c - (c - x);
            (h, x - h)
        };
        let ((ah, al), (bh, bl)) = (split(a), split(b));
        (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
    }
}

impl Split for Fused {
    #[inline(always)]
    fn two_prod(a: f64, b: f64) -> (f64, f64) {
        let p = a * b;
        (p, a.mul_add(b, -p))
    }
}

/// A radius computed in round-to-nearest from non-negative terms, made an upper bound on the
/// exact one (relative roundings and underflow both covered).
#[inline(always)]
fn up(x: f64) -> f64 {
    x * SLACK + TINY
}

impl DdInterval {
    /// The double-double `hi + lo`, exactly.
    #[inline(always)]
    pub(crate) fn exact(hi: f64, lo: f64) -> DdInterval {
        DdInterval { hi, lo, rad: 0.0 }
    }

    pub(crate) fn point(x: f64) -> DdInterval {
        DdInterval {
            hi: x,
            lo: 0.0,
            rad: 0.0,
        }
    }

    /// Exactly zero.
    fn is_zero(&self) -> bool {
        self.hi == 0.0 && self.lo == 0.0 && self.rad == 0.0
    }

    /// Exactly the double `hi`.
    fn is_double(&self) -> bool {
        self.lo == 0.0 && self.rad == 0.0
    }

    pub(crate) fn is_finite(&self) -> bool {
        self.hi.is_finite() && self.lo.is_finite() && self.rad.is_finite()
    }

    /// `self / d` for `d` certainly positive; `None` when `d` may hold zero or a magnitude is
    /// out of the safe range. The centre is the double-double quotient; the radius bounds
    /// `|x - c y| / |y|` for `x` in `self`, `y` in `d`, with `x - c y` enclosed by `self - c d`.
    #[inline(always)]
    pub(crate) fn divide<S: Split>(&self, d: &DdInterval) -> Option<DdInterval> {
        if !(self.is_finite() && d.is_finite() && d.hi >= SAFE && d.hi <= BIG) {
            return None;
        }
        // A lower bound on every value of `d`: `hi` less (a bound on |lo| + rad), rounded down.
        let below = (d.hi - (d.lo.abs() + d.rad) * SLACK) * (1.0 - pow2(-50));
        if below.is_nan() || below <= 0.0 {
            return None;
        }
        if self.is_zero() {
            return Some(*self);
        }
        let q0 = self.hi / d.hi;
        let r = *self - DdInterval::point(q0).times::<S>(*d);
        let (hi, lo) = two_sum(q0, (r.hi + r.lo) / d.hi);
        let c = DdInterval::exact(hi, lo);
        let residual = *self - c.times::<S>(*d);
        let rad = up((residual.hi.abs() + residual.lo.abs() + residual.rad) / below);
        let q = DdInterval { hi, lo, rad };
        q.is_finite().then_some(q)
    }

    /// The squared distance of points `a` and `b`, enclosed: the differences and their squares
    /// split exactly into double-double parts, summed with a bound on what the sum rounds off.
    /// The general operations would do the same at several times the cost (each checks for
    /// exact and zero operands and bounds cancellation); here every square is non-negative, so
    /// nothing cancels and one bound on the small parts' magnitudes covers every rounding.
    #[inline(always)]
    pub(crate) fn squared_distance<S: Split>(a: &[f64; 3], b: &[f64; 3]) -> DdInterval {
        // The large parts' sum is kept exactly as `hi` plus the errors `t`; everything else
        // (product errors, cross terms, the `t`s) is at most 2^-52 of the sum and goes to `small`.
        let (mut hi, mut small, mut size) = (0.0, 0.0, 0.0);
        for k in 0..3 {
            let (h, l) = two_sum(a[k], -b[k]);
            let (p, e) = S::two_prod(h, h);
            let (s, t) = two_sum(hi, p);
            hi = s;
            // (h + l)^2 = p + e + 2 h l + l^2.
            let c = (2.0 * h) * l + l * l;
            small += (t + e) + c;
            size += t.abs() + e.abs() + c.abs();
        }
        let (hi, lo) = two_sum(hi, small);
        // Each `c` is rounded three times (its partial sums no larger than `|c|`), and each
        // step of `small` three times (no larger than `size`): each rounding is at most 2^-53 of
        // its partial sum, 8 2^-53 `size` in all, half the radius. Underflow in them and in the
        // products' errors is covered by `up`.
        DdInterval {
            hi,
            lo,
            rad: up(4.0 * REL * size),
        }
    }

    /// The dot product of two vectors, enclosed: each centre product split exactly where its
    /// leading parts meet, the rest summed with one bound on what the sum rounds off, as
    /// [`DdInterval::squared_distance`] does. The general operations would compute the same
    /// centre at about twice the cost (each checks for exact and zero operands and bounds every
    /// step apart). Unlike a squared distance, the terms may cancel: every error is bounded by
    /// the terms' magnitudes, not the result's.
    #[inline(always)]
    pub(crate) fn dot<S: Split>(a: &[DdInterval; 3], b: &[DdInterval; 3]) -> DdInterval {
        let (mut hi, mut small, mut size, mut rest) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..3 {
            let (x, y) = (a[k], b[k]);
            let (p, e) = S::two_prod(x.hi, y.hi);
            let (s, t) = two_sum(hi, p);
            hi = s;
            // (h + l)(h' + l') = p + e + h l' + l h' + l l': the middle two rounded, the last
            // dropped (at most 2^-106 of the product) and bounded with the radii's spread.
            let (c0, c1) = (x.hi * y.lo, x.lo * y.hi);
            small += (t + e) + (c0 + c1);
            size += t.abs() + e.abs() + c0.abs() + c1.abs();
            rest += (x.lo * y.lo).abs()
                + (x.hi.abs() + x.lo.abs()) * y.rad
                + (y.hi.abs() + y.lo.abs()) * x.rad
                + x.rad * y.rad;
        }
        let (hi, lo) = two_sum(hi, small);
        // Per term, the two cross products and their sum are rounded (at most 2 2^-53 of the
        // products' magnitudes, both in `size`), and `small` takes three more roundings, each at
        // most 2^-53 of a partial sum no larger than `size`: 11 2^-53 `size` in all, under the
        // 16 2^-53 allowed. Underflow, and the rounding of `size` and `rest` (sums of
        // non-negative terms), are covered by `up`.
        DdInterval {
            hi,
            lo,
            rad: up(4.0 * REL * size + rest),
        }
    }

    /// A double within two units in the last place of every value, if there is one: `hi`, when
    /// every value lies within `2^-53 |hi|` of it, at most two of its units (a unit of `hi` is
    /// more than `2^-53 |hi|`, and at least half that below a power of two).
    #[inline]
    pub(crate) fn tight(&self) -> Option<f64> {
        let m = self.hi;
        let off = (self.lo.abs() + self.rad) * SLACK;
        // Both bounds in one test; false for NaN, infinities and magnitudes out of range.
        let ok = off <= m.abs() * pow2(-53) && (SAFE..=BIG).contains(&m.abs());
        (ok || (self.is_double() && m.is_finite())).then_some(m)
    }

    /// The square root of a value (not negative), within one unit in the last place of the
    /// correctly rounded root of every value, if there is one: `s`, the rounded root of `hi`,
    /// when every value lies between the squares of `s`'s neighbours (then its root does, and
    /// rounds to one of them or to `s`).
    #[inline(always)]
    pub(crate) fn tight_sqrt<S: Split>(&self) -> Option<f64> {
        if self.is_zero() {
            return Some(0.0);
        }
        if !(self.is_finite() && self.hi >= SAFE && self.hi <= BIG) {
            return None;
        }
        let s = self.hi.sqrt();
        // `s` lies within 2^±450, a positive normal: its neighbours are one bit pattern away,
        // and the gaps `g` below and `h` above are exact powers of two (Sterbenz).
        let bits = s.to_bits();
        let (g, h) = (s - f64::from_bits(bits - 1), f64::from_bits(bits + 1) - s);
        // A value `y` is `s^2 + delta`; it lies between the neighbours' squares exactly when
        // `-(2 s g - g^2) <= delta <= 2 s h + h^2`. `s^2 = p + e` exactly (no underflow at
        // this scale), and `hi - p` is exact (Sterbenz: `p` is within a factor two of `hi`), so
        // `delta` is `c` give or take `off`: the radius and `c`'s two roundings.
        let (p, e) = S::two_prod(s, s);
        let r = self.hi - p;
        let c = r + (self.lo - e);
        let off = up(self.rad + REL * (r.abs() + self.lo.abs() + e.abs())) * (1.0 + pow2(-50));
        // The gaps' bounds from below: `2 s g` and `g^2` are exact, their sum or difference
        // rounded once, then lowered past that rounding and their own with `c` below.
        let low = 1.0 - pow2(-50);
        let below = (2.0 * s * g - g * g) * low;
        let above = (2.0 * s * h + h * h) * low;
        // Each side rounded once: a rounded sum at least `off` (positive) is exactly at least
        // `off` less 2^-53 of it, which `off`'s own factor covers.
        (c + below >= off && above - c >= off).then_some(s)
    }
}

impl Neg for DdInterval {
    type Output = DdInterval;
    #[inline(always)]
    fn neg(self) -> DdInterval {
        DdInterval {
            hi: -self.hi,
            lo: -self.lo,
            rad: self.rad,
        }
    }
}

impl Add for DdInterval {
    type Output = DdInterval;
    #[inline(always)]
    fn add(self, o: DdInterval) -> DdInterval {
        let (s, e) = two_sum(self.hi, o.hi);
        let rad = self.rad + o.rad;
        if self.lo == 0.0 && o.lo == 0.0 {
            // s + e is the centres' sum exactly; exact sums stay exact.
            let rad = if rad == 0.0 { 0.0 } else { up(rad) };
            return DdInterval { hi: s, lo: e, rad };
        }
        // Rounded twice: (lo + lo') within 2^-53 of it, then plus e.
        let t = (self.lo + o.lo) + e;
        let (hi, lo) = two_sum(s, t);
        let err = REL * ((self.lo.abs() + o.lo.abs()) + e.abs());
        DdInterval {
            hi,
            lo,
            rad: up(rad + err),
        }
    }
}

impl Sub for DdInterval {
    type Output = DdInterval;
    #[inline(always)]
    fn sub(self, o: DdInterval) -> DdInterval {
        self + -o
    }
}

impl Mul for DdInterval {
    type Output = DdInterval;
    #[inline(always)]
    fn mul(self, o: DdInterval) -> DdInterval {
        self.times::<Plain>(o)
    }
}

impl DdInterval {
    /// The product, with the split `S`.
    #[inline(always)]
    pub(crate) fn times<S: Split>(self, o: DdInterval) -> DdInterval {
        // Products with an exact zero stay exact zeros (coordinates shared by both primitives),
        // whatever the other factor, even one that overflowed.
        if self.is_zero() || o.is_zero() {
            return DdInterval::point(0.0);
        }
        let (p, e) = S::two_prod(self.hi, o.hi);
        if self.is_double() && o.is_double() && (SAFE..=BIG).contains(&p.abs()) {
            return DdInterval::exact(p, e);
        }
        // (a + a')(b + b') = p + e + a b' + a' b + a' b': the last term is dropped, the middle
        // two are rounded three times (two products, one sum) and once more added to e.
        let (a, a2, b, b2) = (self.hi, self.lo, o.hi, o.lo);
        let (ab2, a2b) = (a * b2, a2 * b);
        let t = (ab2 + a2b) + e;
        let (hi, lo) = two_sum(p, t);
        let err = (a2 * b2).abs() + REL * (ab2.abs() + a2b.abs() + e.abs());
        // The radii spread through the centres' magnitudes.
        let spread =
            (a.abs() + a2.abs()) * o.rad + (b.abs() + b2.abs()) * self.rad + self.rad * o.rad;
        DdInterval {
            hi,
            lo,
            rad: up(spread + err),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::Rng;
    use crate::geometry::chains::random_double;
    use num_rational::BigRational;
    use num_traits::{Signed, ToPrimitive};

    type Q = BigRational;

    fn q(x: f64) -> Q {
        Q::from_float(x).unwrap()
    }

    /// Does `x` hold `v`?
    fn holds(x: &DdInterval, v: &Q) -> bool {
        let c = q(x.hi) + q(x.lo);
        (v - c).abs() <= q(x.rad)
    }

    /// Is `s` within one unit of the correctly rounded root of `v`? One of `s` and its
    /// neighbours rounds the root: its rounding interval's ends, squared, bracket `v`.
    fn root_near(s: f64, v: &Q) -> bool {
        let two = q(2.0);
        let rounds = |c: f64| {
            let lo = (q(c.next_down().max(0.0)) + q(c)) / &two;
            let hi = (q(c) + q(c.next_up())) / &two;
            &lo * &lo <= *v && *v <= &hi * &hi
        };
        [s.next_down(), s, s.next_up()].into_iter().any(rounds)
    }

    #[test]
    fn enclosures_hold_the_exact_results_of_random_operations() {
        random_operations::<Plain>();
        random_operations::<Fused>();
    }

    fn random_operations<S: Split>() {
        let mut rng = Rng::new(0xdd_1e7e);
        let mut tight = 0;
        let n = crate::fixtures::cases(1000, 4000);
        for case in 0..n {
            // Normal magnitudes, then extreme ones where underflow and overflow happen.
            let span = [4, 40, 600, 1100][case % 4];
            let mut xs: Vec<(DdInterval, Q)> = (0..6)
                .map(|_| {
                    let x = random_double(&mut rng, span);
                    (DdInterval::point(x), q(x))
                })
                .collect();
            for _ in 0..24 {
                let (i, j) = (
                    rng.below(xs.len() as u64) as usize,
                    rng.below(xs.len() as u64) as usize,
                );
                let ((a, qa), (b, qb)) = (xs[i].clone(), xs[j].clone());
                let got = match rng.below(5) {
                    0 => Some((a + b, &qa + &qb)),
                    1 => Some((a - b, &qa - &qb)),
                    2 | 3 => Some((a.times::<S>(b), &qa * &qb)),
                    _ => a.divide::<S>(&b).map(|x| {
                        // Only a divisor certainly positive is accepted.
                        assert!(qb.is_positive(), "{b:?}");
                        (x, &qa / &qb)
                    }),
                };
                let Some((x, v)) = got else { continue };
                if !x.is_finite() {
                    continue;
                }
                assert!(
                    holds(&x, &v),
                    "{a:?} {b:?} -> {x:?}, exact {}",
                    v.to_f64().unwrap()
                );
                if let Some(m) = x.tight() {
                    // Within two units of the exact value rounded.
                    let w = v.to_f64().unwrap();
                    let near = [m, m.next_up(), m.next_up().next_up(), m.next_down()]
                        .into_iter()
                        .chain([m.next_down().next_down()]);
                    assert!(near.into_iter().any(|n| n == w), "{x:?}: {m} against {w}");
                    if x.rad > 0.0 {
                        tight += 1;
                    }
                }
                if v.is_positive()
                    && let Some(s) = x.tight_sqrt::<S>()
                {
                    assert!(root_near(s, &v), "{x:?}: root {s}");
                }
                let k = rng.below(xs.len() as u64) as usize;
                xs[k] = (x, v);
            }
        }
        // The rounding is not vacuous: inexact results were rounded.
        assert!(tight > n * 5 / 2, "{tight}");
    }

    #[test]
    fn squared_distances_hold_the_exact_value_and_round_their_root() {
        squared_distances::<Plain>();
        squared_distances::<Fused>();
    }

    fn squared_distances<S: Split>() {
        let mut rng = Rng::new(0x5eed_d157);
        let mut rounded = 0;
        let n = crate::fixtures::cases(1000, 4000);
        for case in 0..n {
            // Normal magnitudes, extreme ones, and points close together far from the origin.
            let span = [4, 40, 600, 1100][case % 4];
            let a: [f64; 3] = std::array::from_fn(|_| random_double(&mut rng, span));
            let b: [f64; 3] = if case % 3 == 0 {
                a.map(|x| x * (1.0 + rng.range(-1e-9, 1e-9)))
            } else {
                std::array::from_fn(|_| random_double(&mut rng, span))
            };
            let x = DdInterval::squared_distance::<S>(&a, &b);
            let exact: Q = (0..3)
                .map(|k| (q(a[k]) - q(b[k])) * (q(a[k]) - q(b[k])))
                .sum();
            if !x.is_finite() {
                continue;
            }
            assert!(holds(&x, &exact), "{a:?} {b:?} -> {x:?}");
            if let Some(s) = x.tight_sqrt::<S>() {
                assert!(root_near(s, &exact), "{a:?} {b:?}: root {s}");
                rounded += 1;
            }
        }
        // Every finite case in range is rounded: the enclosure is as tight as its centre.
        assert!(rounded > n * 5 / 8, "{rounded}");
    }

    /// A root is claimed only where every value of the enclosure lies between the squares of
    /// its neighbours, and claimed wherever they do with room to spare: enclosures of every
    /// width about a double-double centre, the answer checked in rationals.
    #[test]
    fn a_root_is_claimed_exactly_where_the_enclosure_allows() {
        let mut rng = Rng::new(0x5a7_0f7e);
        let (mut claimed, mut roomy) = (0, 0);
        for _ in 0..20_000 {
            let hi = rng.range(1.0, 4.0) * pow2(rng.below(1600) as i64 - 800);
            let unit = hi - hi.next_down();
            let lo = rng.range(-0.5, 0.5) * unit;
            let rad = [0.0, pow2(-60) * hi, rng.range(0.0, 3.0) * unit][rng.below(3) as usize];
            let x = DdInterval { hi, lo, rad };
            let s = hi.sqrt();
            let (below, above) = (q(s.next_down()), q(s.next_up()));
            let (centre, r) = (q(hi) + q(lo), q(rad));
            // How far the enclosure keeps inside the neighbours' squares, at its nearer end.
            let room = (&centre - &r - &below * &below).min(&above * &above - &centre - &r);
            let root = x.tight_sqrt::<Plain>();
            assert_eq!(root, x.tight_sqrt::<Fused>(), "{x:?}");
            match root {
                Some(root) => {
                    assert_eq!(root, s);
                    assert!(
                        !room.is_negative(),
                        "{x:?}: claimed {s} outside the squares"
                    );
                    claimed += 1;
                }
                // Twice the room the enclosure takes (and what rounding its centre may take,
                // far less): the test must claim it.
                None => {
                    let slack = r.clone() + r + q(pow2(-98) * hi);
                    assert!(room <= slack, "{x:?}: not claimed, room {room}");
                }
            }
            if room > q(0.0) {
                roomy += 1;
            }
        }
        assert!(claimed > 5000 && roomy > claimed / 2, "{claimed} {roomy}");
    }

    /// The two splits give the same parts wherever the error is exact (no underflow), so the
    /// arithmetic built on them gives the same results either way.
    #[test]
    fn both_splits_give_the_same_parts() {
        let mut rng = Rng::new(0x0005_b117);
        for case in 0..100_000 {
            let span = [4, 40, 400][case % 3];
            let (a, b) = (random_double(&mut rng, span), random_double(&mut rng, span));
            let fused = Fused::two_prod(a, b);
            assert_eq!(Plain::two_prod(a, b), fused, "{a:e} * {b:e}");
            assert_eq!(q(fused.0) + q(fused.1), q(a) * q(b), "{a:e} * {b:e}");
        }
    }

    #[test]
    fn roots_of_squares_and_products() {
        let mut rng = Rng::new(0x05ee_d0f5);
        for _ in 0..2000 {
            // An exact square of a double: its root is the double.
            let x = rng.range(1.0, 2.0) * pow2(rng.below(800) as i64 - 400);
            let sq = DdInterval::point(x) * DdInterval::point(x);
            assert_eq!(sq.tight_sqrt::<Plain>(), Some(x), "{x}");
            // A product of three: within one unit of the correctly rounded root.
            let y = rng.range(0.5, 2.0);
            let z = rng.range(0.5, 2.0);
            let p = DdInterval::point(x) * DdInterval::point(y) * DdInterval::point(z);
            let exact = q(x) * q(y) * q(z);
            assert!(holds(&p, &exact));
            let s = p.tight_sqrt::<Plain>().expect("a tight root");
            assert!(root_near(s, &exact), "{p:?}: root {s}");
        }
    }
}
