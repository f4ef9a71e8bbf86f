//! Query results: pairs, the reusable result buffer, counters.

use super::engine::Workspace;
use crate::csr::heap_bytes;

/// A pair of indices, one from each mesh: triangles, or nodes for the coarse modes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(C)]
pub struct Pair {
    /// Index into the first mesh (`a`).
    pub a: u32,
    /// Index into the second mesh (`b`).
    pub b: u32,
}

/// What the indices of a [`Pairs`] buffer refer to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PairKind {
    /// Triangle indices ([`crate::QueryMode::Triangles`], [`crate::QueryMode::FirstHit`]).
    #[default]
    Triangles,
    /// Node indices ([`crate::QueryMode::Leaves`], [`crate::QueryMode::Depth`],
    /// [`crate::QueryMode::Budget`]); expand them with [`crate::Mesh::node_triangles`].
    Nodes,
}

/// A caller-owned, reusable result buffer. It also keeps the scratch space a query needs, so that
/// once it has grown to a scene's needs a query on one thread allocates nothing. Use one per
/// calling thread.
#[derive(Debug, Default)]
pub struct Pairs {
    pub(crate) items: Vec<Pair>,
    /// Where a query writes; swapped with `items` when it succeeds, so a failed query leaves the
    /// previous result in place.
    pub(crate) spare: Vec<Pair>,
    pub(crate) kind: PairKind,
    pub(crate) workspace: Workspace,
}

/// The read side shared by the result buffers ([`Pairs`], the scene's `Contacts`, `Impacts`,
/// `NearPairs`): a struct with a field `items: Vec<$item>` (and `kind: PairKind` when `kind:` is
/// given) and `Default`. The docs of `as_slice` and `kind` are the buffer's own; the others name
/// its items.
macro_rules! result_buffer {
    (
        $buffer:ident, $item:ty, $items:literal, as_slice: $as_slice:literal
        $(, kind: $kind:literal)?
    ) => {
        impl $buffer {
            /// An empty buffer.
            pub fn new() -> $buffer {
                $buffer::default()
            }

            #[doc = $as_slice]
            pub fn as_slice(&self) -> &[$item] {
                &self.items
            }

            #[doc = concat!("Number of ", $items, ".")]
            pub fn len(&self) -> usize {
                self.items.len()
            }

            #[doc = concat!("No ", $items, "?")]
            pub fn is_empty(&self) -> bool {
                self.items.is_empty()
            }

            $(
                #[doc = $kind]
                pub fn kind(&self) -> PairKind {
                    self.kind
                }
            )?

            #[doc = concat!("Iterates over the ", $items, ".")]
            pub fn iter(&self) -> std::slice::Iter<'_, $item> {
                self.items.iter()
            }
        }

        impl<'a> IntoIterator for &'a $buffer {
            type Item = &'a $item;
            type IntoIter = std::slice::Iter<'a, $item>;
            fn into_iter(self) -> Self::IntoIter {
                self.items.iter()
            }
        }
    };
}
pub(crate) use result_buffer;

result_buffer!(
    Pairs,
    Pair,
    "pairs",
    as_slice: "The pairs of the last successful query, sorted and without duplicates.",
    kind: "What the indices refer to."
);

impl Pairs {
    /// Bytes of memory the buffer holds beyond the struct itself: the result, the spare it
    /// writes the next one into, and the scratch space of the queries it served (per thread
    /// that took part: stack, caches of ring boxes and posed vertices, prepared rings, found
    /// pairs). It grows with the largest query served and is kept for the next.
    pub fn memory_bytes(&self) -> usize {
        heap_bytes(&self.items) + heap_bytes(&self.spare) + self.workspace.heap_bytes()
    }
}

/// Counters of one query: the terms of the paper's cost model `T = NV·CV + NP·CP + NU·CU`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct QueryStats {
    /// Volume pairs tested for overlap (`NV`).
    pub bv_tests: u64,
    /// Triangle pairs given to the exact test (`NP`).
    pub triangle_tests: u64,
    /// Triangle pairs of overlapping leaves, before the exact bounding-box filter that decides
    /// which go to the exact test.
    pub triangle_candidates: u64,
    /// Overlapping pairs of terminal nodes (leaves, or nodes at the depth limit) the traversal
    /// reached.
    pub leaf_pairs: u64,
    /// Pairs reported.
    pub pairs: u64,
    /// Nodes recomputed by the last refit of each mesh (`NU` of the frame).
    pub nodes_refit: u64,
    /// Did [`crate::QueryOptions::max_pairs`] stop the query before every pair was found?
    pub truncated: bool,
    /// Overlapping node pairs left unopened when [`crate::QueryMode::Budget`]'s budget ran out,
    /// and reported as they are (0: the budget sufficed, the answer is [`crate::QueryMode::Leaves`]'s).
    pub frontier_pairs: u64,
}

impl QueryStats {
    /// Adds the traversal's counters of `other` (the work of another thread on the same query).
    pub(crate) fn add(&mut self, other: &QueryStats) {
        self.bv_tests += other.bv_tests;
        self.triangle_tests += other.triangle_tests;
        self.triangle_candidates += other.triangle_candidates;
        self.leaf_pairs += other.leaf_pairs;
    }
}
