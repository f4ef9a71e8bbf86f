//! Scenes through the C ABI, calls in the order the bytes say, against a model of the scene.

use super::input::{Bytes, Made, filter, make_mesh, pose, rust_pose, strided};
use super::judge::{corners, judge};
use dvh::ffi::*;

/// One object of a scene as the driver believes it to be.
struct Object {
    /// Index of the mesh it was made from (its triangles and nodes).
    mesh: usize,
    /// Local coordinates (rigid) or world coordinates (deformable; at the end of its step).
    positions: Vec<f64>,
    /// `Some` for a rigid object (its pose at the end of its step).
    pose: Option<dvh::Pose>,
    group: u32,
    mask: u32,
    /// Where its step starts, when it has one: a deformable object's world positions, a rigid
    /// object's pose.
    start: Option<Start>,
    self_contact: bool,
}

enum Start {
    Positions(Vec<f64>),
    Pose(dvh::Pose),
}

impl Object {
    /// World positions at the start and the end of the step.
    fn world(&self) -> (Vec<f64>, Vec<f64>) {
        let place = |pose: &dvh::Pose| -> Vec<f64> {
            self.positions
                .chunks_exact(3)
                .flat_map(|p| pose.transform_point(&[p[0], p[1], p[2]]))
                .collect()
        };
        let end = self
            .pose
            .as_ref()
            .map_or_else(|| self.positions.clone(), place);
        let start = match &self.start {
            Some(Start::Positions(p)) => p.clone(),
            Some(Start::Pose(p)) => place(p),
            None => end.clone(),
        };
        (start, end)
    }
}

/// The impacts in a scene buffer, as tuples (the time as its bits).
fn impact_list(impacts: *const DvhSceneImpacts) -> Vec<(u32, u32, [u32; 5], u64)> {
    // SAFETY: a live buffer, one thread.
    unsafe {
        let n = dvh_scene_impacts_len(impacts);
        let data = dvh_scene_impacts_data(impacts);
        (0..n)
            .map(|i| {
                let x = &*data.add(i);
                let m = &x.impact;
                (
                    x.object_a,
                    x.object_b,
                    [m.kind, m.a0, m.a1, m.b0, m.b1],
                    m.toi.to_bits(),
                )
            })
            .collect()
    }
}

/// The stencils in a scene buffer, as their objects and bytes.
fn near_list(pairs: *const DvhSceneNearPairs) -> Vec<(u32, u32, Vec<u8>)> {
    // SAFETY: a live buffer, one thread; a `DvhNearPair` is plain data with its padding written.
    unsafe {
        let n = dvh_scene_near_pairs_len(pairs);
        let data = dvh_scene_near_pairs_data(pairs);
        (0..n)
            .map(|i| {
                let x = &*data.add(i);
                let bytes = std::slice::from_raw_parts(
                    (&raw const x.pair).cast::<u8>(),
                    std::mem::size_of::<DvhNearPair>(),
                );
                (x.object_a, x.object_b, bytes.to_vec())
            })
            .collect()
    }
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
/// mode; self-contact switched, motions and pose motions given, continuous collision and
/// stencils of the whole scene). No call may report an internal panic; a call refused changes
/// nothing (the model the driver keeps stays right, every result buffer keeps its contents);
/// every successful query's contacts agree with brute force over the object pairs the filters
/// and exclusions allow, its impacts and stencils with the pairwise and self queries on
/// stand-alone meshes holding the objects' world positions and motions.
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
    let impacts = dvh_scene_impacts_new();
    let near = dvh_scene_near_pairs_new();
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
        let start_pose = pose(&mut bytes);
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
        let shift: Vec<f64> = made[source].positions.iter().map(|_| bytes.f64()).collect();
        let mut ccd = dvh_ccd_options_default();
        let c = bytes.u8();
        ccd.mode = u32::from(c % 2);
        ccd.earliest_only = c / 2 % 2 == 1;
        ccd.max_impacts = u64::from(c / 4 % 4) * 3;
        ccd.threads = u32::from(c / 16 % 3);
        let distance = [0.0, 0.01, 0.1, 0.5, -1.0, f64::NAN][usize::from(bytes.u8() % 6)];
        let mut query = dvh_query_options_default();
        query.mode = u32::from(bytes.u8() % 6);
        query.max_depth = u32::from(bytes.u8() % 4);
        query.max_pairs = u64::from(bytes.u8() % 4) * 4;
        query.budget = u64::from(bytes.u8() % 4) * 7;
        query.threads = u32::from(bytes.u8() % 3);
        let before = (
            contact_list(contacts),
            impact_list(impacts),
            near_list(near),
        );
        let mut out = u32::MAX;
        let mut stats = DvhSceneStats::default();
        let live = |id| objects.contains_key(&id);
        // SAFETY: live handles and readable arguments (arrays of the counts given), one thread.
        let status = unsafe {
            match op % 14 {
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
                9 => dvh_scene_set_self_contact(scene, id, op / 16 % 2 == 1),
                10 => {
                    let mut end = moved.clone();
                    end.extend(std::iter::repeat_n(0.25, 3 * extra));
                    let start: Vec<f64> = end
                        .iter()
                        .zip(shift.iter().chain(std::iter::repeat(&0.0)))
                        .map(|(x, d)| x + d)
                        .collect();
                    if (op / 16).is_multiple_of(2) {
                        dvh_scene_set_motion(scene, id, start.as_ptr(), end.as_ptr(), end.len() / 3)
                    } else {
                        let stride = 12 + 4 * usize::from(op / 32 % 3);
                        let (a, b) = (strided(&start, stride), strided(&end, stride));
                        dvh_scene_set_motion_f32(
                            scene,
                            id,
                            a.as_ptr().cast(),
                            b.as_ptr().cast(),
                            stride,
                            end.len() / 3,
                        )
                    }
                }
                11 => {
                    let first: *const DvhPose = if (op / 32).is_multiple_of(3) {
                        std::ptr::null()
                    } else {
                        &start_pose
                    };
                    dvh_scene_set_pose_motion(scene, id, first, pose_ptr)
                }
                12 => {
                    let mut st = std::mem::zeroed::<DvhCcdStats>();
                    dvh_scene_continuous_collide(scene, &ccd, impacts, &mut st)
                }
                13 => {
                    let mut st = DvhQueryStats::default();
                    dvh_scene_nearest_features(scene, distance, &query, near, &mut st)
                }
                _ => dvh_scene_collide(scene, &query, contacts, &mut stats),
            }
        };
        assert_ne!(status, DVH_STATUS_INTERNAL_PANIC);
        if status != DVH_STATUS_OK {
            assert!(
                (
                    contact_list(contacts),
                    impact_list(impacts),
                    near_list(near)
                ) == before,
                "a refused call changed a result"
            );
            // (Other calls with an unknown id may report a bad pose or positions first.)
            if matches!(op % 14, 5 | 6 | 9) && !live(id) {
                assert_eq!(status, DVH_STATUS_INVALID_ARGUMENT, "an unknown id");
            }
            continue;
        }
        // The call succeeded: the model follows, and must have allowed it.
        match op % 14 {
            0 | 1 => {
                assert!(!live(out), "id {out} given twice");
                let rigid = op.is_multiple_of(14);
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
                        start: None,
                        self_contact: false,
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
                o.start = None;
            }
            3 | 4 => {
                assert_eq!(extra, 0, "positions of the wrong count accepted");
                let o = objects.get_mut(&id).expect("positions of an unknown id");
                assert!(o.pose.is_none(), "positions of a rigid object");
                o.positions = if op % 14 == 3 {
                    moved
                } else {
                    moved.iter().map(|&x| f64::from(x as f32)).collect()
                };
                o.start = None;
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
            9 => {
                let o = objects.get_mut(&id).expect("self-contact of an unknown id");
                let on = op / 16 % 2 == 1;
                assert!(
                    !on || o.pose.is_none(),
                    "self-contact on for a rigid object"
                );
                o.self_contact = on;
            }
            10 => {
                assert_eq!(extra, 0, "a motion of the wrong count accepted");
                let o = objects.get_mut(&id).expect("a motion of an unknown id");
                assert!(o.pose.is_none(), "a motion of a rigid object");
                let start: Vec<f64> = moved.iter().zip(&shift).map(|(x, d)| x + d).collect();
                let narrow =
                    |v: &[f64]| -> Vec<f64> { v.iter().map(|&x| f64::from(x as f32)).collect() };
                let f32s = !(op / 16).is_multiple_of(2);
                o.positions = if f32s { narrow(&moved) } else { moved };
                o.start = Some(Start::Positions(if f32s { narrow(&start) } else { start }));
            }
            11 => {
                let o = objects
                    .get_mut(&id)
                    .expect("a pose motion of an unknown id");
                assert!(o.pose.is_some(), "a pose motion of a deformable object");
                let read = |p: *const DvhPose, given: &DvhPose| {
                    if p.is_null() {
                        identity()
                    } else {
                        rust_pose(given).expect("the scene accepted the pose")
                    }
                };
                let first: *const DvhPose = if (op / 32).is_multiple_of(3) {
                    std::ptr::null()
                } else {
                    &start_pose
                };
                o.start = Some(Start::Pose(read(first, &start_pose)));
                o.pose = Some(read(pose_ptr, &pose));
            }
            12 => judge_impacts(&made, &objects, &excluded, &ccd, &impact_list(impacts)),
            13 => {
                assert!(distance >= 0.0, "a bad distance accepted");
                judge_stencils(
                    &made,
                    &objects,
                    &excluded,
                    distance,
                    &query,
                    &near_list(near),
                );
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
        dvh_scene_impacts_free(impacts);
        dvh_scene_near_pairs_free(near);
        dvh_scene_free(scene);
    }
}

/// Stand-alone meshes of the live objects, holding their world positions and motions; `None`
/// when a new mesh refuses an object's world positions (beyond the coordinates' range, which
/// the scene's own checks allow).
fn standalone(
    made: &[Made],
    objects: &std::collections::BTreeMap<u32, Object>,
) -> Option<Vec<(u32, *mut DvhMesh)>> {
    let mut out: Vec<(u32, *mut DvhMesh)> = Vec::new();
    for (&id, o) in objects {
        let Some(mesh) = standalone_one(made, o) else {
            for (_, m) in out {
                // SAFETY: live handles, released once.
                unsafe { dvh_mesh_free(m) };
            }
            return None;
        };
        out.push((id, mesh));
    }
    Some(out)
}

/// A stand-alone mesh holding object `o`'s world positions and motion (`None` when a new mesh
/// refuses them); the caller frees it.
fn standalone_one(made: &[Made], o: &Object) -> Option<*mut DvhMesh> {
    let (start, end) = o.world();
    let tris = &made[o.mesh].triangles;
    let mut mesh = std::ptr::null_mut();
    // SAFETY: arrays of the counts given; a mesh that failed is freed (NULL is a no-op).
    unsafe {
        let st = dvh_mesh_create(
            end.as_ptr(),
            end.len() / 3,
            tris.as_ptr(),
            tris.len() / 3,
            std::ptr::null(),
            &mut mesh,
        );
        let moved = st == DVH_STATUS_OK
            && (o.start.is_none()
                || dvh_mesh_refit_motion(mesh, start.as_ptr(), end.as_ptr(), end.len() / 3)
                    == DVH_STATUS_OK);
        if !moved {
            dvh_mesh_free(mesh);
            return None;
        }
    }
    Some(mesh)
}

/// The object pairs the filters allow, and the objects with self-contact on paired with
/// themselves, in the scene's order.
fn allowed(
    objects: &std::collections::BTreeMap<u32, Object>,
    excluded: &std::collections::HashSet<(u32, u32)>,
) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (&i, oi) in objects {
        if oi.self_contact {
            out.push((i, i));
        }
        for (&j, oj) in objects.range(i + 1..) {
            if oi.group & oj.mask != 0 && oj.group & oi.mask != 0 && !excluded.contains(&(i, j)) {
                out.push((i, j));
            }
        }
    }
    out
}

/// A scene's impacts against the pairwise and self queries on stand-alone meshes: every one, or
/// the earliest, equal; under a limit, as many as it allows, each one of them. (Which impacts a
/// limit keeps depends on the hierarchy's order, and the stand-alone meshes are built with the
/// default options, the objects' meshes with any.)
fn judge_impacts(
    made: &[Made],
    objects: &std::collections::BTreeMap<u32, Object>,
    excluded: &std::collections::HashSet<(u32, u32)>,
    options: &DvhCcdOptions,
    got: &[(u32, u32, [u32; 5], u64)],
) {
    let Some(meshes) = standalone(made, objects) else {
        return;
    };
    let mesh = |id: u32| meshes.iter().find(|m| m.0 == id).expect("live").1;
    let buffer = dvh_impacts_new();
    let mut expected = Vec::new();
    let mut pair_options = *options;
    pair_options.earliest_only = false;
    pair_options.max_impacts = 0;
    for (i, j) in allowed(objects, excluded) {
        // SAFETY: live handles, one thread.
        unsafe {
            let st = if i == j {
                dvh_self_continuous_collide(mesh(i), &pair_options, buffer, std::ptr::null_mut())
            } else {
                dvh_continuous_collide(
                    mesh(i),
                    mesh(j),
                    &pair_options,
                    buffer,
                    std::ptr::null_mut(),
                )
            };
            assert_eq!(st, DVH_STATUS_OK);
            let data = dvh_impacts_data(buffer);
            for k in 0..dvh_impacts_len(buffer) {
                let m = &*data.add(k);
                expected.push((i, j, [m.kind, m.a0, m.a1, m.b0, m.b1], m.toi.to_bits()));
            }
        }
    }
    if options.earliest_only {
        let mut first: Option<(u32, u32, [u32; 5], u64)> = None;
        for x in &expected {
            if first.is_none_or(|f| f64::from_bits(x.3) < f64::from_bits(f.3)) {
                first = Some(*x);
            }
        }
        expected = first.into_iter().collect();
    } else if options.max_impacts > 0 {
        let limit = (options.max_impacts as usize).min(expected.len());
        assert_eq!(got.len(), limit, "a limit kept too few or too many impacts");
        assert!(
            got.iter().all(|x| expected.contains(x)),
            "a limited query reported an impact the pairs do not have"
        );
        assert!(got.is_sorted_by_key(|x| (x.0, x.1)), "impacts out of order");
        expected = got.to_vec();
    }
    assert_eq!(
        got,
        &expected[..],
        "the scene's impacts are not the pairs' ({options:?})"
    );
    // SAFETY: live handles, released once.
    unsafe {
        dvh_impacts_free(buffer);
        for (_, m) in meshes {
            dvh_mesh_free(m);
        }
    }
}

/// A scene's stencils against the pairwise and self queries on stand-alone meshes: equal, but
/// where a limit or the first-hit mode chooses (by the hierarchy's order, as for impacts): then
/// as many as they allow, each one of them.
fn judge_stencils(
    made: &[Made],
    objects: &std::collections::BTreeMap<u32, Object>,
    excluded: &std::collections::HashSet<(u32, u32)>,
    distance: f64,
    options: &DvhQueryOptions,
    got: &[(u32, u32, Vec<u8>)],
) {
    let Some(meshes) = standalone(made, objects) else {
        return;
    };
    let mesh = |id: u32| meshes.iter().find(|m| m.0 == id).expect("live").1;
    let buffer = dvh_near_pairs_new();
    let mut expected = Vec::new();
    let mut pair_options = *options;
    pair_options.threads = 1;
    pair_options.max_pairs = 0;
    let first_hit = options.mode == DVH_QUERY_MODE_FIRST_HIT;
    if first_hit {
        pair_options.mode = DVH_QUERY_MODE_TRIANGLES;
    }
    let mut allowed_count = 0;
    for (i, j) in allowed(objects, excluded) {
        // SAFETY: live handles, one thread.
        unsafe {
            let st = if i == j {
                dvh_self_nearest_features(
                    mesh(i),
                    distance,
                    &pair_options,
                    buffer,
                    std::ptr::null_mut(),
                )
            } else {
                dvh_nearest_features(
                    mesh(i),
                    std::ptr::null(),
                    mesh(j),
                    std::ptr::null(),
                    distance,
                    &pair_options,
                    buffer,
                    std::ptr::null_mut(),
                )
            };
            assert_eq!(st, DVH_STATUS_OK);
            let data = dvh_near_pairs_data(buffer);
            let n = dvh_near_pairs_len(buffer);
            allowed_count += if first_hit { n.min(1) } else { n };
            for k in 0..n {
                let bytes = std::slice::from_raw_parts(
                    data.add(k).cast::<u8>(),
                    std::mem::size_of::<DvhNearPair>(),
                );
                expected.push((i, j, bytes.to_vec()));
            }
        }
    }
    if first_hit || options.max_pairs > 0 {
        let limit = if options.max_pairs > 0 {
            (options.max_pairs as usize).min(allowed_count)
        } else {
            allowed_count
        };
        assert_eq!(
            got.len(),
            limit,
            "a limit kept too few or too many stencils"
        );
        assert!(
            got.iter().all(|x| expected.contains(x)),
            "a limited query reported a stencil the pairs do not have"
        );
        assert!(
            got.is_sorted_by_key(|x| (x.0, x.1)),
            "stencils out of order"
        );
        expected = got.to_vec();
    }
    assert!(
        got == &expected[..],
        "the scene's stencils are not the pairs' ({} against {})",
        got.len(),
        expected.len()
    );
    // SAFETY: live handles, released once.
    unsafe {
        dvh_near_pairs_free(buffer);
        for (_, m) in meshes {
            dvh_mesh_free(m);
        }
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
    // An object with self-contact on: its contacts with itself are `dvh_self_collide`'s on a
    // stand-alone mesh holding its world positions (triangle pairs do not depend on the tree;
    // the coarse modes' node pairs do, and are only counted).
    for (&i, oi) in objects.iter().filter(|(_, o)| o.self_contact) {
        let mine: Vec<(u32, u32)> = got
            .iter()
            .filter(|c| (c.0, c.1) == (i, i))
            .map(|c| (c.2, c.3))
            .collect();
        judged += mine.len();
        if mode != DVH_QUERY_MODE_TRIANGLES && mode != DVH_QUERY_MODE_FIRST_HIT {
            continue;
        }
        // The end of the step is what the discrete query sees: its positions alone.
        let still = Object {
            start: None,
            positions: oi.positions.clone(),
            pose: oi.pose,
            ..*oi
        };
        let Some(mesh) = standalone_one(made, &still) else {
            continue;
        };
        let buffer = dvh_pairs_new();
        // SAFETY: live handles, released once.
        let expected: Vec<(u32, u32)> = unsafe {
            let all = dvh_query_options_default();
            assert_eq!(
                dvh_self_collide(mesh, &all, buffer, std::ptr::null_mut()),
                DVH_STATUS_OK
            );
            let data = dvh_pairs_data(buffer);
            let found = (0..dvh_pairs_len(buffer))
                .map(|k| ((*data.add(k)).a, (*data.add(k)).b))
                .collect();
            dvh_mesh_free(mesh);
            dvh_pairs_free(buffer);
            found
        };
        if mode == DVH_QUERY_MODE_FIRST_HIT || truncated {
            assert!(
                mine.iter().all(|p| expected.contains(p)),
                "object {i}'s contacts with itself are not its self-intersections"
            );
            if mode == DVH_QUERY_MODE_FIRST_HIT && !truncated {
                assert_eq!(mine.len(), expected.len().min(1), "object {i}: first hit");
            }
        } else {
            assert_eq!(mine, expected, "object {i}'s contacts with itself");
        }
    }
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
