//! The kinds of primitive pairs the queries report.

/// Which primitives a result of continuous collision ([`crate::Impact`]) or of the closest-point
/// query names, and what its indices are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u32)]
pub enum ImpactKind {
    /// A vertex of the first mesh (`a0`) against a triangle of the second (`b0`).
    #[default]
    VertexFace = 0,
    /// A triangle of the first mesh (`a0`) against a vertex of the second (`b0`). Not reported
    /// by self queries, whose vertex-face impacts are all [`ImpactKind::VertexFace`].
    FaceVertex = 1,
    /// An edge of the first mesh (`a0 < a1`) against an edge of the second (`b0 < b1`); of one
    /// mesh, `(a0, a1) < (b0, b1)`.
    EdgeEdge = 2,
}
