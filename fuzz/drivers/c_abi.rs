//! One mesh through the C ABI, calls in the order the bytes say.

use super::input::{Bytes, Made, make_mesh, pose, rust_pose, strided};
use super::judge::{Asked, brute, judge, snapshot};
use dvh::ffi::*;

/// Structural and differential target: a mesh through any create entry point, then the C ABI in
/// the order the bytes say (refits through both entry points, with right and wrong counts, and
/// the four pair queries with any mode, limits, poses and distances). No call may report an
/// internal panic; a failed call leaves the mesh and the result buffer as they were; a query
/// changes no mesh; every successful query's answer agrees with brute force (see [`judge`]).
pub fn c_abi(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let Some(Made {
        mesh,
        positions,
        triangles,
    }) = make_mesh(&mut bytes)
    else {
        return;
    };
    let vertex_count = positions.len() / 3;
    let mut current = positions.clone();
    let pairs = dvh_pairs_new();
    while !bytes.is_empty() {
        let before = snapshot(mesh, pairs);
        let mut query = dvh_query_options_default();
        query.mode = u32::from(bytes.u8() % 8);
        query.max_depth = u32::from(bytes.u8() % 8);
        query.max_pairs = u64::from(bytes.u8() % 4) * 3;
        query.budget = u64::from(bytes.u8() % 4) * 5;
        query.threads = u32::from(bytes.u8() % 3);
        let pose = pose(&mut bytes);
        let distance = bytes.f64();
        let moved: Vec<f64> = positions.iter().map(|&x| x + bytes.f64()).collect();
        let mut stats = DvhQueryStats::default();
        let op = bytes.u8();
        // What the positions become if the call succeeds, or what brute force is asked.
        let mut refit_to = None;
        let mut asked = None;
        // SAFETY: live handles and readable arguments, one thread.
        let status = unsafe {
            match op % 7 {
                0 => {
                    refit_to = Some(moved.clone());
                    dvh_mesh_refit(mesh, moved.as_ptr(), vertex_count)
                }
                1 => {
                    asked = rust_pose(&pose).map(Asked::Collide);
                    dvh_collide(
                        mesh,
                        std::ptr::null(),
                        mesh,
                        &pose,
                        &query,
                        pairs,
                        &mut stats,
                    )
                }
                2 => {
                    asked = Some(Asked::SelfCollide);
                    dvh_self_collide(mesh, &query, pairs, &mut stats)
                }
                3 => {
                    asked = rust_pose(&pose).map(|p| Asked::Proximity(p, distance));
                    dvh_proximity(
                        mesh,
                        &pose,
                        mesh,
                        std::ptr::null(),
                        distance,
                        &query,
                        pairs,
                        &mut stats,
                    )
                }
                4 => {
                    asked = Some(Asked::SelfProximity(distance));
                    dvh_self_proximity(mesh, distance, &query, pairs, &mut stats)
                }
                5 => {
                    // Floats at a stride; sometimes a count one too many (with the floats for it).
                    let stride = 12 + 4 * usize::from(op / 7 % 3);
                    let extra = usize::from(op / 21 % 2);
                    let mut xyz = moved.clone();
                    xyz.extend(std::iter::repeat_n(0.5, 3 * extra));
                    let buf = strided(&xyz, stride);
                    refit_to = Some(moved.iter().map(|&x| f64::from(x as f32)).collect());
                    dvh_mesh_refit_f32(mesh, buf.as_ptr().cast(), stride, vertex_count + extra)
                }
                _ => {
                    refit_to = Some(positions.clone());
                    dvh_mesh_refit(
                        mesh,
                        positions.as_ptr(),
                        vertex_count + usize::from(bytes.u8() % 2),
                    )
                }
            }
        };
        assert_ne!(status, DVH_STATUS_INTERNAL_PANIC);
        if status != DVH_STATUS_OK {
            assert_eq!(
                snapshot(mesh, pairs),
                before,
                "a failed call changed something"
            );
            continue;
        }
        if let Some(to) = refit_to {
            current = to;
            continue;
        }
        let after = snapshot(mesh, pairs);
        assert_eq!(
            (after.0, after.1, after.2),
            (before.0, before.1, before.2),
            "a query changed the mesh"
        );
        let asked = asked.expect("the C side accepted the pose");
        let one_mesh = matches!(asked, Asked::SelfCollide | Asked::SelfProximity(_));
        assert_eq!(
            stats.pairs,
            after.3.len() as u64,
            "the count is not the pairs'"
        );
        // SAFETY: a live buffer.
        let kind = unsafe { dvh_pairs_kind(pairs) };
        if stats.truncated {
            assert_eq!(
                after.3.len() as u64,
                query.max_pairs,
                "truncated short of the limit"
            );
        }
        judge(
            (mesh, mesh),
            &brute(&current, &triangles, &asked),
            one_mesh,
            query.mode,
            &after.3,
            kind,
            stats.truncated,
        );
    }
    // SAFETY: live handles, released once.
    unsafe {
        dvh_pairs_free(pairs);
        dvh_mesh_free(mesh);
    }
}
