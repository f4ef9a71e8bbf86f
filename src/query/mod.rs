//! Queries between two meshes and of one mesh against itself (intersection, nearness): options,
//! results, the one traversal, and the brute-force reference.

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
#[cfg(test)]
mod testing;
mod traverse;
mod workspace;

pub use brute_force::brute_force;
pub use collide::collide;
pub(crate) use collide::collide_lazy;
pub use options::{QueryMode, QueryOptions};
pub use pairs::{Pair, PairKind, Pairs, QueryStats};
pub(crate) use patches::{Facts, Patches};
pub use proximity::{proximity, self_proximity};
pub use self_collide::self_collide;
