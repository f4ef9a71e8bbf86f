//! The one traversal of two hierarchies: node pairs whose volumes overlap are opened until they
//! are terminal, and terminal pairs go to whoever asked ([`NarrowPhase`]): the exact triangle
//! tests, or the report of node pairs. Depth first for complete answers; largest volumes first
//! under a budget of volume tests.
//!
//! A mesh against itself (self-collision, self-proximity) is the same traversal from the pair
//! (root, root) of two views of one mesh ([`Walk::own`]): a node paired with itself (an *own*
//! pair) opens into each child with itself and each pair of distinct children, so every
//! unordered pair of nodes is reached once; own pairs need no volume test, and a patch that
//! cannot intersect itself, or a pair of patches that cannot meet beyond their shared seam, is
//! not opened at all.

use super::side::{QuerySide, Volume};
use super::workspace::{Queued, Split};
use crate::mesh::Mesh;
use crate::mesh::Patches;
use crate::query::pairs::{Pair, QueryStats};
use crate::tree::{MAX_CHILDREN, Node};
use std::collections::BinaryHeap;

/// What a traversal hands its terminal node pairs to.
pub(crate) trait NarrowPhase<'m, A: QuerySide<'m>, B: QuerySide<'m>> {
    /// Node `na` of `a` and node `nb` of `b`, whose volumes overlap and which the traversal opens
    /// no further (in a traversal of one mesh, `na == nb` is a node against itself). Returns
    /// whether the traversal must stop.
    fn visit(&mut self, a: &mut A, b: &mut B, na: u32, nb: u32, stats: &mut QueryStats) -> bool;
}

/// A traversal of one mesh against itself.
#[derive(Clone, Copy)]
pub(crate) struct OneMesh<'m> {
    /// Nodes whose patches are proved free of self-intersection are skipped (self-collision);
    /// `None` where nearness, not intersection, is asked.
    pub patches: Option<&'m Patches>,
}

impl OneMesh<'_> {
    /// Can the pair `(x, y)` (a node with itself when `x == y`) be skipped?
    #[inline]
    fn skips(&self, mesh: &Mesh, x: u32, y: u32) -> bool {
        self.patches.is_some_and(|p| {
            if x == y {
                p.cannot_self_intersect(mesh, x)
            } else {
                p.cannot_intersect_each_other(mesh, x, y)
            }
        })
    }
}

/// How a traversal walks.
#[derive(Clone, Copy)]
pub(crate) struct Walk<'m> {
    /// The depth at which nodes are no longer opened.
    pub max_depth: u32,
    /// Both sides are one mesh.
    pub own: Option<OneMesh<'m>>,
}

impl<'m> Walk<'m> {
    /// Is `(na, nb)` a pair of one mesh whose patches are proved apart?
    #[inline(always)]
    fn skips<A: QuerySide<'m>>(&self, a: &A, na: u32, nb: u32) -> bool {
        self.own.is_some_and(|o| o.skips(a.mesh(), na, nb))
    }
}

/// Which node of an overlapping pair to open.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Open {
    /// Neither: the pair is terminal.
    Neither,
    A,
    B,
    Both,
    /// A node against itself: each child against itself, and each pair of distinct children.
    Own,
}

/// A node is opened unless it is a leaf or at the depth limit. Of two that can be, the one with
/// the larger volume is; on equal sizes both are, so that the traversal with the meshes swapped
/// visits the mirrored pairs and the coarse answers are symmetric.
#[inline(always)]
fn open(na: &Node, size_a: f64, nb: &Node, size_b: f64, max_depth: u32) -> Open {
    let end_a = na.is_leaf() || u32::from(na.depth) >= max_depth;
    let end_b = nb.is_leaf() || u32::from(nb.depth) >= max_depth;
    if end_a && end_b {
        Open::Neither
    } else if end_a || (!end_b && size_b > size_a) {
        Open::B
    } else if end_b || size_a > size_b {
        Open::A
    } else {
        Open::Both
    }
}

/// The volumes of nodes `na` and `nb`, and which of them to open. In a traversal of one mesh
/// with the patch test, a node that cannot join a union of patches (see [`Patches::may_join`])
/// is opened before one that can: every union with it fails, while its children may pass with
/// the other node whole.
#[inline(always)]
fn volumes_and_opening<'m, A: QuerySide<'m>, B: QuerySide<'m>>(
    a: &mut A,
    b: &mut B,
    na: u32,
    nb: u32,
    walk: &Walk<'m>,
) -> (A::Volume, B::Volume, Open) {
    let max_depth = walk.max_depth;
    let (va, vb) = (a.volume(na), b.volume(nb));
    if na == nb && walk.own.is_some() {
        let node = &a.nodes()[na as usize];
        let end = node.is_leaf() || u32::from(node.depth) >= max_depth;
        return (va, vb, if end { Open::Neither } else { Open::Own });
    }
    let (node_a, node_b) = (&a.nodes()[na as usize], &b.nodes()[nb as usize]);
    let mut how = open(
        node_a,
        va.size_squared(),
        node_b,
        vb.size_squared(),
        max_depth,
    );
    if let (Some(patches), Open::A | Open::B | Open::Both) = (walk.own.and_then(|o| o.patches), how)
    {
        let mesh = a.mesh();
        let (join_a, join_b) = (patches.may_join(mesh, na), patches.may_join(mesh, nb));
        let end = |n: &Node| n.is_leaf() || u32::from(n.depth) >= max_depth;
        if join_a && !join_b && !end(node_b) {
            how = Open::B;
        } else if join_b && !join_a && !end(node_a) {
            how = Open::A;
        }
    }
    (va, vb, how)
}

/// Do the roots' volumes overlap? (One volume test, counted; none for one mesh.)
#[inline]
fn roots_overlap<'m, A: QuerySide<'m>, B: QuerySide<'m>>(
    a: &mut A,
    b: &mut B,
    walk: &Walk<'m>,
    stats: &mut QueryStats,
) -> bool {
    if walk.own.is_some() {
        return true;
    }
    stats.bv_tests += 1;
    a.volume(0).overlaps(&b.volume(0))
}

/// Tests the child pairs `open` makes of `(na, nb)` (volumes `va`, `vb`) and passes the
/// overlapping ones, with their volumes, to `keep`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn open_pair<'m, A: QuerySide<'m>, B: QuerySide<'m>>(
    a: &mut A,
    b: &mut B,
    na: u32,
    nb: u32,
    va: &A::Volume,
    vb: &B::Volume,
    how: Open,
    stats: &mut QueryStats,
    mut keep: impl FnMut(u32, u32, &A::Volume, &B::Volume),
) {
    let (nodes_a, nodes_b) = (a.nodes(), b.nodes());
    match how {
        Open::Neither => {}
        Open::B => {
            for ch in nodes_b[nb as usize].children() {
                let vc = b.volume(ch);
                stats.bv_tests += 1;
                if va.overlaps(&vc) {
                    keep(na, ch, va, &vc);
                }
            }
        }
        Open::A => {
            for ch in nodes_a[na as usize].children() {
                let vc = a.volume(ch);
                stats.bv_tests += 1;
                if vc.overlaps(vb) {
                    keep(ch, nb, &vc, vb);
                }
            }
        }
        Open::Both => {
            for x in nodes_a[na as usize].children() {
                let vx = a.volume(x);
                for y in nodes_b[nb as usize].children() {
                    let vy = b.volume(y);
                    stats.bv_tests += 1;
                    if vx.overlaps(&vy) {
                        keep(x, y, &vx, &vy);
                    }
                }
            }
        }
        Open::Own => {
            let children = nodes_a[na as usize].children();
            for x in children.clone() {
                let vx = a.volume(x);
                keep(x, x, &vx, &b.volume(x));
                for y in x + 1..children.end {
                    let vy = b.volume(y);
                    stats.bv_tests += 1;
                    if vx.overlaps(&vy) {
                        keep(x, y, &vx, &vy);
                    }
                }
            }
        }
    }
}

/// Every overlapping terminal pair, depth first, from the roots (`start` is `None`) or below
/// the overlapping pair `start` (then in the order the traversal from the roots reaches them):
/// nodes are terminal when they are leaves or at depth `max_depth`. A child pair is tested
/// before it is pushed. Returns whether the narrow phase stopped the traversal.
pub(crate) fn depth_first<'m, A: QuerySide<'m>, B: QuerySide<'m>, N: NarrowPhase<'m, A, B>>(
    a: &mut A,
    b: &mut B,
    start: Option<(u32, u32)>,
    walk: &Walk<'m>,
    stack: &mut Vec<(u32, u32)>,
    stats: &mut QueryStats,
    narrow: &mut N,
) -> bool {
    let start = match start {
        Some(start) => start,
        None if roots_overlap(a, b, walk, stats) => (0, 0),
        None => return false,
    };
    stack.clear();
    stack.push(start);
    while let Some((na, nb)) = stack.pop() {
        if walk.skips(a, na, nb) {
            continue;
        }
        let (va, vb, how) = volumes_and_opening(a, b, na, nb, walk);
        if how == Open::Neither {
            stats.leaf_pairs += 1;
            if narrow.visit(a, b, na, nb, stats) {
                return true;
            }
            continue;
        }
        open_pair(a, b, na, nb, &va, &vb, how, stats, |x, y, _, _| {
            stack.push((x, y))
        });
    }
    false
}

/// Levels [`split`] opens at most: enough for hundreds of pairs from octrees (up to 64 child
/// pairs a level) and binary trees (up to 4) alike when contact is dense, including flat
/// contact, where a level that opens one side of a flat octree only doubles the pairs (two
/// coplanar sheets of 51,200 triangles stayed under 256 pairs after 6 levels: too few to share
/// between two threads).
const SPLIT_LEVELS: usize = 10;

/// Work for several threads: the overlapping node pairs `depth_first` meets, opened level by
/// level until there are at least `target` of them, all are terminal, or [`SPLIT_LEVELS`]
/// levels are open. `into.items` ends in the order in which [`depth_first`] reaches them, so
/// running [`depth_first`] below each in turn visits exactly the terminal pairs of
/// [`depth_first`] from the roots, in its order; the volume tests made here are counted.
pub(crate) fn split<'m, A: QuerySide<'m>, B: QuerySide<'m>>(
    a: &mut A,
    b: &mut B,
    walk: &Walk<'m>,
    target: usize,
    into: &mut Split,
    stats: &mut QueryStats,
) {
    let Split { items, next } = into;
    items.clear();
    if !roots_overlap(a, b, walk, stats) {
        return;
    }
    items.push((0, 0));
    // A few levels at most: where overlap is sparse the levels stay narrow, and opening them all
    // here would compute every volume twice (here, and again below each item).
    for _ in 0..SPLIT_LEVELS {
        if items.len() >= target {
            break;
        }
        next.clear();
        let mut opened = false;
        for &(na, nb) in items.iter() {
            if walk.skips(a, na, nb) {
                continue;
            }
            let (va, vb, how) = volumes_and_opening(a, b, na, nb, walk);
            if how == Open::Neither {
                next.push((na, nb));
                continue;
            }
            opened = true;
            let first = next.len();
            open_pair(a, b, na, nb, &va, &vb, how, stats, |x, y, _, _| {
                next.push((x, y))
            });
            // The depth-first stack pops the last child pair pushed first.
            next[first..].reverse();
        }
        std::mem::swap(items, next);
        if !opened {
            break;
        }
    }
}

/// Overlapping pairs are opened largest volume first while fewer than `budget` volume tests have
/// been made; then the pairs still waiting (the frontier) go to the narrow phase along with the
/// leaf pairs met on the way. The reported pairs cover every leaf pair [`depth_first`] would
/// report (every such pair lies below a reported one), and with a large enough budget they are
/// exactly those. At most one opening runs past the budget: `bv_tests` ends below `budget` plus
/// the child tests of one pair. Returns whether the narrow phase stopped the traversal.
pub(crate) fn best_first<'m, A: QuerySide<'m>, B: QuerySide<'m>, N: NarrowPhase<'m, A, B>>(
    a: &mut A,
    b: &mut B,
    budget: u64,
    own: Option<OneMesh<'m>>,
    queue: &mut BinaryHeap<Queued>,
    stats: &mut QueryStats,
    narrow: &mut N,
) -> bool {
    queue.clear();
    let walk = Walk {
        max_depth: u32::MAX,
        own,
    };
    let (ra, rb) = (a.volume(0), b.volume(0));
    if own.is_none() {
        stats.bv_tests += 1;
        if !ra.overlaps(&rb) {
            return false;
        }
    }
    let (nodes_a, nodes_b) = (a.nodes(), b.nodes());
    let key = |sa: f64, sb: f64| sa.max(sb).to_bits();
    // Leaf pairs cost no test: they are reported when found rather than queued.
    let mut found = [Queued { key: 0, a: 0, b: 0 }; MAX_CHILDREN * MAX_CHILDREN];
    found[0] = Queued {
        key: key(ra.size_squared(), rb.size_squared()),
        a: 0,
        b: 0,
    };
    let mut len = 1;
    loop {
        for q in &found[..len] {
            if walk.skips(a, q.a, q.b) {
                continue;
            }
            if nodes_a[q.a as usize].is_leaf() && nodes_b[q.b as usize].is_leaf() {
                stats.leaf_pairs += 1;
                if narrow.visit(a, b, q.a, q.b, stats) {
                    return true;
                }
            } else {
                queue.push(*q);
            }
        }
        len = 0;
        let Some(Queued { a: na, b: nb, .. }) = queue.pop() else {
            return false;
        };
        if stats.bv_tests >= budget {
            // The frontier: this pair and every one still queued, in any order.
            let rest = queue.drain().map(|q| (q.a, q.b));
            for (x, y) in std::iter::once((na, nb)).chain(rest) {
                stats.frontier_pairs += 1;
                if narrow.visit(a, b, x, y, stats) {
                    return true;
                }
            }
            return false;
        }
        let (va, vb, how) = volumes_and_opening(a, b, na, nb, &walk);
        open_pair(a, b, na, nb, &va, &vb, how, stats, |x, y, vx, vy| {
            found[len] = Queued {
                key: key(vx.size_squared(), vy.size_squared()),
                a: x,
                b: y,
            };
            len += 1;
        });
    }
}

/// Pair `p` as a key whose order is the pairs' `(a, b)` order.
#[inline]
pub(crate) fn pair_key(p: Pair) -> u64 {
    u64::from(p.a) << 32 | u64::from(p.b)
}

/// The pair of [`pair_key`]'s key `k`.
#[inline]
pub(crate) fn key_pair(k: u64) -> Pair {
    Pair {
        a: (k >> 32) as u32,
        b: k as u32,
    }
}

/// A narrow phase that keeps the least pair it has found, in `(a, b)` order: what
/// [`least_first`] prunes by.
pub(crate) trait Least {
    /// The least pair found so far as its [`pair_key`] (its bound before any is found).
    fn least(&self) -> u64;
}

/// The least pair of triangles `(a, b)`, in `(a, b)` order, that the narrow phase finds below
/// the overlapping terminal node pairs of meshes `a` and `b` (not one mesh), without visiting
/// them all: node pairs are opened least first by the least pair they may hold (the least
/// triangle of the rings below each node, `least_a` and `least_b`), and none is visited whose
/// least possible pair is not below the narrow phase's [`Least::least`]. Returns whether the
/// narrow phase stopped the traversal.
pub(crate) fn least_first<'m, A, B, N>(
    a: &mut A,
    b: &mut B,
    (least_a, least_b): (&[u32], &[u32]),
    queue: &mut BinaryHeap<Queued>,
    stats: &mut QueryStats,
    narrow: &mut N,
) -> bool
where
    A: QuerySide<'m>,
    B: QuerySide<'m>,
    N: NarrowPhase<'m, A, B> + Least,
{
    queue.clear();
    let walk = Walk {
        max_depth: u32::MAX,
        own: None,
    };
    if !roots_overlap(a, b, &walk, stats) {
        return false;
    }
    // The heap pops its greatest key: the complement of the least pair pops least first.
    let key = |x: u32, y: u32| {
        !pair_key(Pair {
            a: least_a[x as usize],
            b: least_b[y as usize],
        })
    };
    queue.push(Queued {
        key: key(0, 0),
        a: 0,
        b: 0,
    });
    while let Some(Queued {
        key: k,
        a: na,
        b: nb,
    }) = queue.pop()
    {
        if !k >= narrow.least() {
            // Every pair still queued may hold only pairs from this one's least on.
            return false;
        }
        let (va, vb, how) = volumes_and_opening(a, b, na, nb, &walk);
        if how == Open::Neither {
            stats.leaf_pairs += 1;
            if narrow.visit(a, b, na, nb, stats) {
                return true;
            }
            continue;
        }
        let bound = narrow.least();
        open_pair(a, b, na, nb, &va, &vb, how, stats, |x, y, _, _| {
            let k = key(x, y);
            if !k < bound {
                queue.push(Queued { key: k, a: x, b: y })
            }
        });
    }
    false
}
