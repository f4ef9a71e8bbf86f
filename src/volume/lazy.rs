//! Lazy refit of box volumes, by blocks: a query recomputes the nodes of a block of the tree only
//! when its traversal first reads one of them, so the parts of a deforming mesh that no other
//! mesh comes near are never refit.
//!
//! Why blocks and not single nodes: a box computed top-down from the vertices below it costs as
//! much as refitting its whole subtree bottom-up (both read every vertex of every ring below),
//! so node-by-node laziness would pay once per level. Instead the tree is cut into blocks of
//! about [`BLOCK_RINGS`] rings. The nodes above the cut ("the top", the blocks' roots included)
//! are computed whenever the mesh is needed at all, from one pass over the positions in memory
//! order (each vertex grows the box of its home block) plus the few vertices a block's rings
//! share with another block; a block's nodes below its root are refit bottom-up when the
//! traversal first opens its root. Boxes are minima and maxima of the same coordinates however
//! they are grouped, so every box equals the eager refit's.
//!
//! Threads: the pairs of a scene's query run on several threads and may reach one mesh from
//! several of them. A block is filled once: its flag is read with acquire ordering, and a thread
//! that finds it clear takes the mesh's lock, checks again, refits the block and sets the flag
//! with release ordering. Nodes of a block are read only once its flag is set and written only
//! before, under the lock, so no box is read while it is written.

use super::RefitInput;
use super::boxes::FitBoxes;
use super::fit::{Fit, NodeSlice, VolumeSlices, fit_below};
use crate::csr::Csr;
use crate::geometry::aabb::Aabb;
use crate::tree::{Subtree, Tree};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Rings per block, at most. Smaller blocks skip more of a mesh that is barely touched; the
/// vertices a block shares with its neighbours (read again by the top pass) grow as blocks
/// shrink.
const BLOCK_RINGS: u32 = 32;

/// `Blocks::node_block` of a node above the cut.
const TOP: u32 = u32::MAX;

/// How a tree is cut into blocks for lazy refit. Depends on the shape only: built once per
/// shape, on first use.
#[derive(Debug, Default)]
pub(crate) struct Blocks {
    /// The blocks: inner nodes, none below another, in node order.
    blocks: Vec<Subtree>,
    /// Each node's block, [`TOP`] for nodes above the cut and the blocks' roots.
    node_block: Vec<u32>,
    /// The block whose rings first name each vertex, in leaf order; [`TOP`] for vertices that
    /// only the top's leaves name, or none.
    home: Vec<u32>,
    /// Per block: the vertices its rings name whose home is another block (or the top).
    shared: Csr<u32>,
    /// The nodes above the cut, blocks' roots excluded, children before parents.
    top: Vec<u32>,
}

impl Blocks {
    /// The blocks of `tree`, for meshes of `vertex_count` vertices and rings `input.rings`.
    pub fn new(input: &RefitInput, vertex_count: usize) -> Blocks {
        let (tree, rings) = (input.tree, input.rings);
        let blocks = Tree::cut_while(&tree.nodes, |_, largest| largest > BLOCK_RINGS);
        let mut node_block = vec![TOP; tree.len()];
        let mut home = vec![TOP; vertex_count];
        for (k, b) in blocks.iter().enumerate() {
            node_block[b.nodes.start as usize..b.nodes.end as usize].fill(k as u32);
            for r in b.rings.start as usize..b.rings.end as usize {
                for v in rings.all_vertices(r) {
                    if home[v as usize] == TOP {
                        home[v as usize] = k as u32;
                    }
                }
            }
        }
        let mut shared = Csr::with_capacity(blocks.len(), 0);
        let mut row = Vec::new();
        for (k, b) in blocks.iter().enumerate() {
            row.clear();
            for r in b.rings.start as usize..b.rings.end as usize {
                row.extend(
                    rings
                        .all_vertices(r)
                        .filter(|&v| home[v as usize] != k as u32),
                );
            }
            row.sort_unstable();
            row.dedup();
            for &v in &row {
                shared.push(v);
            }
            shared.end_row();
        }
        let mut is_root = vec![false; tree.len()];
        for b in &blocks {
            is_root[b.root as usize] = true;
        }
        let top = (0..tree.len() as u32)
            .rev()
            .filter(|&n| node_block[n as usize] == TOP && !is_root[n as usize])
            .collect();
        Blocks {
            blocks,
            node_block,
            home,
            shared,
            top,
        }
    }

    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        use crate::csr::heap_bytes;
        heap_bytes(&self.blocks)
            + heap_bytes(&self.node_block)
            + heap_bytes(&self.home)
            + self.shared.heap_bytes()
            + heap_bytes(&self.top)
    }
}

/// Which blocks of one mesh's boxes are current: kept with the mesh between queries, reset when
/// its positions change.
#[derive(Debug, Default)]
pub(crate) struct Freshness {
    /// Are the top's boxes (the blocks' roots included) current?
    top: bool,
    /// Per block: are its boxes below the root current?
    filled: Vec<AtomicBool>,
    /// Blocks not yet filled.
    missing: usize,
    /// Taken to fill a block.
    lock: Mutex<()>,
    /// Nodes recomputed since the counter was last read.
    nodes: AtomicU64,
}

impl Clone for Freshness {
    fn clone(&self) -> Self {
        Freshness {
            top: self.top,
            filled: self
                .filled
                .iter()
                .map(|f| AtomicBool::new(f.load(Ordering::Relaxed)))
                .collect(),
            missing: self.missing,
            lock: Mutex::new(()),
            nodes: AtomicU64::new(self.nodes.load(Ordering::Relaxed)),
        }
    }
}

impl Freshness {
    /// Every box current (an object made from a mesh, whose volumes are).
    pub fn current() -> Freshness {
        Freshness {
            top: true,
            ..Freshness::default()
        }
    }

    /// Nothing current.
    pub fn stale(&mut self) {
        self.top = false;
        self.missing = usize::MAX;
    }

    /// Is every box current?
    pub fn is_current(&self) -> bool {
        self.top && self.missing == 0
    }

    /// Are the top's boxes current, and some block's not? (Then a query reads them through a
    /// [`LazyBoxes`].)
    pub fn is_partial(&self) -> bool {
        self.top && self.missing > 0
    }

    /// Every box current (after an eager refit).
    pub fn refit(&mut self) {
        self.top = true;
        self.missing = 0;
        for f in &mut self.filled {
            *f.get_mut() = true;
        }
    }

    /// Nodes recomputed since the last call.
    pub fn take_nodes(&mut self) -> u64 {
        std::mem::take(self.nodes.get_mut())
    }

    /// Counts the blocks still missing (after a query has filled some).
    pub fn settle(&mut self) {
        if self.top {
            self.missing = self
                .filled
                .iter()
                .filter(|f| !f.load(Ordering::Relaxed))
                .count();
        }
    }

    /// Is node `n`'s box current?
    #[cfg(test)]
    pub fn node_is_current(&self, blocks: &Blocks, n: usize) -> bool {
        if self.is_current() {
            return true;
        }
        let k = blocks.node_block[n];
        self.top && (k == TOP || self.filled[k as usize].load(Ordering::Relaxed))
    }

    /// Makes the top current: the blocks' roots from one pass over the positions and the shared
    /// vertices, then the top's leaves from their rings and its inner nodes from their children.
    /// Marks every block unfilled.
    pub fn fit_top(&mut self, blocks: &Blocks, input: &RefitInput, boxes: &mut [Aabb]) {
        if self.top {
            return;
        }
        let positions = input.positions;
        let mut roots = vec![Aabb::EMPTY; blocks.len()];
        for (p, &k) in positions.iter().zip(&blocks.home) {
            if k != TOP {
                roots[k as usize].grow(p);
            }
        }
        for (k, (b, root)) in blocks.blocks.iter().zip(&mut roots).enumerate() {
            for &v in blocks.shared.row(k) {
                root.grow(&positions[v as usize]);
            }
            boxes[b.root as usize] = *root;
        }
        let mut w = VolumeSlices {
            spheres: NodeSlice::whole(&mut []),
            boxes: NodeSlice::whole(boxes),
        };
        for &n in &blocks.top {
            let node = &input.tree.nodes[n as usize];
            if node.is_leaf() {
                FitBoxes.leaf(&mut w, input, node.ring_start as usize, n as usize);
            } else {
                FitBoxes.inner(&mut w, input, n as usize, &mut Vec::new());
            }
        }
        self.filled.clear();
        self.filled
            .resize_with(blocks.len(), || AtomicBool::new(false));
        self.missing = blocks.len();
        self.top = true;
        *self.nodes.get_mut() += (blocks.top.len() + blocks.len()) as u64;
    }
}

/// One mesh's boxes as a query reads them: nodes above the cut are current; a block's nodes
/// are refit the first time one of them is read.
pub(crate) struct LazyBoxes<'m> {
    boxes: *mut Aabb,
    len: usize,
    blocks: &'m Blocks,
    fresh: &'m Freshness,
    input: RefitInput<'m>,
}

// SAFETY: `boxes` is written only under `fresh.lock`, for a block not yet marked filled, and
// read only for nodes of the top or of filled blocks (see the module's comment).
unsafe impl Sync for LazyBoxes<'_> {}
unsafe impl Send for LazyBoxes<'_> {}

impl<'m> LazyBoxes<'m> {
    /// The lazy view of `boxes`, whose top `fresh` holds current.
    ///
    /// # Safety
    /// `boxes` is valid for reads and writes, and for as long as the view lives nothing else
    /// reads or writes it (it is reached only through this view).
    pub unsafe fn new(
        boxes: *mut [Aabb],
        blocks: &'m Blocks,
        fresh: &'m Freshness,
        input: RefitInput<'m>,
    ) -> Self {
        assert!(fresh.top && boxes.len() == input.tree.len());
        assert_eq!(fresh.filled.len(), blocks.len());
        LazyBoxes {
            boxes: boxes.cast::<Aabb>(),
            len: boxes.len(),
            blocks,
            fresh,
            input,
        }
    }

    /// Node `n`'s box, its block refit first if it is not yet.
    #[inline(always)]
    pub fn get(&self, n: u32) -> Aabb {
        let n = n as usize;
        assert!(n < self.len, "node {n} out of range");
        let k = self.blocks.node_block[n];
        if k != TOP && !self.fresh.filled[k as usize].load(Ordering::Acquire) {
            self.fill(k as usize);
        }
        // SAFETY: in range; the node is in the top or in a filled block, so no thread writes it.
        unsafe { *self.boxes.add(n) }
    }

    #[cold]
    #[inline(never)]
    fn fill(&self, k: usize) {
        let _guard = self.fresh.lock.lock().unwrap_or_else(|e| e.into_inner());
        let flag = &self.fresh.filled[k];
        if flag.load(Ordering::Acquire) {
            return;
        }
        let b = &self.blocks.blocks[k];
        let (start, end) = (b.nodes.start as usize, b.nodes.end as usize);
        assert!(start <= end && end <= self.len);
        // SAFETY: the block's nodes are in range; no thread reads them until the flag is set
        // below, and no other writes them (the lock is held and the flag was clear).
        let items = unsafe { std::slice::from_raw_parts_mut(self.boxes.add(start), end - start) };
        let mut w = VolumeSlices {
            spheres: NodeSlice::whole(&mut []),
            boxes: NodeSlice::at(start, items),
        };
        fit_below(&FitBoxes, &mut w, &self.input, b, &mut Vec::new());
        self.fresh
            .nodes
            .fetch_add((end - start) as u64, Ordering::Relaxed);
        flag.store(true, Ordering::Release);
    }
}
