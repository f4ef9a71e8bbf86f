//! Refitting box volumes: exact, bottom-up.

use super::RefitInput;
use super::fit::{Fit, NodeSlice, Stack, VolumeSlices};
use crate::geometry::aabb::Aabb;
use crate::tree::Node;

/// A leaf's box from its ring's vertices (in ring order), an inner node's as the union of its
/// children's. Exact: no rounding is involved.
pub(super) struct FitBoxes;

impl Fit for FitBoxes {
    #[inline]
    fn leaf(&self, w: &mut VolumeSlices, input: &RefitInput, r: usize, leaf: usize) -> u64 {
        let positions = input.positions;
        let rings = input.rings;
        w.boxes[leaf] = Aabb::of_points(rings.all_vertices(r).map(|v| &positions[v as usize]));
        rings.vertices.row_len(r) as u64 + 1
    }

    #[inline]
    fn inner(&self, w: &mut VolumeSlices, input: &RefitInput, i: usize, _: &mut Stack) -> u64 {
        w.boxes[i] = children_union(&input.tree.nodes[i], &w.boxes);
        0
    }
}

/// The union of the boxes of `node`'s children (children are refit before their parent).
#[inline]
pub(super) fn children_union(node: &Node, boxes: &NodeSlice<Aabb>) -> Aabb {
    let mut b = Aabb::EMPTY;
    for ch in node.children() {
        b.merge(&boxes[ch as usize]);
    }
    b
}
