//! Choosing the DVH's sphere centres at build: mesh vertices, fixed for the mesh's life.

use crate::geometry::predicates::Point;
use crate::geometry::sphere::distance_squared;
use crate::tree::RingTable;
use crate::tree::Tree;

/// Leaves are centred on their ring's centre; an inner node on the vertex below it nearest to
/// the mean of the (distinct) vertices below it, as the paper chooses. Returns the centre vertex
/// of every node.
pub(crate) fn assign_centres(tree: &Tree, rings: &RingTable, points: &[Point]) -> Vec<u32> {
    let mut centre = vec![0u32; tree.len()];
    let mut stamp = vec![u32::MAX; points.len()];
    let mut below = Vec::new();
    for (i, node) in tree.nodes.iter().enumerate() {
        if node.is_leaf() {
            centre[i] = rings.centre[node.ring_start as usize];
            continue;
        }
        below.clear();
        for r in node.ring_start..node.ring_end {
            for v in rings.all_vertices(r as usize) {
                if stamp[v as usize] != i as u32 {
                    stamp[v as usize] = i as u32;
                    below.push(v);
                }
            }
        }
        // Each term divided first so that huge coordinates cannot overflow the sum.
        let w = 1.0 / below.len() as f64;
        let mut mean = [0.0f64; 3];
        for &v in &below {
            let p = &points[v as usize];
            for a in 0..3 {
                mean[a] += p[a] * w;
            }
        }
        centre[i] = below
            .iter()
            .copied()
            .min_by(|&u, &v| {
                distance_squared(&points[u as usize], &mean)
                    .total_cmp(&distance_squared(&points[v as usize], &mean))
                    .then(u.cmp(&v))
            })
            .expect("an inner node has vertices below it");
    }
    centre
}
