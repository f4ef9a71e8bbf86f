//! Intersection of two meshes: the entry point and its pair test.

use super::engine::{
    NodeVolumes, OneMesh, Prepared, QueryMesh, Reach, TriangleTest, least_pair, query,
};
use super::options::QueryOptions;
use super::pairs::{Pair, Pairs, QueryStats};
use crate::error::Result;
use crate::geometry::pose::Pose;
use crate::mesh::Mesh;

/// Finds what intersects between mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b`
/// (`None`: the mesh's coordinates are world coordinates), as [`QueryOptions::mode`] asks.
/// The meshes may have different volume kinds.
///
/// The result replaces the contents of `out`: pairs `(index in a, index in b)`, sorted and
/// without duplicates, of triangles or of nodes according to [`Pairs::kind`]. The counters are
/// returned.
///
/// With poses, triangles are tested at the world coordinates [`Pose::transform_point`] computes
/// (lazily, only for vertices the traversal reaches), so the answer is exactly that of a brute
/// force over those coordinates; volumes are widened by a bound on the rounding of the
/// transformation so that none is dropped.
///
/// Errors: [`crate::Error::ZeroBudget`] for [`crate::QueryMode::Budget`]`(0)`;
/// [`crate::Error::PoseOutOfRange`] when a pose could move coordinates beyond
/// [`crate::geometry::MAX_POSED_MAGNITUDE`]; [`crate::Error::OutOfMemory`] when the result
/// cannot grow (set [`QueryOptions::max_pairs`] to bound it). On error `out` still holds the
/// previous result.
///
/// Cost: proportional to the volume pairs visited plus the triangle pairs tested, shared among
/// [`QueryOptions::threads`] threads when the meshes are large enough; on one thread, allocates
/// nothing once `out` has grown to the scene's needs (on more, one small job per extra thread
/// and step shared out).
pub fn collide(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    collide_lazy((a, pose_a, None), (b, pose_b, None), options, out)
}

/// [`collide`], with either mesh's boxes refit lazily.
pub(crate) fn collide_lazy<'m>(
    a: QueryMesh<'m>,
    b: QueryMesh<'m>,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    query::<_, true>(a, b, Intersect, options, out)
}

/// The first pair [`collide`] reports for the meshes (the least intersecting triangle pair in
/// `(a, b)` order) as the only pair of `out`, or none when they do not intersect: found without
/// finding the others, on the calling thread. `bound`, an intersecting pair (a first hit),
/// prunes from the start. Errors as [`collide`]'s.
pub(crate) fn least_intersecting(
    a: (&Mesh, Option<&Pose>),
    b: (&Mesh, Option<&Pose>),
    bound: Option<Pair>,
    out: &mut Pairs,
) -> Result<QueryStats> {
    least_pair(a, b, Intersect, bound, out)
}

/// Which triangles of two meshes intersect.
#[derive(Clone, Copy)]
struct Intersect;

impl<'m> Reach<'m> for Intersect {
    type SideA<K: NodeVolumes<'m>> = K;

    fn side_a<K: NodeVolumes<'m>>(&self, kind: K) -> K {
        kind
    }

    #[inline(always)]
    fn own(&self) -> Option<OneMesh<'m>> {
        None
    }
}

impl<'m> TriangleTest<'m> for Intersect {
    const CHECKS_DOMAIN: bool = true;

    #[inline]
    fn test(&self, _mesh: &Mesh, ta: &Prepared, tb: &Prepared) -> bool {
        ta.intersects(tb)
    }
}
