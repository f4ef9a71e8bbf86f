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
//!
//! `decide.rs` finds which features hold the closest points and whether they are within the
//! distance (the signs); `values.rs` computes the rounded distance, points and weights of what
//! it chose. Queries decide for every candidate pair and compute values only for those kept.

pub(crate) use super::Primitive;
use super::aabb::Aabb;
use super::ball::Ball;
use super::distance::Big;
use super::double_double::{self, Plain};
use super::permanent::Permanent;
use super::predicates::{Point, to_integers};
use decide::decide;
use num_bigint::BigInt;
use num_traits::One;
use values::values_of;

mod decide;
mod filter;
pub(crate) use filter::{
    point_triangle as point_triangle_estimate, point_triangle_within,
    segment_segment as segments_estimate, triangles_lower_along,
};
#[cfg(test)]
mod tests;
mod values;

/// Where a closest point lies on its primitive, numbered on the primitive's own corners: a
/// vertex is its corner 0; an edge has corners 0 and 1 and its open segment
/// [`Feature::Edge01`]; a triangle has three corners, three open edges and its interior.
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Feature {
    /// Corner 0 (a vertex primitive is always here).
    #[default]
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

    /// Where on the triangle the closest point of a vertex-face pair lies.
    pub(crate) fn face_feature(self) -> Feature {
        match self.choice() {
            Choice::FaceCorner(k) => Feature::corner(k),
            Choice::FaceEdge(k) => Feature::edge(k),
            _ => Feature::Interior,
        }
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

/// Where the closest points of the primitives `p` lie, for primitives whose squared distance
/// is about `estimate`: decided within a little more than the estimate's root, where the
/// filters tell (deciding within the largest double instead takes exact big-integer arithmetic,
/// which allocates), and within the largest double when the estimate was too low. `None` beyond
/// the largest double.
pub(crate) fn decide_near(pair: Primitive, p: &[Point; 4], estimate: f64) -> Option<Decided> {
    let near = (estimate.max(0.0).sqrt() * (1.0 + 1.0 / (1u64 << 20) as f64)).next_up();
    if near.is_finite()
        && let Some(decided) = decide_within(pair, p, near)
    {
        return Some(decided);
    }
    decide_within(pair, p, f64::MAX)
}

/// One candidate of a distance query: a pair of primitives (as [`decide_within`] takes them)
/// and where their closest points lie.
pub(crate) type Candidate<'p> = (Primitive, &'p [Point; 4], Decided);

/// How the exact distances of two candidates compare: in intervals where they are apart, in
/// exact rationals where the intervals meet.
pub(crate) fn cmp_distance(x: Candidate, y: Candidate) -> std::cmp::Ordering {
    use std::cmp::Ordering;
    let (cx, cy) = (x.2.choice(), y.2.choice());
    if let (Some(a), Some(b)) = (
        values::squared_enclosure(x.0, x.1, cx),
        values::squared_enclosure(y.0, y.1, cy),
    ) {
        // Bounds of the intervals `[hi + lo - rad, hi + lo + rad]`, rounded outwards.
        let spread = |v: &double_double::DdInterval| (v.lo.abs() + v.rad) * (1.0 + f64::EPSILON);
        let upper = |v: &double_double::DdInterval| (v.hi + spread(v)).next_up();
        let lower = |v: &double_double::DdInterval| (v.hi - spread(v)).next_down();
        if upper(&a) < lower(&b) {
            return Ordering::Less;
        }
        if upper(&b) < lower(&a) {
            return Ordering::Greater;
        }
    }
    values::squared_exact(x.0, x.1, cx).cmp(&values::squared_exact(y.0, y.1, cy))
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
