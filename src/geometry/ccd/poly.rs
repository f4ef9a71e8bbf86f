//! Exact univariate polynomials and their real roots in an interval: what the exact continuous
//! tests decide with. The polynomials (degree at most 3 or so) are built over the rationals from
//! doubles; roots are isolated, compared and signs decided at them with positive integer
//! multiples of them ([`ZPoly`]), which have the same roots and signs. Fractions would be
//! reduced by a gcd after every operation, which on coordinates far apart in magnitude (a
//! thousand bits and more once scaled to integers) costs far more than the arithmetic.
//!
//! Nothing here bisects to tell roots apart or to find a sign at a root: lines and quadratics
//! are compared with a root through their own roots in closed form, anything else by a Tarski
//! query (the signed remainder sequence of `p` and `p' q`); neither's cost depends on how
//! close the roots are. Isolating the roots of one polynomial splits intervals near its
//! critical points, which separates close roots at once, and halves them otherwise.

use num_bigint::{BigInt, Sign};
use num_rational::BigRational;
use num_traits::{One, Zero};
use std::cmp::Ordering;

/// A polynomial `c[0] + c[1] t + c[2] t² + …` with rational coefficients: integer coefficients
/// over one positive denominator, so that its arithmetic is in integers (no fraction to reduce
/// after each operation). The polynomials the exact path builds have denominator 1.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Poly {
    num: ZPoly,
    den: BigInt,
}

/// An exact rational from a finite double.
pub(crate) fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite coordinates only")
}

impl Poly {
    /// The polynomial with these coefficients, lowest degree first.
    pub(crate) fn new(c: Vec<BigRational>) -> Poly {
        // The product of the distinct denominators: positive, and a multiple of each.
        let mut den = BigInt::one();
        for x in &c {
            if !(&den % x.denom()).is_zero() {
                den *= x.denom();
            }
        }
        let num = c.iter().map(|x| x.numer() * (&den / x.denom())).collect();
        Poly {
            num: ZPoly::new(num),
            den,
        }
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
        Poly {
            num: ZPoly::new(vec![start, d]),
            den: BigInt::one(),
        }
    }

    /// A constant.
    #[cfg(test)]
    pub(crate) fn constant(c: BigRational) -> Poly {
        Poly::new(vec![c])
    }

    /// Is this the zero polynomial?
    pub(crate) fn is_zero(&self) -> bool {
        self.num.is_zero()
    }

    /// `self + sign · o`, over the product of the denominators when they differ.
    fn combine(&self, o: &Poly, sign: Sign) -> Poly {
        let (a, b, den) = if self.den == o.den {
            (self.num.clone(), o.num.clone(), self.den.clone())
        } else {
            (
                self.num.scale(&o.den),
                o.num.scale(&self.den),
                &self.den * &o.den,
            )
        };
        let n = a.0.len().max(b.0.len());
        let z = BigInt::zero();
        let c = (0..n).map(|i| {
            let (x, y) = (a.0.get(i).unwrap_or(&z), b.0.get(i).unwrap_or(&z));
            if sign == Sign::Minus { x - y } else { x + y }
        });
        Poly {
            num: ZPoly::new(c.collect()),
            den,
        }
    }

    pub(crate) fn add(&self, o: &Poly) -> Poly {
        self.combine(o, Sign::Plus)
    }

    pub(crate) fn sub(&self, o: &Poly) -> Poly {
        self.combine(o, Sign::Minus)
    }

    pub(crate) fn mul(&self, o: &Poly) -> Poly {
        Poly {
            num: self.num.mul(&o.num),
            den: &self.den * &o.den,
        }
    }

    #[cfg(test)]
    pub(crate) fn derivative(&self) -> Poly {
        Poly {
            num: self.num.derivative(),
            den: self.den.clone(),
        }
    }

    /// The value at `x` (Horner).
    #[cfg(test)]
    pub(crate) fn eval(&self, x: &BigRational) -> BigRational {
        let mut v = BigRational::zero();
        for c in self.num.0.iter().rev() {
            v = v * x + BigRational::from_integer(c.clone());
        }
        v / BigRational::from_integer(self.den.clone())
    }

    /// The sign of the value at `x`.
    pub(crate) fn sign_at(&self, x: &BigRational) -> Ordering {
        self.num.sign_at(x)
    }

    /// A positive multiple with integer coefficients: the same roots and the same signs.
    pub(crate) fn integer(&self) -> &ZPoly {
        &self.num
    }

    /// The real roots in the closed interval `[lo, hi]` of this non-zero polynomial, each
    /// isolated, in increasing order.
    pub(crate) fn roots_in(&self, lo: &BigRational, hi: &BigRational) -> Vec<Root> {
        assert!(!self.is_zero(), "the zero polynomial vanishes everywhere");
        self.num.roots_in(lo, hi)
    }
}

/// A polynomial `c[0] + c[1] t + …` with integer coefficients, without trailing zeros. Used
/// only up to positive factors: remainders are pseudo-remainders made positive multiples of
/// the true ones, which keeps every sign, every root and every Sturm count.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct ZPoly(Vec<BigInt>);

impl ZPoly {
    fn new(mut c: Vec<BigInt>) -> ZPoly {
        while c.last().is_some_and(Zero::is_zero) {
            c.pop();
        }
        ZPoly(c)
    }

    fn is_zero(&self) -> bool {
        self.0.is_empty()
    }

    fn degree(&self) -> Option<usize> {
        self.0.len().checked_sub(1)
    }

    fn derivative(&self) -> ZPoly {
        ZPoly::new(
            self.0
                .iter()
                .enumerate()
                .skip(1)
                .map(|(i, c)| c * BigInt::from(i))
                .collect(),
        )
    }

    fn mul(&self, o: &ZPoly) -> ZPoly {
        if self.is_zero() || o.is_zero() {
            return ZPoly(Vec::new());
        }
        let mut c = vec![BigInt::zero(); self.0.len() + o.0.len() - 1];
        for (i, a) in self.0.iter().enumerate() {
            for (j, b) in o.0.iter().enumerate() {
                c[i + j] += a * b;
            }
        }
        ZPoly::new(c)
    }

    fn scale(&self, k: &BigInt) -> ZPoly {
        ZPoly::new(self.0.iter().map(|c| c * k).collect())
    }

    fn neg(mut self) -> ZPoly {
        for c in &mut self.0 {
            *c = -std::mem::take(c);
        }
        self
    }

    /// Pseudo-division by non-zero `d`: `(q, r)` with `k · self = q · d + r`, `deg r < deg d`,
    /// for some `k > 0` (a power of `d`'s leading coefficient, both negated when that power is
    /// negative).
    fn pseudo_div(&self, d: &ZPoly) -> (ZPoly, ZPoly) {
        let dd = d.degree().expect("division by the zero polynomial");
        let lead = &d.0[dd];
        let mut r = self.0.clone();
        let mut q = vec![BigInt::zero(); r.len().saturating_sub(dd)];
        let mut steps = 0u32;
        while r.len() > dd {
            let k = r.len() - 1 - dd;
            let c = r.pop().expect("non-empty");
            // r·lead - c·t^k·d: the leading term cancels (popped above).
            for x in r.iter_mut().chain(q.iter_mut()) {
                *x *= lead;
            }
            for (i, di) in d.0[..dd].iter().enumerate() {
                r[k + i] -= &c * di;
            }
            q[k] += c;
            steps += 1;
            while r.last().is_some_and(Zero::is_zero) {
                r.pop();
            }
        }
        let (q, r) = (ZPoly::new(q), ZPoly::new(r));
        if lead.sign() == Sign::Minus && steps % 2 == 1 {
            (q.neg(), r.neg())
        } else {
            (q, r)
        }
    }

    /// The signed remainder sequence of `self` and `o`, up to positive factors: `self`, `o`,
    /// then the negated remainder of the two before, until it is zero.
    fn remainder_sequence(&self, o: &ZPoly) -> Vec<ZPoly> {
        let mut s = vec![self.clone()];
        if o.is_zero() {
            return s;
        }
        s.push(o.clone());
        loop {
            let n = s.len();
            let r = s[n - 2].pseudo_div(&s[n - 1]).1;
            if r.is_zero() {
                return s;
            }
            s.push(r.neg());
        }
    }

    /// The polynomial with the same roots, each simple (a positive multiple of `self` divided
    /// by its gcd with its derivative).
    fn squarefree(&self) -> ZPoly {
        let d = self.derivative();
        if d.is_zero() {
            return self.clone();
        }
        // The last element of the remainder sequence is the gcd, up to a non-zero factor.
        let g = self.remainder_sequence(&d).pop().expect("non-empty");
        if g.degree().unwrap_or(0) == 0 {
            return self.clone();
        }
        self.pseudo_div(&g).0
    }

    /// The sign of the value at `x`, in integers: for `x = n / m` with `m > 0`, the value times
    /// `m^degree` is `sum c_i n^i m^(degree - i)`; for `m = 2^k` the powers are shifts. (The
    /// points the root search and the rounding to doubles evaluate at are dyadic.)
    fn sign_at(&self, x: &BigRational) -> Ordering {
        let Some(deg) = self.degree() else {
            return Ordering::Equal;
        };
        let (n, m) = (x.numer(), x.denom());
        let mut v = self.0[deg].clone();
        if m.bits() == m.trailing_zeros().unwrap_or(0) + 1 {
            let k = m.bits() - 1;
            for i in (0..deg).rev() {
                v = v * n + (&self.0[i] << (k * (deg - i) as u64));
            }
        } else {
            let mut mp = m.clone();
            for i in (0..deg).rev() {
                v = v * n + &self.0[i] * &mp;
                if i > 0 {
                    mp *= m;
                }
            }
        }
        match v.sign() {
            Sign::Minus => Ordering::Less,
            Sign::NoSign => Ordering::Equal,
            Sign::Plus => Ordering::Greater,
        }
    }

    /// The real roots in `[lo, hi]` of this non-zero polynomial, isolated, in increasing order.
    fn roots_in(&self, lo: &BigRational, hi: &BigRational) -> Vec<Root> {
        if self.degree() == Some(1) {
            // A line's one root, exactly (half the condition's polynomials are lines).
            let x = BigRational::new(-&self.0[0], self.0[1].clone());
            return if rcmp(lo, &x).is_le() && rcmp(&x, hi).is_le() {
                vec![Root::exact(self, x)]
            } else {
                Vec::new()
            };
        }
        let p = self.squarefree();
        if p.degree() == Some(0) {
            return Vec::new();
        }
        let sturm = p.remainder_sequence(&p.derivative());
        let mut out = Vec::new();
        if p.sign_at(lo).is_eq() {
            out.push(Root::exact(&p, lo.clone()));
        }
        // Open intervals (a, b] with their Sturm sign variations at both ends, and the
        // precision (bits after the point) of the next split at critical points.
        let mut open = Vec::new();
        if rcmp(lo, hi).is_lt() {
            let (va, vb) = (variations(&sturm, lo), variations(&sturm, hi));
            open.push((lo.clone(), hi.clone(), va, vb, 64u64));
        }
        // Split until each interval holds one root; a split point that is a root is recorded
        // and both sides continue from it (Sturm counts half-open intervals (a, b]).
        while let Some((a, b, va, vb, bits)) = open.pop() {
            let n = va - vb;
            if n == 0 {
                continue;
            }
            if n == 1 && p.sign_at(&b).is_eq() {
                out.push(Root::exact(&p, b));
                continue;
            }
            // An isolating interval must not end on a root (the left end may be one: the
            // interval's lower bound, or a split point found as a root).
            let root_at_a = p.sign_at(&a).is_eq();
            if n == 1 && !root_at_a {
                out.push(Root {
                    poly: p.clone(),
                    lo: a,
                    hi: b,
                });
                continue;
            }
            // Two roots of p (two in (a, b], or a and one in (a, b]) have a root of p' between
            // them: splitting near p's critical points separates roots however close they are
            // (a near double root, two roots 1e-150 apart, would take 500 halvings), once the
            // precision is below their gap; it doubles at each such split. Any split point is
            // sound; the middle is the fallback.
            let mut cuts: Vec<BigRational> = if n >= 2 || root_at_a {
                critical_points(&p, bits)
                    .into_iter()
                    .filter(|x| rcmp(x, &a).is_gt() && rcmp(x, &b).is_lt())
                    .collect()
            } else {
                Vec::new()
            };
            cuts.dedup_by(|x, y| rcmp(x, y).is_eq());
            if cuts.is_empty() {
                cuts.push(midpoint(&a, &b));
            }
            let mut left = (a, va);
            for x in cuts.into_iter().chain(std::iter::once(b.clone())) {
                let vx = if rcmp(&x, &b).is_eq() {
                    vb
                } else {
                    variations(&sturm, &x)
                };
                let (l, vl) = std::mem::replace(&mut left, (x.clone(), vx));
                open.push((l, x, vl, vx, bits.saturating_mul(2)));
            }
        }
        out.sort_by(|x, y| x.cmp(y));
        out.dedup_by(|x, y| x.cmp(y).is_eq());
        out
    }
}

/// The middle of `a` and `b`, without a gcd when both are dyadic (as the points the root
/// search meets are): the sum over the larger power of two, its factors of two stripped.
fn midpoint(a: &BigRational, b: &BigRational) -> BigRational {
    let dyadic = |d: &BigInt| d.bits() == d.trailing_zeros().unwrap_or(0) + 1;
    if !(dyadic(a.denom()) && dyadic(b.denom())) {
        return (a + b) / BigRational::from_integer(2.into());
    }
    let (ka, kb) = (a.denom().bits() - 1, b.denom().bits() - 1);
    let k = ka.max(kb);
    let sum = (a.numer() << (k - ka)) + (b.numer() << (k - kb));
    dyadic_ratio(sum, k + 1)
}

/// `a` against `b` by cross-multiplication (denominators are positive). `BigRational`'s own
/// comparison divides (a continued-fraction expansion), several times slower on large numbers.
pub(crate) fn rcmp(a: &BigRational, b: &BigRational) -> Ordering {
    if a.denom() == b.denom() {
        return a.numer().cmp(b.numer());
    }
    (a.numer() * b.denom()).cmp(&(b.numer() * a.denom()))
}

/// The sign of `u + v √d` for `d > 0`: of the terms when they agree, else of the larger
/// square.
fn sign_plus_sqrt(u: &BigInt, v: &BigInt, d: &BigInt) -> Ordering {
    let (su, sv) = (u.sign(), v.sign());
    let of = |s: Sign| s.cmp(&Sign::NoSign);
    if sv == Sign::NoSign || su == sv {
        return of(su);
    }
    if su == Sign::NoSign {
        return of(sv);
    }
    match (u * u).cmp(&(v * v * d)) {
        Ordering::Greater => of(su),
        Ordering::Less => of(sv),
        Ordering::Equal => Ordering::Equal,
    }
}

/// `m / 2^k` in lowest terms.
fn dyadic_ratio(m: BigInt, k: u64) -> BigRational {
    if m.is_zero() {
        return BigRational::zero();
    }
    let t = m.trailing_zeros().unwrap_or(0).min(k);
    BigRational::new_raw(m >> t, BigInt::one() << (k - t))
}

/// Dyadic points within `2^(1 - bits)` of the real roots of `p'`, for `p` of degree 2 or 3
/// (none otherwise): `(-b ± √D) / 2a` with an integer square root scaled by `2^bits`.
fn critical_points(p: &ZPoly, bits: u64) -> Vec<BigRational> {
    let g = p.derivative();
    let scaled = |num: BigInt, den: &BigInt| -> BigRational {
        // floor(num / den) for den != 0: within one unit of num / den.
        let (mut q, r) = (&num / den, &num % den);
        if !r.is_zero() && (r.sign() == Sign::Minus) != (den.sign() == Sign::Minus) {
            q -= 1;
        }
        dyadic_ratio(q, bits)
    };
    match g.degree() {
        Some(1) => vec![scaled(-(&g.0[0] << bits), &g.0[1])],
        Some(2) => {
            let (c, b, a) = (&g.0[0], &g.0[1], &g.0[2]);
            let d = b * b - BigInt::from(4) * a * c;
            if d.sign() == Sign::Minus {
                return Vec::new();
            }
            let root = (d << (2 * bits)).sqrt();
            let (bb, den) = (-(b << bits), a << 1u32);
            let mut v = vec![scaled(&bb - &root, &den), scaled(&bb + &root, &den)];
            v.sort();
            v
        }
        _ => Vec::new(),
    }
}

/// Sign changes along the sequence at `x`, zeros skipped: for a Sturm sequence, the distinct
/// roots in `(a, b]` are the drop in this count from `a` to `b`.
fn variations(s: &[ZPoly], x: &BigRational) -> usize {
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
    poly: ZPoly,
    lo: BigRational,
    hi: BigRational,
}

impl Root {
    fn exact(p: &ZPoly, x: BigRational) -> Root {
        Root {
            poly: p.clone(),
            lo: x.clone(),
            hi: x,
        }
    }

    /// Is the root a known rational?
    pub(crate) fn is_exact(&self) -> bool {
        rcmp(&self.lo, &self.hi).is_eq()
    }

    /// The sign of `q` at the root.
    pub(crate) fn sign_of(&mut self, q: &Poly) -> Ordering {
        if q.is_zero() {
            return Ordering::Equal;
        }
        let q = q.integer();
        if self.is_exact() {
            return q.sign_at(&self.lo);
        }
        self.sign_at_root(q, &self.lo, &self.hi)
    }

    /// The sign of `q` at the root, which is the only root of `p` in `(lo, hi)`, neither end
    /// a root of `p`. For `q` of degree at most 2 (every polynomial of a condition but the
    /// coplanarity cubic), from `q`'s roots in closed form: the root against a rational, or
    /// against `(-b ± √D) / 2a` by the sign of `p` there, an expression `u + v √D` whose sign
    /// needs only integer squares. Otherwise a Tarski query. Nothing bisects: the cost does
    /// not depend on how close the roots are, and the numbers stay a few times the size of
    /// the coefficients (the remainder sequences of a Tarski query grow to twenty times).
    fn sign_at_root(&self, q: &ZPoly, lo: &BigRational, hi: &BigRational) -> Ordering {
        let sign = |x: &BigInt| x.sign().cmp(&Sign::NoSign);
        match q.degree() {
            None => Ordering::Equal,
            Some(0) => sign(&q.0[0]),
            Some(1) => {
                // q = q1 (t - x): its sign at the root is q1's above x, the opposite below.
                let (q0, q1) = (&q.0[0], &q.0[1]);
                let x = if q1.sign() == Sign::Minus {
                    BigRational::new_raw(q0.clone(), -q1)
                } else {
                    BigRational::new_raw(-q0, q1.clone())
                };
                match self.locate(lo, hi, &x) {
                    Ordering::Equal => Ordering::Equal,
                    Ordering::Greater => sign(q1),
                    Ordering::Less => sign(q1).reverse(),
                }
            }
            Some(2) => {
                let (c, b, a) = (&q.0[0], &q.0[1], &q.0[2]);
                let d = b * b - BigInt::from(4) * a * c;
                let sa = sign(a);
                if d.sign() == Sign::Minus {
                    return sa;
                }
                let two_a = a << 1u32;
                if d.is_zero() {
                    // a (t - x)² with x = -b / 2a.
                    let x = if a.sign() == Sign::Minus {
                        BigRational::new_raw(b.clone(), -&two_a)
                    } else {
                        BigRational::new_raw(-b, two_a)
                    };
                    return if self.locate(lo, hi, &x).is_eq() {
                        Ordering::Equal
                    } else {
                        sa
                    };
                }
                // p mod q (a positive multiple): p's sign at q's roots.
                let r = self.poly.pseudo_div(q).1;
                let mut inside = 0;
                for s in [-1i32, 1] {
                    match self.locate_quadratic(lo, hi, b, &two_a, &d, s, &r) {
                        Ordering::Equal => return Ordering::Equal,
                        // Above the root (-b + s √D) / 2a: the larger one when s a > 0.
                        Ordering::Greater => inside += i32::from((s > 0) != (sa.is_gt())),
                        Ordering::Less => inside += i32::from((s > 0) == (sa.is_gt())),
                    }
                }
                // Between q's roots (above the smaller, below the larger) q has -a's sign.
                if inside == 2 { sa.reverse() } else { sa }
            }
            _ => self.tarski_query(q, lo, hi),
        }
    }

    /// The root (the only root of `p` in `(lo, hi)`) compared with the rational `x`.
    fn locate(&self, lo: &BigRational, hi: &BigRational, x: &BigRational) -> Ordering {
        if rcmp(x, lo).is_le() {
            return Ordering::Greater;
        }
        if rcmp(x, hi).is_ge() {
            return Ordering::Less;
        }
        // p keeps its sign at lo up to the root.
        match self.poly.sign_at(x) {
            Ordering::Equal => Ordering::Equal,
            s if s == self.poly.sign_at(lo) => Ordering::Greater,
            _ => Ordering::Less,
        }
    }

    /// The root (the only root of `p` in `(lo, hi)`) compared with `β = (-b + s √d) / 2a`
    /// (`two_a` = 2a, `d` > 0), where `r` is a positive multiple of `p` modulo the quadratic
    /// whose root `β` is (so `r(β)` has the sign of `p(β)`).
    #[allow(clippy::too_many_arguments)]
    fn locate_quadratic(
        &self,
        lo: &BigRational,
        hi: &BigRational,
        b: &BigInt,
        two_a: &BigInt,
        d: &BigInt,
        s: i32,
        r: &ZPoly,
    ) -> Ordering {
        let sa = two_a.sign().cmp(&Sign::NoSign);
        let sqrt_coeff = |v: BigInt| if s < 0 { -v } else { v };
        // sign(β - n/m) = sign(a) · sign(-b m - 2a n + s m √d), for m > 0.
        let beta_vs = |x: &BigRational| -> Ordering {
            let (n, m) = (x.numer(), x.denom());
            let u = -(b * m) - two_a * n;
            let s = sign_plus_sqrt(&u, &sqrt_coeff(m.clone()), d);
            if sa.is_lt() { s.reverse() } else { s }
        };
        if beta_vs(lo).is_le() {
            return Ordering::Greater;
        }
        if beta_vs(hi).is_ge() {
            return Ordering::Less;
        }
        // β in (lo, hi): p(β) decides, as p(x) does for a rational x in `locate`.
        let zero = BigInt::zero();
        let (r0, r1) = (r.0.first().unwrap_or(&zero), r.0.get(1).unwrap_or(&zero));
        // r(β) = (2a r0 - b r1 + s r1 √d) / 2a.
        let mut at_beta = sign_plus_sqrt(&(two_a * r0 - b * r1), &sqrt_coeff(r1.clone()), d);
        if sa.is_lt() {
            at_beta = at_beta.reverse();
        }
        match at_beta {
            Ordering::Equal => Ordering::Equal,
            v if v == self.poly.sign_at(lo) => Ordering::Greater,
            _ => Ordering::Less,
        }
    }

    /// The sign of `q` at the root, which is the only root of `p` in `(lo, hi)`, neither end
    /// a root of `p`. Sylvester: the sign variations of the signed remainder sequence of `p`
    /// and `p' q` drop from `lo` to `hi` by the sum of the signs of `q` at `p`'s roots between
    /// (the Cauchy index of `p' q / p`, which jumps by the sign of `q` at a simple root of `p`).
    /// `p' q` may be replaced by its remainder modulo `p` times a positive factor, which has
    /// the same values at `p`'s roots. No bisection: the cost does not depend on how close
    /// the roots of `p` and `q` are.
    fn tarski_query(&self, q: &ZPoly, lo: &BigRational, hi: &BigRational) -> Ordering {
        let p = &self.poly;
        let r = p.derivative().mul(q).pseudo_div(p).1;
        if r.is_zero() {
            return Ordering::Equal;
        }
        let s = p.remainder_sequence(&r);
        let (a, b) = (variations(&s, lo), variations(&s, hi));
        debug_assert!(a.abs_diff(b) <= 1, "one root of p in ({lo}, {hi})");
        a.cmp(&b)
    }

    /// The root compared with the rational `x`.
    fn cmp_rational(&self, x: &BigRational) -> Ordering {
        if self.is_exact() {
            return rcmp(&self.lo, x);
        }
        self.locate(&self.lo, &self.hi, x)
    }

    /// Compares two roots exactly.
    pub(crate) fn cmp(&self, o: &Root) -> Ordering {
        if self.is_exact() {
            return o.cmp_rational(&self.lo).reverse();
        }
        if o.is_exact() {
            return self.cmp_rational(&o.lo);
        }
        if rcmp(&self.hi, &o.lo).is_le() {
            return Ordering::Less;
        }
        if rcmp(&o.hi, &self.lo).is_le() {
            return Ordering::Greater;
        }
        // The intervals overlap in (lo, hi). A root outside it (or on its ends, which are the
        // other's open ends) is on one side of the other root.
        let lo = if rcmp(&self.lo, &o.lo).is_ge() {
            &self.lo
        } else {
            &o.lo
        };
        let hi = if rcmp(&self.hi, &o.hi).is_le() {
            &self.hi
        } else {
            &o.hi
        };
        if rcmp(lo, &self.lo).is_gt() && self.cmp_rational(lo).is_le() {
            return Ordering::Less;
        }
        if rcmp(lo, &o.lo).is_gt() && o.cmp_rational(lo).is_le() {
            return Ordering::Greater;
        }
        if rcmp(hi, &self.hi).is_lt() && self.cmp_rational(hi).is_ge() {
            return Ordering::Greater;
        }
        if rcmp(hi, &o.hi).is_lt() && o.cmp_rational(hi).is_ge() {
            return Ordering::Less;
        }
        // Both are the only roots of their polynomials in (lo, hi), whose ends are roots of
        // neither. q = o.poly vanishes at this root exactly when they are equal; otherwise q
        // has at this root its sign at lo exactly when this root is below o's.
        let q = &o.poly;
        match self.sign_at_root(q, lo, hi) {
            Ordering::Equal => Ordering::Equal,
            s if s == q.sign_at(lo) => Ordering::Less,
            _ => Ordering::Greater,
        }
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
            if rcmp(&q, &self.lo).is_le() {
                return true;
            }
            if rcmp(&q, &self.hi).is_ge() {
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
    while rcmp(&rational(f), x).is_gt() {
        f = f.next_down();
    }
    while rcmp(&rational(f.next_up()), x).is_le() {
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
        let seq = a.integer().remainder_sequence(b.integer());
        assert_eq!(seq.last().and_then(ZPoly::degree), Some(1)); // the gcd, t + 1
        assert_eq!(b.mul(&poly(&[-1, 1])), a);
        assert_eq!(a.derivative(), poly(&[0, 2]));
        let c = poly(&[0, 0, 1]).mul(&poly(&[-1, 2])); // t² (2t - 1)
        assert_eq!(c.integer().squarefree().degree(), Some(2));
        assert!(a.sub(&a).is_zero());
        // Rational coefficients: a positive multiple, with the same signs.
        let h = Poly::new(vec![q(-1, 3), q(5, 6), q(-7, 4)]);
        assert_eq!(
            h.integer(),
            &ZPoly(vec![(-24).into(), 60.into(), (-126).into()])
        );
        // Pseudo-division by a negative leading coefficient: the multiple stays positive.
        let (d, r) = poly(&[1, 0, 0, 1])
            .integer()
            .pseudo_div(poly(&[1, -3]).integer());
        assert_eq!(r.sign_at(&q(0, 1)), Ordering::Greater); // 27 (1 + 1/27)
        assert_eq!(d.degree(), Some(2));
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

    /// Roots 2^-k apart (k up to 600, far below what halving could separate quickly) and not
    /// dyadic, so that they stay inexact: isolated, ordered, and every sign at them and every
    /// comparison with other polynomials' roots as exact evaluation at the known values says.
    #[test]
    fn close_roots_signs_and_order_agree_with_exact_values() {
        let (z, o) = (BigRational::zero(), one());
        let line = |a: BigRational, b: BigRational| Poly::new(vec![-b, a]); // a t - b
        for k in [3u32, 60, 200, 600] {
            let eps = BigRational::new(1.into(), BigInt::from(2).pow(k));
            let x = [q(1, 3), q(1, 3) + &eps / q(3, 1), q(5, 7)];
            let factors = [
                line(q(3, 1), q(1, 1)),
                line(q(3, 1), q(1, 1) + &eps),
                line(q(7, 1), q(5, 1)),
            ];
            let p = factors[0].mul(&factors[1]).mul(&factors[2]);
            let mut roots = p.roots_in(&z, &o);
            assert_eq!(roots.len(), 3, "k {k}");
            assert!(roots.iter().all(|r| !r.is_exact()));
            for w in roots.windows(2) {
                assert_eq!(w[0].cmp(&w[1]), Ordering::Less, "k {k}");
            }
            // Lines and quadratics through the roots, beside them and between them.
            let mut tests = vec![
                factors[0].clone(),
                factors[1].clone(),
                line(q(6, 1), q(2, 1) + &eps),
                Poly::constant(q(-2, 1)),
            ];
            for (a, b) in [(0, 1), (1, 2), (0, 2)] {
                tests.push(line(one(), x[a].clone()).mul(&line(one(), x[b].clone())));
            }
            let mid = (&x[0] + &x[1]) / q(2, 1);
            tests.push(line(one(), mid.clone()).mul(&line(q(9, 1), q(7, 1))));
            tests.push(line(one(), mid.clone()).mul(&line(one(), mid.clone())));
            tests.push(Poly::new(vec![q(1, 1), q(0, 1), q(1, 1)])); // t² + 1
            tests.push(Poly::new(vec![-(&mid * &mid), q(0, 1), q(1, 1)])); // t² - mid²
            tests.push(p.clone());
            for (i, r) in roots.iter_mut().enumerate() {
                for t in &tests {
                    let want = t.eval(&x[i]).cmp(&BigRational::zero());
                    assert_eq!(r.sign_of(t), want, "k {k} root {i} of {t:?}");
                }
            }
            // Against other polynomials' roots, some equal to these.
            for t in &tests[..tests.len() - 1] {
                if t.is_zero() || t.integer().degree() == Some(0) {
                    continue;
                }
                let mut values: Vec<BigRational> = Vec::new();
                for c in [&x[0], &x[1], &x[2], &mid] {
                    if t.eval(c).is_zero() {
                        values.push(c.clone());
                    }
                }
                let theirs = t.roots_in(&z, &o);
                for (r, v) in roots.iter().zip(&x) {
                    for s in &theirs {
                        // Each of their roots is one of the known values, or irrational and
                        // off every root of p (t² - mid²: ±mid, t² + 1: none).
                        let got = r.cmp(s);
                        if let Some(w) = values.iter().find(|w| s.cmp_rational(w).is_eq()) {
                            assert_eq!(got, v.cmp(w), "k {k} {t:?}");
                        }
                        assert_eq!(got, s.cmp(r).reverse());
                    }
                }
            }
        }
    }

    #[test]
    fn floor_to_double_is_the_largest_double_not_above() {
        for x in [q(1, 3), q(1, 10), q(0, 1), q(1, 1), q(2, 3)] {
            let f = floor_f64(&x);
            assert!(rational(f) <= x && rational(f.next_up()) > x, "{x}");
        }
    }
}
