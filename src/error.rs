//! The errors dvh reports. Each names what was wrong: which triangle, vertex, axis or value.

use std::fmt;

/// Which of the two meshes of a query an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The first mesh of the query (`a`).
    A,
    /// The second mesh of the query (`b`).
    B,
}

/// Which positions of a motion an error is about ([`crate::Mesh::refit_motion`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instant {
    /// The positions at the start of the step (t = 0).
    Start,
    /// The positions at the end of the step (t = 1).
    End,
}

/// Everything that can go wrong when building, refitting or querying.
///
/// A call that returns an error has changed nothing: meshes and result buffers are exactly as
/// they were before the call.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The mesh has no triangles.
    NoTriangles,
    /// The position array's length is not a multiple of 3.
    PositionsLength {
        /// Length of the array, in `f64` values.
        len: usize,
    },
    /// The triangle index array's length is not a multiple of 3.
    TrianglesLength {
        /// Length of the array, in indices.
        len: usize,
    },
    /// More vertices than `u32` indices can address.
    TooManyVertices {
        /// Number of vertices given.
        count: usize,
    },
    /// More triangles than `u32` indices can address.
    TooManyTriangles {
        /// Number of triangles given.
        count: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// Its corner, 0 to 2.
        corner: usize,
        /// The index it holds.
        index: u32,
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// A coordinate is NaN or infinite.
    NonFiniteCoordinate {
        /// The vertex.
        vertex: usize,
        /// Its axis, 0 (x) to 2 (z).
        axis: usize,
        /// The value found.
        value: f64,
    },
    /// A refit was given a different number of vertices than the mesh has.
    VertexCountMismatch {
        /// Vertices in the mesh.
        expected: usize,
        /// Vertices given.
        got: usize,
    },
    /// A pose entry is NaN or infinite.
    NonFinitePose {
        /// `"rotation"` or `"translation"`.
        part: &'static str,
        /// Index of the entry (row-major for the rotation).
        index: usize,
        /// The value found.
        value: f64,
    },
    /// A pose's rotation is not orthonormal within [`crate::RIGIDITY_TOLERANCE`], or it is a
    /// reflection.
    NonRigidPose {
        /// Largest entry of `|RᵀR - I|`.
        deviation: f64,
        /// Determinant of the rotation.
        determinant: f64,
    },
    /// Memory ran out: the allocation of this many bytes failed. A mesh build checks up front
    /// that its working memory can be had; a query's result grows fallibly.
    OutOfMemory {
        /// Size of the allocation that failed (or of the build's estimated working memory).
        bytes: usize,
    },
    /// [`crate::QueryMode::Budget`] with a budget of 0: at least the roots' test is needed.
    ZeroBudget,
    /// A proximity distance that is negative, NaN or infinite.
    InvalidDistance {
        /// The distance given.
        distance: f64,
    },
    /// A pose would move a mesh's coordinates beyond the range where the query is sound
    /// (transformed coordinates could overflow).
    PoseOutOfRange {
        /// The mesh whose pose it is.
        side: Side,
        /// Bound on the magnitude of its transformed coordinates.
        bound: f64,
    },
    /// A scene object's pose would move its coordinates beyond the range where the query is
    /// sound ([`crate::Scene::add_rigid`]; [`crate::Scene::set_pose`] wraps it in
    /// [`Error::Object`]).
    ObjectPoseOutOfRange {
        /// Bound on the magnitude of the object's transformed coordinates.
        bound: f64,
    },
    /// No object of the scene has this id (never added, or removed).
    UnknownObject {
        /// The id given.
        object: u32,
    },
    /// A rigid object was given positions, or a deformable one a pose.
    WrongObjectKind {
        /// The object.
        object: u32,
        /// Is it rigid (moved by a pose) rather than deformable (moved by its positions)?
        rigid: bool,
    },
    /// Self-contact was asked of a rigid object (it cannot touch itself: only deformable objects
    /// have it).
    RigidSelfContact {
        /// The object.
        object: u32,
    },
    /// A pair of an object with itself was given where two objects are needed.
    SameObject {
        /// The object.
        object: u32,
    },
    /// What went wrong with one object of a scene.
    Object {
        /// The object.
        object: u32,
        /// The error, as for a mesh.
        error: Box<Error>,
    },
    /// A query was asked in a mode it does not answer.
    UnsupportedMode {
        /// The mode given.
        mode: crate::QueryMode,
        /// The query, as the message names it.
        query: &'static str,
    },
    /// Curves name a vertex or triangle that the meshes given with them do not have: they are
    /// not these meshes' curves.
    ForeignCurves {
        /// `"vertex"` or `"triangle"`.
        what: &'static str,
        /// The index named.
        index: u32,
        /// How many the mesh has.
        count: usize,
    },
    /// A gradient's length is not its mesh's vertex count.
    GradientLength {
        /// The mesh's vertex count.
        expected: usize,
        /// The gradient's length.
        got: usize,
    },
    /// The gradient of two meshes' curves was asked of one mesh's self-intersection curves, or
    /// the other way round.
    CurvesKind {
        /// Are the curves a mesh's self-intersection curves?
        self_curves: bool,
    },
    /// What was wrong with the start or the end positions of a motion.
    Motion {
        /// Which positions.
        instant: Instant,
        /// The error, as for a refit.
        error: Box<Error>,
    },
    /// The mesh is not closed, so it bounds no region (winding numbers and signed distances
    /// need one): the directed edge `(u, v)` of some triangle side is not matched by a side
    /// `(v, u)`. [`crate::Mesh::open_edge`] names the least such edge.
    NotClosed {
        /// The unmatched directed edge `(u, v)`.
        edge: [u32; 2],
    },
    /// A query point has a NaN or infinite coordinate.
    NonFinitePoint {
        /// The point's index in the query's array.
        point: usize,
        /// Its axis, 0 (x) to 2 (z).
        axis: usize,
        /// The value found.
        value: f64,
    },
    /// A distance query's option is out of range: `max_distance` negative or NaN, `rel_err`
    /// or `abs_err` negative, NaN or infinite.
    InvalidDistanceOption {
        /// The option.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A point query's result array does not have one entry per point.
    ResultLength {
        /// The number of points.
        expected: usize,
        /// The number of entries.
        got: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::NoTriangles => write!(f, "the mesh has no triangles"),
            Error::PositionsLength { len } => write!(
                f,
                "position array has {len} values, which is not a multiple of 3 (x, y, z per vertex)"
            ),
            Error::TrianglesLength { len } => write!(
                f,
                "triangle index array has {len} indices, which is not a multiple of 3"
            ),
            Error::TooManyVertices { count } => write!(
                f,
                "{count} vertices: at most {} can be addressed with u32 indices",
                u32::MAX
            ),
            Error::TooManyTriangles { count } => write!(
                f,
                "{count} triangles: at most {} can be addressed with u32 indices",
                u32::MAX
            ),
            Error::IndexOutOfRange {
                triangle,
                corner,
                index,
                vertex_count,
            } => write!(
                f,
                "triangle {triangle}, corner {corner}: vertex index {index} is out of range (the mesh has {vertex_count} vertices)"
            ),
            Error::NonFiniteCoordinate {
                vertex,
                axis,
                value,
            } => write!(
                f,
                "vertex {vertex}: coordinate {} is {value}, not a finite number",
                ["x", "y", "z"][axis]
            ),
            Error::VertexCountMismatch { expected, got } => {
                write!(f, "refit given {got} vertices, but the mesh has {expected}")
            }
            Error::NonFinitePose { part, index, value } => {
                write!(f, "pose {part}[{index}] is {value}, not a finite number")
            }
            Error::NonRigidPose {
                deviation,
                determinant,
            } => write!(
                f,
                "pose rotation is not a rotation: max |R^T R - I| = {deviation:e} (tolerance {:e}), determinant {determinant}",
                crate::limits::RIGIDITY_TOLERANCE
            ),
            Error::OutOfMemory { bytes } => {
                write!(f, "out of memory: could not allocate {bytes} bytes")
            }
            Error::InvalidDistance { distance } => write!(
                f,
                "distance = {distance}: a proximity distance must be finite and not negative"
            ),
            Error::ZeroBudget => write!(
                f,
                "the query's budget is 0 volume tests: it must be at least 1 (the roots' test)"
            ),
            Error::PoseOutOfRange { side, bound } => write!(
                f,
                "pose of mesh {side:?} moves coordinates up to {bound:e}, beyond the supported magnitude {:e}",
                crate::limits::MAX_POSED_MAGNITUDE
            ),
            Error::ObjectPoseOutOfRange { bound } => write!(
                f,
                "pose moves the object's coordinates up to {bound:e}, beyond the supported magnitude {:e}",
                crate::limits::MAX_POSED_MAGNITUDE
            ),
            Error::UnknownObject { object } => write!(
                f,
                "object {object} is not in the scene (never added, or removed)"
            ),
            Error::WrongObjectKind {
                object,
                rigid: true,
            } => write!(
                f,
                "object {object} is rigid: it is moved by a pose, not given positions"
            ),
            Error::WrongObjectKind {
                object,
                rigid: false,
            } => write!(
                f,
                "object {object} is deformable: it is moved by its positions, not by a pose"
            ),
            Error::UnsupportedMode { mode, query } => write!(
                f,
                "{query} are found pair by pair, in the triangles mode only \
                 (DVH_QUERY_MODE_TRIANGLES, QueryMode::Triangles), not in {mode:?}"
            ),
            Error::ForeignCurves { what, index, count } => write!(
                f,
                "the curves name {what} {index}, but the mesh has {count}: they are not this \
                 mesh's curves"
            ),
            Error::GradientLength { expected, got } => write!(
                f,
                "the gradient has room for {got} vertices, but the mesh has {expected}"
            ),
            Error::CurvesKind { self_curves: true } => write!(
                f,
                "these are one mesh's self-intersection curves: their gradient is the self \
                 length gradient's, of that mesh"
            ),
            Error::CurvesKind { self_curves: false } => write!(
                f,
                "these are the curves of two meshes: their gradient is the length gradient's, \
                 of both meshes"
            ),
            Error::RigidSelfContact { object } => write!(
                f,
                "object {object} is rigid: self-contact is for deformable objects (a rigid \
                 object cannot touch itself)"
            ),
            Error::SameObject { object } => write!(
                f,
                "object {object} was paired with itself: a pair needs two objects"
            ),
            Error::Object { object, ref error } => write!(f, "object {object}: {error}"),
            Error::NotClosed { edge: [u, v] } => write!(
                f,
                "the mesh is not closed: its edge from vertex {u} to vertex {v} is not matched \
                 by an edge from {v} to {u}, so it bounds no region (winding numbers and signs \
                 need a closed surface)"
            ),
            Error::NonFinitePoint { point, axis, value } => write!(
                f,
                "point {point} has a non-finite coordinate {} = {value}",
                ["x", "y", "z"][axis.min(2)]
            ),
            Error::InvalidDistanceOption { name, value } => write!(
                f,
                "{name} = {value}: {}",
                if name == "max_distance" {
                    "the bound must not be negative or NaN (infinity: no bound)"
                } else {
                    "a tolerance must be finite and not negative"
                }
            ),
            Error::ResultLength { expected, got } => write!(
                f,
                "the result has room for {got} entries, but there are {expected} points"
            ),
            Error::Motion { instant, ref error } => write!(
                f,
                "{} positions: {error}",
                match instant {
                    Instant::Start => "start",
                    Instant::End => "end",
                }
            ),
        }
    }
}

impl std::error::Error for Error {}

/// `Result` with dvh's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
