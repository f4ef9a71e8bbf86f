//! Exact univariate polynomials over the rationals and their real roots in an interval: what
//! the exact continuous tests decide with. The polynomials have degree at most 3 or so and are
//! built from doubles (which are rationals), so plain big-rational arithmetic is simple and
//! quick enough for the cases the floating-point filters cannot decide.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Zero};
use std::cmp::Ordering;

/// A polynomial `c[0] + c[1] t + c[2] t² + …` with rational coefficients, without trailing zero
/// coefficients (the zero polynomial has none).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Poly(Vec<BigRational>);

/// An exact rational from a finite double.
pub(crate) fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite coordinates only")
}

impl Poly {
    /// The polynomial with these coefficients, lowest degree first.
    pub(crate) fn new(mut c: Vec<BigRational>) -> Poly {
        while c.last().is_some_and(Zero::is_zero) {
            c.pop();
        }
        Poly(c)
    }

    /// `start + t (end - start)`: a coordinate moving linearly from `start` to `end`.
    pub(crate) fn motion(start: f64, end: f64) -> Poly {
        let s = rational(start);
        let d = rational(end) - &s;
        Poly::new(vec![s, d])
    }

    /// `start + t (end - start)` for integer ends.
    pub(crate) fn motion_int(start: BigInt, end: BigInt) -> Poly {
        let d = &end - &start;
        Poly::new(vec![
            BigRational::from_integer(start),
            BigRational::from_integer(d),
        ])
    }

    /// A constant.
    #[cfg(test)]
    pub(crate) fn constant(c: BigRational) -> Poly {
        Poly::new(vec![c])
    }

    /// Is this the zero polynomial?
    pub(crate) fn is_zero(&self) -> bool {
        self.0.is_empty()
    }

    /// The degree (`None` for the zero polynomial).
    pub(crate) fn degree(&self) -> Option<usize> {
        self.0.len().checked_sub(1)
    }

    fn lead(&self) -> &BigRational {
        self.0.last().expect("a non-zero polynomial")
    }

    pub(crate) fn add(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        let z = BigRational::zero();
        Poly::new(
            (0..n)
                .map(|i| self.0.get(i).unwrap_or(&z) + o.0.get(i).unwrap_or(&z))
                .collect(),
        )
    }

    pub(crate) fn sub(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        let z = BigRational::zero();
        Poly::new(
            (0..n)
                .map(|i| self.0.get(i).unwrap_or(&z) - o.0.get(i).unwrap_or(&z))
                .collect(),
        )
    }

    pub(crate) fn mul(&self, o: &Poly) -> Poly {
        if self.is_zero() || o.is_zero() {
            return Poly(Vec::new());
        }
        let mut c = vec![BigRational::zero(); self.0.len() + o.0.len() - 1];
        for (i, a) in self.0.iter().enumerate() {
            for (j, b) in o.0.iter().enumerate() {
                c[i + j] += a * b;
            }
        }
        Poly::new(c)
    }

    fn scale(&self, k: &BigRational) -> Poly {
        Poly::new(self.0.iter().map(|c| c * k).collect())
    }

    pub(crate) fn derivative(&self) -> Poly {
        Poly::new(
            self.0
                .iter()
                .enumerate()
                .skip(1)
                .map(|(i, c)| c * BigRational::from_integer(BigInt::from(i)))
                .collect(),
        )
    }

    /// The value at `x` (Horner).
    pub(crate) fn eval(&self, x: &BigRational) -> BigRational {
        let mut v = BigRational::zero();
        for c in self.0.iter().rev() {
            v = v * x + c;
        }
        v
    }

    /// The sign of the value at `x`.
    pub(crate) fn sign_at(&self, x: &BigRational) -> Ordering {
        let d = x.denom();
        if d.bits() == d.trailing_zeros().unwrap_or(0) + 1 {
            return self.sign_at_dyadic(x.numer(), d.bits() - 1);
        }
        self.eval(x).cmp(&BigRational::zero())
    }

    /// The sign of the value at `m / 2^k`, in integers: the value times `2^(k · degree)` and
    /// the product of the coefficients' denominators, both positive, is
    /// `sum a_i m^i 2^(k (degree - i))` with integer `a_i`. The points the root search and the
    /// rounding to doubles evaluate at are all of this form; rationals would reduce every
    /// intermediate by a gcd, which costs more than the arithmetic.
    fn sign_at_dyadic(&self, m: &BigInt, k: u64) -> Ordering {
        let Some(deg) = self.degree() else {
            return Ordering::Equal;
        };
        // a_i = numerator_i times the other coefficients' denominators.
        let a: Vec<BigInt> = (0..=deg)
            .map(|i| {
                let mut x = self.0[i].numer().clone();
                for (j, c) in self.0.iter().enumerate() {
                    if j != i && !c.denom().is_one() {
                        x *= c.denom();
                    }
                }
                x
            })
            .collect();
        let mut v = a[deg].clone();
        for i in (0..deg).rev() {
            v = v * m + (&a[i] << (k * (deg - i) as u64));
        }
        match v.sign() {
            num_bigint::Sign::Minus => Ordering::Less,
            num_bigint::Sign::NoSign => Ordering::Equal,
            num_bigint::Sign::Plus => Ordering::Greater,
        }
    }

    /// Quotient and remainder of the division by non-zero `d`.
    fn div_rem(&self, d: &Poly) -> (Poly, Poly) {
        let dd = d.degree().expect("division by the zero polynomial");
        let mut r = self.0.clone();
        let mut q = vec![BigRational::zero(); r.len().saturating_sub(dd)];
        let lead = d.lead();
        while r.len() > dd && !r.is_empty() {
            let k = r.len() - 1 - dd;
            let f = r.last().expect("non-empty") / lead;
            for (i, c) in d.0.iter().enumerate() {
                r[k + i] -= &f * c;
            }
            q[k] = f;
            r.pop();
            while r.last().is_some_and(Zero::is_zero) {
                r.pop();
            }
        }
        (Poly::new(q), Poly::new(r))
    }

    /// The monic greatest common divisor (zero only when both are zero).
    pub(crate) fn gcd(&self, o: &Poly) -> Poly {
        let (mut a, mut b) = (self.clone(), o.clone());
        while !b.is_zero() {
            let r = a.div_rem(&b).1;
            a = b;
            b = r;
        }
        if a.is_zero() {
            return a;
        }
        let inv = a.lead().recip();
        a.scale(&inv)
    }

    /// The polynomial with the same roots, each simple.
    pub(crate) fn squarefree(&self) -> Poly {
        let g = self.gcd(&self.derivative());
        if g.degree().unwrap_or(0) == 0 {
            return self.clone();
        }
        self.div_rem(&g).0
    }

    /// The Sturm sequence of a squarefree polynomial.
    fn sturm(&self) -> Vec<Poly> {
        let mut s = vec![self.clone(), self.derivative()];
        loop {
            let n = s.len();
            if s[n - 1].is_zero() {
                s.pop();
                return s;
            }
            let r = s[n - 2].div_rem(&s[n - 1]).1;
            if r.is_zero() {
                return s;
            }
            s.push(Poly::new(r.0.into_iter().map(|c| -c).collect()));
        }
    }

    /// The real roots in the closed interval `[lo, hi]` of this non-zero polynomial, each
    /// isolated, in increasing order.
    pub(crate) fn roots_in(&self, lo: &BigRational, hi: &BigRational) -> Vec<Root> {
        assert!(!self.is_zero(), "the zero polynomial vanishes everywhere");
        if self.degree() == Some(1) {
            // A line's one root, exactly (half the condition's polynomials are lines).
            let x = -&self.0[0] / &self.0[1];
            return if *lo <= x && x <= *hi {
                vec![Root::exact(self, x)]
            } else {
                Vec::new()
            };
        }
        let p = self.squarefree();
        if p.degree() == Some(0) {
            return Vec::new();
        }
        let sturm = p.sturm();
        let mut out = Vec::new();
        if p.sign_at(lo).is_eq() {
            out.push(Root::exact(&p, lo.clone()));
        }
        let mut open = Vec::new();
        if lo < hi {
            open.push((lo.clone(), hi.clone()));
        }
        let mut found = Vec::new();
        // Bisection on open intervals whose ends are not roots; a middle that is a root is
        // recorded and both sides continue from it (Sturm counts half-open intervals (a, b]).
        while let Some((a, b)) = open.pop() {
            let n = sturm_count(&sturm, &a, &b);
            if n == 0 {
                continue;
            }
            if n == 1 && p.sign_at(&b).is_eq() {
                found.push(Root::exact(&p, b));
                continue;
            }
            // An isolating interval must not end on a root (the left end may be one: the
            // interval's lower bound, or a middle found as a root).
            if n == 1 && !p.sign_at(&a).is_eq() {
                found.push(Root {
                    poly: p.clone(),
                    lo: a,
                    hi: b,
                });
                continue;
            }
            let m = (&a + &b) / BigRational::from_integer(2.into());
            open.push((a, m.clone()));
            open.push((m, b));
        }
        out.extend(found);
        out.sort_by(|x, y| x.cmp(y));
        out.dedup_by(|x, y| x.cmp(y).is_eq());
        out
    }
}

/// Distinct roots in `(a, b]` of the squarefree polynomial whose Sturm sequence this is.
fn sturm_count(s: &[Poly], a: &BigRational, b: &BigRational) -> usize {
    variations(s, a) - variations(s, b)
}

fn variations(s: &[Poly], x: &BigRational) -> usize {
    let mut last = Ordering::Equal;
    let mut n = 0;
    for p in s {
        let v = p.sign_at(x);
        if v.is_eq() {
            continue;
        }
        if !last.is_eq() && v != last {
            n += 1;
        }
        last = v;
    }
    n
}

/// A real root of a squarefree polynomial: `lo == hi`, the root itself; or `lo < hi`, the only
/// root in the open interval `(lo, hi)`, at neither end.
#[derive(Clone, Debug)]
pub(crate) struct Root {
    poly: Poly,
    lo: BigRational,
    hi: BigRational,
}

impl Root {
    fn exact(p: &Poly, x: BigRational) -> Root {
        Root {
            poly: p.clone(),
            lo: x.clone(),
            hi: x,
        }
    }

    /// Is the root a known rational?
    pub(crate) fn is_exact(&self) -> bool {
        self.lo == self.hi
    }

    /// Halves the isolating interval (or finds the root exactly at its middle).
    fn refine(&mut self) {
        if self.is_exact() {
            return;
        }
        let m = (&self.lo + &self.hi) / BigRational::from_integer(2.into());
        let s = self.poly.sign_at(&m);
        if s.is_eq() {
            self.lo = m.clone();
            self.hi = m;
        } else if s == self.poly.sign_at(&self.lo) {
            self.lo = m;
        } else {
            self.hi = m;
        }
    }

    /// The sign of `q` at the root.
    pub(crate) fn sign_of(&mut self, q: &Poly) -> Ordering {
        if q.is_zero() {
            return Ordering::Equal;
        }
        if self.is_exact() {
            return q.sign_at(&self.lo);
        }
        if q.degree() == Some(1) {
            // A line: its one root x decides, without a gcd. Outside (lo, hi), q keeps one sign
            // over the interval; inside, the root is x exactly when p vanishes there (p has no
            // other root in the interval), and otherwise lies on the side where p keeps its
            // sign at lo.
            let x = -&q.0[0] / &q.0[1];
            if x <= self.lo || x >= self.hi {
                let end = if x <= self.lo { &self.hi } else { &self.lo };
                return q.sign_at(end);
            }
            let at_x = self.poly.sign_at(&x);
            if at_x.is_eq() {
                return Ordering::Equal;
            }
            // The root is above x when p has at x the sign it has at lo.
            let above = at_x == self.poly.sign_at(&self.lo);
            return q.sign_at(if above { &self.hi } else { &self.lo });
        }
        // The root is a root of q exactly when it is one of gcd(p, q), which has at most this
        // one root in (lo, hi) (its roots are p's), so a sign change there tells.
        let g = self.poly.gcd(q);
        if g.degree().unwrap_or(0) > 0 && g.sign_at(&self.lo) != g.sign_at(&self.hi) {
            return Ordering::Equal;
        }
        // Otherwise q keeps one sign near the root: narrow until q has no root in [lo, hi].
        let qs = q.squarefree();
        let sturm = qs.sturm();
        loop {
            if self.is_exact() {
                return q.sign_at(&self.lo);
            }
            let (slo, shi) = (q.sign_at(&self.lo), q.sign_at(&self.hi));
            if !slo.is_eq() && slo == shi && sturm_count(&sturm, &self.lo, &self.hi) == 0 {
                return slo;
            }
            self.refine();
        }
    }

    /// Compares two roots exactly.
    pub(crate) fn cmp(&self, o: &Root) -> Ordering {
        if self.equals(o) {
            return Ordering::Equal;
        }
        // Distinct roots: narrow both until their intervals part.
        let (mut a, mut b) = (self.clone(), o.clone());
        loop {
            if a.hi <= b.lo {
                return Ordering::Less;
            }
            if b.hi <= a.lo {
                return Ordering::Greater;
            }
            a.refine();
            b.refine();
        }
    }

    /// Are the two roots the same number?
    fn equals(&self, o: &Root) -> bool {
        match (self.is_exact(), o.is_exact()) {
            (true, true) => self.lo == o.lo,
            (true, false) => o.holds_exact(&self.lo),
            (false, true) => self.holds_exact(&o.lo),
            (false, false) => {
                // A common root lies in both open intervals, where each polynomial has only
                // this one; so the two are equal exactly when the gcd has a root in the
                // intersection (whose ends are roots of neither, hence not of the gcd).
                let g = self.poly.gcd(&o.poly);
                let lo = (&self.lo).max(&o.lo);
                let hi = (&self.hi).min(&o.hi);
                g.degree().unwrap_or(0) > 0 && lo < hi && !g.roots_in(lo, hi).is_empty()
            }
        }
    }

    /// Is `x` this (inexact) root?
    fn holds_exact(&self, x: &BigRational) -> bool {
        *x > self.lo && *x < self.hi && self.poly.sign_at(x).is_eq()
    }

    /// The largest double not above the root (which lies in [0, 1]): a bisection over the
    /// doubles between the isolating interval's ends, each decided by the polynomial's exact
    /// sign at a double.
    pub(crate) fn floor_f64(&mut self) -> f64 {
        if self.is_exact() {
            return floor_f64(&self.lo);
        }
        let at_lo = self.poly.sign_at(&self.lo);
        // Is the double t at most the root?
        let below = |t: f64| -> bool {
            let q = rational(t);
            if q <= self.lo {
                return true;
            }
            if q >= self.hi {
                return false;
            }
            match self.poly.sign_at(&q) {
                Ordering::Equal => true,
                s => s == at_lo,
            }
        };
        let mut a = floor_f64(&self.lo);
        let mut b = floor_f64(&self.hi).next_up();
        debug_assert!(a >= 0.0 && below(a) && !below(b));
        // Non-negative doubles are ordered as their bits.
        while b.to_bits() - a.to_bits() > 1 {
            let mid = f64::from_bits(a.to_bits() + (b.to_bits() - a.to_bits()) / 2);
            if below(mid) {
                a = mid;
            } else {
                b = mid;
            }
        }
        a
    }
}

/// The largest double not above `x` (which must lie within the doubles' range).
pub(crate) fn floor_f64(x: &BigRational) -> f64 {
    use num_traits::ToPrimitive;
    let mut f = x.to_f64().unwrap_or(0.0);
    while rational(f) > *x {
        f = f.next_down();
    }
    while rational(f.next_up()) <= *x {
        f = f.next_up();
    }
    f
}

/// One, as a rational.
pub(crate) fn one() -> BigRational {
    BigRational::one()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> BigRational {
        BigRational::new(n.into(), d.into())
    }

    fn poly(c: &[i64]) -> Poly {
        Poly::new(c.iter().map(|&x| q(x, 1)).collect())
    }

    /// The integer evaluation at dyadic points agrees with rational Horner, for rational
    /// coefficients of every sign and size, at points with and without powers of two below.
    #[test]
    fn signs_at_dyadic_points_are_those_of_the_rational_value() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % 2001) as i64 - 1000
        };
        for _ in 0..2000 {
            let deg = (next().unsigned_abs() % 4) as usize;
            let c: Vec<BigRational> = (0..=deg).map(|_| q(next(), 1 + next().abs() % 7)).collect();
            let p = Poly::new(c);
            let k = (next().unsigned_abs() % 12) as i32;
            let t = q(next(), 1) / BigRational::from_integer(BigInt::from(2).pow(k as u32));
            assert_eq!(
                p.sign_at(&t),
                p.eval(&t).cmp(&BigRational::zero()),
                "{p:?} at {t}"
            );
        }
    }

    #[test]
    fn arithmetic_and_gcd() {
        let a = poly(&[-1, 0, 1]); // t² - 1
        let b = poly(&[1, 1]); // t + 1
        assert_eq!(a.gcd(&b), b);
        assert_eq!(b.mul(&poly(&[-1, 1])), a);
        assert_eq!(a.derivative(), poly(&[0, 2]));
        let c = poly(&[0, 0, 1]).mul(&poly(&[-1, 2])); // t² (2t - 1)
        assert_eq!(c.squarefree().degree(), Some(2));
        assert!(a.sub(&a).is_zero());
    }

    #[test]
    fn roots_in_the_unit_interval_are_isolated_and_ordered() {
        let (z, o) = (BigRational::zero(), one());
        // (t)(2t - 1)(3t - 2)(t - 1): roots 0, 1/2, 2/3, 1, all on the interval or at its ends.
        let p = poly(&[0, 1])
            .mul(&poly(&[-1, 2]))
            .mul(&poly(&[-2, 3]))
            .mul(&poly(&[-1, 1]));
        let mut r = p.roots_in(&z, &o);
        assert_eq!(r.len(), 4);
        let want = [q(0, 1), q(1, 2), q(2, 3), q(1, 1)];
        for (root, w) in r.iter_mut().zip(&want) {
            assert_eq!(
                root.sign_of(&poly(&[0, 1]).sub(&Poly::constant(w.clone()))),
                Ordering::Equal
            );
        }
        // t² - 1/2: one root, irrational, 0.7071…
        let mut s = Poly::new(vec![q(-1, 2), q(0, 1), q(1, 1)]).roots_in(&z, &o);
        assert_eq!(s.len(), 1);
        let f = s[0].floor_f64();
        assert_eq!(f, std::f64::consts::FRAC_1_SQRT_2.next_down().max(f));
        assert!(rational(f) * rational(f) < q(1, 2));
        assert!(rational(f.next_up()) * rational(f.next_up()) > q(1, 2));
        // A double root inside: (3t - 1)², counted once.
        assert_eq!(
            poly(&[-1, 3]).mul(&poly(&[-1, 3])).roots_in(&z, &o).len(),
            1
        );
        // No roots.
        assert!(poly(&[1, 0, 1]).roots_in(&z, &o).is_empty());
    }

    #[test]
    fn roots_compare_exactly() {
        let (z, o) = (BigRational::zero(), one());
        let r2 = Poly::new(vec![q(-1, 2), q(0, 1), q(1, 1)])
            .roots_in(&z, &o)
            .remove(0); // √½
        let r4 = Poly::new(vec![q(-1, 4), q(0, 1), q(0, 1), q(0, 1), q(1, 1)])
            .roots_in(&z, &o)
            .remove(0); // ⁴√¼ = √½
        let r3 = poly(&[-5, 7]).roots_in(&z, &o).remove(0); // 5/7 = 0.714…
        assert_eq!(r2.cmp(&r4), Ordering::Equal);
        assert_eq!(r2.cmp(&r3), Ordering::Less);
        assert_eq!(r3.cmp(&r4), Ordering::Greater);
        let mut r2 = r2;
        assert_eq!(r2.sign_of(&poly(&[-1, 0, 2])), Ordering::Equal);
        assert_eq!(r2.sign_of(&poly(&[-5, 7])), Ordering::Less);
    }

    #[test]
    fn floor_to_double_is_the_largest_double_not_above() {
        for x in [q(1, 3), q(1, 10), q(0, 1), q(1, 1), q(2, 3)] {
            let f = floor_f64(&x);
            assert!(rational(f) <= x && rational(f.next_up()) > x, "{x}");
        }
    }
}
