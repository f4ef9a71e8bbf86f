//! Brute force over raw arrays and the judge of a query's answer against it; what a mesh handle
//! reports, to check that a failed call changed nothing.

use dvh::ffi::*;

pub type Tri = [[f64; 3]; 3];

/// Triangle `t`'s corners, placed by `pose` as the queries place them.
pub fn corners(positions: &[f64], triangles: &[u32], t: usize, pose: Option<&dvh::Pose>) -> Tri {
    std::array::from_fn(|k| {
        let v = triangles[3 * t + k] as usize;
        let p = [positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]];
        pose.map_or(p, |q| q.transform_point(&p))
    })
}

/// Do two triangles of one mesh meet, as self-collision defines it: apart from what they share
/// (a vertex, an edge) when they share vertices. `None` for pairs that share vertices and repeat
/// an index or all three vertices: how those count is the library's choice, not judged here.
pub fn self_hit(ti: [u32; 3], pi: &Tri, tj: [u32; 3], pj: &Tri) -> Option<bool> {
    let shared: Vec<usize> = (0..3).filter(|&k| tj.contains(&ti[k])).collect();
    if shared.is_empty() {
        return Some(dvh::exact::triangles_intersect(pi, pj));
    }
    let repeats = |t: [u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    if repeats(ti) || repeats(tj) {
        return None;
    }
    let at = |v: u32| tj.iter().position(|&x| x == v).expect("shared");
    match shared[..] {
        [k] => {
            let l = at(ti[k]);
            Some(dvh::fixtures::oracle::meet_beyond_vertex(
                &pi[k],
                [&pi[(k + 1) % 3], &pi[(k + 2) % 3]],
                [&pj[(l + 1) % 3], &pj[(l + 2) % 3]],
            ))
        }
        [k1, k2] => {
            let (l1, l2) = (at(ti[k1]), at(ti[k2]));
            Some(dvh::fixtures::oracle::meet_beyond_edge(
                &pi[k1],
                &pi[k2],
                &pi[3 - k1 - k2],
                &pj[3 - l1 - l2],
            ))
        }
        _ => None,
    }
}

/// What a query asked, to judge its answer.
pub enum Asked {
    Collide(dvh::Pose),
    SelfCollide,
    Proximity(dvh::Pose, f64),
    SelfProximity(f64),
}

/// The answer brute force gives, pair by pair: `Some(hit)`, or `None` for pairs not judged.
pub fn brute(
    positions: &[f64],
    triangles: &[u32],
    asked: &Asked,
) -> Vec<((u32, u32), Option<bool>)> {
    let n = triangles.len() / 3;
    let mut out = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let one_mesh = matches!(asked, Asked::SelfCollide | Asked::SelfProximity(_));
            if one_mesh && i >= j {
                continue;
            }
            let tri = |t: usize| -> [u32; 3] { std::array::from_fn(|k| triangles[3 * t + k]) };
            let plain = |t, pose| corners(positions, triangles, t, pose);
            let verdict = match asked {
                Asked::Collide(p) => Some(dvh::exact::triangles_intersect(
                    &plain(i, None),
                    &plain(j, Some(p)),
                )),
                Asked::SelfCollide => self_hit(tri(i), &plain(i, None), tri(j), &plain(j, None)),
                Asked::Proximity(p, d) => Some(dvh::exact::triangles_within(
                    &plain(i, Some(p)),
                    &plain(j, None),
                    *d,
                )),
                Asked::SelfProximity(d) => Some(
                    !tri(i).iter().any(|v| tri(j).contains(v))
                        && dvh::exact::triangles_within(&plain(i, None), &plain(j, None), *d),
                ),
            };
            out.push(((i as u32, j as u32), verdict));
        }
    }
    out
}

/// Judges a successful query's pairs against brute force: in the triangle modes exactly the
/// hits (some of them when truncated; one when first hit), in the coarse modes node pairs
/// covering every hit.
/// `a` and `b` are the meshes whose nodes the pairs index; `truncated`: the query stopped at
/// `max_pairs` (its caller checks the count), so only what was reported is judged.
pub fn judge(
    (a, b): (*const DvhMesh, *const DvhMesh),
    brute: &[((u32, u32), Option<bool>)],
    one_mesh: bool,
    mode: DvhQueryMode,
    got: &[(u32, u32)],
    kind: DvhPairKind,
    truncated: bool,
) {
    use std::collections::HashSet;
    let hits: HashSet<(u32, u32)> = brute
        .iter()
        .filter(|p| p.1 == Some(true))
        .map(|p| p.0)
        .collect();
    let open: HashSet<(u32, u32)> = brute
        .iter()
        .filter(|p| p.1.is_none())
        .map(|p| p.0)
        .collect();
    let unique: HashSet<(u32, u32)> = got.iter().copied().collect();
    assert_eq!(unique.len(), got.len(), "a pair reported twice: {got:?}");
    if mode == DVH_QUERY_MODE_TRIANGLES || mode == DVH_QUERY_MODE_FIRST_HIT {
        assert_eq!(kind, DVH_PAIR_KIND_TRIANGLES);
        for p in got {
            assert!(
                hits.contains(p) || open.contains(p),
                "{p:?} reported, brute force says apart"
            );
        }
        if mode == DVH_QUERY_MODE_FIRST_HIT {
            assert!(got.len() <= 1, "first hit reported {}", got.len());
            if !hits.is_empty() && !truncated {
                assert_eq!(
                    got.len(),
                    1,
                    "first hit found nothing, brute force {hits:?}"
                );
            }
        } else if !truncated {
            let missed: Vec<_> = hits.iter().filter(|p| !unique.contains(p)).collect();
            assert!(missed.is_empty(), "missed {missed:?}");
        }
        return;
    }
    assert_eq!(kind, DVH_PAIR_KIND_NODES);
    if truncated {
        return;
    }
    let below = |mesh: *const DvhMesh, node: u32| -> Vec<u32> {
        let mut list = std::ptr::null();
        let mut count = 0;
        // SAFETY: a live mesh; the list lives as long as it.
        unsafe {
            assert_eq!(
                dvh_mesh_node_triangles(mesh, node, &mut list, &mut count),
                DVH_STATUS_OK
            );
            std::slice::from_raw_parts(list, count).to_vec()
        }
    };
    let mut covered = HashSet::new();
    for &(na, nb) in got {
        for &x in &below(a, na) {
            for &y in &below(b, nb) {
                covered.insert((x, y));
                if one_mesh {
                    covered.insert((y, x));
                }
            }
        }
    }
    for p in &hits {
        assert!(covered.contains(p), "{p:?} is in no node pair of {got:?}");
    }
}

/// Everything a mesh handle reports, to check that a failed call changed nothing.
pub fn snapshot(
    mesh: *const DvhMesh,
    pairs: *const DvhPairs,
) -> (usize, usize, u64, Vec<(u32, u32)>) {
    let mut stats = DvhRefitStats::default();
    // SAFETY: live handles, one thread.
    unsafe {
        assert_eq!(dvh_mesh_last_refit_stats(mesh, &mut stats), DVH_STATUS_OK);
        assert_eq!(dvh_mesh_validate(mesh), DVH_STATUS_OK);
        let n = dvh_pairs_len(pairs);
        let data = dvh_pairs_data(pairs);
        let list = (0..n)
            .map(|i| ((*data.add(i)).a, (*data.add(i)).b))
            .collect();
        (
            dvh_mesh_vertex_count(mesh),
            dvh_mesh_node_count(mesh),
            stats.nodes_refit,
            list,
        )
    }
}
