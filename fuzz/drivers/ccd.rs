//! Continuous collision: primitives and moving meshes through the C ABI.

use super::input::{Bytes, c_mesh, nudge, primitives, small_shape};
use super::triangle::oracle;
use dvh::ffi::*;
use dvh::fixtures::ccd_judge::{Primitives, Verdict, judge};

type Points = [[f64; 3]; 4];

/// A primitive test through the C ABI: the time of impact, or `None`. An exact answer is
/// judged by the independent judge (which shares no code with the library's continuous tests):
/// it must not be proved wrong. Primitives whose corners' boxes over the step are apart need no
/// judge: they cannot meet, and the answer must be `None`.
fn impact(edges: bool, start: &Points, end: &Points, mode: DvhCcdMode) -> Option<f64> {
    let toi = library_impact(edges, start, end, mode);
    if mode == DVH_CCD_MODE_EXACT {
        let split = if edges { 2 } else { 1 };
        let apart = (0..3).any(|k| {
            let range = |points: std::ops::Range<usize>| {
                let v = points.flat_map(|i| [start[i][k], end[i][k]]);
                v.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                })
            };
            let (a, b) = (range(0..split), range(split..4));
            a.1 < b.0 || b.1 < a.0
        });
        if apart {
            assert_eq!(
                toi, None,
                "a contact reported for primitives whose boxes are apart"
            );
        } else {
            let primitives = if edges {
                Primitives::EdgeEdge
            } else {
                Primitives::VertexFace
            };
            if let Verdict::Wrong(why) = judge(primitives, start, end, toi) {
                panic!("the exact answer {toi:?} is wrong: {why}\n{start:?}\n{end:?}");
            }
        }
    }
    toi
}

/// The C ABI's answer alone.
fn library_impact(edges: bool, start: &Points, end: &Points, mode: DvhCcdMode) -> Option<f64> {
    let mut options = dvh_ccd_options_default();
    options.mode = mode;
    let (mut hit, mut toi) = (false, -1.0);
    let (s, e) = (start.as_flattened(), end.as_flattened());
    // SAFETY: 12 doubles each; the outputs are locals.
    let status = unsafe {
        if edges {
            dvh_ccd_edge_edge(s.as_ptr(), e.as_ptr(), &options, &mut hit, &mut toi)
        } else {
            dvh_ccd_vertex_face(s.as_ptr(), e.as_ptr(), &options, &mut hit, &mut toi)
        }
    };
    assert_eq!(status, DVH_STATUS_OK);
    if hit {
        assert!((0.0..=1.0).contains(&toi), "time {toi} outside the step");
        Some(toi)
    } else {
        assert_eq!(toi, -1.0, "time written on a miss");
        None
    }
}

/// Do the primitives touch at these positions (the static exact oracle, a point or segment as a
/// degenerate triangle)?
fn touching(edges: bool, p: &Points) -> bool {
    if edges {
        oracle(&[p[0], p[1], p[1]], &[p[2], p[3], p[3]])
    } else {
        oracle(&[p[0], p[0], p[0]], &[p[1], p[2], p[3]])
    }
}

/// Primitive target: a vertex-face or edge-edge motion on a grid of sixteenths (so coplanar,
/// collinear, touching and degenerate motions are common), at a power-of-two scale and offset.
/// Judged by what must hold of the exact answer whatever it is: it does not change when the
/// corners are permuted, the edges swapped or reversed, the scene scaled or shifted exactly;
/// it is 0 when the primitives touch at the start, it exists when they touch at the end or the
/// reversed motion meets; the conservative mode never misses it nor reports a later time.
pub fn ccd_primitive(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let head = bytes.u8();
    let edges = head % 2 == 1;
    let mut start = [[0.0; 3]; 4];
    let mut end = [[0.0; 3]; 4];
    for p in start.iter_mut().chain(end.iter_mut()) {
        for x in p.iter_mut() {
            *x = f64::from(bytes.u8() as i8 % 24) / 16.0;
        }
    }
    // A degenerate pattern now and then: a point of the end on another, one not moving.
    match head / 2 % 4 {
        1 => end[3] = end[2],
        2 => start[1] = end[1],
        _ => {}
    }
    let exact = impact(edges, &start, &end, DVH_CCD_MODE_EXACT);
    let conservative = impact(edges, &start, &end, DVH_CCD_MODE_CONSERVATIVE);
    if let Some(t) = exact {
        let c = conservative.expect("the conservative mode missed a contact");
        assert!(c <= t, "conservative time {c} after the exact {t}");
    }
    if touching(edges, &start) {
        assert_eq!(exact, Some(0.0), "touching at the start");
    }
    if touching(edges, &end) {
        assert!(exact.is_some(), "touching at the end");
    }
    assert_eq!(
        exact.is_some(),
        impact(edges, &end, &start, DVH_CCD_MODE_EXACT).is_some(),
        "the reversed motion meets iff the motion does"
    );
    // Symmetries: the same contact set, so the same time.
    let permutation: [usize; 4] = if edges {
        [[0, 1, 2, 3], [1, 0, 2, 3], [2, 3, 0, 1], [3, 2, 1, 0]][usize::from(head / 8 % 4)]
    } else {
        [[0, 1, 2, 3], [0, 2, 3, 1], [0, 3, 2, 1], [0, 1, 3, 2]][usize::from(head / 8 % 4)]
    };
    let permute = |p: &Points| permutation.map(|i| p[i]);
    assert_eq!(
        library_impact(edges, &permute(&start), &permute(&end), DVH_CCD_MODE_EXACT),
        exact,
        "permuted {permutation:?}"
    );
    // Scaled by a power of two and shifted by a multiple of the grid: every coordinate exact.
    let scale = 2f64.powi(i32::from(bytes.u8() as i8) * 4);
    let shift = f64::from(bytes.u8() as i8) * 4.0;
    let moved = |p: &Points| p.map(|q| q.map(|x| (x + shift) * scale));
    assert_eq!(
        library_impact(edges, &moved(&start), &moved(&end), DVH_CCD_MODE_EXACT),
        exact,
        "scaled by {scale:e}, shifted by {shift}"
    );
}

/// Mesh target: a small sheet or torus moved by the bytes between two frames, each vertex
/// by sixteenths or the whole by a fold; `dvh_self_continuous_collide` and
/// `dvh_continuous_collide` (against a moved copy) in both modes and with every option,
/// against brute force over every primitive pair through the C primitive tests.
pub fn ccd_mesh(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let kind = bytes.u8();
    let (rest, triangles) = small_shape(kind);
    let n = rest.len() / 3;
    let frame = |bytes: &mut Bytes| -> Vec<f64> {
        let mut p = rest.clone();
        let fold = bytes.u8();
        if fold % 2 == 1 {
            let c = f64::from(fold as i8 / 2) / 32.0;
            for q in p.chunks_mut(3) {
                if q[0] > c {
                    q[2] += q[0] - c;
                    q[0] = 2.0 * c - q[0];
                }
            }
        }
        nudge(bytes, &mut p);
        p
    };
    let (start, end) = (frame(&mut bytes), frame(&mut bytes));
    let mut options = dvh_build_options_default();
    options.volume = u32::from(kind / 8 % 3);
    let make = || c_mesh(&rest, &triangles, &options);
    let (mesh, other) = (make(), make());
    // The other mesh moves the opposite way, shifted by the bytes.
    let shift = [0, 1, 2].map(|_| f64::from(bytes.u8() as i8 % 8) / 16.0);
    let other_start: Vec<f64> = end
        .iter()
        .enumerate()
        .map(|(i, x)| x + shift[i % 3])
        .collect();
    let other_end: Vec<f64> = start
        .iter()
        .enumerate()
        .map(|(i, x)| x + shift[i % 3])
        .collect();
    // SAFETY: live meshes, their vertex counts.
    unsafe {
        assert_eq!(
            dvh_mesh_refit_motion(mesh, start.as_ptr(), end.as_ptr(), n),
            DVH_STATUS_OK
        );
        assert_eq!(
            dvh_mesh_refit_motion(other, other_start.as_ptr(), other_end.as_ptr(), n),
            DVH_STATUS_OK
        );
    }
    let impacts = dvh_impacts_new();
    let (tris, edges, used) = primitives(&triangles);
    let at = |p: &[f64], v: u32| {
        [
            p[3 * v as usize],
            p[3 * v as usize + 1],
            p[3 * v as usize + 2],
        ]
    };
    for mode in [DVH_CCD_MODE_EXACT, DVH_CCD_MODE_CONSERVATIVE] {
        for one in [true, false] {
            let (sb, eb) = if one {
                (&start, &end)
            } else {
                (&other_start, &other_end)
            };
            let mut expected: Vec<(u32, u32, u32, u32, u32, f64)> = Vec::new();
            for &v in &used {
                for (t, c) in tris.iter().enumerate() {
                    if one && c.contains(&v) {
                        continue;
                    }
                    let s = [at(&start, v), at(sb, c[0]), at(sb, c[1]), at(sb, c[2])];
                    let e = [at(&end, v), at(eb, c[0]), at(eb, c[1]), at(eb, c[2])];
                    if let Some(toi) = impact(false, &s, &e, mode) {
                        expected.push((0, v, 0, t as u32, 0, toi));
                    }
                    if !one {
                        let s = [
                            at(sb, v),
                            at(&start, c[0]),
                            at(&start, c[1]),
                            at(&start, c[2]),
                        ];
                        let e = [at(eb, v), at(&end, c[0]), at(&end, c[1]), at(&end, c[2])];
                        if let Some(toi) = impact(false, &s, &e, mode) {
                            expected.push((1, t as u32, 0, v, 0, toi));
                        }
                    }
                }
            }
            for (i, x) in edges.iter().enumerate() {
                for y in if one { &edges[i + 1..] } else { &edges[..] } {
                    if one && (y.contains(&x[0]) || y.contains(&x[1])) {
                        continue;
                    }
                    let s = [
                        at(&start, x[0]),
                        at(&start, x[1]),
                        at(sb, y[0]),
                        at(sb, y[1]),
                    ];
                    let e = [at(&end, x[0]), at(&end, x[1]), at(eb, y[0]), at(eb, y[1])];
                    if let Some(toi) = impact(true, &s, &e, mode) {
                        expected.push((2, x[0], x[1], y[0], y[1], toi));
                    }
                }
            }
            expected.sort_by(|p, q| p.partial_cmp(q).unwrap());
            for (threads, earliest_only, max_impacts) in
                [(1, false, 0), (2, false, 0), (1, true, 0), (2, false, 2)]
            {
                let mut o = dvh_ccd_options_default();
                o.mode = mode;
                o.threads = threads;
                o.earliest_only = earliest_only;
                o.max_impacts = max_impacts;
                let mut stats = std::mem::MaybeUninit::<DvhCcdStats>::uninit();
                // SAFETY: live handles, one thread.
                let status = unsafe {
                    if one {
                        dvh_self_continuous_collide(mesh, &o, impacts, stats.as_mut_ptr())
                    } else {
                        dvh_continuous_collide(mesh, other, &o, impacts, stats.as_mut_ptr())
                    }
                };
                assert_eq!(status, DVH_STATUS_OK);
                // SAFETY: written on success.
                let stats = unsafe { stats.assume_init() };
                // SAFETY: a live buffer.
                let got: Vec<(u32, u32, u32, u32, u32, f64)> = unsafe {
                    let len = dvh_impacts_len(impacts);
                    let data = dvh_impacts_data(impacts);
                    (0..len)
                        .map(|i| {
                            let x = &*data.add(i);
                            (x.kind, x.a0, x.a1, x.b0, x.b1, x.toi)
                        })
                        .collect()
                };
                assert_eq!(stats.impacts, got.len() as u64);
                if earliest_only {
                    let first = expected.iter().min_by(|p, q| {
                        (p.5, p.0, p.1, p.2, p.3, p.4)
                            .partial_cmp(&(q.5, q.0, q.1, q.2, q.3, q.4))
                            .unwrap()
                    });
                    assert_eq!(got.first(), first, "earliest only");
                } else if max_impacts > 0 && expected.len() >= max_impacts as usize {
                    assert_eq!(got.len(), max_impacts as usize);
                    assert!(stats.truncated);
                    assert!(got.iter().all(|x| expected.contains(x)));
                } else {
                    assert_eq!(got, expected, "mode {mode}, self {one}, {threads} threads");
                }
            }
        }
    }
    // SAFETY: live handles, released once.
    unsafe {
        dvh_impacts_free(impacts);
        dvh_mesh_free(mesh);
        dvh_mesh_free(other);
    }
}
