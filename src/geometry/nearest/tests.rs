//! The closest features against an oracle in exact rationals that computes values, where the
//! code under test decides signs: every candidate closest pair (corners, edge and face
//! projections that land strictly inside) with its exact squared distance.

use super::values::sqrt_rational;
use super::*;
use crate::fixtures::Rng;
use crate::fixtures::rational::{Q, QPoint, q, qcross, qdot, qp as qv, qsub};
use num_traits::{One, ToPrimitive, Zero};

type QV = QPoint;

fn qlerp(a: &QV, b: &QV, s: &Q) -> QV {
    [0, 1, 2].map(|k| &a[k] + s * (&b[k] - &a[k]))
}

/// One candidate of the oracle: features, exact closest points, weights.
#[derive(Clone)]
struct Cand {
    features: [Feature; 2],
    points: [QV; 2],
    weights: [[Q; 3]; 2],
}

impl Cand {
    fn squared(&self) -> Q {
        let d = qsub(&self.points[0], &self.points[1]);
        qdot(&d, &d)
    }
}

fn unit(k: usize) -> [Q; 3] {
    let mut w = [Q::zero(), Q::zero(), Q::zero()];
    w[k] = Q::one();
    w
}
fn edge_w(k: usize, s: &Q) -> [Q; 3] {
    let mut w = [Q::zero(), Q::zero(), Q::zero()];
    w[k] = Q::one() - s;
    w[(k + 1) % 3] = s.clone();
    w
}

/// Point `x` against segment `[a, b]`: the corners, and the projection when strictly inside.
fn point_segment_cands(x: &QV, a: &QV, b: &QV) -> Vec<(Option<usize>, QV, Q)> {
    let mut out = vec![
        (Some(0), a.clone(), Q::zero()),
        (Some(1), b.clone(), Q::one()),
    ];
    let u = qsub(b, a);
    let uu = qdot(&u, &u);
    if !uu.is_zero() {
        let s = qdot(&qsub(x, a), &u) / &uu;
        if s > Q::zero() && s < Q::one() {
            out.push((None, qlerp(a, b, &s), s));
        }
    }
    out
}

fn oracle(pair: Primitive, p: &[Point; 4]) -> Vec<Cand> {
    let v: Vec<QV> = p.iter().map(qv).collect();
    let mut c = Vec::new();
    match pair {
        Primitive::VertexFace => {
            for k in 0..3 {
                c.push(Cand {
                    features: [Feature::Vertex0, Feature::corner(k)],
                    points: [v[0].clone(), v[1 + k].clone()],
                    weights: [unit(0), unit(k)],
                });
                let (a, b) = (&v[1 + k], &v[1 + (k + 1) % 3]);
                for (on, point, s) in point_segment_cands(&v[0], a, b) {
                    if on.is_none() {
                        c.push(Cand {
                            features: [Feature::Vertex0, Feature::edge(k)],
                            points: [v[0].clone(), point],
                            weights: [unit(0), edge_w(k, &s)],
                        });
                    }
                }
            }
            let n = qcross(&qsub(&v[2], &v[1]), &qsub(&v[3], &v[1]));
            let nn = qdot(&n, &n);
            if !nn.is_zero() {
                let w: Vec<Q> = (0..3)
                    .map(|k| {
                        let (b, c) = (&v[1 + (k + 1) % 3], &v[1 + (k + 2) % 3]);
                        qdot(&n, &qcross(&qsub(b, &v[0]), &qsub(c, &v[0]))) / &nn
                    })
                    .collect();
                if w.iter().all(|x| x > &Q::zero()) {
                    let point =
                        [0, 1, 2].map(|k| &w[0] * &v[1][k] + &w[1] * &v[2][k] + &w[2] * &v[3][k]);
                    c.push(Cand {
                        features: [Feature::Vertex0, Feature::Interior],
                        points: [v[0].clone(), point],
                        weights: [unit(0), [w[0].clone(), w[1].clone(), w[2].clone()]],
                    });
                }
            }
        }
        Primitive::EdgeEdge => {
            for x in 0..4 {
                let other = if x < 2 { 1 } else { 0 };
                let (a, b) = (&v[2 * other], &v[2 * other + 1]);
                for (on, point, s) in point_segment_cands(&v[x], a, b) {
                    let mut features = [Feature::corner(x % 2); 2];
                    features[other] = on.map_or(Feature::Edge01, Feature::corner);
                    let mut points = [v[x].clone(), v[x].clone()];
                    points[other] = point;
                    let mut weights = [unit(x % 2), unit(x % 2)];
                    weights[other] = edge_w(0, &s);
                    c.push(Cand {
                        features,
                        points,
                        weights,
                    });
                }
            }
            let (u, w2, w) = (qsub(&v[1], &v[0]), qsub(&v[3], &v[2]), qsub(&v[0], &v[2]));
            let n = qcross(&u, &w2);
            let nn = qdot(&n, &n);
            if !nn.is_zero() {
                let (uu, uv, vv) = (qdot(&u, &u), qdot(&u, &w2), qdot(&w2, &w2));
                let (uw, vw) = (qdot(&u, &w), qdot(&w2, &w));
                let s = (&uv * &vw - &vv * &uw) / &nn;
                let t = (&uu * &vw - &uv * &uw) / &nn;
                let inside = |x: &Q| x > &Q::zero() && x < &Q::one();
                if inside(&s) && inside(&t) {
                    c.push(Cand {
                        features: [Feature::Edge01, Feature::Edge01],
                        points: [qlerp(&v[0], &v[1], &s), qlerp(&v[2], &v[3], &t)],
                        weights: [edge_w(0, &s), edge_w(0, &t)],
                    });
                }
            }
        }
    }
    c
}

/// Units in the last place between `got` and the exact `want` rounded.
fn ulps(got: f64, want: &Q) -> u64 {
    let w = want.to_f64().unwrap();
    if got == w {
        return 0;
    }
    let key = |x: f64| {
        let b = x.to_bits() as i64;
        if b < 0 { i64::MIN - b } else { b }
    };
    key(got).abs_diff(key(w))
}

/// Checks `closest` against the oracle for `p` at distance `d`.
fn check(pair: Primitive, p: &[Point; 4], d: f64) -> bool {
    let cands = oracle(pair, p);
    let min = cands.iter().map(Cand::squared).min().unwrap();
    let dd = q(d) * q(d);
    let got = nearest(pair, p, d);
    assert_eq!(got.is_some(), min <= dd, "{pair:?} {p:?} d {d}");
    let Some(got) = got else {
        return false;
    };
    // The candidate the rules pick: any closest; its points are the reported ones.
    let closest_cands: Vec<&Cand> = cands.iter().filter(|c| c.squared() == min).collect();
    let want = closest_cands
        .iter()
        .find(|c| c.features == got.features)
        .unwrap_or_else(|| panic!("{pair:?} {p:?}: feature {:?} is not closest", got.features));
    // The lowest-dimensional feature of the unique closest point (vertex-face).
    if pair == Primitive::VertexFace {
        let best = closest_cands.iter().map(|c| c.features[1]).min().unwrap();
        let rank = |f: Feature| match f {
            Feature::Vertex0 | Feature::Vertex1 | Feature::Vertex2 => 0,
            Feature::Interior => 2,
            _ => 1,
        };
        assert_eq!(rank(got.features[1]), rank(best), "{p:?}");
    }
    // Distance: within one unit of the correctly rounded root r of the exact square, the
    // double whose rounding interval (between the midpoints to its neighbours) holds the root.
    let dist = got.distance;
    let rounds_to = |c: f64| {
        let two = q(2.0);
        let lo = (q(c.next_down().max(0.0)) + q(c)) / &two;
        let hi = (q(c) + q(c.next_up())) / &two;
        &lo * &lo <= min && min <= &hi * &hi
    };
    assert!(
        [dist.next_down().max(0.0), dist, dist.next_up()]
            .into_iter()
            .any(rounds_to),
        "{pair:?} {p:?}: distance {dist} against squared {}",
        min.to_f64().unwrap()
    );
    for s in 0..2 {
        for k in 0..3 {
            assert!(
                ulps(got.points[s][k], &want.points[s][k]) <= 2,
                "{pair:?} {p:?}: point {s} {k}: {} against {}",
                got.points[s][k],
                want.points[s][k].to_f64().unwrap()
            );
            assert!(
                ulps(got.weights[s][k], &want.weights[s][k]) <= 2,
                "{pair:?} {p:?}: weight {s} {k}: {} against {}",
                got.weights[s][k],
                want.weights[s][k].to_f64().unwrap()
            );
        }
    }
    true
}

/// Four points on a coarse grid (so that coplanar, collinear, parallel and coincident cases
/// are common), scaled by `scale` and moved by `offset`.
fn grid_points(rng: &mut Rng, grid: u64, scale: f64, offset: f64) -> [Point; 4] {
    let mut c = || (rng.below(grid + 1) as f64 / grid as f64 - 0.5) * scale + offset;
    [
        [c(), c(), c()],
        [c(), c(), c()],
        [c(), c(), c()],
        [c(), c(), c()],
    ]
}

#[test]
fn every_feature_and_value_is_the_oracles() {
    let mut rng = Rng::new(0x5eed_c105);
    let mut within = 0;
    let mut seen = std::collections::HashSet::new();
    for case in 0..3000 {
        let grid = [2, 3, 4, 8, 1 << 20][case % 5];
        let p = grid_points(&mut rng, grid, 1.0, 0.0);
        for pair in [Primitive::VertexFace, Primitive::EdgeEdge] {
            let d = [0.0, 0.1, 0.3, 0.5, 2.0][rng.below(5) as usize];
            if check(pair, &p, d) {
                within += 1;
                seen.insert((
                    pair == Primitive::VertexFace,
                    nearest(pair, &p, d).unwrap().features,
                ));
            }
        }
    }
    assert!(within > 1000, "{within}");
    // Every feature of both pairs was met: 7 vertex-face, 4 + 4 + 1 edge-edge.
    assert!(seen.len() >= 15, "{seen:?}");
}

#[test]
fn extreme_scales_and_far_from_the_origin() {
    let mut rng = Rng::new(0xfa7_0ff);
    for case in 0..600 {
        let (scale, offset) = [
            (1e-300, 0.0),
            (1e300, 0.0),
            (1.0, 1e9),
            (1e-6, 1e6),
            (1e150, -1e151),
            (3e-310, 0.0),
        ][case % 6];
        let grid = [3, 1 << 10, 1 << 30][case % 3];
        let p = grid_points(&mut rng, grid, scale, offset);
        for pair in [Primitive::VertexFace, Primitive::EdgeEdge] {
            for d in [0.0, 0.3 * scale, 2.0 * scale] {
                check(pair, &p, d);
            }
        }
    }
}

#[test]
fn touching_is_within_zero() {
    // A vertex on an edge, an edge through a triangle's corner, crossing edges.
    let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let on_edge = [[0.5, 0.5, 0.0], t[0], t[1], t[2]];
    let c = nearest(Primitive::VertexFace, &on_edge, 0.0).unwrap();
    assert_eq!(c.features, [Feature::Vertex0, Feature::Edge12]);
    assert_eq!(c.distance, 0.0);
    assert_eq!(c.weights[1], [0.0, 0.5, 0.5]);
    let crossing = [
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let c = nearest(Primitive::EdgeEdge, &crossing, 0.0).unwrap();
    assert_eq!(c.features, [Feature::Edge01, Feature::Edge01]);
    assert_eq!(c.points, [[0.5, 0.5, 0.0]; 2]);
    // Parallel overlapping edges: the first end in the documented order, a0 against b.
    let parallel = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [3.0, 1.0, 0.0],
    ];
    let c = nearest(Primitive::EdgeEdge, &parallel, 1.0).unwrap();
    assert_eq!(c.features, [Feature::Vertex1, Feature::Edge01]);
    assert_eq!(c.distance, 1.0);
    assert_eq!(c.points, [[2.0, 0.0, 0.0], [2.0, 1.0, 0.0]]);
    assert!(nearest(Primitive::EdgeEdge, &parallel, 1.0f64.next_down()).is_none());
}

#[test]
fn bad_inputs_are_named_and_refused() {
    use crate::Error;
    use crate::exact::{edge_edge_nearest, vertex_face_nearest};
    let mut p = [[0.0; 3]; 4];
    p[2][1] = f64::NAN;
    match vertex_face_nearest(&p, 1.0) {
        Err(Error::NonFiniteCoordinate {
            vertex: 2, axis: 1, ..
        }) => {}
        other => panic!("{other:?}"),
    }
    for d in [-1.0, f64::NAN, f64::INFINITY] {
        let e = edge_edge_nearest(&[[0.0; 3]; 4], d).unwrap_err();
        assert!(matches!(e, Error::InvalidDistance { .. }), "{e}");
    }
    // Coincident edges are at distance 0, reported at a0.
    let n = edge_edge_nearest(&[[0.0; 3]; 4], 0.0).unwrap().unwrap();
    assert_eq!((n.features, n.distance), ([Feature::Vertex0; 2], 0.0));
}

/// Four points, each coordinate uniform in `offset +- scale / 2`.
fn random_points(rng: &mut Rng, scale: f64, offset: f64) -> [Point; 4] {
    std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-0.5, 0.5) * scale + offset))
}

#[test]
fn the_filter_never_rejects_at_the_exact_distance() {
    // d the least double at or beyond the exact distance, and the double below: the first is
    // within, the second not, and the floating-point filter must leave both to the exact test.
    let mut rng = Rng::new(0xf11_7e5);
    for case in 0..crate::fixtures::cases(500, 2000) {
        let (scale, offset) = [(1.0, 0.0), (1e-200, 0.0), (1e200, 1e201), (1.0, 1e12)][case % 4];
        let p = random_points(&mut rng, scale, offset);
        for pair in [Primitive::VertexFace, Primitive::EdgeEdge] {
            let min = oracle(pair, &p).iter().map(Cand::squared).min().unwrap();
            // Within a unit of the root, then stepped to the boundary.
            let mut d = sqrt_rational(&min);
            while q(d) * q(d) < min {
                d = d.next_up();
            }
            while d > 0.0 && q(d.next_down()) * q(d.next_down()) >= min {
                d = d.next_down();
            }
            assert!(check(pair, &p, d), "{pair:?} {p:?} at {d}");
            if d > 0.0 {
                assert!(!check(pair, &p, d.next_down()), "{pair:?} {p:?}");
            }
        }
    }
}

#[test]
fn the_walks_lower_bound_is_never_above_the_exact_distance() {
    // The point-triangle bound a walk drops triangles by: at every scale (1e-160 is where the
    // squared direction would be subnormal without its scaling), never above the exact
    // distance, and dropping a triangle only beyond the reach; nearly tight on most triangles.
    let mut rng = Rng::new(0x10_3e7b);
    let mut tight = 0;
    let cases = crate::fixtures::cases(1000, 5000);
    for case in 0..cases {
        let (scale, offset) = [
            (1.0, 0.0),
            (1e-160, 0.0),
            (1e-300, 0.0),
            (1e200, 1e201),
            (1.0, 1e12),
        ][case % 5];
        let p = random_points(&mut rng, scale, offset);
        let min = oracle(Primitive::VertexFace, &p)
            .iter()
            .map(Cand::squared)
            .min()
            .unwrap();
        let exact = sqrt_rational(&min);
        let near = exact * (1.0 - 1e-9);
        for reach in [
            0.0,
            exact * 0.5,
            near,
            exact.next_down(),
            exact,
            f64::INFINITY,
        ] {
            match filter::point_triangle_within(&p[0], &p[1], &p[2], &p[3], reach) {
                None => {
                    assert!(q(reach) * q(reach) < min, "{p:?} dropped within {reach}");
                    tight += usize::from(reach == near && case % 5 < 2);
                }
                Some((_, lower)) => {
                    assert!(q(lower) * q(lower) <= min, "{p:?}: {lower} above {exact}")
                }
            }
        }
    }
    // Tight where the estimate is good: at unit scale and at 1e-160 (there its products
    // underflow, so its point is rough); the others are checked for safety only.
    assert!(
        tight * 5 >= cases,
        "the bound was tight on {tight} of {cases}"
    );
}

#[test]
fn the_corner_shortcut_claims_only_pairs_within() {
    // d just below the least distance between corners of the two primitives: the shortcut
    // must not claim the pair; a little beyond it, it should.
    let mut rng = Rng::new(0x0510_7c07);
    let mut told = 0;
    for case in 0..2000 {
        let (scale, offset) = [(1.0, 0.0), (1e-130, 0.0), (1e150, 1e151), (1.0, 1e12)][case % 4];
        let p = random_points(&mut rng, scale, offset);
        for pair in [Primitive::VertexFace, Primitive::EdgeEdge] {
            let split = pair.split();
            let min = (0..split)
                .flat_map(|i| (split..4).map(move |j| (i, j)))
                .map(|(i, j)| {
                    let x = qsub(&qv(&p[i]), &qv(&p[j]));
                    qdot(&x, &x)
                })
                .min()
                .unwrap();
            let mut d = sqrt_rational(&min);
            while d > 0.0 && q(d) * q(d) >= min {
                d = d.next_down();
            }
            assert!(
                !filter::certainly_within(pair, &p, d),
                "{pair:?} {p:?} at {d}"
            );
            if filter::certainly_within(pair, &p, d * (1.0 + 1e-12)) {
                told += 1;
            }
        }
    }
    // Not vacuous: where no underflow or overflow intervenes, pairs just beyond are told.
    assert!(told >= 1500, "{told}");
    // Corners farther apart than a huge d, whose squares overflow, are not claimed.
    let far = [
        [0.0; 3],
        [1e250, 0.0, 0.0],
        [1e250, 1.0, 0.0],
        [1e250, 0.0, 1.0],
    ];
    assert!(!filter::certainly_within(
        Primitive::VertexFace,
        &far,
        1e200
    ));
}

/// Every polynomial the decisions sign stays within what the bound of [`Permanent`] requires:
/// at most its roundings on the longest path and its degree, on every path (corners, edges,
/// interiors, flat triangles, parallel and overlapping segments).
#[test]
fn decisions_stay_within_the_permanents_limits() {
    use crate::geometry::chains::Traced;
    use crate::geometry::permanent::{MOST_DEGREE, MOST_ROUNDINGS};
    let mut rng = Rng::new(0x7aced);
    Traced::<Ball>::most_signed();
    let mut decided = 0;
    for case in 0..4000 {
        let grid = [2, 3, 4, 8, 1 << 20][case % 5];
        let p = grid_points(&mut rng, grid, 1.0, 0.0);
        let mut v = [0.0; 13];
        for (k, x) in p.iter().flatten().enumerate() {
            v[k] = *x;
        }
        v[12] = [0.0, 0.1, 0.5, 2.0][rng.below(4) as usize];
        for pair in [Primitive::VertexFace, Primitive::EdgeEdge] {
            let inputs = v.map(|x| Traced::input(Ball::point(x)));
            if decide(pair, &inputs, &Traced::constant(Ball::point(1.0)), false).is_some() {
                decided += 1;
            }
        }
    }
    let (roundings, degree) = Traced::<Ball>::most_signed();
    assert!(decided > 5000, "{decided}");
    assert!(roundings <= MOST_ROUNDINGS, "{roundings} roundings");
    assert_eq!(degree, MOST_DEGREE, "the highest degree signed");
}

#[test]
fn a_decision_keeps_its_choice_in_one_byte() {
    let mut all = vec![Choice::FaceInterior, Choice::BothInside];
    for k in 0..3 {
        all.extend([Choice::FaceEdge(k), Choice::FaceCorner(k)]);
    }
    for p in 0..4 {
        all.extend([None, Some(0), Some(1)].map(|on| Choice::End { p, on }));
    }
    let mut bytes = std::collections::HashSet::new();
    for c in all {
        let d = Decided::of(c);
        assert_eq!(d.choice(), c, "{d:?}");
        assert!(bytes.insert(d.0), "{c:?} shares its byte");
    }
}
