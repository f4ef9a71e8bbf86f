//! The query engine every entry point shares: the typed sides of a query, the one traversal,
//! the leaf narrow phase with its pair tests, the threads, the sink and sort of the result, and
//! the scratch space kept between queries.

mod dispatch;
mod pair_test;
mod parallel;
mod side;
mod sink;
mod sort;
mod terminal;
mod traverse;
mod workspace;

pub(crate) use dispatch::{QueryMesh, leaf_pairs, node_pairs, query, query_lazy, query_one};
pub(crate) use pair_test::{Reach, TriangleTest};
pub(crate) use side::{NodeVolumes, Widened};
pub(crate) use traverse::OneMesh;
pub(crate) use workspace::{Prepared, Stamped, Workspace};
