//! Exact proximity: is the Euclidean distance between two closed triangles at most `d`?
//! (The proximity queries rest on it.)
//!
//! Two triangles that do not intersect are closest at a vertex of one and the other triangle,
//! or between two edges where the closest points lie inside both edges. Each of those cases
//! compares a squared distance, rational in the inputs, with `d²`; clearing the (positive)
//! denominators leaves the sign of a polynomial of degree at most 6 in the coordinates and `d`.
//! Every polynomial is homogeneous in the coordinates and `d` together, so scaling all inputs by
//! one power of two changes no sign.
//!
//! Each decision is made first with interval arithmetic (every operation rounded outwards), and
//! when an interval cannot tell a sign (close calls, distances exactly `d`, overflow at huge
//! coordinates, underflow at tiny ones), again with big integers: every finite double is an
//! integer times a power of two. The answer is exact for the given doubles.

use super::interval::Interval;
use super::predicates::{Sign, to_integers};
use super::tri_tri::{Triangle, triangles_intersect};
use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::ops::{Add, Mul, Sub};

/// Is the distance between the closed triangles `t1` and `t2` at most `d`? `d` must be finite
/// and not negative (callers check); `d = 0` asks whether they intersect. Exact for any finite
/// coordinates, degenerate triangles included.
pub fn triangles_within(t1: &Triangle, t2: &Triangle, d: f64) -> bool {
    debug_assert!(d >= 0.0 && d.is_finite());
    if d > 0.0
        && let Some(answer) = decide_by_filter(t1, t2, d)
    {
        return answer;
    }
    if triangles_intersect(t1, t2) {
        return true;
    }
    if d == 0.0 {
        return false;
    }
    let inputs = |t1: &Triangle, t2: &Triangle| -> [f64; 19] {
        let mut v = [0.0; 19];
        for (k, p) in t1.iter().chain(t2).enumerate() {
            v[3 * k..3 * k + 3].copy_from_slice(p);
        }
        v[18] = d;
        v
    };
    let values = inputs(t1, t2);
    if let Some(answer) = within::<Interval>(&values.map(Interval::point)) {
        return answer;
    }
    within::<Big>(&to_integers(values).map(Big)).expect("exact arithmetic decides every sign")
}

/// Relative slack of the quick decisions: far more than the few roundings each makes (a few
/// units of 2^-53 each), so that every rounding, however it falls, is covered.
const SLACK: f64 = 1e-12;

/// Absolute slack of the quick decisions: covers what underflow can lose (a few 2^-1074).
const TINY: f64 = 1e-290;

/// The common cases in plain floating point, with bounds on the rounding wide enough to be sure:
/// two triangles far apart along a triangle's normal or the line between their centroids, or a
/// vertex of one close to a vertex of the other. `None` when these cannot tell (then the exact
/// decision runs).
#[inline]
fn decide_by_filter(t1: &Triangle, t2: &Triangle, d: f64) -> Option<bool> {
    let m = t1
        .iter()
        .chain(t2)
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    // Beyond this the products below could overflow (the in-plane axes are of degree 3).
    if m > 1e60 || d > 1e60 {
        return None;
    }
    let diff = |p: &[f64; 3], q: &[f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: &[f64; 3], b: &[f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let sum = |t: &Triangle| [0, 1, 2].map(|k| t[0][k] + t[1][k] + t[2][k]);
    let edges = |t: &Triangle| [0, 1, 2].map(|k| diff(&t[(k + 1) % 3], &t[k]));
    let (e1, e2) = (edges(t1), edges(t2));
    let (n1, n2) = (cross(&e1[0], &e1[1]), cross(&e2[0], &e2[1]));
    // The axes of the separating-axis test, cheapest and likeliest first: the normals, the line
    // between the centroids, the normals of the edges within each plane (nearly coplanar
    // neighbours), the cross products of edges.
    let axes = [n1, n2, diff(&sum(t2), &sum(t1))]
        .into_iter()
        .chain(e1.iter().map(|e| cross(&n1, e)))
        .chain(e2.iter().map(|e| cross(&n2, e)))
        .chain((0..9).map(|k| cross(&e1[k / 3], &e2[k % 3])));
    for n in axes {
        let n = &n;
        // Any vector serves as an axis: what matters is that the projections on this one (as
        // rounded) are bounded. Each is off by at most 3 roundings of terms at most |n|_1 m.
        let err = 1e-15 * (n[0].abs() + n[1].abs() + n[2].abs()) * m + TINY;
        let nn = dot(n, n);
        if nn < 1e-280 {
            continue;
        }
        let (mut lo1, mut hi1, mut lo2, mut hi2) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in t1 {
            let x = dot(n, p);
            (lo1, hi1) = (lo1.min(x), hi1.max(x));
        }
        for p in t2 {
            let x = dot(n, p);
            (lo2, hi2) = (lo2.min(x), hi2.max(x));
        }
        let gap = (lo2 - hi1).max(lo1 - hi2);
        // The gap's width along the unit axis exceeds d: d |n| < gap, |n| bounded above.
        let norm = (nn * (1.0 + SLACK)).sqrt();
        if (gap - 2.0 * err) * (1.0 - SLACK) > d * norm * (1.0 + SLACK) + TINY {
            return Some(false);
        }
    }
    let dd = d * d * (1.0 - SLACK);
    for p in t1 {
        for q in t2 {
            let w = diff(p, q);
            if dot(&w, &w) * (1.0 + SLACK) + TINY < dd {
                return Some(true);
            }
        }
    }
    None
}

/// The numbers the decision is computed with: an interval that may leave a sign unknown, or an
/// exact integer.
pub(crate) trait Num: Ring {
    /// The sign, if known.
    fn sign(&self) -> Option<Sign>;
}

/// The sign of a number within `error` of `value` (a NaN in either leaves it unknown), or 0 when
/// it is known to be `exact_zero`.
#[inline(always)]
pub(crate) fn sign_within(value: f64, error: f64, exact_zero: bool) -> Option<Sign> {
    if value > error {
        Some(1)
    } else if -value > error {
        Some(-1)
    } else if exact_zero {
        Some(0)
    } else {
        None
    }
}

impl Num for Interval {
    fn sign(&self) -> Option<Sign> {
        if self.lo > 0.0 {
            Some(1)
        } else if self.hi < 0.0 {
            Some(-1)
        } else if self.lo == 0.0 && self.hi == 0.0 {
            Some(0)
        } else {
            None
        }
    }
}

/// An exact integer.
#[derive(Clone, Debug)]
pub(crate) struct Big(pub(crate) BigInt);

impl Add for Big {
    type Output = Big;
    fn add(self, o: Big) -> Big {
        Big(self.0 + o.0)
    }
}

impl Sub for Big {
    type Output = Big;
    fn sub(self, o: Big) -> Big {
        Big(self.0 - o.0)
    }
}

impl Mul for Big {
    type Output = Big;
    fn mul(self, o: Big) -> Big {
        Big(self.0 * o.0)
    }
}

impl Num for Big {
    fn sign(&self) -> Option<Sign> {
        Some(if self.0.is_zero() {
            0
        } else if self.0.is_positive() {
            1
        } else {
            -1
        })
    }
}

/// Numbers that add, subtract and multiply: what the vector helpers below need.
pub(crate) trait Ring:
    Clone + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self>
{
}

impl<T: Clone + Add<Output = T> + Sub<Output = T> + Mul<Output = T>> Ring for T {}

pub(crate) type V<T> = [T; 3];

#[inline]
pub(crate) fn sub<T: Ring>(a: &V<T>, b: &V<T>) -> V<T> {
    [
        a[0].clone() - b[0].clone(),
        a[1].clone() - b[1].clone(),
        a[2].clone() - b[2].clone(),
    ]
}

#[inline]
pub(crate) fn dot<T: Ring>(a: &V<T>, b: &V<T>) -> T {
    a[0].clone() * b[0].clone() + a[1].clone() * b[1].clone() + a[2].clone() * b[2].clone()
}

#[inline]
pub(crate) fn cross<T: Ring>(a: &V<T>, b: &V<T>) -> V<T> {
    [
        a[1].clone() * b[2].clone() - a[2].clone() * b[1].clone(),
        a[2].clone() * b[0].clone() - a[0].clone() * b[2].clone(),
        a[0].clone() * b[1].clone() - a[1].clone() * b[0].clone(),
    ]
}

/// `x <= y`, if the arithmetic can tell.
pub(crate) fn at_most<T: Num>(x: T, y: T) -> Option<bool> {
    Some((x - y).sign()? <= 0)
}

/// Is any of the tests true? `None` as soon as one cannot be decided and none is known true
/// before it (so the exact pass redoes everything).
macro_rules! any_of {
    ($($test:expr),* $(,)?) => {{
        let mut unknown = false;
        let mut found = false;
        $(
            if !found {
                match $test {
                    Some(true) => found = true,
                    Some(false) => {}
                    None => unknown = true,
                }
            }
        )*
        if found { Some(true) } else if unknown { None } else { Some(false) }
    }};
}

/// The decision for the 18 coordinates of two triangles and `d` (see [`triangles_within`]),
/// after the intersection test: a vertex of one near the other triangle, or two edges near each
/// other between their ends.
fn within<T: Num>(v: &[T; 19]) -> Option<bool> {
    let point =
        |k: usize| -> V<T> { [v[3 * k].clone(), v[3 * k + 1].clone(), v[3 * k + 2].clone()] };
    let t1 = [point(0), point(1), point(2)];
    let t2 = [point(3), point(4), point(5)];
    let dd = v[18].clone() * v[18].clone();
    let mut unknown = false;
    for (tri, other) in [(&t1, &t2), (&t2, &t1)] {
        for p in other.iter() {
            match point_triangle(p, tri, &dd) {
                Some(true) => return Some(true),
                Some(false) => {}
                None => unknown = true,
            }
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let (a, b) = (&t1[i], &t1[(i + 1) % 3]);
            let (c, e) = (&t2[j], &t2[(j + 1) % 3]);
            match edges_between_ends(a, b, c, e, &dd) {
                Some(true) => return Some(true),
                Some(false) => {}
                None => unknown = true,
            }
        }
    }
    if unknown { None } else { Some(false) }
}

/// Is `p` within `sqrt(dd)` of the triangle `t`?
fn point_triangle<T: Num>(p: &V<T>, t: &[V<T>; 3], dd: &T) -> Option<bool> {
    let edges = any_of!(
        point_segment(p, &t[0], &t[1], dd),
        point_segment(p, &t[1], &t[2], dd),
        point_segment(p, &t[2], &t[0], dd),
    );
    if edges == Some(true) {
        return Some(true);
    }
    // Over the face: p projects inside t, and its distance to t's plane is at most d.
    let n = cross(&sub(&t[1], &t[0]), &sub(&t[2], &t[0]));
    let nn = dot(&n, &n);
    let face = (|| {
        if nn.sign()? == 0 {
            return Some(false); // a flat triangle: its edges are all of it
        }
        for k in 0..3 {
            let (a, b) = (&t[k], &t[(k + 1) % 3]);
            let side = dot(&n, &cross(&sub(b, a), &sub(p, a)));
            if side.sign()? < 0 {
                return Some(false);
            }
        }
        let h = dot(&n, &sub(p, &t[0]));
        at_most(h.clone() * h, dd.clone() * nn.clone())
    })();
    any_of!(edges, face)
}

/// Is `p` within `sqrt(dd)` of the segment `[a, b]`?
fn point_segment<T: Num>(p: &V<T>, a: &V<T>, b: &V<T>, dd: &T) -> Option<bool> {
    let u = sub(b, a);
    let w = sub(p, a);
    let uu = dot(&u, &u);
    let along = dot(&w, &u);
    if along.sign()? <= 0 || uu.sign()? == 0 {
        return at_most(dot(&w, &w), dd.clone());
    }
    if (along.clone() - uu.clone()).sign()? >= 0 {
        let x = sub(p, b);
        return at_most(dot(&x, &x), dd.clone());
    }
    let c = cross(&w, &u);
    at_most(dot(&c, &c), dd.clone() * uu)
}

/// Are the segments `[a, b]` and `[c, e]` within `sqrt(dd)` where their closest points lie
/// strictly inside both? (Closest points at an end are a vertex-triangle case.)
fn edges_between_ends<T: Num>(a: &V<T>, b: &V<T>, c: &V<T>, e: &V<T>, dd: &T) -> Option<bool> {
    let (u, v, w) = (sub(b, a), sub(e, c), sub(a, c));
    let n = cross(&u, &v);
    let nn = dot(&n, &n);
    if nn.sign()? == 0 {
        return Some(false); // parallel or flat: the closest points include an end
    }
    let (uu, uv, vv) = (dot(&u, &u), dot(&u, &v), dot(&v, &v));
    let (uw, vw) = (dot(&u, &w), dot(&v, &w));
    // Closest points a + s u and c + t v with s = s_num / nn, t = t_num / nn (nn = uu vv - uv²).
    let s_num = uv.clone() * vw.clone() - vv * uw.clone();
    let t_num = uu * vw - uv * uw;
    for x in [s_num, t_num] {
        if x.sign()? <= 0 || (x - nn.clone()).sign()? >= 0 {
            return Some(false);
        }
    }
    let h = dot(&w, &n);
    at_most(h.clone() * h, dd.clone() * nn)
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_rational::BigRational;
    use num_traits::ToPrimitive;
    use proptest::prelude::*;

    /// The squared distance between two triangles that do not intersect, exactly, over the
    /// rationals: the least distance between the closest points of every vertex-vertex,
    /// vertex-edge, vertex-face and edge-edge pair whose closest points lie inside both
    /// features (computed as values, where `triangles_within` compares signs).
    fn exact_squared_distance(t1: &Triangle, t2: &Triangle) -> BigRational {
        let q = |x: f64| BigRational::from_float(x).expect("finite");
        let p1: Vec<[BigRational; 3]> = t1.iter().map(|p| p.map(q)).collect();
        let p2: Vec<[BigRational; 3]> = t2.iter().map(|p| p.map(q)).collect();
        let mut best: Option<BigRational> = None;
        let mut consider = |x: &[BigRational; 3], y: &[BigRational; 3]| {
            let d: BigRational = (0..3).map(|k| (&x[k] - &y[k]) * (&x[k] - &y[k])).sum();
            if best.as_ref().is_none_or(|b| d < *b) {
                best = Some(d);
            }
        };
        // Closest points of a point and a segment, of two segments (interior), and of a point
        // and a triangle's face (interior), each where the parameters lie inside.
        let lerp = |a: &[BigRational; 3], b: &[BigRational; 3], s: &BigRational| {
            [0, 1, 2].map(|k| &a[k] + (&b[k] - &a[k]) * s)
        };
        let zero = BigRational::zero();
        let one = BigRational::from_integer(1.into());
        let dotq = |a: &[BigRational; 3], b: &[BigRational; 3]| -> BigRational {
            (0..3).map(|k| &a[k] * &b[k]).sum()
        };
        let subq = |a: &[BigRational; 3], b: &[BigRational; 3]| [0, 1, 2].map(|k| &a[k] - &b[k]);
        for (ta, tb) in [(&p1, &p2), (&p2, &p1)] {
            for x in ta.iter() {
                for y in tb.iter() {
                    consider(x, y);
                }
                for k in 0..3 {
                    let (a, b) = (&tb[k], &tb[(k + 1) % 3]);
                    let u = subq(b, a);
                    let uu = dotq(&u, &u);
                    if uu != zero {
                        let s = dotq(&subq(x, a), &u) / &uu;
                        if s > zero && s < one {
                            consider(x, &lerp(a, b, &s));
                        }
                    }
                }
                // The face: solve for barycentric coordinates of the projection.
                let (a, b, c) = (&tb[0], &tb[1], &tb[2]);
                let (e1, e2, w) = (subq(b, a), subq(c, a), subq(x, a));
                let (d11, d12, d22) = (dotq(&e1, &e1), dotq(&e1, &e2), dotq(&e2, &e2));
                let det = &d11 * &d22 - &d12 * &d12;
                if det != zero {
                    let (w1, w2) = (dotq(&w, &e1), dotq(&w, &e2));
                    let s = (&d22 * &w1 - &d12 * &w2) / &det;
                    let t = (&d11 * &w2 - &d12 * &w1) / &det;
                    if s >= zero && t >= zero && &s + &t <= one {
                        let f = [0, 1, 2].map(|k| &a[k] + &e1[k] * &s + &e2[k] * &t);
                        consider(x, &f);
                    }
                }
            }
        }
        for i in 0..3 {
            for j in 0..3 {
                let (a, b) = (&p1[i], &p1[(i + 1) % 3]);
                let (c, e) = (&p2[j], &p2[(j + 1) % 3]);
                let (u, v, w) = (subq(b, a), subq(e, c), subq(a, c));
                let (uu, uv, vv) = (dotq(&u, &u), dotq(&u, &v), dotq(&v, &v));
                let det = &uu * &vv - &uv * &uv;
                if det != zero {
                    let (uw, vw) = (dotq(&u, &w), dotq(&v, &w));
                    let s = (&uv * &vw - &vv * &uw) / &det;
                    let t = (&uu * &vw - &uv * &uw) / &det;
                    if s > zero && s < one && t > zero && t < one {
                        consider(&lerp(a, b, &s), &lerp(c, e, &t));
                    }
                }
            }
        }
        best.expect("some pair")
    }

    fn coord() -> impl Strategy<Value = f64> {
        (-6i32..=6).prop_map(|x| f64::from(x) / 2.0)
    }

    fn triangle() -> impl Strategy<Value = Triangle> {
        [
            [coord(), coord(), coord()],
            [coord(), coord(), coord()],
            [coord(), coord(), coord()],
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

        /// Against the exact squared distance over the rationals, at distances just below, at
        /// and just above it (the decision "at most" must flip exactly there when the distance
        /// is a double), and at random distances.
        #[test]
        fn agrees_with_rational_distance(t1 in triangle(), t2 in triangle(), d in 0.0..4.0f64) {
            let exact = if triangles_intersect(&t1, &t2) {
                BigRational::zero()
            } else {
                exact_squared_distance(&t1, &t2)
            };
            let q = |x: f64| BigRational::from_float(x).unwrap();
            prop_assert_eq!(triangles_within(&t1, &t2, d), q(d) * q(d) >= exact);
            // Where the distance is a double, the answer flips exactly at it.
            let approx = exact.to_f64().unwrap_or(0.0).sqrt();
            for x in [approx.next_down(), approx, approx.next_up()] {
                if x >= 0.0 {
                    prop_assert_eq!(triangles_within(&t1, &t2, x), q(x) * q(x) >= exact, "d = {}", x);
                }
            }
        }
    }

    #[test]
    fn touching_and_exact_distances() {
        let t1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        // A triangle above, at height exactly 0.5.
        let t2 = [[0.2, 0.2, 0.5], [0.3, 0.2, 0.7], [0.2, 0.3, 0.9]];
        assert!(triangles_within(&t1, &t2, 0.5));
        assert!(!triangles_within(&t1, &t2, 0.5f64.next_down()));
        // Parallel edges 3 apart: exactly 3.
        let e1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]];
        let e2 = [[0.0, 3.0, 0.0], [1.0, 3.0, 0.0], [0.0, 4.0, 0.0]];
        assert!(triangles_within(&e1, &e2, 3.0));
        assert!(!triangles_within(&e1, &e2, 3.0f64.next_down()));
        // Skew edges crossing at distance 2 between their interiors.
        let s1 = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -5.0]];
        let s2 = [[0.0, -1.0, 2.0], [0.0, 1.0, 2.0], [0.0, 0.0, 7.0]];
        assert!(triangles_within(&s1, &s2, 2.0));
        assert!(!triangles_within(&s1, &s2, 2.0f64.next_down()));
        // Zero distance is the intersection test.
        assert!(!triangles_within(&t1, &t2, 0.0));
        assert!(triangles_within(
            &t1,
            &[[0.5, 0.5, 0.0], [3.0, 3.0, 1.0], [3.0, 3.0, -1.0]],
            0.0
        ));
    }

    #[test]
    fn extreme_scales() {
        for scale in [1e-300, 1e-150, 1.0, 1e150, 1e300] {
            let t1 = [[0.0, 0.0, 0.0], [scale, 0.0, 0.0], [0.0, scale, 0.0]];
            let t2 = [[0.0, 0.0, scale], [scale, 0.0, scale], [0.0, scale, scale]];
            assert!(triangles_within(&t1, &t2, scale), "{scale}");
            assert!(!triangles_within(&t1, &t2, scale.next_down()), "{scale}");
        }
    }
}
