//! The floating-point path of the exact continuous tests: the contact condition's polynomials
//! built with intervals that certainly enclose their exact coefficients, the coplanarity
//! polynomial's roots enclosed by bisection, and the condition judged over each enclosure.
//! It answers only when every step is certain; otherwise it says so, and the exact rational
//! path decides (a root at t = 0 or 1, a double root, motion coplanar throughout, a contact
//! exactly on an edge or a corner).

use super::condition::{
    GROUPS, Moving, Ring, Signs, Tri, build_group, coplanarity, group_holds, group_range, moving,
    projection_normals,
};
use crate::geometry::Primitive;
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
        let Some((top, rest)) = self.c[..self.n].split_last() else {
            return ZERO;
        };
        let mut v = *top;
        for c in rest.iter().rev() {
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

/// The condition's polynomials in intervals, each group built when first judged: most tests
/// are settled by f and a group or two.
struct Lazy {
    edges: bool,
    m: [Moving<IPoly>; 4],
    /// In the layout of [`super::condition::Condition`].
    polys: [IPoly; 25],
    /// Bit `g`: group `g` is built.
    built: u8,
}

impl Lazy {
    fn new(kind: Primitive, start: &[Point; 4], end: &[Point; 4]) -> Lazy {
        let edges = kind == Primitive::EdgeEdge;
        let m: [Moving<IPoly>; 4] = [0, 1, 2, 3].map(|i| moving(&start[i], &end[i]));
        let mut polys = [IPoly { c: [ZERO; 4], n: 0 }; 25];
        polys[0] = coplanarity(edges, [&m[0], &m[1], &m[2], &m[3]]);
        Lazy {
            edges,
            m,
            polys,
            built: 0,
        }
    }

    fn f(&self) -> &IPoly {
        &self.polys[0]
    }

    /// The polynomials of group `g`, built on first use.
    fn group(&mut self, g: usize) -> &[IPoly] {
        let range = group_range(self.edges, g);
        if self.built & (1 << g) == 0 {
            let mut k = range.start;
            let [a, b, c, d] = &self.m;
            let polys = &mut self.polys;
            build_group(self.edges, [a, b, c, d], g, |p| {
                polys[k] = p;
                k += 1;
            });
            self.built |= 1 << g;
        }
        &self.polys[range]
    }

    /// Group `g` judged by `value`, an enclosure of each polynomial's values.
    fn judge(&mut self, g: usize, value: impl Fn(&IPoly) -> Interval) -> Tri {
        let edges = self.edges;
        let mut signs = [Signs::within(0.0, 0.0); 4];
        let polys = self.group(g);
        for (s, p) in signs.iter_mut().zip(polys) {
            *s = value(p).signs();
        }
        group_holds(edges, g, &signs[..polys.len()])
    }

    /// The whole condition judged by `value`, f's signs being `f`: stops at the first group
    /// that cannot hold.
    fn holds(&mut self, f: Signs, value: impl Fn(&IPoly) -> Interval) -> Tri {
        let mut all = f.eq();
        for g in 0..GROUPS {
            match self.judge(g, &value) {
                Tri::No => return Tri::No,
                v => all = all.and(v),
            }
        }
        all
    }
}

/// The floating-point path of [`super::filtered::time_of_impact`]. Time spans that start after
/// `until` are not searched: what it answers about a contact after `until` is only that none
/// comes earlier.
pub(crate) fn time_of_impact(
    kind: Primitive,
    start: &[Point; 4],
    end: &[Point; 4],
    until: f64,
) -> Answer {
    let mut c = Lazy::new(kind, start, end);
    // In contact at the start (resting contact, most often): certain from the start
    // positions alone.
    let f0 = c.f().at_zero().signs();
    if f0.zero && c.holds(f0, IPoly::at_zero) == Tri::Yes {
        return Answer::Decided(Some(0.0));
    }
    let f = *c.f();
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
        if a > until {
            // Cells come out in increasing order of their starts: all that remain are later.
            break;
        }
        opened += 1;
        if opened > MAX_CELLS {
            return Answer::Unknown(a);
        }
        let cell = Interval::new(a, b);
        let fc = f.enclose(&df, a, b);
        if fc.sign() != 0 {
            continue; // no root here
        }
        // The other groups over the cell: where some projection certainly keeps the
        // primitives apart (say a vertex beside a triangle while both stay in one plane, as in
        // a flat sheet), nothing in the cell can touch, root of f or not.
        if c.holds(fc.signs(), |p| p.eval(cell)) == Tri::No {
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
            match at_root(&mut c, a, b, fa) {
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
fn at_root(c: &mut Lazy, mut a: f64, mut b: f64, fa: i8) -> Answer {
    let f = *c.f();
    let normals = {
        let [p, q, r, s] = &c.m;
        projection_normals(c.edges, [p, q, r, s])
    };
    // Narrow the root's enclosure while the condition over it is undecided; once it is
    // decided, only the time remains to be narrowed, down to adjacent doubles.
    let mut decided = false;
    loop {
        if !decided {
            let t = Interval::new(a, b);
            // Orientations of projection q are group 3 + q.
            let verdict = (0..3)
                .find(|&q| normals[q].eval(t).sign() != 0)
                .map_or(Tri::Maybe, |q| c.judge(3 + q, |p| p.eval(t)));
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
