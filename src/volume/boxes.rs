//! Refitting box volumes: exact, bottom-up.

use super::RefitInput;
use crate::geometry::aabb::Aabb;
use crate::mesh::RefitStats;

/// A leaf's box from its ring's vertices, an inner node's as the union of its children's,
/// children before parents (children have higher indices). Exact: no rounding is involved.
pub(super) fn refit_aabb(boxes: &mut [Aabb], input: &RefitInput) -> RefitStats {
    let RefitInput {
        tree,
        rings,
        positions,
        ..
    } = *input;
    let mut vertices = 0u64;
    for i in (0..boxes.len()).rev() {
        let node = &tree.nodes[i];
        boxes[i] = if node.is_leaf() {
            let r = node.ring_start as usize;
            vertices += rings.vertices.row_len(r) as u64 + 1;
            Aabb::of_points(rings.all_vertices(r).map(|v| &positions[v as usize]))
        } else {
            let mut b = Aabb::EMPTY;
            for ch in node.children() {
                b.merge(&boxes[ch as usize]);
            }
            b
        };
    }
    RefitStats {
        nodes_refit: boxes.len() as u64,
        distance_evaluations: vertices,
    }
}
