//! The reference answer: every triangle pair, by the exact test.

use super::pairs::Pair;
use crate::geometry::aabb::Aabb;
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::geometry::tri_tri::{Triangle, triangles_intersect};
use crate::mesh::Mesh;

/// Every intersecting triangle pair of `a` and `b`, sorted, found without the hierarchy: all
/// triangle pairs whose bounding boxes overlap (a sweep along x, an exact filter) go to the exact
/// test. Vertices are placed by the poses with [`Pose::transform_point`], as
/// [`crate::collide`] does, so the two agree bit for bit. This is the oracle the tests compare
/// against; it costs `O(n log n)` plus the box-overlapping pairs, which is quadratic at worst.
pub fn brute_force(a: &Mesh, pose_a: Option<&Pose>, b: &Mesh, pose_b: Option<&Pose>) -> Vec<Pair> {
    let ta = world_triangles(a, pose_a);
    let tb = world_triangles(b, pose_b);
    // Events sorted by the box's low x; a box overlaps an earlier one in x iff that one's high x
    // reaches this one's low x.
    let mut events: Vec<(f64, bool, u32)> = ta
        .iter()
        .enumerate()
        .map(|(i, t)| (t.1.lo[0], false, i as u32))
        .chain(
            tb.iter()
                .enumerate()
                .map(|(i, t)| (t.1.lo[0], true, i as u32)),
        )
        .collect();
    events.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut active_a: Vec<u32> = Vec::new();
    let mut active_b: Vec<u32> = Vec::new();
    let mut out = Vec::new();
    for (x, from_b, i) in events {
        let (mine, other, active_other, active_mine) = if from_b {
            (&tb, &ta, &mut active_a, &mut active_b)
        } else {
            (&ta, &tb, &mut active_b, &mut active_a)
        };
        active_other.retain(|&j| other[j as usize].1.hi[0] >= x);
        let (tri, bounds) = &mine[i as usize];
        for &j in active_other.iter() {
            let (tri2, bounds2) = &other[j as usize];
            if bounds.meets(bounds2) && triangles_intersect(tri, tri2) {
                out.push(if from_b {
                    Pair { a: j, b: i }
                } else {
                    Pair { a: i, b: j }
                });
            }
        }
        active_mine.push(i);
    }
    out.sort_unstable();
    out.dedup();
    out
}

fn world_triangles(mesh: &Mesh, pose: Option<&Pose>) -> Vec<(Triangle, Aabb)> {
    let world: Vec<Point> = match pose {
        Some(p) => mesh
            .positions()
            .iter()
            .map(|q| p.transform_point(q))
            .collect(),
        None => mesh.positions().to_vec(),
    };
    mesh.triangles()
        .iter()
        .map(|t| {
            let tri = t.map(|v| world[v as usize]);
            (tri, Aabb::of_points(&tri))
        })
        .collect()
}
