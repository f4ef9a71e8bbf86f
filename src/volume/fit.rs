//! The refit driver shared by the volume kinds: leaves from their rings, then inner nodes from
//! their children, on one thread or split by subtrees over several.
//!
//! Every node's volume depends only on the vertices and volumes below it, and a subtree's nodes
//! below its root are contiguous (the builder allocates depth first), so the subtrees of a fixed
//! cut through the tree ([`Subtree`], chosen at build) refit independently, each in its own
//! window of the arrays; the few nodes above the cut follow on the calling thread. The result is
//! the same, bit for bit, whatever the number of threads.

use super::RefitInput;
use crate::geometry::aabb::Aabb;
use crate::geometry::sphere::Sphere;
use crate::tree::Subtree;
use std::ops::{Index, IndexMut};

/// A contiguous run of a per-node array, indexed by node as the whole array is.
pub(super) struct NodeSlice<'a, T> {
    base: usize,
    items: &'a mut [T],
}

impl<'a, T> NodeSlice<'a, T> {
    /// The whole array.
    pub fn whole(items: &'a mut [T]) -> Self {
        NodeSlice { base: 0, items }
    }

    /// Nodes `base..base + items.len()`.
    pub fn at(base: usize, items: &'a mut [T]) -> Self {
        NodeSlice { base, items }
    }

    /// Nodes before `at`, and from `at` on (an empty array stays empty on both sides).
    fn split_at(self, at: usize) -> (NodeSlice<'a, T>, NodeSlice<'a, T>) {
        let from = (at - self.base).min(self.items.len());
        let (lo, hi) = self.items.split_at_mut(from);
        (
            NodeSlice {
                base: self.base,
                items: lo,
            },
            NodeSlice {
                base: at,
                items: hi,
            },
        )
    }

    /// The nodes from `at` on, borrowed (an empty array stays empty).
    fn rest(&mut self, at: usize) -> NodeSlice<'_, T> {
        let from = (at - self.base).min(self.items.len());
        NodeSlice {
            base: at,
            items: &mut self.items[from..],
        }
    }
}

impl<T> Index<usize> for NodeSlice<'_, T> {
    type Output = T;
    #[inline(always)]
    fn index(&self, i: usize) -> &T {
        &self.items[i - self.base]
    }
}

impl<T> IndexMut<usize> for NodeSlice<'_, T> {
    #[inline(always)]
    fn index_mut(&mut self, i: usize) -> &mut T {
        &mut self.items[i - self.base]
    }
}

/// The arrays a refit writes, over a run of nodes: spheres, boxes, or both (an unused one is
/// empty).
pub(super) struct VolumeSlices<'a> {
    pub spheres: NodeSlice<'a, Sphere>,
    pub boxes: NodeSlice<'a, Aabb>,
}

impl VolumeSlices<'_> {
    /// The nodes from `at` on, borrowed.
    fn rest(&mut self, at: usize) -> VolumeSlices<'_> {
        VolumeSlices {
            spheres: self.spheres.rest(at),
            boxes: self.boxes.rest(at),
        }
    }

    /// Nodes before `at`, and from `at` on.
    fn split_at(self, at: usize) -> (Self, Self) {
        let (s0, s1) = self.spheres.split_at(at);
        let (b0, b1) = self.boxes.split_at(at);
        (
            VolumeSlices {
                spheres: s0,
                boxes: b0,
            },
            VolumeSlices {
                spheres: s1,
                boxes: b1,
            },
        )
    }
}

/// A refit's scratch for a search down the tree: the nodes still to visit.
pub(super) type Stack = Vec<u32>;

/// How one volume kind recomputes a node. Returns the distance evaluations made.
pub(super) trait Fit: Sync {
    /// Leaf `leaf`, of ring `r`.
    fn leaf(&self, w: &mut VolumeSlices, input: &RefitInput, r: usize, leaf: usize) -> u64;
    /// Inner node `i`, whose children are current. `stack` is scratch for searches below it.
    fn inner(&self, w: &mut VolumeSlices, input: &RefitInput, i: usize, stack: &mut Stack) -> u64;
}

/// Below this many rings per thread, a refit stays on fewer threads: handing a subtree to
/// another thread costs more than refitting it.
const RINGS_PER_THREAD: usize = 4096;

/// Meshes with fewer rings refit on the calling thread.
pub(crate) const REFIT_PARALLEL_MIN_RINGS: usize = 2 * RINGS_PER_THREAD;

/// Refits every node on at most `stacks.len()` threads (one scratch stack each). Returns the
/// distance evaluations.
pub(super) fn refit<F: Fit>(
    fit: &F,
    mut w: VolumeSlices,
    input: &RefitInput,
    stacks: &mut [Vec<u32>],
) -> u64 {
    let (tree, rings) = (input.tree, input.rings);
    let threads = stacks.len().min(rings.len() / RINGS_PER_THREAD).max(1);
    let subtrees = &tree.subtrees[..];
    if threads == 1 || subtrees.len() < 2 {
        let all = Subtree {
            root: 0,
            nodes: 1..tree.len() as u32,
            rings: 0..rings.len() as u32,
        };
        let below = fit_below(fit, &mut w, input, &all, &mut stacks[0]);
        return below + fit_node(fit, &mut w, input, 0, &mut stacks[0]);
    }
    let below = w.rest(subtrees[0].nodes.start as usize);
    let mut evaluations = fit_subtrees(fit, below, input, subtrees, &mut stacks[..threads]);
    // The nodes above the cut (the subtrees' roots included), children before parents.
    let mut k = subtrees.len();
    let mut i = tree.len();
    while i > 0 {
        i -= 1;
        while k > 0 && subtrees[k - 1].nodes.start as usize > i {
            k -= 1;
        }
        if k > 0 && i < subtrees[k - 1].nodes.end as usize {
            // Refit already: skip to the node before the subtree.
            i = subtrees[k - 1].nodes.start as usize;
            k -= 1;
            continue;
        }
        evaluations += fit_node(fit, &mut w, input, i, &mut stacks[0]);
    }
    evaluations
}

/// Refits the nodes below the roots of `subtrees` (contiguous, in order, within `w`) on
/// `stacks.len()` threads, each taking a run of subtrees with about its share of the rings.
fn fit_subtrees<F: Fit>(
    fit: &F,
    mut w: VolumeSlices,
    input: &RefitInput,
    subtrees: &[Subtree],
    stacks: &mut [Vec<u32>],
) -> u64 {
    if stacks.len() == 1 || subtrees.len() == 1 {
        return subtrees
            .iter()
            .map(|s| fit_below(fit, &mut w, input, s, &mut stacks[0]))
            .sum();
    }
    let rings = |s: &[Subtree]| -> usize { s.iter().map(|t| t.rings.len()).sum() };
    let (stacks_l, stacks_r) = stacks.split_at_mut(stacks.len() / 2);
    // The left threads' share of the rings, in whole subtrees (at least one on each side).
    let share = rings(subtrees) * stacks_l.len() / (stacks_l.len() + stacks_r.len());
    let mut mid = 1;
    let mut left = subtrees[0].rings.len();
    while mid + 1 < subtrees.len() && left + subtrees[mid].rings.len() / 2 < share {
        left += subtrees[mid].rings.len();
        mid += 1;
    }
    let (sub_l, sub_r) = subtrees.split_at(mid);
    let (w_l, w_r) = w.split_at(sub_r[0].nodes.start as usize);
    let (a, b) = crate::threads::join(
        crate::threads::Step::Refit,
        || fit_subtrees(fit, w_l, input, sub_l, stacks_l),
        || fit_subtrees(fit, w_r, input, sub_r, stacks_r),
    );
    a + b
}

/// How many rings ahead a refit asks for the vertices it will read: rings are visited in leaf
/// order, but their vertices lie where the caller numbered them, and on a mesh numbered without
/// regard to space (a subdivided one) each leaf waited on its vertices' cache misses.
const PREFETCH_RINGS: usize = 8;

/// Refits the nodes below a subtree's root: its leaves ring by ring in leaf order (the order
/// the ring table is stored in, so it is read straight through; the vertices it names are
/// asked for [`PREFETCH_RINGS`] rings ahead), then its inner nodes, children before parents.
pub(super) fn fit_below<F: Fit>(
    fit: &F,
    w: &mut VolumeSlices,
    input: &RefitInput,
    s: &Subtree,
    stack: &mut Vec<u32>,
) -> u64 {
    let tree = input.tree;
    let mut evaluations = 0;
    if tree.nodes[s.root as usize].is_leaf() {
        return 0;
    }
    for r in s.rings.start as usize..s.rings.end as usize {
        if let Some(ahead) = input
            .rings
            .vertices_of(r + PREFETCH_RINGS, s.rings.end as usize)
        {
            for v in ahead {
                crate::prefetch::read(&input.positions[v as usize]);
            }
        }
        evaluations += fit.leaf(w, input, r, tree.leaf_of_ring[r] as usize);
    }
    for i in (s.nodes.start as usize..s.nodes.end as usize).rev() {
        if !tree.nodes[i].is_leaf() {
            evaluations += fit.inner(w, input, i, stack);
        }
    }
    evaluations
}

/// Refits node `i`, leaf or inner.
fn fit_node<F: Fit>(
    fit: &F,
    w: &mut VolumeSlices,
    input: &RefitInput,
    i: usize,
    stack: &mut Vec<u32>,
) -> u64 {
    let node = &input.tree.nodes[i];
    if node.is_leaf() {
        fit.leaf(w, input, node.ring_start as usize, i)
    } else {
        fit.inner(w, input, i, stack)
    }
}
