//! What continuous collision reports: impacts, the reusable buffer they go to, options and
//! counters.

use crate::csr::heap_bytes;
use crate::geometry::ccd::CcdMode;
use crate::query::pairs::{Pairs, result_buffer};
pub use crate::query::primitives::ImpactKind;
use crate::query::primitives::Workspace;

/// Two primitives that meet during the step, and the earliest time they do.
///
/// Impacts are sorted by `(kind, a0, a1, b0, b1)`; the indices are vertex or triangle indices
/// as [`ImpactKind`] says, `a1` and `b1` zero where unused.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Impact {
    /// Which primitives.
    pub kind: ImpactKind,
    /// The first mesh's vertex, triangle, or edge's lower vertex.
    pub a0: u32,
    /// The first mesh's edge's higher vertex; 0 otherwise.
    pub a1: u32,
    /// The second mesh's triangle, vertex, or edge's lower vertex.
    pub b0: u32,
    /// The second mesh's edge's higher vertex; 0 otherwise.
    pub b1: u32,
    /// The earliest time in [0, 1] at which they meet, rounded down to a double (the largest
    /// double not above it; 0 when they touch at the start). With
    /// [`CcdMode::Conservative`], a time no later than that.
    pub toi: f64,
}

impl Impact {
    /// The order of a result: `(kind, a0, a1, b0, b1)`.
    pub(crate) fn key(&self) -> (ImpactKind, u32, u32, u32, u32) {
        (self.kind, self.a0, self.a1, self.b0, self.b1)
    }
}

/// Options of [`crate::continuous_collide`] and [`crate::self_continuous_collide`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct CcdOptions {
    /// Exact, or floating point only.
    pub mode: CcdMode,
    /// Threads, as [`crate::QueryOptions::threads`]: 0 for every core, 1 for the calling
    /// thread. The impacts are the same, in the same order, whatever the count.
    pub threads: u32,
    /// Stop once this many impacts are found (`None`: no limit); [`CcdStats::truncated`] then
    /// says so. Which impacts are kept does not depend on the thread count.
    pub max_impacts: Option<usize>,
    /// Report only the earliest impact (of several at that time, the first in the result's
    /// order): the fraction of the step that is free of contact, which a line search needs.
    /// Much cheaper than the whole list: each primitive test searches only up to the earliest
    /// impact found so far, and in the exact mode triangle pairs whose sweeps up to that time
    /// are apart are not tested at all. (The conservative mode's times may come before the
    /// contact, so it cannot skip pairs so and tests every pair.)
    pub earliest_only: bool,
}

impl CcdOptions {
    /// These options with [`CcdOptions::mode`] set.
    pub fn with_mode(self, mode: CcdMode) -> CcdOptions {
        CcdOptions { mode, ..self }
    }

    /// These options with [`CcdOptions::threads`] set.
    pub fn with_threads(self, threads: u32) -> CcdOptions {
        CcdOptions { threads, ..self }
    }

    /// These options with [`CcdOptions::max_impacts`] set.
    pub fn with_max_impacts(self, max_impacts: Option<usize>) -> CcdOptions {
        CcdOptions {
            max_impacts,
            ..self
        }
    }

    /// These options with [`CcdOptions::earliest_only`] set.
    pub fn with_earliest_only(self, earliest_only: bool) -> CcdOptions {
        CcdOptions {
            earliest_only,
            ..self
        }
    }
}

/// Counters of one continuous query.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct CcdStats {
    /// Volume pairs tested by the traversal over the motion.
    pub bv_tests: u64,
    /// Primitive pairs (vertex-face, edge-edge) given to the continuous test.
    pub primitive_tests: u64,
    /// Impacts reported.
    pub impacts: u64,
    /// The earliest time of the impacts reported; infinity when there are none.
    pub earliest_toi: f64,
    /// Did [`CcdOptions::max_impacts`] stop the query before every impact was found?
    pub truncated: bool,
}

impl Default for CcdStats {
    fn default() -> CcdStats {
        CcdStats {
            bv_tests: 0,
            primitive_tests: 0,
            impacts: 0,
            earliest_toi: f64::INFINITY,
            truncated: false,
        }
    }
}

/// A caller-owned, reusable buffer of impacts, with the scratch space continuous queries need
/// (so that once grown to a scene's needs, a query on one thread allocates little). Use one per
/// calling thread.
#[derive(Debug, Default)]
pub struct Impacts {
    pub(crate) items: Vec<Impact>,
    /// Where a query writes; swapped with `items` when it succeeds.
    pub(crate) spare: Vec<Impact>,
    /// The traversal's leaf pairs, and its scratch space.
    pub(crate) leaves: Pairs,
    /// The narrow phase's scratch space.
    pub(crate) narrow_space: Workspace<Impact>,
}

result_buffer!(
    Impacts,
    Impact,
    "impacts",
    as_slice: "The impacts of the last successful query, sorted by `(kind, a0, a1, b0, b1)`."
);

impl Impacts {
    /// Bytes of memory the buffer holds beyond the struct itself: the result, its spare, and
    /// the scratch space of the queries it served.
    pub fn memory_bytes(&self) -> usize {
        heap_bytes(&self.items)
            + heap_bytes(&self.spare)
            + self.leaves.memory_bytes()
            + self.narrow_space.heap_bytes()
    }
}
