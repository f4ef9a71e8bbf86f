//! A mesh is queried from several threads at once, each with its own result buffer.

use dvh::fixtures::{icosphere, torus};
use dvh::{BuildOptions, Mesh, Pairs, Pose, QueryOptions, collide};

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
