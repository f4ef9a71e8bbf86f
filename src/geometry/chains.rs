//! A test of the arithmetic types that bound their own errors: random chains of sums,
//! differences and products over doubles of every magnitude (zeros, small integers, and
//! exponents up to the subnormals and to overflow), each step checked against exact rationals.

use super::distance::{Num, Ring};
use super::predicates::Sign;
use crate::fixtures::Rng;
use num_rational::BigRational;
use num_traits::{Signed, Zero};
use std::cell::Cell;
use std::fmt::Debug;
use std::ops::{Add, Mul, Sub};

type Q = BigRational;

fn q(x: f64) -> Q {
    Q::from_float(x).unwrap()
}

const fn pow2(e: i64) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}

/// A double of random sign, mantissa and exponent within `2^±span`, sometimes zero or a small
/// integer (so that exact results and cancellations happen).
pub(crate) fn random_double(rng: &mut Rng, span: i64) -> f64 {
    let x = match rng.below(8) {
        0 => 0.0,
        1 => rng.below(8) as f64,
        _ => {
            // Exponents down into the subnormals, up to 2^1000 (finite inputs).
            let e = rng.below((span + span.min(1000)) as u64 + 1) as i64 - span;
            rng.range(1.0, 2.0) * pow2(e / 2) * pow2(e - e / 2)
        }
    };
    if rng.below(2) == 0 { x } else { -x }
}

/// Runs 4,000 chains of 24 steps from `seed`, values made by `point` from inputs whose exponents
/// lie within `2^±span` for the spans `spans` in turn. Every sign `sign` claims must be the
/// exact one, and wherever `enclosure` gives a finite centre and radius, the exact value must lie
/// within it. Returns how many signs were claimed, and how many of them zero.
pub(crate) fn check<T: Ring + Debug>(
    seed: u64,
    spans: [i64; 4],
    point: impl Fn(f64) -> T,
    enclosure: impl Fn(&T) -> (f64, f64),
    sign: impl Fn(&T) -> Option<Sign>,
) -> (usize, usize) {
    let mut rng = Rng::new(seed);
    let (mut known, mut zeros) = (0, 0);
    for case in 0..4000 {
        let span = spans[case % 4];
        let mut xs: Vec<(T, Q)> = (0..6)
            .map(|_| {
                let x = random_double(&mut rng, span);
                (point(x), q(x))
            })
            .collect();
        for _ in 0..24 {
            let i = rng.below(6) as usize;
            let j = rng.below(6) as usize;
            let ((a, qa), (b, qb)) = (xs[i].clone(), xs[j].clone());
            let (x, v) = match rng.below(3) {
                0 => (a.clone() + b.clone(), &qa + &qb),
                1 => (a.clone() - b.clone(), &qa - &qb),
                _ => (a.clone() * b.clone(), &qa * &qb),
            };
            if let Some(s) = sign(&x) {
                let want = if v.is_zero() {
                    0
                } else if v.is_positive() {
                    1
                } else {
                    -1
                };
                assert_eq!(s, want, "{a:?} {b:?} -> {x:?}");
                known += 1;
                zeros += usize::from(s == 0);
            }
            let (centre, radius) = enclosure(&x);
            if centre.is_finite() && radius.is_finite() {
                assert!((&v - q(centre)).abs() <= q(radius), "{a:?} {b:?} -> {x:?}");
            }
            let k = rng.below(6) as usize;
            xs[k] = (x, v);
        }
    }
    (known, zeros)
}

/// A value of arithmetic `T` with the roundings on its longest path (a product counting both
/// factors' and its own, as [`super::permanent`] counts them) and its degree in the inputs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Traced<T> {
    pub x: T,
    pub roundings: u32,
    pub degree: u32,
}

thread_local! {
    /// The most roundings and the highest degree of any value signed on this thread since
    /// [`Traced::most_signed`] last read them.
    static MOST_SIGNED: Cell<(u32, u32)> = const { Cell::new((0, 0)) };
}

impl<T> Traced<T> {
    /// An input: exact, of degree one.
    pub(crate) fn input(x: T) -> Traced<T> {
        Traced {
            x,
            roundings: 0,
            degree: 1,
        }
    }

    /// A constant: exact, of degree zero.
    pub(crate) fn constant(x: T) -> Traced<T> {
        Traced {
            x,
            roundings: 0,
            degree: 0,
        }
    }

    /// The most roundings and the highest degree of the values signed on this thread since the
    /// last call; resets them.
    pub(crate) fn most_signed() -> (u32, u32) {
        MOST_SIGNED.with(|m| m.replace((0, 0)))
    }
}

impl<T: Add<Output = T>> Add for Traced<T> {
    type Output = Traced<T>;
    fn add(self, o: Traced<T>) -> Traced<T> {
        Traced {
            x: self.x + o.x,
            roundings: self.roundings.max(o.roundings) + 1,
            degree: self.degree.max(o.degree),
        }
    }
}

impl<T: Sub<Output = T>> Sub for Traced<T> {
    type Output = Traced<T>;
    fn sub(self, o: Traced<T>) -> Traced<T> {
        Traced {
            x: self.x - o.x,
            roundings: self.roundings.max(o.roundings) + 1,
            degree: self.degree.max(o.degree),
        }
    }
}

impl<T: Mul<Output = T>> Mul for Traced<T> {
    type Output = Traced<T>;
    fn mul(self, o: Traced<T>) -> Traced<T> {
        Traced {
            x: self.x * o.x,
            roundings: self.roundings + o.roundings + 1,
            degree: self.degree + o.degree,
        }
    }
}

impl<T: Num> Num for Traced<T> {
    /// The sign of the value, recording its roundings and degree.
    fn sign(&self) -> Option<Sign> {
        MOST_SIGNED.with(|m| {
            let (r, d) = m.get();
            m.set((r.max(self.roundings), d.max(self.degree)));
        });
        self.x.sign()
    }
}
