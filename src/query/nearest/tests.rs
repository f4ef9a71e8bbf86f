use super::*;
use crate::exact::Feature;
use crate::fixtures::oracle::nearest_brute_force;
use crate::fixtures::{Rng, grid, icosphere, torus};
use crate::query::testing::{build, folded, moved};
use crate::threads::{Step, sharing};
use crate::{
    BuildOptions, Error, ImpactKind, Mesh, Pose, QueryMode, QueryOptions, QueryStats, VolumeKind,
};

type Side<'m> = Option<(&'m Mesh, Option<&'m Pose>)>;

fn run(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: Side,
    d: f64,
    options: &QueryOptions,
    out: &mut NearPairs,
) -> QueryStats {
    match b {
        Some((b, pose_b)) => nearest_features(a, pose_a, b, pose_b, d, options, out).unwrap(),
        None => self_nearest_features(a, d, options, out).unwrap(),
    }
}

/// The query against brute force in every mode, thread count and limit. Returns the number of
/// stencils.
fn check(a: &Mesh, pose_a: Option<&Pose>, b: Side, d: f64, what: &str) -> usize {
    let expected = nearest_brute_force(a, pose_a, b, d);
    let mut out = NearPairs::new();
    // Meshes this small are queried on the calling thread whatever the thread count: threads
    // are compared on larger ones.
    let threads = 1;
    for mode in [
        QueryMode::Triangles,
        QueryMode::Leaves,
        QueryMode::Depth(2),
        QueryMode::Budget(7),
    ] {
        let options = QueryOptions::with_mode(mode).with_threads(threads);
        let stats = run(a, pose_a, b, d, &options, &mut out);
        assert_eq!(
            out.as_slice(),
            &expected[..],
            "{what}: d {d}, {mode:?}, {threads} threads"
        );
        assert!(!stats.truncated);
        assert_eq!(stats.pairs, expected.len() as u64);
        assert!(stats.triangle_tests >= stats.pairs);
    }
    let options = QueryOptions::with_mode(QueryMode::FirstHit).with_threads(threads);
    let stats = run(a, pose_a, b, d, &options, &mut out);
    assert_eq!(out.len(), expected.len().min(1), "{what}: first hit");
    assert!(out.iter().all(|p| expected.contains(p)));
    assert!(!stats.truncated);
    if expected.len() > 3 {
        let options = QueryOptions::default()
            .with_max_pairs(Some(3))
            .with_threads(threads);
        let stats = run(a, pose_a, b, d, &options, &mut out);
        assert!(stats.truncated && out.len() == 3, "{what}");
        assert!(out.iter().all(|p| expected.contains(p)));
        assert!(out.as_slice().is_sorted_by_key(NearPair::key));
    }
    for p in &expected {
        check_stencil(p, a, pose_a, b, what);
    }
    expected.len()
}

/// What a stencil's fields promise, against its own primitives: in range, consistent.
fn check_stencil(p: &NearPair, a: &Mesh, pose_a: Option<&Pose>, b: Side, what: &str) {
    let (mb, pose_b) = b.unwrap_or((a, pose_a));
    let at = |m: &Mesh, pose: Option<&Pose>, v: u32| {
        let q = m.positions()[v as usize];
        pose.map_or(q, |t| t.transform_point(&q))
    };
    let weighted = |corners: &[[f64; 3]], w: &[f64; 3]| -> [f64; 3] {
        let mut x = [0.0; 3];
        for (c, wi) in corners.iter().zip(w) {
            for k in 0..3 {
                x[k] += wi * c[k];
            }
        }
        x
    };
    let (corners_a, corners_b): (Vec<[f64; 3]>, Vec<[f64; 3]>) = match p.kind {
        ImpactKind::VertexFace => (
            vec![at(a, pose_a, p.a0)],
            mb.triangles()[p.b0 as usize]
                .iter()
                .map(|&v| at(mb, pose_b, v))
                .collect(),
        ),
        ImpactKind::FaceVertex => (
            a.triangles()[p.a0 as usize]
                .iter()
                .map(|&v| at(a, pose_a, v))
                .collect(),
            vec![at(mb, pose_b, p.b0)],
        ),
        ImpactKind::EdgeEdge => (
            vec![at(a, pose_a, p.a0), at(a, pose_a, p.a1)],
            vec![at(mb, pose_b, p.b0), at(mb, pose_b, p.b1)],
        ),
    };
    for (corners, w, x, f) in [
        (&corners_a, &p.weights_a, &p.closest_a, p.feature_a),
        (&corners_b, &p.weights_b, &p.closest_b, p.feature_b),
    ] {
        assert!(
            w.iter().all(|&wi| (0.0..=1.0).contains(&wi)),
            "{what}: {p:?}"
        );
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{what}: {p:?}");
        assert!(
            w[corners.len()..].iter().all(|&wi| wi == 0.0),
            "{what}: {p:?}"
        );
        let y = weighted(corners, w);
        for k in 0..3 {
            assert!((x[k] - y[k]).abs() < 1e-9, "{what}: {p:?}");
        }
        // A corner feature has weight one there.
        if (f as usize) < 3 {
            assert_eq!(w[f as usize], 1.0, "{what}: {p:?}");
        }
        match corners.len() {
            1 => assert_eq!(f, Feature::Vertex0),
            2 => assert!(matches!(
                f,
                Feature::Vertex0 | Feature::Vertex1 | Feature::Edge01
            )),
            _ => {}
        }
    }
    let gap: f64 = (0..3)
        .map(|k| (p.closest_a[k] - p.closest_b[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((gap - p.distance).abs() <= 1e-9, "{what}: {p:?}");
}

#[test]
fn two_meshes_equal_brute_force() {
    let mut rng = Rng::new(31);
    let s = icosphere(1);
    let t = torus(0.5, 0.2, 12, 6);
    let pose = Pose::new(
        [[0.6, -0.8, 0.0], [0.8, 0.6, 0.0], [0.0, 0.0, 1.0]],
        [0.05, -0.02, 0.01],
    )
    .unwrap();
    let mut found = 0;
    for volume in [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv] {
        let mut a = build(&s, volume);
        let mut b = build(&t, volume);
        for trial in 0..2 {
            a.refit(&moved(
                &s.positions,
                [0.6 + 0.1 * trial as f64, 0.0, 0.0],
                0.02,
                &mut rng,
            ))
            .unwrap();
            b.refit(&moved(&t.positions, [0.0; 3], 0.02, &mut rng))
                .unwrap();
            for d in [0.0, 0.02, 0.1] {
                let what = format!("{volume:?} {trial}");
                found += check(&a, None, Some((&b, None)), d, &what);
                found += check(&b, None, Some((&a, None)), d, &format!("{what} swapped"));
                found += check(
                    &a,
                    Some(&pose),
                    Some((&b, None)),
                    d,
                    &format!("{what} posed"),
                );
            }
        }
    }
    assert!(found > 300, "stencils found: {found}");
}

#[test]
fn one_mesh_equals_brute_force() {
    let mut rng = Rng::new(9);
    let t = torus(0.5, 0.2, 16, 8);
    let g = grid(8, 1.0);
    let mut found = 0;
    for volume in [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv] {
        let mut m = build(&t, volume);
        m.refit(&moved(&t.positions, [0.0; 3], 0.05, &mut rng))
            .unwrap();
        for d in [0.0, 0.05, 0.15] {
            found += check(&m, None, None, d, &format!("torus {volume:?}"));
        }
        // A sheet folded flat over itself: its halves a small gap apart, coplanar neighbours.
        let mut sheet = build(&g, volume);
        let folded = folded(&g.positions, |x, y| [1.0 - x, y, 0.01]);
        sheet.refit(&folded).unwrap();
        for d in [0.0, 0.01, 0.03] {
            found += check(&sheet, None, None, d, &format!("sheet {volume:?}"));
        }
        // Flat: neighbours touch, but share vertices; the rest are a grid step apart.
        sheet.refit(&g.positions).unwrap();
        assert_eq!(check(&sheet, None, None, 0.0, "flat sheet"), 0);
        assert!(check(&sheet, None, None, 0.125, "flat sheet") > 0);
    }
    assert!(found > 300, "stencils found: {found}");
}

#[test]
fn threads_and_limits_give_one_answer_on_larger_meshes() {
    let mut rng = Rng::new(41);
    let s = icosphere(3);
    let g = grid(40, 2.0);
    let mut a = build(&s, VolumeKind::Aabb);
    let b = build(&g, VolumeKind::Dvh);
    a.refit(&moved(&s.positions, [1.0, 1.0, 1.02], 0.005, &mut rng))
        .unwrap();
    let (mut one, mut two) = (NearPairs::new(), NearPairs::new());
    let base = QueryOptions::default();
    for options in [
        base,
        base.with_max_pairs(Some(50)),
        QueryOptions::with_mode(QueryMode::FirstHit),
        QueryOptions::with_mode(QueryMode::Depth(3)),
    ] {
        let s1 = run(
            &a,
            None,
            Some((&b, None)),
            0.05,
            &options.with_threads(1),
            &mut one,
        );
        // A depth limit stops the traversal before its node pairs are many enough to share out.
        let steps: &[Step] = match options.mode {
            QueryMode::Depth(_) => &[],
            _ => &[Step::Traversal, Step::Pairs],
        };
        let many = options.with_threads(2);
        let s2 = sharing(steps, &format!("{options:?}"), || {
            run(&a, None, Some((&b, None)), 0.05, &many, &mut two)
        });
        assert_eq!(one.as_slice(), two.as_slice(), "{options:?}");
        assert_eq!(s1.truncated, s2.truncated);
        assert!(!one.is_empty());
    }
    run(&a, None, Some((&b, None)), 0.05, &base, &mut one);
    assert!(one.len() > 50, "{}", one.len());
    run(&b, None, None, 0.06, &base.with_threads(1), &mut one);
    let steps = [Step::Traversal, Step::Pairs, Step::Values];
    sharing(&steps, "self", || {
        run(&b, None, None, 0.06, &base.with_threads(2), &mut two)
    });
    assert_eq!(one.as_slice(), two.as_slice());
    assert!(one.len() > 1000, "{}", one.len());
    assert!(one.memory_bytes() >= one.len() * std::mem::size_of::<NearPair>());
}

#[test]
fn bad_input_leaves_the_result_unchanged() {
    let s = icosphere(1);
    let a = build(&s, VolumeKind::Dvh);
    let mut out = NearPairs::new();
    self_nearest_features(&a, 0.5, &QueryOptions::default(), &mut out).unwrap();
    let before = out.as_slice().to_vec();
    assert!(!before.is_empty());
    for d in [-1.0, f64::NAN, f64::INFINITY] {
        let e = self_nearest_features(&a, d, &QueryOptions::default(), &mut out).unwrap_err();
        assert!(matches!(e, Error::InvalidDistance { .. }), "{e}");
        let e = nearest_features(&a, None, &a, None, d, &QueryOptions::default(), &mut out)
            .unwrap_err();
        assert!(matches!(e, Error::InvalidDistance { .. }), "{e}");
    }
    let far = Pose::new(
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [1e301; 3],
    )
    .unwrap();
    let e = nearest_features(
        &a,
        Some(&far),
        &a,
        None,
        0.1,
        &QueryOptions::default(),
        &mut out,
    )
    .unwrap_err();
    assert!(matches!(e, Error::PoseOutOfRange { .. }), "{e}");
    let e = self_nearest_features(
        &a,
        0.1,
        &QueryOptions::with_mode(QueryMode::Budget(0)),
        &mut out,
    )
    .unwrap_err();
    assert!(matches!(e, Error::ZeroBudget), "{e}");
    assert_eq!(out.as_slice(), &before[..]);
}

#[test]
fn hand_worked_stencils() {
    // A vertex 0.5 above a unit right triangle's interior, and two crossing edges 0.25 apart.
    let a = Mesh::new(
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        &[0, 1, 2],
        &BuildOptions::default(),
    )
    .unwrap();
    let b = Mesh::new(
        &[0.25, 0.25, 0.5, 0.25, -1.0, 0.25, 0.25, 2.0, 0.25],
        &[0, 1, 2],
        &BuildOptions::default(),
    )
    .unwrap();
    let mut out = NearPairs::new();
    nearest_features(&a, None, &b, None, 0.25, &QueryOptions::default(), &mut out).unwrap();
    // b's edge (1, 2) runs along x = 0.25, 0.25 above a's plane: over a's edges (0, 1) and
    // (1, 2), crossing each inside; parallel to a's edge (0, 2), farther than 0.25. Nothing
    // else comes within 0.25.
    let ee: Vec<_> = out
        .iter()
        .filter(|p| p.kind == ImpactKind::EdgeEdge)
        .collect();
    assert_eq!(ee.len(), out.len(), "{out:?}");
    for p in &ee {
        assert_eq!(p.distance, 0.25, "{p:?}");
        assert_eq!(p.feature_a, Feature::Edge01);
        assert_eq!(p.feature_b, Feature::Edge01);
        assert_eq!(p.closest_a[2], 0.0);
        assert_eq!(p.closest_b[2], 0.25);
    }
    assert_eq!(
        ee.iter()
            .map(|p| (p.a0, p.a1, p.b0, p.b1))
            .collect::<Vec<_>>(),
        vec![(0, 1, 1, 2), (1, 2, 1, 2)]
    );
    let e01 = ee[0];
    assert_eq!(e01.closest_a, [0.25, 0.0, 0.0]);
    assert_eq!(e01.weights_a, [0.75, 0.25, 0.0]);
    assert_eq!(e01.closest_b, [0.25, 0.0, 0.25]);
    assert_eq!(e01.weights_b, [2.0 / 3.0, 1.0 / 3.0, 0.0]);
    // b's vertex 0 is 0.5 above the interior: found at 0.5, not at 0.25.
    nearest_features(&a, None, &b, None, 0.5, &QueryOptions::default(), &mut out).unwrap();
    let fv = out
        .iter()
        .find(|p| p.kind == ImpactKind::FaceVertex && p.b0 == 0)
        .expect("the vertex above the face");
    assert_eq!((fv.a0, fv.distance), (0, 0.5));
    assert_eq!(
        (fv.feature_a, fv.feature_b),
        (Feature::Interior, Feature::Vertex0)
    );
    assert_eq!(fv.closest_a, [0.25, 0.25, 0.0]);
    assert_eq!(fv.weights_a, [0.5, 0.25, 0.25]);
    assert_eq!(fv.weights_b, [1.0, 0.0, 0.0]);
}
