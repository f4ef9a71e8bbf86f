//! The pair level against an independent judge in exact rationals: the intersection of the two
//! triangles gathered as the points where each one's edges meet the other, its extremes along
//! `n_a x n_b`, and the features holding them read off the exact points.

use super::*;
use crate::fixtures::Rng;
use crate::fixtures::rational::{Q, QPoint, q, qcross, qdot, qp, qsub};
use crate::geometry::predicates::Plane;
use num_traits::Signed;

fn is_zero(v: &QPoint) -> bool {
    v.iter().all(Zero::is_zero)
}

struct Tri {
    p: [QPoint; 3],
    n: QPoint,
}

impl Tri {
    fn of(t: &Triangle) -> Tri {
        let p = t.map(|c| qp(&c));
        let n = qcross(&qsub(&p[1], &p[0]), &qsub(&p[2], &p[0]));
        Tri { p, n }
    }
    fn side(&self, x: &QPoint) -> Q {
        qdot(&self.n, &qsub(x, &self.p[0]))
    }
    /// For `x` in the (proper) triangle's plane: inside or on the boundary?
    fn holds(&self, x: &QPoint) -> bool {
        [(0, 1), (1, 2), (2, 0)].iter().all(|&(i, j)| {
            !qdot(
                &qcross(&qsub(&self.p[j], &self.p[i]), &qsub(x, &self.p[i])),
                &self.n,
            )
            .is_negative()
        })
    }
    /// Where the segment `xy` meets this triangle's plane, when at one point.
    fn meet(&self, x: &QPoint, y: &QPoint) -> Option<QPoint> {
        let (sx, sy) = (self.side(x), self.side(y));
        if sx == sy {
            return None;
        }
        let den = &sx - &sy;
        Some(std::array::from_fn(|k| (&sx * &y[k] - &sy * &x[k]) / &den))
    }
}

fn on_segment(a: &QPoint, b: &QPoint, x: &QPoint) -> bool {
    let (ab, ax) = (qsub(b, a), qsub(x, a));
    is_zero(&qcross(&ab, &ax))
        && !qdot(&ab, &ax).is_negative()
        && !qdot(&qsub(a, b), &qsub(x, b)).is_negative()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Apart,
    Point,
    Segment,
    Coplanar,
}

fn kind_of(r: &PairIntersection) -> Kind {
    match r {
        PairIntersection::Apart => Kind::Apart,
        PairIntersection::Point => Kind::Point,
        PairIntersection::Segment { .. } => Kind::Segment,
        PairIntersection::Coplanar => Kind::Coplanar,
    }
}

/// The judge's answer: the kind and, for a segment, its exact ends in order along `n_a x n_b`.
fn judge(a: &Triangle, b: &Triangle) -> (Kind, Option<[QPoint; 2]>) {
    let (ta, tb) = (Tri::of(a), Tri::of(b));
    let meets = triangles_intersect(a, b);
    let (degenerate_a, degenerate_b) = (is_zero(&ta.n), is_zero(&tb.n));
    let all_in = |t: &Tri, plane: &Tri| t.p.iter().all(|x| plane.side(x).is_zero());
    if degenerate_a || degenerate_b {
        let kind = if !meets {
            Kind::Apart
        } else if degenerate_a && degenerate_b {
            Kind::Coplanar
        } else if (degenerate_a && !all_in(&ta, &tb)) || (degenerate_b && !all_in(&tb, &ta)) {
            Kind::Point
        } else {
            Kind::Coplanar
        };
        return (kind, None);
    }
    if all_in(&tb, &ta) {
        return (if meets { Kind::Coplanar } else { Kind::Apart }, None);
    }
    let mut points = Vec::new();
    for (t, other) in [(&ta, &tb), (&tb, &ta)] {
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let (x, y) = (&t.p[i], &t.p[j]);
            let candidates = if other.side(x).is_zero() && other.side(y).is_zero() {
                vec![x.clone(), y.clone()]
            } else if (other.side(x) * other.side(y)).is_positive() {
                vec![]
            } else {
                vec![other.meet(x, y).expect("crossing")]
            };
            points.extend(candidates.into_iter().filter(|c| other.holds(c)));
        }
    }
    assert_eq!(
        points.is_empty(),
        !meets,
        "the judge disagrees with the test"
    );
    if points.is_empty() {
        return (Kind::Apart, None);
    }
    let d = qcross(&ta.n, &tb.n);
    let at = |x: &QPoint| qdot(&d, x);
    let low = points.iter().min_by(|x, y| at(x).cmp(&at(y))).unwrap();
    let high = points.iter().max_by(|x, y| at(x).cmp(&at(y))).unwrap();
    if at(low) == at(high) {
        (Kind::Point, None)
    } else {
        (Kind::Segment, Some([low.clone(), high.clone()]))
    }
}

/// The features naming the exact point `x`, an end of the intersection, by the rule of the
/// module docs: corners first, then two edges, then one.
fn expected_feature(a: &Triangle, b: &Triangle, x: &QPoint) -> EndFeature {
    let carrier = |t: &Triangle| -> Carrier {
        let t = Tri::of(t);
        if let Some(k) = t.p.iter().position(|c| c == x) {
            return Carrier::Corner(k);
        }
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            if on_segment(&t.p[i], &t.p[j], x) {
                return Carrier::Edge(i, j);
            }
        }
        Carrier::Interior
    };
    // The naming rule itself is the library's; the carriers are found here, exactly.
    EndFeature::of_carriers(carrier(a), carrier(b)).expect("an end inside both triangles")
}

/// The exact point a reported feature names, checked to be one point for every part of it.
fn point_of(a: &Triangle, b: &Triangle, f: EndFeature) -> QPoint {
    let (ta, tb) = (Tri::of(a), Tri::of(b));
    let edge = |t: &Tri, other: &Tri, (i, j): (u8, u8)| {
        assert!(i < j, "{f:?}");
        let x = other
            .meet(&t.p[usize::from(i)], &t.p[usize::from(j)])
            .unwrap_or_else(|| panic!("{f:?}: the edge does not cross the plane once"));
        assert!(on_segment(&t.p[usize::from(i)], &t.p[usize::from(j)], &x));
        x
    };
    match f {
        EndFeature::CornerOfA(k) => ta.p[usize::from(k)].clone(),
        EndFeature::CornerOfB(k) => tb.p[usize::from(k)].clone(),
        EndFeature::SharedCorner { a: i, b: j } => {
            assert_eq!(ta.p[usize::from(i)], tb.p[usize::from(j)], "{f:?}");
            ta.p[usize::from(i)].clone()
        }
        EndFeature::EdgeOfA { i, j } => edge(&ta, &tb, (i, j)),
        EndFeature::EdgeOfB { i, j } => edge(&tb, &ta, (i, j)),
        EndFeature::Edges { a: ea, b: eb } => {
            // One of the edges may lie in the other triangle's plane.
            let corners = |t: &Tri, (i, j): (u8, u8)| {
                [t.p[usize::from(i)].clone(), t.p[usize::from(j)].clone()]
            };
            let ([p, q], [r, s]) = (corners(&ta, ea), corners(&tb, eb));
            let x = if tb.side(&p).is_zero() && tb.side(&q).is_zero() {
                edge(&tb, &ta, eb)
            } else {
                edge(&ta, &tb, ea)
            };
            assert!(on_segment(&p, &q, &x) && on_segment(&r, &s, &x), "{f:?}");
            x
        }
    }
}

/// Is `r` the double nearest to `x` (ties to even)?
fn is_nearest(x: &Q, r: f64) -> bool {
    if !r.is_finite() {
        return false;
    }
    let error = (q(r) - x).abs();
    [r.next_up(), r.next_down()]
        .into_iter()
        .filter(|n| n.is_finite())
        .all(|n| {
            let other = (q(n) - x).abs();
            other > error || (other == error && r.to_bits() & 1 == 0)
        })
}

/// Checks `triangle_pair_intersection(a, b)` against the judge; returns its kind.
fn check(a: &Triangle, b: &Triangle) -> Kind {
    let result = triangle_pair_intersection(a, b);
    let (kind, ends) = judge(a, b);
    assert_eq!(kind_of(&result), kind, "{a:?} {b:?}: {result:?}");
    if let PairIntersection::Segment { start, end } = result {
        let ends = ends.expect("a segment");
        for (reported, exact) in [start, end].iter().zip(&ends) {
            let x = point_of(a, b, reported.feature);
            assert_eq!(&x, exact, "{a:?} {b:?}: {result:?}");
            assert_eq!(
                reported.feature,
                expected_feature(a, b, exact),
                "{a:?} {b:?}: {result:?}"
            );
            for (k, (x, r)) in x.iter().zip(reported.point).enumerate() {
                assert!(is_nearest(x, r), "{a:?} {b:?}: {result:?}, coordinate {k}");
            }
            // The features alone, and each point rounded from its feature, are the same.
            let bits = |p: Point| p.map(f64::to_bits);
            assert_eq!(
                bits(end_point(a, b, reported.feature)),
                bits(reported.point),
                "{a:?} {b:?}: {result:?}"
            );
        }
        match triangle_pair_features(a, b) {
            PairIntersection::Segment { start: s, end: e } => {
                assert_eq!([s.feature, e.feature], [start.feature, end.feature]);
            }
            other => panic!("{a:?} {b:?}: {other:?} without points, {result:?} with"),
        }
    } else {
        assert_eq!(triangle_pair_features(a, b), result);
    }
    kind
}

/// The feature of the permuted pair renamed to the original corners (`pa[k]` is the original
/// index of corner `k` of the permuted `a`).
fn renamed(f: EndFeature, pa: [usize; 3], pb: [usize; 3]) -> EndFeature {
    let corner = |p: [usize; 3], k: u8| p[usize::from(k)] as u8;
    let edge = |p: [usize; 3], (i, j): (u8, u8)| {
        let (x, y) = (corner(p, i), corner(p, j));
        (x.min(y), x.max(y))
    };
    match f {
        EndFeature::CornerOfA(k) => EndFeature::CornerOfA(corner(pa, k)),
        EndFeature::CornerOfB(k) => EndFeature::CornerOfB(corner(pb, k)),
        EndFeature::SharedCorner { a, b } => EndFeature::SharedCorner {
            a: corner(pa, a),
            b: corner(pb, b),
        },
        EndFeature::EdgeOfA { i, j } => {
            let (i, j) = edge(pa, (i, j));
            EndFeature::EdgeOfA { i, j }
        }
        EndFeature::EdgeOfB { i, j } => {
            let (i, j) = edge(pb, (i, j));
            EndFeature::EdgeOfB { i, j }
        }
        EndFeature::Edges { a, b } => EndFeature::Edges {
            a: edge(pa, a),
            b: edge(pb, b),
        },
    }
}

/// The answer is the same, relabelled, for every order of the corners and, mirrored, for the
/// triangles swapped; the segment turns with the orientation of a triangle.
fn check_symmetry(a: &Triangle, b: &Triangle) {
    let base = triangle_pair_intersection(a, b);
    assert_eq!(
        triangle_pair_intersection(b, a),
        base.mirrored(),
        "{a:?} {b:?}"
    );
    for (n, pa) in crate::geometry::CORNER_ORDERS.iter().enumerate() {
        for (m, pb) in crate::geometry::CORNER_ORDERS.iter().enumerate() {
            let a2 = pa.map(|k| a[k]);
            let b2 = pb.map(|k| b[k]);
            let flipped = (n >= 3) != (m >= 3);
            let r = match triangle_pair_intersection(&a2, &b2) {
                PairIntersection::Segment { start, end } => {
                    let name = |e: SegmentEnd| SegmentEnd {
                        feature: renamed(e.feature, *pa, *pb),
                        point: e.point,
                    };
                    let (start, end) = if flipped {
                        (name(end), name(start))
                    } else {
                        (name(start), name(end))
                    };
                    PairIntersection::Segment { start, end }
                }
                other => other,
            };
            assert_eq!(r, base, "{a:?} {b:?} permuted {pa:?} {pb:?}");
        }
    }
}

/// Counts of the kinds seen.
#[derive(Default, Debug)]
struct Tally([usize; 4]);

impl Tally {
    fn add(&mut self, k: Kind) {
        self.0[k as usize] += 1;
    }
}

fn check_all(a: &Triangle, b: &Triangle, tally: &mut Tally) {
    tally.add(check(a, b));
    check(b, a);
    check_symmetry(a, b);
}

/// [`check_all`] for slow (big-number) cases, leaving most of the symmetries to the others.
fn check_some(a: &Triangle, b: &Triangle, tally: &mut Tally, case: usize) {
    tally.add(check(a, b));
    if case.is_multiple_of(8) {
        check_symmetry(a, b);
    } else {
        assert_eq!(
            triangle_pair_intersection(b, a),
            triangle_pair_intersection(a, b).mirrored()
        );
    }
}

fn small_point(rng: &mut Rng, n: u64) -> Point {
    std::array::from_fn(|_| rng.below(2 * n + 1) as f64 - n as f64)
}

/// The geometry a feature names, as the bits of the corners it takes (an edge's sorted, a
/// triangle's in order), for comparing the points of the same feature reached by different pairs.
type FeatureKey = Vec<[u64; 3]>;

fn feature_key(a: &Triangle, b: &Triangle, f: EndFeature) -> FeatureKey {
    let bits = |p: &Point| p.map(f64::to_bits);
    let edge = |t: &Triangle, (i, j): (u8, u8)| {
        let mut e = vec![bits(&t[usize::from(i)]), bits(&t[usize::from(j)])];
        e.sort();
        e
    };
    let mut key = match f {
        EndFeature::CornerOfA(k) | EndFeature::SharedCorner { a: k, .. } => {
            return vec![bits(&a[usize::from(k)])];
        }
        EndFeature::CornerOfB(k) => return vec![bits(&b[usize::from(k)])],
        EndFeature::Edges { a: ea, b: eb } => {
            let (mut x, y) = (edge(a, ea), edge(b, eb));
            if x > y {
                return [y, x].concat();
            }
            x.extend(y);
            return x;
        }
        EndFeature::EdgeOfA { i, j } => [edge(a, (i, j)), b.iter().map(bits).collect()].concat(),
        EndFeature::EdgeOfB { i, j } => [edge(b, (i, j)), a.iter().map(bits).collect()].concat(),
    };
    key.push([u64::from(matches!(f, EndFeature::EdgeOfB { .. })); 3]);
    key
}

#[test]
fn small_integer_triangles_agree_with_the_judge() {
    // A coarse grid makes shared corners, touching, coplanar and degenerate pairs common.
    let mut rng = Rng::new(11);
    let mut tally = Tally::default();
    let mut seen = std::collections::HashMap::<FeatureKey, Point>::new();
    let mut variants = std::collections::HashSet::new();
    let mut again = 0;
    for case in 0..6000 {
        let n = 1 + (case % 3) as u64;
        let mut a: Triangle = std::array::from_fn(|_| small_point(&mut rng, n));
        let mut b: Triangle = std::array::from_fn(|_| small_point(&mut rng, n));
        if case % 4 == 0 {
            // Into one plane.
            for p in a.iter_mut().chain(&mut b) {
                p[2] = 0.0;
            }
        }
        check_all(&a, &b, &mut tally);
        if let PairIntersection::Segment { start, end } = triangle_pair_intersection(&a, &b) {
            for e in [start, end] {
                variants.insert(std::mem::discriminant(&e.feature));
                let key = feature_key(&a, &b, e.feature);
                if let Some(p) = seen.insert(key, e.point) {
                    again += 1;
                    assert_eq!(p.map(f64::to_bits), e.point.map(f64::to_bits));
                }
            }
        }
    }
    // Every kind and every feature occurs often; features recur across pairs.
    assert!(tally.0.iter().all(|&c| c > 100), "{tally:?}");
    assert_eq!(variants.len(), 6);
    assert!(again > 100, "{again}");
}

/// A triangle through the point `c`: `c` plus three random offsets whose convex hull holds the
/// origin, scaled by `size`.
fn around(rng: &mut Rng, c: Point, size: f64) -> Triangle {
    let mut t = [[0.0; 3]; 3];
    let w = [
        rng.range(0.05, 1.0),
        rng.range(0.05, 1.0),
        rng.range(0.05, 1.0),
    ];
    let o: [Point; 3] = std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-1.0, 1.0)));
    let sum = w[0] + w[1] + w[2];
    let centre: Point = std::array::from_fn(|k| (0..3).map(|i| w[i] * o[i][k]).sum::<f64>() / sum);
    for i in 0..3 {
        t[i] = std::array::from_fn(|k| c[k] + size * (o[i][k] - centre[k]));
    }
    t
}

#[test]
fn crossing_float_triangles_agree_with_the_judge() {
    let mut rng = Rng::new(5);
    let mut tally = Tally::default();
    let n = crate::fixtures::cases(400, 1500);
    for _ in 0..n {
        let a: Triangle = std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-1.0, 1.0)));
        let c: Point = std::array::from_fn(|k| {
            let w = [rng.unit(), rng.unit(), rng.unit()];
            (0..3).map(|i| w[i] * a[i][k]).sum::<f64>() / (w[0] + w[1] + w[2])
        });
        let size = rng.range(0.1, 2.0);
        let b = around(&mut rng, c, size);
        check_all(&a, &b, &mut tally);
    }
    assert!(tally.0[Kind::Segment as usize] > n * 7 / 10, "{tally:?}");
}

#[test]
fn extreme_scales_and_offsets_agree_with_the_judge() {
    let mut rng = Rng::new(9);
    let mut tally = Tally::default();
    // `x 2^k`, exactly where the result is representable (two steps reach the subnormals).
    let scaled = |x: f64, k: i32| x * 2f64.powi(k / 2) * 2f64.powi(k - k / 2);
    let n = crate::fixtures::cases(500, 2000);
    for case in 0..n {
        let a: Triangle = std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-1.0, 1.0)));
        let c: Point = std::array::from_fn(|k| (a[0][k] + a[1][k] + a[2][k]) / 3.0);
        let b = around(&mut rng, c, 1.0);
        let (mut a, b) = match case % 4 {
            0 | 1 => {
                // Powers of two keep the geometry exactly, until coordinates turn subnormal;
                // then rounded inputs make it nearly degenerate.
                let k = if case % 4 == 0 {
                    rng.below(1801) as i32 - 900
                } else if rng.below(2) == 0 {
                    rng.below(75) as i32 - 1074
                } else {
                    rng.below(63) as i32 + 960
                };
                let s = |t: Triangle| t.map(|p| p.map(|x| scaled(x, k)));
                (s(a), s(b))
            }
            2 => {
                let o: Point = std::array::from_fn(|_| rng.range(-1e6, 1e6));
                let moved = |t: Triangle| t.map(|p| std::array::from_fn(|k| p[k] + o[k]));
                (moved(a), moved(b))
            }
            _ => (a, b),
        };
        if case % 4 == 3 {
            // One coordinate outside the predicates' safe range, in otherwise plain input.
            a[rng.below(3) as usize][rng.below(3) as usize] = 1e-250;
        }
        check_some(&a, &b, &mut tally, case);
    }
    assert!(tally.0[Kind::Segment as usize] > n * 3 / 5, "{tally:?}");
}

#[test]
fn constructed_contacts_agree_with_the_judge() {
    let t = |p: [[f64; 3]; 3]| -> Triangle { p };
    let a = t([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]);
    let cases: Vec<(Triangle, Triangle, Kind)> = vec![
        // A proper crossing: an edge of b through the interior of a and out across a's edge.
        (
            a,
            t([[1.0, 1.0, -1.0], [1.0, 1.0, 1.0], [6.0, 1.0, 0.0]]),
            Kind::Segment,
        ),
        // An edge of b through the corner (0, 0, 0) of a.
        (
            a,
            t([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [1.0, 1.0, 0.0]]),
            Kind::Segment,
        ),
        // A shared corner, b crossing a's interior from it.
        (
            a,
            t([[0.0, 0.0, 0.0], [2.0, 2.0, 1.0], [2.0, 1.0, -1.0]]),
            Kind::Segment,
        ),
        // A shared corner and nothing else.
        (
            a,
            t([[0.0, 0.0, 0.0], [-1.0, -1.0, 1.0], [-1.0, -2.0, -1.0]]),
            Kind::Point,
        ),
        // A shared edge, folded.
        (
            a,
            t([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [1.0, -1.0, 2.0]]),
            Kind::Segment,
        ),
        // A corner touching a's face from above.
        (
            a,
            t([[1.0, 1.0, 0.0], [1.0, 2.0, 3.0], [2.0, 1.0, 3.0]]),
            Kind::Point,
        ),
        // An edge of b lying in a's face, b above it (touching, not crossing).
        (
            a,
            t([[1.0, 1.0, 0.0], [2.0, 1.0, 0.0], [1.0, 1.0, 3.0]]),
            Kind::Segment,
        ),
        // An edge of b lying across a, longer than a.
        (
            a,
            t([[-1.0, 1.0, 0.0], [6.0, 1.0, 0.0], [1.0, 1.0, 3.0]]),
            Kind::Segment,
        ),
        // Edges crossing edges: b's edge crosses a's edge (x axis) at (1, 0, 0).
        (
            a,
            t([[1.0, -1.0, -1.0], [1.0, 1.0, 1.0], [3.0, 1.0, -1.0]]),
            Kind::Segment,
        ),
        // Coplanar overlap, coplanar touching at a corner, coplanar apart.
        (
            a,
            t([[1.0, 1.0, 0.0], [5.0, 1.0, 0.0], [1.0, 5.0, 0.0]]),
            Kind::Coplanar,
        ),
        (
            a,
            t([[4.0, 0.0, 0.0], [5.0, 0.0, 0.0], [5.0, 1.0, 0.0]]),
            Kind::Coplanar,
        ),
        (
            a,
            t([[5.0, 5.0, 0.0], [6.0, 5.0, 0.0], [5.0, 6.0, 0.0]]),
            Kind::Apart,
        ),
        // Degenerate b: a segment piercing a, lying in a, a point in a, a point off a.
        (
            a,
            t([[1.0, 1.0, -1.0], [1.0, 1.0, 1.0], [1.0, 1.0, 0.5]]),
            Kind::Point,
        ),
        (
            a,
            t([[1.0, 1.0, 0.0], [2.0, 1.0, 0.0], [3.0, 1.0, 0.0]]),
            Kind::Coplanar,
        ),
        (
            a,
            t([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 0.0]]),
            Kind::Coplanar,
        ),
        (
            a,
            t([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]),
            Kind::Apart,
        ),
        // Both degenerate, crossing.
        (
            t([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
            t([[1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 0.0]]),
            Kind::Coplanar,
        ),
        // Apart: b above a.
        (
            a,
            t([[1.0, 1.0, 1.0], [2.0, 1.0, 2.0], [1.0, 2.0, 3.0]]),
            Kind::Apart,
        ),
    ];
    let mut tally = Tally::default();
    for (a, b, kind) in &cases {
        assert_eq!(check(a, b), *kind, "{a:?} {b:?}");
        check_all(a, b, &mut tally);
    }
    // Features of the named cases.
    let features = |a: &Triangle, b: &Triangle| match triangle_pair_intersection(a, b) {
        PairIntersection::Segment { start, end } => (start.feature, end.feature),
        other => panic!("{other:?}"),
    };
    let (s, e) = features(&cases[1].0, &cases[1].1);
    assert!(s == EndFeature::CornerOfA(0) || e == EndFeature::CornerOfA(0));
    let (s, e) = features(&cases[4].0, &cases[4].1);
    assert!(
        matches!(s, EndFeature::SharedCorner { .. })
            && matches!(e, EndFeature::SharedCorner { .. })
    );
    let (s, e) = features(&cases[8].0, &cases[8].1);
    assert!([s, e].contains(&EndFeature::Edges {
        a: (0, 1),
        b: (0, 1)
    }));
}

#[test]
fn fast_rounding_agrees_with_the_exact_one() {
    let mut rng = Rng::new(21);
    let (mut fast, mut total) = (0, 0);
    for case in 0..20000 {
        let t: Triangle = std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-1.0, 1.0)));
        let p: Point = std::array::from_fn(|_| rng.range(-1.0, 1.0));
        let mut q: Point = std::array::from_fn(|_| rng.range(-1.0, 1.0));
        if case % 4 == 0 {
            // Nearly parallel to the plane: the quotient is ill-conditioned.
            let n = Plane::of(&t).normal();
            let step = rng.range(-1e-12, 1e-12);
            q = std::array::from_fn(|k| p[k] + q[k] - n[k] * (q[k] * n[k]) + step * n[k]);
        }
        let tt = Tri::of(&t);
        let (sp, sq) = (tt.side(&qp(&p)), tt.side(&qp(&q)));
        if (&sp * &sq).is_positive() || sp == sq {
            continue;
        }
        total += 1;
        let exact = edge_meets_plane_exact(&p, &q, &t);
        let x = tt.meet(&qp(&p), &qp(&q)).unwrap();
        for k in 0..3 {
            assert!(is_nearest(&x[k], exact[k]));
        }
        let plain = PlaneOf::new(&t).meet_fast::<Plain>(&p, &q);
        let bits = |x: Option<Point>| x.map(|x| x.map(f64::to_bits));
        // The fused multiply-add (where the processor has it) splits products as exactly.
        assert_eq!(
            bits(plain),
            bits(PlaneOf::new(&t).meet_fast_dispatch(&p, &q))
        );
        if let Some(f) = plain {
            fast += 1;
            assert_eq!(
                f.map(f64::to_bits),
                exact.map(f64::to_bits),
                "{p:?} {q:?} {t:?}"
            );
        }
    }
    assert!(fast * 100 >= total * 99, "{fast} of {total}");
}

/// Times the pair level on crossing pairs (run with `--ignored --nocapture` in release).
#[test]
#[ignore]
fn time_crossing_pairs() {
    let mut rng = Rng::new(3);
    let pairs: Vec<(Triangle, Triangle)> = (0..100_000)
        .map(|_| {
            let a: Triangle =
                std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-1.0, 1.0)));
            let c: Point = std::array::from_fn(|k| (a[0][k] + a[1][k] + a[2][k]) / 3.0);
            let b = around(&mut rng, c, 1.0);
            (a, b)
        })
        .collect();
    for round in 0..3 {
        let start = std::time::Instant::now();
        let mut segments = 0;
        for (a, b) in &pairs {
            if let PairIntersection::Segment { start, .. } = triangle_pair_intersection(a, b) {
                segments += usize::from(start.point[0] != f64::MAX);
            }
        }
        let took = start.elapsed();
        let rounding = std::time::Instant::now();
        let mut sum = 0.0;
        for (a, b) in &pairs {
            // The line through the edge meets the plane: the same arithmetic as a crossing.
            let x = edge_meets_plane(&a[0], &a[1], b);
            sum += x[0];
        }
        let rounded = rounding.elapsed();
        let cached = std::time::Instant::now();
        for (a, b) in &pairs {
            let plane = PlaneOf::new(b);
            sum += plane.meet(&a[0], &a[1])[0] + plane.meet(&a[1], &a[2])[0];
        }
        println!(
            "two points against one plane: {:.0} ns",
            cached.elapsed().as_nanos() as f64 / pairs.len() as f64
        );
        println!(
            "rounding one point (any edge against a plane): {:.0} ns ({sum})",
            rounded.as_nanos() as f64 / pairs.len() as f64
        );
        let test = std::time::Instant::now();
        let mut hits = 0;
        for (a, b) in &pairs {
            hits += usize::from(triangles_intersect(a, b));
        }
        let tested = test.elapsed();
        println!(
            "round {round}: {segments} segments of {} pairs, {:.0} ns a pair; the triangle test \
             {:.0} ns ({hits} hits)",
            pairs.len(),
            took.as_nanos() as f64 / pairs.len() as f64,
            tested.as_nanos() as f64 / pairs.len() as f64
        );
    }
}
