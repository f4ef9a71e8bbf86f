//! Closest points of a point and a closed triangle, and of two closed segments, exactly: which
//! feature of each primitive holds the closest point, whether the distance is at most `d`, and
//! the distance, closest points and barycentric weights rounded from their exact values.
//!
//! Every decision is the sign of a polynomial in the coordinates (and `d`): in doubles with a
//! forward error bound first ([`Permanent`], two operations per operation), then in
//! midpoint-radius intervals ([`Ball`], tighter where terms cancel), then in big integers where
//! neither can tell. The values are rational functions of the coordinates: computed in
//! intervals about double-double centres ([`DdInterval`]), which are narrow enough to round
//! from in all but nearly singular cases, and where one is wider than the rounding allows, again
//! in exact rationals and rounded.
//!
//! The closest point of a point and a triangle (a convex set) is unique; the feature reported
//! is the lowest-dimensional one holding it (a corner before an edge before the interior). Two
//! segments may have many closest pairs (parallel ones): when their lines' closest points are
//! not both strictly inside the segments, the pair is taken at an end, tried in the order
//! a0 against b, a1 against b, b0 against a, b1 against a, the first of the closest kept. Of a
//! degenerate triangle's edges that hold the closest point in the same way (a triangle folded
//! flat onto a segment), the first in the order 01, 12, 20 is kept.

pub(crate) use super::Primitive;
use super::aabb::Aabb;
use super::ball::Ball;
use super::distance::{Big, Num, Ring, V, at_most, cross, dot, sub};
use super::double_double::{DdInterval, Plain, Split, two_sum};
use super::permanent::Permanent;
use super::predicates::{Point, to_integers, to_integers_scaled};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::ops::{Add, Mul, Sub};

/// Where a closest point lies on its primitive, numbered on the primitive's own corners: a
/// vertex is its corner 0; an edge has corners 0 and 1 and its open segment
/// [`Feature::Edge01`]; a triangle has three corners, three open edges and its interior.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Feature {
    /// Corner 0 (a vertex primitive is always here).
    Vertex0 = 0,
    /// Corner 1.
    Vertex1 = 1,
    /// Corner 2 (of a triangle).
    Vertex2 = 2,
    /// The open edge from corner 0 to corner 1 (an edge primitive's interior).
    Edge01 = 3,
    /// The open edge from corner 1 to corner 2.
    Edge12 = 4,
    /// The open edge from corner 2 to corner 0.
    Edge20 = 5,
    /// The interior of a triangle.
    Interior = 6,
}

impl Feature {
    fn corner(k: usize) -> Feature {
        [Feature::Vertex0, Feature::Vertex1, Feature::Vertex2][k]
    }
    fn edge(k: usize) -> Feature {
        [Feature::Edge01, Feature::Edge12, Feature::Edge20][k]
    }
}

/// The closest points of two primitives (a point and a triangle, or two segments) and how far
/// apart they are. Index 0 is the first primitive (the point, or edge a), 1 the second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// Where each closest point lies.
    pub features: [Feature; 2],
    /// The distance, within one unit in the last place of the exact one correctly rounded.
    pub distance: f64,
    /// The closest points, each coordinate within two units in the last place of the exact one.
    pub points: [Point; 2],
    /// Their barycentric weights on each primitive's corners: a vertex (1, 0, 0), an edge
    /// (1 - s, s, 0), a triangle three weights summing to one.
    pub weights: [[f64; 3]; 2],
}

/// Which pair is closest, as an exact description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Choice {
    /// Vertex-face: the point's projection, strictly inside the triangle.
    FaceInterior,
    /// Vertex-face: inside edge `k` (corners `k`, `k + 1`).
    FaceEdge(usize),
    /// Vertex-face: corner `k`.
    FaceCorner(usize),
    /// Edge-edge: the lines' closest points, strictly inside both segments.
    BothInside,
    /// Edge-edge: point `p` (0, 1: edge a's ends; 2, 3: edge b's) and the other segment, at its
    /// end `Some(j)` or inside it (`None`).
    End { p: usize, on: Option<usize> },
}

/// A candidate: its squared distance `num / den` (`den > 0`) and what it is.
struct Candidate<T> {
    num: T,
    den: T,
    choice: Choice,
}

/// Is `x` strictly closer than `y`, if the arithmetic can tell?
fn closer<T: Num>(x: &Candidate<T>, y: &Candidate<T>) -> Option<bool> {
    if corners(x.choice).is_some() && corners(x.choice) == corners(y.choice) {
        // The same two corners, reached from two edges: equal exactly (an interval could not
        // tell, and the exact arithmetic would be asked for nothing).
        return Some(false);
    }
    Some((x.num.clone() * y.den.clone() - y.num.clone() * x.den.clone()).sign()? < 0)
}

/// Keeps `c` in `best` when it is strictly closer (or the first): of equals, the first stays.
/// `None` when the arithmetic cannot tell.
fn keep_closer<T: Num>(best: &mut Option<Candidate<T>>, c: Candidate<T>) -> Option<()> {
    if best.as_ref().map_or(Some(true), |b| closer(&c, b))? {
        *best = Some(c);
    }
    Some(())
}

/// The two input points a corner-to-corner choice joins, lower (the first primitive's) first.
fn corners(c: Choice) -> Option<(usize, usize)> {
    match c {
        Choice::FaceCorner(k) => Some((0, 1 + k)),
        Choice::End { p, on: Some(j) } => {
            let other = if p < 2 { 2 + j } else { j };
            Some((p.min(other), p.max(other)))
        }
        _ => None,
    }
}

/// The closest point of segment `[a, b]` to `p`: at `a` (`Some(0)`), at `b` (`Some(1)`), or
/// inside (`None`); with its squared distance.
fn point_segment<T: Num>(p: &V<T>, a: &V<T>, b: &V<T>, one: &T) -> Option<(Option<usize>, T, T)> {
    let (u, w) = (sub(b, a), sub(p, a));
    let (uu, along) = (dot(&u, &u), dot(&w, &u));
    if uu.sign()? == 0 || along.sign()? <= 0 {
        return Some((Some(0), dot(&w, &w), one.clone()));
    }
    if (along - uu.clone()).sign()? >= 0 {
        let x = sub(p, b);
        return Some((Some(1), dot(&x, &x), one.clone()));
    }
    let c = cross(&w, &u);
    Some((None, dot(&c, &c), uu))
}

/// The vertex-face choice for point `p` and triangle `t`, if the arithmetic can tell.
///
/// For a triangle that is not flat, the closest feature is found by signs alone (no distances
/// compared), from the six products of the edges from corner 0 with the point's offsets from
/// the corners (as in Ericson, *Real-Time Collision Detection*, 5.1.5): the closest point is
/// corner `k` exactly when the point lies at 90 degrees or more from both edges at `k`; inside
/// an edge exactly when it projects strictly inside the edge and lies on or outside its line;
/// else inside the triangle. The three "outside" tests are `n.(e x w)` for the edge `e`, the
/// point's offset `w` from its start and the normal `n`, written as differences of products of
/// the six; they sum to `n.n`, which tells a flat triangle.
fn vertex_face<T: Num>(p: &V<T>, t: &[V<T>; 3], one: &T) -> Option<Choice> {
    let (ab, ac) = (sub(&t[1], &t[0]), sub(&t[2], &t[0]));
    let (ap, bp, cp) = (sub(p, &t[0]), sub(p, &t[1]), sub(p, &t[2]));
    let (d1, d2) = (dot(&ab, &ap), dot(&ac, &ap));
    let (d3, d4) = (dot(&ab, &bp), dot(&ac, &bp));
    let (d5, d6) = (dot(&ab, &cp), dot(&ac, &cp));
    // n.(bc x bp), n.(ca x cp) and n.(ab x ap), by Lagrange's identity.
    let va = d3.clone() * d6.clone() - d5.clone() * d4.clone();
    let vb = d5.clone() * d2.clone() - d1.clone() * d6.clone();
    let vc = d1.clone() * d4.clone() - d3.clone() * d2.clone();
    if (va.clone() + vb.clone() + vc.clone()).sign()? > 0 {
        let [s1, s2, s3, s6] = [&d1, &d2, &d3, &d6].map(|x| x.sign());
        let (s1, s2, s3, s6) = (s1?, s2?, s3?, s6?);
        // Past corner 1 towards corner 2, and past corner 2 towards corner 1 (`bc.bp`, `cb.cp`).
        let (b_in, c_in) = ((d4 - d3).sign()?, (d5 - d6).sign()?);
        // Corners: `p` at 90 degrees or more from both edges there (closed).
        if s1 <= 0 && s2 <= 0 {
            return Some(Choice::FaceCorner(0));
        }
        if s3 >= 0 && b_in <= 0 {
            return Some(Choice::FaceCorner(1));
        }
        if s6 >= 0 && c_in <= 0 {
            return Some(Choice::FaceCorner(2));
        }
        // Edges: on or outside the line, strictly between its ends' perpendiculars.
        let (a, b, c) = (va.sign()?, vb.sign()?, vc.sign()?);
        if c <= 0 && s1 > 0 && s3 < 0 {
            return Some(Choice::FaceEdge(0));
        }
        if a <= 0 && b_in > 0 && c_in > 0 {
            return Some(Choice::FaceEdge(1));
        }
        if b <= 0 && s2 > 0 && s6 < 0 {
            return Some(Choice::FaceEdge(2));
        }
        // No corner or edge claims the point: it projects strictly inside every edge's line.
        debug_assert!(a > 0 && b > 0 && c > 0);
        return Some(Choice::FaceInterior);
    }
    // A flat triangle: the closest of the edges' closest points.
    let mut best: Option<Candidate<T>> = None;
    for k in 0..3 {
        let (on, num, den) = point_segment(p, &t[k], &t[(k + 1) % 3], one)?;
        let choice = match on {
            Some(j) => Choice::FaceCorner((k + j) % 3),
            None => Choice::FaceEdge(k),
        };
        keep_closer(&mut best, Candidate { num, den, choice })?;
    }
    best.map(|c| c.choice)
}

/// The edge-edge choice for segments `[q[0], q[1]]` and `[q[2], q[3]]`, if the arithmetic can
/// tell.
fn edge_edge<T: Num>(q: &[V<T>; 4], one: &T) -> Option<Choice> {
    let (u, v, w) = (sub(&q[1], &q[0]), sub(&q[3], &q[2]), sub(&q[0], &q[2]));
    let dots = Dots {
        uu: dot(&u, &u),
        uv: dot(&u, &v),
        vv: dot(&v, &v),
        uw: dot(&u, &w),
        vw: dot(&v, &w),
    };
    let Dots { uu, uv, vv, uw, vw } = &dots;
    // |u x v|^2, by Lagrange's identity: zero exactly for parallel segments.
    let nn = uu.clone() * vv.clone() - uv.clone() * uv.clone();
    if nn.sign()? > 0 {
        let s = uv.clone() * vw.clone() - vv.clone() * uw.clone();
        let t = uu.clone() * vw.clone() - uv.clone() * uw.clone();
        let mut inside = true;
        for x in [s, t] {
            if x.sign()? <= 0 || (x - nn.clone()).sign()? >= 0 {
                inside = false;
            }
        }
        if inside {
            return Some(Choice::BothInside);
        }
        if let Some(c) = by_slopes(&dots)? {
            return Some(c);
        }
    }
    // Parallel segments: the closest of the ends' candidates, the first of equals.
    let mut best: Option<Candidate<T>> = None;
    for p in 0..4 {
        let (a, b) = if p < 2 {
            (&q[2], &q[3])
        } else {
            (&q[0], &q[1])
        };
        let (on, num, den) = point_segment(&q[p], a, b, one)?;
        let choice = Choice::End { p, on };
        keep_closer(&mut best, Candidate { num, den, choice })?;
    }
    best.map(|c| c.choice)
}

/// The end pair of two segments that are not parallel, found by signs alone (no distances
/// compared), for segments whose lines' closest points are not both inside them. The squared
/// distance is strictly convex in the two parameters, so its minimum over the segments is at one
/// pair of points, on the side of the parameter square of the first end `p` (in the order of
/// [`Choice::End`]) from which moving into its own segment brings it no closer to its closest
/// point on the other: the same choice as comparing the four ends' candidates. `dots` holds the
/// products of the directions `u = q[1] - q[0]`, `v = q[3] - q[2]` and `w = q[0] - q[2]`.
/// `Some(None)` if no end qualifies (exactly, one always does).
fn by_slopes<T: Num>(dots: &Dots<T>) -> Option<Option<Choice>> {
    let Dots { uu, uv, vv, uw, vw } = dots;
    for p in 0..4 {
        // With `x` the end less the other segment's start, `g` that segment's direction and `e`
        // the end's own: each product of them is one of `dots` or a sum of two or three, since
        // `x` is `w`, `w + u`, `-w` or `v - w` and `e.g` is `uv`. At `p = 2` the products `x`
        // enters are kept unnegated and their signs flipped.
        let flip = p == 2;
        let signed = |x: &T| Some(if flip { -x.sign()? } else { x.sign()? });
        let gg = if p < 2 { vv } else { uu };
        // g.x, and e.x (each flipped at 2).
        let along = match p {
            0 => vw.clone(),
            1 => vw.clone() + uv.clone(),
            2 => uw.clone(),
            _ => uv.clone() - uw.clone(),
        };
        let ex = || match p {
            0 => uw.clone(),
            1 => uw.clone() + uu.clone(),
            2 => vw.clone(),
            _ => vv.clone() - vw.clone(),
        };
        // The slope of the squared distance as end `p` moves into its segment, up to a positive
        // factor, against its closest point on the other segment: at its start, `e.x`; at its
        // end, `e.(x - g)`; inside, `e.x g.g - g.x e.g`.
        // g.x - g.g, flipped at 2.
        let past = if flip {
            along.clone() + gg.clone()
        } else {
            along.clone() - gg.clone()
        };
        let (on, sign) = if signed(&along)? <= 0 {
            (Some(0), signed(&ex())?)
        } else if signed(&past)? >= 0 {
            let slope = if flip {
                ex() + uv.clone()
            } else {
                ex() - uv.clone()
            };
            (Some(1), signed(&slope)?)
        } else if flip {
            (
                None,
                (uw.clone() * uv.clone() - vw.clone() * uu.clone()).sign()?,
            )
        } else {
            (None, (ex() * gg.clone() - along * uv.clone()).sign()?)
        };
        // Moving in from end 0 is along the direction, from end 1 against it.
        if (p % 2 == 0 && sign < 0) || (p % 2 == 1 && sign > 0) {
            continue;
        }
        return Some(Some(Choice::End { p, on }));
    }
    Some(None)
}

/// The products of two segments' directions `u`, `v` and the vector `w` from the second's start
/// to the first's, as [`edge_edge`] names them.
struct Dots<T> {
    uu: T,
    uv: T,
    vv: T,
    uw: T,
    vw: T,
}

/// The choice and the decision "distance at most `d`" for the points `v` (12 coordinates) and
/// `d`, in the arithmetic `T`; the decision is not computed again when `within` is already
/// known.
fn decide<T: Num>(pair: Primitive, v: &[T; 13], one: &T, within: bool) -> Option<(Choice, bool)> {
    let point =
        |k: usize| -> V<T> { [v[3 * k].clone(), v[3 * k + 1].clone(), v[3 * k + 2].clone()] };
    let q = [point(0), point(1), point(2), point(3)];
    let choice = match pair {
        Primitive::VertexFace => {
            vertex_face(&q[0], &[q[1].clone(), q[2].clone(), q[3].clone()], one)?
        }
        Primitive::EdgeEdge => edge_edge(&q, one)?,
    };
    if within {
        return Some((choice, true));
    }
    let (num, den) = squared(&q, choice, one);
    let dd = v[12].clone() * v[12].clone();
    Some((choice, at_most(num, dd * den)?))
}

/// The squared distance of `choice`'s closest points among `q` (the point and the triangle's
/// corners, or the two segments' ends), as `num / den`.
fn squared<T: Num>(q: &[V<T>; 4], choice: Choice, one: &T) -> (T, T) {
    // The height over a plane through `o` spanned by `u` and `v`, squared, over `|u x v|^2`.
    let height = |x: &V<T>, o: &V<T>, u: V<T>, v: V<T>| {
        let n = cross(&u, &v);
        let h = dot(&n, &sub(x, o));
        (h.clone() * h, dot(&n, &n))
    };
    // Point `x` against the line through `a` and `b`.
    let to_line = |x: &V<T>, a: &V<T>, b: &V<T>| {
        let u = sub(b, a);
        let c = cross(&sub(x, a), &u);
        (dot(&c, &c), dot(&u, &u))
    };
    if let Some((i, j)) = corners(choice) {
        let x = sub(&q[i], &q[j]);
        return (dot(&x, &x), one.clone());
    }
    match choice {
        Choice::FaceInterior => height(&q[0], &q[1], sub(&q[2], &q[1]), sub(&q[3], &q[1])),
        Choice::FaceEdge(k) => to_line(&q[0], &q[1 + k], &q[1 + (k + 1) % 3]),
        Choice::BothInside => height(&q[0], &q[2], sub(&q[1], &q[0]), sub(&q[3], &q[2])),
        Choice::End { p, on: None } => {
            let other = 1 - p / 2;
            to_line(&q[p], &q[2 * other], &q[2 * other + 1])
        }
        _ => unreachable!("corners are taken above"),
    }
}

/// The closest points of the primitives `p` (as [`Primitive`] says) when their distance is at most
/// `d`, else `None`. `d` must be finite and not negative, the coordinates finite.
#[inline]
pub(crate) fn nearest(pair: Primitive, p: &[Point; 4], d: f64) -> Option<Nearest> {
    debug_assert!(d >= 0.0 && d.is_finite());
    // Most pairs a query tests have boxes apart: told without a call.
    if boxes_apart(pair, p, d) {
        return None;
    }
    decide_within(pair, p, d).map(|decided| values(pair, p, decided))
}

/// Where the closest points of a pair within the distance lie, as the exact decision found it:
/// all [`values`] needs besides the points. One byte, so that a query can keep it for every
/// pair it finds and compute the values later, in the results' final order and place.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Decided(u8);

impl Decided {
    fn of(choice: Choice) -> Decided {
        Decided(match choice {
            Choice::FaceInterior => 0,
            Choice::FaceEdge(k) => 1 + k as u8,
            Choice::FaceCorner(k) => 4 + k as u8,
            Choice::BothInside => 7,
            Choice::End { p, on: None } => 8 + p as u8,
            Choice::End { p, on: Some(j) } => 12 + 2 * p as u8 + j as u8,
        })
    }

    fn choice(self) -> Choice {
        match self.0 {
            0 => Choice::FaceInterior,
            1..=3 => Choice::FaceEdge((self.0 - 1) as usize),
            4..=6 => Choice::FaceCorner((self.0 - 4) as usize),
            7 => Choice::BothInside,
            8..=11 => Choice::End {
                p: (self.0 - 8) as usize,
                on: None,
            },
            k => Choice::End {
                p: ((k - 12) / 2) as usize,
                on: Some(((k - 12) % 2) as usize),
            },
        }
    }
}

/// The exact decision "distance at most `d`", and where the closest points lie if so, for
/// primitives whose boxes the caller found within `d` of each other (as
/// [`crate::geometry::aabb::Aabb::within`] tells, [`nearest`]'s own filter, which is not
/// repeated here). Exact for any primitives: the filter only spares work.
#[inline(never)]
pub(crate) fn decide_within(pair: Primitive, p: &[Point; 4], d: f64) -> Option<Decided> {
    debug_assert!(d >= 0.0 && d.is_finite());
    let within = filter::certainly_within(pair, p, d);
    if !within && filter::certainly_apart(pair, p, d) {
        return None;
    }
    let mut values = [0.0; 13];
    for (k, x) in p.iter().flatten().enumerate() {
        values[k] = *x;
    }
    values[12] = d;
    let decided = Permanent::inputs(&values)
        .and_then(|inputs| decide(pair, &inputs, &Permanent::point(1.0), within))
        .or_else(|| decide(pair, &values.map(Ball::point), &Ball::point(1.0), within))
        .or_else(|| {
            // The same signs in integers: every double is an integer times a power of two, and
            // scaling all inputs by one power changes no sign (each test compares terms of one
            // degree). The constant one is not scaled, so the comparisons that use it (a vertex
            // candidate's denominator) must be of one degree on both sides: they are (num is a
            // squared length, the others' num / den too).
            decide(
                pair,
                &to_integers(values).map(Big),
                &Big(BigInt::one()),
                within,
            )
        });
    let (choice, within) = decided.expect("exact arithmetic decides every sign");
    within.then(|| Decided::of(choice))
}

/// The distance, closest points and weights of the primitives `p`, whose closest points lie
/// where `decided` says ([`decide_within`] on the same points).
#[inline]
pub(crate) fn values(pair: Primitive, p: &[Point; 4], decided: Decided) -> Nearest {
    let choice = decided.choice();
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the processor has the fused multiply-add.
        return unsafe { values_fused(pair, p, choice) };
    }
    values_of::<Plain>(pair, p, choice)
}

/// [`values_of`] with the products of the common choices split by the fused multiply-add,
/// which the default x86-64 target does not assume: Dekker's split takes about nine operations
/// more a product, a quarter of a point's values against a segment. The results are the same.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
fn values_fused(pair: Primitive, p: &[Point; 4], choice: Choice) -> Nearest {
    values_of::<super::double_double::Fused>(pair, p, choice)
}

/// Are the boxes of the two primitives more than `d` apart along some axis? (Then so are the
/// primitives.) Exact, as [`Aabb::within`].
#[inline]
fn boxes_apart(pair: Primitive, p: &[Point; 4], d: f64) -> bool {
    let (first, second) = p.split_at(pair.split());
    !Aabb::of_points(first).within(&Aabb::of_points(second), d)
}

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

impl Sub for Frac {
    type Output = Frac;
    fn sub(self, o: Frac) -> Frac {
        self + Frac {
            num: -o.num,
            den: o.den,
        }
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
fn sqrt_rational(x: &BigRational) -> f64 {
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
fn values_of<S: Split>(pair: Primitive, p: &[Point; 4], choice: Choice) -> Nearest {
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
    // In integers: every coordinate an integer times one power of two, 2^e. Weights are ratios
    // of terms of one degree, free of the scale; points are of degree one (times 2^e), squared
    // distances of degree two (times 2^2e).
    let mut flat = [0.0; 12];
    for (k, x) in p.iter().flatten().enumerate() {
        flat[k] = *x;
    }
    let (ints, e) = to_integers_scaled(flat);
    let mut ints = ints.into_iter().map(Frac::integer);
    let q: [V<Frac>; 4] = std::array::from_fn(|_| std::array::from_fn(|_| ints.next().unwrap()));
    let v = values_in(pair, q, choice).expect("exact division by a positive value");
    let f = |x: &Frac, power: i32| x.scaled(power).to_f64().expect("a finite value");
    Nearest {
        features,
        distance: sqrt_rational(&v.squared.scaled(2 * e)),
        points: v.points.map(|x| [f(&x[0], e), f(&x[1], e), f(&x[2], e)]),
        weights: v.weights.map(|w| [f(&w[0], 0), f(&w[1], 0), f(&w[2], 0)]),
    }
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

mod filter;
#[cfg(test)]
mod tests;
