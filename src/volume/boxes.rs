//! Refitting box volumes: exact, bottom-up.

use super::RefitInput;
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::mesh::RefitStats;
use crate::tree::Node;

/// A leaf's box from its ring's vertices (in ring order), then an inner node's as the union of
/// its children's, children before parents (children have higher indices). Exact: no rounding is
/// involved.
pub(super) fn refit_aabb(
    boxes: &mut [Aabb],
    input: &RefitInput,
    positions: &[Point],
) -> RefitStats {
    let RefitInput { tree, rings, .. } = *input;
    let mut vertices = 0u64;
    for r in 0..rings.len() {
        vertices += rings.vertices.row_len(r) as u64 + 1;
        boxes[tree.leaf_of_ring[r] as usize] =
            Aabb::of_points(rings.all_vertices(r).map(|v| &positions[v as usize]));
    }
    for i in (0..boxes.len()).rev() {
        let node = &tree.nodes[i];
        if node.is_leaf() {
            continue;
        }
        boxes[i] = children_union(node, boxes);
    }
    RefitStats {
        nodes_refit: boxes.len() as u64,
        distance_evaluations: vertices,
    }
}

/// The union of the boxes of `node`'s children (children are refit before their parent).
#[inline]
pub(super) fn children_union(node: &Node, boxes: &[Aabb]) -> Aabb {
    let mut b = Aabb::EMPTY;
    for ch in node.children() {
        b.merge(&boxes[ch as usize]);
    }
    b
}
