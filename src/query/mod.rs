//! Queries between two meshes: options, results, the traversal, and the brute-force reference.

mod brute_force;
mod collide;
mod options;
mod pairs;
mod sort;
mod workspace;

pub use brute_force::brute_force;
pub use collide::collide;
pub use options::{QueryMode, QueryOptions};
pub use pairs::{Pair, PairKind, Pairs, QueryStats};
