//! Closest-point stencils through the C ABI: sheets and tori bent by the bytes, one placed by a
//! pose from the bytes, queried at distances from the bytes; every answer compared with brute
//! force over every primitive pair by the exact primitive functions of the Rust API, in every
//! mode and thread count, and every stencil checked against what its fields promise.

use super::input::{Bytes, c_mesh, nudge, pose, primitives, rust_pose, small_shape};
use dvh::exact::{Feature, edge_edge_nearest, vertex_face_nearest};
use dvh::ffi::*;

type Key = (u32, u32, u32, u32, u32);

/// One stencil as the brute force computes it.
struct Expected {
    key: Key,
    features: [u32; 2],
    distance: f64,
    points: [[f64; 3]; 2],
    weights: [[f64; 3]; 2],
}

pub fn nearest_mesh(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let kind = bytes.u8();
    let (mut p, triangles) = small_shape(kind);
    let fold = bytes.u8();
    if fold % 2 == 1 {
        let c = f64::from(fold as i8 / 2) / 32.0;
        let lift = f64::from(bytes.u8() % 8) / 16.0;
        for q in p.chunks_mut(3) {
            if q[0] > c {
                q[2] += lift + (q[0] - c) / 8.0;
                q[0] = 2.0 * c - q[0];
            }
        }
    }
    nudge(&mut bytes, &mut p);
    let d = match bytes.u8() % 4 {
        0 => 0.0,
        1 => f64::from(bytes.u8()) / 64.0,
        2 => f64::from(bytes.u8() % 16) / 16.0,
        _ => bytes.f64().abs(),
    };
    let c_pose = pose(&mut bytes);
    let posed = rust_pose(&c_pose);
    let mut options = dvh_build_options_default();
    options.volume = u32::from(kind / 8 % 3);
    let mesh = c_mesh(&p, &triangles, &options);
    let out = dvh_near_pairs_new();
    if !d.is_finite() {
        refused(mesh, d, out);
        return;
    }
    let (tris, edges, used) = primitives(&triangles);
    let at = |q: &[[f64; 3]], v: u32| q[v as usize];
    let own: Vec<[f64; 3]> = p.chunks(3).map(|q| [q[0], q[1], q[2]]).collect();
    for one in [true, false] {
        // The second mesh: the same mesh placed by the pose (a refused pose: refused by the
        // query too, and nothing changes).
        let other: Vec<[f64; 3]> = if one {
            own.clone()
        } else {
            let Some(pose) = &posed else {
                // SAFETY: live handles; the pose is readable.
                let status = unsafe {
                    dvh_nearest_features(
                        mesh,
                        std::ptr::null(),
                        mesh,
                        &c_pose,
                        d,
                        std::ptr::null(),
                        out,
                        std::ptr::null_mut(),
                    )
                };
                assert_ne!(status, DVH_STATUS_OK);
                continue;
            };
            own.iter().map(|q| pose.transform_point(q)).collect()
        };
        if !one
            && other
                .iter()
                .flatten()
                .any(|x| x.abs() > dvh::MAX_POSED_MAGNITUDE / 4.0)
        {
            continue;
        }
        let mut expected = Vec::new();
        let mut push = |key: Key, flip: bool, n: Option<dvh::exact::Nearest>| {
            if let Some(n) = n {
                let (a, b) = if flip { (1, 0) } else { (0, 1) };
                expected.push(Expected {
                    key,
                    features: [n.features[a] as u32, n.features[b] as u32],
                    distance: n.distance,
                    points: [n.points[a], n.points[b]],
                    weights: [n.weights[a], n.weights[b]],
                });
            }
        };
        for &v in &used {
            for (t, c) in tris.iter().enumerate() {
                if one && c.contains(&v) {
                    continue;
                }
                let q = [
                    at(&own, v),
                    at(&other, c[0]),
                    at(&other, c[1]),
                    at(&other, c[2]),
                ];
                push(
                    (0, v, 0, t as u32, 0),
                    false,
                    vertex_face_nearest(&q, d).unwrap(),
                );
                if !one {
                    let q = [
                        at(&other, v),
                        at(&own, c[0]),
                        at(&own, c[1]),
                        at(&own, c[2]),
                    ];
                    push(
                        (1, t as u32, 0, v, 0),
                        true,
                        vertex_face_nearest(&q, d).unwrap(),
                    );
                }
            }
        }
        for (i, x) in edges.iter().enumerate() {
            for y in if one { &edges[i + 1..] } else { &edges[..] } {
                if one && (y.contains(&x[0]) || y.contains(&x[1])) {
                    continue;
                }
                let q = [
                    at(&own, x[0]),
                    at(&own, x[1]),
                    at(&other, y[0]),
                    at(&other, y[1]),
                ];
                push(
                    (2, x[0], x[1], y[0], y[1]),
                    false,
                    edge_edge_nearest(&q, d).unwrap(),
                );
            }
        }
        expected.sort_by_key(|e| e.key);
        for (mode, threads, max_pairs) in [
            (DVH_QUERY_MODE_TRIANGLES, 1, 0),
            (DVH_QUERY_MODE_TRIANGLES, 2, 0),
            (DVH_QUERY_MODE_LEAVES, 1, 0),
            (DVH_QUERY_MODE_DEPTH, 2, 0),
            (DVH_QUERY_MODE_BUDGET, 1, 0),
            (DVH_QUERY_MODE_FIRST_HIT, 2, 0),
            (DVH_QUERY_MODE_TRIANGLES, 2, 2),
        ] {
            let mut o = dvh_query_options_default();
            o.mode = mode;
            o.threads = threads;
            o.max_pairs = max_pairs;
            o.max_depth = 1;
            o.budget = 3;
            let mut stats = std::mem::MaybeUninit::<DvhQueryStats>::uninit();
            // SAFETY: live handles, one thread; the pose is readable.
            let status = unsafe {
                if one {
                    dvh_self_nearest_features(mesh, d, &o, out, stats.as_mut_ptr())
                } else {
                    dvh_nearest_features(
                        mesh,
                        std::ptr::null(),
                        mesh,
                        &c_pose,
                        d,
                        &o,
                        out,
                        stats.as_mut_ptr(),
                    )
                }
            };
            assert_eq!(status, DVH_STATUS_OK);
            // SAFETY: written on success.
            let stats = unsafe { stats.assume_init() };
            // SAFETY: a live buffer.
            let got: &[DvhNearPair] = unsafe {
                let len = dvh_near_pairs_len(out);
                if len == 0 {
                    &[]
                } else {
                    std::slice::from_raw_parts(dvh_near_pairs_data(out), len)
                }
            };
            assert_eq!(stats.pairs, got.len() as u64);
            let key = |x: &DvhNearPair| (x.kind, x.a0, x.a1, x.b0, x.b1);
            assert!(
                got.windows(2).all(|w| key(&w[0]) < key(&w[1])),
                "sorted, no repeats"
            );
            let limit = match (mode, max_pairs) {
                (DVH_QUERY_MODE_FIRST_HIT, _) => 1,
                (_, 0) => usize::MAX,
                (_, m) => m as usize,
            };
            assert_eq!(got.len(), expected.len().min(limit));
            let mut e = expected.iter();
            for x in got {
                let want = e
                    .find(|w| w.key == key(x))
                    .expect("a stencil of the brute force");
                assert_eq!(x.feature_a, want.features[0]);
                assert_eq!(x.feature_b, want.features[1]);
                assert_eq!(x.distance, want.distance);
                assert_eq!([x.closest_a, x.closest_b], want.points);
                assert_eq!([x.weights_a, x.weights_b], want.weights);
                promises(x, d);
            }
        }
    }
    // SAFETY: live handles, each freed once.
    unsafe {
        dvh_near_pairs_free(out);
        dvh_mesh_free(mesh);
    }
}

/// A NaN or infinite distance: the primitive functions and both queries refuse it, the queries
/// with INVALID_ARGUMENT and the output left as it was (empty). Frees `mesh` and `out`.
fn refused(mesh: *mut DvhMesh, d: f64, out: *mut DvhNearPairs) {
    let q = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    for e in [
        vertex_face_nearest(&q, d).unwrap_err(),
        edge_edge_nearest(&q, d).unwrap_err(),
    ] {
        assert!(
            matches!(e, dvh::Error::InvalidDistance { distance } if distance.to_bits() == d.to_bits()),
            "{e}"
        );
    }
    let o = dvh_query_options_default();
    // SAFETY: live handles, one thread; a null pose is the identity; each freed once.
    unsafe {
        assert_eq!(
            dvh_self_nearest_features(mesh, d, &o, out, std::ptr::null_mut()),
            DVH_STATUS_INVALID_ARGUMENT
        );
        assert_eq!(
            dvh_nearest_features(
                mesh,
                std::ptr::null(),
                mesh,
                std::ptr::null(),
                d,
                &o,
                out,
                std::ptr::null_mut(),
            ),
            DVH_STATUS_INVALID_ARGUMENT
        );
        assert_eq!(dvh_near_pairs_len(out), 0);
        dvh_near_pairs_free(out);
        dvh_mesh_free(mesh);
    }
}

/// What a stencil's fields promise on their own.
fn promises(x: &DvhNearPair, d: f64) {
    assert!(
        x.distance >= 0.0 && x.distance <= d,
        "distance {} beyond {d}",
        x.distance
    );
    let corners = |kind: u32, first: bool| match (kind, first) {
        (DVH_IMPACT_KIND_EDGE_EDGE, _) => 2,
        (DVH_IMPACT_KIND_VERTEX_FACE, true) | (DVH_IMPACT_KIND_FACE_VERTEX, false) => 1,
        _ => 3,
    };
    for (f, w, n) in [
        (x.feature_a, x.weights_a, corners(x.kind, true)),
        (x.feature_b, x.weights_b, corners(x.kind, false)),
    ] {
        assert!(w.iter().all(|&v| (0.0..=1.0).contains(&v)), "{w:?}");
        assert!(w[n..].iter().all(|&v| v == 0.0), "{w:?}");
        assert!(
            (w.iter().sum::<f64>() - 1.0).abs() <= 4.0 * f64::EPSILON,
            "{w:?}"
        );
        match n {
            1 => assert_eq!(f, Feature::Vertex0 as u32),
            2 => assert!(f <= Feature::Edge01 as u32 && f != Feature::Vertex2 as u32),
            _ => assert!(f <= Feature::Interior as u32),
        }
        if f <= Feature::Vertex2 as u32 {
            assert_eq!(w[f as usize], 1.0, "a corner feature's weight");
        }
    }
}
