//! The query engine every entry point shares, each file one step of a query:
//!
//! - `dispatch.rs`: from an entry point's meshes, poses and options to the one traversal typed
//!   for them (placement x volume kind), run on one thread or shared out;
//! - `side.rs`: a query's typed sides (placed vertices, node volumes, widened by a distance);
//! - `traverse.rs`: the one traversal of node pairs, which hands terminal pairs on;
//! - `parallel.rs`: the traversal's top shared out between threads;
//! - `query_traits.rs`: the traits a query implements: its settings (`Reach`) and, for the
//!   triangle queries, the triangle test (`TriangleTest`);
//! - `terminal.rs`: what becomes of a terminal node pair: kept as a node pair (the coarse
//!   modes), or its triangle pairs tested (the leaf narrow phase);
//! - `sink.rs`, `sort.rs`: where found pairs go, and their order;
//! - `workspace.rs`: the scratch space kept between queries.

mod dispatch;
mod parallel;
mod query_traits;
mod side;
mod sink;
mod sort;
mod terminal;
mod traverse;
mod workspace;

pub(crate) use dispatch::{QueryMesh, leaf_pairs, least_pair, node_pairs, query, query_one};
pub(crate) use query_traits::{Reach, TriangleTest};
pub(crate) use side::{NodeVolumes, Widened};
pub(crate) use traverse::OneMesh;
pub(crate) use workspace::{Prepared, Stamped, Workspace};
