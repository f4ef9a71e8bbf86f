//! The curve queries against the independent judge of [`crate::fixtures::curve_judge`] on
//! constructed, random, degenerate and extreme cases; the chaining, the options, the errors and
//! the length gradient (against central differences).

use super::chain::{chain, link, piece};
use super::*;
use crate::fixtures::curve_judge::{World, is_chained, judge};
use crate::fixtures::{MeshData, Rng, icosphere, soup, torus};
use crate::geometry::predicates::Point;
use crate::threads::{Step, at_least_two_threads, shared_count};
use crate::{BuildOptions, Error, Mesh, Pairs, Pose, QueryMode, QueryOptions, collide};
use std::collections::BTreeSet;

fn build(m: &MeshData) -> Mesh {
    Mesh::new(&m.positions, &m.triangles, &BuildOptions::default()).unwrap()
}

fn sphere(subdivisions: u32, scale: f64, at: [f64; 3], seed: u64) -> MeshData {
    let mut m = icosphere(subdivisions);
    m.perturb(0.01, seed).scale(scale).translate(at);
    m
}

/// Curves of `a` and `b`, judged.
fn two_meshes(a: &Mesh, pa: Option<&Pose>, b: &Mesh, pb: Option<&Pose>, oriented: bool) -> Curves {
    let mut pairs = Pairs::new();
    collide(a, pa, b, pb, &QueryOptions::default(), &mut pairs).unwrap();
    let mut curves = Curves::new();
    let stats = intersection_curves(a, pa, b, pb, &QueryOptions::default(), &mut curves).unwrap();
    assert_eq!(stats.pairs as usize, pairs.len());
    judge(
        &curves,
        &World::new(a, pa),
        &World::new(b, pb),
        false,
        pairs.as_slice(),
        oriented,
    );
    curves
}

/// Self curves of `m`, judged (`oriented`: their orientation too).
fn one_mesh(m: &Mesh, oriented: bool) -> Curves {
    let mut pairs = Pairs::new();
    crate::self_collide(m, &QueryOptions::default(), &mut pairs).unwrap();
    let mut curves = Curves::new();
    self_intersection_curves(m, &QueryOptions::default(), &mut curves).unwrap();
    let w = World::new(m, None);
    judge(&curves, &w, &w, true, pairs.as_slice(), oriented);
    curves
}

fn same(x: &Curves, y: &Curves) -> bool {
    x.segments() == y.segments()
        && x.curves() == y.curves()
        && x.degenerate() == y.degenerate()
        && x.result.points == y.result.points
}

#[test]
fn overlapping_spheres_cross_in_closed_curves() {
    for seed in 0..6 {
        let mut rng = Rng::new(seed);
        let offset = [0; 3].map(|_| rng.range(-0.8, 0.8));
        let a = build(&sphere(3, 1.0, [0.0; 3], seed));
        let b = build(&sphere(2, 0.7, offset, seed + 100));
        let curves = two_meshes(&a, None, &b, None, true);
        assert!(!curves.is_empty(), "seed {seed}");
        assert!(curves.degenerate().is_empty());
        assert!(curves.curves().iter().all(|c| c.closed), "seed {seed}");
        for i in 0..curves.curves().len() {
            assert!(curves.curve_length(i) > 0.0);
        }
    }
}

#[test]
fn a_sphere_through_a_torus_at_extreme_scales_and_far_away() {
    for (scale, shift) in [
        (1.0, 0.0),
        (1e-300, 0.0),
        (1e300, 0.0),
        (1.0, 1e9),
        (1e-6, -3e4),
    ] {
        let mut t = torus(1.0, 0.3, 40, 16);
        t.perturb(1e-3, 7).scale(scale).translate([shift; 3]);
        let mut s = icosphere(2);
        s.perturb(1e-3, 8).scale(0.5 * scale).translate([
            1.0 * scale + shift,
            0.1 * scale + shift,
            shift,
        ]);
        let curves = two_meshes(&build(&t), None, &build(&s), None, true);
        assert!(!curves.is_empty() && curves.curves().iter().all(|c| c.closed));
    }
}

#[test]
fn swapped_meshes_give_the_mirrored_curves() {
    let a = build(&sphere(2, 1.0, [0.0; 3], 1));
    let b = build(&sphere(2, 0.8, [0.5, 0.2, 0.1], 2));
    let ab = two_meshes(&a, None, &b, None, true);
    let ba = two_meshes(&b, None, &a, None, true);
    let key = |c: &Curves| {
        let mut v: Vec<_> = c
            .segments()
            .iter()
            .map(|s| {
                let (x, y) = (s.start.map(f64::to_bits), s.end.map(f64::to_bits));
                (s.triangle_a, s.triangle_b, x.min(y), x.max(y))
            })
            .collect();
        v.sort_unstable();
        v
    };
    let mirrored: Vec<_> = key(&ba)
        .into_iter()
        .map(|(x, y, s, e)| (y, x, s, e))
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    assert_eq!(key(&ab), mirrored);
    assert_eq!(ab.curves().len(), ba.curves().len());
}

#[test]
fn posed_meshes_cross_where_their_placed_copies_do() {
    let a = sphere(2, 1.0, [0.0; 3], 3);
    let b = sphere(2, 0.9, [0.0; 3], 4);
    let (ca, sa) = (0.3f64.cos(), 0.3f64.sin());
    let pose_a = Pose::new(
        [[ca, -sa, 0.0], [sa, ca, 0.0], [0.0, 0.0, 1.0]],
        [0.1, 0.0, 0.3],
    )
    .unwrap();
    let pose_b = Pose::new(
        [[1.0, 0.0, 0.0], [0.0, ca, sa], [0.0, -sa, ca]],
        [0.6, 0.2, 0.0],
    )
    .unwrap();
    let place = |m: &MeshData, pose: &Pose| {
        let positions: Vec<f64> = m
            .positions
            .chunks_exact(3)
            .flat_map(|p| pose.transform_point(&[p[0], p[1], p[2]]))
            .collect();
        build(&MeshData {
            positions,
            triangles: m.triangles.clone(),
        })
    };
    let (ma, mb) = (build(&a), build(&b));
    let posed = two_meshes(&ma, Some(&pose_a), &mb, Some(&pose_b), true);
    let placed = two_meshes(&place(&a, &pose_a), None, &place(&b, &pose_b), None, true);
    assert!(!posed.is_empty());
    assert!(same(&posed, &placed));
}

#[test]
fn a_copy_touches_everywhere_and_stays_a_valid_answer() {
    // Identical triangles are coplanar pairs, neighbours across an edge share that edge (a
    // segment lying in both surfaces), neighbours at a vertex meet there only.
    let m = sphere(2, 1.0, [0.0; 3], 5);
    let (a, b) = (build(&m), build(&m));
    let curves = two_meshes(&a, None, &b, None, false);
    let coplanar = curves
        .degenerate()
        .iter()
        .filter(|d| d.kind == DegenerateKind::Coplanar)
        .count();
    assert_eq!(coplanar, m.triangle_count());
    assert!(
        curves
            .degenerate()
            .iter()
            .all(|d| (d.kind == DegenerateKind::Coplanar) == (d.triangle_a == d.triangle_b))
    );
    // Every shared edge, once from each side's pair of its two triangles.
    assert_eq!(curves.len(), 3 * m.triangle_count());
}

#[test]
fn soups_agree_on_every_thread_count() {
    at_least_two_threads();
    // Enough triangles that the pairs are shared out (the full run's judge takes more).
    let n = crate::fixtures::cases(2500, 6000);
    let a = build(&soup(n, 10.0, 1.0, 11));
    let b = build(&soup(n, 10.0, 1.0, 12));
    let one = two_meshes(&a, None, &b, None, false);
    assert!(one.len() + one.degenerate().len() > super::entry::PARALLEL_MIN_PAIRS);
    for threads in [0, 2, 3] {
        let before = shared_count(Step::Crossings);
        let mut curves = Curves::new();
        let options = QueryOptions::default().with_threads(threads);
        intersection_curves(&a, None, &b, None, &options, &mut curves).unwrap();
        assert!(same(&one, &curves), "threads {threads}");
        assert!(shared_count(Step::Crossings) > before);
    }
}

/// A folded and crumpled sheet: a grid whose far half is turned back through the near half.
fn folded_sheet(n: usize, seed: u64) -> MeshData {
    let mut m = crate::fixtures::grid(n, 1.0);
    let mut rng = Rng::new(seed);
    for p in m.positions.chunks_exact_mut(3) {
        let (x, y) = (p[0], p[1]);
        let bump = 0.08 * (6.0 * y).sin();
        if x <= 0.5 {
            p[2] = bump;
        } else {
            let u = x - 0.5;
            p[0] = 0.5 - 0.8 * u;
            p[2] = 0.25 * u - 0.05 + 0.5 * bump;
        }
        for c in p.iter_mut() {
            *c += rng.range(-1e-4, 1e-4);
        }
    }
    m
}

#[test]
fn a_folded_sheet_crosses_itself_in_chains() {
    for seed in 0..3 {
        let curves = one_mesh(&build(&folded_sheet(24, seed)), false);
        assert!(!curves.is_empty());
    }
}

#[test]
fn a_crumpled_sphere_crosses_itself_in_chains() {
    let mut s = icosphere(3);
    s.perturb(0.15, 21);
    let curves = one_mesh(&build(&s), false);
    assert!(curves.len() > 50);
}

#[test]
fn two_meshes_as_one_cross_in_the_same_curves() {
    // Self curves of two spheres appended into one mesh are the two-mesh curves, with the
    // second's indices shifted.
    let a = sphere(2, 1.0, [0.0; 3], 31);
    let b = sphere(2, 0.8, [0.4, 0.3, -0.2], 32);
    let mut both = a.clone();
    both.append(&b);
    let two = two_meshes(&build(&a), None, &build(&b), None, true);
    let curves = one_mesh(&build(&both), true);
    let shift = a.triangle_count() as u32;
    let bits = |p: Point| p.map(f64::to_bits);
    let of = |c: &Curves, shift: u32| -> Vec<_> {
        c.segments()
            .iter()
            .map(|s| {
                (
                    s.triangle_a,
                    s.triangle_b + shift,
                    s.curve,
                    bits(s.start),
                    bits(s.end),
                )
            })
            .collect()
    };
    assert_eq!(of(&two, shift), of(&curves, 0));
    assert!(curves.curves().iter().all(|c| c.closed));
}

#[test]
fn coarse_modes_are_refused_and_change_nothing() {
    let a = build(&sphere(2, 1.0, [0.0; 3], 41));
    let b = build(&sphere(2, 0.8, [0.5, 0.0, 0.0], 42));
    let mut curves = Curves::new();
    intersection_curves(&a, None, &b, None, &QueryOptions::default(), &mut curves).unwrap();
    let before = curves.segments().to_vec();
    for mode in [
        QueryMode::FirstHit,
        QueryMode::Leaves,
        QueryMode::Depth(2),
        QueryMode::Budget(10),
    ] {
        let options = QueryOptions::with_mode(mode);
        let e = intersection_curves(&a, None, &b, None, &options, &mut curves).unwrap_err();
        assert!(matches!(e, Error::UnsupportedMode { .. }), "{e}");
        let e = self_intersection_curves(&a, &options, &mut curves).unwrap_err();
        assert!(matches!(e, Error::UnsupportedMode { .. }), "{e}");
        assert_eq!(curves.segments(), before);
    }
}

#[test]
fn max_pairs_bounds_segments_and_degenerate_pairs() {
    let m = sphere(2, 1.0, [0.0; 3], 51);
    let (a, b) = (build(&m), build(&m));
    let mut all = Curves::new();
    intersection_curves(&a, None, &b, None, &QueryOptions::default(), &mut all).unwrap();
    let total = all.len() + all.degenerate().len();
    for max in [0, 1, 17, total - 1, total, total + 1] {
        let mut curves = Curves::new();
        let options = QueryOptions::default().with_max_pairs(Some(max));
        let stats = intersection_curves(&a, None, &b, None, &options, &mut curves).unwrap();
        let n = curves.len() + curves.degenerate().len();
        assert_eq!(n, max.min(total));
        // Reaching the limit stops the query, as `collide`: truncated, even at exactly all.
        assert_eq!(stats.truncated, max <= total);
        assert!(is_chained(&curves));
    }
}

#[test]
fn chaining_follows_names_only() {
    use CurvePoint::VertexA as V;
    // A closed triangle of pieces given out of order and reversed, an open run of two, and a
    // junction of three pieces at vertex 20.
    let pieces = vec![
        piece(0, 0, [V(2), V(1)]),
        piece(0, 1, [V(1), V(3)]),
        piece(0, 2, [V(2), V(3)]),
        piece(1, 0, [V(11), V(10)]),
        piece(1, 1, [V(11), V(12)]),
        piece(2, 0, [V(20), V(21)]),
        piece(2, 1, [V(22), V(20)]),
        piece(2, 2, [V(20), V(23)]),
    ];
    let mut work = super::result::CurveWork {
        pieces,
        ..Default::default()
    };
    let mut set = super::result::CurveSet::default();
    link(&mut work);
    chain(&mut work, &mut set).unwrap();
    let set = Curves {
        result: set,
        ..Curves::default()
    };
    assert!(is_chained(&set));
    let set = &set.result;
    let runs: Vec<(Vec<(u32, u32)>, bool)> = set
        .curves
        .iter()
        .map(|c| {
            let s = &set.segments[c.segments.clone()];
            (
                s.iter().map(|s| (s.triangle_a, s.triangle_b)).collect(),
                c.closed,
            )
        })
        .collect();
    assert_eq!(
        runs,
        vec![
            (vec![(0, 0), (0, 1), (0, 2)], true),
            (vec![(1, 1), (1, 0)], false),
            (vec![(2, 0)], false),
            (vec![(2, 1)], false),
            (vec![(2, 2)], false),
        ]
    );
    // The closed curve's last piece runs against its own direction; the open run goes the way
    // its least piece goes (11 to 10), so from 12 to 10.
    assert_eq!(set.points[2], [V(3), V(2)]);
    assert_eq!(set.points[3], [V(12), V(11)]);
    assert_eq!(set.points[4], [V(11), V(10)]);
}

/// The curves' total length.
fn total_length(c: &Curves) -> f64 {
    (0..c.curves().len()).map(|i| c.curve_length(i)).sum()
}

/// `m` with vertex `v` moved by `d`.
fn nudged(m: &MeshData, v: usize, d: [f64; 3]) -> Mesh {
    let mut moved = m.clone();
    for (x, dx) in moved.positions[3 * v..3 * v + 3].iter_mut().zip(d) {
        *x += dx;
    }
    build(&moved)
}

#[test]
fn the_length_gradient_is_the_lengths_derivative() {
    // Central differences on vertices the curves pass by, of both meshes, in random
    // directions: small enough steps keep the curves' combinatorics.
    let ma = sphere(2, 1.0, [0.0; 3], 61);
    let mb = sphere(2, 0.7, [0.5, 0.2, 0.1], 62);
    let (a, b) = (build(&ma), build(&mb));
    let mut curves = Curves::new();
    intersection_curves(&a, None, &b, None, &QueryOptions::default(), &mut curves).unwrap();
    let mut ga = vec![[0.0; 3]; a.vertex_count()];
    let mut gb = vec![[0.0; 3]; b.vertex_count()];
    curves
        .length_gradient(&a, None, &b, None, &mut ga, &mut gb)
        .unwrap();
    let mut rng = Rng::new(63);
    let mut checked = 0;
    for (second, grad, m) in [(false, &ga, &ma), (true, &gb, &mb)] {
        for v in (0..grad.len()).filter(|&v| grad[v] != [0.0; 3]).take(12) {
            let dir = [0; 3].map(|_| rng.range(-1.0, 1.0));
            let h = 1e-7;
            let length = |sign: f64| {
                let moved = nudged(m, v, dir.map(|x| sign * h * x));
                let mut c = Curves::new();
                let o = QueryOptions::default();
                if second {
                    intersection_curves(&a, None, &moved, None, &o, &mut c).unwrap();
                } else {
                    intersection_curves(&moved, None, &b, None, &o, &mut c).unwrap();
                }
                total_length(&c)
            };
            let numeric = (length(1.0) - length(-1.0)) / (2.0 * h);
            let analytic: f64 = (0..3).map(|k| grad[v][k] * dir[k]).sum();
            assert!(
                (numeric - analytic).abs() <= 1e-5 * (1.0 + analytic.abs()),
                "vertex {v} of {}: {numeric} by differences, {analytic} by the gradient",
                if second { "b" } else { "a" }
            );
            checked += 1;
        }
    }
    assert!(checked >= 20);
    // Vertices far from every crossing get nothing.
    assert!(ga.iter().filter(|g| **g == [0.0; 3]).count() > ga.len() / 2);
}

#[test]
fn a_step_against_the_self_gradient_shortens_the_curves() {
    let m = folded_sheet(16, 71);
    let mesh = build(&m);
    let mut curves = Curves::new();
    self_intersection_curves(&mesh, &QueryOptions::default(), &mut curves).unwrap();
    let before = total_length(&curves);
    assert!(before > 0.0);
    let mut g = vec![[0.0; 3]; mesh.vertex_count()];
    curves.self_length_gradient(&mesh, &mut g).unwrap();
    let step = 1e-4;
    let mut moved = m.clone();
    for (p, gv) in moved.positions.chunks_exact_mut(3).zip(&g) {
        for (x, gx) in p.iter_mut().zip(gv) {
            *x -= step * gx;
        }
    }
    let mut after = Curves::new();
    self_intersection_curves(&build(&moved), &QueryOptions::default(), &mut after).unwrap();
    assert!(total_length(&after) < before);
}

#[test]
fn a_gradient_of_other_meshes_is_refused() {
    let a = build(&sphere(2, 1.0, [0.0; 3], 81));
    let b = build(&sphere(2, 0.7, [0.5, 0.2, 0.1], 82));
    let small = build(&sphere(0, 1.0, [0.0; 3], 83));
    let mut curves = Curves::new();
    intersection_curves(&a, None, &b, None, &QueryOptions::default(), &mut curves).unwrap();
    let mut ga = vec![[1.0; 3]; a.vertex_count()];
    let mut gb = vec![[1.0; 3]; b.vertex_count()];
    let mut gs = vec![[1.0; 3]; small.vertex_count()];
    let e = curves
        .length_gradient(&a, None, &small, None, &mut ga, &mut gs)
        .unwrap_err();
    assert!(matches!(e, Error::ForeignCurves { .. }), "{e}");
    let e = curves
        .length_gradient(&a, None, &b, None, &mut ga, &mut gs)
        .unwrap_err();
    assert!(matches!(e, Error::GradientLength { .. }), "{e}");
    assert!(ga.iter().chain(&gb).all(|g| *g == [1.0; 3]));
    curves
        .length_gradient(&a, None, &b, None, &mut ga, &mut gb)
        .unwrap();
}
