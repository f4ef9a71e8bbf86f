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

/// A subtree of a cut through the tree: its root, the nodes below the root (contiguous: the
/// builder allocates depth first) and its rings.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Subtree {
    pub root: u32,
    pub nodes: Range<u32>,
    pub rings: Range<u32>,
}

/// Subtrees in the cut a threaded refit shares out: enough to balance 16 threads or so.
const CUT_SUBTREES: usize = 64;

/// The shape of a hierarchy over rings: node 0 is the root; every child comes after its parent,
/// so a reverse sweep visits children before parents.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Tree {
    pub nodes: Vec<Node>,
    /// The leaf node of each ring (rings in leaf order).
    pub leaf_of_ring: Vec<u32>,
    /// A cut through the tree: inner nodes, none below another, in node order, whose subtrees
    /// hold most rings, the largest opened first.
    pub subtrees: Vec<Subtree>,
}

impl Tree {
    /// Number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The cut for [`Tree::subtrees`]: the largest subtree (by rings) is replaced by its children
    /// until there are [`CUT_SUBTREES`] or only leaves remain.
    pub(crate) fn cut(nodes: &[Node]) -> Vec<Subtree> {
        Tree::cut_while(nodes, |count, _| count < CUT_SUBTREES)
    }

    /// A cut through the tree: the largest subtree (by rings) is replaced by its children while
    /// `open(subtrees so far, rings of the largest)` holds and it is not a leaf. Inner nodes
    /// only, in node order; the leaves of the cut are left out.
    pub(crate) fn cut_while(nodes: &[Node], open: impl Fn(usize, u32) -> bool) -> Vec<Subtree> {
        // One past the last node below each node: children come after their parent and each
        // node's descendants are contiguous, so a reverse sweep finds it.
        let mut end: Vec<u32> = (0..nodes.len() as u32).map(|i| i + 1).collect();
        for i in (0..nodes.len()).rev() {
            let n = &nodes[i];
            if !n.is_leaf() {
                end[i] = n
                    .children()
                    .map(|c| end[c as usize])
                    .max()
                    .unwrap_or(end[i]);
            }
        }
        let size = |i: u32| nodes[i as usize].ring_end - nodes[i as usize].ring_start;
        let mut heap = std::collections::BinaryHeap::from([(size(0), 0u32)]);
        while let Some(&(largest, i)) = heap.peek() {
            if !open(heap.len(), largest) {
                break;
            }
            let n = &nodes[i as usize];
            if n.is_leaf() {
                // The largest holds one ring: so do all.
                break;
            }
            heap.pop();
            heap.extend(n.children().map(|c| (size(c), c)));
        }
        let mut cut: Vec<Subtree> = heap
            .into_iter()
            .map(|(_, i)| i)
            .filter(|&i| !nodes[i as usize].is_leaf())
            .map(|i| {
                let n = &nodes[i as usize];
                Subtree {
                    root: i,
                    nodes: n.first_child..end[i as usize],
                    rings: n.ring_start..n.ring_end,
                }
            })
            .collect();
        cut.sort_by_key(|s| s.nodes.start);
        cut
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
