//! What the fuzz targets run, shared with `tests/fuzz_replay.rs`, which replays the kept inputs
//! under `cargo test` (stable): each driver turns arbitrary bytes into calls and panics when a
//! promise breaks. One file per driver; `input` reads numbers, meshes, poses and filters from
//! the bytes, `judge` holds brute force and the judge of answers.
//!
//! - [`triangle_oracle`]: the exact triangle test against an independent exact oracle (a
//!   feasibility test of the two triangles' convex combinations meeting, in rationals).
//! - [`c_abi`]: the C ABI driven in the order the bytes say, with the counts, indices,
//!   positions, options, poses and distances they say; no call may report an internal panic,
//!   a failed call must leave the mesh and the result buffer as they were, and every answer
//!   must agree with brute force.
//! - [`scene`]: scenes built, changed and queried through the C ABI in the order the bytes say,
//!   every contact list compared with brute force over the objects the filters allow.
//! - [`self_collision`]: sheets, tori and spheres moved, folded and pinched by the bytes,
//!   self-collision and self-proximity compared with brute force after every change.
//! - [`ccd_primitive`]: the continuous primitive tests on degenerate motions, judged by the
//!   invariants of the exact answer (symmetries, exact scaling and shifting, contact at either
//!   end, the reversed motion) and the conservative mode's promises.
//! - [`ccd_mesh`]: moving sheets and tori, the continuous queries of one mesh and of two against
//!   brute force over every primitive pair, with every option.
//! - [`nearest_mesh`]: sheets and tori bent and placed by the bytes, the closest-point queries
//!   of one mesh and of two against brute force by the exact primitive functions, in every mode,
//!   and every stencil's own promises.
//! - [`curves`]: surfaces moved, folded and pinched by the bytes, the intersection curves of two
//!   and of one through the C ABI, equal to the Rust API's and judged exactly against brute
//!   force by `dvh::fixtures::curve_judge`.
//! - [`distance_mesh`]: sheets and tori bent and placed by the bytes, their least distance
//!   under every option through the C ABI, equal to the Rust API's and judged by brute force
//!   in exact arithmetic (`dvh::fixtures::distance_judge`).
//! - [`points`]: closed and open meshes (two shells through each other among them) and points
//!   on and off their vertices, edges, faces and grid: closest points against brute force,
//!   winding numbers against the turned and the reversed surface, the exact distance 0 and the
//!   solid angles, signed distances against both.

#![allow(dead_code, unused_imports)] // each fuzz target uses one driver

mod c_abi;
mod ccd;
mod curves;
mod distance;
mod input;
mod judge;
mod nearest;
mod scene;
mod self_collision;
mod triangle;

pub use c_abi::c_abi;
pub use ccd::{ccd_mesh, ccd_primitive};
pub use curves::curves;
pub use distance::{distance_mesh, points};
pub use nearest::nearest_mesh;
pub use scene::scene;
pub use self_collision::self_collision;
pub use triangle::{oracle, triangle_oracle};
