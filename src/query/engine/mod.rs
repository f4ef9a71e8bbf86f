//! The query engine every entry point shares: the typed sides of a query, the one traversal,
//! the leaf narrow phase with its pair tests, the threads, the sink and sort of the result, and
//! the scratch space kept between queries.

mod narrow;
mod parallel;
mod run;
mod side;
mod sink;
mod sort;
mod traverse;
mod workspace;

pub(crate) use narrow::{Reach, TriangleTest};
pub(crate) use run::{QueryMesh, leaf_pairs, node_pairs, query, query_lazy, query_one};
pub(crate) use side::{NodeVolumes, Widened};
pub(crate) use traverse::OneMesh;
pub(crate) use workspace::{Prepared, Stamped, Workspace};
