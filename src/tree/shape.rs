//! [`Tree`] and its [`Node`]s.

use std::ops::Range;

/// A node of the shape. Children of a node are contiguous and numbered after it; the rings below
/// a node are `ring_start..ring_end` (rings are stored in leaf order), so are their triangles.
/// Sixteen bytes, so that four share a cache line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Node {
    /// First child; for a leaf, equal to `ring_start`.
    pub first_child: u32,
    pub ring_start: u32,
    pub ring_end: u32,
    /// Number of children; 0 for a leaf.
    pub child_count: u16,
    /// Distance from the root, which has depth 0. The builder keeps depths logarithmic (far
    /// below `u16::MAX`) whatever the input.
    pub depth: u16,
}

impl Node {
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.child_count == 0
    }

    #[inline(always)]
    pub fn children(&self) -> Range<u32> {
        self.first_child..self.first_child + u32::from(self.child_count)
    }
}

/// The shape of a hierarchy over rings: node 0 is the root; every child comes after its parent,
/// so a reverse sweep visits children before parents.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Tree {
    pub nodes: Vec<Node>,
    /// The leaf node of each ring (rings in leaf order).
    pub leaf_of_ring: Vec<u32>,
}

impl Tree {
    /// Number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Levels: the depth of the deepest node plus one.
    pub fn levels(&self) -> usize {
        self.nodes
            .iter()
            .map(|n| usize::from(n.depth) + 1)
            .max()
            .unwrap_or(0)
    }
}
