//! The distance, closest points and weights of a decided choice, rounded from their exact
//! values: in intervals about double-double centres, and in exact rationals where those are
//! too wide to round from.

use super::{Choice, Feature, Nearest, Primitive, corners};
use crate::geometry::distance::{Ring, V, cross, dot, sub};
use crate::geometry::double_double::{DdInterval, Plain, Split, two_sum};
use crate::geometry::predicates::{Point, to_integers_scaled};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::ops::{Add, Mul, Neg, Sub};

/// Arithmetic for the values: intervals, or exact rationals.
trait Field: Ring {
    fn of(x: f64) -> Self;
    /// The dot product of `a` and `b`.
    fn dot(a: &V<Self>, b: &V<Self>) -> Self {
        dot(a, b)
    }
    /// `self / d`, `d` positive; `None` when the arithmetic cannot divide (an interval holding
    /// zero).
    fn over(&self, d: &Self) -> Option<Self>;
}

impl Field for DdInterval {
    fn of(x: f64) -> DdInterval {
        DdInterval::point(x)
    }
    fn dot(a: &V<DdInterval>, b: &V<DdInterval>) -> DdInterval {
        DdInterval::dot::<Plain>(a, b)
    }
    fn over(&self, d: &DdInterval) -> Option<DdInterval> {
        self.divide::<Plain>(d)
    }
}

/// An exact fraction kept unreduced: `BigRational` divides by a gcd after every operation,
/// which costs more than the few operations here gain from it. The denominator is positive.
#[derive(Clone, Debug)]
struct Frac {
    num: BigInt,
    den: BigInt,
}

impl Frac {
    fn integer(num: BigInt) -> Frac {
        Frac {
            num,
            den: BigInt::one(),
        }
    }
    /// The value times `2^power`, as a rational (unreduced).
    fn scaled(&self, power: i32) -> BigRational {
        let s = power.unsigned_abs() as usize;
        if power >= 0 {
            BigRational::new_raw(&self.num << s, self.den.clone())
        } else {
            BigRational::new_raw(self.num.clone(), &self.den << s)
        }
    }
}

impl Add for Frac {
    type Output = Frac;
    fn add(self, o: Frac) -> Frac {
        if self.den == o.den {
            return Frac {
                num: self.num + o.num,
                den: self.den,
            };
        }
        Frac {
            num: self.num * &o.den + o.num * &self.den,
            den: self.den * o.den,
        }
    }
}

impl Neg for Frac {
    type Output = Frac;
    fn neg(self) -> Frac {
        Frac {
            num: -self.num,
            den: self.den,
        }
    }
}

impl Sub for Frac {
    type Output = Frac;
    fn sub(self, o: Frac) -> Frac {
        self + -o
    }
}

impl Mul for Frac {
    type Output = Frac;
    fn mul(self, o: Frac) -> Frac {
        Frac {
            num: self.num * o.num,
            den: self.den * o.den,
        }
    }
}

impl Field for Frac {
    /// Only the constants 0 and 1 are made so: coordinates come as integers.
    fn of(x: f64) -> Frac {
        debug_assert!(x == 0.0 || x == 1.0);
        Frac::integer(BigInt::from(x as i64))
    }
    fn over(&self, d: &Frac) -> Option<Frac> {
        if d.num.is_zero() {
            return None;
        }
        let (num, den) = (&self.num * &d.den, &self.den * &d.num);
        Some(if den.is_negative() {
            Frac {
                num: -num,
                den: -den,
            }
        } else {
            Frac { num, den }
        })
    }
}

/// The exact values of a choice: squared distance, closest points and weights.
struct Values<F> {
    squared: F,
    points: [V<F>; 2],
    weights: [[F; 3]; 2],
}

fn values_in<F: Field>(pair: Primitive, q: [V<F>; 4], choice: Choice) -> Option<Values<F>> {
    let (zero, one) = (F::of(0.0), F::of(1.0));
    // The point `a + s (b - a)`.
    let along = |a: &V<F>, b: &V<F>, s: &F| -> V<F> {
        [0, 1, 2].map(|k| a[k].clone() + s.clone() * (b[k].clone() - a[k].clone()))
    };
    // Weights on a segment or a triangle's edge `k` at parameter `s`.
    let on_edge = |k: usize, s: &F| -> [F; 3] {
        let mut w = [zero.clone(), zero.clone(), zero.clone()];
        w[k] = one.clone() - s.clone();
        w[(k + 1) % 3] = s.clone();
        w
    };
    let unit = |k: usize| -> [F; 3] {
        let mut w = [zero.clone(), zero.clone(), zero.clone()];
        w[k] = one.clone();
        w
    };
    // Point `x` against segment `[a, b]`, inside it: the parameter `s` = w.u / u.u, the
    // closest point `a + s u`, and the squared distance as the length of what is left of `w`.
    // The products `s u` serve both; one division, no cross product.
    let on_segment = |x: &V<F>, a: &V<F>, b: &V<F>| -> Option<(F, F, V<F>)> {
        let (u, w) = (sub(b, a), sub(x, a));
        let s = F::dot(&w, &u).over(&F::dot(&u, &u))?;
        let su = u.map(|c| s.clone() * c);
        let point = [0, 1, 2].map(|k| a[k].clone() + su[k].clone());
        let r = sub(&w, &su);
        Some((s, F::dot(&r, &r), point))
    };
    // Two corners: the points are inputs, the weights units.
    if let Some((i, j)) = corners(choice) {
        let x = sub(&q[i], &q[j]);
        return Some(Values {
            squared: F::dot(&x, &x),
            points: [q[i].clone(), q[j].clone()],
            weights: [unit(i), unit(j - pair.split())],
        });
    }
    Some(match (pair, choice) {
        (Primitive::VertexFace, Choice::FaceInterior) => {
            let t = [&q[1], &q[2], &q[3]];
            let n = cross(&sub(t[1], t[0]), &sub(t[2], t[0]));
            let inv = one.over(&F::dot(&n, &n))?;
            // Two weights from the areas they weigh; the third is what they leave of one.
            let [w0, w1] = [0, 1].map(|k| {
                let (b, c) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                F::dot(&n, &cross(&sub(b, &q[0]), &sub(c, &q[0]))) * inv.clone()
            });
            let w2 = one.clone() - w0.clone() - w1.clone();
            // The point is the vertex less its height along the normal: `h / |n|^2` of `n`.
            let h = F::dot(&n, &sub(&q[0], t[0]));
            let along_n = h.clone() * inv;
            let point = [0, 1, 2].map(|k| q[0][k].clone() - along_n.clone() * n[k].clone());
            Values {
                squared: h * along_n,
                points: [q[0].clone(), point],
                weights: [unit(0), [w0, w1, w2]],
            }
        }
        (Primitive::VertexFace, Choice::FaceEdge(k)) => {
            let (a, b) = (&q[1 + k], &q[1 + (k + 1) % 3]);
            let (s, squared, point) = on_segment(&q[0], a, b)?;
            Values {
                squared,
                points: [q[0].clone(), point],
                weights: [unit(0), on_edge(k, &s)],
            }
        }
        (Primitive::EdgeEdge, Choice::BothInside) => {
            let (u, v, w) = (sub(&q[1], &q[0]), sub(&q[3], &q[2]), sub(&q[0], &q[2]));
            let n = cross(&u, &v);
            let inv = one.over(&F::dot(&n, &n))?;
            let (uu, uv, vv) = (F::dot(&u, &u), F::dot(&u, &v), F::dot(&v, &v));
            let (uw, vw) = (F::dot(&u, &w), F::dot(&v, &w));
            let s = (uv.clone() * vw.clone() - vv * uw.clone()) * inv.clone();
            let t = (uu * vw - uv * uw) * inv.clone();
            let h = F::dot(&w, &n);
            Values {
                squared: h.clone() * (h * inv),
                points: [along(&q[0], &q[1], &s), along(&q[2], &q[3], &t)],
                weights: [on_edge(0, &s), on_edge(0, &t)],
            }
        }
        (Primitive::EdgeEdge, Choice::End { p, on: None }) => {
            let other = if p < 2 { 1 } else { 0 };
            let (a, b) = (&q[2 * other], &q[2 * other + 1]);
            let (s, squared, point) = on_segment(&q[p], a, b)?;
            let mut points = [q[p].clone(), q[p].clone()];
            let mut weights = [unit(p % 2), unit(p % 2)];
            points[other] = point;
            weights[other] = on_edge(0, &s);
            Values {
                squared,
                points,
                weights,
            }
        }
        _ => unreachable!("corners are taken above; no choice of the other kind of pair"),
    })
}

/// The features of a choice.
fn features(choice: Choice) -> [Feature; 2] {
    let on_segment = |on: Option<usize>| on.map_or(Feature::Edge01, Feature::corner);
    match choice {
        Choice::FaceInterior => [Feature::Vertex0, Feature::Interior],
        Choice::FaceEdge(k) => [Feature::Vertex0, Feature::edge(k)],
        Choice::FaceCorner(k) => [Feature::Vertex0, Feature::corner(k)],
        Choice::BothInside => [Feature::Edge01, Feature::Edge01],
        Choice::End { p, on } if p < 2 => [Feature::corner(p), on_segment(on)],
        Choice::End { p, on } => [on_segment(on), Feature::corner(p - 2)],
    }
}

/// The square root of `x >= 0`, within one unit in the last place of the correctly rounded one:
/// the integer square root of `x` scaled by an even power of two to at least 110 bits, rounded.
pub(super) fn sqrt_rational(x: &BigRational) -> f64 {
    if x.is_zero() {
        return 0.0;
    }
    let (n, d) = (x.numer().abs(), x.denom().clone());
    // x 4^k >= 2^110: the root's integer part has at least 55 bits.
    let shift = 110i64 - (n.bits() as i64 - d.bits() as i64);
    let k = shift.div_euclid(2) + 1;
    let scaled = if k >= 0 {
        (n << (2 * k as usize)) / d
    } else {
        n / (d << (-2 * k) as usize)
    };
    let root = scaled.sqrt();
    // root 2^-k, truncated at 55 bits or more: rounding it to a double adds under one unit.
    let r = if k >= 0 {
        BigRational::new_raw(root, BigInt::one() << k as usize)
    } else {
        BigRational::new_raw(root << (-k) as usize, BigInt::one())
    };
    r.to_f64().expect("a finite root")
}

/// The rounded values of `choice` for the points `p`: the common choices directly, with the
/// split `S` (inlined, so that a caller compiled for the fused multiply-add uses it), the others
/// by the general path.
#[inline(always)]
pub(super) fn values_of<S: Split>(pair: Primitive, p: &[Point; 4], choice: Choice) -> Nearest {
    let features = features(choice);
    // Two corners, the most common choice where many pairs come near: the points are inputs and
    // the weights units, so only the distance is computed.
    let unit = |k: usize| {
        let mut w = [0.0; 3];
        w[k] = 1.0;
        w
    };
    if let Some((i, j)) = corners(choice)
        && let Some(distance) = DdInterval::squared_distance::<S>(&p[i], &p[j]).tight_sqrt::<S>()
    {
        return Nearest {
            features,
            distance,
            points: [p[i], p[j]],
            weights: [unit(i), unit(j - pair.split())],
        };
    }
    // A point and a segment it projects strictly inside, the next most common: computed
    // directly, without the general path's vectors of intervals. `x` is the point, `[a, b]`
    // the segment, on side `side`; the point's own weight is a unit at `own`, the segment's
    // weights start at corner `k`.
    let inside = match choice {
        Choice::FaceEdge(k) => Some((0, 1 + k, 1 + (k + 1) % 3, 1, 0, k)),
        Choice::End { p: e, on: None } => {
            let other = if e < 2 { 1 } else { 0 };
            Some((e, 2 * other, 2 * other + 1, other, e % 2, 0))
        }
        _ => None,
    };
    if let Some((x, a, b, side, own, k)) = inside
        && let Some((distance, point, [s0, s1])) = on_segment::<S>(&p[x], &p[a], &p[b])
    {
        let mut points = [p[x]; 2];
        points[side] = point;
        let mut weights = [unit(own); 2];
        weights[side] = [0.0; 3];
        weights[side][k] = s0;
        weights[side][(k + 1) % 3] = s1;
        return Nearest {
            features,
            distance,
            points,
            weights,
        };
    }
    // The two choices inside: rarer, but each several times a corner's cost in the general
    // path.
    let inside = match choice {
        Choice::FaceInterior => in_triangle::<S>(&p[0], [&p[1], &p[2], &p[3]])
            .map(|(distance, point, w)| (distance, [p[0], point], [unit(0), w])),
        Choice::BothInside => between_segments::<S>(p).map(|(distance, points, [s, t])| {
            let w = |s: [f64; 2]| [s[0], s[1], 0.0];
            (distance, points, [w(s), w(t)])
        }),
        _ => None,
    };
    if let Some((distance, points, weights)) = inside {
        return Nearest {
            features,
            distance,
            points,
            weights,
        };
    }
    general_values(pair, p, choice)
}

// The direct paths below are inlined whole into the caller compiled for the fused
// multiply-add, so they take no closures over the arithmetic (`array::map` and the like): one
// left out of line is compiled for the default target, where a fused multiply-add is a call.

/// `a - b` exactly, as double-doubles.
#[inline(always)]
fn exact_difference(a: &Point, b: &Point) -> V<DdInterval> {
    let (h0, l0) = two_sum(a[0], -b[0]);
    let (h1, l1) = two_sum(a[1], -b[1]);
    let (h2, l2) = two_sum(a[2], -b[2]);
    let exact = DdInterval::exact;
    [exact(h0, l0), exact(h1, l1), exact(h2, l2)]
}

/// The cross product, with the split `S`.
#[inline(always)]
fn cross_with<S: Split>(a: &V<DdInterval>, b: &V<DdInterval>) -> V<DdInterval> {
    [
        a[1].times::<S>(b[2]) - a[2].times::<S>(b[1]),
        a[2].times::<S>(b[0]) - a[0].times::<S>(b[2]),
        a[0].times::<S>(b[1]) - a[1].times::<S>(b[0]),
    ]
}

/// `n.(b x c)`, with the split `S`.
#[inline(always)]
fn triple_with<S: Split>(n: &V<DdInterval>, b: &V<DdInterval>, c: &V<DdInterval>) -> DdInterval {
    DdInterval::dot::<S>(n, &cross_with::<S>(b, c))
}

/// `s u`, with the split `S`.
#[inline(always)]
fn scaled<S: Split>(s: DdInterval, u: &V<DdInterval>) -> V<DdInterval> {
    [s.times::<S>(u[0]), s.times::<S>(u[1]), s.times::<S>(u[2])]
}

/// `(1 - s, s)` and the point `a + su`, rounded, for the segment from `a` along `u`, with `su`
/// the product `s u`.
#[inline(always)]
fn rounded_along(a: &Point, s: DdInterval, su: &V<DdInterval>) -> Option<([f64; 2], Point)> {
    let weights = [(DdInterval::point(1.0) - s).tight()?, s.tight()?];
    let mut point = [0.0; 3];
    for k in 0..3 {
        point[k] = (DdInterval::point(a[k]) + su[k]).tight()?;
    }
    Some((weights, point))
}

/// The distance of point `x` from the plane of triangle `t`, its projection and that
/// projection's weights, rounded, for a point that projects strictly inside; `None` when the
/// enclosures are too wide to round. The same computation as `values_in`'s, in intervals with
/// the split `S`.
#[inline(always)]
fn in_triangle<S: Split>(x: &Point, t: [&Point; 3]) -> Option<(f64, Point, [f64; 3])> {
    let n = cross_with::<S>(&exact_difference(t[1], t[0]), &exact_difference(t[2], t[0]));
    let inv = DdInterval::point(1.0).divide::<S>(&DdInterval::dot::<S>(&n, &n))?;
    let to = [
        exact_difference(t[0], x),
        exact_difference(t[1], x),
        exact_difference(t[2], x),
    ];
    // Two weights from the areas they weigh; the third is what they leave of one.
    let w0 = triple_with::<S>(&n, &to[1], &to[2]).times::<S>(inv);
    let w1 = triple_with::<S>(&n, &to[2], &to[0]).times::<S>(inv);
    let w2 = DdInterval::point(1.0) - w0 - w1;
    // The height `h = n.(x - t0)`: the point is `x` less `h / |n|^2` of `n`.
    let h = -DdInterval::dot::<S>(&n, &to[0]);
    let along = h.times::<S>(inv);
    let mut point = [0.0; 3];
    for k in 0..3 {
        point[k] = (DdInterval::point(x[k]) - along.times::<S>(n[k])).tight()?;
    }
    let distance = h.times::<S>(along).tight_sqrt::<S>()?;
    Some((distance, point, [w0.tight()?, w1.tight()?, w2.tight()?]))
}

/// The distance of the lines of segments `[q0, q1]` and `[q2, q3]`, their closest points and
/// those points' parameters `(1 - s, s)` on each, rounded, for lines whose closest points lie
/// strictly inside both segments; `None` when the enclosures are too wide to round. The same
/// computation as `values_in`'s, in intervals with the split `S`.
#[inline(always)]
fn between_segments<S: Split>(q: &[Point; 4]) -> Option<(f64, [Point; 2], [[f64; 2]; 2])> {
    let (u, v) = (
        exact_difference(&q[1], &q[0]),
        exact_difference(&q[3], &q[2]),
    );
    let w = exact_difference(&q[0], &q[2]);
    let n = cross_with::<S>(&u, &v);
    let inv = DdInterval::point(1.0).divide::<S>(&DdInterval::dot::<S>(&n, &n))?;
    let (uu, uv, vv) = (
        DdInterval::dot::<S>(&u, &u),
        DdInterval::dot::<S>(&u, &v),
        DdInterval::dot::<S>(&v, &v),
    );
    let (uw, vw) = (DdInterval::dot::<S>(&u, &w), DdInterval::dot::<S>(&v, &w));
    let s = (uv.times::<S>(vw) - vv.times::<S>(uw)).times::<S>(inv);
    let t = (uu.times::<S>(vw) - uv.times::<S>(uw)).times::<S>(inv);
    let h = DdInterval::dot::<S>(&w, &n);
    let distance = h.times::<S>(h.times::<S>(inv)).tight_sqrt::<S>()?;
    let (ws, ps) = rounded_along(&q[0], s, &scaled::<S>(s, &u))?;
    let (wt, pt) = rounded_along(&q[2], t, &scaled::<S>(t, &v))?;
    Some((distance, [ps, pt], [ws, wt]))
}

/// The rounded values of `choice` for the points `p`, by the general path: in intervals, and
/// where they are too wide, in exact rationals.
#[inline(never)]
fn general_values(pair: Primitive, p: &[Point; 4], choice: Choice) -> Nearest {
    let features = features(choice);
    let done = |rounded: Rounded| Nearest {
        features,
        distance: rounded.0,
        points: rounded.1,
        weights: rounded.2,
    };
    if let Some(v) = values_in(pair, p.map(|x| x.map(DdInterval::point)), choice)
        && let Some(rounded) = round(&v)
    {
        return done(rounded);
    }
    // Weights are ratios of terms of one degree, free of the scale; points are of degree one
    // (times 2^e), squared distances of degree two (times 2^2e).
    let (v, e) = integer_values(pair, p, choice);
    let f = |x: &Frac, power: i32| x.scaled(power).to_f64().expect("a finite value");
    Nearest {
        features,
        distance: sqrt_rational(&v.squared.scaled(2 * e)),
        points: v.points.map(|x| [f(&x[0], e), f(&x[1], e), f(&x[2], e)]),
        weights: v.weights.map(|w| [f(&w[0], 0), f(&w[1], 0), f(&w[2], 0)]),
    }
}

/// An enclosure of the squared distance of `choice`'s closest points for `p`, in intervals
/// about double-double centres; `None` where the intervals cannot divide.
pub(super) fn squared_enclosure(
    pair: Primitive,
    p: &[Point; 4],
    choice: Choice,
) -> Option<DdInterval> {
    values_in(pair, p.map(|x| x.map(DdInterval::point)), choice)
        .map(|v| v.squared)
        .filter(DdInterval::is_finite)
}

/// The squared distance of `choice`'s closest points for `p`, exactly.
pub(super) fn squared_exact(pair: Primitive, p: &[Point; 4], choice: Choice) -> BigRational {
    let (v, e) = integer_values(pair, p, choice);
    v.squared.scaled(2 * e)
}

/// `choice`'s values for `p` exactly, with every coordinate an integer times one power of two
/// `2^e`: the values of the integers, and `e`.
fn integer_values(pair: Primitive, p: &[Point; 4], choice: Choice) -> (Values<Frac>, i32) {
    let mut flat = [0.0; 12];
    for (k, x) in p.iter().flatten().enumerate() {
        flat[k] = *x;
    }
    let (ints, e) = to_integers_scaled(flat);
    let mut ints = ints.into_iter().map(Frac::integer);
    let q: [V<Frac>; 4] = std::array::from_fn(|_| std::array::from_fn(|_| ints.next().unwrap()));
    let v = values_in(pair, q, choice).expect("exact division by a positive value");
    (v, e)
}

/// The distance of point `x` from segment `[a, b]`, its closest point on the segment and the
/// weights `(1 - s, s)` of that point, rounded, for a point that projects inside the segment;
/// `None` when the enclosures are too wide to round (then the general path decides). The same
/// computation as `values_in`'s, in intervals throughout, with the split `S`.
#[inline(always)]
fn on_segment<S: Split>(x: &Point, a: &Point, b: &Point) -> Option<(f64, Point, [f64; 2])> {
    let (u, w) = (exact_difference(b, a), exact_difference(x, a));
    let s = DdInterval::dot::<S>(&w, &u).divide::<S>(&DdInterval::dot::<S>(&u, &u))?;
    let su = scaled::<S>(s, &u);
    let (weights, point) = rounded_along(a, s, &su)?;
    let r = [w[0] - su[0], w[1] - su[1], w[2] - su[2]];
    let distance = DdInterval::dot::<S>(&r, &r).tight_sqrt::<S>()?;
    Some((distance, point, weights))
}

type Rounded = (f64, [Point; 2], [[f64; 3]; 2]);

fn round(v: &Values<DdInterval>) -> Option<Rounded> {
    let distance = v.squared.tight_sqrt::<Plain>()?;
    let mut points = [[0.0; 3]; 2];
    let mut weights = [[0.0; 3]; 2];
    for s in 0..2 {
        for k in 0..3 {
            points[s][k] = v.points[s][k].tight()?;
            weights[s][k] = v.weights[s][k].tight()?;
        }
    }
    Some((distance, points, weights))
}
