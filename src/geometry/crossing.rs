//! Where two triangles meet, exactly: the segment along which two non-coplanar triangles cross,
//! with each end named symbolically and rounded once to doubles.
//!
//! # Contract
//!
//! [`triangle_pair_intersection`] classifies the intersection of two closed triangles `a` and
//! `b` ([`PairIntersection`]). Every decision is the sign of an exact orientation determinant
//! (see [`super::predicates`]); rounded coordinates never decide anything. So the kind agrees
//! with [`super::tri_tri::triangles_intersect`] (`Apart` exactly when it says `false`), and the
//! answer does not depend on the order of the corners beyond relabelling them: the end features
//! name corners by their index (`0..3`) in the triangle as given, and an odd permutation of a
//! triangle's corners flips its normal and so reverses the segment. Swapping `a` and `b` gives
//! the mirrored answer: features of `a` become features of `b` and the segment is reversed
//! (`n_b x n_a = -(n_a x n_b)`).
//!
//! - Two proper (non-degenerate), non-coplanar triangles that share more than one point meet in
//!   a segment on the line where their planes meet, oriented along `n_a x n_b`, `n` a triangle's
//!   normal `(t1 - t0) x (t2 - t0)`. Each end is where the boundary of one triangle meets the
//!   other, named by the lowest-dimensional features holding it, one per triangle ([`EndFeature`]):
//!   a corner wins over everything (a corner of `a` lying in `b`, or a corner of both); otherwise
//!   an edge of `a` crossing an edge of `b` ([`EndFeature::Edges`], the point where the two
//!   edges meet); otherwise the edge of one crossing the interior of the other. The same exact
//!   point is thus named the same way by every pair that reaches it through the same features.
//!   Where the two triangles' interval ends coincide exactly (an orientation of zero), the end
//!   is named from both triangles' features by this rule, which treats `a` and `b` alike, so
//!   that swapping them mirrors the name. Other kinds carry no points or features.
//! - Two such triangles sharing exactly one point: [`PairIntersection::Point`].
//! - Two proper coplanar triangles that meet: [`PairIntersection::Coplanar`].
//! - A degenerate triangle (collinear or repeated corners) has no plane and no normal: a pair
//!   with one that meets the other is [`PairIntersection::Point`] when the degenerate triangle
//!   (a segment or a point) has a corner off the proper triangle's plane, so that it meets that
//!   plane in one point only, and [`PairIntersection::Coplanar`] otherwise (it lies in the proper
//!   triangle's plane, or both are degenerate: any two meeting segments lie in one plane).
//!
//! # Method
//!
//! Each proper triangle crossing the other's plane meets the line of the planes in an interval
//! whose ends lie on the two edges from its vertex alone on its side of that plane (Guigue and
//! Devillers). The intersection is the overlap of the two intervals. Two ends from different
//! triangles, on edges `uv` of `a` and `wz` of `b`, are compared along `d = n_a x n_b` by one
//! orientation: with `X = uv ∩ plane(b)` and `Y = wz ∩ plane(a)`,
//! `det[v - u, z - w, Y - X] = det[v - u, z - w, w - u]`, the sign of `orient3d(u, v, w, z)`, and
//! with `Y - X = λ d`, the same determinant is `λ d.((v - u) x (z - w)) =
//! -λ (n_a.(z - w)) (n_b.(v - u))`, whose last two signs are the edges' crossing directions.
//! The two ends of one triangle's interval are ordered by its orientation alone (see
//! [`interval`]).
//!
//! # Rounding
//!
//! The point where edge `pq` meets the plane of `t` is `p + s (q - p)`, `s = o_p / (o_p - o_q)`
//! with `o_x = n_t.(x - t0)`. Each coordinate is rounded to the nearest double (ties to even)
//! from its exact value, so the same exact point always gets the same bits, whichever pair,
//! edge direction or features reach it. A fast path encloses the coordinate in a double-double
//! interval and takes its centre when the whole enclosure rounds to it (nearly always); the
//! rest are computed in exact rationals. The exact point lies in the edge's bounding box, so no
//! coordinate overflows; one of magnitude below `2^-1022` is the nearest subnormal (absolute
//! error at most `2^-1075`). An exact zero is `+0.0`; a corner keeps its input bits.

use super::distance::V;
use super::double_double::{DdInterval, Fused, Plain, Split, two_sum};
use super::predicates::{
    Adaptive, BigExact, Orient, Point, Sign, is_safe_point, projected_orientations,
    to_integers_scaled,
};
use super::tri_tri::{Triangle, triangles_intersect};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};
use std::cell::Cell;

/// Which features of the two triangles hold an end of their segment of intersection. Corners
/// are local indices `0..3`; an edge is its two corners, the lower first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum EndFeature {
    /// Corner `k` of `a`, lying in `b` (its interior or an edge) but not a corner of `b`.
    CornerOfA(u8),
    /// Corner `k` of `b`, lying in `a` but not a corner of `a`.
    CornerOfB(u8),
    /// Corner `a` of the first triangle and corner `b` of the second: the same point.
    SharedCorner { a: u8, b: u8 },
    /// Edge `(i, j)` of `a`, its ends on opposite sides of `b`'s plane, crossing the interior
    /// of `b` (at the point where it meets `b`'s plane).
    EdgeOfA { i: u8, j: u8 },
    /// Edge `(i, j)` of `b` crossing the interior of `a`.
    EdgeOfB { i: u8, j: u8 },
    /// Edge `a` of the first triangle meeting edge `b` of the second at one point, a corner of
    /// neither. One of the two may lie in the other triangle's plane (touching it along the
    /// planes' line); the point is where the other one meets that plane.
    Edges { a: (u8, u8), b: (u8, u8) },
}

impl EndFeature {
    /// The name of a point whose carriers in `a` and in `b` are these, by the rule of the
    /// module documentation (a corner wins, then two edges, then an edge and an interior);
    /// `None` for a point inside both.
    fn of_carriers(in_a: Carrier, in_b: Carrier) -> Option<EndFeature> {
        Some(match (in_a, in_b) {
            (Carrier::Corner(i), Carrier::Corner(j)) => EndFeature::SharedCorner {
                a: i as u8,
                b: j as u8,
            },
            (Carrier::Corner(i), _) => EndFeature::CornerOfA(i as u8),
            (_, Carrier::Corner(j)) => EndFeature::CornerOfB(j as u8),
            (Carrier::Edge(i, j), Carrier::Edge(k, l)) => EndFeature::Edges {
                a: (i as u8, j as u8),
                b: (k as u8, l as u8),
            },
            (Carrier::Edge(i, j), Carrier::Interior) => EndFeature::EdgeOfA {
                i: i as u8,
                j: j as u8,
            },
            (Carrier::Interior, Carrier::Edge(i, j)) => EndFeature::EdgeOfB {
                i: i as u8,
                j: j as u8,
            },
            (Carrier::Interior, Carrier::Interior) => return None,
        })
    }

    /// The same feature with the roles of the triangles swapped.
    #[cfg(test)]
    pub(crate) fn mirrored(self) -> EndFeature {
        match self {
            EndFeature::CornerOfA(k) => EndFeature::CornerOfB(k),
            EndFeature::CornerOfB(k) => EndFeature::CornerOfA(k),
            EndFeature::SharedCorner { a, b } => EndFeature::SharedCorner { a: b, b: a },
            EndFeature::EdgeOfA { i, j } => EndFeature::EdgeOfB { i, j },
            EndFeature::EdgeOfB { i, j } => EndFeature::EdgeOfA { i, j },
            EndFeature::Edges { a, b } => EndFeature::Edges { a: b, b: a },
        }
    }
}

/// One end of a segment of intersection: its features and its rounded point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SegmentEnd {
    pub feature: EndFeature,
    pub point: Point,
}

/// What two closed triangles share.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PairIntersection {
    /// Nothing.
    Apart,
    /// A segment of positive length, from `start` to `end` along `n_a x n_b`: proper,
    /// non-coplanar triangles.
    Segment { start: SegmentEnd, end: SegmentEnd },
    /// A single point, of non-coplanar triangles or of a degenerate triangle crossing the other's
    /// plane.
    Point,
    /// Coplanar triangles that meet (in an area, a segment or a point), or degenerate ones that
    /// meet in the other's plane.
    Coplanar,
}

impl PairIntersection {
    /// The answer for the triangles swapped.
    #[cfg(test)]
    pub(crate) fn mirrored(self) -> PairIntersection {
        match self {
            PairIntersection::Segment { start, end } => PairIntersection::Segment {
                start: SegmentEnd {
                    feature: end.feature.mirrored(),
                    point: end.point,
                },
                end: SegmentEnd {
                    feature: start.feature.mirrored(),
                    point: start.point,
                },
            },
            other => other,
        }
    }
}

/// What the closed triangles `a` and `b` share; see the [module documentation](self).
pub(crate) fn triangle_pair_intersection(a: &Triangle, b: &Triangle) -> PairIntersection {
    if a.iter().chain(b).all(is_safe_point) {
        pair::<Adaptive, true>(a, b)
    } else {
        pair::<BigExact, true>(a, b)
    }
}

/// [`triangle_pair_intersection`] without the points: a segment's ends carry their features
/// and `[NaN; 3]`, for a caller that rounds each distinct point once ([`end_point`]).
pub(crate) fn triangle_pair_features(a: &Triangle, b: &Triangle) -> PairIntersection {
    if a.iter().chain(b).all(is_safe_point) {
        pair::<Adaptive, false>(a, b)
    } else {
        pair::<BigExact, false>(a, b)
    }
}

/// The point of the end at `feature` of the segment where `a` and `b` cross (as
/// [`triangle_pair_intersection`] gives it, bit for bit).
#[cfg(test)]
pub(crate) fn end_point(a: &Triangle, b: &Triangle, feature: EndFeature) -> Point {
    end_point_kept(a, b, feature, (0, 0), &mut Normals::default())
}

/// The normals of the last plane of each side that a rounded point was found in, kept for the
/// next point: the points of one triangle's plane are rounded one after another when they are
/// taken in the order of their names, and the normal is over a third of a point's arithmetic.
#[derive(Default)]
pub(crate) struct Normals {
    /// `(triangle, normal)` of side `a`, then of side `b`.
    kept: [Option<(u32, V<DdInterval>)>; 2],
}

impl Normals {
    /// The plane of triangle `t`, numbered `index` on `side` (0: `a`, 1: `b`), with its normal
    /// if it is kept.
    fn plane<'t>(&self, side: usize, index: u32, t: &'t Triangle) -> PlaneOf<'t> {
        let normal = self.kept[side].filter(|k| k.0 == index).map(|k| k.1);
        PlaneOf {
            t,
            normal: Cell::new(normal),
        }
    }

    /// Keeps the normal `plane` computed, if it did.
    fn keep(&mut self, side: usize, index: u32, plane: &PlaneOf) {
        if let Some(n) = plane.normal.get() {
            self.kept[side] = Some((index, n));
        }
    }
}

/// [`end_point`], for the triangles numbered `indices` (`a`'s, `b`'s; for one mesh, both of
/// it), with the normals kept in `normals`.
pub(crate) fn end_point_kept(
    a: &Triangle,
    b: &Triangle,
    feature: EndFeature,
    indices: (u32, u32),
    normals: &mut Normals,
) -> Point {
    let corner = |t: &Triangle, k: u8| t[usize::from(k)];
    // Where edge `pq` meets the plane of side `side`'s triangle `t`.
    let mut meet = |side: usize, t: &Triangle, p: &Point, q: &Point| {
        let index = if side == 0 { indices.0 } else { indices.1 };
        let plane = normals.plane(side, index, t);
        let x = plane.meet(p, q);
        normals.keep(side, index, &plane);
        x
    };
    match feature {
        EndFeature::CornerOfA(k) | EndFeature::SharedCorner { a: k, .. } => corner(a, k),
        EndFeature::CornerOfB(k) => corner(b, k),
        EndFeature::EdgeOfA { i, j } => meet(1, b, &corner(a, i), &corner(a, j)),
        EndFeature::EdgeOfB { i, j } => meet(0, a, &corner(b, i), &corner(b, j)),
        EndFeature::Edges {
            a: (i, j),
            b: (k, l),
        } => {
            // As `Pair::end`: where a's edge meets b's plane, unless that edge lies in it.
            let (p, q) = (corner(a, i), corner(a, j));
            let safe = a.iter().chain(b).all(is_safe_point);
            let off = |x: &Point| {
                if safe {
                    Adaptive::orient3d(&b[0], &b[1], &b[2], x) != 0
                } else {
                    BigExact::orient3d(&b[0], &b[1], &b[2], x) != 0
                }
            };
            if off(&p) || off(&q) {
                meet(1, b, &p, &q)
            } else {
                meet(0, a, &corner(b, k), &corner(b, l))
            }
        }
    }
}

/// Sides of `points` relative to the plane of `t`: the sign of `n_t.(p - t0)` (zero for all
/// when `t` is degenerate).
#[inline]
fn sides<O: Orient>(t: &Triangle, points: &Triangle) -> [Sign; 3] {
    O::plane_sides(t, points).map(|s| -s)
}

fn strictly_one_side(s: [Sign; 3]) -> bool {
    s.iter().all(|&x| x > 0) || s.iter().all(|&x| x < 0)
}

fn degenerate(t: &Triangle) -> bool {
    projected_orientations(&t[0], &t[1], &t[2]) == [0; 3]
}

/// Where one triangle's boundary meets the other's plane: on its edge `(u, v)`, whose sides of
/// that plane differ (at most one of them zero). It is corner `v` when `v` lies in the plane,
/// corner `u` when `u` does.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    u: usize,
    v: usize,
}

/// The carrier of a point in one triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Carrier {
    Corner(usize),
    Edge(usize, usize),
    Interior,
}

impl Crossing {
    fn carrier(self, s: [Sign; 3]) -> Carrier {
        if s[self.v] == 0 {
            Carrier::Corner(self.v)
        } else if s[self.u] == 0 {
            Carrier::Corner(self.u)
        } else {
            Carrier::Edge(self.u.min(self.v), self.u.max(self.v))
        }
    }
}

/// The ends of the interval where the proper triangle with sides `s` (relative to the other's
/// plane, neither all zero nor all of one strict side) meets the planes' line, in increasing
/// order along `n_a x n_b`; `first` tells whether the triangle is `a`.
///
/// With `p` the vertex alone on its side and `(p, q, r)` in the triangle's cyclic order, the
/// interval's ends are on edges `pq` and `pr`. The points `X1` on `pq` and `X2` on `pr` make
/// `(X1 - p) x (X2 - p)` a positive multiple of the triangle's normal `n`; with `p` on the
/// positive side of the other plane (normal `m`), that puts `X2` before `X1` along `n x m`.
/// For `a`, `n x m = n_a x n_b`; for `b` it is the opposite direction.
fn interval(s: [Sign; 3], first: bool) -> [Crossing; 2] {
    let (p, side) = apex(s);
    let (q, r) = ((p + 1) % 3, (p + 2) % 3);
    let (pq, pr) = (Crossing { u: p, v: q }, Crossing { u: p, v: r });
    if (side > 0) == first {
        [pr, pq]
    } else {
        [pq, pr]
    }
}

/// The vertex alone on its side of the other plane, and that side; with signs `(+, +, 0)` the
/// vertex on the plane (both ends of the interval are then that vertex).
fn apex(s: [Sign; 3]) -> (usize, Sign) {
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        if s[i] != 0 && s[j] * s[i] <= 0 && s[k] * s[i] <= 0 {
            return (i, s[i]);
        }
    }
    let i = s.iter().position(|&x| x == 0).expect("signs with a zero");
    (i, -s[(i + 1) % 3])
}

/// The two triangles with their sides relative to each other's plane.
struct Pair<'t> {
    a: &'t Triangle,
    b: &'t Triangle,
    /// Sides of `a`'s corners relative to `b`'s plane.
    sa: [Sign; 3],
    /// Sides of `b`'s corners relative to `a`'s plane.
    sb: [Sign; 3],
    plane_a: PlaneOf<'t>,
    plane_b: PlaneOf<'t>,
}

impl Pair<'_> {
    /// The sign of `s(Y) - s(X)` along `n_a x n_b`, for `X` where `x` (of `a`) meets `b`'s plane
    /// and `Y` where `y` (of `b`) meets `a`'s plane (see the method in the module docs).
    fn compare<O: Orient>(&self, x: Crossing, y: Crossing) -> Sign {
        let (u, v, w, z) = (x.u, x.v, y.u, y.v);
        let tetra = O::orient3d(&self.a[u], &self.a[v], &self.b[w], &self.b[z]);
        let along_b = (self.sa[v] - self.sa[u]).signum();
        let along_a = (self.sb[z] - self.sb[w]).signum();
        -tetra * along_a * along_b
    }
}

/// An end of the overlap: from `a`'s interval, `b`'s, or both at the same point.
#[derive(Clone, Copy)]
enum Source {
    A(Crossing),
    B(Crossing),
    Both(Crossing, Crossing),
}

fn pair<O: Orient, const ROUND: bool>(a: &Triangle, b: &Triangle) -> PairIntersection {
    let sb = sides::<O>(a, b);
    if strictly_one_side(sb) {
        return PairIntersection::Apart;
    }
    let sa = sides::<O>(b, a);
    if strictly_one_side(sa) {
        return PairIntersection::Apart;
    }
    let (flat_a, flat_b) = (sb == [0; 3], sa == [0; 3]);
    if flat_a || flat_b {
        if !triangles_intersect(a, b) {
            return PairIntersection::Apart;
        }
        // A degenerate triangle has every side zero. Otherwise all zero sides make the
        // triangles coplanar (then both are flat).
        let (degenerate_a, degenerate_b) = (flat_a && degenerate(a), flat_b && degenerate(b));
        let crosses_once = (degenerate_a && !degenerate_b && !flat_b)
            || (degenerate_b && !degenerate_a && !flat_a);
        return if crosses_once {
            PairIntersection::Point
        } else {
            PairIntersection::Coplanar
        };
    }
    let pair = Pair {
        a,
        b,
        sa,
        sb,
        plane_a: PlaneOf::new(a),
        plane_b: PlaneOf::new(b),
    };
    let [a_lo, a_hi] = interval(sa, true);
    let [b_lo, b_hi] = interval(sb, false);
    let start = match pair.compare::<O>(a_lo, b_lo) {
        1 => Source::B(b_lo),
        -1 => Source::A(a_lo),
        _ => Source::Both(a_lo, b_lo),
    };
    let end = match pair.compare::<O>(a_hi, b_hi) {
        1 => Source::A(a_hi),
        -1 => Source::B(b_hi),
        _ => Source::Both(a_hi, b_hi),
    };
    // The sign of the overlap's length. One triangle's interval is a single point exactly when
    // its lone vertex lies in the other's plane.
    let spread = |s: [Sign; 3]| Sign::from(s[apex(s).0] != 0);
    let length = match (start, end) {
        (Source::A(_) | Source::Both(..), Source::A(_) | Source::Both(..)) => spread(sa),
        (Source::B(_) | Source::Both(..), Source::B(_) | Source::Both(..)) => spread(sb),
        (Source::A(x), Source::B(y)) => pair.compare::<O>(x, y),
        (Source::B(y), Source::A(x)) => -pair.compare::<O>(x, y),
    };
    match length {
        -1 => PairIntersection::Apart,
        0 => PairIntersection::Point,
        _ => PairIntersection::Segment {
            start: pair.end::<ROUND>(start),
            end: pair.end::<ROUND>(end),
        },
    }
}

impl Pair<'_> {
    /// The carrier in the other triangle of a point strictly inside its interval: an edge when
    /// that triangle's interval is one of its edges (lying in this triangle's plane).
    fn inside_interval(s: [Sign; 3]) -> Carrier {
        match s.iter().filter(|&&x| x == 0).count() {
            2 => {
                let k = s
                    .iter()
                    .position(|&x| x != 0)
                    .expect("one corner off the plane");
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                Carrier::Edge(i.min(j), i.max(j))
            }
            _ => Carrier::Interior,
        }
    }

    fn end<const ROUND: bool>(&self, source: Source) -> SegmentEnd {
        let (in_a, in_b) = match source {
            Source::A(x) => (x.carrier(self.sa), Pair::inside_interval(self.sb)),
            Source::B(y) => (Pair::inside_interval(self.sa), y.carrier(self.sb)),
            Source::Both(x, y) => (x.carrier(self.sa), y.carrier(self.sb)),
        };
        let feature = EndFeature::of_carriers(in_a, in_b)
            .expect("an end of the overlap lies on a triangle's boundary");
        if !ROUND {
            return SegmentEnd {
                feature,
                point: [f64::NAN; 3],
            };
        }
        let point = match feature {
            EndFeature::CornerOfA(k) | EndFeature::SharedCorner { a: k, .. } => {
                self.a[usize::from(k)]
            }
            EndFeature::CornerOfB(k) => self.b[usize::from(k)],
            // Of two edges meeting, one may lie in the other triangle's plane: the point is
            // where the other edge meets that plane.
            EndFeature::EdgeOfA { i, j } | EndFeature::Edges { a: (i, j), .. }
                if self.sa[usize::from(i)] != 0 || self.sa[usize::from(j)] != 0 =>
            {
                (self.plane_b).meet(&self.a[usize::from(i)], &self.a[usize::from(j)])
            }
            EndFeature::EdgeOfA { .. } => unreachable!("an edge of a crossing b's interior"),
            EndFeature::EdgeOfB { i, j } | EndFeature::Edges { b: (i, j), .. } => {
                (self.plane_a).meet(&self.b[usize::from(i)], &self.b[usize::from(j)])
            }
        };
        SegmentEnd { feature, point }
    }
}

/// The point where the segment `pq`, which crosses the plane of the proper triangle `t` at one
/// point (`p` and `q` on different sides, at most one in the plane), meets it, each coordinate
/// rounded to the nearest double.
pub(crate) fn edge_meets_plane(p: &Point, q: &Point, t: &Triangle) -> Point {
    PlaneOf::new(t).meet(p, q)
}

/// A triangle's plane, for rounding where edges meet it: its normal in double-double intervals
/// is computed on first use and kept for the segment's other end.
struct PlaneOf<'t> {
    t: &'t Triangle,
    normal: Cell<Option<V<DdInterval>>>,
}

impl<'t> PlaneOf<'t> {
    /// Costs nothing until a point is asked for (a pair's features need no plane).
    fn new(t: &'t Triangle) -> PlaneOf<'t> {
        PlaneOf {
            t,
            normal: Cell::new(None),
        }
    }

    /// [`edge_meets_plane`] for this plane.
    fn meet(&self, p: &Point, q: &Point) -> Point {
        let x = if self.t.iter().all(is_safe_point)
            && is_safe_point(p)
            && is_safe_point(q)
            && let Some(x) = self.meet_fast_dispatch(p, q)
        {
            x
        } else {
            edge_meets_plane_exact(p, q, self.t)
        };
        // One zero for both signs, whichever way the arithmetic reached it.
        x.map(|c| c + 0.0)
    }

    /// [`PlaneOf::meet_fast`] with the products split by the fused multiply-add where the
    /// processor has it (the default x86-64 target does not assume it, and Dekker's split is
    /// most of the arithmetic of a rounded point); the results are the same either way.
    #[inline]
    fn meet_fast_dispatch(&self, p: &Point, q: &Point) -> Option<Point> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the processor has the fused multiply-add.
            return unsafe { self.meet_fast_fused(p, q) };
        }
        self.meet_fast::<Plain>(p, q)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "fma")]
    fn meet_fast_fused(&self, p: &Point, q: &Point) -> Option<Point> {
        self.meet_fast::<Fused>(p, q)
    }

    /// [`edge_meets_plane`] in double-double intervals, when every coordinate's enclosure rounds
    /// to one double; `None` otherwise. Only for safe coordinates (products of up to three
    /// differences then stay in the intervals' range).
    #[inline(always)]
    fn meet_fast<S: Split>(&self, p: &Point, q: &Point) -> Option<Point> {
        let t = self.t;
        let n = match self.normal.get() {
            Some(n) => n,
            None => {
                // `cross`, written out: a closure or a generic helper may be compiled apart from
                // this function, without the fused multiply-add.
                let (d1, d2) = (difference(&t[1], &t[0]), difference(&t[2], &t[0]));
                let n = [
                    d1[1].times::<S>(d2[2]) - d1[2].times::<S>(d2[1]),
                    d1[2].times::<S>(d2[0]) - d1[0].times::<S>(d2[2]),
                    d1[0].times::<S>(d2[1]) - d1[1].times::<S>(d2[0]),
                ];
                self.normal.set(Some(n));
                n
            }
        };
        let op = DdInterval::dot::<S>(&n, &difference(p, &t[0]));
        let oq = DdInterval::dot::<S>(&n, &difference(q, &t[0]));
        let (num, den) = if op.hi >= oq.hi {
            (op, op - oq)
        } else {
            (-op, oq - op)
        };
        let s = num.divide::<S>(&den)?;
        let pq = difference(q, p);
        let mut x = [0.0; 3];
        for k in 0..3 {
            x[k] = nearest(&(DdInterval::point(p[k]) + s.times::<S>(pq[k])))?;
        }
        Some(x)
    }
}

/// `a - b` exactly, as double-doubles.
#[inline(always)]
fn difference(a: &Point, b: &Point) -> V<DdInterval> {
    std::array::from_fn(|k| {
        let (h, l) = two_sum(a[k], -b[k]);
        DdInterval::exact(h, l)
    })
}

/// The double nearest to every value of `x`, if one is: its centre `hi`, when the enclosure
/// lies strictly between the midpoints from `hi` to its neighbours.
fn nearest(x: &DdInterval) -> Option<f64> {
    let hi = x.hi;
    if x.lo == 0.0 && x.rad == 0.0 {
        return hi.is_finite().then_some(hi);
    }
    // Normal magnitudes well inside the range, so that neighbours and halves are exact.
    if !(x.is_finite() && (f64::MIN_POSITIVE * 2f64.powi(60)..=f64::MAX / 4.0).contains(&hi.abs()))
    {
        return None;
    }
    let half_up = (hi.next_up() - hi) / 2.0;
    let half_down = (hi - hi.next_down()) / 2.0;
    // Each difference below is rounded once (relative error 2^-53); the margin covers it.
    let shrink = 1.0 - f64::EPSILON * 4.0;
    let room = (half_up - x.lo).min(half_down + x.lo) * shrink;
    (room > x.rad * (1.0 + f64::EPSILON * 4.0)).then_some(hi)
}

/// [`edge_meets_plane`] in exact rational arithmetic: the point is
/// `(o_p q - o_q p) / (o_p - o_q)` with `o_x = n_t.(x - t0)`, all on integers scaled by one power
/// of two.
fn edge_meets_plane_exact(p: &Point, q: &Point, t: &Triangle) -> Point {
    let (values, power) = to_integers_scaled([
        p[0], p[1], p[2], q[0], q[1], q[2], t[0][0], t[0][1], t[0][2], t[1][0], t[1][1], t[1][2],
        t[2][0], t[2][1], t[2][2],
    ]);
    let point = |i: usize| -> [BigInt; 3] { std::array::from_fn(|k| values[3 * i + k].clone()) };
    let (p, q, t0, t1, t2) = (point(0), point(1), point(2), point(3), point(4));
    let minus = |a: &[BigInt; 3], b: &[BigInt; 3]| -> [BigInt; 3] {
        std::array::from_fn(|k| &a[k] - &b[k])
    };
    let (e1, e2) = (minus(&t1, &t0), minus(&t2, &t0));
    let n = [
        &e1[1] * &e2[2] - &e1[2] * &e2[1],
        &e1[2] * &e2[0] - &e1[0] * &e2[2],
        &e1[0] * &e2[1] - &e1[1] * &e2[0],
    ];
    let side = |x: &[BigInt; 3]| -> BigInt {
        let f = minus(x, &t0);
        &n[0] * &f[0] + &n[1] * &f[1] + &n[2] * &f[2]
    };
    let (op, oq) = (side(&p), side(&q));
    let den = &op - &oq;
    assert!(!den.is_zero(), "the segment crosses the plane at one point");
    std::array::from_fn(|k| {
        let num = &op * &q[k] - &oq * &p[k];
        let shift = power.unsigned_abs() as usize;
        let value = if power >= 0 {
            BigRational::new_raw(num << shift, den.clone())
        } else {
            BigRational::new_raw(num, den.clone() << shift)
        };
        // Correctly rounded, ties to even, subnormals included.
        value.to_f64().expect("a finite coordinate")
    })
}

#[cfg(test)]
mod tests;
