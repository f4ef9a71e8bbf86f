//! A floating-point filter that rejects most pairs farther apart than `d` without exact
//! arithmetic: the gap along one direction is a lower bound on the distance of two convex sets,
//! and the direction between approximate closest points makes that bound nearly tight.

use super::Primitive;
use crate::geometry::predicates::Point;

/// Is the distance of the primitives `p` (a point and a triangle, or two segments) certainly
/// more than `d`? `false` when the filter cannot tell (then the exact test decides).
///
/// For any direction `u`, every point `a` of the first primitive and `b` of the second satisfy
/// `|a - b| >= u.(a - b) / |u| >= (min over a's corners of u.a - max over b's corners of u.b) /
/// |u|`, the corners spanning each convex primitive. The floating-point evaluation is bounded
/// below with a margin for every rounding, so "more than `d`" holds exactly when said.
pub(super) fn certainly_apart(pair: Primitive, p: &[Point; 4], d: f64) -> bool {
    let split = pair.split();
    let u = match pair {
        Primitive::VertexFace => sub(&p[0], &point_triangle(&p[0], &p[1], &p[2], &p[3])),
        Primitive::EdgeEdge => {
            let (a, b) = segment_segment(&p[0], &p[1], &p[2], &p[3]);
            sub(&a, &b)
        }
    };
    // Projections relative to one corner of the second primitive, so that coordinates far from
    // the origin cancel before the products.
    let o = p[split];
    let mut lo_a = f64::INFINITY;
    let mut hi_b = f64::NEG_INFINITY;
    let mut err: f64 = 0.0;
    for (k, q) in p.iter().enumerate() {
        let x = sub(q, &o);
        let s = u[0] * x[0] + u[1] * x[1] + u[2] * x[2];
        let size = u[0].abs() * x[0].abs() + u[1].abs() * x[1].abs() + u[2].abs() * x[2].abs();
        err = err.max(size);
        if k < split {
            lo_a = lo_a.min(s);
        } else {
            hi_b = hi_b.max(s);
        }
    }
    // Each projection is within 5 eps of its size of the exact u.(q - o) (the difference
    // rounded once, three products and two sums); the gap's subtraction adds one rounding; the
    // absolute term covers underflow.
    let gap = (lo_a - hi_b) - 8.0 * f64::EPSILON * err - (lo_a.abs() + hi_b.abs()) * f64::EPSILON;
    let gap = gap - 1e-300;
    let uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    // |u| within 3 eps of fl(sqrt(uu)); the product with d one more rounding.
    let reach = d * uu.sqrt() * (1.0 + 8.0 * f64::EPSILON);
    gap.is_finite() && reach.is_finite() && uu > 0.0 && gap > reach
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
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(&ab, &ap), dot(&ac, &ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(&ab, &bp), dot(&ac, &bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return along(a, &ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(&ab, &cp), dot(&ac, &cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return along(a, &ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return along(b, &sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    [
        a[0] + ab[0] * v + ac[0] * w,
        a[1] + ab[1] * v + ac[1] * w,
        a[2] + ab[2] * v + ac[2] * w,
    ]
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
