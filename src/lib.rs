//! # dvh: collision detection between deformable triangle meshes
//!
//! dvh implements the DVH algorithm (Madera, Day, Laycock 2009): a sphere hierarchy whose spheres
//! are centred on mesh vertices and whose leaves bound vertex 1-rings. When a mesh deforms, its
//! hierarchy is refit by recomputing radii only; the centres move with their vertices. A query
//! between two meshes (each optionally moved by a rigid [`Pose`]) reports the intersecting
//! triangle pairs, decided by an exact triangle test, or coarser answers when speed matters more
//! than precision ([`QueryMode`]). A mesh can be queried against itself ([`self_collide`]: folds
//! and crossings, not the contact of neighbouring triangles), and for nearness: every triangle
//! pair within a distance ([`proximity`], [`self_proximity`]), exact like the rest.
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
mod mesh;
mod prefetch;
mod query;
mod scene;
mod threads;
mod tree;
mod volume;

pub use error::{Error, Result, Side};
pub use geometry::MAX_POSED_MAGNITUDE;
pub use geometry::aabb::Aabb;
pub use geometry::pose::{Pose, RIGIDITY_TOLERANCE};
pub use geometry::sphere::Sphere;
pub use mesh::{
    BoundingVolume, BuildOptions, InvariantError, LeftoverPolicy, Mesh, NodeView, RadiusKind,
    RefitStats, TreeStats,
};
pub use query::{
    Pair, PairKind, Pairs, QueryMode, QueryOptions, QueryStats, brute_force, collide, proximity,
    self_collide, self_proximity,
};
pub use scene::{Contact, Contacts, Scene, SceneStats};
pub use tree::TreeKind;
pub use volume::VolumeKind;

/// The README's examples, compiled and run as documentation tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
