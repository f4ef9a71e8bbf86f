//! Scenes through the C ABI, calls in the order the bytes say, against a model of the scene.

use super::input::{Bytes, Made, filter, make_mesh, pose, rust_pose, strided};
use super::judge::{corners, judge};
use dvh::ffi::*;

/// One object of a scene as the driver believes it to be.
struct Object {
    /// Index of the mesh it was made from (its triangles and nodes).
    mesh: usize,
    /// Local coordinates (rigid) or world coordinates (deformable).
    positions: Vec<f64>,
    /// `Some` for a rigid object.
    pose: Option<dvh::Pose>,
    group: u32,
    mask: u32,
}

/// The contacts in a buffer, as tuples.
fn contact_list(contacts: *const DvhContacts) -> Vec<(u32, u32, u32, u32)> {
    // SAFETY: a live buffer, one thread.
    unsafe {
        let n = dvh_contacts_len(contacts);
        let data = dvh_contacts_data(contacts);
        (0..n)
            .map(|i| {
                let c = &*data.add(i);
                (c.object_a, c.object_b, c.a, c.b)
            })
            .collect()
    }
}

/// Scene target: up to three meshes (any create entry point), a scene built, changed and queried
/// through the C ABI in the order the bytes say (rigid and deformable objects added and
/// removed, poses, positions in doubles and strided floats with right and wrong counts, pair
/// exclusions, filters, lazy or eager refits, refits of the source meshes, queries in every
/// mode). No call may report an internal panic; a call refused changes nothing (the model the
/// driver keeps stays right, the contact buffer keeps its contents); every successful query's
/// contacts agree with brute force over the object pairs the filters and exclusions allow.
pub fn scene(data: &[u8]) {
    use std::collections::{BTreeMap, HashSet};
    let mut bytes = Bytes::new(data);
    let wanted = 1 + bytes.u8() % 3;
    let mut made: Vec<Made> = (0..wanted).filter_map(|_| make_mesh(&mut bytes)).collect();
    if made.is_empty() {
        return;
    }
    let mut scene = std::ptr::null_mut();
    // SAFETY: a writable out-parameter.
    assert_eq!(unsafe { dvh_scene_create(&mut scene) }, DVH_STATUS_OK);
    let contacts = dvh_contacts_new();
    let mut objects: BTreeMap<u32, Object> = BTreeMap::new();
    let mut excluded: HashSet<(u32, u32)> = HashSet::new();
    while !bytes.is_empty() {
        let op = bytes.u8();
        let k = usize::from(bytes.u8()) % made.len();
        // A live id mostly, sometimes any small number (live or not).
        let pick = |bytes: &mut Bytes| {
            let live: Vec<u32> = objects.keys().copied().collect();
            let b = bytes.u8();
            live.get(usize::from(b) % (live.len() + 1))
                .copied()
                .unwrap_or(u32::from(b))
        };
        let id = pick(&mut bytes);
        let other = pick(&mut bytes);
        let (group, mask) = (filter(&mut bytes), filter(&mut bytes));
        let pose = pose(&mut bytes);
        let pose_ptr: *const DvhPose = if (op / 16).is_multiple_of(4) {
            std::ptr::null()
        } else {
            &pose
        };
        let source = objects.get(&id).map_or(k, |o| o.mesh);
        let moved: Vec<f64> = made[source]
            .positions
            .iter()
            .map(|&x| x + bytes.f64())
            .collect();
        let extra = usize::from(op / 64 % 2);
        let mut query = dvh_query_options_default();
        query.mode = u32::from(bytes.u8() % 6);
        query.max_depth = u32::from(bytes.u8() % 4);
        query.max_pairs = u64::from(bytes.u8() % 4) * 4;
        query.budget = u64::from(bytes.u8() % 4) * 7;
        query.threads = u32::from(bytes.u8() % 3);
        let before = contact_list(contacts);
        let mut out = u32::MAX;
        let mut stats = DvhSceneStats::default();
        let live = |id| objects.contains_key(&id);
        // SAFETY: live handles and readable arguments (arrays of the counts given), one thread.
        let status = unsafe {
            match op % 9 {
                0 => dvh_scene_add_rigid(scene, made[k].mesh, pose_ptr, group, mask, &mut out),
                1 => dvh_scene_add_deformable(scene, made[k].mesh, group, mask, &mut out),
                2 => dvh_scene_set_pose(scene, id, pose_ptr),
                3 => {
                    let mut xyz = moved.clone();
                    xyz.extend(std::iter::repeat_n(0.25, 3 * extra));
                    dvh_scene_set_positions(scene, id, xyz.as_ptr(), xyz.len() / 3)
                }
                4 => {
                    let stride = 12 + 4 * usize::from(op / 16 % 3);
                    let mut xyz = moved.clone();
                    xyz.extend(std::iter::repeat_n(0.25, 3 * extra));
                    let buf = strided(&xyz, stride);
                    dvh_scene_set_positions_f32(
                        scene,
                        id,
                        buf.as_ptr().cast(),
                        stride,
                        xyz.len() / 3,
                    )
                }
                5 => dvh_scene_remove(scene, id),
                6 => dvh_scene_exclude_pair(scene, id, other),
                7 => {
                    if (op / 16).is_multiple_of(2) {
                        dvh_scene_set_lazy_refit(scene, (op / 32).is_multiple_of(2))
                    } else {
                        dvh_mesh_refit(made[k].mesh, moved.as_ptr(), moved.len() / 3)
                    }
                }
                _ => dvh_scene_collide(scene, &query, contacts, &mut stats),
            }
        };
        assert_ne!(status, DVH_STATUS_INTERNAL_PANIC);
        if status != DVH_STATUS_OK {
            assert_eq!(
                contact_list(contacts),
                before,
                "a refused call changed the contacts"
            );
            // (Other calls with an unknown id may report a bad pose or positions first.)
            if matches!(op % 9, 5 | 6) && !live(id) {
                assert_eq!(status, DVH_STATUS_INVALID_ARGUMENT, "an unknown id");
            }
            continue;
        }
        // The call succeeded: the model follows, and must have allowed it.
        match op % 9 {
            0 | 1 => {
                assert!(!live(out), "id {out} given twice");
                let rigid = op.is_multiple_of(9);
                let placed = if pose_ptr.is_null() || !rigid {
                    None
                } else {
                    Some(rust_pose(&pose).expect("the scene accepted the pose"))
                };
                objects.insert(
                    out,
                    Object {
                        mesh: k,
                        positions: made[k].positions.clone(),
                        pose: rigid.then(|| placed.unwrap_or_else(identity)),
                        group,
                        mask,
                    },
                );
            }
            2 => {
                let o = objects.get_mut(&id).expect("set_pose of an unknown id");
                assert!(o.pose.is_some(), "set_pose of a deformable object");
                o.pose = Some(if pose_ptr.is_null() {
                    identity()
                } else {
                    rust_pose(&pose).expect("the scene accepted the pose")
                });
            }
            3 | 4 => {
                assert_eq!(extra, 0, "positions of the wrong count accepted");
                let o = objects.get_mut(&id).expect("positions of an unknown id");
                assert!(o.pose.is_none(), "positions of a rigid object");
                o.positions = if op % 9 == 3 {
                    moved
                } else {
                    moved.iter().map(|&x| f64::from(x as f32)).collect()
                };
            }
            5 => {
                assert!(objects.remove(&id).is_some(), "removed an unknown id");
                excluded.retain(|&(a, b)| a != id && b != id);
            }
            6 => {
                assert!(
                    live(id) && live(other) && id != other,
                    "excluded {id} {other}"
                );
                excluded.insert((id.min(other), id.max(other)));
            }
            7 => {
                if op / 16 % 2 == 1 {
                    made[k].positions = moved;
                }
            }
            _ => {
                let got = contact_list(contacts);
                assert_eq!(stats.objects, objects.len() as u64);
                assert_eq!(stats.contacts, got.len() as u64);
                if stats.truncated {
                    assert_eq!(
                        got.len() as u64,
                        query.max_pairs,
                        "truncated short of the limit"
                    );
                }
                judge_scene(
                    &made,
                    &objects,
                    &excluded,
                    query.mode,
                    &got,
                    contacts,
                    stats.truncated,
                );
            }
        }
    }
    // SAFETY: live handles, released once (the scene before the meshes it was made from is not
    // required; the reverse order checks that objects outlive their meshes).
    unsafe {
        for m in &made {
            dvh_mesh_free(m.mesh);
        }
        dvh_contacts_free(contacts);
        dvh_scene_free(scene);
    }
}

fn identity() -> dvh::Pose {
    dvh::Pose::new(
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [0.0; 3],
    )
    .expect("rigid")
}

/// Judges a scene's contacts object pair by object pair against brute force (see [`judge`]).
fn judge_scene(
    made: &[Made],
    objects: &std::collections::BTreeMap<u32, Object>,
    excluded: &std::collections::HashSet<(u32, u32)>,
    mode: DvhQueryMode,
    got: &[(u32, u32, u32, u32)],
    contacts: *const DvhContacts,
    truncated: bool,
) {
    let mut sorted = got.to_vec();
    sorted.sort_unstable();
    assert_eq!(sorted, got, "contacts not sorted");
    // SAFETY: a live buffer.
    let kind = unsafe { dvh_contacts_kind(contacts) };
    let mut judged = 0;
    for (&i, oi) in objects {
        for (&j, oj) in objects.range(i + 1..) {
            let allowed =
                oi.group & oj.mask != 0 && oj.group & oi.mask != 0 && !excluded.contains(&(i, j));
            let mine: Vec<(u32, u32)> = got
                .iter()
                .filter(|c| (c.0, c.1) == (i, j))
                .map(|c| (c.2, c.3))
                .collect();
            judged += mine.len();
            if !allowed {
                assert!(
                    mine.is_empty(),
                    "objects {i} and {j} are filtered out: {mine:?}"
                );
                continue;
            }
            let (mi, mj) = (&made[oi.mesh], &made[oj.mesh]);
            let mut brute = Vec::new();
            for a in 0..mi.triangles.len() / 3 {
                let ta = corners(&oi.positions, &mi.triangles, a, oi.pose.as_ref());
                for b in 0..mj.triangles.len() / 3 {
                    let tb = corners(&oj.positions, &mj.triangles, b, oj.pose.as_ref());
                    let hit = dvh::exact::triangles_intersect(&ta, &tb);
                    brute.push(((a as u32, b as u32), Some(hit)));
                }
            }
            judge(
                (mi.mesh, mj.mesh),
                &brute,
                false,
                mode,
                &mine,
                kind,
                truncated,
            );
        }
    }
    assert_eq!(
        judged,
        got.len(),
        "contacts of objects that are not in the scene: {got:?}"
    );
}
