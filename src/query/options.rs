//! What a query computes: the speed/accuracy knobs.

/// What a query reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum QueryMode {
    /// Every intersecting triangle pair, decided by the exact test: exactly the pairs a
    /// brute-force all-pairs exact test reports.
    #[default]
    Triangles,
    /// Stop at the first intersecting triangle pair found; report it (or nothing). `true` from
    /// this mode is the same as a non-empty result from [`QueryMode::Triangles`].
    FirstHit,
    /// Pairs of leaves (1-rings) whose spheres overlap, without triangle tests. Conservative: the
    /// triangle pairs of the reported leaves include every intersecting pair.
    Leaves,
    /// Stop descending at this depth (the root is depth 0): pairs of nodes whose spheres overlap,
    /// each node a leaf or at the depth limit. Conservative like [`QueryMode::Leaves`].
    Depth(u32),
    /// A guaranteed cost: at most this many volume tests, plus the child tests of one node pair
    /// (64 at most, for two octree nodes). Overlapping node pairs are opened largest volumes
    /// first; when the budget is spent, the pairs still unopened (the frontier, counted by
    /// [`crate::QueryStats::frontier_pairs`]) are reported along with the leaf pairs reached.
    /// Conservative like [`QueryMode::Leaves`]: the reported pairs' triangles include every
    /// intersecting pair. With a budget large enough to finish, exactly the pairs
    /// [`QueryMode::Leaves`] reports. The budget must be at least 1 (the roots' test).
    Budget(u64),
}

impl QueryMode {
    /// The depth at which the traversal stops opening nodes.
    pub(crate) fn max_depth(self) -> u32 {
        match self {
            QueryMode::Depth(d) => d,
            _ => u32::MAX,
        }
    }

    /// Does this mode report node pairs ([`crate::PairKind::Nodes`]) rather than triangle pairs?
    pub fn reports_nodes(self) -> bool {
        matches!(
            self,
            QueryMode::Leaves | QueryMode::Depth(_) | QueryMode::Budget(_)
        )
    }
}

/// Options for [`crate::collide`]. Start from the defaults or [`QueryOptions::with_mode`], then
/// set what you need with the `with_*` methods (or the fields).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct QueryOptions {
    /// What the query reports.
    pub mode: QueryMode,
    /// Stop once this many pairs are found (`None`: no limit). The pairs reported are then some
    /// of the pairs, still sorted, and [`crate::QueryStats::truncated`] says so. A bound on the
    /// work and memory of a query whatever the input, as contact-generation APIs usually offer.
    pub max_pairs: Option<usize>,
    /// Threads the query may use: 0 (the default) for every core, 1 for the calling thread
    /// only, `n` for at most `n`. Threads come from rayon's global pool, created once per
    /// process (see the README); no call creates any. The result is the same, pair for pair and
    /// in the same order, whatever the count; so are the counters, except that a query cut
    /// short by [`QueryOptions::max_pairs`] or [`QueryMode::FirstHit`] may count work done by
    /// other threads past the cut. [`QueryMode::Budget`] and small meshes (a few thousand
    /// triangles between them, where handing work out costs more than it saves) run on the
    /// calling thread.
    pub threads: u32,
}

impl QueryOptions {
    /// Options with the given mode, no pair limit, every core.
    pub fn with_mode(mode: QueryMode) -> QueryOptions {
        QueryOptions {
            mode,
            ..QueryOptions::default()
        }
    }

    /// These options with [`QueryOptions::max_pairs`] set: `QueryOptions::with_mode(mode)
    /// .with_max_pairs(Some(100))`.
    pub fn with_max_pairs(self, max_pairs: Option<usize>) -> QueryOptions {
        QueryOptions { max_pairs, ..self }
    }

    /// These options with [`QueryOptions::threads`] set.
    pub fn with_threads(self, threads: u32) -> QueryOptions {
        QueryOptions { threads, ..self }
    }
}
