//! What a query computes: the speed/accuracy knobs.

/// What a query reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
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
}

/// Options for [`crate::collide`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct QueryOptions {
    /// What the query reports.
    pub mode: QueryMode,
    /// Stop once this many pairs are found (`None`: no limit). The pairs reported are then some
    /// of the pairs, still sorted, and [`crate::QueryStats::truncated`] says so. A bound on the
    /// work and memory of a query whatever the input, as contact-generation APIs usually offer.
    pub max_pairs: Option<usize>,
}

impl QueryOptions {
    /// Options with the given mode and no pair limit.
    pub fn with_mode(mode: QueryMode) -> QueryOptions {
        QueryOptions {
            mode,
            max_pairs: None,
        }
    }
}
