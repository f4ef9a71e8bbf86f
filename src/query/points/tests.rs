//! The point queries against brute force over every triangle in exact arithmetic, and the
//! winding numbers against independent counts: the solid angles away from the surface, the
//! shapes' own insides, and the same surface with its axes permuted (a ray along another axis,
//! meeting other edges and vertices).

use super::*;
use crate::fixtures::distance_judge::judge_closest_points;
use crate::fixtures::oracle::{closest_triangle_brute_force, corners, winding_by_solid_angles};
use crate::fixtures::rational::q;
use crate::fixtures::{MeshData, Rng, grid, icosphere, torus};
use crate::geometry::predicates::Point;
use crate::{Error, Pose, VolumeKind};

use crate::query::testing::{VOLUMES, build};

/// Points about `m`: random ones in and around its box, its vertices, the midpoints of its
/// edges and the centroids of its triangles, and points a little off those.
fn points_about(m: &MeshData, rng: &mut Rng, random: usize) -> Vec<Point> {
    let b = m.bounds();
    let grow = 0.3 * (0..3).map(|k| b.hi[k] - b.lo[k]).fold(0.0, f64::max);
    let mut points: Vec<Point> = (0..random)
        .map(|_| std::array::from_fn(|k| rng.range(b.lo[k] - grow, b.hi[k] + grow)))
        .collect();
    let v = |i: u32| -> Point { std::array::from_fn(|k| m.positions[3 * i as usize + k]) };
    for t in m.triangles.chunks_exact(3).take(40) {
        let (a, b, c) = (v(t[0]), v(t[1]), v(t[2]));
        points.push(a);
        points.push(std::array::from_fn(|k| 0.5 * (a[k] + b[k])));
        let centroid: Point = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
        points.push(centroid);
        points.push(std::array::from_fn(|k| {
            centroid[k] + 1e-12 * (k as f64 + 1.0)
        }));
    }
    points
}

/// `closest_points` against brute force on `m` for `points`, with every volume kind and thread
/// count the same.
fn check_closest(m: &MeshData, pose: Option<&Pose>, points: &[Point], max: f64, what: &str) {
    let mut first: Option<Vec<ClosestPoint>> = None;
    for volume in VOLUMES {
        let mesh = build(m, volume);
        for threads in [1, 0] {
            let options = DistanceOptions::default()
                .with_max_distance(max)
                .with_threads(threads);
            let mut out = vec![ClosestPoint::default(); points.len()];
            closest_points(&mesh, pose, points, &options, &mut out).unwrap();
            let what = format!("{what}: {volume:?}, {threads} threads");
            match &first {
                Some(f) => assert_eq!(f, &out, "{what}"),
                // Brute force once: the answer depends on the coordinates only.
                None => judge_closest_points(&mesh, pose, points, max, &out, &what),
            }
            first = Some(out);
        }
    }
}

#[test]
fn closest_points_are_brute_forces_on_closed_and_open_meshes() {
    let mut rng = Rng::new(3);
    let mut sphere = icosphere(2);
    sphere.perturb(0.02, 5);
    let mut sheet = grid(8, 2.0);
    sheet.perturb(0.05, 7);
    let ring = torus(1.0, 0.3, 12, 8);
    for (m, what) in [(&sphere, "sphere"), (&sheet, "sheet"), (&ring, "torus")] {
        let points = points_about(m, &mut rng, 150);
        check_closest(m, None, &points, f64::INFINITY, what);
        check_closest(m, None, &points, 0.1, &format!("{what} within 0.1"));
    }
}

#[test]
fn closest_points_of_posed_meshes_and_at_extreme_scales() {
    let mut rng = Rng::new(11);
    let mut sphere = icosphere(1);
    sphere.perturb(0.05, 2);
    let pose = Pose::new(
        [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        [3.0, -1.0, 0.5],
    )
    .unwrap();
    let mut placed = sphere.clone();
    placed.translate([3.0, -1.0, 0.5]);
    let points = points_about(&placed, &mut rng, 100);
    check_closest(&sphere, Some(&pose), &points, f64::INFINITY, "posed");
    for (scale, offset) in [
        (1e-300, 0.0),
        (1e300, 0.0),
        (1.0, 1e12),
        (2f64.powi(-600), 0.0),
    ] {
        let mut m = sphere.clone();
        m.scale(scale).translate([offset; 3]);
        let points = points_about(&m, &mut rng, 60);
        check_closest(
            &m,
            None,
            &points,
            f64::INFINITY,
            &format!("scale {scale:e}, offset {offset:e}"),
        );
    }
}

#[test]
fn a_tolerance_accepts_only_what_it_allows() {
    let mut rng = Rng::new(17);
    let mut m = icosphere(3);
    m.perturb(0.01, 3);
    let mesh = build(&m, VolumeKind::Aabb);
    let points = points_about(&m, &mut rng, 300);
    let (rel, abs) = (0.05, 1e-3);
    let options = DistanceOptions::default().with_tolerance(rel, abs);
    let mut out = vec![ClosestPoint::default(); points.len()];
    closest_points(&mesh, None, &points, &options, &mut out).unwrap();
    for (p, c) in points.iter().zip(&out) {
        let (_, least) = closest_triangle_brute_force(&mesh, None, p, f64::INFINITY).unwrap();
        // d <= (1 + rel) m + abs, in exact arithmetic from the reported triangle's own distance.
        let own = crate::fixtures::oracle::point_triangle_squared(
            p,
            &corners(&mesh, c.triangle as usize, None),
        );
        let root =
            |x: &crate::fixtures::rational::Q| num_traits::ToPrimitive::to_f64(x).unwrap().sqrt();
        let (m, d) = (root(&least), root(&own));
        assert!(d <= (1.0 + rel) * m + abs + 1e-15, "{p:?}: {d} against {m}");
    }
}

#[test]
fn bad_inputs_are_named_and_change_nothing() {
    let mesh = build(&icosphere(1), VolumeKind::Aabb);
    let mut out = vec![ClosestPoint::default(); 2];
    let before = out.clone();
    let e = closest_points(
        &mesh,
        None,
        &[[0.0; 3], [1.0, f64::NAN, 0.0]],
        &DistanceOptions::default(),
        &mut out,
    );
    assert!(
        matches!(
            e,
            Err(Error::NonFinitePoint {
                point: 1,
                axis: 1,
                ..
            })
        ),
        "{e:?}"
    );
    assert_eq!(out, before);
    let e = closest_points(
        &mesh,
        None,
        &[[0.0; 3]],
        &DistanceOptions::default(),
        &mut out,
    );
    assert_eq!(
        e,
        Err(Error::ResultLength {
            expected: 1,
            got: 2
        })
    );
    for (name, options) in [
        (
            "max_distance",
            DistanceOptions::default().with_max_distance(-1.0),
        ),
        (
            "max_distance",
            DistanceOptions::default().with_max_distance(f64::NAN),
        ),
        (
            "rel_err",
            DistanceOptions::default().with_tolerance(-0.1, 0.0),
        ),
        (
            "abs_err",
            DistanceOptions::default().with_tolerance(0.0, f64::INFINITY),
        ),
    ] {
        let e = closest_points(&mesh, None, &[[0.0; 3], [1.0; 3]], &options, &mut out);
        assert!(
            matches!(e, Err(Error::InvalidDistanceOption { name: n, .. }) if n == name),
            "{e:?}"
        );
    }
    assert_eq!(out, before);
    // Winding numbers and signs of an open surface are refused, naming its edge.
    let open = build(&grid(3, 1.0), VolumeKind::Aabb);
    assert!(!open.is_closed());
    let edge = open.open_edge().unwrap();
    let mut w = vec![7; 2];
    let e = winding_numbers(&open, None, &[[0.0; 3], [1.0; 3]], 0, &mut w);
    assert_eq!(e, Err(Error::NotClosed { edge }));
    assert_eq!(w, vec![7; 2]);
    let mut s = vec![7.0; 2];
    let e = signed_distances(
        &open,
        None,
        &[[0.0; 3], [1.0; 3]],
        &DistanceOptions::default(),
        &mut s,
    );
    assert_eq!(e, Err(Error::NotClosed { edge }));
    assert_eq!(s, vec![7.0; 2]);
}

/// `m` with its axes turned x -> y -> z -> x `k` times: the same surface for a ray along +x
/// that runs along another of its axes.
fn permuted(m: &MeshData, k: usize) -> MeshData {
    let mut out = m.clone();
    for (p, q) in out
        .positions
        .chunks_exact_mut(3)
        .zip(m.positions.chunks_exact(3))
    {
        for i in 0..3 {
            p[(i + k) % 3] = q[i];
        }
    }
    out
}

/// Winding numbers of `points` about `m`, checked against the solid angles where the points lie
/// well off the surface and against the same count with the axes permuted everywhere; with
/// every volume kind and thread count the same. Returns them.
fn check_winding(m: &MeshData, points: &[Point], what: &str) -> Vec<i32> {
    let mut first: Option<Vec<i32>> = None;
    for k in 0..3 {
        let mk = permuted(m, k);
        let pk: Vec<Point> = points
            .iter()
            .map(|p| {
                let mut q = [0.0; 3];
                for i in 0..3 {
                    q[(i + k) % 3] = p[i];
                }
                q
            })
            .collect();
        for volume in VOLUMES {
            let mesh = build(&mk, volume);
            for threads in [1, 0] {
                let mut out = vec![0; points.len()];
                winding_numbers(&mesh, None, &pk, threads, &mut out).unwrap();
                if k == 0 && volume == VolumeKind::Aabb && threads == 1 {
                    // The solid angles are a voice away from the surface only: near it their
                    // floating-point sum may land on the wrong integer.
                    let b = mk.bounds();
                    let size = (0..3).map(|k| b.hi[k] - b.lo[k]).fold(0.0, f64::max);
                    let far = q(1e-6 * size) * q(1e-6 * size);
                    for (p, &w) in pk.iter().zip(&out) {
                        let (_, d2) = closest_triangle_brute_force(&mesh, None, p, f64::INFINITY)
                            .expect("a triangle");
                        if d2 > far {
                            let (by_angles, off) = winding_by_solid_angles(&mesh, None, p);
                            assert!(off < 1e-6, "{what}: {p:?} off by {off}");
                            assert_eq!(i64::from(w), by_angles, "{what}: {p:?}");
                        }
                    }
                }
                match &first {
                    None => first = Some(out),
                    Some(f) => {
                        assert_eq!(f, &out, "{what}: axes turned {k}, {volume:?}, {threads}")
                    }
                }
            }
        }
    }
    first.unwrap()
}

#[test]
fn winding_numbers_of_closed_shapes_inside_outside_and_on() {
    let mut rng = Rng::new(23);
    let sphere = icosphere(2);
    let points = points_about(&sphere, &mut rng, 300);
    let w = check_winding(&sphere, &points, "sphere");
    let mesh = build(&sphere, VolumeKind::Aabb);
    for (p, &w) in points.iter().zip(&w) {
        let on = closest_triangle_brute_force(&mesh, None, p, 0.0).is_some();
        assert_eq!(w == WINDING_ON_SURFACE, on, "{p:?}");
        if !on {
            // Convex with outward faces: inside exactly where the point lies below every
            // face's plane.
            let inside = (0..mesh.triangle_count()).all(|t| {
                let c = corners(&mesh, t, None);
                crate::geometry::predicates::orient3d(&c[0], &c[1], &c[2], p) == 1
            });
            assert_eq!(w, i32::from(inside), "{p:?}");
        }
    }
    // The torus: its hole and the far outside are outside, the tube inside.
    let ring = torus(1.0, 0.3, 16, 10);
    let w = check_winding(
        &ring,
        &[
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.05],
            [2.0, 0.0, 0.0],
        ],
        "torus",
    );
    assert_eq!(w, vec![0, 1, 1, 0]);
}

#[test]
fn grid_aligned_points_on_a_grid_aligned_box() {
    // A box of unit cubes' faces, 2 x 2 x 2, its vertices on the integer grid: rays from grid
    // points run along its edges and through its vertices.
    let mut cube = MeshData {
        positions: Vec::new(),
        triangles: Vec::new(),
    };
    let n = 2;
    let mut index = std::collections::HashMap::new();
    let mut vertex = |p: [i64; 3], m: &mut MeshData| -> u32 {
        *index.entry(p).or_insert_with(|| {
            m.positions.extend(p.map(|c| c as f64));
            (m.positions.len() / 3 - 1) as u32
        })
    };
    for axis in 0..3 {
        for side in [0, n] {
            for u in 0..n {
                for v in 0..n {
                    let at = |du: i64, dv: i64| {
                        let mut p = [0; 3];
                        p[axis] = side;
                        p[(axis + 1) % 3] = u + du;
                        p[(axis + 2) % 3] = v + dv;
                        p
                    };
                    let q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
                    let ids: Vec<u32> = q.iter().map(|&p| vertex(p, &mut cube)).collect();
                    // Outward: counter-clockwise seen from outside.
                    let tris = if side == n {
                        [[ids[0], ids[1], ids[2]], [ids[0], ids[2], ids[3]]]
                    } else {
                        [[ids[0], ids[2], ids[1]], [ids[0], ids[3], ids[2]]]
                    };
                    for t in tris {
                        cube.triangles.extend(t);
                    }
                }
            }
        }
    }
    let mut points = Vec::new();
    let mut expected = Vec::new();
    for x in -1..=3 {
        for y in -1..=3 {
            for z in -1..=3 {
                points.push([x as f64, y as f64, z as f64]);
                let c = [x, y, z];
                let inside = c.iter().all(|&c| c > 0 && c < n);
                let on = c.iter().all(|&c| (0..=n).contains(&c)) && !inside;
                expected.push(if on {
                    WINDING_ON_SURFACE
                } else {
                    i32::from(inside)
                });
            }
        }
    }
    assert_eq!(check_winding(&cube, &points, "grid box"), expected);
}

#[test]
fn overlapping_and_nested_shells_wind_twice() {
    // Two overlapping spheres as one closed mesh: their common part is wound twice.
    let mut two = icosphere(2);
    let mut other = icosphere(2);
    other.translate([0.8, 0.0, 0.0]);
    two.append(&other);
    let w = check_winding(
        &two,
        &[
            [0.4, 0.0, 0.0],
            [-0.5, 0.0, 0.0],
            [1.3, 0.0, 0.0],
            [3.0, 0.0, 0.0],
        ],
        "two spheres",
    );
    assert_eq!(w, vec![2, 1, 1, 0]);
    // A shell inside a shell: wound twice inside both; the inner one turned inside out cancels.
    let mut nested = icosphere(2);
    let mut inner = icosphere(1);
    inner.scale(0.5);
    nested.append(&inner);
    let w = check_winding(
        &nested,
        &[[0.0; 3], [0.0, 0.8, 0.0], [0.0, 0.0, 1.5]],
        "nested",
    );
    assert_eq!(w, vec![2, 1, 0]);
    let mut hollow = icosphere(2);
    let mut inner = icosphere(1);
    inner.scale(0.5);
    for t in inner.triangles.chunks_exact_mut(3) {
        t.swap(1, 2);
    }
    hollow.append(&inner);
    let w = check_winding(
        &hollow,
        &[[0.0; 3], [0.0, 0.8, 0.0], [0.0, 0.0, 1.5]],
        "hollow",
    );
    assert_eq!(w, vec![0, 1, 0]);
}

#[test]
fn signed_distances_are_the_closest_distances_with_the_winding_sign() {
    let mut rng = Rng::new(29);
    let mut two = icosphere(2);
    let mut other = icosphere(2);
    other.translate([0.8, 0.1, 0.0]);
    two.append(&other);
    let points = points_about(&two, &mut rng, 200);
    for volume in VOLUMES {
        let mesh = build(&two, volume);
        let mut signed = vec![0.0; points.len()];
        signed_distances(
            &mesh,
            None,
            &points,
            &DistanceOptions::default(),
            &mut signed,
        )
        .unwrap();
        let mut closest = vec![ClosestPoint::default(); points.len()];
        closest_points(
            &mesh,
            None,
            &points,
            &DistanceOptions::default(),
            &mut closest,
        )
        .unwrap();
        let mut winding = vec![0; points.len()];
        winding_numbers(&mesh, None, &points, 0, &mut winding).unwrap();
        for i in 0..points.len() {
            let expected = match winding[i] {
                WINDING_ON_SURFACE => 0.0,
                0 => closest[i].distance,
                _ => -closest[i].distance,
            };
            assert_eq!(
                signed[i].to_bits(),
                expected.to_bits(),
                "{volume:?}: {:?}",
                points[i]
            );
        }
        // Beyond a bound: an infinity of the point's sign.
        let options = DistanceOptions::default().with_max_distance(0.05);
        signed_distances(
            &mesh,
            None,
            &[[0.4, 0.0, 0.0], [5.0, 0.0, 0.0]],
            &options,
            &mut signed[..2],
        )
        .unwrap();
        assert_eq!(signed[..2], [f64::NEG_INFINITY, f64::INFINITY]);
    }
}
