//! A floating-point filter that can only say "no contact up to a time": the condition's
//! polynomials in Bernstein form on [0, 1], in plain doubles with one a-priori error bound per
//! polynomial kind, and their ranges over time cells from blossoms (the Bernstein coefficients
//! over a cell, whose hull holds the polynomial's values there). First the spans of time over
//! which the primitives are certainly apart along an axis (the coordinate-difference groups,
//! linear); then, by bisection, a cell is settled when it lies in those spans, f is certainly
//! non-zero over it, or a projection's orientations certainly fail over it. The test is
//! settled when every cell up to the cut-off is, within a few levels of bisection. Anything
//! else goes on to the interval path unchanged, so the answers are those of the paths behind
//! it.
//!
//! Error bounds, with u = 2^-53 (unit roundoff) and D an upper bound on every coordinate
//! difference of two of the four points at one end of the step:
//! - a difference of two doubles is rounded once: error at most u |d| <= u D;
//! - an orientation coefficient (a 2 x 2 determinant of rounded differences, or the mean of
//!   two) is off by at most 10.01 u D^2 (each product 3.0001 u D^2, their difference's rounding
//!   2.0001 u D^2, and for the middle coefficient the sum's rounding 4.001 u D^2, halved);
//! - a blossom is n levels of `(1 - s) x + s y` with `s` a cell end (dyadic, so `1 - s` is
//!   exact): each level adds at most 2.01 u times the largest magnitude M of its inputs, and
//!   passes on the inputs' errors unamplified (a convex combination).
//!
//! Underflow adds at most 2^-1075 per product; the absolute term `TINY` covers every such
//! error many times over. D is at most 1e150, so no product or sum overflows, and every
//! input is finite, so nothing is NaN; outside that range the filter does not answer.

use super::condition::PROJECTIONS;
use crate::geometry::Primitive;
use crate::geometry::predicates::Point;

const U: f64 = f64::EPSILON / 2.0;
/// Far above any sum of underflow errors (each at most 2^-1075), far below any value the
/// filter needs to separate from zero.
const TINY: f64 = 1e-300;
const LARGEST_D: f64 = 1e150;
/// Bisection stops here (cells of 1/32): what is not settled by then is left to the
/// interval path, whose root certification handles what subdivision alone cannot.
const MAX_DEPTH: u32 = 5;

/// The coplanarity cubic's Bernstein coefficients on [0, 1], each within `err` of the exact.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cubic {
    pub b: [f64; 4],
    pub err: f64,
}

impl Cubic {
    /// How far the coefficients over a cell may be from the exact ones: the coefficients'
    /// own error, and three levels of blossom adding 6.1 u M at most.
    fn bound(&self) -> f64 {
        let m = self.b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        1.01 * self.err + 8.0 * U * m + TINY
    }
}

/// `(1 - s) x + s y`.
#[inline(always)]
fn lerp(x: f64, y: f64, s: f64) -> f64 {
    (1.0 - s) * x + s * y
}

/// The Bernstein coefficients over `[s, t]` of the polynomial whose coefficients on [0, 1]
/// are `b` (degree 1, 2 or 3): its blossom at `(s, .., s, t, .., t)`.
#[inline(always)]
fn on_cell<const N: usize>(b: &[f64; N], s: f64, t: f64) -> [f64; N] {
    let mut c = [0.0; N];
    match N {
        2 => {
            c[0] = lerp(b[0], b[1], s);
            c[1] = lerp(b[0], b[1], t);
        }
        3 => {
            let (l0, l1) = (lerp(b[0], b[1], s), lerp(b[1], b[2], s));
            let (r0, r1) = (lerp(b[0], b[1], t), lerp(b[1], b[2], t));
            c[0] = lerp(l0, l1, s);
            c[1] = lerp(l0, l1, t);
            c[2] = lerp(r0, r1, t);
        }
        4 => {
            let l = [0, 1, 2].map(|i| lerp(b[i], b[i + 1], s));
            let r = [0, 1, 2].map(|i| lerp(b[i], b[i + 1], t));
            let (ll0, ll1) = (lerp(l[0], l[1], s), lerp(l[1], l[2], s));
            let (rr0, rr1) = (lerp(r[0], r[1], t), lerp(r[1], r[2], t));
            c[0] = lerp(ll0, ll1, s);
            c[1] = lerp(ll0, ll1, t);
            c[2] = lerp(rr0, rr1, s);
            c[3] = lerp(rr0, rr1, t);
        }
        _ => unreachable!("degrees 1 to 3"),
    }
    c
}

/// The polynomial's sign over `[s, t]` when certain (1 or -1), else 0, its computed
/// coefficients there being within `bound` of the exact ones (whose hull holds its values).
#[inline(always)]
fn sign<const N: usize>(b: &[f64; N], s: f64, t: f64, bound: f64) -> i8 {
    let c = on_cell(b, s, t);
    let (lo, hi) = c[1..]
        .iter()
        .fold((c[0], c[0]), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    if lo > bound {
        1
    } else if hi < -bound {
        -1
    } else {
        0
    }
}

/// The group polynomials in Bernstein form, the orientations built on first use.
struct Groups {
    edges: bool,
    /// Coordinate differences, per axis (3 for vertex-face, 4 for edge-edge).
    diff: [[[f64; 2]; 4]; 3],
    /// Projected orientations, per projection, once built.
    orient: [[[f64; 3]; 4]; 3],
    built: [bool; 3],
    /// The points at the start and at the end.
    pts: [[Point; 4]; 2],
    /// Bounds over any cell: linear and quadratic polynomials.
    lin_bound: f64,
    quad_bound: f64,
    width: usize,
}

impl Groups {
    fn new(kind: Primitive, start: &[Point; 4], end: &[Point; 4]) -> Option<Groups> {
        let edges = kind == Primitive::EdgeEdge;
        // D: the largest extent of the four points along an axis, at either end (rounded
        // extents; the 1.0001 below covers their rounding).
        let mut d = 0.0f64;
        for p in [start, end] {
            for k in 0..3 {
                let (lo, hi) = p
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), q| {
                        (l.min(q[k]), h.max(q[k]))
                    });
                d = d.max(hi - lo);
            }
        }
        // An extent that overflowed is infinite (the coordinates are finite, so none is NaN).
        if d > LARGEST_D || d.is_nan() {
            return None;
        }
        let d = d * 1.0001;
        let mut diff = [[[0.0; 2]; 4]; 3];
        let pairs: &[(usize, usize)] = if edges {
            &[(0, 2), (0, 3), (1, 2), (1, 3)]
        } else {
            &[(0, 1), (0, 2), (0, 3)]
        };
        for (k, axis) in diff.iter_mut().enumerate() {
            for (slot, &(i, j)) in axis.iter_mut().zip(pairs) {
                *slot = [start[i][k] - start[j][k], end[i][k] - end[j][k]];
            }
        }
        Some(Groups {
            edges,
            diff,
            orient: [[[0.0; 3]; 4]; 3],
            built: [false; 3],
            pts: [*start, *end],
            // Coefficients within u D, one level of blossom 2.01 u D.
            lin_bound: 4.0 * U * d + TINY,
            // Coefficients within 10.01 u D^2, magnitudes at most 2.0001 D^2, two levels of
            // blossom 8.05 u D^2.
            quad_bound: 24.0 * U * (d * d) + TINY,
            width: if edges { 4 } else { 3 },
        })
    }

    /// The orientation of (u, v, w) projected on axes i, j, as `condition::orient2d` orders
    /// it, in Bernstein form.
    fn orient(&self, u: usize, v: usize, w: usize, i: usize, j: usize) -> [f64; 3] {
        let [p0, p1] = &self.pts;
        let dv = |p: &[Point; 4], k: usize| p[v][k] - p[u][k];
        let dw = |p: &[Point; 4], k: usize| p[w][k] - p[u][k];
        let (a0, b0, c0, d0) = (dv(p0, i), dw(p0, j), dv(p0, j), dw(p0, i));
        let (a1, b1, c1, d1) = (dv(p1, i), dw(p1, j), dv(p1, j), dw(p1, i));
        [
            a0 * b0 - c0 * d0,
            0.5 * ((a0 * b1 - c0 * d1) + (a1 * b0 - c1 * d0)),
            a1 * b1 - c1 * d1,
        ]
    }

    fn build(&mut self, q: usize) {
        let (i, j) = PROJECTIONS[q];
        let polys = if self.edges {
            [
                self.orient(0, 1, 2, i, j),
                self.orient(0, 1, 3, i, j),
                self.orient(2, 3, 0, i, j),
                self.orient(2, 3, 1, i, j),
            ]
        } else {
            [
                self.orient(1, 2, 0, i, j),
                self.orient(2, 3, 0, i, j),
                self.orient(3, 1, 0, i, j),
                [0.0; 3],
            ]
        };
        self.orient[q] = polys;
        self.built[q] = true;
    }

    /// Time spans over which some coordinate-difference group certainly fails (every
    /// difference of one strict sign): candidates from the differences' roots in floating
    /// point, moved inwards to multiples of 2^-20 (so that `1 - s` stays exact in the
    /// blossom) and kept only when the cell test proves them. Sorted by start.
    fn linear_spans(&self) -> Spans {
        const GRID: f64 = (1u64 << 20) as f64;
        let n = self.width;
        let mut spans = Spans {
            at: [(0.0, 0.0); 6],
            len: 0,
        };
        for axis in &self.diff {
            for sigma in [1.0, -1.0] {
                // Below 0 and above 1 while no root bounds them.
                let (mut lo, mut hi) = (-1.0f64, 2.0f64);
                for b in &axis[..n] {
                    let (x, y) = (sigma * b[0], sigma * b[1]);
                    if x > 0.0 && y > 0.0 {
                        continue;
                    }
                    if x <= 0.0 && y <= 0.0 {
                        lo = 2.0;
                        break;
                    }
                    // One root, x / (x - y): positive before it when x > 0, after it if not.
                    let r = x / (x - y);
                    if x > 0.0 {
                        hi = hi.min(r);
                    } else {
                        lo = lo.max(r);
                    }
                }
                // Strictly inside the roots (a root at 0 leaves out t = 0).
                let p = if lo >= 0.0 {
                    ((lo * GRID).floor() + 1.0) / GRID
                } else {
                    0.0
                };
                let q = if hi <= 1.0 {
                    ((hi * GRID).ceil() - 1.0) / GRID
                } else {
                    1.0
                };
                let proved = p < q
                    && axis[..n]
                        .iter()
                        .all(|b| f64::from(sign(b, p, q, self.lin_bound)) == sigma);
                if proved {
                    spans.at[spans.len] = (p, q);
                    spans.len += 1;
                }
            }
        }
        spans.at[..spans.len].sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        spans
    }

    /// Do the orientations of projection `q` (group `3 + q` of `condition::GROUPS`)
    /// certainly fail over `[s, t]`, as `condition::group_holds` says `No`? For vertex-face,
    /// orientations of both strict signs; for edge-edge, one segment's ends strictly on one
    /// side of the other's line.
    #[inline]
    fn orientations_fail(&mut self, q: usize, s: f64, t: f64) -> bool {
        if !self.built[q] {
            self.build(q);
        }
        let mut sg = [0i8; 4];
        for (x, b) in sg.iter_mut().zip(&self.orient[q][..self.width]) {
            *x = sign(b, s, t, self.quad_bound);
        }
        if self.edges {
            (sg[0] != 0 && sg[0] == sg[1]) || (sg[2] != 0 && sg[2] == sg[3])
        } else {
            sg[..3].contains(&1) && sg[..3].contains(&-1)
        }
    }
}

/// Closed time spans, sorted by start.
struct Spans {
    at: [(f64, f64); 6],
    len: usize,
}

impl Spans {
    /// Does their union hold `[s, t]`?
    fn cover(&self, s: f64, t: f64) -> bool {
        let mut x = s;
        for &(p, q) in &self.at[..self.len] {
            if p > x {
                break;
            }
            x = x.max(q);
            if x >= t {
                return true;
            }
        }
        false
    }
}

/// Is there certainly no contact at or before `until`? `f` is the coplanarity cubic. `false`
/// says only that this filter could not tell.
pub(crate) fn apart_until(
    kind: Primitive,
    start: &[Point; 4],
    end: &[Point; 4],
    f: &Cubic,
    until: f64,
) -> bool {
    let Some(mut groups) = Groups::new(kind, start, end) else {
        return false;
    };
    let f_bound = f.bound();
    // Where the primitives are apart along an axis: most cells end here.
    let spans = groups.linear_spans();
    // Depth-first, left half first: cells come out in increasing order of their starts.
    let mut stack = [(0.0f64, 1.0f64, 0u32); MAX_DEPTH as usize + 2];
    let mut top = 1;
    while top > 0 {
        top -= 1;
        let (s, t, depth) = stack[top];
        if s > until {
            // Every cell left starts later: a contact there has a rounded time after `until`.
            break;
        }
        if spans.cover(s, t) || sign(&f.b, s, t, f_bound) != 0 {
            continue;
        }
        // The orientations (the differences are in the spans).
        if (0..3).any(|q| groups.orientations_fail(q, s, t)) {
            continue;
        }
        if depth == MAX_DEPTH {
            return false;
        }
        let mid = 0.5 * (s + t);
        stack[top] = (mid, t, depth + 1);
        stack[top + 1] = (s, mid, depth + 1);
        top += 2;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::Rng;
    use crate::geometry::ccd::condition::{GROUPS, Moving, build_group, coplanarity, moving};
    use crate::geometry::ccd::grid_cases::{Prim, grid_case};
    use crate::geometry::ccd::oracle::{edge_edge_toi, vertex_face_toi};
    use crate::geometry::ccd::poly::{Poly, rational};
    use num_rational::BigRational;
    use num_traits::Signed;

    /// Grid points, with the degenerate motions of the filtered tests' cases: coplanar
    /// throughout, corners shared or repeated, edges parallel throughout, nothing moving.
    fn case(rng: &mut Rng, case: usize, grid: u64) -> (Prim, Prim) {
        let shape = match case % 7 {
            6 => 1,
            c => c,
        };
        grid_case(rng, grid, case % 7 == 5, shape)
    }

    /// The exact Bernstein coefficients over `[s, t]` of `p`, of degree below `n`, from its
    /// values and derivatives at the ends.
    fn exact_on_cell(p: &Poly, n: usize, s: &BigRational, t: &BigRational) -> Vec<BigRational> {
        let h = t - s;
        let d = p.derivative();
        let (ps, pt) = (p.eval(s), p.eval(t));
        match n {
            2 => vec![ps, pt],
            3 => vec![
                ps.clone(),
                ps + d.eval(s) * h / BigRational::from_integer(2.into()),
                pt,
            ],
            _ => {
                let third = |x: BigRational| x * &h / BigRational::from_integer(3.into());
                vec![
                    ps.clone(),
                    ps + third(d.eval(s)),
                    pt.clone() - third(d.eval(t)),
                    pt,
                ]
            }
        }
    }

    fn within(got: &[f64], want: &[BigRational], bound: f64) -> bool {
        got.iter()
            .zip(want)
            .all(|(&g, w)| (rational(g) - w).abs() <= rational(bound))
    }

    /// Motions whose arithmetic rounds: full-precision coordinates at scales from tiny to
    /// huge, far from the origin, points near each other and far apart, and the degenerate
    /// grid cases.
    fn rounding_case(rng: &mut Rng, c: usize) -> (Prim, Prim) {
        if c % 5 == 4 {
            return case(rng, c, [4, 1 << 20][c % 2]);
        }
        let scale = [1.0, 1e-7, 1e7, 2f64.powi(-990), 1e140, 3e-300][c % 6];
        let shift = [0.0, 1e6, -3.3, 0.0][c % 4];
        let spread = [1.0, 1e-9][c % 2];
        let mut x =
            |i: usize| (rng.range(-1.0, 1.0) * if i == 0 { 1.0 } else { spread }) * scale + shift;
        let mut s: Prim = [[0.0; 3]; 4];
        let mut e: Prim = [[0.0; 3]; 4];
        for i in 0..4 {
            for k in 0..3 {
                s[i][k] = x(i);
                e[i][k] = x(i);
            }
        }
        (s, e)
    }

    /// Each coefficient over a cell, of f and of every group polynomial, is within the bound
    /// the filter adds of the exact coefficient (computed in rationals from the exact
    /// polynomials of the condition).
    #[test]
    fn coefficients_over_cells_are_within_their_bounds() {
        let mut rng = Rng::new(0xb0_0d5);
        let mut checked = 0;
        for c in 0..1500 {
            let (s, e) = rounding_case(&mut rng, c);
            // The bisection's cells, and spans on the grid of 2^-20.
            let depth = [0, 1, 2, 3, 4, 5, 20][c % 7];
            let n = 1u64 << depth;
            let k = rng.next_u64() % n;
            let j = if depth == 20 {
                k + 1 + rng.next_u64() % (n - k)
            } else {
                k + 1
            };
            let (cs, ct) = (k as f64 / n as f64, j as f64 / n as f64);
            let (rs, rt) = (rational(cs), rational(ct));
            for kind in [Primitive::VertexFace, Primitive::EdgeEdge] {
                let edges = kind == Primitive::EdgeEdge;
                let m: Vec<Moving<Poly>> = (0..4).map(|i| moving(&s[i], &e[i])).collect();
                let m = [&m[0], &m[1], &m[2], &m[3]];
                if let Some(f) = super::super::filtered::cubic(kind, &s, &e) {
                    let want = exact_on_cell(&coplanarity(edges, m), 4, &rs, &rt);
                    let got = on_cell(&f.b, cs, ct);
                    assert!(within(&got, &want, f.bound()), "case {c} {kind:?} f");
                    checked += 1;
                }
                let Some(mut groups) = Groups::new(kind, &s, &e) else {
                    continue;
                };
                for g in 0..GROUPS {
                    let mut exact = vec![];
                    build_group(edges, m, g, |p| exact.push(p));
                    for (i, p) in exact.iter().enumerate() {
                        let ok = if g < 3 {
                            let want = exact_on_cell(p, 2, &rs, &rt);
                            within(
                                &on_cell(&groups.diff[g][i], cs, ct),
                                &want,
                                groups.lin_bound,
                            )
                        } else {
                            if !groups.built[g - 3] {
                                groups.build(g - 3);
                            }
                            let want = exact_on_cell(p, 3, &rs, &rt);
                            let got = on_cell(&groups.orient[g - 3][i], cs, ct);
                            within(&got, &want, groups.quad_bound)
                        };
                        assert!(ok, "case {c} {kind:?} group {g} polynomial {i}");
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 40_000, "{checked}");
    }

    /// The filter says "apart" only where the rational oracle finds no contact up to the
    /// cut-off, on grid motions mapped so that their arithmetic rounds (scaled by non-dyadic
    /// factors, moved far from the origin, to tiny and huge scales): degenerate contacts whose
    /// signs rounding could flip, where a bound too small answers wrongly.
    #[test]
    fn apart_only_where_the_oracle_finds_no_contact() {
        let mut rng = Rng::new(0xbe25_7e17);
        let (mut apart, mut tested) = (0, 0);
        for c in 0..700 {
            let grid = [2, 4, 8, 1 << 20][c % 4];
            let (s, e) = case(&mut rng, c, grid);
            let (scale, shift) = [
                (1.0, 0.0),
                (0.1, 0.0),
                (1.0 / 3.0, 0.7),
                (0.3, 1e6),
                (2f64.powi(-1000) * 0.7, 0.0),
                (2f64.powi(250) / 3.0, 0.0),
            ][c % 6];
            let f = |p: &Prim| p.map(|v| v.map(|x| x * scale + shift));
            let (s, e) = (f(&s), f(&e));
            for kind in [Primitive::VertexFace, Primitive::EdgeEdge] {
                let want = match kind {
                    Primitive::VertexFace => vertex_face_toi(&s, &e),
                    Primitive::EdgeEdge => edge_edge_toi(&s, &e),
                };
                let Some(cubic) = super::super::filtered::cubic(kind, &s, &e) else {
                    continue;
                };
                tested += 1;
                let cuts = [1.0, want.unwrap_or(0.5), want.map_or(0.25, f64::next_down)];
                for until in cuts {
                    if apart_until(kind, &s, &e, &cubic, until) {
                        apart += 1;
                        assert!(
                            want.is_none_or(|t| t > until),
                            "case {c} {kind:?} until {until}: contact at {want:?}\n{s:?}\n{e:?}"
                        );
                    }
                }
            }
        }
        assert!(tested > 600 && apart > 600, "{tested} {apart}");
    }
}
