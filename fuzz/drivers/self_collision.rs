//! Self-collision and self-proximity of folded, pinched surfaces.

use super::input::Bytes;
use super::judge::{Asked, brute, judge, snapshot};
use dvh::ffi::*;

/// Self-collision target: surfaces with real topology (a sheet, a torus, a sphere) whose
/// vertices the bytes move (by sixteenths, so coplanar and touching configurations are common),
/// fold along a line, or drop onto other vertices, refit through the C ABI frame after frame;
/// `dvh_self_collide` and `dvh_self_proximity` in every mode after each change, judged against
/// brute force (see [`judge`]). This is where the patch test decides which node pairs
/// cannot meet.
pub fn self_collision(data: &[u8]) {
    use dvh::fixtures::{grid, icosphere, torus};
    let mut bytes = Bytes::new(data);
    let kind = bytes.u8();
    let size = usize::from(bytes.u8());
    let shape = match kind % 3 {
        0 => grid(1 + size % 7, 1.0),
        1 => torus(0.5, 0.25, 3 + size % 6, 3 + size / 6 % 4),
        _ => icosphere(u32::from(size % 2 == 1)),
    };
    // Coordinates on a grid of sixteenths, so that moves keep exact coincidences.
    let mut positions: Vec<f64> = shape
        .positions
        .iter()
        .map(|&x| (x * 16.0).round() / 16.0)
        .collect();
    let triangles = shape.triangles.clone();
    let vertex_count = positions.len() / 3;
    let mut options = dvh_build_options_default();
    options.tree = u32::from(kind / 3 % 2);
    options.volume = u32::from(kind / 6 % 3);
    options.radius = u32::from(kind / 18 % 2);
    options.leftovers = u32::from(kind / 36 % 2);
    let mut mesh = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given.
    let status = unsafe {
        dvh_mesh_create(
            positions.as_ptr(),
            vertex_count,
            triangles.as_ptr(),
            triangles.len() / 3,
            &options,
            &mut mesh,
        )
    };
    assert_eq!(status, DVH_STATUS_OK);
    let pairs = dvh_pairs_new();
    while !bytes.is_empty() {
        let op = bytes.u8();
        let v = usize::from(bytes.u8()) % vertex_count;
        match op % 4 {
            // Move a vertex by sixteenths.
            0 => {
                for k in 0..3 {
                    positions[3 * v + k] += f64::from(bytes.u8() as i8) / 16.0;
                }
            }
            // Fold: mirror every vertex beyond a plane x = c (or y, z) to its other side, shifted.
            1 => {
                let axis = usize::from(bytes.u8() % 3);
                let c = f64::from(bytes.u8() as i8) / 32.0;
                let shift = f64::from(bytes.u8() as i8) / 64.0;
                for p in positions.chunks_mut(3) {
                    if p[axis] > c {
                        p[axis] = 2.0 * c - p[axis] + shift;
                    }
                }
            }
            // Drop a vertex onto another.
            2 => {
                let w = usize::from(bytes.u8()) % vertex_count;
                for k in 0..3 {
                    positions[3 * v + k] = positions[3 * w + k];
                }
            }
            _ => {}
        }
        // SAFETY: a live mesh, its vertex count.
        let status = unsafe { dvh_mesh_refit(mesh, positions.as_ptr(), vertex_count) };
        assert_eq!(status, DVH_STATUS_OK);
        let mut query = dvh_query_options_default();
        query.mode = u32::from(bytes.u8() % 5);
        query.max_depth = u32::from(bytes.u8() % 4);
        query.budget = 1 + u64::from(bytes.u8());
        query.threads = u32::from(bytes.u8() % 3);
        let distance = f64::from(bytes.u8()) / 64.0;
        for asked in [Asked::SelfCollide, Asked::SelfProximity(distance)] {
            let mut stats = DvhQueryStats::default();
            // SAFETY: live handles, one thread.
            let status = unsafe {
                match asked {
                    Asked::SelfCollide => dvh_self_collide(mesh, &query, pairs, &mut stats),
                    _ => dvh_self_proximity(mesh, distance, &query, pairs, &mut stats),
                }
            };
            assert_eq!(status, DVH_STATUS_OK);
            let (_, _, _, got) = snapshot(mesh, pairs);
            // SAFETY: a live buffer.
            let kind = unsafe { dvh_pairs_kind(pairs) };
            judge(
                (mesh, mesh),
                &brute(&positions, &triangles, &asked),
                true,
                query.mode,
                &got,
                kind,
                false,
            );
        }
    }
    // SAFETY: live handles, released once.
    unsafe {
        dvh_pairs_free(pairs);
        dvh_mesh_free(mesh);
    }
}
