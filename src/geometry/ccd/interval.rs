//! The floating-point path of the exact continuous tests: the contact condition's polynomials
//! built with intervals that certainly enclose their exact coefficients, the coplanarity
//! polynomial's roots enclosed by bisection, and the condition judged over each enclosure.
//! It answers only when every step is certain; otherwise it says so, and the exact rational
//! path decides (a root at t = 0 or 1, a double root, motion coplanar throughout, a contact
//! exactly on an edge or a corner).

use super::condition::{
    Condition, Moving, Ring, Signs, Tri, all_of_one_sign, apart_or_on, edge_edge, moving,
    projection_normals, vertex_face,
};
use super::exact::Primitive;
use crate::geometry::interval::Interval;
use crate::geometry::predicates::Point;

/// Enclosures: the signs the enclosed value may have, and its sign when certain.
impl Interval {
    fn new(lo: f64, hi: f64) -> Interval {
        Interval { lo, hi }
    }

    fn signs(self) -> Signs {
        Signs::within(self.lo, self.hi)
    }

    /// Certainly positive (1), certainly negative (-1), or unknown (0).
    fn sign(self) -> i8 {
        if self.lo > 0.0 {
            1
        } else if self.hi < 0.0 {
            -1
        } else {
            0
        }
    }
}

/// A polynomial in t of degree at most 3 with interval coefficients, lowest degree first: the
/// condition's polynomials are at most cubic, so a fixed array holds them without allocating.
#[derive(Clone, Copy, Debug)]
pub(crate) struct IPoly {
    c: [Interval; 4],
    /// Coefficients in use.
    n: usize,
}

const ZERO: Interval = Interval { lo: 0.0, hi: 0.0 };

impl Ring for IPoly {
    fn motion(start: f64, end: f64) -> IPoly {
        IPoly {
            c: [
                Interval::point(start),
                Interval::point(end) - Interval::point(start),
                ZERO,
                ZERO,
            ],
            n: 2,
        }
    }

    fn add(&self, o: &IPoly) -> IPoly {
        self.zip(o, |a, b| a + b)
    }

    fn sub(&self, o: &IPoly) -> IPoly {
        self.zip(o, |a, b| a - b)
    }

    fn mul(&self, o: &IPoly) -> IPoly {
        if self.n == 0 || o.n == 0 {
            return IPoly { c: [ZERO; 4], n: 0 };
        }
        let n = self.n + o.n - 1;
        debug_assert!(n <= 4, "the contact polynomials are at most cubic");
        let mut c = [ZERO; 4];
        for i in 0..self.n {
            for j in 0..o.n {
                c[i + j] = c[i + j] + self.c[i] * o.c[j];
            }
        }
        IPoly { c, n }
    }
}

impl IPoly {
    /// Coefficient by coefficient, the shorter padded with zeros.
    fn zip(&self, o: &IPoly, op: fn(Interval, Interval) -> Interval) -> IPoly {
        let n = self.n.max(o.n);
        let mut c = [ZERO; 4];
        for (i, x) in c.iter_mut().enumerate().take(n) {
            *x = op(self.c[i], o.c[i]);
        }
        IPoly { c, n }
    }

    /// An enclosure of the values over `t` (Horner in intervals).
    fn eval(&self, t: Interval) -> Interval {
        let mut v = ZERO;
        for c in self.c[..self.n].iter().rev() {
            v = v * t + *c;
        }
        v
    }

    /// An enclosure of the values over `[a, b]`, `d` being the derivative: Horner's, cut by
    /// the mean-value form `p(m) + d([a, b]) ([a, b] - m)`, whose width shrinks with the
    /// square of the cell's near a root where Horner's shrinks only with the cell (so a motion
    /// that comes close to coplanar without reaching it is settled in few cells).
    fn enclose(&self, d: &IPoly, a: f64, b: f64) -> Interval {
        let cell = Interval::new(a, b);
        let horner = self.eval(cell);
        let m = Interval::point(0.5 * (a + b));
        let mean = self.eval(m) + d.eval(cell) * (cell - m);
        Interval::new(horner.lo.max(mean.lo), horner.hi.min(mean.hi))
    }

    /// The value at t = 0.
    fn at_zero(&self) -> Interval {
        if self.n == 0 { ZERO } else { self.c[0] }
    }

    fn derivative(&self) -> IPoly {
        let mut c = [ZERO; 4];
        for i in 1..self.n {
            c[i - 1] = self.c[i] * Interval::point(i as f64);
        }
        IPoly {
            c,
            n: self.n.saturating_sub(1),
        }
    }
}

/// What the floating-point path found.
pub(crate) enum Answer {
    /// Certain: the earliest contact time rounded down, or none.
    Decided(Option<f64>),
    /// Certain contact, at the coplanarity polynomial's only root in `(lo, hi)` (where it has
    /// non-zero values of opposite signs, this one at `lo`), too close to a double for the
    /// intervals to round.
    ContactIn(f64, f64, std::cmp::Ordering),
    /// Something was too close to call: the exact path must decide. No contact comes before
    /// the time given (the start of the first time span the search could not settle).
    Unknown(f64),
}

/// Cells narrower than this that may hold a root without being certified send the query to
/// the exact path; so does a search that opens more cells than `MAX_CELLS`.
const MIN_CELL: f64 = 1.0 / (1u64 << 30) as f64;
const MAX_CELLS: usize = 400;

/// The floating-point path of [`super::exact::time_of_impact`].
pub(crate) fn time_of_impact(kind: Primitive, start: &[Point; 4], end: &[Point; 4]) -> Answer {
    let m: [Moving<IPoly>; 4] = [0, 1, 2, 3].map(|i| moving(&start[i], &end[i]));
    let c = match kind {
        Primitive::VertexFace => vertex_face(&m[0], [&m[1], &m[2], &m[3]]),
        Primitive::EdgeEdge => edge_edge([&m[0], &m[1]], [&m[2], &m[3]]),
    };
    let edges = kind == Primitive::EdgeEdge;
    let normals = projection_normals(edges, [&m[0], &m[1], &m[2], &m[3]]);
    // In contact at the start (resting contact, most often): certain from the start
    // positions alone.
    let mut signs = [Signs::within(0.0, 0.0); 25];
    let signs = &mut signs[..c.polys.len()];
    for (s, p) in signs.iter_mut().zip(&c.polys) {
        *s = p.at_zero().signs();
    }
    if (c.holds)(signs) == Tri::Yes {
        return Answer::Decided(Some(0.0));
    }
    let f = &c.polys[0];
    let df = f.derivative();
    let ddf = df.derivative();
    // Depth-first, left half first: cells come out in increasing t.
    // Each level of the bisection leaves one right half pending, and cells stop at MIN_CELL
    // (2^-30): a fixed stack holds them, so the search allocates nothing.
    let mut stack = [(0.0f64, 0.0f64); 64];
    stack[0] = (0.0, 1.0);
    let mut top = 1;
    let mut opened = 0;
    while top > 0 {
        top -= 1;
        let (a, b) = stack[top];
        opened += 1;
        if opened > MAX_CELLS {
            return Answer::Unknown(a);
        }
        let cell = Interval::new(a, b);
        if f.enclose(&df, a, b).sign() != 0 {
            continue; // no root here
        }
        // Every polynomial of the condition over the cell: where some projection certainly
        // keeps the primitives apart (say a vertex beside a triangle while both stay in one
        // plane, as in a flat sheet), nothing in the cell can touch, root of f or not.
        for (s, p) in signs.iter_mut().zip(&c.polys) {
            *s = p.eval(cell).signs();
        }
        if (c.holds)(signs) == Tri::No {
            continue;
        }
        let (fa, fb) = (
            f.eval(Interval::point(a)).sign(),
            f.eval(Interval::point(b)).sign(),
        );
        if fa != 0 && fb != 0 && fa != fb && df.enclose(&ddf, a, b).sign() != 0 {
            // Exactly one root, simple, strictly inside.
            // Undecided at the root, the answer's bound is where the root was narrowed to:
            // nothing before it in the cell can touch (f has no other root there).
            match at_root(&c, &normals, edges, a, b, fa) {
                Answer::Decided(None) => continue,
                answer => return answer,
            }
        }
        if b - a < MIN_CELL {
            return Answer::Unknown(a);
        }
        let mid = 0.5 * (a + b);
        stack[top] = (mid, b);
        stack[top + 1] = (a, mid);
        top += 2;
    }
    Answer::Decided(None)
}

/// The condition at the one root of `f` in `(a, b)`, where `f(a)` has sign `fa`: contact
/// (with its time rounded down), none (`Decided(None)`), or unknown.
///
/// At a root of f the primitives are coplanar, and a projection whose normal component is
/// certainly non-zero over the enclosure decides by its orientations alone (the other
/// projections may be degenerate there, their orientations vanishing with f).
fn at_root(
    c: &Condition<IPoly>,
    normals: &[IPoly; 3],
    edges: bool,
    mut a: f64,
    mut b: f64,
    fa: i8,
) -> Answer {
    let f = &c.polys[0];
    // Narrow the root's enclosure while the condition over it is undecided; once it is
    // decided, only the time remains to be narrowed, down to adjacent doubles.
    let mut decided = false;
    loop {
        if !decided {
            let t = Interval::new(a, b);
            let verdict =
                (0..3)
                    .find(|&q| normals[q].eval(t).sign() != 0)
                    .map_or(Tri::Maybe, |q| {
                        let s = |k: usize| c.polys[k].eval(t).signs();
                        if edges {
                            // Layout of `edge_edge`: 4 orientations per projection after f.
                            let o = 1 + 4 * q;
                            apart_or_on(s(o), s(o + 1)).and(apart_or_on(s(o + 2), s(o + 3)))
                        } else {
                            // Layout of `vertex_face`: 3 orientations per projection after f.
                            let o = 1 + 3 * q;
                            all_of_one_sign(&[s(o), s(o + 1), s(o + 2)])
                        }
                    });
            match verdict {
                Tri::No => return Answer::Decided(None),
                Tri::Yes => decided = true,
                Tri::Maybe => {}
            }
        }
        if b == a.next_up() {
            // The root lies strictly between adjacent doubles: a is the largest below it.
            return if decided {
                Answer::Decided(Some(a))
            } else {
                Answer::Unknown(a)
            };
        }
        let mid = a + 0.5 * (b - a);
        let mid = if mid <= a || mid >= b {
            a.next_up()
        } else {
            mid
        };
        match f.eval(Interval::point(mid)).sign() {
            0 if decided => {
                return Answer::ContactIn(
                    a,
                    b,
                    if fa > 0 {
                        std::cmp::Ordering::Greater
                    } else {
                        std::cmp::Ordering::Less
                    },
                );
            }
            0 => return Answer::Unknown(a),
            s if s == fa => a = mid,
            _ => b = mid,
        }
    }
}
