//! Queries between two meshes: options, results, the traversal, and the brute-force reference.

mod brute_force;
mod collide;
mod narrow;
mod options;
mod pairs;
mod parallel;
mod patches;
mod proximity;
mod self_collide;
mod side;
mod sink;
mod sort;
mod traverse;
mod workspace;

pub use brute_force::brute_force;
pub use collide::collide;
pub(crate) use collide::collide_lazy;
pub use options::{QueryMode, QueryOptions};
pub use pairs::{Pair, PairKind, Pairs, QueryStats};
pub(crate) use patches::Patches;
