//! Threads: a mesh queried from several threads at once, each with its own result buffer; one
//! query or refit shared out over several threads gives the single-threaded answer.

use dvh::fixtures::{Morph, Rng, icosphere, torus};
use dvh::{
    BuildOptions, Mesh, Pairs, Pose, QueryMode, QueryOptions, RadiusKind, TreeKind, VolumeKind,
    collide,
};

#[test]
fn shared_meshes_queried_concurrently_give_the_single_threaded_answer() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<Mesh>();
    assert_send_sync::<Pose>();
    fn assert_send<T: Send>() {}
    assert_send::<Pairs>();

    let s = icosphere(4);
    let mut t = torus(0.7, 0.3, 80, 40);
    t.translate([0.5, 0.2, 0.0]);
    let a = Mesh::new(&s.positions, &s.triangles, &BuildOptions::default()).unwrap();
    let b = Mesh::new(&t.positions, &t.triangles, &BuildOptions::default()).unwrap();
    let poses: Vec<Pose> = (0..8)
        .map(|i| {
            let angle = f64::from(i) * 0.4;
            let (c, s) = (angle.cos(), angle.sin());
            Pose::new(
                [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
                [0.05 * f64::from(i), 0.0, 0.0],
            )
            .unwrap()
        })
        .collect();
    let expected: Vec<Vec<dvh::Pair>> = poses
        .iter()
        .map(|p| {
            let mut pairs = Pairs::new();
            collide(&a, None, &b, Some(p), &QueryOptions::default(), &mut pairs).unwrap();
            pairs.as_slice().to_vec()
        })
        .collect();
    assert!(expected.iter().all(|e| !e.is_empty()));
    std::thread::scope(|scope| {
        for worker in 0..4 {
            let (a, b, poses, expected) = (&a, &b, &poses, &expected);
            scope.spawn(move || {
                let mut pairs = Pairs::new();
                for round in 0..5 {
                    for (i, p) in poses.iter().enumerate().skip((worker + round) % 3) {
                        collide(a, None, b, Some(p), &QueryOptions::default(), &mut pairs).unwrap();
                        assert_eq!(
                            pairs.as_slice(),
                            &expected[i][..],
                            "worker {worker}, pose {i}"
                        );
                    }
                }
            });
        }
    });
}

/// The options every threaded answer is compared under: each mode, with and without a pair
/// limit that cuts the answer.
fn all_modes(limit: usize) -> Vec<QueryOptions> {
    let mut all = Vec::new();
    for mode in [
        QueryMode::Triangles,
        QueryMode::FirstHit,
        QueryMode::Leaves,
        QueryMode::Depth(3),
        QueryMode::Budget(500),
    ] {
        for max_pairs in [None, Some(1), Some(limit)] {
            all.push(
                QueryOptions::with_mode(mode)
                    .with_max_pairs(max_pairs)
                    .with_threads(1),
            );
        }
    }
    all
}

/// On random scenes (deformed meshes large enough to be shared out, some posed, every volume
/// kind), every mode with and without pair limits: 2, 3 and all threads give the calling
/// thread's pairs in the same order, and the same counters unless a limit cut the query.
#[test]
fn threaded_queries_equal_single_threaded_ones_on_random_scenes() {
    let mut rng = Rng::new(77);
    let volumes = [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv];
    for scene in 0..6 {
        let mut sa = icosphere(4 + (scene % 2) as u32);
        sa.perturb(0.01, scene);
        let mut sb = torus(0.7, 0.3, 60 + 10 * scene as usize, 40);
        sb.translate([rng.range(0.2, 0.6), rng.range(-0.2, 0.2), 0.0]);
        let morph = Morph::random(&sb, 4, 0.1, scene + 10);
        let moved = morph.at(&sb.positions, 0.5);
        let options_a = BuildOptions::default().with_volume(volumes[scene as usize % 3]);
        let options_b = BuildOptions::default()
            .with_volume(volumes[(scene as usize + 1) % 3])
            .with_tree([TreeKind::Octree, TreeKind::Binary][scene as usize % 2]);
        let a = Mesh::new(&sa.positions, &sa.triangles, &options_a).unwrap();
        let mut b = Mesh::new(&sb.positions, &sb.triangles, &options_b).unwrap();
        b.refit(&moved).unwrap();
        let angle = rng.range(0.0, 0.5);
        let (c, s) = (angle.cos(), angle.sin());
        let pose = Pose::new(
            [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
            [0.01, 0.0, 0.0],
        )
        .unwrap();
        let mut single = Pairs::new();
        let mut threaded = Pairs::new();
        for pose_b in [None, Some(&pose)] {
            for options in all_modes(50) {
                let one = collide(&a, None, &b, pose_b, &options, &mut single).unwrap();
                if options.mode == QueryMode::Triangles && options.max_pairs.is_none() {
                    assert!(
                        one.pairs > 50,
                        "scene {scene}: too little contact to share out"
                    );
                }
                for threads in [2, 3, 0] {
                    let options = options.with_threads(threads);
                    let many = collide(&a, None, &b, pose_b, &options, &mut threaded).unwrap();
                    let what = format!("scene {scene}, posed {}, {options:?}", pose_b.is_some());
                    assert_eq!(threaded.as_slice(), single.as_slice(), "{what}");
                    assert_eq!(threaded.kind(), single.kind(), "{what}");
                    assert_eq!(many.pairs, one.pairs, "{what}");
                    assert_eq!(many.truncated, one.truncated, "{what}");
                    let cut = one.truncated || options.mode == QueryMode::FirstHit;
                    if !cut {
                        assert_eq!(many, one, "{what}");
                    }
                }
            }
        }
    }
}

/// Refits on several threads give every node's volume bit for bit as on one, for every volume
/// kind and radius kind, on a mesh large enough to be shared out.
#[test]
fn threaded_refits_equal_single_threaded_ones() {
    let s = icosphere(6);
    assert!(s.vertex_count() > 2 * 16_384);
    let morph = Morph::random(&s, 6, 0.2, 3);
    let frames: Vec<Vec<f64>> = (1..3)
        .map(|f| morph.at(&s.positions, f as f64 / 3.0))
        .collect();
    for (volume, radius) in [
        (VolumeKind::Aabb, RadiusKind::Layered),
        (VolumeKind::Dvh, RadiusKind::Layered),
        (VolumeKind::Dvh, RadiusKind::Wrapped),
        (VolumeKind::Sbv, RadiusKind::Layered),
        (VolumeKind::Sbv, RadiusKind::Wrapped),
    ] {
        for tree in [TreeKind::Octree, TreeKind::Binary] {
            let options = |refit_threads| {
                BuildOptions::default()
                    .with_volume(volume)
                    .with_radius(radius)
                    .with_tree(tree)
                    .with_refit_threads(refit_threads)
            };
            let mut one = Mesh::new(&s.positions, &s.triangles, &options(1)).unwrap();
            for threads in [2, 3, 0] {
                let mut many = Mesh::new(&s.positions, &s.triangles, &options(threads)).unwrap();
                for frame in &frames {
                    let stats_one = one.refit(frame).unwrap();
                    let stats_many = many.refit(frame).unwrap();
                    assert_eq!(
                        stats_one, stats_many,
                        "{volume:?} {radius:?} {tree:?} {threads}"
                    );
                    for n in 0..one.node_count() as u32 {
                        assert_eq!(one.node(n), many.node(n), "node {n}, {volume:?} {radius:?}");
                    }
                }
            }
        }
    }
}
