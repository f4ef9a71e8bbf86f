//! Threads: a mesh queried from several threads at once, each with its own result buffer; one
//! query or refit shared out over several threads gives the single-threaded answer.

use dvh::fixtures::{MeshData, Morph, Rng, grid, icosphere, torus};
use dvh::testing::{Step, sharing};
use dvh::{
    BuildOptions, CcdMode, CcdOptions, Impacts, Mesh, NearPairs, Pairs, Pose, QueryMode,
    QueryOptions, RadiusKind, TreeKind, VolumeKind, collide, continuous_collide, nearest_features,
    proximity, self_continuous_collide, self_nearest_features, self_proximity,
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
        QueryMode::Depth(5),
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
                    let what = format!("scene {scene}, posed {}, {options:?}", pose_b.is_some());
                    // A budget is spent in the single-threaded traversal's order: it never
                    // shares out.
                    let steps: &[Step] = match options.mode {
                        QueryMode::Budget(_) => &[],
                        _ => &[Step::Traversal],
                    };
                    let many = sharing(steps, &what, || {
                        collide(&a, None, &b, pose_b, &options, &mut threaded).unwrap()
                    });
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
                    let what = format!("{volume:?} {radius:?} {tree:?} {threads}");
                    let stats_many = sharing(&[Step::Store, Step::Refit], &what, || {
                        many.refit(frame).unwrap()
                    });
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

/// Two sheets of `n × n` cells a unit on a side, the second turned a little about the vertical
/// and lifted by `lift` (its vertices jittered too, so no edges of the two are parallel).
fn two_sheets(n: usize, lift: f64, seed: u64) -> (MeshData, MeshData) {
    let a = grid(n, 1.0);
    let mut b = grid(n, 1.0);
    b.translate([-0.5, -0.5, 0.0]);
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let mut rng = Rng::new(seed);
    for v in b.positions.chunks_exact_mut(3) {
        let (x, y) = (v[0], v[1]);
        let jitter = 0.05 / n as f64;
        v[0] = 0.5 + c * x - s * y + rng.range(-jitter, jitter);
        v[1] = 0.5 + s * x + c * y + rng.range(-jitter, jitter);
        v[2] = lift + rng.range(-jitter, jitter);
    }
    (a, b)
}

/// Two meshes (sheets of `n × n` cells a quarter cell apart, as [`two_sheets`]) and one mesh
/// made of both, the distance between them, and their data.
fn sheets(n: usize) -> (Mesh, Mesh, Mesh, f64, [MeshData; 3]) {
    let cell = 1.0 / n as f64;
    let (sa, sb) = two_sheets(n, 0.25 * cell, 5);
    let mut both = sa.clone();
    both.append(&sb);
    let build = |m: &MeshData| Mesh::new(&m.positions, &m.triangles, &BuildOptions::default());
    let (a, b, ab) = (
        build(&sa).unwrap(),
        build(&sb).unwrap(),
        build(&both).unwrap(),
    );
    (a, b, ab, 0.25 * cell, [sa, sb, both])
}

/// Proximity and nearest features, between two meshes and of one, on meshes and contact large
/// enough that every step they may share out is shared out: 2 and all threads give the calling
/// thread's answer. (Within each sheet, triangles that share no corner are farther apart than
/// the distance: the self queries find the pairs between the sheets.)
#[test]
fn threaded_distance_queries_equal_single_threaded_ones() {
    let (a, b, ab, lift, _) = sheets(40);
    let d = 2.0 * lift;
    let one = QueryOptions::default().with_threads(1);
    let (mut single, mut threaded) = (Pairs::new(), Pairs::new());
    let (mut near_one, mut near_many) = (NearPairs::new(), NearPairs::new());
    let near_steps = [Step::Traversal, Step::Pairs, Step::Sort, Step::Values];
    for threads in [2, 0] {
        let many = one.with_threads(threads);
        let what = format!("{threads} threads");
        let s1 = proximity(&a, None, &b, None, d, &one, &mut single).unwrap();
        let s2 = sharing(&[Step::Traversal], &what, || {
            proximity(&a, None, &b, None, d, &many, &mut threaded).unwrap()
        });
        assert_eq!(threaded.as_slice(), single.as_slice(), "proximity, {what}");
        assert_eq!(s1, s2, "proximity, {what}");
        self_proximity(&ab, d, &one, &mut single).unwrap();
        assert!(single.len() > 1000, "{} near pairs", single.len());
        sharing(&[Step::Traversal], &what, || {
            self_proximity(&ab, d, &many, &mut threaded).unwrap()
        });
        assert_eq!(threaded.as_slice(), single.as_slice(), "self, {what}");

        let s1 = nearest_features(&a, None, &b, None, d, &one, &mut near_one).unwrap();
        let s2 = sharing(&near_steps, &what, || {
            nearest_features(&a, None, &b, None, d, &many, &mut near_many).unwrap()
        });
        assert_eq!(
            near_many.as_slice(),
            near_one.as_slice(),
            "stencils, {what}"
        );
        assert_eq!(s1, s2, "stencils, {what}");
        self_nearest_features(&ab, d, &one, &mut near_one).unwrap();
        sharing(&near_steps, &what, || {
            self_nearest_features(&ab, d, &many, &mut near_many).unwrap()
        });
        let what = format!("self stencils, {what}");
        assert_eq!(near_many.as_slice(), near_one.as_slice(), "{what}");
    }
}

/// Continuous collision, between two meshes and of one, on meshes and contact large enough that
/// every step it may share out is shared out (one sheet falls through the other): 2 and all
/// threads give the calling thread's answer.
#[test]
fn threaded_continuous_queries_equal_single_threaded_ones() {
    let (mut a, mut b, mut ab, lift, [sa, sb, both]) = sheets(46);
    let fall = |p: &[f64]| -> Vec<f64> {
        p.chunks_exact(3)
            .flat_map(|v| [v[0], v[1], v[2] - 2.0 * lift])
            .collect()
    };
    a.refit_motion(&sa.positions, &sa.positions).unwrap();
    b.refit_motion(&sb.positions, &fall(&sb.positions)).unwrap();
    let mut both_fallen = both.positions.clone();
    both_fallen.truncate(sa.positions.len());
    both_fallen.extend(fall(&sb.positions));
    ab.refit_motion(&both.positions, &both_fallen).unwrap();
    let (mut single, mut threaded) = (Impacts::new(), Impacts::new());
    let steps = [Step::Traversal, Step::Pairs, Step::Sort];
    // Each mode on one thread count beyond one: the exact mode costs the more.
    for (mode, threads) in [(CcdMode::Exact, 2), (CcdMode::Conservative, 0)] {
        let one = CcdOptions::default().with_mode(mode).with_threads(1);
        let many = one.with_threads(threads);
        let what = format!("{mode:?}, {threads} threads");
        let s1 = continuous_collide(&a, &b, &one, &mut single).unwrap();
        let s2 = sharing(&steps, &what, || {
            continuous_collide(&a, &b, &many, &mut threaded).unwrap()
        });
        assert_eq!(threaded.as_slice(), single.as_slice(), "{what}");
        assert_eq!(s1, s2, "{what}");
        self_continuous_collide(&ab, &one, &mut single).unwrap();
        assert!(single.len() > 1000, "{} impacts", single.len());
        sharing(&steps, &what, || {
            self_continuous_collide(&ab, &many, &mut threaded).unwrap()
        });
        assert_eq!(threaded.as_slice(), single.as_slice(), "self, {what}");
    }
}
