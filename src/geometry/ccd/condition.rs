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

/// The arithmetic the polynomials are built in: exact rationals ([`Poly`]), or floating-point
/// intervals that enclose them.
pub(crate) trait Ring: Sized {
    /// `start + t (end - start)`.
    fn motion(start: f64, end: f64) -> Self;
    fn add(&self, o: &Self) -> Self;
    fn sub(&self, o: &Self) -> Self;
    fn mul(&self, o: &Self) -> Self;
}

impl Ring for Poly {
    fn motion(start: f64, end: f64) -> Poly {
        Poly::motion(start, end)
    }
    fn add(&self, o: &Poly) -> Poly {
        Poly::add(self, o)
    }
    fn sub(&self, o: &Poly) -> Poly {
        Poly::sub(self, o)
    }
    fn mul(&self, o: &Poly) -> Poly {
        Poly::mul(self, o)
    }
}

/// A point moving linearly: one polynomial of degree at most 1 per coordinate.
pub(crate) type Moving<P> = [P; 3];

pub(crate) fn moving<P: Ring>(start: &[f64; 3], end: &[f64; 3]) -> Moving<P> {
    [0, 1, 2].map(|k| P::motion(start[k], end[k]))
}

fn minus<P: Ring>(a: &Moving<P>, b: &Moving<P>) -> Moving<P> {
    [0, 1, 2].map(|k| a[k].sub(&b[k]))
}

/// `u · (v × w)`.
fn det3<P: Ring>(u: &Moving<P>, v: &Moving<P>, w: &Moving<P>) -> P {
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
fn orient2d<P: Ring>(u: &Moving<P>, v: &Moving<P>, w: &Moving<P>, i: usize, j: usize) -> P {
    let (a, b) = (v[i].sub(&u[i]), w[j].sub(&u[j]));
    let (c, d) = (v[j].sub(&u[j]), w[i].sub(&u[i]));
    a.mul(&b).sub(&c.mul(&d))
}

/// The axis projections, in the order the conditions list their orientations.
pub(crate) const PROJECTIONS: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// For each projection, the component of the primitives' plane normal along the projection's
/// missing axis: the triangle's projected orientation (vertex-face), or the projected cross
/// product of the two edges' directions (edge-edge). Where it is non-zero the projection is
/// one-to-one on the plane, the projected triangle is proper (or the projected edges are not
/// parallel), and that projection's orientations alone decide contact of coplanar primitives.
pub(crate) fn projection_normals<P: Ring>(edges: bool, m: [&Moving<P>; 4]) -> [P; 3] {
    PROJECTIONS.map(|(i, j)| {
        if edges {
            let (da, db) = (minus(m[1], m[0]), minus(m[3], m[2]));
            da[i].mul(&db[j]).sub(&da[j].mul(&db[i]))
        } else {
            orient2d(m[1], m[2], m[3], i, j)
        }
    })
}

/// A truth value that may be unknown (when signs are only enclosed).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Tri {
    No,
    Maybe,
    Yes,
}

impl Tri {
    pub(crate) fn and(self, o: Tri) -> Tri {
        match (self, o) {
            (Tri::No, _) | (_, Tri::No) => Tri::No,
            (Tri::Yes, Tri::Yes) => Tri::Yes,
            _ => Tri::Maybe,
        }
    }
    fn or(self, o: Tri) -> Tri {
        match (self, o) {
            (Tri::Yes, _) | (_, Tri::Yes) => Tri::Yes,
            (Tri::No, Tri::No) => Tri::No,
            _ => Tri::Maybe,
        }
    }
    fn all(it: impl IntoIterator<Item = Tri>) -> Tri {
        it.into_iter().fold(Tri::Yes, Tri::and)
    }
    fn any(it: impl IntoIterator<Item = Tri>) -> Tri {
        it.into_iter().fold(Tri::No, Tri::or)
    }
}

/// The signs a value may have: exactly one for an exact value, several for an enclosure.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) struct Signs {
    pub neg: bool,
    pub zero: bool,
    pub pos: bool,
}

impl Signs {
    /// The sign of an exact value.
    pub(crate) fn exact(o: Ordering) -> Signs {
        Signs {
            neg: o.is_lt(),
            zero: o.is_eq(),
            pos: o.is_gt(),
        }
    }
    /// The signs of a value in `[lo, hi]`.
    pub(crate) fn within(lo: f64, hi: f64) -> Signs {
        Signs {
            neg: lo < 0.0,
            zero: lo <= 0.0 && hi >= 0.0,
            pos: hi > 0.0,
        }
    }
    fn ge(self) -> Tri {
        Tri::of(!self.neg, self.zero || self.pos)
    }
    fn le(self) -> Tri {
        Tri::of(!self.pos, self.zero || self.neg)
    }
    pub(crate) fn eq(self) -> Tri {
        Tri::of(!self.neg && !self.pos, self.zero)
    }
}

impl Tri {
    /// `Yes` when certain, `No` when impossible, else `Maybe`.
    fn of(certain: bool, possible: bool) -> Tri {
        if certain {
            Tri::Yes
        } else if possible {
            Tri::Maybe
        } else {
            Tri::No
        }
    }
}

/// A contact condition: polynomials in a fixed layout, and a test of their signs.
///
/// Layout: the coplanarity determinant f first, then the orientations of each axis projection
/// in turn (3 for vertex-face, 4 for edge-edge), then the coordinate differences of each axis
/// in turn. Contact holds when f vanishes and every one of [`GROUPS`] groups holds: each group
/// is necessary alone, so a search can stop at the first that cannot hold.
pub(crate) struct Condition<P> {
    pub polys: Vec<P>,
    pub edges: bool,
}

/// Groups of a condition besides f: the coordinate differences of each axis, then the
/// orientations of each projection. This is the order they are judged in: differences are
/// linear, the cheapest to build and evaluate, and rule out most of what they can.
pub(crate) const GROUPS: usize = 6;

/// The polynomials of group `g` in the layout of [`Condition`].
pub(crate) fn group_range(edges: bool, g: usize) -> std::ops::Range<usize> {
    let w = if edges { 4 } else { 3 };
    let first = if g < 3 {
        1 + 3 * w + w * g
    } else {
        1 + w * (g - 3)
    };
    first..first + w
}

/// Does group `g` hold, given the signs its polynomials may have?
pub(crate) fn group_holds(edges: bool, g: usize, s: &[Signs]) -> Tri {
    if g < 3 {
        // Bounding boxes meet on this axis: the point (or some end of one edge) is on each
        // side of some corner (end of the other), or level with it.
        straddles(s)
    } else if edges {
        // Each segment's ends on both sides of the other's line, or on it.
        apart_or_on(s[0], s[1]).and(apart_or_on(s[2], s[3]))
    } else {
        // The point on the inner side of the triangle's three edges, or on them.
        all_of_one_sign(s)
    }
}

/// Builds the polynomials of group `g` for the points `m` (the vertex and the triangle's
/// corners, or edge a's ends and edge b's), in order, into `push`.
pub(crate) fn build_group<P: Ring>(
    edges: bool,
    m: [&Moving<P>; 4],
    g: usize,
    mut push: impl FnMut(P),
) {
    if g < 3 {
        let k = g;
        if edges {
            for ai in &m[..2] {
                for bj in &m[2..] {
                    push(ai[k].sub(&bj[k]));
                }
            }
        } else {
            for c in &m[1..] {
                push(m[0][k].sub(&c[k]));
            }
        }
    } else {
        let (i, j) = PROJECTIONS[g - 3];
        if edges {
            let ([a0, a1], [b0, b1]) = ([m[0], m[1]], [m[2], m[3]]);
            push(orient2d(a0, a1, b0, i, j));
            push(orient2d(a0, a1, b1, i, j));
            push(orient2d(b0, b1, a0, i, j));
            push(orient2d(b0, b1, a1, i, j));
        } else {
            let (p, t) = (m[0], [m[1], m[2], m[3]]);
            for e in 0..3 {
                push(orient2d(t[e], t[(e + 1) % 3], p, i, j));
            }
        }
    }
}

impl<P: Ring> Condition<P> {
    /// The whole condition for the points `m`, built eagerly.
    pub(crate) fn new(edges: bool, m: [&Moving<P>; 4]) -> Condition<P> {
        let mut polys = Vec::with_capacity(if edges { 25 } else { 19 });
        polys.push(coplanarity(edges, m));
        // The layout's order: orientations (groups 3..6), then differences (0..3).
        for g in (3..GROUPS).chain(0..3) {
            build_group(edges, m, g, |p| polys.push(p));
        }
        Condition { polys, edges }
    }
}

impl<P> Condition<P> {
    /// Does contact hold, given the signs each polynomial may have?
    pub(crate) fn holds(&self, s: &[Signs]) -> Tri {
        (0..GROUPS).fold(s[0].eq(), |all, g| {
            all.and(group_holds(self.edges, g, &s[group_range(self.edges, g)]))
        })
    }
}

pub(crate) fn all_of_one_sign(s: &[Signs]) -> Tri {
    Tri::all(s.iter().map(|x| x.ge())).or(Tri::all(s.iter().map(|x| x.le())))
}

pub(crate) fn apart_or_on(a: Signs, b: Signs) -> Tri {
    a.ge().and(b.le()).or(a.le().and(b.ge()))
}

/// Some of `c` is at least zero and some at most zero.
fn straddles(c: &[Signs]) -> Tri {
    Tri::any(c.iter().map(|x| x.ge())).and(Tri::any(c.iter().map(|x| x.le())))
}

/// The coplanarity determinant of the four moving points: for vertex-face (point, corners)
/// det(B - A, C - A, P - A), for edge-edge (a0, a1, b0, b1) det(a1 - a0, b0 - a0, b1 - a0).
pub(crate) fn coplanarity<P: Ring>(edges: bool, m: [&Moving<P>; 4]) -> P {
    if edges {
        det3(&minus(m[1], m[0]), &minus(m[2], m[0]), &minus(m[3], m[0]))
    } else {
        det3(&minus(m[2], m[1]), &minus(m[3], m[1]), &minus(m[0], m[1]))
    }
}

/// Vertex-face contact of point `p` and triangle `t`: [orientation, 3 × 3 edge orientations,
/// 3 × 3 coordinate differences point - corner].
pub(crate) fn vertex_face<P: Ring>(p: &Moving<P>, t: [&Moving<P>; 3]) -> Condition<P> {
    Condition::new(false, [p, t[0], t[1], t[2]])
}

/// Edge-edge contact of segments `a` and `b`: [orientation, 3 × 4 orientations, 3 × 4
/// coordinate differences a_i - b_j].
pub(crate) fn edge_edge<P: Ring>(a: [&Moving<P>; 2], b: [&Moving<P>; 2]) -> Condition<P> {
    Condition::new(true, [a[0], a[1], b[0], b[1]])
}
