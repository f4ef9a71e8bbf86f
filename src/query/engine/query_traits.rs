//! What a query asks of the engine: how its traversal meets the two sides ([`Reach`]), and,
//! for the queries that test triangles, the test of a triangle pair ([`TriangleTest`]).

use super::side::NodeVolumes;
use super::traverse::OneMesh;
use super::workspace::Prepared;
use crate::geometry::aabb::Aabb;
use crate::mesh::Mesh;

/// How a query's traversal meets its two sides: side `a`'s volumes (grown by the query's
/// margin, if it has one), whether both sides are one mesh, and the margin by which the leaf
/// narrow phase grows boxes. Queries that only want leaf pairs (continuous collision, the
/// closest-point stencils) say this much; those that test triangles add a [`TriangleTest`].
pub(crate) trait Reach<'m>: Copy + Send + Sync {
    /// Side `a`'s volume kind, given the mesh's own (grown by the margin, if there is one).
    type SideA<K: NodeVolumes<'m>>: NodeVolumes<'m>;

    /// Side `a`'s volume kind, given the mesh's own.
    fn side_a<K: NodeVolumes<'m>>(&self, kind: K) -> Self::SideA<K>;
    /// `Some` when both sides are one mesh: a leaf is then paired with itself too, and pairs are
    /// reported `(lower, higher)`.
    fn own(&self) -> Option<OneMesh<'m>>;
    /// Box `b` grown by the margin within which pairs are wanted; by default `b` itself, as
    /// intersection asks (and then it costs nothing).
    #[inline(always)]
    fn widen(&self, b: &Aabb) -> Aabb {
        *b
    }
}

/// What a query asks of the triangle pairs its traversal brings together (intersection,
/// nearness; of two meshes or of one). A new query of this kind is a new test and an entry
/// point: the traversal, the threads and the leaf narrow phase are shared.
pub(crate) trait TriangleTest<'m>: Reach<'m> {
    /// Does the test read [`Prepared::in_fast_range`]? Then each triangle checks, when the query's
    /// coordinates may leave that range, whether they suit the fast predicates.
    const CHECKS_DOMAIN: bool;

    /// Is the pair of no interest to the test, and not counted as tested (say, two triangles
    /// of one mesh that share a vertex, for nearness)?
    #[inline(always)]
    fn skips(&self, _mesh: &Mesh, _ta: &Prepared, _tb: &Prepared) -> bool {
        false
    }
    /// The exact test of two triangles whose boxes come within the margin; `mesh` is side
    /// `a`'s (for tests of one mesh, both sides').
    fn test(&self, mesh: &Mesh, ta: &Prepared, tb: &Prepared) -> bool;
}
