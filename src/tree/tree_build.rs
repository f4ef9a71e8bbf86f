//! Building a [`Tree`] top-down over the rings' centres: octree or binary midpoint splits, with a
//! median guard against wildly uneven spacing.

use super::shape::{Node, Tree};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;

/// How the hierarchy above the 1-rings is split.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum TreeKind {
    /// Each node's box of ring centres is cut at its midpoint on all three axes: up to 8
    /// children, shallow trees.
    #[default]
    Octree,
    /// Each node's box is cut at the midpoint of its longest axis: 2 children, deeper trees.
    Binary,
}

/// Children of an octree node at most: one per octant of its box.
const OCTANTS: usize = 8;
/// Children of a binary node.
const HALVES: usize = 2;
/// Most children any node has.
pub(crate) const MAX_CHILDREN: usize = OCTANTS;

impl TreeKind {
    /// Most children a node can have.
    pub(crate) fn max_children(self) -> usize {
        match self {
            TreeKind::Octree => OCTANTS,
            TreeKind::Binary => HALVES,
        }
    }
}

/// A split that leaves less than this fraction (1/16) of the rings on its smallest side (binary)
/// or more than 15/16 in one octant is redone at the median. Midpoint splits follow the geometry
/// and are what the paper builds; the median guard bounds the depth by `O(log n)` on inputs with
/// wildly uneven spacing, so the build stays `O(n log n)`.
const IMBALANCE: usize = 16;

impl Tree {
    /// Splits the rings top-down by their centres until each node holds one ring. Returns the
    /// tree (children contiguous and after their parent, blocks of children in depth-first
    /// order) and the order of the rings that makes every node's rings a contiguous range (leaf
    /// order).
    pub(crate) fn build(centres: &[Point], kind: TreeKind) -> (Tree, Vec<u32>) {
        let count = centres.len() as u32;
        let mut order: Vec<u32> = (0..count).collect();
        let mut nodes = vec![Node {
            ring_start: 0,
            ring_end: count,
            ..Node::default()
        }];
        let mut bounds = Vec::with_capacity(OCTANTS + 1);
        let mut scratch = Vec::new();
        // Depth first, each node's children allocated together when it is split: children stay
        // contiguous and after their parent, and the blocks follow the leaf order, so that the
        // leaves of neighbouring rings (and the nodes a depth-first traversal visits in turn)
        // are close in memory.
        let mut pending = vec![0usize];
        while let Some(i) = pending.pop() {
            let (s, e) = (nodes[i].ring_start as usize, nodes[i].ring_end as usize);
            if e - s > 1 {
                bounds.clear();
                let part = &mut order[s..e];
                match kind {
                    TreeKind::Binary => split_binary(part, centres, &mut bounds),
                    TreeKind::Octree => split_octree(part, centres, &mut bounds, &mut scratch),
                }
                debug_assert!(bounds.len() >= 3 && bounds.windows(2).all(|w| w[0] < w[1]));
                let first = nodes.len() as u32;
                let depth = nodes[i].depth + 1;
                for w in bounds.windows(2) {
                    nodes.push(Node {
                        ring_start: (s + w[0]) as u32,
                        ring_end: (s + w[1]) as u32,
                        depth,
                        ..Node::default()
                    });
                }
                nodes[i].first_child = first;
                nodes[i].child_count = (bounds.len() - 1) as u16;
                pending.extend((first as usize..nodes.len()).rev());
            } else {
                nodes[i].first_child = nodes[i].ring_start;
            }
        }
        let mut leaf_of_ring = vec![0; order.len()];
        for (i, n) in nodes.iter().enumerate() {
            if n.is_leaf() {
                leaf_of_ring[n.ring_start as usize] = i as u32;
            }
        }
        let subtrees = Tree::cut(&nodes);
        (
            Tree {
                nodes,
                leaf_of_ring,
                subtrees,
            },
            order,
        )
    }
}

fn box_of(part: &[u32], centres: &[Point]) -> Aabb {
    Aabb::of_points(part.iter().map(|&r| &centres[r as usize]))
}

/// Moves the entries with `pred` true to the front; returns how many there are.
fn partition(part: &mut [u32], pred: impl Fn(u32) -> bool) -> usize {
    let mut k = 0;
    for i in 0..part.len() {
        if pred(part[i]) {
            part.swap(i, k);
            k += 1;
        }
    }
    k
}

/// Splits at the median along `axis`; returns the split index (`len / 2`, both sides non-empty
/// for `len >= 2`).
fn median_split(part: &mut [u32], centres: &[Point], axis: usize) -> usize {
    let mid = part.len() / 2;
    if mid > 0 {
        part.select_nth_unstable_by(mid, |&a, &b| {
            centres[a as usize][axis].total_cmp(&centres[b as usize][axis])
        });
    }
    mid
}

fn split_binary(part: &mut [u32], centres: &[Point], bounds: &mut Vec<usize>) {
    let len = part.len();
    let b = box_of(part, centres);
    let axis = b.longest_axis();
    let m = b.centre()[axis];
    let k = partition(part, |r| centres[r as usize][axis] < m);
    let k = if k.min(len - k) * IMBALANCE < len {
        median_split(part, centres, axis)
    } else {
        k
    };
    bounds.extend([0, k, len]);
}

fn split_octree(
    part: &mut [u32],
    centres: &[Point],
    bounds: &mut Vec<usize>,
    scratch: &mut Vec<u32>,
) {
    let len = part.len();
    let m = box_of(part, centres).centre();
    // Bit `a` of the octant is set when the centre is on the high side of the cut on axis `a`.
    let octant = |r: u32| {
        let p = &centres[r as usize];
        (0..3).fold(0usize, |code, a| code | (usize::from(p[a] >= m[a]) << a))
    };
    let mut counts = [0usize; OCTANTS];
    for &r in part.iter() {
        counts[octant(r)] += 1;
    }
    let occupied = counts.iter().filter(|&&c| c > 0).count();
    let largest = counts.iter().copied().max().unwrap_or(0);
    if occupied < 2 || largest * IMBALANCE > len * (IMBALANCE - 1) {
        median_octree(part, centres, bounds);
        return;
    }
    // Counting sort by octant.
    let mut start = [0usize; OCTANTS + 1];
    for o in 0..OCTANTS {
        start[o + 1] = start[o] + counts[o];
    }
    scratch.clear();
    scratch.resize(len, 0);
    let mut cursor = start;
    for &r in part.iter() {
        let o = octant(r);
        scratch[cursor[o]] = r;
        cursor[o] += 1;
    }
    part.copy_from_slice(scratch);
    push_distinct(bounds, &start);
}

/// Eight parts by successive medians on x, then y, then z.
fn median_octree(part: &mut [u32], centres: &[Point], bounds: &mut Vec<usize>) {
    let len = part.len();
    let h = median_split(part, centres, 0);
    let (left, right) = part.split_at_mut(h);
    let q1 = median_split(left, centres, 1);
    let q3 = h + median_split(right, centres, 1);
    let mut cuts = [0, 0, q1, 0, h, 0, q3, 0, len];
    for k in 0..OCTANTS / 2 {
        let (s, e) = (cuts[2 * k], cuts[2 * k + 2]);
        cuts[2 * k + 1] = s + median_split(&mut part[s..e], centres, 2);
    }
    push_distinct(bounds, &cuts);
}

/// Appends the part boundaries `cuts` (non-decreasing, starting at 0), dropping empty parts.
fn push_distinct(bounds: &mut Vec<usize>, cuts: &[usize]) {
    bounds.push(0);
    for &c in &cuts[1..] {
        if c > *bounds.last().unwrap_or(&0) {
            bounds.push(c);
        }
    }
}
