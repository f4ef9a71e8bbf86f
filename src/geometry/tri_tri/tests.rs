//! Tests of the exact triangle-triangle test against the rational oracle and constructed cases.

use super::*;
use proptest::prelude::*;

fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Triangle {
    [a, b, c]
}

#[test]
fn the_filter_settles_clear_pairs_and_not_touching_ones() {
    let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let through = tri([0.2, 0.3, -1.0], [0.25, 0.2, 1.0], [0.9, 0.8, 0.5]);
    assert_eq!(settled_by_filter(&t, &through), (true, true));
    // A corner of one exactly on the face of the other (the plane x + y + z = 1), not a
    // shared corner: the plane side is exactly zero, which only exact arithmetic can tell.
    let slanted = tri([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let touching = tri([0.25, 0.25, 0.5], [1.0, 1.0, 1.0], [1.0, 0.5, 1.0]);
    assert_eq!(settled_by_filter(&slanted, &touching), (true, false));
    // Shared corners are settled combinatorially.
    let fan = tri([0.0, 0.0, 0.0], [0.0, -1.0, 0.5], [-1.0, 0.0, 0.5]);
    assert_eq!(settled_by_filter(&t, &fan), (true, true));
    let huge = tri([1e100, 0.0, 0.0], [1e100, 1.0, 0.0], [1e100, 0.0, 1.0]);
    assert!(!settled_by_filter(&t, &huge).1);
    // The answer is always the exact test's, settled or not.
    let mut rng = crate::fixtures::Rng::new(3);
    let mut settled = 0;
    for _ in 0..5000 {
        let mut corner = || [0; 3].map(|_| (rng.below(5) as f64 - 2.0) * 0.5);
        let (a, b) = (
            [corner(), corner(), corner()],
            [corner(), corner(), corner()],
        );
        let (hit, by_filter) = settled_by_filter(&a, &b);
        assert_eq!(hit, triangles_intersect(&a, &b), "{a:?} {b:?}");
        settled += usize::from(by_filter);
    }
    // Small integer grids are full of exact contacts; many, not all, are settled cheaply.
    assert!((500..5000).contains(&settled), "{settled}");
}

/// Asserts the expected answer under every vertex order and argument order, and through both
/// predicate implementations.
fn check(t1: Triangle, t2: Triangle, expected: bool) {
    let perms = crate::geometry::CORNER_ORDERS;
    for p in perms {
        for q in perms {
            let a = [t1[p[0]], t1[p[1]], t1[p[2]]];
            let b = [t2[q[0]], t2[q[1]], t2[q[2]]];
            assert_eq!(triangles_intersect(&a, &b), expected, "{a:?} {b:?}");
            assert_eq!(triangles_intersect(&b, &a), expected, "{b:?} {a:?}");
            assert_eq!(intersect::<BigExact>(&a, &b), expected, "big {a:?} {b:?}");
        }
    }
}

const O: [f64; 3] = [0.0, 0.0, 0.0];
const X: [f64; 3] = [1.0, 0.0, 0.0];
const Y: [f64; 3] = [0.0, 1.0, 0.0];
const Z: [f64; 3] = [0.0, 0.0, 1.0];

#[test]
fn shared_vertex_touches() {
    check(
        tri(O, X, Y),
        tri(O, [-1.0, 0.0, 0.5], [0.0, -1.0, 1.0]),
        true,
    );
}

#[test]
fn shared_edge_touches() {
    check(tri(O, X, Y), tri(O, X, [0.0, -1.0, 0.5]), true);
    check(tri(O, X, Y), tri(O, X, Z), true);
}

#[test]
fn coplanar_overlap_and_disjoint() {
    check(
        tri(O, X, Y),
        tri([0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0]),
        true,
    );
    // One inside the other.
    check(
        tri(O, [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]),
        tri([0.5, 0.5, 0.0], [1.0, 0.5, 0.0], [0.5, 1.0, 0.0]),
        true,
    );
    // Star of David: edges cross, no vertex inside.
    check(
        tri([0.0, 2.0, 0.0], [-1.732, -1.0, 0.0], [1.732, -1.0, 0.0]),
        tri([0.0, -2.0, 0.0], [1.732, 1.0, 0.0], [-1.732, 1.0, 0.0]),
        true,
    );
    check(
        tri(O, X, Y),
        tri([0.6, 0.6, 0.0], [2.0, 0.6, 0.0], [0.6, 2.0, 0.0]),
        false,
    );
    // Touching along the hypotenuse at a single point.
    check(
        tri(O, X, Y),
        tri([0.5, 0.5, 0.0], [1.0, 1.0, 0.0], [0.5, 2.0, 0.0]),
        true,
    );
    // Coplanar, parallel edges one ulp apart.
    let e = f64::EPSILON;
    check(
        tri(O, X, Y),
        tri([0.0, -e, 0.0], [1.0, -e, 0.0], [0.5, -1.0, 0.0]),
        false,
    );
    check(
        tri(O, X, Y),
        tri([0.0, 0.0, 0.0], [1.0, -e, 0.0], [0.5, -1.0, 0.0]),
        true,
    );
}

#[test]
fn point_on_face() {
    check(
        tri(O, [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
        tri([0.5, 0.5, 0.0], [0.5, 0.5, 1.0], [1.0, 0.0, 1.0]),
        true,
    );
    check(
        tri(O, [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
        tri([0.5, 0.5, 1e-300], [0.5, 0.5, 1.0], [1.0, 0.0, 1.0]),
        false,
    );
}

#[test]
fn edge_through_edge() {
    // Edge (-1,0.5,0)-(1,0.5,0)... of a vertical triangle crossing the edge x = 0 of the other.
    check(
        tri(O, [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]),
        tri([-1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, -1.0]),
        true,
    );
    // Shifted by a tiny amount below: the edges miss.
    check(
        tri(O, [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]),
        tri([-1.0, 1.0, -1e-17], [1.0, 1.0, -1e-17], [0.0, 1.0, -1.0]),
        false,
    );
}

#[test]
fn piercing_and_separated() {
    check(
        tri(O, [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
        tri([0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [3.0, 3.0, 0.5]),
        true,
    );
    check(
        tri(O, X, Y),
        tri([0.0, 0.0, 0.1], [1.0, 0.0, 0.2], [0.0, 1.0, 0.3]),
        false,
    );
    // The other's plane is crossed, but outside the triangle.
    check(
        tri(O, X, Y),
        tri([2.0, 2.0, -1.0], [2.0, 2.0, 1.0], [3.0, 2.0, 0.0]),
        false,
    );
}

#[test]
fn segments_and_points() {
    let seg = tri([0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.5]);
    check(
        tri([-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]),
        seg,
        true,
    );
    check(
        tri([1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [1.0, 1.0, 0.0]),
        seg,
        false,
    );
    // Segment lying in the plane, crossing an edge.
    check(
        tri(O, X, Y),
        tri([-1.0, 0.5, 0.0], [0.25, 0.5, 0.0], [-0.5, 0.5, 0.0]),
        true,
    );
    check(
        tri(O, X, Y),
        tri([-1.0, 0.5, 0.0], [-0.25, 0.5, 0.0], [-0.5, 0.5, 0.0]),
        false,
    );
    // Repeated indices: a point.
    let p = [0.25, 0.25, 0.0];
    check(tri(O, X, Y), tri(p, p, p), true);
    let q = [0.25, 0.25, 1e-200];
    check(tri(O, X, Y), tri(q, q, q), false);
    check(tri(p, p, p), tri(p, p, p), true);
    check(tri(p, p, p), tri(q, q, q), false);
    // Segment against segment: crossing, touching at endpoints, parallel, skew.
    let s1 = tri([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    check(
        s1,
        tri([0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]),
        true,
    );
    check(
        s1,
        tri([1.0, 0.0, 0.0], [2.0, 1.0, 0.0], [2.0, 1.0, 0.0]),
        true,
    );
    check(
        s1,
        tri([-1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]),
        false,
    );
    check(
        s1,
        tri([0.0, -1.0, 1.0], [0.0, 1.0, 1.0], [0.0, 1.0, 1.0]),
        false,
    );
    // Collinear overlapping and collinear disjoint.
    check(
        s1,
        tri([0.5, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 0.0, 0.0]),
        true,
    );
    check(
        s1,
        tri([1.5, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 0.0, 0.0]),
        false,
    );
    // Point on a segment, point off a segment.
    check(
        s1,
        tri([0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.0, 0.0]),
        true,
    );
    check(
        s1,
        tri([0.5, 1e-300, 0.0], [0.5, 1e-300, 0.0], [0.5, 1e-300, 0.0]),
        false,
    );
}

#[test]
fn extreme_scales() {
    for k in [-1000, -500, -200, 0, 200, 500, 1000] {
        let s = 2f64.powi(k);
        let sc = |t: Triangle| t.map(|p| p.map(|x| x * s));
        check(
            sc(tri(O, X, Y)),
            sc(tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [1.0, 1.0, 0.0])),
            true,
        );
        check(
            sc(tri(O, X, Y)),
            sc(tri([0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5])),
            false,
        );
        check(
            sc(tri(O, X, Y)),
            sc(tri([0.5, 0.5, 0.0], [1.0, 1.0, 0.0], [0.5, 2.0, 0.0])),
            true,
        );
    }
    // Far from the origin: touching at a single point of a huge translate.
    let t = 1e15;
    let sh = |p: [f64; 3]| [p[0] + t, p[1] + t, p[2] + t];
    check(
        tri(sh(O), sh(X), sh(Y)),
        tri(
            sh([0.5, 0.5, 0.0]),
            sh([0.5, 0.5, 1.0]),
            sh([1.0, 1.0, 1.0]),
        ),
        true,
    );
}

/// Independent oracle for integer coordinates: the triangles are disjoint iff the origin is not
/// in the convex hull of the nine differences `p - q`, iff the direction from the origin to the
/// closest point of that hull separates strictly. That direction is the origin's projection on
/// the affine hull of one, two or three of the differences, so trying all of them is complete.
fn oracle(t1: &[[i64; 3]; 3], t2: &[[i64; 3]; 3]) -> bool {
    type V = [i128; 3];
    let sub = |a: V, b: V| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: V, b: V| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: V, b: V| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let scale = |k: i128, a: V| a.map(|x| x * k);
    let mut s: Vec<V> = Vec::new();
    for p in t1 {
        for q in t2 {
            s.push([0, 1, 2].map(|i| (p[i] - q[i]) as i128));
        }
    }
    let separates = |d: V| s.iter().all(|&x| dot(d, x) > 0);
    let n = s.len();
    for i in 0..n {
        if separates(s[i]) {
            return false;
        }
        for j in i + 1..n {
            let e = sub(s[j], s[i]);
            let d = sub(scale(dot(e, e), s[i]), scale(dot(s[i], e), e));
            if separates(d) {
                return false;
            }
            for k in j + 1..n {
                let nrm = cross(e, sub(s[k], s[i]));
                if separates(scale(dot(nrm, s[i]), nrm)) {
                    return false;
                }
            }
        }
    }
    true
}

fn small_int_triangle(r: i64) -> impl Strategy<Value = [[i64; 3]; 3]> {
    [
        [-r..=r, -r..=r, -r..=r],
        [-r..=r, -r..=r, -r..=r],
        [-r..=r, -r..=r, -r..=r],
    ]
}

fn to_f(t: &[[i64; 3]; 3]) -> Triangle {
    t.map(|p| p.map(|x| x as f64))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Tiny coordinate range: many coplanar, touching and degenerate configurations.
    #[test]
    fn agrees_with_separating_direction_oracle_small(a in small_int_triangle(2), b in small_int_triangle(2)) {
        let expected = oracle(&a, &b);
        prop_assert_eq!(triangles_intersect(&to_f(&a), &to_f(&b)), expected, "{:?} {:?}", a, b);
        prop_assert_eq!(prepared_both_ways(&to_f(&a), &to_f(&b)), expected, "prepared {:?} {:?}", a, b);
    }

    #[test]
    fn agrees_with_separating_direction_oracle(a in small_int_triangle(40), b in small_int_triangle(40)) {
        let expected = oracle(&a, &b);
        prop_assert_eq!(triangles_intersect(&to_f(&a), &to_f(&b)), expected, "{:?} {:?}", a, b);
        prop_assert_eq!(prepared_both_ways(&to_f(&a), &to_f(&b)), expected, "prepared {:?} {:?}", a, b);
    }

    /// Same with one triangle forced into the other's plane z = 0 (coplanar cases).
    #[test]
    fn agrees_with_oracle_coplanar(a in small_int_triangle(3), b in small_int_triangle(3)) {
        let flat = |t: [[i64; 3]; 3]| t.map(|p| [p[0], p[1], 0]);
        let (a, b) = (flat(a), flat(b));
        let expected = oracle(&a, &b);
        prop_assert_eq!(triangles_intersect(&to_f(&a), &to_f(&b)), expected, "{:?} {:?}", a, b);
        prop_assert_eq!(prepared_both_ways(&to_f(&a), &to_f(&b)), expected, "prepared {:?} {:?}", a, b);
    }
}

/// The prepared test's answer, which must not depend on the argument order nor on what the
/// prepared triangles kept from earlier pairs (each is asked twice, in both orders).
fn prepared_both_ways(a: &Triangle, b: &Triangle) -> bool {
    let (pa, pb) = (PreparedTriangle::new(*a), PreparedTriangle::new(*b));
    let r = prepared_triangles_intersect(&pa, &pb);
    assert_eq!(prepared_triangles_intersect(&pb, &pa), r, "{a:?} {b:?}");
    assert_eq!(prepared_triangles_intersect(&pa, &pb), r, "{a:?} {b:?}");
    r
}

fn real_triangle() -> impl Strategy<Value = Triangle> {
    let c = || prop_oneof![-2.0f64..2.0, (-4i32..4).prop_map(|x| f64::from(x) * 0.5)];
    [[c(), c(), c()], [c(), c(), c()], [c(), c(), c()]]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn symmetric_and_order_invariant(a in real_triangle(), b in real_triangle()) {
        let r = triangles_intersect(&a, &b);
        prop_assert_eq!(triangles_intersect(&b, &a), r);
        prop_assert_eq!(triangles_intersect(&[a[1], a[2], a[0]], &[b[2], b[1], b[0]]), r);
        prop_assert_eq!(intersect::<BigExact>(&a, &b), r);
        prop_assert_eq!(prepared_both_ways(&a, &b), r);
    }

    /// The interval comparison against the edge-by-edge method it replaces for proper,
    /// non-coplanar pairs, on real coordinates (the oracle above needs integers).
    #[test]
    fn interval_method_agrees_with_edge_method(a in real_triangle(), offsets in real_triangle()) {
        // b around a's first vertex, so that most pairs cross each other's planes.
        let b = offsets.map(|o| [a[0][0] + o[0] * 0.5, a[0][1] + o[1] * 0.5, a[0][2] + o[2] * 0.5]);
        let s2 = Adaptive::plane_sides(&a, &b);
        let s1 = Adaptive::plane_sides(&b, &a);
        if strictly_one_side(s1) || strictly_one_side(s2) || all_zero(s1) || all_zero(s2) {
            return Ok(());
        }
        let by_edges = edges_meet_triangle::<Adaptive>(&a, s1, &b, None) || edges_meet_triangle::<Adaptive>(&b, s2, &a, None);
        prop_assert_eq!(crossing_intervals_meet::<Adaptive>(&a, s1, &b, s2), by_edges);
    }

    /// The coplanar test against the edge-by-edge method, on real coordinates in z = 0 and
    /// in a tilted plane through the origin (exactly coplanar: z = x + y with small integers).
    #[test]
    fn coplanar_method_agrees_with_edge_method(a in real_triangle(), b in real_triangle(), tilt in any::<bool>()) {
        let flat = |t: Triangle| t.map(|p| {
            let (x, y) = ((p[0] * 4.0).round(), (p[1] * 4.0).round());
            if tilt { [x, y, x + y] } else { [p[0], p[1], 0.0] }
        });
        let (a, b) = (flat(a), flat(b));
        if collinear::<Adaptive>(&a) || collinear::<Adaptive>(&b) {
            return Ok(());
        }
        let zero = [0, 0, 0];
        let by_edges = edges_meet_triangle::<Adaptive>(&a, zero, &b, None) || edges_meet_triangle::<Adaptive>(&b, zero, &a, None);
        let axis = projection::<Adaptive>(&a).expect("proper");
        prop_assert_eq!(coplanar_meet::<Adaptive, _>(&a, axis, &Bare(&b, PhantomData)), by_edges);
        prop_assert_eq!(coplanar_meet::<Adaptive, _>(&a, axis, &PreparedTriangle::new(b)), by_edges);
        prop_assert_eq!(triangles_intersect(&a, &b), by_edges);
    }

    #[test]
    fn filtered_plane_sides_are_exact(a in real_triangle(), b in real_triangle(), k in -30i32..30) {
        let s = 2f64.powi(k);
        let (a, b) = (a.map(|p| p.map(|x| x * s)), b.map(|p| p.map(|x| x * s)));
        prop_assert_eq!(Adaptive::plane_sides(&a, &b), b.map(|p| BigExact::orient3d(&a[0], &a[1], &a[2], &p)));
    }

    #[test]
    fn invariant_under_exact_transformations(
        a in real_triangle(),
        b in real_triangle(),
        k in -60i32..60,
        perm in 0usize..6,
        shift in prop::array::uniform3(-8i32..8),
    ) {
        let r = triangles_intersect(&a, &b);
        let axes = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]][perm];
        let s = 2f64.powi(k);
        let f = |t: &Triangle| t.map(|p| [p[axes[0]] * s, p[axes[1]] * s, p[axes[2]] * s]);
        prop_assert_eq!(triangles_intersect(&f(&a), &f(&b)), r);
        // A translation is only an exact transformation when no sum loses bits: check each
        // sum with the exact rounding error of TwoSum before comparing.
        let t = shift.map(f64::from);
        let g = |tri: &Triangle| tri.map(|p| [p[0] + t[0], p[1] + t[1], p[2] + t[2]]);
        let sum_is_exact = |a: f64, b: f64| {
            let s = a + b;
            let bb = s - a;
            (a - (s - bb)) + (b - bb) == 0.0
        };
        let exact = [a, b].iter().all(|tri| tri.iter().all(|p| (0..3).all(|i| sum_is_exact(p[i], t[i]))));
        if exact {
            prop_assert_eq!(triangles_intersect(&g(&a), &g(&b)), r);
        }
    }
}
