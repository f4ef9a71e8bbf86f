//! Distances through the C ABI. `distance_mesh`: two small sheets or tori bent by the bytes,
//! the second placed by a pose from the bytes, their least distance under options from the
//! bytes, equal to the Rust API's for every thread count and judged by brute force in exact
//! arithmetic (`dvh::fixtures::distance_judge`). `points`: a sheet, a torus or two tori through
//! each other, placed by a pose, and points from the bytes (on vertices, edges and faces, on the
//! grid the meshes are drawn on, anywhere): closest points judged by brute force; winding
//! numbers the same with the axes turned (another ray, meeting other edges and vertices),
//! negated with the triangles reversed, on the surface exactly where the brute-force distance is
//! 0, and the solid angles' count wherever that count is clear; signed distances the closest
//! distances with the winding numbers' sign; an open mesh refused.

use super::input::{Bytes, c_mesh, nudge, pose, rust_pose, small_shape};
use dvh::ffi::*;
use dvh::fixtures::distance_judge::{judge_closest_points, judge_distance};
use dvh::fixtures::oracle::{closest_triangle_brute_force, winding_by_solid_angles};
use dvh::fixtures::rational::q;
use dvh::{
    BuildOptions, ClosestPoint, Distance, DistanceOptions, Mesh, VolumeKind, WINDING_ON_SURFACE,
};

/// A shape from the bytes, bent and nudged (its triangles never change: a closed shape stays
/// closed), and its volume kind.
fn shape(bytes: &mut Bytes) -> (Vec<f64>, Vec<u32>, u32) {
    let kind = bytes.u8();
    let (mut p, triangles) = small_shape(kind);
    let bend = bytes.u8();
    if bend % 2 == 1 {
        let c = f64::from(bend as i8 / 2) / 32.0;
        for q in p.chunks_mut(3) {
            if q[0] > c {
                q[2] += (q[0] - c) / 4.0;
            }
        }
    }
    nudge(bytes, &mut p);
    (p, triangles, u32::from(kind / 8 % 3))
}

/// The mesh through the C ABI with volume kind `volume`, and the same through the Rust API (the
/// same tree: with a tolerance, which of the acceptable answers comes depends on it).
fn meshes(p: &[f64], triangles: &[u32], volume: u32) -> (*mut DvhMesh, Mesh) {
    let mut options = dvh_build_options_default();
    options.volume = volume;
    let kind = [VolumeKind::Dvh, VolumeKind::Sbv, VolumeKind::Aabb][volume as usize];
    let rust =
        Mesh::new(p, triangles, &BuildOptions::default().with_volume(kind)).expect("a valid mesh");
    (c_mesh(p, triangles, &options), rust)
}

/// Distance options from the bytes: no bound, a bound, a tolerance, a bad value.
fn options(bytes: &mut Bytes) -> DvhDistanceOptions {
    let mut o = dvh_distance_options_default();
    match bytes.u8() % 8 {
        0..=2 => {}
        3 => o.max_distance = f64::from(bytes.u8()) / 32.0,
        4 => o.rel_err = f64::from(bytes.u8()) / 64.0,
        5 => o.abs_err = f64::from(bytes.u8()) / 64.0,
        6 => o.max_distance = bytes.f64(),
        _ => {
            o.rel_err = bytes.f64();
            o.abs_err = bytes.f64();
        }
    }
    o
}

/// The Rust reading of valid C options.
fn rust_options(o: &DvhDistanceOptions) -> DistanceOptions {
    DistanceOptions::default()
        .with_max_distance(o.max_distance)
        .with_tolerance(o.rel_err, o.abs_err)
        .with_threads(o.threads)
}

fn valid(o: &DvhDistanceOptions) -> bool {
    [o.max_distance, o.rel_err, o.abs_err]
        .iter()
        .all(|x| *x >= 0.0 && !x.is_nan())
        && o.rel_err.is_finite()
        && o.abs_err.is_finite()
}

pub fn distance_mesh(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let (pa, ta, va) = shape(&mut bytes);
    let (mut pb, tb, vb) = shape(&mut bytes);
    let shift: [f64; 3] = std::array::from_fn(|_| f64::from(bytes.u8() as i8 % 64) / 16.0);
    for q in pb.chunks_mut(3) {
        for k in 0..3 {
            q[k] += shift[k];
        }
    }
    let c_pose = pose(&mut bytes);
    let posed = if bytes.u8().is_multiple_of(2) {
        None
    } else {
        Some(c_pose)
    };
    let mut o = options(&mut bytes);
    let (ca, ra) = meshes(&pa, &ta, va);
    let (cb, rb) = meshes(&pb, &tb, vb);
    let pose_ptr = posed
        .as_ref()
        .map_or(std::ptr::null(), |p| p as *const DvhPose);
    let rust_pose = posed.as_ref().map(rust_pose);
    let mut first: Option<Distance> = None;
    for threads in [1, 2] {
        o.threads = threads;
        let sentinel = DvhDistance {
            found: 7,
            ..Default::default()
        };
        let mut out = sentinel;
        // SAFETY: live handles; the pose and options are readable, the output writable.
        let status = unsafe {
            dvh_distance(
                ca,
                std::ptr::null(),
                cb,
                pose_ptr,
                &o,
                &mut out,
                std::ptr::null_mut(),
            )
        };
        assert_ne!(status, DVH_STATUS_INTERNAL_PANIC);
        let refused_pose = matches!(rust_pose, Some(None));
        if !valid(&o) || refused_pose || status != DVH_STATUS_OK {
            assert!(
                !valid(&o) || refused_pose || status == DVH_STATUS_POSE_OUT_OF_RANGE,
                "status {status}"
            );
            assert_ne!(status, DVH_STATUS_OK);
            assert_eq!(out, sentinel, "a failed call wrote its output");
            break;
        }
        // SAFETY: `DvhDistance` has `Distance`'s layout (the library's layout tests say so).
        let got: Distance = unsafe { std::mem::transmute(out) };
        let options = rust_options(&o);
        let pose = rust_pose.flatten();
        let mut rust = Distance::default();
        dvh::distance(&ra, None, &rb, pose.as_ref(), &options, &mut rust).unwrap();
        assert_eq!(got, rust, "the C answer is the Rust answer");
        match &first {
            Some(f) => assert_eq!(*f, got, "the same for every thread count"),
            None => judge_distance(&ra, None, &rb, pose.as_ref(), &options, &got, "distance"),
        }
        first = Some(got);
    }
    // SAFETY: live handles, each freed once.
    unsafe {
        dvh_mesh_free(ca);
        dvh_mesh_free(cb);
    }
}

/// Points from the bytes about the mesh `p`: its vertices, midpoints of its edges, centroids,
/// points on the sixteenths grid the shapes are drawn on, any doubles.
fn points_about(bytes: &mut Bytes, p: &[f64], triangles: &[u32]) -> Vec<[f64; 3]> {
    let v = |i: u32| -> [f64; 3] { std::array::from_fn(|k| p[3 * i as usize + k]) };
    let t = |i: usize| &triangles[3 * (i % (triangles.len() / 3))..][..3];
    (0..1 + bytes.u8() % 12)
        .map(|_| match bytes.u8() % 6 {
            0 => v(t(usize::from(bytes.u8()))[0]),
            1 => {
                let c = t(usize::from(bytes.u8()));
                let (a, b) = (v(c[0]), v(c[1]));
                std::array::from_fn(|k| 0.5 * (a[k] + b[k]))
            }
            2 => {
                let c = t(usize::from(bytes.u8()));
                let (a, b, d) = (v(c[0]), v(c[1]), v(c[2]));
                std::array::from_fn(|k| (a[k] + b[k] + d[k]) / 3.0)
            }
            3 | 4 => std::array::from_fn(|_| f64::from(bytes.u8() as i8 % 32) / 16.0),
            _ => std::array::from_fn(|_| bytes.f64()),
        })
        .collect()
}

pub fn points(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let (mut p, mut triangles, volume) = shape(&mut bytes);
    if bytes.u8().is_multiple_of(3) {
        // A second copy, moved by sixteenths: two shells through each other (a region wound
        // twice where both are closed).
        let n = (p.len() / 3) as u32;
        let shift: [f64; 3] = std::array::from_fn(|_| f64::from(bytes.u8() as i8 % 16) / 16.0);
        let copy: Vec<f64> = p
            .chunks(3)
            .flat_map(|q| [q[0] + shift[0], q[1] + shift[1], q[2] + shift[2]])
            .collect();
        p.extend(copy);
        triangles.extend(triangles.clone().iter().map(|i| i + n));
    }
    let c_pose = pose(&mut bytes);
    let pose = if bytes.u8().is_multiple_of(2) {
        None
    } else {
        rust_pose(&c_pose).filter(|q| {
            p.chunks(3)
                .flat_map(|v| q.transform_point(&[v[0], v[1], v[2]]))
                .all(|x| x.abs() < dvh::MAX_POSED_MAGNITUDE / 4.0)
        })
    };
    let pose_ptr = if pose.is_some() {
        &c_pose as *const DvhPose
    } else {
        std::ptr::null()
    };
    let points = points_about(&mut bytes, &p, &triangles);
    let mut o = options(&mut bytes);
    o.rel_err = 0.0;
    o.abs_err = 0.0;
    if !valid(&o) {
        o.max_distance = f64::INFINITY;
    }
    let (mesh, rust) = meshes(&p, &triangles, volume);
    let flat: Vec<f64> = points.iter().flatten().copied().collect();
    let n = points.len();
    let finite = flat.iter().all(|x| x.is_finite());

    // Closest points.
    let mut closest = vec![DvhClosestPoint::default(); n];
    let mut first: Option<Vec<DvhClosestPoint>> = None;
    for threads in [1, 2] {
        o.threads = threads;
        closest.fill(DvhClosestPoint {
            found: 9,
            ..Default::default()
        });
        // SAFETY: live handle; `n` points and results.
        let status = unsafe {
            dvh_closest_points(
                mesh,
                pose_ptr,
                flat.as_ptr(),
                n,
                &o,
                closest.as_mut_ptr(),
                std::ptr::null_mut(),
            )
        };
        if !finite {
            assert_eq!(status, DVH_STATUS_NON_FINITE_COORDINATE);
            assert!(closest.iter().all(|c| c.found == 9), "nothing written");
            break;
        }
        assert_eq!(status, DVH_STATUS_OK);
        match &first {
            Some(f) => assert_eq!(f, &closest, "the same for every thread count"),
            None => {
                // SAFETY: `DvhClosestPoint` has `ClosestPoint`'s layout (the library's layout
                // tests say so).
                let got: Vec<ClosestPoint> = closest
                    .iter()
                    .map(|c| unsafe { std::mem::transmute(*c) })
                    .collect();
                judge_closest_points(
                    &rust,
                    pose.as_ref(),
                    &points,
                    o.max_distance,
                    &got,
                    "closest",
                );
            }
        }
        first = Some(closest.clone());
    }

    // Winding numbers and signed distances.
    let mut closed = false;
    // SAFETY: live handle, writable answer.
    assert_eq!(
        unsafe { dvh_mesh_is_closed(mesh, &mut closed) },
        DVH_STATUS_OK
    );
    assert_eq!(closed, rust.is_closed());
    let winding = |m: *const DvhMesh, pose_ptr: *const DvhPose, pts: &[f64], threads: u32| {
        let mut w = vec![17i32; pts.len() / 3];
        // SAFETY: live handle; the counts given.
        let status = unsafe {
            dvh_winding_numbers(
                m,
                pose_ptr,
                pts.as_ptr(),
                pts.len() / 3,
                threads,
                w.as_mut_ptr(),
            )
        };
        (status, w)
    };
    let (status, w) = winding(mesh, pose_ptr, &flat, 1);
    let mut signed = vec![5.0f64; n];
    // SAFETY: live handle; the counts given.
    let signed_status = unsafe {
        dvh_signed_distances(
            mesh,
            pose_ptr,
            flat.as_ptr(),
            n,
            &o,
            signed.as_mut_ptr(),
            std::ptr::null_mut(),
        )
    };
    if !closed || !finite {
        // The mesh is checked first: an open mesh is refused whatever the points.
        let expected = if !closed {
            DVH_STATUS_NOT_CLOSED
        } else {
            DVH_STATUS_NON_FINITE_COORDINATE
        };
        assert_eq!((status, signed_status), (expected, expected));
        assert!(
            w.iter().all(|&x| x == 17) && signed.iter().all(|&x| x == 5.0),
            "nothing written"
        );
    } else {
        assert_eq!((status, signed_status), (DVH_STATUS_OK, DVH_STATUS_OK));
        assert_eq!(
            winding(mesh, pose_ptr, &flat, 2).1,
            w,
            "the same on two threads"
        );
        // The same surface placed by the pose's own arithmetic, its axes turned (x, y, z) to
        // (y, z, x) and its triangles reversed: the ray meets other edges and vertices.
        let placed: Vec<[f64; 3]> = p
            .chunks(3)
            .map(|v| {
                let v = [v[0], v[1], v[2]];
                pose.as_ref().map_or(v, |q| q.transform_point(&v))
            })
            .collect();
        let turn = |v: &[f64; 3]| [v[1], v[2], v[0]];
        let turned: Vec<f64> = placed.iter().flat_map(turn).collect();
        let turned_points: Vec<f64> = points.iter().flat_map(turn).collect();
        let reversed: Vec<u32> = triangles
            .chunks(3)
            .flat_map(|t| [t[0], t[2], t[1]])
            .collect();
        for (tris, sign) in [(&triangles, 1), (&reversed, -1)] {
            let mut options = dvh_build_options_default();
            options.volume = volume;
            let other = c_mesh(&turned, tris, &options);
            let (s, w2) = winding(other, std::ptr::null(), &turned_points, 2);
            assert_eq!(s, DVH_STATUS_OK);
            for (i, (x, y)) in w.iter().zip(&w2).enumerate() {
                let expected = if *x == WINDING_ON_SURFACE {
                    *x
                } else {
                    sign * x
                };
                assert_eq!(
                    *y, expected,
                    "point {i} {:?}: axes turned, sign {sign}",
                    points[i]
                );
            }
            // SAFETY: a live handle, freed once.
            unsafe { dvh_mesh_free(other) };
        }
        for (i, point) in points.iter().enumerate() {
            let (_, d2) = closest_triangle_brute_force(&rust, pose.as_ref(), point, f64::INFINITY)
                .expect("a triangle");
            let on = d2 == q(0.0);
            assert_eq!(
                w[i] == WINDING_ON_SURFACE,
                on,
                "point {i} {point:?}: on the surface"
            );
            // The solid angles' float sum is a clear voice only well off the surface.
            let size = placed
                .iter()
                .flatten()
                .chain(point)
                .fold(f64::MIN_POSITIVE, |m, x| m.max(x.abs()));
            let far = q(1e-6 * size) * q(1e-6 * size) < d2;
            let (count, off) = winding_by_solid_angles(&rust, pose.as_ref(), point);
            if far && off < 0.05 {
                assert_eq!(i64::from(w[i]), count, "point {i} {point:?}: solid angles");
            }
            let c = &first.as_ref().expect("closest points")[i];
            // Off the surface the distance is above 0, even where it rounds to 0.
            let expected = match w[i] {
                WINDING_ON_SURFACE => 0.0,
                _ if c.found == 0 => f64::INFINITY,
                _ => c.distance.max(f64::from_bits(1)),
            };
            let expected = if w[i] != 0 && w[i] != WINDING_ON_SURFACE {
                -expected
            } else {
                expected
            };
            assert_eq!(
                signed[i].to_bits(),
                expected.to_bits(),
                "point {i} {point:?}: signed"
            );
        }
    }
    // SAFETY: a live handle, freed once.
    unsafe { dvh_mesh_free(mesh) };
}
