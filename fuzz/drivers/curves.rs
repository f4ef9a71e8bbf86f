//! Intersection curves of two meshes and of one mesh, of surfaces moved, folded and pinched by
//! the bytes.

use super::input::Bytes;
use dvh::ffi::*;
use dvh::fixtures::curve_judge::{World, judge, reported_pairs};
use dvh::fixtures::oracle::self_collide_brute_force;
use dvh::{BuildOptions, Curves, Mesh, Pair, Pose, QueryOptions};

/// A surface with real topology (a sheet, a torus, a sphere) on a grid of sixteenths, so that
/// moves keep exact coincidences: coplanar, touching and edge-through-vertex cases are common.
fn shape(bytes: &mut Bytes) -> (Vec<f64>, Vec<u32>) {
    use dvh::fixtures::{grid, icosphere, torus};
    let kind = bytes.u8();
    let size = usize::from(bytes.u8());
    let s = match kind % 3 {
        0 => grid(1 + size % 6, 1.0),
        1 => torus(0.5, 0.25, 3 + size % 5, 3 + size / 5 % 4),
        _ => icosphere(u32::from(size % 2 == 1)),
    };
    let positions = s
        .positions
        .iter()
        .map(|&x| (x * 16.0).round() / 16.0)
        .collect();
    (positions, s.triangles)
}

/// A pose whose arithmetic is exact on sixteenths: a signed permutation (a rotation) and a
/// translation by sixteenths; or none.
fn pose(bytes: &mut Bytes) -> Option<Pose> {
    let b = bytes.u8();
    if b.is_multiple_of(3) {
        return None;
    }
    let perm = [
        [0, 1, 2],
        [1, 2, 0],
        [2, 0, 1],
        [0, 2, 1],
        [2, 1, 0],
        [1, 0, 2],
    ][usize::from(b / 3 % 6)];
    let mut r = [[0.0; 3]; 3];
    let mut signs = [1.0, 1.0, 1.0];
    signs[0] = if b & 0x40 != 0 { -1.0 } else { 1.0 };
    signs[1] = if b & 0x80 != 0 { -1.0 } else { 1.0 };
    // An odd permutation, or one sign flipped, needs the third sign to keep det = +1.
    let odd = b / 3 % 6 >= 3;
    signs[2] = signs[0] * signs[1] * if odd { -1.0 } else { 1.0 };
    for (row, &col) in perm.iter().enumerate() {
        r[row][col] = signs[row];
    }
    let t = [0; 3].map(|_| f64::from(bytes.u8() as i8) / 16.0);
    Some(Pose::new(r, t).expect("a rotation"))
}

fn c_mesh(positions: &[f64], triangles: &[u32]) -> *mut DvhMesh {
    let mut mesh = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given.
    let status = unsafe {
        dvh_mesh_create(
            positions.as_ptr(),
            positions.len() / 3,
            triangles.as_ptr(),
            triangles.len() / 3,
            std::ptr::null(),
            &mut mesh,
        )
    };
    assert_eq!(status, DVH_STATUS_OK);
    mesh
}

fn c_pose(p: &Option<Pose>) -> Option<DvhPose> {
    p.as_ref().map(|p| {
        let r = p.rotation();
        DvhPose {
            rotation: [
                r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2],
            ],
            translation: p.translation(),
        }
    })
}

/// A curve buffer's contents: its segments and degenerate pairs as bytes, and its curves
/// `(first, count, closed)`.
type Contents = (Vec<u8>, Vec<u8>, Vec<(usize, usize, bool)>);

/// The contents of a C buffer.
fn c_contents(c: *const DvhCurves) -> Contents {
    // SAFETY: a live buffer, read by this thread only; the arrays hold the lengths given.
    unsafe {
        let bytes = |data: *const u8, n: usize| {
            if n == 0 {
                Vec::new()
            } else {
                std::slice::from_raw_parts(data, n).to_vec()
            }
        };
        let seg = bytes(
            dvh_curves_data(c).cast(),
            dvh_curves_len(c) * std::mem::size_of::<DvhCurveSegment>(),
        );
        let deg = bytes(
            dvh_curves_degenerate_data(c).cast(),
            dvh_curves_degenerate_len(c) * std::mem::size_of::<DvhDegeneratePair>(),
        );
        let curves = (0..dvh_curves_curve_count(c))
            .map(|i| {
                let (mut first, mut count, mut closed) = (0, 0, false);
                assert_eq!(
                    dvh_curves_curve(c, i, &mut first, &mut count, &mut closed),
                    DVH_STATUS_OK
                );
                (first, count, closed)
            })
            .collect();
        (seg, deg, curves)
    }
}

/// The same in a Rust buffer.
fn rust_contents(c: &Curves) -> Contents {
    let as_bytes = |p: *const u8, n: usize| {
        // SAFETY: `n` bytes of a live slice of plain `repr(C)` values without padding holes
        // read as uninitialised (`reserved` fields are written).
        unsafe { std::slice::from_raw_parts(p, n) }.to_vec()
    };
    let seg = as_bytes(
        c.segments().as_ptr().cast(),
        std::mem::size_of_val(c.segments()),
    );
    let deg = as_bytes(
        c.degenerate().as_ptr().cast(),
        std::mem::size_of_val(c.degenerate()),
    );
    let curves = c
        .curves()
        .iter()
        .map(|x| (x.segments.start, x.segments.len(), x.closed))
        .collect();
    (seg, deg, curves)
}

/// Curves target: two surfaces (the second placed by an exact pose) whose vertices the bytes
/// move by sixteenths, fold along a plane or drop onto other vertices; after each change, the
/// curves of the two and of the first with itself through the C ABI (threads, `max_pairs`,
/// modes from the bytes) must equal the Rust API's byte for byte, and are judged by
/// [`dvh::fixtures::curve_judge`] against brute force over every triangle pair; a refused mode
/// leaves the buffer as it was; the length gradients are finite.
pub fn curves(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let (mut pa, ta) = shape(&mut bytes);
    let (mut pb, tb) = shape(&mut bytes);
    let pose_b = pose(&mut bytes);
    let (ma, mb) = (c_mesh(&pa, &ta), c_mesh(&pb, &tb));
    // The same meshes through the Rust API, built and refit alike: the same trees, so that a
    // truncated result keeps the same pairs.
    let mut ra = Mesh::new(&pa, &ta, &BuildOptions::default()).expect("valid");
    let mut rb = Mesh::new(&pb, &tb, &BuildOptions::default()).expect("valid");
    let cb = c_pose(&pose_b);
    let cb_ptr = cb
        .as_ref()
        .map_or(std::ptr::null(), |p| p as *const DvhPose);
    let buffer = dvh_curves_new();
    let mut rounds = 0;
    while !bytes.is_empty() && rounds < 8 {
        rounds += 1;
        let op = bytes.u8();
        let (p, n) = if op & 0x10 == 0 {
            let n = pa.len() / 3;
            (&mut pa, n)
        } else {
            let n = pb.len() / 3;
            (&mut pb, n)
        };
        let v = usize::from(bytes.u8()) % n;
        match op % 4 {
            0 => {
                for k in 0..3 {
                    p[3 * v + k] += f64::from(bytes.u8() as i8) / 16.0;
                }
            }
            1 => {
                let axis = usize::from(bytes.u8() % 3);
                let c = f64::from(bytes.u8() as i8) / 32.0;
                let shift = f64::from(bytes.u8() as i8) / 64.0;
                for q in p.chunks_mut(3) {
                    if q[axis] > c {
                        q[axis] = 2.0 * c - q[axis] + shift;
                    }
                }
            }
            2 => {
                let w = usize::from(bytes.u8()) % n;
                for k in 0..3 {
                    p[3 * v + k] = p[3 * w + k];
                }
            }
            _ => {}
        }
        // SAFETY: live meshes, their vertex counts.
        unsafe {
            assert_eq!(dvh_mesh_refit(ma, pa.as_ptr(), pa.len() / 3), DVH_STATUS_OK);
            assert_eq!(dvh_mesh_refit(mb, pb.as_ptr(), pb.len() / 3), DVH_STATUS_OK);
        }
        let mut q = dvh_query_options_default();
        let m = bytes.u8();
        q.mode = if m < 224 {
            DVH_QUERY_MODE_TRIANGLES
        } else {
            u32::from(m % 6)
        };
        q.threads = u32::from(bytes.u8() % 3);
        q.max_pairs = if m % 7 == 1 {
            u64::from(bytes.u8() % 8)
        } else {
            0
        };
        ra.refit(&pa).expect("finite");
        rb.refit(&pb).expect("finite");
        for one in [false, true] {
            let before = c_contents(buffer);
            let mut stats = DvhQueryStats::default();
            // SAFETY: live handles, one thread.
            let status = unsafe {
                if one {
                    dvh_self_intersection_curves(ma, &q, buffer, &mut stats)
                } else {
                    dvh_intersection_curves(
                        ma,
                        std::ptr::null(),
                        mb,
                        cb_ptr,
                        &q,
                        buffer,
                        &mut stats,
                    )
                }
            };
            if q.mode != DVH_QUERY_MODE_TRIANGLES {
                assert_eq!(status, DVH_STATUS_INVALID_ARGUMENT);
                assert!(
                    c_contents(buffer) == before,
                    "a refused query changed the buffer"
                );
                continue;
            }
            assert_eq!(status, DVH_STATUS_OK);
            let options = QueryOptions::default()
                .with_threads(q.threads)
                .with_max_pairs((q.max_pairs != 0).then_some(q.max_pairs as usize));
            let mut rust = Curves::new();
            let expected: Vec<Pair> = if one {
                dvh::self_intersection_curves(&ra, &options, &mut rust).expect("curves");
                self_collide_brute_force(&ra)
            } else {
                dvh::intersection_curves(&ra, None, &rb, pose_b.as_ref(), &options, &mut rust)
                    .expect("curves");
                dvh::brute_force(&ra, None, &rb, pose_b.as_ref())
            };
            assert!(
                c_contents(buffer) == rust_contents(&rust),
                "C and Rust differ"
            );
            let wa = World::new(&ra, None);
            let wb = if one {
                World::new(&ra, None)
            } else {
                World::new(&rb, pose_b.as_ref())
            };
            let got = rust.len() + rust.degenerate().len();
            assert_eq!(stats.pairs as usize, got);
            if stats.truncated {
                // Some of the pairs: judged as those.
                assert_eq!(got as u64, q.max_pairs);
                let kept = reported_pairs(&rust);
                assert!(kept.iter().all(|p| expected.binary_search(p).is_ok()));
                judge(&rust, &wa, &wb, one, &kept, false);
            } else {
                judge(&rust, &wa, &wb, one, &expected, false);
            }
            // The gradient: finite, through C.
            let mut ga = vec![0.0; pa.len()];
            let mut gb = vec![0.0; pb.len()];
            // SAFETY: live handles; the arrays hold three doubles per vertex.
            let status = unsafe {
                if one {
                    dvh_curves_self_length_gradient(buffer, ma, ga.as_mut_ptr(), pa.len() / 3)
                } else {
                    dvh_curves_length_gradient(
                        buffer,
                        ma,
                        std::ptr::null(),
                        mb,
                        cb_ptr,
                        ga.as_mut_ptr(),
                        pa.len() / 3,
                        gb.as_mut_ptr(),
                        pb.len() / 3,
                    )
                }
            };
            assert_eq!(status, DVH_STATUS_OK);
            assert!(ga.iter().chain(&gb).all(|x| x.is_finite()));
        }
    }
    // SAFETY: live handles, released once.
    unsafe {
        dvh_curves_free(buffer);
        dvh_mesh_free(ma);
        dvh_mesh_free(mb);
    }
}
