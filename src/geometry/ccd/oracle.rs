//! The reference answer of the continuous tests, in exact rational arithmetic: slow, simple,
//! and exact for every finite double input. What the filtered tests are checked against.
//!
//! The truth of a contact condition is constant between consecutive roots of its polynomials, and
//! the set of contact times is closed; so the earliest contact, when there is one, is 0 or a
//! root of one of them. Every such candidate is tried, in increasing order.

use super::condition::{Moving, edge_edge, moving, vertex_face};
use super::poly::Poly;
#[cfg(test)]
use super::poly::floor_f64;
use super::rational::earliest_of_every_candidate;
#[cfg(test)]
use num_rational::BigRational;

/// Does the point `start[0] → end[0]` meet the closed triangle `start[1..4] → end[1..4]` for
/// some t in [0, 1], and when first (rounded down)?
pub(crate) fn vertex_face_toi(start: &[[f64; 3]; 4], end: &[[f64; 3]; 4]) -> Option<f64> {
    let m: Vec<Moving<Poly>> = (0..4).map(|i| moving(&start[i], &end[i])).collect();
    earliest_of_every_candidate(
        &vertex_face(&m[0], [&m[1], &m[2], &m[3]]),
        &num_traits::Zero::zero(),
        &num_traits::One::one(),
    )
}

/// Do the closed segments `start[0..2] → end[0..2]` and `start[2..4] → end[2..4]` share a point
/// for some t in [0, 1], and when first (rounded down)?
pub(crate) fn edge_edge_toi(start: &[[f64; 3]; 4], end: &[[f64; 3]; 4]) -> Option<f64> {
    let m: Vec<Moving<Poly>> = (0..4).map(|i| moving(&start[i], &end[i])).collect();
    earliest_of_every_candidate(
        &edge_edge([&m[0], &m[1]], [&m[2], &m[3]]),
        &num_traits::Zero::zero(),
        &num_traits::One::one(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::tri_tri::triangles_intersect;

    type Prim = [[f64; 3]; 4];

    #[test]
    fn a_point_through_a_triangle() {
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let s = [[0.25, 0.25, 1.0], tri[0], tri[1], tri[2]];
        let e = [[0.25, 0.25, -1.0], tri[0], tri[1], tri[2]];
        assert_eq!(vertex_face_toi(&s, &e), Some(0.5));
        // Beside it: never.
        let s2 = [[2.0, 2.0, 1.0], tri[0], tri[1], tri[2]];
        let e2 = [[2.0, 2.0, -1.0], tri[0], tri[1], tri[2]];
        assert_eq!(vertex_face_toi(&s2, &e2), None);
        // Touching only at the end, only at the start.
        let e3 = [[0.25, 0.25, 0.0], tri[0], tri[1], tri[2]];
        assert_eq!(vertex_face_toi(&s, &e3), Some(1.0));
        assert_eq!(vertex_face_toi(&e3, &s), Some(0.0));
        // Through a corner exactly, and a hair beside it.
        let s4 = [[1.0, 0.0, 1.0], tri[0], tri[1], tri[2]];
        let e4 = [[1.0, 0.0, -3.0], tri[0], tri[1], tri[2]];
        assert_eq!(vertex_face_toi(&s4, &e4), Some(0.25));
        let s5 = [[1.0f64.next_up(), 0.0, 1.0], tri[0], tri[1], tri[2]];
        let e5 = [[1.0f64.next_up(), 0.0, -3.0], tri[0], tri[1], tri[2]];
        assert_eq!(vertex_face_toi(&s5, &e5), None);
    }

    #[test]
    fn coplanar_motion_enters_through_an_edge() {
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let s = [[0.5, -1.0, 0.0], tri[0], tri[1], tri[2]];
        let e = [[0.5, 1.0, 0.0], tri[0], tri[1], tri[2]];
        assert_eq!(vertex_face_toi(&s, &e), Some(0.5));
        // Coplanar and sliding past the hypotenuse's far side: never.
        let s = [[2.0, -1.0, 0.0], tri[0], tri[1], tri[2]];
        let e = [[2.0, 1.0, 0.0], tri[0], tri[1], tri[2]];
        assert_eq!(vertex_face_toi(&s, &e), None);
    }

    #[test]
    fn a_collapsing_triangle_is_the_segment_it_covers() {
        // C sweeps across A: the triangle is the segment AB at t = 1/2, and the point, on the
        // line AB beyond B's side, meets it only if it lies on AB then.
        let a = [0.0, 0.0, 0.0];
        let b = [1.0, 0.0, 0.0];
        let s = [[0.5, 0.0, 0.0], a, b, [0.0, 1.0, 0.0]];
        let e = [[0.5, 0.0, 0.0], a, b, [0.0, -1.0, 0.0]];
        assert_eq!(vertex_face_toi(&s, &e), Some(0.0)); // on edge AB all along
        let s = [[0.5, 0.0, 1.0], a, b, [0.0, 1.0, 0.0]];
        let e = [[0.5, 0.0, -1.0], a, b, [0.0, -1.0, 0.0]];
        assert_eq!(vertex_face_toi(&s, &e), Some(0.5));
        // A triangle that is a point all along, and a point passing through it.
        let p = [0.5, 0.5, 0.5];
        let s = [[0.0, 0.0, 0.0], p, p, p];
        let e = [[1.0, 1.0, 1.0], p, p, p];
        assert_eq!(vertex_face_toi(&s, &e), Some(0.5));
        let e = [[1.0, 1.0, 1.0f64.next_up()], p, p, p];
        assert_eq!(vertex_face_toi(&s, &e), None);
    }

    #[test]
    fn edges_crossing_parallel_collinear_and_degenerate() {
        let a0 = [-1.0, 0.0, 0.0];
        let a1 = [1.0, 0.0, 0.0];
        let s = [a0, a1, [0.0, -1.0, 1.0], [0.0, 1.0, 1.0]];
        let e = [a0, a1, [0.0, -1.0, -1.0], [0.0, 1.0, -1.0]];
        assert_eq!(edge_edge_toi(&s, &e), Some(0.5));
        // Parallel, a unit apart all along.
        let s = [a0, a1, [-1.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        assert_eq!(edge_edge_toi(&s, &s), None);
        // Collinear, sliding into each other: b's near end reaches a's at t = 1/5.
        let (s, e) = crate::fixtures::ccd_judge::COLLINEAR_AT_A_FIFTH;
        let fifth = BigRational::new(1.into(), 5.into());
        assert_eq!(edge_edge_toi(&s, &e), Some(floor_f64(&fifth)));
        // Two zero-length edges meeting at t = 3/4.
        let s = [[0.0; 3], [0.0; 3], [3.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
        let e = [[0.0; 3], [0.0; 3], [-1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]];
        assert_eq!(edge_edge_toi(&s, &e), Some(0.75));
    }

    #[test]
    fn an_irrational_time_is_rounded_down() {
        let (s, e) = crate::fixtures::ccd_judge::IRRATIONAL_SWEEP;
        let toi = vertex_face_toi(&s, &e).expect("the plane sweeps through the point");
        // Independently: where the floating-point orientation changes sign, by bisection.
        let orient = |t: f64| {
            let at = |i: usize| [0, 1, 2].map(|k| s[i][k] + t * (e[i][k] - s[i][k]));
            crate::exact::orient3d(&at(1), &at(2), &at(3), &at(0))
        };
        let (mut lo, mut hi) = (0.0, 1.0);
        assert!(orient(lo) != orient(hi));
        for _ in 0..200 {
            let m = 0.5 * (lo + hi);
            if orient(m) == orient(lo) {
                lo = m
            } else {
                hi = m
            }
        }
        assert!((toi - lo).abs() < 1e-12, "{toi} {lo}");
        assert!(toi > 0.1 && toi < 0.9);
    }

    /// Dyadic coordinates and dyadic times, so positions at those times are exact doubles and
    /// the static exact test decides contact there: a contact seen at time t means the oracle
    /// reports one no later than t.
    #[test]
    fn never_later_than_a_contact_seen_by_the_static_test() {
        let mut rng = crate::fixtures::Rng::new(0x5eed_cc0d);
        let mut coord = || (rng.next_u64() % 17) as f64 / 8.0 - 1.0;
        let (mut hits, mut misses) = (0, 0);
        for case in 0..300 {
            let mut s: Prim = [[0.0; 3]; 4];
            let mut e: Prim = [[0.0; 3]; 4];
            for i in 0..4 {
                for k in 0..3 {
                    s[i][k] = coord();
                    e[i][k] = if case % 3 == 0 { s[i][k] } else { coord() };
                }
            }
            // Flatten some cases into the plane z = 0 (coplanar for all t).
            if case % 4 == 1 {
                for i in 0..4 {
                    s[i][2] = 0.0;
                    e[i][2] = 0.0;
                }
            }
            let vf = vertex_face_toi(&s, &e);
            let ee = edge_edge_toi(&s, &e);
            for j in 0..=32 {
                let t = j as f64 / 32.0;
                let mut m = [[0.0; 3]; 4];
                for i in 0..4 {
                    for k in 0..3 {
                        m[i][k] = s[i][k] + t * (e[i][k] - s[i][k]);
                    }
                }
                if triangles_intersect(&[m[0], m[0], m[0]], &[m[1], m[2], m[3]]) {
                    assert!(vf.is_some_and(|x| x <= t), "case {case}: vf {vf:?} at {t}");
                }
                if triangles_intersect(&[m[0], m[1], m[1]], &[m[2], m[3], m[3]]) {
                    assert!(ee.is_some_and(|x| x <= t), "case {case}: ee {ee:?} at {t}");
                }
            }
            if vf.is_some() { hits += 1 } else { misses += 1 }
        }
        assert!(hits > 20 && misses > 20, "{hits} {misses}");
    }

    /// Scaling every coordinate by a power of two, or moving everything by a dyadic offset far
    /// from the origin, changes no coordinate's rounding, so it must change no answer: from
    /// 2^-1000 to 2^1000, and 2^40 away.
    #[test]
    fn answers_do_not_depend_on_scale_or_place() {
        let mut rng = crate::fixtures::Rng::new(0xcc0d_5ca1e);
        let mut coord = || (rng.next_u64() % 9) as f64 / 4.0 - 1.0;
        for case in 0..30 {
            let mut s: Prim = [[0.0; 3]; 4];
            let mut e: Prim = [[0.0; 3]; 4];
            for i in 0..4 {
                for k in 0..3 {
                    s[i][k] = coord();
                    e[i][k] = coord();
                }
            }
            let base = (vertex_face_toi(&s, &e), edge_edge_toi(&s, &e));
            for (scale, shift) in [
                (2f64.powi(-1000), 0.0),
                (2f64.powi(1000), 0.0),
                (1.0, 2f64.powi(40)),
            ] {
                let f = |p: &Prim| p.map(|v| v.map(|x| x * scale + shift));
                let (fs, fe) = (f(&s), f(&e));
                assert_eq!(
                    (vertex_face_toi(&fs, &fe), edge_edge_toi(&fs, &fe)),
                    base,
                    "case {case} x{scale} +{shift}"
                );
            }
        }
    }
}
