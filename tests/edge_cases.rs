//! Numerical extremes and exact contact: touching copies, coplanar sheets, near-touching offsets,
//! tiny and huge coordinates, far from the origin, degenerate triangles. Every query is checked
//! against the brute-force oracle in every mode, with every build option.

mod common;

use common::{Body, all_build_options, check_all_modes, random_pose};
use dvh::fixtures::{MeshData, Rng, grid, icosphere, soup, torus};
use dvh::{
    BuildOptions, LeftoverPolicy, Mesh, Pair, Pairs, Pose, QueryOptions, RadiusKind, TreeKind,
    VolumeKind, brute_force, collide,
};

fn body(m: &MeshData, options: &BuildOptions) -> Body {
    Body::new(m.clone(), 5, 0.1, None, options)
}

fn posed_body(m: &MeshData, options: &BuildOptions, pose: Pose) -> Body {
    Body::new(m.clone(), 5, 0.1, Some(pose), options)
}

#[test]
fn a_mesh_touches_an_exact_copy_of_itself() {
    for options in all_build_options() {
        for m in [icosphere(2), torus(0.4, 0.15, 12, 8), grid(6, 1.0)] {
            let (a, b) = (body(&m, &options), body(&m, &options));
            let mut pairs = Pairs::new();
            let exact = check_all_modes(&a, &b, 2, &mut pairs);
            // Every triangle touches itself and every triangle sharing a vertex with it, and
            // nothing else: none of these surfaces touches itself away from shared vertices.
            let shares = |s: usize, t: usize| {
                let (s, t) = (&m.triangles[s * 3..][..3], &m.triangles[t * 3..][..3]);
                s.iter().any(|v| t.contains(v))
            };
            let n = m.triangle_count();
            let sharing: Vec<Pair> = (0..n)
                .flat_map(|s| (0..n).filter(move |&t| shares(s, t)).map(move |t| (s, t)))
                .map(|(s, t)| Pair {
                    a: s as u32,
                    b: t as u32,
                })
                .collect();
            assert_eq!(exact, sharing, "{n} triangles");
        }
    }
}

#[test]
fn coplanar_sheets_overlap_touch_and_separate_exactly() {
    let sheet = grid(8, 1.0);
    for options in all_build_options() {
        let a = body(&sheet, &options);
        let mut pairs = Pairs::new();
        // In-plane shifts: overlapping, touching along an edge, disjoint by one ulp.
        for (dx, dy, expect_contact) in [
            (0.3, 0.45, true),
            (1.0, 0.0, true),
            (1.0 + f64::EPSILON * 2.0, 0.0, false),
        ] {
            let mut s = sheet.clone();
            s.translate([dx, dy, 0.0]);
            let b = body(&s, &options);
            let exact = check_all_modes(&a, &b, 3, &mut pairs);
            assert_eq!(!exact.is_empty(), expect_contact, "shift ({dx}, {dy})");
        }
        // Offsets along the normal: any positive offset separates.
        for dz in [
            0.0,
            1e-9,
            1e-12,
            1e-15,
            2f64.powi(-60),
            2f64.powi(-1000),
            5e-324,
        ] {
            let mut s = sheet.clone();
            s.translate([0.25, 0.25, dz]);
            let b = body(&s, &options);
            let exact = check_all_modes(&a, &b, 3, &mut pairs);
            assert_eq!(exact.is_empty(), dz > 0.0, "offset {dz:e}");
        }
    }
}

#[test]
fn near_touching_spheres() {
    let options = BuildOptions::default();
    let s = icosphere(3);
    let a = body(&s, &options);
    let mut pairs = Pairs::new();
    // Unit spheres whose centres are 2 + d apart along x: the closest vertices are at x = ±1.
    // 2^-51 is one ulp of 2: the smallest gap the translation can make.
    for d in [-1e-3, 0.0, 1e-9, 1e-12, 1e-15, 2f64.powi(-51)] {
        let mut m = s.clone();
        m.translate([2.0 + d, 0.0, 0.0]);
        let b = body(&m, &options);
        let exact = check_all_modes(&a, &b, 2, &mut pairs);
        assert_eq!(exact.is_empty(), d > 0.0, "gap {d:e}");
    }
}

/// Scales a scene by a power of two: exact unless values leave the normal range, so the pairs
/// must be those of the unscaled scene.
#[test]
fn tiny_and_huge_coordinates() {
    let mut a_shape = torus(0.4, 0.15, 16, 10);
    a_shape.translate([0.3, 0.1, 0.05]);
    let mut b_shape = icosphere(2);
    b_shape.scale(0.5);
    b_shape.translate([0.7, 0.0, 0.0]);
    let mut c_shape = soup(150, 1.0, 0.3, 9);
    c_shape.translate([-0.2, -0.3, -0.1]);
    let sbv = BuildOptions::default()
        .with_tree(TreeKind::Binary)
        .with_radius(RadiusKind::Wrapped)
        .with_leftovers(LeftoverPolicy::ExtraRings)
        .with_volume(VolumeKind::Sbv)
        .with_refit_threads(1);
    let aabb = BuildOptions::default()
        .with_tree(TreeKind::Binary)
        .with_volume(VolumeKind::Aabb);
    for options in [BuildOptions::default(), sbv, aabb] {
        let mut pairs = Pairs::new();
        let reference_ab = check_all_modes(
            &body(&a_shape, &options),
            &body(&b_shape, &options),
            3,
            &mut pairs,
        );
        let reference_ac = check_all_modes(
            &body(&a_shape, &options),
            &body(&c_shape, &options),
            3,
            &mut pairs,
        );
        assert!(!reference_ab.is_empty() && !reference_ac.is_empty());
        for k in [-1000, -700, -400, -160, -60, 60, 160, 400, 700, 1000] {
            let s = 2f64.powi(k);
            let scaled = |m: &MeshData| {
                let mut m = m.clone();
                m.scale(s);
                m
            };
            // Rest shapes only: the deformation is not scale-exact.
            let make = |m: &MeshData| Body::new(scaled(m), 1, 0.0, None, &options);
            let (a, b, c) = (make(&a_shape), make(&b_shape), make(&c_shape));
            let ab = check_all_modes(&a, &b, 3, &mut pairs);
            let ac = check_all_modes(&a, &c, 3, &mut pairs);
            // Morph with amplitude 0 leaves the rest shape; the pairs are the unscaled ones.
            let rest_ab = {
                let a0 = Body::new(a_shape.clone(), 1, 0.0, None, &options);
                let b0 = Body::new(b_shape.clone(), 1, 0.0, None, &options);
                brute_force(&a0.mesh, None, &b0.mesh, None)
            };
            let scaling_exact = [&a_shape, &b_shape]
                .iter()
                .all(|m| m.positions.iter().all(|&x| (x * s) / s == x));
            if scaling_exact {
                assert_eq!(ab, rest_ab, "scale 2^{k}");
            }
            assert!(!ac.is_empty(), "scale 2^{k}");
        }
    }
}

/// One option set per volume kind.
fn each_volume_kind() -> [BuildOptions; 3] {
    [VolumeKind::Dvh, VolumeKind::Sbv, VolumeKind::Aabb]
        .map(|volume| BuildOptions::default().with_volume(volume))
}

#[test]
fn far_from_the_origin() {
    let mut pairs = Pairs::new();
    for (offset, options) in [1e6, 1e9, 1e12, 1e15, -3e17]
        .into_iter()
        .flat_map(|o| each_volume_kind().map(|k| (o, k)))
    {
        let mut a = torus(0.4, 0.15, 16, 10);
        let mut b = icosphere(2);
        b.scale(0.5);
        b.translate([0.6, 0.0, 0.0]);
        a.translate([offset; 3]);
        b.translate([offset; 3]);
        let exact = check_all_modes(&body(&a, &options), &body(&b, &options), 3, &mut pairs);
        if offset.abs() <= 1e12 {
            assert!(!exact.is_empty(), "offset {offset:e}");
        }
        // The same scene at the origin, moved out there by poses.
        let mut a0 = torus(0.4, 0.15, 16, 10);
        a0.translate([0.0; 3]);
        let pose = Pose::new(Pose::IDENTITY.rotation(), [offset; 3]).unwrap();
        let mut b0 = icosphere(2);
        b0.scale(0.5);
        b0.translate([0.6, 0.0, 0.0]);
        check_all_modes(
            &posed_body(&a0, &options, pose),
            &posed_body(&b0, &options, pose),
            3,
            &mut pairs,
        );
    }
}

#[test]
fn degenerate_triangles_segments_and_points() {
    // A mesh made only of zero-area triangles: collinear, repeated corners, single points.
    let mut rng = Rng::new(3);
    let mut m = MeshData::default();
    for i in 0..300u32 {
        let p = [
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
            rng.range(0.0, 1.0),
        ];
        let d = [
            rng.range(-0.2, 0.2),
            rng.range(-0.2, 0.2),
            rng.range(-0.2, 0.2),
        ];
        let q = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
        let mid = [p[0] + d[0] * 0.5, p[1] + d[1] * 0.5, p[2] + d[2] * 0.5];
        m.positions.extend(p.iter().chain(&q).chain(&mid));
        let v = i * 3;
        m.triangles.extend_from_slice(&match i % 3 {
            0 => [v, v + 1, v + 2],
            1 => [v, v, v + 1],
            _ => [v, v, v],
        });
    }
    let mut sheet = grid(10, 1.0);
    sheet.translate([0.0, 0.0, 0.5]);
    for options in all_build_options() {
        let mut pairs = Pairs::new();
        let exact = check_all_modes(&body(&m, &options), &body(&sheet, &options), 3, &mut pairs);
        assert!(!exact.is_empty());
        check_all_modes(&body(&m, &options), &body(&m, &options), 3, &mut pairs);
    }
}

#[test]
fn explicit_identity_pose_is_no_pose() {
    let a = Mesh::new(
        &icosphere(2).positions,
        &icosphere(2).triangles,
        &BuildOptions::default(),
    )
    .unwrap();
    let mut bm = icosphere(2);
    bm.translate([1.5, 0.2, 0.0]);
    let b = Mesh::new(&bm.positions, &bm.triangles, &BuildOptions::default()).unwrap();
    let mut p1 = Pairs::new();
    let mut p2 = Pairs::new();
    let s1 = collide(&a, None, &b, None, &QueryOptions::default(), &mut p1).unwrap();
    let s2 = collide(
        &a,
        Some(&Pose::IDENTITY),
        &b,
        Some(&Pose::default()),
        &QueryOptions::default(),
        &mut p2,
    )
    .unwrap();
    assert!(!p1.is_empty());
    assert_eq!(p1.as_slice(), p2.as_slice());
    assert_eq!(s1, s2);
}

#[test]
fn rotations_from_single_precision_are_accepted_and_exact() {
    let mut rng = Rng::new(11);
    let options = BuildOptions::default();
    let mut pairs = Pairs::new();
    for _ in 0..10 {
        let r = random_pose(&mut rng, 0.5).rotation();
        // Round the rotation through f32, as engines store it: orthonormal only to about 1e-7.
        let r32 = r.map(|row| row.map(|x| f64::from(x as f32)));
        let pose = Pose::new(r32, [0.2, 0.1, 0.0]).expect("f32 rotation accepted");
        let a = posed_body(&torus(0.4, 0.15, 20, 12), &options, pose);
        let b = body(&icosphere(2), &options);
        check_all_modes(&a, &b, 2, &mut pairs);
    }
}

#[test]
fn deformation_over_many_frames_with_all_options() {
    for options in all_build_options() {
        let mut rng = Rng::new(17);
        let mut a = Body::new(
            icosphere(3),
            1,
            0.25,
            Some(random_pose(&mut rng, 0.3)),
            &options,
        );
        let mut bm = torus(0.5, 0.2, 24, 12);
        bm.translate([0.6, 0.0, 0.0]);
        let mut b = Body::new(bm, 2, 0.25, None, &options);
        let mut pairs = Pairs::new();
        let mut contact_frames = 0;
        for frame in 0..12 {
            let t = f64::from(frame) / 12.0;
            a.deform(t);
            b.deform(t);
            if !check_all_modes(&a, &b, 3, &mut pairs).is_empty() {
                contact_frames += 1;
            }
        }
        assert!(contact_frames > 0);
    }
}

fn single(t: [[f64; 3]; 3], options: &BuildOptions) -> Mesh {
    Mesh::new(t.as_flattened(), &[0, 1, 2], options).unwrap()
}

/// Two triangles whose one-leaf volumes touch at exactly the point where the triangles touch:
/// `a` is posed, `b` is built from `a`'s world coordinates. Only the widening of posed volumes
/// (the rotation's stretch, the rounding of the transformation) keeps the pair: for spheres
/// centred on corner 0, the touching point is at the full radius; for boxes it is a corner of
/// the rotated box's bound on some axis.
#[test]
fn posed_volumes_are_widened_enough() {
    let mut rng = Rng::new(23);
    let mut pairs = Pairs::new();
    let mut hits = 0;
    for (trial, options) in (0..400).flat_map(|t| each_volume_kind().map(|k| (t, k))) {
        let exact = random_pose(&mut rng, 1.0);
        // Half the trials stretch the rotation to near the rigidity tolerance; the other half put
        // the triangle far from the origin, where the transformation rounds coarsely.
        let (rotation, translation) = if trial % 2 == 0 {
            let s = 1.0 + 4e-6;
            (
                exact.rotation().map(|r| r.map(|x| x * s)),
                exact.translation(),
            )
        } else {
            (exact.rotation(), exact.translation().map(|x| x * 1e8 + 3e7))
        };
        let pose = Pose::new(rotation, translation).unwrap();
        // Local triangle: the leaf is centred on corner 0, its radius is |corner 1| = 1.
        let local = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.5, 0.0]];
        let w = local.map(|p| pose.transform_point(&p));
        // b: centred on its corner 0, at w1 + (w1 - w0), touching a at w1.
        let far = [0, 1, 2].map(|k| w[1][k] + (w[1][k] - w[0][k]));
        let side = [0, 1, 2].map(|k| far[k] + (w[2][k] - w[0][k]));
        let a = single(local, &options);
        let b = single([far, w[1], side], &options);
        let expected = brute_force(&a, Some(&pose), &b, None);
        collide(
            &a,
            Some(&pose),
            &b,
            None,
            &QueryOptions::default(),
            &mut pairs,
        )
        .unwrap();
        assert_eq!(
            pairs.as_slice(),
            &expected[..],
            "trial {trial}, {options:?}"
        );
        collide(
            &b,
            None,
            &a,
            Some(&pose),
            &QueryOptions::default(),
            &mut pairs,
        )
        .unwrap();
        assert_eq!(pairs.len(), expected.len(), "trial {trial} swapped");
        hits += expected.len();
    }
    assert!(hits > 900, "the triangles touch in most trials: {hits}");
}
