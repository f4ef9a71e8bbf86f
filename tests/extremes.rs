//! The numerical extremes, on top of `edge_cases.rs`: coordinates scaled by 1e-300 and 1e300 (and
//! near the largest double, where differences overflow), one-triangle meshes, every vertex at
//! one point, every triangle degenerate, a mesh collapsed to a point and restored, rotations
//! orthonormal only within rounding or just within the tolerance, counts and indices at the
//! limits of `uint32_t`. Every query (pair collision, self-collision, proximity, self-proximity)
//! is compared with brute force by the exact predicates, with every volume kind.

use dvh::exact::triangles_intersect;
use dvh::ffi::*;
use dvh::fixtures::oracle::{
    corners, proximity_brute_force, self_collide_brute_force as self_brute_force,
    self_proximity_brute_force,
};
use dvh::fixtures::{MeshData, Rng, grid, icosphere, torus};
use dvh::{
    BuildOptions, Mesh, Pair, Pairs, Pose, QueryMode, QueryOptions, RIGIDITY_TOLERANCE, VolumeKind,
    brute_force, collide, proximity, self_collide, self_proximity,
};

fn sorted(p: &Pairs) -> Vec<Pair> {
    let mut v = p.as_slice().to_vec();
    v.sort_unstable();
    v
}

fn options(volume: VolumeKind) -> BuildOptions {
    BuildOptions::default().with_volume(volume)
}

/// Figures of one scene checked by [`check`].
#[derive(Debug, Default, PartialEq)]
struct Found {
    collide: usize,
    self_a: usize,
    near: usize,
    self_near: usize,
}

/// Builds `a` and `b` with every volume kind and checks the four queries (exact mode, and first
/// hit) against brute force; `d` is the proximity distance. Returns the pair counts (the same
/// for every volume kind). The brute-force answers depend on the coordinates only, so they are
/// computed once, on the first build.
fn check(
    a: &MeshData,
    pa: Option<&Pose>,
    b: &MeshData,
    pb: Option<&Pose>,
    d: f64,
    what: &str,
) -> Found {
    let mut pairs = Pairs::new();
    let mut expected = None;
    for volume in [VolumeKind::Dvh, VolumeKind::Sbv, VolumeKind::Aabb] {
        let ma = Mesh::new(&a.positions, &a.triangles, &options(volume)).expect("mesh a");
        let mb = Mesh::new(&b.positions, &b.triangles, &options(volume)).expect("mesh b");
        ma.validate().expect("valid a");
        mb.validate().expect("valid b");
        let what = format!("{what}, {volume:?}");
        let exact = QueryOptions::default();
        let first = QueryOptions::with_mode(QueryMode::FirstHit);
        let (collide_set, self_set, near_set, self_near_set) = expected.get_or_insert_with(|| {
            let near = proximity_brute_force(&ma, pa, &mb, pb, d);
            let pairs = brute_force(&ma, pa, &mb, pb);
            assert!(
                pairs.iter().all(|p| near.binary_search(p).is_ok()),
                "an intersecting pair is not within {d:e}: {what}"
            );
            (
                pairs,
                self_brute_force(&ma),
                near,
                self_proximity_brute_force(&ma, d),
            )
        });

        collide(&ma, pa, &mb, pb, &exact, &mut pairs).expect("collide");
        assert_eq!(&sorted(&pairs), collide_set, "collide: {what}");
        collide(&ma, pa, &mb, pb, &first, &mut pairs).expect("collide");
        assert_eq!(
            pairs.len(),
            usize::from(!collide_set.is_empty()),
            "first hit: {what}"
        );
        self_collide(&ma, &exact, &mut pairs).expect("self");
        assert_eq!(&sorted(&pairs), self_set, "self-collision: {what}");
        proximity(&ma, pa, &mb, pb, d, &exact, &mut pairs).expect("proximity");
        assert_eq!(&sorted(&pairs), near_set, "proximity {d:e}: {what}");
        self_proximity(&ma, d, &exact, &mut pairs).expect("self-proximity");
        assert_eq!(
            &sorted(&pairs),
            self_near_set,
            "self-proximity {d:e}: {what}"
        );
    }
    let (collide_set, self_set, near_set, self_near_set) = expected.expect("three volume kinds");
    Found {
        collide: collide_set.len(),
        self_a: self_set.len(),
        near: near_set.len(),
        self_near: self_near_set.len(),
    }
}

/// A torus through a sphere, with a crumpled sheet through both: contact, self-contact, near
/// misses, at the unit scale.
fn unit_scene() -> (MeshData, MeshData) {
    let mut a = torus(0.4, 0.15, 10, 6);
    let mut sheet = grid(5, 1.2);
    sheet.translate([-0.6, -0.6, 0.02]);
    sheet.perturb(0.08, 4);
    a.append(&sheet);
    let mut b = icosphere(1);
    b.scale(0.3);
    b.translate([0.45, 0.0, 0.05]);
    (a, b)
}

/// `2^k` exactly, subnormal powers included (`powi` may round those).
fn pow2(k: i32) -> f64 {
    assert!((-1074..=1023).contains(&k));
    if k >= -1022 {
        f64::from_bits(((1023 + k) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (k + 1074))
    }
}

fn scaled(m: &MeshData, s: f64) -> MeshData {
    let mut m = m.clone();
    m.scale(s);
    m
}

/// Scales that round (1e-300, 1e300) change the geometry a little, so the answer is brute
/// force's on the scaled coordinates, whatever it is; at 1e300 the volumes' squared sizes and
/// distances overflow and at 1e-300 they underflow, yet nothing may be lost. Powers of two
/// scale exactly, so there the answer must also be the unit scene's.
#[test]
fn coordinates_scaled_by_1e_minus_300_and_1e300() {
    let (a, b) = unit_scene();
    let d = 0.05;
    let unit = check(&a, None, &b, None, d, "unit scale");
    assert!(unit.collide > 0 && unit.self_a > 0 && unit.near > unit.collide);
    assert!(unit.self_near > unit.self_a);
    let mut exact_scalings = 0;
    for s in [1e-300, 1e300, pow2(-1020), pow2(1000)] {
        let found = check(
            &scaled(&a, s),
            None,
            &scaled(&b, s),
            None,
            d * s,
            &format!("scale {s:e}"),
        );
        assert!(
            found.collide > 0 && found.near > 0,
            "scale {s:e}: {found:?}"
        );
        let exact = [&a, &b]
            .iter()
            .all(|m| m.positions.iter().all(|&x| (x * s) / s == x));
        if exact {
            assert_eq!(found, unit, "scale {s:e}");
            exact_scalings += 1;
        }
    }
    assert!(
        exact_scalings >= 1,
        "2^1000 scales every coordinate exactly"
    );
}

/// Coordinates near the largest double: a difference of two coordinates overflows to infinity.
#[test]
fn coordinates_near_the_largest_double() {
    let (a, b) = unit_scene();
    // Coordinates of the unit scene are within 1 in magnitude; 2^1022 keeps them finite and
    // their differences (up to 2^1023 * 2) at the edge of overflow.
    let s = pow2(1022);
    let found = check(
        &scaled(&a, s),
        None,
        &scaled(&b, s),
        None,
        0.05 * s,
        "scale 2^1022",
    );
    assert!(found.collide > 0);
    // Two triangles on opposite sides of the origin: at +-1e308 their gap overflows to infinity
    // in double arithmetic (and is beyond every finite distance); at +-8e307 it is 1.6e308,
    // whose square overflows.
    let far = |x: f64| MeshData {
        positions: vec![x, 0.0, 0.0, x, 1.0, 0.0, x, 0.0, 1.0],
        triangles: vec![0, 1, 2],
    };
    let found = check(
        &far(-1e308),
        None,
        &far(1e308),
        None,
        f64::MAX,
        "2e308 apart",
    );
    assert_eq!((found.collide, found.near), (0, 0));
    let found = check(
        &far(-8e307),
        None,
        &far(8e307),
        None,
        1.7e308,
        "1.6e308 apart",
    );
    assert_eq!(found.near, 1, "1.6e308 apart is within 1.7e308");
    let found = check(
        &far(-8e307),
        None,
        &far(8e307),
        None,
        1.5e308,
        "1.6e308 apart",
    );
    assert_eq!(found.near, 0, "1.6e308 apart is beyond 1.5e308");
}

/// Distances exactly at the threshold, where squared distances overflow or underflow: two
/// parallel unit triangles (scaled) a gap `g` apart are within `g` and not within the double
/// below it.
#[test]
fn proximity_decides_exactly_at_the_threshold() {
    for k in [-1070, -1000, -500, 0, 500, 1000, 1020] {
        let s = pow2(k);
        let tri = |z: f64| MeshData {
            positions: [0.0, 0.0, z, 1.0, 0.0, z, 0.0, 1.0, z]
                .map(|x| x * s)
                .to_vec(),
            triangles: vec![0, 1, 2],
        };
        let (a, b) = (tri(0.0), tri(0.75));
        let gap = 0.75 * s;
        let within = check(&a, None, &b, None, gap, &format!("gap 2^{k} * 0.75"));
        assert_eq!(within.near, 1, "scale 2^{k}");
        let below = f64::from_bits(gap.to_bits() - 1);
        let short = check(&a, None, &b, None, below, &format!("just below, 2^{k}"));
        assert_eq!(short.near, 0, "scale 2^{k}");
    }
}

#[test]
fn one_triangle_meshes() {
    let one = |p: [f64; 9]| MeshData {
        positions: p.to_vec(),
        triangles: vec![0, 1, 2],
    };
    let a = one([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let through = one([0.2, 0.2, -1.0, 0.3, 0.2, 1.0, 0.2, 0.3, 1.0]);
    let apart = one([0.2, 0.2, 0.5, 0.3, 0.2, 1.0, 0.2, 0.3, 1.0]);
    let hit = check(&a, None, &through, None, 0.1, "through");
    assert_eq!(
        (hit.collide, hit.self_a, hit.near, hit.self_near),
        (1, 0, 1, 0)
    );
    let miss = check(&a, None, &apart, None, 0.5, "apart, within 0.5");
    assert_eq!((miss.collide, miss.near), (0, 1));
    let miss = check(&a, None, &apart, None, 0.49, "apart, beyond 0.49");
    assert_eq!((miss.collide, miss.near), (0, 0));
    // Posed: the same triangle, turned about z by a quarter and moved back onto the first.
    let quarter = Pose::new(
        [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
        [0.0; 3],
    )
    .unwrap();
    let posed = check(&a, None, &a, Some(&quarter), 0.0, "quarter turn");
    assert_eq!((posed.collide, posed.near), (1, 1));
}

/// Every vertex at one point (zero, tiny, huge, far): every triangle is that point, so every
/// pair of the two meshes meets; in one mesh, only pairs sharing no vertex do.
#[test]
fn every_vertex_at_one_point() {
    let shape = torus(0.4, 0.15, 8, 5);
    for p in [
        [0.0; 3],
        [1e-310, -1e-310, 0.0],
        [1e300, -1e300, 1e300],
        [1e15, 1e15, -1e15],
    ] {
        let mut m = shape.clone();
        for v in m.positions.chunks_mut(3) {
            v.copy_from_slice(&p);
        }
        let n = m.triangles.len() / 3;
        let found = check(&m, None, &m, None, 0.0, &format!("all at {p:?}"));
        assert_eq!(found.collide, n * n, "{p:?}");
        assert_eq!(found.near, n * n, "{p:?}");
        assert!(
            found.self_a > 0 && found.self_a == found.self_near,
            "{p:?}: {found:?}"
        );
        // A copy one unit (or one ulp) away: apart.
        let mut other = m.clone();
        for v in other.positions.chunks_mut(3) {
            v[0] = if p[0] == 0.0 {
                1.0
            } else {
                f64::from_bits(p[0].to_bits() + 1)
            };
        }
        let apart = check(&m, None, &other, None, 0.0, &format!("one step from {p:?}"));
        assert_eq!(apart.collide, 0, "{p:?}");
    }
}

/// Every triangle degenerate: segments (collinear corners), repeated indices, points, in a mesh
/// whose triangles share vertices, against itself and a sheet through it.
#[test]
fn every_triangle_degenerate() {
    let mut rng = Rng::new(12);
    let mut m = MeshData::default();
    let n = 60u32;
    for i in 0..n {
        let x = f64::from(i) / f64::from(n);
        let y = rng.range(-0.3, 0.3);
        m.positions.extend([x, y, -0.2, x, y, 0.2, x, y, 0.0]);
    }
    for i in 0..n - 1 {
        let v = 3 * i;
        m.triangles.extend_from_slice(&match i % 4 {
            0 => [v, v + 1, v + 2],         // a segment along z
            1 => [v, v + 3, v + 3],         // a segment between columns
            2 => [v + 2, v + 2, v + 2],     // a point
            _ => [v + 1, v + 4, v + 3 + 1], // a repeated corner
        });
    }
    let mut sheet = grid(6, 1.2);
    sheet.translate([-0.1, -0.6, 0.0]);
    let found = check(&m, None, &sheet, None, 0.01, "degenerate against a sheet");
    assert!(found.collide > 0, "{found:?}");
    check(&m, None, &m, None, 0.01, "degenerate against itself");
}

/// A deformation that collapses a mesh to one point and restores it: while collapsed every pair
/// meets; restored, every answer is the rest shape's again (the refit keeps nothing of the
/// collapse), for every volume kind and through a scene.
#[test]
fn collapse_to_a_point_and_restore() {
    let (a, b) = unit_scene();
    for volume in [VolumeKind::Dvh, VolumeKind::Sbv, VolumeKind::Aabb] {
        let mut ma = Mesh::new(&a.positions, &a.triangles, &options(volume)).unwrap();
        let mb = Mesh::new(&b.positions, &b.triangles, &options(volume)).unwrap();
        let mut pairs = Pairs::new();
        let q = QueryOptions::default();
        let rest = (
            brute_force(&ma, None, &mb, None),
            self_brute_force(&ma),
            proximity_brute_force(&ma, None, &mb, None, 0.05),
        );
        let point = mb.positions()[0]; // a vertex of the sphere b
        for step in [0.5, 0.999, 1.0, 0.999, 0.5, 0.0] {
            let moved: Vec<f64> = a
                .positions
                .chunks(3)
                .flat_map(|p| (0..3).map(move |k| p[k] + (point[k] - p[k]) * step))
                .collect();
            ma.refit(&moved).unwrap();
            ma.validate().unwrap();
            collide(&ma, None, &mb, None, &q, &mut pairs).unwrap();
            assert_eq!(
                sorted(&pairs),
                brute_force(&ma, None, &mb, None),
                "step {step}"
            );
            self_collide(&ma, &q, &mut pairs).unwrap();
            assert_eq!(sorted(&pairs), self_brute_force(&ma), "step {step}");
            proximity(&ma, None, &mb, None, 0.05, &q, &mut pairs).unwrap();
            let near = proximity_brute_force(&ma, None, &mb, None, 0.05);
            assert_eq!(sorted(&pairs), near, "step {step}");
        }
        collide(&ma, None, &mb, None, &q, &mut pairs).unwrap();
        assert_eq!(sorted(&pairs), rest.0);
        self_collide(&ma, &q, &mut pairs).unwrap();
        assert_eq!(sorted(&pairs), rest.1);
        proximity(&ma, None, &mb, None, 0.05, &q, &mut pairs).unwrap();
        assert_eq!(sorted(&pairs), rest.2);

        // The same through a scene: a deformable object collapsed and restored.
        let mut scene = dvh::Scene::new();
        let ida = scene.add_deformable(&ma, u32::MAX, u32::MAX).unwrap();
        let idb = scene.add_deformable(&mb, u32::MAX, u32::MAX).unwrap();
        let mut contacts = dvh::Contacts::new();
        let collapsed: Vec<f64> = a.positions.chunks(3).flat_map(|_| point).collect();
        scene.set_positions(ida, &collapsed).unwrap();
        scene.collide(&q, &mut contacts).unwrap();
        assert_eq!(
            contacts.len(),
            a.triangles.len() / 3 * brute_force_hits_at(&mb, point)
        );
        scene.set_positions(ida, &a.positions).unwrap();
        scene.collide(&q, &mut contacts).unwrap();
        let got: Vec<Pair> = contacts
            .iter()
            .map(|c| {
                assert_eq!((c.object_a, c.object_b), (ida.min(idb), ida.max(idb)));
                Pair { a: c.a, b: c.b }
            })
            .collect();
        assert_eq!(got, rest.0);
    }
}

/// How many triangles of `m` contain the point.
fn brute_force_hits_at(m: &Mesh, p: [f64; 3]) -> usize {
    (0..m.triangle_count())
        .filter(|&t| triangles_intersect(&corners(m, t, None), &[p; 3]))
        .count()
}

/// Rotations orthonormal only within rounding (from angles, from a quaternion, from single
/// precision), and ones off by just under the tolerance: accepted, and every answer is brute
/// force's on the posed coordinates (the volumes are widened by the rotation's stretch). Just
/// over the tolerance: refused.
#[test]
fn rotations_within_rounding_and_at_the_tolerance() {
    let (a, b) = unit_scene();
    let mut rng = Rng::new(7);
    let mut poses = Vec::new();
    for _ in 0..3 {
        let t = rng.range(0.0, std::f64::consts::TAU);
        let (s, c) = t.sin_cos();
        let r = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        poses.push(Pose::new(r, [0.01, -0.02, 0.0]).unwrap());
        let f = r.map(|row| row.map(|x| f64::from(x as f32)));
        poses.push(Pose::new(f, [0.0; 3]).unwrap());
    }
    // Stretched by just under the tolerance along x (the scale's square is what is checked).
    let e = RIGIDITY_TOLERANCE * 0.45;
    let stretched = [[1.0 + e, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    poses.push(Pose::new(stretched, [0.0; 3]).expect("within the tolerance"));
    let sheared = [[1.0, e, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    poses.push(Pose::new(sheared, [0.0; 3]).expect("within the tolerance"));
    for (i, p) in poses.iter().enumerate() {
        check(&a, Some(p), &b, None, 0.05, &format!("pose {i}"));
        check(
            &b,
            None,
            &a,
            Some(p),
            0.05,
            &format!("pose {i}, other side"),
        );
    }
    let too_far = [
        [1.0 + 4.0 * RIGIDITY_TOLERANCE, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    assert!(Pose::new(too_far, [0.0; 3]).is_err());
}

/// Counts and indices at the limits of `uint32_t`, through the C ABI: refused with a status
/// naming the problem before anything is read or allocated.
#[test]
fn counts_and_indices_at_the_limits_of_uint32() {
    let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut mesh = std::ptr::null_mut();
    // SAFETY: every pointer is readable for what the library may read before it refuses the
    // count (nothing: counts are checked first), and the out-parameter is writable.
    unsafe {
        let too_many = 1usize << 32;
        let t = [0u32, 1, 2];
        let s = dvh_mesh_create(
            positions.as_ptr(),
            too_many,
            t.as_ptr(),
            1,
            std::ptr::null(),
            &mut mesh,
        );
        assert_eq!(s, DVH_STATUS_INVALID_ARGUMENT);
        let s = dvh_mesh_create(
            positions.as_ptr(),
            3,
            t.as_ptr(),
            too_many,
            std::ptr::null(),
            &mut mesh,
        );
        assert_eq!(s, DVH_STATUS_INVALID_ARGUMENT);
        let s = dvh_mesh_create(
            positions.as_ptr(),
            usize::MAX,
            t.as_ptr(),
            1,
            std::ptr::null(),
            &mut mesh,
        );
        assert_eq!(s, DVH_STATUS_INVALID_ARGUMENT);
        assert!(mesh.is_null());
        for bad in [3u32, u32::MAX - 1, u32::MAX] {
            let t = [0, bad, 2];
            let s = dvh_mesh_create(
                positions.as_ptr(),
                3,
                t.as_ptr(),
                1,
                std::ptr::null(),
                &mut mesh,
            );
            assert_eq!(s, DVH_STATUS_INDEX_OUT_OF_RANGE, "index {bad}");
            assert!(mesh.is_null());
        }
        let t = [0u32, 1, 2];
        assert_eq!(
            dvh_mesh_create(
                positions.as_ptr(),
                3,
                t.as_ptr(),
                1,
                std::ptr::null(),
                &mut mesh
            ),
            DVH_STATUS_OK
        );
        // Node and object ids at the limit; the largest limits and budgets a query takes.
        let (mut list, mut count) = (std::ptr::null(), 0usize);
        assert_eq!(
            dvh_mesh_node_triangles(mesh, u32::MAX, &mut list, &mut count),
            DVH_STATUS_INVALID_ARGUMENT
        );
        assert_eq!(
            dvh_mesh_refit(mesh, positions.as_ptr(), 1usize << 32),
            DVH_STATUS_INVALID_ARGUMENT
        );
        let pairs = dvh_pairs_new();
        for mode in [
            DVH_QUERY_MODE_TRIANGLES,
            DVH_QUERY_MODE_DEPTH,
            DVH_QUERY_MODE_BUDGET,
        ] {
            let mut q = dvh_query_options_default();
            q.mode = mode;
            q.max_depth = u32::MAX;
            q.max_pairs = u64::MAX;
            q.budget = u64::MAX;
            q.threads = u32::MAX;
            let mut stats = DvhQueryStats::default();
            assert_eq!(
                dvh_collide(
                    mesh,
                    std::ptr::null(),
                    mesh,
                    std::ptr::null(),
                    &q,
                    pairs,
                    &mut stats
                ),
                DVH_STATUS_OK,
                "mode {mode}"
            );
            assert_eq!(dvh_pairs_len(pairs), 1, "mode {mode}");
        }
        let mut scene = std::ptr::null_mut();
        assert_eq!(dvh_scene_create(&mut scene), DVH_STATUS_OK);
        let mut id = 0;
        assert_eq!(
            dvh_scene_add_deformable(scene, mesh, u32::MAX, u32::MAX, &mut id),
            DVH_STATUS_OK
        );
        for bad in [u32::MAX, u32::MAX - 1, id + 1] {
            assert_eq!(dvh_scene_remove(scene, bad), DVH_STATUS_INVALID_ARGUMENT);
            assert_eq!(
                dvh_scene_exclude_pair(scene, id, bad),
                DVH_STATUS_INVALID_ARGUMENT
            );
            assert_eq!(
                dvh_scene_set_positions(scene, bad, positions.as_ptr(), 3),
                DVH_STATUS_INVALID_ARGUMENT
            );
        }
        assert_eq!(
            dvh_scene_set_positions(scene, id, positions.as_ptr(), 1usize << 32),
            DVH_STATUS_INVALID_ARGUMENT
        );
        dvh_scene_free(scene);
        dvh_pairs_free(pairs);
        dvh_mesh_free(mesh);
    }
}
