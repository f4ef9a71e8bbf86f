//! Exact orientation predicates on `f64` coordinates.
//!
//! Every geometric decision of the triangle test is the sign of one of two determinants:
//! `orient3d` (which side of the plane through `a, b, c` the point `d` lies on) and `orient2d`
//! (the same in a coordinate plane). The signs are exact for the given doubles.
//!
//! Shewchuk's adaptive predicates (the `robust` crate) give the exact sign as long as no
//! intermediate product overflows or underflows. That is guaranteed when every coordinate is zero
//! or has a magnitude in [`SAFE_MIN`, `SAFE_MAX`] (about 1e-60 to 1e60): differences are then
//! multiples of `2^-252` and at most `2^201`, so products of three stay far inside the normal
//! range. Callers check that once per triangle pair and otherwise use [`BigExact`], which
//! evaluates the same determinants with big integers (every finite double is an integer times a
//! power of two). That path is slow but only ever taken for coordinates outside the range.

use num_bigint::BigInt;
use num_traits::Signed;
use num_traits::Zero;
use std::cell::Cell;

/// A point in space.
pub type Point = [f64; 3];

/// Smallest non-zero magnitude for which the adaptive predicates are known to be exact: `2^-200`.
pub const SAFE_MIN: f64 = f64::from_bits((1023 - 200) << 52);
/// Largest magnitude for which the adaptive predicates are known to be exact: `2^200`.
pub const SAFE_MAX: f64 = f64::from_bits((1023 + 200) << 52);

/// Is `x` zero or of a magnitude inside [`SAFE_MIN`, `SAFE_MAX`]?
#[inline]
pub fn is_safe_coordinate(x: f64) -> bool {
    let a = x.abs();
    a == 0.0 || (SAFE_MIN..=SAFE_MAX).contains(&a)
}

/// Are all coordinates of `p` safe (see [`is_safe_coordinate`])?
#[inline]
pub fn is_safe_point(p: &Point) -> bool {
    is_safe_coordinate(p[0]) && is_safe_coordinate(p[1]) && is_safe_coordinate(p[2])
}

/// A sign: -1, 0 or 1.
pub type Sign = i8;

#[inline]
fn sign_of(v: f64) -> Sign {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

/// Orientation predicates, implemented twice: fast for safe coordinates, big-integer otherwise.
pub trait Orient {
    /// Sign of `det[a - d; b - d; c - d]`: positive when `d` lies below the plane through `a, b, c`
    /// (seen from above, `a, b, c` turn counter-clockwise), zero when the four are coplanar.
    fn orient3d(a: &Point, b: &Point, c: &Point, d: &Point) -> Sign;
    /// Sign of `(a - c) x (b - c)`: positive when `a, b, c` turn counter-clockwise.
    fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign;
    /// `orient3d(t[0], t[1], t[2], p)` for each of three points `p`.
    fn plane_sides(t: &[Point; 3], points: &[Point; 3]) -> [Sign; 3] {
        points.map(|p| Self::orient3d(&t[0], &t[1], &t[2], &p))
    }
    /// With `t` of orientation `inside` (not zero), how the edge lines of `t` place the points
    /// of `other` (see [`EdgeTest`]), when a cheap stage can tell; `None` when it cannot, and
    /// the caller asks `orient2d` sign by sign.
    #[inline(always)]
    fn edge_test(_t: &[[f64; 2]; 3], _inside: Sign, _other: &[[f64; 2]; 3]) -> Option<EdgeTest> {
        None
    }
}

/// Where the points of a triangle lie relative to the edge lines of another, `t`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeTest {
    /// All three strictly outside the line through one edge of `t`: the triangles are disjoint.
    Separated,
    /// One of them strictly inside `t`: the triangles meet.
    Inside,
    /// Neither: no edge of `t` separates the triangles.
    Open,
}

/// [`Orient::edge_test`] from the floating-point stage of the nine `orient2d`, computed without
/// branches (the early exits of asking sign after sign mispredict between coplanar sheets): a
/// sign is certain when the determinant exceeds Shewchuk's bound, or is zero when the bound is
/// (both products exactly zero: no underflow for safe coordinates). Only for safe coordinates.
#[inline(always)]
fn edge_test_filtered(t: &[[f64; 2]; 3], inside: Sign, other: &[[f64; 2]; 3]) -> Option<EdgeTest> {
    let s = f64::from(inside);
    let (mut separated, mut open) = (false, true);
    let mut strictly_inside = [true; 3];
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        let (mut outside, mut not_outside) = (true, false);
        for (p, inner) in other.iter().zip(&mut strictly_inside) {
            let (det, bound) = orient2d_stage_one(t[i], t[j], *p);
            let d = s * det;
            outside &= d < -bound;
            *inner &= d > bound;
            not_outside |= d > bound || bound == 0.0;
        }
        separated |= outside;
        open &= not_outside;
    }
    if separated {
        Some(EdgeTest::Separated)
    } else if strictly_inside.iter().any(|&x| x) {
        Some(EdgeTest::Inside)
    } else if open {
        Some(EdgeTest::Open)
    } else {
        None
    }
}

/// Shewchuk's error bound for the floating-point orientation determinant (`o3derrboundA`). It
/// holds for any evaluation of the determinant as a sum, in order, of three rounded coordinate
/// differences each times a rounded 2x2 minor of rounded differences, against the permanent of
/// the same shape, when nothing overflows or underflows.
const ORIENT3D_FILTER: f64 = (7.0 + 56.0 * HALF_ULP) * HALF_ULP;
const HALF_ULP: f64 = f64::EPSILON / 2.0;

/// Shewchuk's first, floating-point stage of `orient3d`: the determinant and the permanent its
/// error bound scales (the same expression as the `robust` crate's).
#[inline(always)]
fn orient3d_stage_one(a: &Point, b: &Point, c: &Point, d: &Point) -> (f64, f64) {
    let (adx, ady, adz) = (a[0] - d[0], a[1] - d[1], a[2] - d[2]);
    let (bdx, bdy, bdz) = (b[0] - d[0], b[1] - d[1], b[2] - d[2]);
    let (cdx, cdy, cdz) = (c[0] - d[0], c[1] - d[1], c[2] - d[2]);
    let (bdxcdy, cdxbdy) = (bdx * cdy, cdx * bdy);
    let (cdxady, adxcdy) = (cdx * ady, adx * cdy);
    let (adxbdy, bdxady) = (adx * bdy, bdx * ady);
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * adz.abs()
        + (cdxady.abs() + adxcdy.abs()) * bdz.abs()
        + (adxbdy.abs() + bdxady.abs()) * cdz.abs();
    (det, permanent)
}

/// More than the absolute error of the two products of [`orient2d_stage_one`] where they
/// underflow (each at most half the least subnormal, `2^-1075`).
const UNDERFLOW_SLACK: f64 = f64::from_bits((1023 - 1000) << 52);

/// Shewchuk's error bound for the floating-point `orient2d` (`ccwerrboundA`).
const ORIENT2D_FILTER: f64 = (3.0 + 16.0 * HALF_ULP) * HALF_ULP;

/// Shewchuk's first, floating-point stage of `orient2d`: the determinant and its error bound
/// (`ccwerrboundA` times the sum of the two products' magnitudes). With the products of opposite
/// signs, or one of them zero, the determinant exceeds the bound unless both are zero.
#[inline(always)]
fn orient2d_stage_one(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> (f64, f64) {
    let detleft = (a[0] - c[0]) * (b[1] - c[1]);
    let detright = (a[1] - c[1]) * (b[0] - c[0]);
    (
        detleft - detright,
        ORIENT2D_FILTER * (detleft.abs() + detright.abs()),
    )
}

/// A triangle's plane as the `orient3d` filter evaluates it: the floating-point normal
/// `n = (t1 - t0) x (t2 - t0)` and, per component, the sum of its two products' magnitudes. The
/// determinant `det[t1 - t0; t2 - t0; p - t0]` is then `n . (p - t0)`, one rounded difference per
/// coordinate times a rounded minor of rounded differences, summed in order: the shape of
/// Shewchuk's bound ([`ORIENT3D_FILTER`] times the permanent `k . |p - t0|`). Computed once per
/// triangle, it serves every point tested against the triangle: the three corners of each
/// triangle it meets, in a query as many times as the triangle is tested.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Plane {
    n: [f64; 3],
    k: [f64; 3],
}

impl Plane {
    /// The plane of `t`.
    #[inline(always)]
    pub fn of(t: &[Point; 3]) -> Plane {
        let a = &t[0];
        let e1 = [t[1][0] - a[0], t[1][1] - a[1], t[1][2] - a[2]];
        let e2 = [t[2][0] - a[0], t[2][1] - a[1], t[2][2] - a[2]];
        let m = [
            e1[1] * e2[2],
            e1[2] * e2[1],
            e1[2] * e2[0],
            e1[0] * e2[2],
            e1[0] * e2[1],
            e1[1] * e2[0],
        ];
        Plane {
            n: [m[0] - m[1], m[2] - m[3], m[4] - m[5]],
            k: [
                m[0].abs() + m[1].abs(),
                m[2].abs() + m[3].abs(),
                m[4].abs() + m[5].abs(),
            ],
        }
    }

    /// The floating-point normal: its components are the triangle's projected areas, doubled
    /// (each with a rounding error).
    #[inline(always)]
    pub fn normal(&self) -> [f64; 3] {
        self.n
    }

    /// `det[t1 - t0; t2 - t0; p - t0]` in floating point (`-orient3d(t0, t1, t2, p)`) and its
    /// error bound, for `a = t0`.
    #[inline(always)]
    fn stage_one(&self, a: &Point, p: &Point) -> (f64, f64) {
        let (n, k) = (&self.n, &self.k);
        let f = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
        let det = f[0] * n[0] + f[1] * n[1] + f[2] * n[2];
        let bound = ORIENT3D_FILTER * (f[0].abs() * k[0] + f[1].abs() * k[1] + f[2].abs() * k[2]);
        (det, bound)
    }
}

/// Shewchuk's adaptive predicates; exact when every coordinate is safe.
pub struct Adaptive;

impl Adaptive {
    /// [`Orient::plane_sides`] for `t` whose [`Plane`] is `plane`: each sign is taken from the
    /// floating-point determinant when it exceeds Shewchuk's error bound; only uncertain signs
    /// go to the adaptive predicate. Exact when every coordinate is safe.
    #[inline]
    pub(crate) fn sides_of_plane(plane: &Plane, t: &[Point; 3], points: &[Point; 3]) -> [Sign; 3] {
        [
            Adaptive::side_of_plane(plane, t, &points[0]),
            Adaptive::side_of_plane(plane, t, &points[1]),
            Adaptive::side_of_plane(plane, t, &points[2]),
        ]
    }

    /// One sign of [`Adaptive::sides_of_plane`]: a function of its own, always inlined (a closure
    /// or `array::map` may be left as an out-of-line call per point in the triangle test's
    /// hottest loop).
    #[inline(always)]
    fn side_of_plane(plane: &Plane, t: &[Point; 3], p: &Point) -> Sign {
        let (det, bound) = plane.stage_one(&t[0], p);
        if det > bound {
            -1
        } else if -det > bound {
            1
        } else if bound == 0.0 || t.contains(p) {
            // A zero bound has every term with an exactly zero factor (no product underflows in
            // the safe range), so the determinant is exactly zero, as is one with `p` a corner.
            0
        } else {
            Self::orient3d(&t[0], &t[1], &t[2], p)
        }
    }
}

impl Orient for Adaptive {
    /// Shewchuk's first, floating-point stage is evaluated here (the same expression and bound as
    /// the `robust` crate's) so that what it leaves uncertain can be triaged before the adaptive
    /// stages: an exactly zero determinant, the common case of triangles that share a vertex,
    /// otherwise runs those stages to the end. Coincident points, or a permanent of zero (every
    /// product has an exactly zero factor), give zero at once.
    #[inline]
    fn orient3d(a: &Point, b: &Point, c: &Point, d: &Point) -> Sign {
        let (det, permanent) = orient3d_stage_one(a, b, c, d);
        let bound = ORIENT3D_FILTER * permanent;
        if det > bound {
            return 1;
        }
        if -det > bound {
            return -1;
        }
        if permanent == 0.0 || a == b || a == c || b == c {
            return 0;
        }
        let c3 = |p: &Point| robust::Coord3D {
            x: p[0],
            y: p[1],
            z: p[2],
        };
        sign_of(robust::orient3d(c3(a), c3(b), c3(c), c3(d)))
    }

    /// The triangle's plane is computed once for the three points.
    #[inline]
    fn plane_sides(t: &[Point; 3], points: &[Point; 3]) -> [Sign; 3] {
        Adaptive::sides_of_plane(&Plane::of(t), t, points)
    }

    #[inline(always)]
    fn edge_test(t: &[[f64; 2]; 3], inside: Sign, other: &[[f64; 2]; 3]) -> Option<EdgeTest> {
        edge_test_filtered(t, inside, other)
    }

    /// Shewchuk's floating-point stage is evaluated here, inline (a call into `robust` per sign
    /// was a third of a query between coplanar sheets); only uncertain signs go further.
    #[inline]
    fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
        let (det, bound) = orient2d_stage_one(a, b, c);
        if det > bound {
            return 1;
        }
        if -det > bound {
            return -1;
        }
        // A zero bound has both products exactly zero (no underflow in the safe range); `robust`
        // settles c == a and c == b in its first stage but not a == b.
        if bound == 0.0 || a == b {
            return 0;
        }
        let c2 = |p: [f64; 2]| robust::Coord { x: p[0], y: p[1] };
        sign_of(robust::orient2d(c2(a), c2(b), c2(c)))
    }
}

thread_local! {
    /// Set by [`FilterProbe`] when a predicate's floating-point stage leaves its sign undecided.
    static UNSETTLED: Cell<bool> = const { Cell::new(false) };
}

/// The adaptive predicates, recording whether any sign needed more than the floating-point
/// stage (the adaptive stages): how often exactness costs extra arithmetic. Signs decided by
/// exact shortcuts (coincident points, exactly zero products) count as settled, as they cost
/// nothing either. Diagnostics only, served by `dvh::fixtures`; the queries use [`Adaptive`].
#[cfg_attr(not(feature = "fixtures"), allow(dead_code))]
pub(crate) struct FilterProbe;

#[cfg_attr(not(feature = "fixtures"), allow(dead_code))]
impl FilterProbe {
    /// Clears the record; returns whether a sign was left undecided since the last call.
    pub fn take() -> bool {
        UNSETTLED.with(|u| u.replace(false))
    }

    fn unsettled() {
        UNSETTLED.with(|u| u.set(true));
    }
}

impl Orient for FilterProbe {
    fn orient3d(a: &Point, b: &Point, c: &Point, d: &Point) -> Sign {
        let (det, permanent) = orient3d_stage_one(a, b, c, d);
        let bound = ORIENT3D_FILTER * permanent;
        if det.abs() <= bound && !(permanent == 0.0 || a == b || a == c || b == c) {
            FilterProbe::unsettled();
        }
        Adaptive::orient3d(a, b, c, d)
    }

    /// [`Adaptive::plane_sides`]'s per-triangle filter; what it leaves goes to `orient3d` above.
    fn plane_sides(t: &[Point; 3], points: &[Point; 3]) -> [Sign; 3] {
        let plane = Plane::of(t);
        points.map(|p| {
            let (det, bound) = plane.stage_one(&t[0], &p);
            if det.abs() > bound || t.contains(&p) {
                Adaptive::side_of_plane(&plane, t, &p)
            } else {
                Self::orient3d(&t[0], &t[1], &t[2], &p)
            }
        })
    }

    fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
        let (det, bound) = orient2d_stage_one(a, b, c);
        if det.abs() <= bound && !(bound == 0.0 || a == b) {
            FilterProbe::unsettled();
        }
        Adaptive::orient2d(a, b, c)
    }
}

/// The same determinants in exact integer arithmetic, for any finite coordinates.
pub struct BigExact;

/// `x = mantissa * 2^exponent` exactly, for finite `x`.
fn decompose(x: f64) -> (i64, i32) {
    let bits = x.to_bits();
    let exponent_bits = ((bits >> 52) & 0x7ff) as i32;
    let fraction = (bits & ((1u64 << 52) - 1)) as i64;
    let (mantissa, exponent) = if exponent_bits == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1i64 << 52), exponent_bits - 1075)
    };
    if x.is_sign_negative() {
        (-mantissa, exponent)
    } else {
        (mantissa, exponent)
    }
}

/// The values scaled by one common power of two, as exact integers.
pub(crate) fn to_integers<const N: usize>(values: [f64; N]) -> [BigInt; N] {
    to_integers_scaled(values).0
}

/// [`to_integers`], with the power: each value is its integer times `2^power`.
pub(crate) fn to_integers_scaled<const N: usize>(values: [f64; N]) -> ([BigInt; N], i32) {
    let parts = values.map(decompose);
    let lowest = parts
        .iter()
        .filter(|(m, _)| *m != 0)
        .map(|&(_, e)| e)
        .min()
        .unwrap_or(0);
    (
        parts.map(|(m, e)| BigInt::from(m) << ((e - lowest) as usize)),
        lowest,
    )
}

fn sign_of_big(v: &BigInt) -> Sign {
    if v.is_zero() {
        0
    } else if v.is_positive() {
        1
    } else {
        -1
    }
}

impl Orient for BigExact {
    fn orient3d(a: &Point, b: &Point, c: &Point, d: &Point) -> Sign {
        let [ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz] = to_integers([
            a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2],
        ]);
        let (adx, ady, adz) = (&ax - &dx, &ay - &dy, &az - &dz);
        let (bdx, bdy, bdz) = (&bx - &dx, &by - &dy, &bz - &dz);
        let (cdx, cdy, cdz) = (&cx - &dx, &cy - &dy, &cz - &dz);
        let det = &adz * (&bdx * &cdy - &cdx * &bdy)
            + &bdz * (&cdx * &ady - &adx * &cdy)
            + &cdz * (&adx * &bdy - &bdx * &ady);
        sign_of_big(&det)
    }

    fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
        let [ax, ay, bx, by, cx, cy] = to_integers([a[0], a[1], b[0], b[1], c[0], c[1]]);
        let det = (&ax - &cx) * (&by - &cy) - (&ay - &cy) * (&bx - &cx);
        sign_of_big(&det)
    }
}

/// Exact `orient2d` for any finite coordinates (see [`Orient::orient2d`]).
#[inline]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    // The first stage settles most calls whatever the range: its bound holds for rounding, and
    // [`UNDERFLOW_SLACK`] covers products that fell below the normal range; an overflow makes
    // the bound infinite or NaN, which no comparison passes.
    let (det, bound) = orient2d_stage_one(a, b, c);
    let bound = bound + UNDERFLOW_SLACK;
    if det > bound {
        return 1;
    }
    if -det > bound {
        return -1;
    }
    orient2d_beyond_filter(a, b, c)
}

/// [`orient2d`] of the triangle `a, b, c` in the three coordinate projections: entry `k` leaves
/// coordinate `k` out and keeps the other two in cyclic order (`k + 1`, `k + 2`), so it is the
/// sign of component `k` of the triangle's normal. Exact; the three first stages share their
/// coordinate differences.
#[inline]
pub fn projected_orientations(a: &Point, b: &Point, c: &Point) -> [Sign; 3] {
    let ac = [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
    let bc = [b[0] - c[0], b[1] - c[1], b[2] - c[2]];
    std::array::from_fn(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        // `orient2d_stage_one` of the projections, from the shared differences.
        let (left, right) = (ac[i] * bc[j], ac[j] * bc[i]);
        let det = left - right;
        let bound = ORIENT2D_FILTER * (left.abs() + right.abs()) + UNDERFLOW_SLACK;
        if det > bound {
            1
        } else if -det > bound {
            -1
        } else {
            orient2d_beyond_filter([a[i], a[j]], [b[i], b[j]], [c[i], c[j]])
        }
    })
}

/// [`orient2d`] where its first stage cannot decide: rare, so kept out of its callers' loops.
#[cold]
#[inline(never)]
fn orient2d_beyond_filter(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    if [a, b, c]
        .iter()
        .all(|p| is_safe_coordinate(p[0]) && is_safe_coordinate(p[1]))
    {
        Adaptive::orient2d(a, b, c)
    } else {
        BigExact::orient2d(a, b, c)
    }
}

/// Exact `orient3d` for any finite coordinates (see [`Orient::orient3d`]).
pub fn orient3d(a: &Point, b: &Point, c: &Point, d: &Point) -> Sign {
    if [a, b, c, d].into_iter().all(is_safe_point) {
        Adaptive::orient3d(a, b, c, d)
    } else {
        BigExact::orient3d(a, b, c, d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn decompose_is_exact() {
        for x in [
            0.0,
            -0.0,
            1.0,
            -3.5,
            f64::MIN_POSITIVE,
            f64::MIN_POSITIVE / 7.0,
            5e-324,
            f64::MAX,
            -f64::MAX,
            0.1,
        ] {
            let (m, e) = decompose(x);
            // In two steps: a power of two below 2^-1022 computed at run time is 1 / 2^-e,
            // which overflows to infinity (0 then), unless the compiler folded the constant.
            assert_eq!(m as f64 * 2f64.powi(e / 2) * 2f64.powi(e - e / 2), x, "{x}");
        }
        assert_eq!(SAFE_MIN, 2f64.powi(-200));
        assert_eq!(SAFE_MAX, 2f64.powi(200));
    }

    #[test]
    fn orientation_conventions_agree() {
        let a = [0.0, 0.0, 0.0];
        let b = [1.0, 0.0, 0.0];
        let c = [0.0, 1.0, 0.0];
        let below = [0.0, 0.0, -1.0];
        let above = [0.0, 0.0, 1.0];
        assert_eq!(Adaptive::orient3d(&a, &b, &c, &below), 1);
        assert_eq!(BigExact::orient3d(&a, &b, &c, &below), 1);
        assert_eq!(Adaptive::orient3d(&a, &b, &c, &above), -1);
        assert_eq!(BigExact::orient3d(&a, &b, &c, &above), -1);
        assert_eq!(Adaptive::orient2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 1);
        assert_eq!(BigExact::orient2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 1);
    }

    #[test]
    fn extreme_coordinates_use_the_exact_path() {
        // Scaled by 2^-1000 the adaptive predicate underflows to zero; the exact answer stays.
        let s = 2f64.powi(-1000);
        let a = [0.0, 0.0, 0.0];
        let b = [s, 0.0, 0.0];
        let c = [0.0, s, 0.0];
        let d = [0.0, 0.0, -s];
        assert_eq!(orient3d(&a, &b, &c, &d), 1);
        let big = 2f64.powi(1000);
        let b = [big, 0.0, 0.0];
        let c = [0.0, big, 0.0];
        let d = [0.0, 0.0, -big];
        assert_eq!(orient3d(&a, &b, &c, &d), 1);
        // Nearly coplanar at a huge offset: the answer depends on the last bit.
        let o = 1e250;
        let a = [o, o, o];
        let b = [o + o * f64::EPSILON, o, o];
        let c = [o, o + o * f64::EPSILON, o];
        let d_on = [o, o, o];
        assert_eq!(orient3d(&a, &b, &c, &d_on), 0);
    }

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            (-8i32..8).prop_map(f64::from),
            -1e3f64..1e3,
            (-1e3f64..1e3).prop_map(|x| x * 1e-12),
        ]
    }

    fn point() -> impl Strategy<Value = Point> {
        [coordinate(), coordinate(), coordinate()]
    }

    proptest! {
        #[test]
        fn adaptive_and_big_integer_agree(a in point(), b in point(), c in point(), d in point()) {
            prop_assert_eq!(Adaptive::orient3d(&a, &b, &c, &d), BigExact::orient3d(&a, &b, &c, &d));
            let p = |p: Point| [p[0], p[2]];
            prop_assert_eq!(
                Adaptive::orient2d(p(a), p(b), p(c)),
                BigExact::orient2d(p(a), p(b), p(c))
            );
        }

        #[test]
        fn projected_orientations_are_orient2d(
            a in point(), b in point(), c in point(), k in prop_oneof![Just(0i32), -1000i32..-900, 900i32..1000]
        ) {
            // Also at scales where the products underflow into subnormals or overflow.
            let s = 2f64.powi(k);
            let (a, b, c) = (a.map(|x| x * s), b.map(|x| x * s), c.map(|x| x * s));
            let flat = |p: Point, k: usize| [p[(k + 1) % 3], p[(k + 2) % 3]];
            let expected: [Sign; 3] = std::array::from_fn(|k| BigExact::orient2d(flat(a, k), flat(b, k), flat(c, k)));
            prop_assert_eq!(projected_orientations(&a, &b, &c), expected);
            for (k, &sign) in expected.iter().enumerate() {
                prop_assert_eq!(orient2d(flat(a, k), flat(b, k), flat(c, k)), sign);
            }
        }

        #[test]
        fn scaling_by_powers_of_two_keeps_the_sign(
            a in point(), b in point(), c in point(), d in point(), k in prop_oneof![-950i32..-850, 850i32..950]
        ) {
            let s = 2f64.powi(k);
            let scale = |p: Point| p.map(|x| x * s);
            // Scaling can make tiny inputs subnormal, which is inexact: only compare when exact.
            let exact = [a, b, c, d].iter().all(|p| p.iter().all(|&x| (x * s) / s == x));
            prop_assume!(exact);
            prop_assert_eq!(
                orient3d(&scale(a), &scale(b), &scale(c), &scale(d)),
                Adaptive::orient3d(&a, &b, &c, &d)
            );
        }
    }
}
