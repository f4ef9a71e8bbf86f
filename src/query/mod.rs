//! Queries between two meshes and of one mesh against itself (intersection, nearness): the entry
//! points, their options and results, and the brute-force reference; the engine they share is
//! in `engine`.

mod brute_force;
mod collide;
mod continuous;
mod curves;
mod distance;
mod engine;
mod nearest;
mod options;
mod pairs;
mod points;
mod primitives;
mod proximity;
mod self_collide;
#[cfg(test)]
mod testing;

pub use brute_force::brute_force;
pub use collide::collide;
pub(crate) use collide::collide_lazy;
pub(crate) use continuous::impacts_sharing;
pub use continuous::{
    CcdOptions, CcdStats, Impact, ImpactKind, Impacts, continuous_collide, self_continuous_collide,
};
pub use curves::{
    Curve, CurvePoint, CurveSegment, Curves, DegenerateKind, DegeneratePair, intersection_curves,
    self_intersection_curves,
};
pub use distance::{Distance, distance};
pub use nearest::{NearPair, NearPairs, nearest_features, self_nearest_features};
pub use options::{QueryMode, QueryOptions};
pub(crate) use pairs::result_buffer;
pub use pairs::{Pair, PairKind, Pairs, QueryStats};
pub use points::{
    ClosestPoint, DistanceOptions, WINDING_ON_SURFACE, closest_points, signed_distances,
    winding_numbers,
};
pub(crate) use proximity::check_distance;
pub use proximity::{proximity, self_proximity};
pub use self_collide::self_collide;
