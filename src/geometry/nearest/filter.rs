//! A floating-point filter that rejects most pairs farther apart than `d` without exact
//! arithmetic: the gap along one direction is a lower bound on the distance of two convex sets,
//! and the direction between approximate closest points makes that bound nearly tight.

use super::Primitive;
use crate::geometry::predicates::Point;

/// Is the distance of the primitives `p` (a point and a triangle, or two segments) certainly
/// more than `d`? `false` when the filter cannot tell (then the exact test decides).
pub(super) fn certainly_apart(pair: Primitive, p: &[Point; 4], d: f64) -> bool {
    let u = match pair {
        Primitive::VertexFace => sub(&p[0], &point_triangle(&p[0], &p[1], &p[2], &p[3])),
        Primitive::EdgeEdge => {
            let (a, b) = segment_segment(&p[0], &p[1], &p[2], &p[3]);
            sub(&a, &b)
        }
    };
    lower_along(pair, p, u) > d
}

/// The squared distance of `p` from an approximate closest point of triangle `abc` (an
/// estimate, for choosing a nearest triangle) and a certain lower bound of the exact distance,
/// or `None` when that bound is beyond `reach`. The bound is the separation along the
/// estimate's own direction ([`lower_along`], sharing the differences the estimate took):
/// nearly the exact distance. It is computed only where the estimate is beyond `reach`;
/// within, it is given as 0.
#[inline]
pub(crate) fn point_triangle_within(
    p: &Point,
    a: &Point,
    b: &Point,
    c: &Point,
    reach: f64,
) -> Option<(f64, f64)> {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let u = sub(&ap, &point_triangle_offset(p, b, c, &ab, &ac, &ap));
    let estimate = dot(&u, &u);
    // Within the reach, or a NaN estimate (a degenerate triangle): kept, unbounded.
    if estimate.partial_cmp(&(reach * reach)) != Some(std::cmp::Ordering::Greater) {
        return Some((estimate, 0.0));
    }
    let big = u[0].abs().max(u[1].abs()).max(u[2].abs());
    if !(big > 0.0 && big.is_finite()) {
        return Some((estimate, 0.0));
    }
    let scale = power_of_two_below(big);
    let u = [u[0] / scale, u[1] / scale, u[2] / scale];
    // As `lower_along` with the triangle's corner `a` as origin: the point's projection, and the
    // corners' (0 for `a` itself).
    let proj = |x: &Point| {
        (
            u[0] * x[0] + u[1] * x[1] + u[2] * x[2],
            u[0].abs() * x[0].abs() + u[1].abs() * x[1].abs() + u[2].abs() * x[2].abs(),
        )
    };
    let (lo_a, e0) = proj(&ap);
    let (sb, e1) = proj(&ab);
    let (sc, e2) = proj(&ac);
    let hi_b = sb.max(sc).max(0.0);
    let err = e0.max(e1).max(e2);
    let lower = finish_lower(lo_a, hi_b, err, &u);
    (lower <= reach).then_some((estimate, lower))
}

/// A lower bound of the distance of the primitives `p` from their separation along `u` (0 when
/// it cannot tell).
///
/// For any direction `u`, every point `a` of the first primitive and `b` of the second satisfy
/// `|a - b| >= u.(a - b) / |u| >= (min over a's corners of u.a - max over b's corners of u.b) /
/// |u|`, the corners spanning each convex primitive. The floating-point evaluation is bounded
/// below with a margin for every rounding, so the bound holds exactly.
#[inline]
fn lower_along(pair: Primitive, p: &[Point; 4], u: Point) -> f64 {
    let split = pair.split();
    // Projections relative to one corner of the second primitive, so that coordinates far from
    // the origin cancel before the products.
    separation_along(&p[..split], &p[split..], &p[split], u)
}

/// A lower bound of the distance between two triangles (each the convex hull of its corners)
/// from their separation along `u`, pointing from `b` towards `a` (0 when it cannot tell), as
/// [`lower_along`] bounds a primitive pair's.
#[inline]
pub(crate) fn triangles_lower_along(a: &[Point; 3], b: &[Point; 3], u: Point) -> f64 {
    separation_along(a, b, &b[0], u)
}

/// [`lower_along`] of the convex hulls of `first` and `second`, the projections taken
/// relative to `o`.
#[inline(always)]
fn separation_along(first: &[Point], second: &[Point], o: &Point, u: Point) -> f64 {
    // Scaled by a power of two (exact) so that `u`'s largest component is about one: its
    // squared length then neither underflows nor loses relative precision, whatever the scale
    // of the coordinates.
    let big = u[0].abs().max(u[1].abs()).max(u[2].abs());
    if !(big > 0.0 && big.is_finite()) {
        return 0.0;
    }
    let scale = power_of_two_below(big);
    let u = [u[0] / scale, u[1] / scale, u[2] / scale];
    let mut lo_a = f64::INFINITY;
    let mut hi_b = f64::NEG_INFINITY;
    let mut err: f64 = 0.0;
    let mut project = |q: &Point| {
        let x = sub(q, o);
        let s = u[0] * x[0] + u[1] * x[1] + u[2] * x[2];
        let size = u[0].abs() * x[0].abs() + u[1].abs() * x[1].abs() + u[2].abs() * x[2].abs();
        err = err.max(size);
        s
    };
    for q in first {
        lo_a = lo_a.min(project(q));
    }
    for q in second {
        hi_b = hi_b.max(project(q));
    }
    finish_lower(lo_a, hi_b, err, &u)
}

/// The lower bound of [`lower_along`] from the least projection `lo_a` of the first
/// primitive's corners, the greatest `hi_b` of the second's, the largest size `err` of a
/// projection's terms and the (scaled) direction `u`.
#[inline(always)]
fn finish_lower(lo_a: f64, hi_b: f64, err: f64, u: &Point) -> f64 {
    // Each projection is within 5 eps of its size of the exact u.(q - o) (the difference
    // rounded once, three products and two sums); the gap's subtraction adds one rounding; the
    // absolute term covers underflow.
    let gap = (lo_a - hi_b) - 8.0 * f64::EPSILON * err - (lo_a.abs() + hi_b.abs()) * f64::EPSILON;
    let gap = gap - 1e-300;
    if !(gap > 0.0 && gap.is_finite()) {
        return 0.0;
    }
    // |u| (its largest component between 1 and 2: squared at most 12) within 3 eps of
    // fl(sqrt(uu)); the product and the quotient one rounding each, the last product one more.
    let uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    let lower = gap / (uu.sqrt() * (1.0 + 8.0 * f64::EPSILON));
    lower * (1.0 - 4.0 * f64::EPSILON)
}

/// The power of two at most `x` (positive and finite), as a double: dividing by it is exact.
#[inline]
fn power_of_two_below(x: f64) -> f64 {
    if x < f64::MIN_POSITIVE {
        // Subnormal: scale by the smallest normal power, which keeps the division exact.
        return f64::MIN_POSITIVE;
    }
    f64::from_bits(x.to_bits() & 0x7ff0_0000_0000_0000)
}

/// Is the distance of the primitives `p` certainly at most `d`? True when a corner of one is
/// certainly within `d` of a corner of the other (`false` when it cannot tell). Pairs so told
/// need not be filtered: where many pairs come near, most are.
#[inline]
pub(super) fn certainly_within(pair: Primitive, p: &[Point; 4], d: f64) -> bool {
    let ends: &[(usize, usize)] = match pair {
        Primitive::VertexFace => &[(0, 1), (0, 2), (0, 3)],
        Primitive::EdgeEdge => &[(0, 2), (0, 3), (1, 2), (1, 3)],
    };
    // The rounded squared length is within 3 eps of the exact one (a rounded difference
    // squared, three terms summed), `d d` and the margin's product within one eps each: a
    // margin of 8 eps covers them all, unless `d d` is so small that underflow counts or so
    // large that it overflows (then nothing is told).
    let dd = d * d;
    if !(1e-280..=f64::MAX).contains(&dd) {
        return false;
    }
    let within = dd * (1.0 - 8.0 * f64::EPSILON);
    ends.iter().any(|&(i, j)| {
        let x = sub(&p[i], &p[j]);
        dot(&x, &x) <= within
    })
}

#[inline]
fn sub(a: &Point, b: &Point) -> Point {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn dot(a: &Point, b: &Point) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn along(a: &Point, u: &Point, s: f64) -> Point {
    [a[0] + s * u[0], a[1] + s * u[1], a[2] + s * u[2]]
}

/// An approximate closest point of triangle `abc` to `p` (by the Voronoi regions of its
/// corners and edges; a direction is all the filter needs, so degenerate triangles may give
/// any point, or a non-finite one that the filter refuses).
pub(crate) fn point_triangle(p: &Point, a: &Point, b: &Point, c: &Point) -> Point {
    let o = point_triangle_offset(p, b, c, &sub(b, a), &sub(c, a), &sub(p, a));
    [a[0] + o[0], a[1] + o[1], a[2] + o[2]]
}

/// [`point_triangle`]'s point less `a`, given the differences `b - a`, `c - a` and `p - a`:
/// relative to a corner, so that far from the origin the direction from it to `p` keeps its
/// precision.
#[inline(always)]
fn point_triangle_offset(
    p: &Point,
    b: &Point,
    c: &Point,
    ab: &Point,
    ac: &Point,
    ap: &Point,
) -> Point {
    let (ab, ac, ap) = (*ab, *ac, *ap);
    let (d1, d2) = (dot(&ab, &ap), dot(&ac, &ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [0.0; 3];
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(&ab, &bp), dot(&ac, &bp));
    if d3 >= 0.0 && d4 <= d3 {
        return ab;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return scale(&ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(&ab, &cp), dot(&ac, &cp));
    if d6 >= 0.0 && d5 <= d6 {
        return ac;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return scale(&ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return along(&ab, &sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    [
        ab[0] * v + ac[0] * w,
        ab[1] * v + ac[1] * w,
        ab[2] * v + ac[2] * w,
    ]
}

#[inline]
fn scale(u: &Point, s: f64) -> Point {
    [u[0] * s, u[1] * s, u[2] * s]
}

/// Approximate closest points of segments `[p1, q1]` and `[p2, q2]` (parameters clamped to
/// the segments, zero-length and parallel segments handled as points and by an end).
pub(crate) fn segment_segment(p1: &Point, q1: &Point, p2: &Point, q2: &Point) -> (Point, Point) {
    let (d1, d2, r) = (sub(q1, p1), sub(q2, p2), sub(p1, p2));
    let (a, e, f) = (dot(&d1, &d1), dot(&d2, &d2), dot(&d2, &r));
    let (s, t) = if a == 0.0 && e == 0.0 {
        (0.0, 0.0)
    } else if a == 0.0 {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = dot(&d1, &r);
        if e == 0.0 {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = dot(&d1, &d2);
            let denom = a * e - b * b;
            let mut s = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    (along(p1, &d1, s), along(p2, &d2, t))
}
