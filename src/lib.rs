//! # dvh
//!
//! Collision detection between deformable triangle meshes, with the DVH hierarchy (Madera, Day,
//! Laycock 2009): spheres centred on mesh vertices over vertex 1-rings, refit by recomputing
//! radii only when the mesh deforms (boxes and recentred spheres are offered too). Every
//! triangle pair it reports is decided by an exact test, touching included.
//!
//! ```
//! use dvh::{BuildOptions, Mesh, Pairs, QueryOptions, collide};
//!
//! // Two unit right triangles, the second standing through the first.
//! let a = Mesh::new(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0], &[0, 1, 2], &BuildOptions::default())?;
//! let mut b = Mesh::new(&[0.2, 0.2, -1.0, 0.2, 0.2, 1.0, 1.0, 1.0, 0.0], &[0, 1, 2], &BuildOptions::default())?;
//! let mut pairs = Pairs::new();
//! collide(&a, None, &b, None, &QueryOptions::default(), &mut pairs)?;
//! assert_eq!(pairs.len(), 1);
//!
//! // Deform b (move it up by 2) and query again: no more contact.
//! b.refit(&[0.2, 0.2, 1.0, 0.2, 0.2, 3.0, 1.0, 1.0, 2.0])?;
//! collide(&a, None, &b, None, &QueryOptions::default(), &mut pairs)?;
//! assert!(pairs.is_empty());
//! # Ok::<(), dvh::Error>(())
//! ```
//!
//! ## Where to go
//!
//! - **Two meshes.** Build a [`Mesh`] with [`BuildOptions`], [`Mesh::refit`] it after each
//!   deformation, and [`collide`] two of them, each placed by an optional [`Pose`].
//!   [`QueryOptions`] and [`QueryMode`] trade precision for speed (exact pairs, the first hit,
//!   leaf or node pairs); results go to a reusable [`Pairs`], counters to [`QueryStats`].
//!   [`brute_force`] is the all-pairs reference.
//! - **One mesh against itself.** [`self_collide`]: folds and crossings, not the contact of
//!   neighbouring triangles.
//! - **Nearness.** [`proximity`] and [`self_proximity`]: every triangle pair within a distance,
//!   exact.
//! - **Motion over a step.** [`Mesh::refit_motion`] gives a mesh straight-line motion from
//!   start to end positions; [`continuous_collide`] and [`self_continuous_collide`] report
//!   every vertex-face and edge-edge pair that meets during the step, with its earliest time
//!   ([`Impacts`], [`CcdOptions`], [`CcdStats`]), exactly or ([`CcdMode::Conservative`]) in
//!   floating point only.
//! - **Many objects.** A [`Scene`] of rigid and deformable objects sharing meshes, with groups,
//!   masks and exclusions; [`Scene::collide`] reports [`Contacts`] and [`SceneStats`].
//! - **The exact predicates on their own.** [`exact`]: [`exact::triangles_intersect`],
//!   [`exact::triangles_within`], [`exact::orient3d`]; and for primitives moving over a step,
//!   [`exact::vertex_face_impact`] and [`exact::edge_edge_impact`] (whether and first when).
//! - **Failures.** Every fallible call returns an [`Error`] that says what was wrong, and
//!   changes nothing when it fails.
//! - **From C and other languages.** The C ABI is declared in `include/dvh.h` (the library
//!   builds as `cdylib` and `staticlib`); the header's opening comment gives its conventions.
//! - **Figures and guarantees.** `BENCHMARKS.md` measures the options against each other and
//!   against FCL and parry; `ROBUSTNESS.md` says how the exactness and the C ABI's resistance to
//!   misuse are tested.

#![warn(missing_docs)]

mod csr;
mod error;
pub mod exact;
// The C ABI: public so that the fuzz drivers and the FFI benchmark call it as C does, hidden
// because Rust users have the Rust API; its functions are exported from the cdylib and declared
// in include/dvh.h either way.
#[doc(hidden)]
pub mod ffi;
#[cfg(feature = "fixtures")]
pub mod fixtures;
mod geometry;
mod limits;
mod mesh;
mod prefetch;
mod query;
mod scene;
mod threads;
mod tree;
mod volume;

/// Hooks for the tests of the threaded paths: not part of the API.
#[doc(hidden)]
pub mod testing {
    pub use crate::mesh::scratch_growths as patch_scratch_growths;
    pub use crate::threads::{Step, at_least_two_threads, shared_count, sharing};
}

pub use error::{Error, Instant, Result, Side};
pub use geometry::MAX_POSED_MAGNITUDE;
pub use geometry::aabb::Aabb;
pub use geometry::ccd::CcdMode;
pub use geometry::pose::{Pose, RIGIDITY_TOLERANCE};
pub use geometry::sphere::Sphere;
pub use mesh::{
    BoundingVolume, BuildOptions, InvariantError, LeftoverPolicy, Mesh, NodeView, RadiusKind,
    RefitStats, TreeStats,
};
pub use query::{
    CcdOptions, CcdStats, ClosestPoint, Curve, CurvePoint, CurveSegment, Curves, DegenerateKind,
    DegeneratePair, Distance, DistanceOptions, Impact, ImpactKind, Impacts, NearPair, NearPairs,
    Pair, PairKind, Pairs, QueryMode, QueryOptions, QueryStats, WINDING_ON_SURFACE, brute_force,
    closest_points, collide, continuous_collide, distance, intersection_curves, nearest_features,
    proximity, self_collide, self_continuous_collide, self_intersection_curves,
    self_nearest_features, self_proximity, signed_distances, winding_numbers,
};
pub use scene::{
    Contact, Contacts, Scene, SceneDistance, SceneImpact, SceneImpacts, SceneNearPair,
    SceneNearPairs, SceneStats,
};
pub use tree::TreeKind;
pub use volume::VolumeKind;

/// The README's examples, compiled and run as documentation tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
