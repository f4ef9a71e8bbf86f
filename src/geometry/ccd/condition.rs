//! Contact of linearly moving primitives as a condition on the signs of polynomials in t.
//!
//! Every point moves linearly over t in [0, 1]. A contact at time t is a condition on the signs
//! of a few polynomials in t:
//! - the four points are coplanar (a cubic, the orientation determinant, is zero), and
//! - in each of the three axis projections, the projected primitives meet: a point in a closed
//!   triangle (the three edge orientations, quadratics, all of one sign or zero, and the point
//!   in the corners' bounding box) or two closed segments (each segment's ends on both sides of
//!   the other's line or on it, and their bounding boxes overlapping).
//!
//! Coplanar primitives that meet in every projection meet in space: a projection along an axis
//! the plane does not contain is one-to-one on it, and a point off a segment (or off a point)
//! stays off it in some axis projection. Bounding boxes make the tests exact for collinear and
//! coincident corners, where all orientations vanish.

use super::poly::Poly;
use std::cmp::Ordering;

/// A point moving linearly: one polynomial of degree at most 1 per coordinate.
pub(crate) type Moving = [Poly; 3];

pub(crate) fn moving(start: &[f64; 3], end: &[f64; 3]) -> Moving {
    [0, 1, 2].map(|k| Poly::motion(start[k], end[k]))
}

fn minus(a: &Moving, b: &Moving) -> Moving {
    [0, 1, 2].map(|k| a[k].sub(&b[k]))
}

/// `u · (v × w)`.
fn det3(u: &Moving, v: &Moving, w: &Moving) -> Poly {
    let cross = [
        v[1].mul(&w[2]).sub(&v[2].mul(&w[1])),
        v[2].mul(&w[0]).sub(&v[0].mul(&w[2])),
        v[0].mul(&w[1]).sub(&v[1].mul(&w[0])),
    ];
    u[0].mul(&cross[0])
        .add(&u[1].mul(&cross[1]))
        .add(&u[2].mul(&cross[2]))
}

/// The orientation of `(u, v, w)` projected on axes `i`, `j`.
fn orient2d(u: &Moving, v: &Moving, w: &Moving, i: usize, j: usize) -> Poly {
    let (a, b) = (v[i].sub(&u[i]), w[j].sub(&u[j]));
    let (c, d) = (v[j].sub(&u[j]), w[i].sub(&u[i]));
    a.mul(&b).sub(&c.mul(&d))
}

const PROJECTIONS: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// A contact condition: polynomials and a test of their signs.
pub(crate) struct Condition {
    /// The polynomials; the first is the coplanarity determinant.
    pub polys: Vec<Poly>,
    /// Does contact hold, given each polynomial's sign?
    pub holds: fn(&[Ordering]) -> bool,
}

fn all_of_one_sign(s: &[Ordering]) -> bool {
    s.iter().all(|x| x.is_ge()) || s.iter().all(|x| x.is_le())
}

fn apart_or_on(a: Ordering, b: Ordering) -> bool {
    (a.is_ge() && b.is_le()) || (a.is_le() && b.is_ge())
}

/// Polynomials of vertex-face contact: [orientation, 3 × 3 edge orientations, 3 × 3 coordinate
/// differences point - corner].
pub(crate) fn vertex_face(p: &Moving, t: [&Moving; 3]) -> Condition {
    let mut polys = vec![det3(
        &minus(t[1], t[0]),
        &minus(t[2], t[0]),
        &minus(p, t[0]),
    )];
    for (i, j) in PROJECTIONS {
        for e in 0..3 {
            polys.push(orient2d(t[e], t[(e + 1) % 3], p, i, j));
        }
    }
    for k in 0..3 {
        for c in t {
            polys.push(p[k].sub(&c[k]));
        }
    }
    fn holds(s: &[Ordering]) -> bool {
        let (o, d) = (&s[1..10], &s[10..19]);
        s[0].is_eq()
            && o.chunks(3).all(all_of_one_sign)
            && d.chunks(3)
                .all(|c| c.iter().any(|x| x.is_ge()) && c.iter().any(|x| x.is_le()))
    }
    Condition { polys, holds }
}

/// Polynomials of edge-edge contact: [orientation, 3 × 4 orientations, 3 × 4 coordinate
/// differences a_i - b_j].
pub(crate) fn edge_edge(a: [&Moving; 2], b: [&Moving; 2]) -> Condition {
    let mut polys = vec![det3(
        &minus(a[1], a[0]),
        &minus(b[0], a[0]),
        &minus(b[1], a[0]),
    )];
    for (i, j) in PROJECTIONS {
        polys.push(orient2d(a[0], a[1], b[0], i, j));
        polys.push(orient2d(a[0], a[1], b[1], i, j));
        polys.push(orient2d(b[0], b[1], a[0], i, j));
        polys.push(orient2d(b[0], b[1], a[1], i, j));
    }
    for k in 0..3 {
        for ai in a {
            for bj in b {
                polys.push(ai[k].sub(&bj[k]));
            }
        }
    }
    fn holds(s: &[Ordering]) -> bool {
        let (o, d) = (&s[1..13], &s[13..25]);
        s[0].is_eq()
            && o.chunks(4)
                .all(|c| apart_or_on(c[0], c[1]) && apart_or_on(c[2], c[3]))
            && d.chunks(4)
                .all(|c| c.iter().any(|x| x.is_ge()) && c.iter().any(|x| x.is_le()))
    }
    Condition { polys, holds }
}
