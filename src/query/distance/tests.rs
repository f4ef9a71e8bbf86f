//! The least distance of two meshes against brute force over every primitive pair in exact
//! arithmetic, and the scene's against the least of its pairs'.

use super::*;
use crate::fixtures::distance_judge::judge_distance;
use crate::fixtures::{MeshData, Rng, grid, icosphere, torus};
use crate::query::DistanceOptions;
use crate::{Pose, Scene, VolumeKind, collide};

use crate::query::testing::{VOLUMES, build};

/// `distance` of `a` and `b` against brute force, with every volume kind and thread count the
/// same; returns the answer.
fn check(a: &MeshData, pa: Option<&Pose>, b: &MeshData, pb: Option<&Pose>, what: &str) -> Distance {
    let mut first: Option<Distance> = None;
    for volume in VOLUMES {
        let (ma, mb) = (build(a, volume), build(b, volume));
        for threads in [1, 0] {
            let options = DistanceOptions::default().with_threads(threads);
            let mut d = Distance::default();
            distance(&ma, pa, &mb, pb, &options, &mut d).unwrap();
            let what = format!("{what}, {volume:?}, {threads} threads");
            match &first {
                Some(f) => assert_eq!(f, &d, "{what}"),
                // Brute force once: the answer depends on the coordinates only.
                None => judge_distance(&ma, pa, &mb, pb, &options, &d, &what),
            }
            first = Some(d);
        }
    }
    first.unwrap()
}

#[test]
fn apart_touching_and_intersecting_meshes_are_brute_forces() {
    let mut rng = Rng::new(41);
    let mut sphere = icosphere(1);
    sphere.perturb(0.03, 1);
    let ring = torus(0.8, 0.25, 10, 6);
    let mut sheet = grid(6, 2.0);
    sheet.perturb(0.05, 2);
    sheet.translate([-1.0, -1.0, 0.0]);
    for (x, y, what) in [
        (&sphere, &ring, "sphere, torus"),
        (&sheet, &sphere, "sheet, sphere"),
    ] {
        for trial in 0..4 {
            let t: [f64; 3] = std::array::from_fn(|_| rng.range(-2.5, 2.5));
            let mut moved = y.clone();
            moved.translate(t);
            check(x, None, &moved, None, &format!("{what} {trial} at {t:?}"));
        }
    }
    // Intersecting.
    let mut through = sphere.clone();
    through.translate([0.5, 0.2, 0.0]);
    let d = check(&sphere, None, &through, None, "overlapping spheres");
    assert!(d.intersecting());
    // Touching exactly: grid-aligned cubes face to face, and corner to corner.
    let cube = |at: [f64; 3]| {
        let mut m = MeshData {
            positions: (0..8)
                .flat_map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
                .collect(),
            triangles: vec![
                0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0,
                6, 2, 1, 3, 7, 1, 7, 5,
            ],
        };
        m.translate(at);
        m
    };
    let base = cube([0.0; 3]);
    assert!(check(&base, None, &cube([1.0, 0.0, 0.0]), None, "face to face").intersecting());
    assert!(
        check(
            &base,
            None,
            &cube([1.0, 1.0, 1.0]),
            None,
            "corner to corner"
        )
        .intersecting()
    );
    let d = check(
        &base,
        None,
        &cube([1.5, 0.25, 0.0]),
        None,
        "half a unit apart",
    );
    assert_eq!(d.distance, 0.5);
    let d = check(
        &base,
        None,
        &cube([2.0, 2.0, 2.0]),
        None,
        "corner to corner, apart",
    );
    assert_eq!(d.distance, 3f64.sqrt());
}

#[test]
fn posed_far_and_extreme_meshes_are_brute_forces() {
    let mut sphere = icosphere(1);
    sphere.perturb(0.03, 4);
    let pose = Pose::new(
        [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
        [2.2, 0.1, -0.3],
    )
    .unwrap();
    check(&sphere, None, &sphere, Some(&pose), "posed");
    check(
        &sphere,
        Some(&pose),
        &sphere,
        Some(&Pose::IDENTITY),
        "posed first",
    );
    for (scale, offset) in [(1e-300, 0.0), (1e300, 0.0), (1.0, 1e12)] {
        let mut a = sphere.clone();
        a.scale(scale).translate([offset; 3]);
        let mut b = sphere.clone();
        b.scale(scale)
            .translate([offset + 2.5 * scale, 0.3 * scale, 0.0]);
        check(
            &a,
            None,
            &b,
            None,
            &format!("scale {scale:e}, offset {offset:e}"),
        );
    }
}

#[test]
fn bounds_and_tolerances() {
    let mut a = icosphere(2);
    a.perturb(0.01, 8);
    let mut b = a.clone();
    b.translate([3.0, 0.4, 0.0]);
    let (ma, mb) = (build(&a, VolumeKind::Aabb), build(&b, VolumeKind::Aabb));
    let mut exact = Distance::default();
    distance(
        &ma,
        None,
        &mb,
        None,
        &DistanceOptions::default(),
        &mut exact,
    )
    .unwrap();
    let m = exact.distance;
    // Beyond the bound: not found; at it: found.
    let mut d = Distance::default();
    distance(
        &ma,
        None,
        &mb,
        None,
        &DistanceOptions::default().with_max_distance(0.9 * m),
        &mut d,
    )
    .unwrap();
    assert!(!d.found());
    assert_eq!(d, Distance::default());
    distance(
        &ma,
        None,
        &mb,
        None,
        &DistanceOptions::default().with_max_distance(m),
        &mut d,
    )
    .unwrap();
    assert_eq!(d, exact);
    for (rel, abs) in [(0.1, 0.0), (0.0, 0.05), (0.5, 0.1)] {
        let options = DistanceOptions::default().with_tolerance(rel, abs);
        distance(&ma, None, &mb, None, &options, &mut d).unwrap();
        assert!(
            d.found() && d.distance <= (1.0 + rel) * m + abs + 1e-12,
            "{rel} {abs}: {} against {m}",
            d.distance
        );
        assert!(d.distance >= m);
    }
    // Bad options change nothing.
    let before = d;
    let e = distance(
        &ma,
        None,
        &mb,
        None,
        &DistanceOptions::default().with_max_distance(-1.0),
        &mut d,
    );
    assert!(e.is_err());
    assert_eq!(d, before);
}

#[test]
fn the_scene_distance_is_the_least_of_its_pairs() {
    let mut rng = Rng::new(43);
    let sphere = build(&icosphere(1), VolumeKind::Aabb);
    let ring = build(&torus(0.6, 0.2, 8, 5), VolumeKind::Dvh);
    let mut scene = Scene::new();
    let mut placed = Vec::new();
    for k in 0..6 {
        let t = [
            rng.range(-6.0, 6.0),
            rng.range(-6.0, 6.0),
            rng.range(-1.0, 1.0),
        ];
        let pose = Pose::new(Pose::IDENTITY.rotation(), t).unwrap();
        let mesh = if k % 2 == 0 { &sphere } else { &ring };
        let id = scene.add_rigid(mesh, Some(&pose), 1, u32::MAX).unwrap();
        placed.push((id, mesh.clone(), pose));
    }
    // One pair excluded.
    scene.exclude_pair(placed[0].0, placed[1].0).unwrap();
    let least = |pairs: &[(usize, usize)]| {
        let mut best: Option<(u32, u32, Distance)> = None;
        for &(i, j) in pairs {
            let (a, b) = (&placed[i], &placed[j]);
            let mut d = Distance::default();
            distance(
                &a.1,
                Some(&a.2),
                &b.1,
                Some(&b.2),
                &DistanceOptions::default(),
                &mut d,
            )
            .unwrap();
            if best.as_ref().is_none_or(|x| d.distance < x.2.distance) {
                best = Some((a.0, b.0, d));
            }
        }
        best.unwrap()
    };
    let all: Vec<(usize, usize)> = (0..6)
        .flat_map(|i| (i + 1..6).map(move |j| (i, j)))
        .filter(|&p| p != (0, 1))
        .collect();
    let (i, j, d) = least(&all);
    let found = scene
        .distance(&DistanceOptions::default())
        .unwrap()
        .unwrap();
    assert_eq!((found.object_a, found.object_b), (i, j));
    assert_eq!(found.distance, d);
    // One object's closest other: it is the first side.
    let mine: Vec<(usize, usize)> = (1..6).filter(|&j| j != 1).map(|j| (0, j)).collect();
    let (i, j, d) = least(&mine);
    let found = scene
        .object_distance(placed[0].0, &DistanceOptions::default())
        .unwrap()
        .unwrap();
    assert_eq!((found.object_a, found.object_b), (i, j));
    assert_eq!(found.distance, d);
    assert!(
        scene
            .object_distance(99, &DistanceOptions::default())
            .is_err()
    );
    // Within a bound below the least: none.
    let bound = DistanceOptions::default().with_max_distance(0.5 * d.distance);
    assert_eq!(scene.object_distance(placed[0].0, &bound).unwrap(), None);
}

#[test]
fn intersecting_meshes_report_collides_least_pair() {
    let mut a = icosphere(2);
    a.perturb(0.05, 9);
    let mut b = torus(0.9, 0.3, 12, 8);
    b.translate([0.2, 0.1, 0.0]);
    let (ma, mb) = (build(&a, VolumeKind::Aabb), build(&b, VolumeKind::Aabb));
    let mut pairs = crate::Pairs::new();
    collide(
        &ma,
        None,
        &mb,
        None,
        &crate::QueryOptions::default(),
        &mut pairs,
    )
    .unwrap();
    assert!(!pairs.is_empty());
    let mut d = Distance::default();
    distance(&ma, None, &mb, None, &DistanceOptions::default(), &mut d).unwrap();
    assert!(d.intersecting() && d.found());
    assert_eq!(
        (d.triangle_a, d.triangle_b),
        (pairs.as_slice()[0].a, pairs.as_slice()[0].b)
    );
    assert_eq!(d.stencil, crate::NearPair::default());
}

/// The least intersecting pair, found without finding the others, is `collide`'s first pair on
/// meshes that meet sparsely, densely (a copy, coplanar sheets) and not at all; in place and
/// posed; with every volume kind on each side; with and without a first hit to start from.
#[test]
fn the_least_intersecting_pair_is_collides_first() {
    use crate::query::collide::least_intersecting;
    let mut sphere = icosphere(3);
    sphere.perturb(0.03, 4);
    let mut ring = torus(0.9, 0.3, 24, 12);
    ring.translate([0.2, 0.1, 0.0]);
    let mut far = ring.clone();
    far.translate([5.0, 0.0, 0.0]);
    let sheet = grid(12, 1.0);
    let mut shifted = grid(9, 1.0);
    shifted.translate([0.13, 0.07, 0.0]);
    let soup_a = crate::fixtures::soup(300, 1.0, 0.2, 7);
    let soup_b = crate::fixtures::soup(300, 1.0, 0.2, 8);
    let turn = Pose::new(
        [[0.6, -0.8, 0.0], [0.8, 0.6, 0.0], [0.0, 0.0, 1.0]],
        [0.1, -0.05, 0.02],
    )
    .unwrap();
    let cases: [(&MeshData, &MeshData, &str); 5] = [
        (&sphere, &ring, "sphere and torus"),
        (&sphere, &sphere, "a copy"),
        (&sheet, &shifted, "coplanar sheets"),
        (&soup_a, &soup_b, "soups"),
        (&sphere, &far, "apart"),
    ];
    let mut met = 0;
    for (a, b, what) in cases {
        for va in VOLUMES {
            for vb in VOLUMES {
                let (ma, mb) = (build(a, va), build(b, vb));
                for pose in [None, Some(&turn)] {
                    let mut all = crate::Pairs::new();
                    collide(
                        &ma,
                        None,
                        &mb,
                        pose,
                        &crate::QueryOptions::default(),
                        &mut all,
                    )
                    .unwrap();
                    let first = all.as_slice().first().copied();
                    let hits: Vec<_> = first
                        .into_iter()
                        .chain(all.as_slice().last().copied())
                        .collect();
                    for bound in std::iter::once(None).chain(hits.into_iter().map(Some)) {
                        let mut least = crate::Pairs::new();
                        least_intersecting((&ma, None), (&mb, pose), bound, &mut least).unwrap();
                        let what = format!(
                            "{what}, {va:?}/{vb:?}, posed {}, from {bound:?}",
                            pose.is_some()
                        );
                        assert_eq!(least.as_slice().first().copied(), first, "{what}");
                        assert!(least.len() <= 1, "{what}");
                    }
                    met += usize::from(first.is_some() && pose.is_none());
                }
            }
        }
    }
    assert_eq!(met, 4 * 9, "in place, every case but the apart one meets");
}
