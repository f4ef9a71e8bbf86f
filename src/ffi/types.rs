//! The C ABI's types and constants.
//!
//! Enumerations cross the boundary as fixed-width integers with named constants, never as Rust
//! enums: a C caller can pass any integer, and an out-of-range value read as a Rust enum would be
//! undefined behaviour. Every such value is checked and reported as an invalid argument.

use crate::{CcdStats, Contact, Impact, Pair, QueryStats, RefitStats, SceneStats, TreeStats};

/// Result of every fallible call: `DVH_STATUS_OK` (0) or one of the `DVH_STATUS_*` codes.
/// `dvh_last_error_message` gives the details of a failure.
pub type DvhStatus = u32;

/// The call succeeded.
pub const DVH_STATUS_OK: DvhStatus = 0;
/// A required pointer argument was NULL.
pub const DVH_STATUS_NULL_ARGUMENT: DvhStatus = 1;
/// An argument is out of range or inconsistent: a size, a stride, an option value, a
/// misaligned pointer, a mesh without triangles, a vertex count that differs from the mesh's.
pub const DVH_STATUS_INVALID_ARGUMENT: DvhStatus = 2;
/// A coordinate (or pose entry) is NaN or infinite.
pub const DVH_STATUS_NON_FINITE_COORDINATE: DvhStatus = 3;
/// A triangle refers to a vertex index not below the vertex count.
pub const DVH_STATUS_INDEX_OUT_OF_RANGE: DvhStatus = 4;
/// A pose's rotation is not orthonormal (within 1e-5) or is a reflection.
pub const DVH_STATUS_NON_RIGID_POSE: DvhStatus = 5;
/// Memory ran out; nothing was changed.
pub const DVH_STATUS_OUT_OF_MEMORY: DvhStatus = 6;
/// A bug in dvh: an internal panic was caught at the boundary. A mesh that was being refit when
/// it happened refuses further use with this code.
pub const DVH_STATUS_INTERNAL_PANIC: DvhStatus = 7;
/// A pose would move a mesh's coordinates beyond 1e300 in magnitude.
pub const DVH_STATUS_POSE_OUT_OF_RANGE: DvhStatus = 8;
/// `dvh_mesh_validate` found a broken invariant: a bug in dvh.
pub const DVH_STATUS_INVARIANT_BROKEN: DvhStatus = 9;
/// The call would break the threading rules: a refit of a mesh while a query on it runs on
/// another thread, two calls changing one scene at once, one result buffer used by two threads.
/// The object was not touched; the call may be retried once the other has returned.
pub const DVH_STATUS_BUSY: DvhStatus = 10;
/// The mesh is not closed (a directed edge of a triangle side has no reverse), so winding
/// numbers and signed distances are not defined for it; the message names the edge.
pub const DVH_STATUS_NOT_CLOSED: DvhStatus = 11;

/// How the hierarchy above the 1-rings is split: a `DVH_TREE_KIND_*` value.
pub type DvhTreeKind = u32;
/// Up to 8 children per node (midpoint cut on all three axes): shallow trees. The default.
pub const DVH_TREE_KIND_OCTREE: DvhTreeKind = 0;
/// 2 children per node (midpoint cut of the longest axis): deeper trees.
pub const DVH_TREE_KIND_BINARY: DvhTreeKind = 1;

/// How node radii are recomputed at each refit: a `DVH_RADIUS_KIND_*` value.
pub type DvhRadiusKind = u32;
/// `max(|c - c_child| + r_child)` over the children: cheap refit. The default.
pub const DVH_RADIUS_KIND_LAYERED: DvhRadiusKind = 0;
/// The farthest vertex below the node: tighter spheres, dearer refit.
pub const DVH_RADIUS_KIND_WRAPPED: DvhRadiusKind = 1;

/// How triangles touching no 1-ring centre are put into leaves: a `DVH_LEFTOVER_POLICY_*` value.
pub type DvhLeftoverPolicy = u32;
/// Each joins the adjacent ring with the nearest centre: fewer leaves. The default.
pub const DVH_LEFTOVER_POLICY_JOIN_ADJACENT: DvhLeftoverPolicy = 0;
/// Extra rings hold them: more leaves, tighter spheres.
pub const DVH_LEFTOVER_POLICY_EXTRA_RINGS: DvhLeftoverPolicy = 1;

/// The bounding volume on every node of a mesh's hierarchy: a `DVH_VOLUME_KIND_*` value.
pub type DvhVolumeKind = u32;
/// The DVH: spheres centred on mesh vertices, refit by recomputing radii only. The value of a
/// zeroed `volume` (the library's behaviour before volume kinds existed).
pub const DVH_VOLUME_KIND_DVH: DvhVolumeKind = 0;
/// A standard sphere tree (SBV): centres recomputed at every refit (midpoints of the boxes of
/// the vertices below each node), then radii.
pub const DVH_VOLUME_KIND_SBV: DvhVolumeKind = 1;
/// Axis-aligned boxes, refit bottom-up: the fastest measured for deforming meshes. The default
/// of `dvh_build_options_default()`.
pub const DVH_VOLUME_KIND_AABB: DvhVolumeKind = 2;

/// What a query reports: a `DVH_QUERY_MODE_*` value.
pub type DvhQueryMode = u32;
/// Every intersecting triangle pair, by the exact test. The default.
pub const DVH_QUERY_MODE_TRIANGLES: DvhQueryMode = 0;
/// The first intersecting triangle pair found, or none.
pub const DVH_QUERY_MODE_FIRST_HIT: DvhQueryMode = 1;
/// Pairs of leaf nodes (1-rings) whose spheres overlap; no triangle tests.
pub const DVH_QUERY_MODE_LEAVES: DvhQueryMode = 2;
/// Pairs of nodes whose volumes overlap, descending no deeper than `max_depth`.
pub const DVH_QUERY_MODE_DEPTH: DvhQueryMode = 3;
/// At most `budget` volume tests (plus the child tests of one node pair): node pairs are opened
/// largest volumes first, and when the budget is spent the unopened pairs (the frontier) are
/// reported with the leaf pairs reached. Their triangles include every intersecting pair; with
/// a large enough budget the result is `DVH_QUERY_MODE_LEAVES`'s.
pub const DVH_QUERY_MODE_BUDGET: DvhQueryMode = 4;

/// What the indices of a result refer to: a `DVH_PAIR_KIND_*` value.
pub type DvhPairKind = u32;
/// Triangle indices (modes `TRIANGLES` and `FIRST_HIT`).
pub const DVH_PAIR_KIND_TRIANGLES: DvhPairKind = 0;
/// Node indices (modes `LEAVES`, `DEPTH` and `BUDGET`); expand with `dvh_mesh_node_triangles`.
pub const DVH_PAIR_KIND_NODES: DvhPairKind = 1;

/// Options for `dvh_mesh_create`; start from `dvh_build_options_default()`.
///
/// Growth: fields are only ever appended, and a zero field keeps the results from before the
/// field existed. A release that appends a field changes the library's soname (see the header's
/// ABI note), so a program never runs against a layout it was not compiled for.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DvhBuildOptions {
    /// A `DVH_TREE_KIND_*` value.
    pub tree: DvhTreeKind,
    /// A `DVH_RADIUS_KIND_*` value (sphere volumes; boxes ignore it).
    pub radius: DvhRadiusKind,
    /// A `DVH_LEFTOVER_POLICY_*` value.
    pub leftovers: DvhLeftoverPolicy,
    /// A `DVH_VOLUME_KIND_*` value.
    pub volume: DvhVolumeKind,
    /// Threads each `dvh_mesh_refit` of this mesh may use: 0 for every core (the default), 1
    /// for the calling thread only, n for at most n. The volumes are the same whatever the
    /// count; meshes of fewer than 8,192 rings (about vertices) refit on the calling thread.
    pub refit_threads: u32,
}

/// Options for `dvh_collide`, `dvh_self_collide`, `dvh_proximity`, `dvh_self_proximity`,
/// `dvh_scene_collide` and the stencil queries (`dvh_nearest_features`,
/// `dvh_self_nearest_features`, `dvh_scene_nearest_features`); start from
/// `dvh_query_options_default()` (all fields zero). Grows like `DvhBuildOptions`: appended
/// fields, zero the earlier results.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DvhQueryOptions {
    /// A `DVH_QUERY_MODE_*` value.
    pub mode: DvhQueryMode,
    /// Deepest level descended in `DVH_QUERY_MODE_DEPTH` (the root is level 0); ignored by the
    /// other modes.
    pub max_depth: u32,
    /// Stop after this many pairs (0: no limit); `DvhQueryStats.truncated` then says so.
    pub max_pairs: u64,
    /// Volume tests allowed in `DVH_QUERY_MODE_BUDGET` (at least 1; 0 is INVALID_ARGUMENT in
    /// that mode); ignored by the other modes.
    pub budget: u64,
    /// Threads the query may use: 0 for every core (the default), 1 for the calling thread
    /// only, n for at most n. The result is the same whatever the count. Threads come from one
    /// pool created on first use and kept for the life of the process; no call creates any.
    pub threads: u32,
}

/// Counters of one query: the terms of the paper's cost model `T = NV*CV + NP*CP + NU*CU`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DvhQueryStats {
    /// Volume pairs tested for overlap (`NV`).
    pub bv_tests: u64,
    /// Triangle pairs given to the exact test (`NP`).
    pub triangle_tests: u64,
    /// Triangle pairs of overlapping leaves, before the exact bounding-box filter that decides
    /// which go to the exact test.
    pub triangle_candidates: u64,
    /// Overlapping pairs of terminal nodes (leaves, or nodes at the depth limit) the traversal
    /// reached.
    pub leaf_pairs: u64,
    /// Pairs reported.
    pub pairs: u64,
    /// Nodes recomputed by the last refit of each mesh (`NU` of the frame).
    pub nodes_refit: u64,
    /// Did `max_pairs` stop the query before every pair was found?
    pub truncated: bool,
    /// Overlapping node pairs left unopened when `DVH_QUERY_MODE_BUDGET`'s budget ran out, and
    /// reported as they are (0: the budget sufficed, the answer is `DVH_QUERY_MODE_LEAVES`'s).
    pub frontier_pairs: u64,
}

/// Counters of the last refit of a mesh (or of its build).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DvhRefitStats {
    /// Nodes whose volume was recomputed (`NU`).
    pub nodes_refit: u64,
    /// Vertex-to-centre distances evaluated (for boxes: vertices folded into leaf boxes).
    pub distance_evaluations: u64,
}

/// Shape of a mesh's hierarchy.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DvhTreeStats {
    /// Triangles in the mesh.
    pub triangles: usize,
    /// 1-rings, that is leaves.
    pub rings: usize,
    /// Inner nodes ("clusters" in the paper).
    pub inner_nodes: usize,
    /// Levels: the depth of the deepest leaf plus one.
    pub levels: usize,
    /// Most triangles in one ring.
    pub max_ring_triangles: usize,
}

/// A rigid placement of a mesh: `world = R * p + t`, with `rotation` row-major. The rotation must
/// be orthonormal within 1e-5 with determinant +1.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvhPose {
    /// `R`, row-major: `rotation[3 * i + j]` is row `i`, column `j`.
    pub rotation: [f64; 9],
    /// `t`.
    pub translation: [f64; 3],
}

/// One result: an index into mesh `a` and one into mesh `b` (triangles or nodes, see
/// `dvh_pairs_kind`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DvhPair {
    /// Index in mesh `a`.
    pub a: u32,
    /// Index in mesh `b`.
    pub b: u32,
}

// `dvh_pairs_data` hands out the library's own `Pair` array as `DvhPair`: same fields, same
// order, both `repr(C)`.
const _: () = {
    assert!(std::mem::size_of::<DvhPair>() == std::mem::size_of::<Pair>());
    assert!(std::mem::align_of::<DvhPair>() == std::mem::align_of::<Pair>());
    assert!(std::mem::offset_of!(DvhPair, a) == std::mem::offset_of!(Pair, a));
    assert!(std::mem::offset_of!(DvhPair, b) == std::mem::offset_of!(Pair, b));
};

/// One contact of a scene query: `a` in object `object_a` meets `b` in object `object_b`, with
/// `object_a <= object_b` (triangles, or nodes in the coarse modes: see `dvh_contacts_kind`).
/// `object_a == object_b` for a contact of an object with itself, reported when its self-contact
/// is on (`dvh_scene_set_self_contact`), with `a < b` as `dvh_self_collide` reports them.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DvhContact {
    /// The object with the lower id.
    pub object_a: u32,
    /// The object with the higher id (the same, for a contact of an object with itself).
    pub object_b: u32,
    /// Index in `object_a`'s mesh.
    pub a: u32,
    /// Index in `object_b`'s mesh.
    pub b: u32,
}

// `dvh_contacts_data` hands out the library's own `Contact` array as `DvhContact`: same fields,
// same order, both `repr(C)`.
const _: () = {
    assert!(std::mem::size_of::<DvhContact>() == std::mem::size_of::<Contact>());
    assert!(std::mem::align_of::<DvhContact>() == std::mem::align_of::<Contact>());
    assert!(std::mem::offset_of!(DvhContact, object_a) == std::mem::offset_of!(Contact, object_a));
    assert!(std::mem::offset_of!(DvhContact, object_b) == std::mem::offset_of!(Contact, object_b));
    assert!(std::mem::offset_of!(DvhContact, a) == std::mem::offset_of!(Contact, a));
    assert!(std::mem::offset_of!(DvhContact, b) == std::mem::offset_of!(Contact, b));
};

/// Counters of one scene query.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DvhSceneStats {
    /// Objects in the scene.
    pub objects: u64,
    /// Object pairs that passed the broad phase and the filters, and were queried. A pair that
    /// an earlier query found without contact is not queried again while neither object has
    /// changed (nor the options): it is not counted.
    pub object_pairs_tested: u64,
    /// Object pairs with at least one contact.
    pub object_pairs_colliding: u64,
    /// Volume pairs tested, over every object pair.
    pub bv_tests: u64,
    /// Triangle pairs given to the exact test, over every object pair.
    pub triangle_tests: u64,
    /// Nodes recomputed by the refits the query made (`NU`): only in deformable objects some
    /// pair needed whose positions had changed and, with box volumes in the modes that report
    /// triangles, only the blocks of their trees that a traversal reached.
    pub nodes_refit: u64,
    /// Contacts reported.
    pub contacts: u64,
    /// Did `max_pairs` cut the result short?
    pub truncated: bool,
}

/// How a continuous test decides (`DvhCcdOptions.mode`).
pub type DvhCcdMode = u32;
/// Exact for every finite input: a floating-point filter, then exact arithmetic where it cannot
/// decide; the time of impact is the earliest contact rounded down to a double. The default.
pub const DVH_CCD_MODE_EXACT: DvhCcdMode = 0;
/// Floating point only: never misses a contact and never reports a later time than the exact
/// mode, but may report primitives that come within rounding error of contact (coplanar and
/// touching to within the error of interval arithmetic on their coordinates), at the start of
/// the time span it could not settle. Bounded time per test.
pub const DVH_CCD_MODE_CONSERVATIVE: DvhCcdMode = 1;

/// Options for `dvh_ccd_vertex_face`, `dvh_ccd_edge_edge` (which read `mode` only),
/// `dvh_continuous_collide`, `dvh_self_continuous_collide` and `dvh_scene_continuous_collide`;
/// start from `dvh_ccd_options_default()` (all fields zero). Grows like `DvhBuildOptions`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DvhCcdOptions {
    /// A `DVH_CCD_MODE_*` value.
    pub mode: DvhCcdMode,
    /// Threads, as `DvhQueryOptions.threads`: 0 for every core, 1 for the calling thread. The
    /// impacts are the same, in the same order, whatever the count.
    pub threads: u32,
    /// Stop once this many impacts are found (0: no limit); `DvhCcdStats.truncated` then says so.
    pub max_impacts: u64,
    /// Report only the earliest impact (of several at that time, the first in the result's
    /// order). In `DVH_CCD_MODE_EXACT` much cheaper than the whole list: triangle pairs whose
    /// sweeps up to the earliest impact found so far are apart are not tested (the conservative
    /// mode, whose times may come before the contact, tests every pair).
    pub earliest_only: bool,
}

/// Which primitives of a `DvhImpact` meet.
pub type DvhImpactKind = u32;
/// A vertex of the first mesh (`a0`) against a triangle of the second (`b0`).
pub const DVH_IMPACT_KIND_VERTEX_FACE: DvhImpactKind = 0;
/// A triangle of the first mesh (`a0`) against a vertex of the second (`b0`); not reported by
/// self queries.
pub const DVH_IMPACT_KIND_FACE_VERTEX: DvhImpactKind = 1;
/// An edge of the first mesh (`a0 < a1`) against an edge of the second (`b0 < b1`); in self
/// queries `(a0, a1) < (b0, b1)`.
pub const DVH_IMPACT_KIND_EDGE_EDGE: DvhImpactKind = 2;

/// Two primitives that meet during the step, and the earliest time they do. Results are sorted
/// by `(kind, a0, a1, b0, b1)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvhImpact {
    /// A `DVH_IMPACT_KIND_*` value.
    pub kind: DvhImpactKind,
    /// VERTEX_FACE: a vertex of the first mesh; FACE_VERTEX: a triangle of the first mesh;
    /// EDGE_EDGE: the edge's lower vertex.
    pub a0: u32,
    /// EDGE_EDGE: the first edge's higher vertex; 0 otherwise.
    pub a1: u32,
    /// VERTEX_FACE: a triangle of the second mesh; FACE_VERTEX: a vertex of the second mesh;
    /// EDGE_EDGE: the second edge's lower vertex.
    pub b0: u32,
    /// EDGE_EDGE: the second edge's higher vertex; 0 otherwise.
    pub b1: u32,
    /// The earliest time of impact in [0, 1], rounded down to a double (in
    /// `DVH_CCD_MODE_CONSERVATIVE`, a time no later than that).
    pub toi: f64,
}

// `dvh_impacts_data` hands out the library's own `Impact` array as `DvhImpact`: same fields,
// same order, both `repr(C)` (the kind a `u32` enum).
const _: () = {
    assert!(std::mem::size_of::<DvhImpact>() == std::mem::size_of::<Impact>());
    assert!(std::mem::align_of::<DvhImpact>() == std::mem::align_of::<Impact>());
    assert!(std::mem::offset_of!(DvhImpact, kind) == std::mem::offset_of!(Impact, kind));
    assert!(std::mem::offset_of!(DvhImpact, a0) == std::mem::offset_of!(Impact, a0));
    assert!(std::mem::offset_of!(DvhImpact, a1) == std::mem::offset_of!(Impact, a1));
    assert!(std::mem::offset_of!(DvhImpact, b0) == std::mem::offset_of!(Impact, b0));
    assert!(std::mem::offset_of!(DvhImpact, b1) == std::mem::offset_of!(Impact, b1));
    assert!(std::mem::offset_of!(DvhImpact, toi) == std::mem::offset_of!(Impact, toi));
    assert!(crate::ImpactKind::VertexFace as u32 == DVH_IMPACT_KIND_VERTEX_FACE);
    assert!(crate::ImpactKind::FaceVertex as u32 == DVH_IMPACT_KIND_FACE_VERTEX);
    assert!(crate::ImpactKind::EdgeEdge as u32 == DVH_IMPACT_KIND_EDGE_EDGE);
};

/// Where a closest point of a `DvhNearPair` lies, numbered on its primitive's own corners.
pub type DvhFeature = u32;
/// Corner 0 (a vertex primitive is always here).
pub const DVH_FEATURE_VERTEX_0: DvhFeature = 0;
/// Corner 1.
pub const DVH_FEATURE_VERTEX_1: DvhFeature = 1;
/// Corner 2 (of a triangle).
pub const DVH_FEATURE_VERTEX_2: DvhFeature = 2;
/// The open edge from corner 0 to corner 1 (an edge primitive's interior).
pub const DVH_FEATURE_EDGE_01: DvhFeature = 3;
/// The open edge from corner 1 to corner 2.
pub const DVH_FEATURE_EDGE_12: DvhFeature = 4;
/// The open edge from corner 2 to corner 0.
pub const DVH_FEATURE_EDGE_20: DvhFeature = 5;
/// The interior of a triangle.
pub const DVH_FEATURE_INTERIOR: DvhFeature = 6;

/// A vertex-face or edge-edge pair within the query's distance, with its closest points: a
/// contact stencil. Kinds and indices as in `DvhImpact`; fields ending in `_a` describe the
/// primitive named by `a0, a1`. Features and weights are numbered on each primitive's own
/// corners: a vertex is corner 0, an edge `(a0, a1)` has corners `a0`, `a1`, a triangle its
/// corners in the mesh's order. Results are sorted by `(kind, a0, a1, b0, b1)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DvhNearPair {
    /// A `DVH_IMPACT_KIND_*` value.
    pub kind: DvhImpactKind,
    /// VERTEX_FACE: a vertex of the first mesh; FACE_VERTEX: a triangle of the first mesh;
    /// EDGE_EDGE: the edge's lower vertex.
    pub a0: u32,
    /// EDGE_EDGE: the first edge's higher vertex; 0 otherwise.
    pub a1: u32,
    /// VERTEX_FACE: a triangle of the second mesh; FACE_VERTEX: a vertex of the second mesh;
    /// EDGE_EDGE: the second edge's lower vertex.
    pub b0: u32,
    /// EDGE_EDGE: the second edge's higher vertex; 0 otherwise.
    pub b1: u32,
    /// A `DVH_FEATURE_*` value: where the first primitive's closest point lies.
    pub feature_a: u32,
    /// A `DVH_FEATURE_*` value: where the second primitive's closest point lies.
    pub feature_b: u32,
    /// The distance, within one unit in the last place of the exact one correctly rounded.
    pub distance: f64,
    /// The first primitive's closest point, in world coordinates (each within two units in the
    /// last place of the exact one).
    pub closest_a: [f64; 3],
    /// The second primitive's closest point, in world coordinates.
    pub closest_b: [f64; 3],
    /// The first closest point's barycentric weights: a vertex (1, 0, 0), an edge
    /// (1 - s, s, 0), a triangle three weights summing to one.
    pub weights_a: [f64; 3],
    /// The second closest point's barycentric weights.
    pub weights_b: [f64; 3],
}

// `dvh_near_pairs_data` hands out the library's own `NearPair` array as `DvhNearPair`: same
// fields, same order, both `repr(C)` (the kind and features `u32` enums).
const _: () = {
    use crate::NearPair;
    use crate::exact::Feature;
    use std::mem::{align_of, offset_of, size_of};
    assert!(size_of::<DvhNearPair>() == size_of::<NearPair>());
    assert!(align_of::<DvhNearPair>() == align_of::<NearPair>());
    assert!(offset_of!(DvhNearPair, kind) == offset_of!(NearPair, kind));
    assert!(offset_of!(DvhNearPair, a0) == offset_of!(NearPair, a0));
    assert!(offset_of!(DvhNearPair, a1) == offset_of!(NearPair, a1));
    assert!(offset_of!(DvhNearPair, b0) == offset_of!(NearPair, b0));
    assert!(offset_of!(DvhNearPair, b1) == offset_of!(NearPair, b1));
    assert!(offset_of!(DvhNearPair, feature_a) == offset_of!(NearPair, feature_a));
    assert!(offset_of!(DvhNearPair, feature_b) == offset_of!(NearPair, feature_b));
    assert!(offset_of!(DvhNearPair, distance) == offset_of!(NearPair, distance));
    assert!(offset_of!(DvhNearPair, closest_a) == offset_of!(NearPair, closest_a));
    assert!(offset_of!(DvhNearPair, closest_b) == offset_of!(NearPair, closest_b));
    assert!(offset_of!(DvhNearPair, weights_a) == offset_of!(NearPair, weights_a));
    assert!(offset_of!(DvhNearPair, weights_b) == offset_of!(NearPair, weights_b));
    assert!(size_of::<Feature>() == size_of::<u32>());
    assert!(Feature::Vertex0 as u32 == DVH_FEATURE_VERTEX_0);
    assert!(Feature::Vertex1 as u32 == DVH_FEATURE_VERTEX_1);
    assert!(Feature::Vertex2 as u32 == DVH_FEATURE_VERTEX_2);
    assert!(Feature::Edge01 as u32 == DVH_FEATURE_EDGE_01);
    assert!(Feature::Edge12 as u32 == DVH_FEATURE_EDGE_12);
    assert!(Feature::Edge20 as u32 == DVH_FEATURE_EDGE_20);
    assert!(Feature::Interior as u32 == DVH_FEATURE_INTERIOR);
};

/// An impact of a scene's continuous query (`dvh_scene_continuous_collide`): between objects
/// `object_a` and `object_b`, or within one object with self-contact on when they are equal.
/// `impact` is as `dvh_continuous_collide` reports it with `object_a`'s mesh first and
/// `object_b`'s second (as `dvh_self_continuous_collide` reports it for an object with itself),
/// its indices into those objects' meshes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvhSceneImpact {
    /// The object with the lower id.
    pub object_a: u32,
    /// The object with the higher id (the same, for an impact of an object with itself).
    pub object_b: u32,
    /// The primitives (`a0, a1` in `object_a`'s mesh, `b0, b1` in `object_b`'s) and the time.
    pub impact: DvhImpact,
}

// `dvh_scene_impacts_data` hands out the library's own `SceneImpact` array as `DvhSceneImpact`:
// same fields, same order, both `repr(C)`, the impact itself `DvhImpact`'s twin (checked above).
const _: () = {
    use crate::SceneImpact;
    use std::mem::{align_of, offset_of, size_of};
    assert!(size_of::<DvhSceneImpact>() == size_of::<SceneImpact>());
    assert!(align_of::<DvhSceneImpact>() == align_of::<SceneImpact>());
    assert!(offset_of!(DvhSceneImpact, object_a) == offset_of!(SceneImpact, object_a));
    assert!(offset_of!(DvhSceneImpact, object_b) == offset_of!(SceneImpact, object_b));
    assert!(offset_of!(DvhSceneImpact, impact) == offset_of!(SceneImpact, impact));
};

/// A stencil of a scene's closest-point query (`dvh_scene_nearest_features`): between objects
/// `object_a` and `object_b`, or within one object with self-contact on when they are equal.
/// `pair` is as `dvh_nearest_features` reports it with `object_a`'s mesh (and pose) first and
/// `object_b`'s second (as `dvh_self_nearest_features` reports it for an object with itself):
/// its indices into those objects' meshes, its points in world coordinates.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvhSceneNearPair {
    /// The object with the lower id.
    pub object_a: u32,
    /// The object with the higher id (the same, for a stencil of an object with itself).
    pub object_b: u32,
    /// The primitives (`a0, a1` in `object_a`'s mesh, `b0, b1` in `object_b`'s), their distance,
    /// closest points, weights and features.
    pub pair: DvhNearPair,
}

// `dvh_scene_near_pairs_data` hands out the library's own `SceneNearPair` array as
// `DvhSceneNearPair`: same fields, same order, both `repr(C)`, the stencil itself
// `DvhNearPair`'s twin (checked above).
const _: () = {
    use crate::SceneNearPair;
    use std::mem::{align_of, offset_of, size_of};
    assert!(size_of::<DvhSceneNearPair>() == size_of::<SceneNearPair>());
    assert!(align_of::<DvhSceneNearPair>() == align_of::<SceneNearPair>());
    assert!(offset_of!(DvhSceneNearPair, object_a) == offset_of!(SceneNearPair, object_a));
    assert!(offset_of!(DvhSceneNearPair, object_b) == offset_of!(SceneNearPair, object_b));
    assert!(offset_of!(DvhSceneNearPair, pair) == offset_of!(SceneNearPair, pair));
};

/// Counters of one continuous query.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvhCcdStats {
    /// Volume pairs tested by the traversal over the motion.
    pub bv_tests: u64,
    /// Primitive pairs (vertex-face, edge-edge) given to the continuous test.
    pub primitive_tests: u64,
    /// Impacts reported.
    pub impacts: u64,
    /// The earliest time of the impacts reported; INFINITY when there are none.
    pub earliest_toi: f64,
    /// Did `max_impacts` stop the query before every impact was found?
    pub truncated: bool,
}

// The counters cross the boundary as mirrors of the library's own, field for field and in the
// same order. Each conversion names every field of both sides, so that a field added to one
// without the other does not compile; the tests below check names, order, values and layout.
macro_rules! mirror {
    ($rust:ident => $c:ident { $($field:ident),+ $(,)? }) => {
        impl From<&$rust> for $c {
            fn from(s: &$rust) -> $c {
                let $rust { $($field),+ } = *s;
                $c { $($field),+ }
            }
        }
    };
}

mirror!(QueryStats => DvhQueryStats {
    bv_tests, triangle_tests, triangle_candidates, leaf_pairs, pairs, nodes_refit, truncated,
    frontier_pairs,
});
mirror!(SceneStats => DvhSceneStats {
    objects, object_pairs_tested, object_pairs_colliding, bv_tests, triangle_tests, nodes_refit,
    contacts, truncated,
});
mirror!(RefitStats => DvhRefitStats { nodes_refit, distance_evaluations });
mirror!(TreeStats => DvhTreeStats { triangles, rings, inner_nodes, levels, max_ring_triangles });
mirror!(CcdStats => DvhCcdStats { bv_tests, primitive_tests, impacts, earliest_toi, truncated });

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{align_of, offset_of, size_of};

    /// Each C counter struct, converted from its Rust twin holding a distinct value in every
    /// field, prints as the twin does: the same fields, in the same order, with the same values.
    #[test]
    fn c_counters_mirror_the_rust_counters_field_by_field() {
        let query = QueryStats {
            bv_tests: 1,
            triangle_tests: 2,
            triangle_candidates: 3,
            leaf_pairs: 4,
            pairs: 5,
            nodes_refit: 6,
            truncated: true,
            frontier_pairs: 7,
        };
        let scene = SceneStats {
            objects: 1,
            object_pairs_tested: 2,
            object_pairs_colliding: 3,
            bv_tests: 4,
            triangle_tests: 5,
            nodes_refit: 6,
            contacts: 7,
            truncated: true,
        };
        let refit = RefitStats {
            nodes_refit: 1,
            distance_evaluations: 2,
        };
        let tree = TreeStats {
            triangles: 1,
            rings: 2,
            inner_nodes: 3,
            levels: 4,
            max_ring_triangles: 5,
        };
        let pairs = [
            (
                format!("{:?}", DvhQueryStats::from(&query)),
                format!("Dvh{query:?}"),
            ),
            (
                format!("{:?}", DvhSceneStats::from(&scene)),
                format!("Dvh{scene:?}"),
            ),
            (
                format!("{:?}", DvhRefitStats::from(&refit)),
                format!("Dvh{refit:?}"),
            ),
            (
                format!("{:?}", DvhTreeStats::from(&tree)),
                format!("Dvh{tree:?}"),
            ),
        ];
        for (c, rust) in pairs {
            assert_eq!(c, rust);
        }
    }

    /// Asserts the size and alignment of a C struct and the offset of each field, in order.
    macro_rules! assert_layout {
        ($t:ty, size $size:expr, align $align:expr, $($field:ident $offset:expr),+ $(,)?) => {
            assert_eq!(size_of::<$t>(), $size, "size of {}", stringify!($t));
            assert_eq!(align_of::<$t>(), $align, "alignment of {}", stringify!($t));
            $(assert_eq!(
                offset_of!($t, $field),
                $offset,
                "offset of {}.{}",
                stringify!($t),
                stringify!($field)
            );)+
        };
    }

    /// The layouts programs were compiled against (`include/dvh.h`, on 64-bit targets): a change
    /// here breaks every program built against the header.
    #[test]
    #[cfg(target_pointer_width = "64")]
    fn c_structs_keep_their_layout() {
        assert_layout!(DvhBuildOptions, size 20, align 4,
            tree 0, radius 4, leftovers 8, volume 12, refit_threads 16);
        assert_layout!(DvhQueryOptions, size 32, align 8,
            mode 0, max_depth 4, max_pairs 8, budget 16, threads 24);
        assert_layout!(DvhQueryStats, size 64, align 8,
            bv_tests 0, triangle_tests 8, triangle_candidates 16, leaf_pairs 24, pairs 32,
            nodes_refit 40, truncated 48, frontier_pairs 56);
        assert_layout!(DvhSceneStats, size 64, align 8,
            objects 0, object_pairs_tested 8, object_pairs_colliding 16, bv_tests 24,
            triangle_tests 32, nodes_refit 40, contacts 48, truncated 56);
        assert_layout!(DvhRefitStats, size 16, align 8, nodes_refit 0, distance_evaluations 8);
        assert_layout!(DvhTreeStats, size 40, align 8,
            triangles 0, rings 8, inner_nodes 16, levels 24, max_ring_triangles 32);
        assert_layout!(DvhPose, size 96, align 8, rotation 0, translation 72);
        assert_layout!(DvhPair, size 8, align 4, a 0, b 4);
        assert_layout!(DvhContact, size 16, align 4, object_a 0, object_b 4, a 8, b 12);
        assert_layout!(DvhCcdOptions, size 24, align 8,
            mode 0, threads 4, max_impacts 8, earliest_only 16);
        assert_layout!(DvhImpact, size 32, align 8, kind 0, a0 4, a1 8, b0 12, b1 16, toi 24);
        assert_layout!(DvhCcdStats, size 40, align 8,
            bv_tests 0, primitive_tests 8, impacts 16, earliest_toi 24, truncated 32);
        assert_layout!(DvhNearPair, size 136, align 8,
            kind 0, a0 4, a1 8, b0 12, b1 16, feature_a 20, feature_b 24, distance 32,
            closest_a 40, closest_b 64, weights_a 88, weights_b 112);
        assert_layout!(DvhSceneImpact, size 40, align 8, object_a 0, object_b 4, impact 8);
        assert_layout!(DvhSceneNearPair, size 144, align 8, object_a 0, object_b 4, pair 8);
        assert_layout!(DvhDistanceOptions, size 32, align 8,
            max_distance 0, rel_err 8, abs_err 16, threads 24, reserved 28);
        assert_layout!(DvhDistance, size 208, align 8,
            found 0, intersecting 4, triangle_a 8, triangle_b 12, distance 16, closest_a 24,
            closest_b 48, stencil 72);
        assert_layout!(DvhClosestPoint, size 72, align 8,
            found 0, triangle 4, feature 8, reserved 12, distance 16, point 24, weights 48);
    }
}

/// The winding number `dvh_winding_numbers` reports for a point on the surface (on a triangle,
/// its edges and corners included), where none is defined: `INT32_MIN`, which no closed
/// surface's winding number reaches.
pub const DVH_WINDING_ON_SURFACE: i32 = -2147483648;

/// Options of the distance queries (`dvh_distance`, `dvh_closest_points`,
/// `dvh_signed_distances`, `dvh_scene_distance`, `dvh_scene_object_distance`); start from
/// `dvh_distance_options_default()`. Grows like `DvhBuildOptions`: appended fields.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvhDistanceOptions {
    /// Farther than this is "not found" (a signed distance: an infinity of its sign); the
    /// search looks no farther, so a small bound is the cheapest query. INFINITY by default: no
    /// bound. Negative or NaN is INVALID_ARGUMENT.
    pub max_distance: f64,
    /// Relative tolerance: a result at distance `d <= (1 + rel_err) m + abs_err` of the least
    /// `m` is accepted, so that branches that cannot beat it by more are not searched. 0 by
    /// default: exact. Negative, NaN or infinite is INVALID_ARGUMENT.
    pub rel_err: f64,
    /// Absolute tolerance, as `rel_err` says. 0 by default.
    pub abs_err: f64,
    /// Threads, as `DvhQueryOptions.threads`: 0 every core, 1 the calling thread, n at most n.
    /// The answer is the same for every count.
    pub threads: u32,
    /// Always 0.
    pub reserved: u32,
}

/// The least distance between two meshes' surfaces (`dvh_distance`, the scene's).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DvhDistance {
    /// 0: farther apart than the options' `max_distance` (every other field 0).
    pub found: u32,
    /// 1: the meshes intersect (touching counts); the distance is 0.
    pub intersecting: u32,
    /// The first mesh's triangle the closest point lies on (the least of several); for
    /// intersecting meshes, of the least intersecting pair.
    pub triangle_a: u32,
    /// The second mesh's triangle.
    pub triangle_b: u32,
    /// The distance, within one unit in the last place of the exact one correctly rounded.
    pub distance: f64,
    /// The first mesh's closest point, in world coordinates.
    pub closest_a: [f64; 3],
    /// The second mesh's closest point (intersecting: `closest_a` again, a point of both
    /// triangles within rounding).
    pub closest_b: [f64; 3],
    /// The vertex-face or edge-edge pair attaining the distance, as `dvh_nearest_features`
    /// reports it; zero when intersecting.
    pub stencil: DvhNearPair,
}

/// The closest point of a mesh to a query point (`dvh_closest_points`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DvhClosestPoint {
    /// 0: no triangle within the options' `max_distance` (every other field 0).
    pub found: u32,
    /// The triangle the closest point lies on (of several at the same distance, the least).
    pub triangle: u32,
    /// A `DVH_FEATURE_*` value: where on the triangle (its corners as the mesh orders them).
    pub feature: DvhFeature,
    /// Always 0.
    pub reserved: u32,
    /// The distance, within one unit in the last place of the exact one correctly rounded.
    pub distance: f64,
    /// The closest point, in world coordinates (within two units in the last place).
    pub point: [f64; 3],
    /// Its barycentric weights on the triangle's corners.
    pub weights: [f64; 3],
}

// `dvh_distance` and `dvh_closest_points` write the library's own `Distance` and
// `ClosestPoint`: same fields, same order, all `repr(C)`.
const _: () = {
    use crate::{ClosestPoint, Distance};
    use std::mem::{align_of, offset_of, size_of};
    assert!(size_of::<DvhDistance>() == size_of::<Distance>());
    assert!(align_of::<DvhDistance>() == align_of::<Distance>());
    assert!(offset_of!(DvhDistance, triangle_a) == offset_of!(Distance, triangle_a));
    assert!(offset_of!(DvhDistance, triangle_b) == offset_of!(Distance, triangle_b));
    assert!(offset_of!(DvhDistance, distance) == offset_of!(Distance, distance));
    assert!(offset_of!(DvhDistance, closest_a) == offset_of!(Distance, closest_a));
    assert!(offset_of!(DvhDistance, closest_b) == offset_of!(Distance, closest_b));
    assert!(offset_of!(DvhDistance, stencil) == offset_of!(Distance, stencil));
    assert!(size_of::<DvhClosestPoint>() == size_of::<ClosestPoint>());
    assert!(align_of::<DvhClosestPoint>() == align_of::<ClosestPoint>());
    assert!(offset_of!(DvhClosestPoint, triangle) == offset_of!(ClosestPoint, triangle));
    assert!(offset_of!(DvhClosestPoint, feature) == offset_of!(ClosestPoint, feature));
    assert!(offset_of!(DvhClosestPoint, distance) == offset_of!(ClosestPoint, distance));
    assert!(offset_of!(DvhClosestPoint, point) == offset_of!(ClosestPoint, point));
    assert!(offset_of!(DvhClosestPoint, weights) == offset_of!(ClosestPoint, weights));
    assert!(crate::WINDING_ON_SURFACE == DVH_WINDING_ON_SURFACE);
};

/// One segment of an intersection curve: where triangle `triangle_a` of the first mesh crosses
/// triangle `triangle_b` of the second. The points are world coordinates, each coordinate the
/// exact one rounded to the nearest double (within half a unit in the last place; a mesh
/// vertex keeps its bits); every segment ending at one exact point carries the same bits for
/// it, so within a curve `end` of one segment equals `start` of the next, bit for bit.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvhCurveSegment {
    /// The triangle of the first mesh (self: the lower index).
    pub triangle_a: u32,
    /// The triangle of the second mesh (self: the higher index).
    pub triangle_b: u32,
    /// The curve it belongs to (`0 .. dvh_curves_curve_count`).
    pub curve: u32,
    /// Always 0.
    pub reserved: u32,
    /// Where the segment starts, in the curve's direction.
    pub start: [f64; 3],
    /// Where it ends.
    pub end: [f64; 3],
}

/// Why an intersecting triangle pair of `DvhDegeneratePair` has no segment.
pub type DvhDegenerateKind = u32;
/// The pair meets in one point only (not coplanar, or a degenerate triangle crossing the other's
/// plane).
pub const DVH_DEGENERATE_KIND_POINT: DvhDegenerateKind = 0;
/// Coplanar triangles that meet (in an area, a segment or a point), or a degenerate triangle
/// meeting the other in its plane.
pub const DVH_DEGENERATE_KIND_COPLANAR: DvhDegenerateKind = 1;

/// An intersecting triangle pair whose intersection is not a segment, reported apart from the
/// curves. Sorted by `(triangle_a, triangle_b)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DvhDegeneratePair {
    /// The triangle of the first mesh (self: the lower index).
    pub triangle_a: u32,
    /// The triangle of the second mesh (self: the higher index).
    pub triangle_b: u32,
    /// A `DVH_DEGENERATE_KIND_*` value.
    pub kind: DvhDegenerateKind,
    /// Always 0.
    pub reserved: u32,
}

// `dvh_curves_data` and `dvh_curves_degenerate_data` hand out the library's own arrays: same
// fields, same order, all `repr(C)` (the kind a `u32` enum).
const _: () = {
    use crate::{CurveSegment, DegenerateKind, DegeneratePair};
    use std::mem::{align_of, offset_of, size_of};
    assert!(size_of::<DvhCurveSegment>() == size_of::<CurveSegment>());
    assert!(align_of::<DvhCurveSegment>() == align_of::<CurveSegment>());
    assert!(offset_of!(DvhCurveSegment, triangle_a) == offset_of!(CurveSegment, triangle_a));
    assert!(offset_of!(DvhCurveSegment, triangle_b) == offset_of!(CurveSegment, triangle_b));
    assert!(offset_of!(DvhCurveSegment, curve) == offset_of!(CurveSegment, curve));
    assert!(offset_of!(DvhCurveSegment, reserved) == offset_of!(CurveSegment, reserved));
    assert!(offset_of!(DvhCurveSegment, start) == offset_of!(CurveSegment, start));
    assert!(offset_of!(DvhCurveSegment, end) == offset_of!(CurveSegment, end));
    assert!(size_of::<DvhDegeneratePair>() == size_of::<DegeneratePair>());
    assert!(align_of::<DvhDegeneratePair>() == align_of::<DegeneratePair>());
    assert!(offset_of!(DvhDegeneratePair, triangle_a) == offset_of!(DegeneratePair, triangle_a));
    assert!(offset_of!(DvhDegeneratePair, triangle_b) == offset_of!(DegeneratePair, triangle_b));
    assert!(offset_of!(DvhDegeneratePair, kind) == offset_of!(DegeneratePair, kind));
    assert!(offset_of!(DvhDegeneratePair, reserved) == offset_of!(DegeneratePair, reserved));
    assert!(size_of::<DegenerateKind>() == size_of::<u32>());
    assert!(DegenerateKind::Point as u32 == DVH_DEGENERATE_KIND_POINT);
    assert!(DegenerateKind::Coplanar as u32 == DVH_DEGENERATE_KIND_COPLANAR);
};
