//! What the closest-point query reports, and the reusable buffer it goes to.

use crate::csr::heap_bytes;
use crate::geometry::nearest::{Decided, Feature, Nearest};
use crate::geometry::predicates::Point;
use crate::query::pairs::{Pairs, result_buffer};
use crate::query::primitives::{ImpactKind, Key, Workspace};

/// A vertex-face or edge-edge pair within the query's distance: a contact stencil, with the
/// closest point on each primitive.
///
/// The kinds and indices are those of [`crate::Impact`]: a vertex of `a` and a triangle of `b`
/// ([`ImpactKind::VertexFace`]), a triangle of `a` and a vertex of `b`
/// ([`ImpactKind::FaceVertex`]), or two edges, each with its lower vertex first
/// ([`ImpactKind::EdgeEdge`]). Fields ending in `_a` describe the primitive named by `a0, a1`.
///
/// Features and weights are numbered on the primitive's own corners: a vertex is corner 0; an
/// edge `(a0, a1)` has corners `a0`, `a1`; a triangle has its corners in the mesh's order.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct NearPair {
    /// Which primitives.
    pub kind: ImpactKind,
    /// The first mesh's vertex, triangle, or edge's lower vertex.
    pub a0: u32,
    /// The first mesh's edge's higher vertex; 0 otherwise.
    pub a1: u32,
    /// The second mesh's triangle, vertex, or edge's lower vertex.
    pub b0: u32,
    /// The second mesh's edge's higher vertex; 0 otherwise.
    pub b1: u32,
    /// Where the closest point of the first primitive lies.
    pub feature_a: Feature,
    /// Where the closest point of the second primitive lies.
    pub feature_b: Feature,
    /// Always zero: the C layout's padding, written so that results compare and hash byte for
    /// byte.
    pub(crate) padding: u32,
    /// The distance, within one unit in the last place of the exact one correctly rounded.
    pub distance: f64,
    /// The closest point of the first primitive, in world coordinates (each within two units in
    /// the last place of the exact one).
    pub closest_a: Point,
    /// The closest point of the second primitive, in world coordinates.
    pub closest_b: Point,
    /// The first closest point's barycentric weights on its primitive's corners: a vertex
    /// `(1, 0, 0)`, an edge `(1 - s, s, 0)`, a triangle three weights summing to one.
    pub weights_a: [f64; 3],
    /// The second closest point's barycentric weights.
    pub weights_b: [f64; 3],
}

impl NearPair {
    /// The stencil `key` from the closest points `n` of its primitives as the primitive test
    /// took them: the vertex first for a vertex-face pair, so a triangle of `a` against a vertex
    /// of `b` ([`ImpactKind::FaceVertex`]) has its sides swapped.
    pub(crate) fn new((kind, a0, a1, b0, b1): Key, n: &Nearest) -> NearPair {
        let (ia, ib) = if kind == ImpactKind::FaceVertex {
            (1, 0)
        } else {
            (0, 1)
        };
        NearPair {
            kind,
            a0,
            a1,
            b0,
            b1,
            feature_a: n.features[ia],
            feature_b: n.features[ib],
            padding: 0,
            distance: n.distance,
            closest_a: n.points[ia],
            closest_b: n.points[ib],
            weights_a: n.weights[ia],
            weights_b: n.weights[ib],
        }
    }

    /// The order of a result: `(kind, a0, a1, b0, b1)`.
    pub(crate) fn key(&self) -> Key {
        (self.kind, self.a0, self.a1, self.b0, self.b1)
    }
}

/// A stencil as the narrow phase finds it: its key and where its closest points lie. Its values
/// are computed once the stencils are sorted, straight into the result, so that what the
/// narrow phase keeps, and what is moved and sorted, is 24 bytes a stencil rather than 136.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stencil {
    pub key: Key,
    pub decided: Decided,
}

impl Stencil {
    pub(crate) fn key(&self) -> Key {
        self.key
    }
}

/// A caller-owned, reusable buffer of closest-point stencils, with the scratch space the
/// queries need (so that once grown to a scene's needs, a query on one thread allocates
/// little). Use one per calling thread.
#[derive(Debug, Default)]
pub struct NearPairs {
    pub(crate) items: Vec<NearPair>,
    /// Where a query writes; swapped with `items` when it succeeds.
    pub(crate) spare: Vec<NearPair>,
    /// The traversal's node pairs, and its scratch space.
    pub(crate) nodes: Pairs,
    /// The stencils found, sorted, before their values are computed into `spare`.
    pub(crate) found: Vec<Stencil>,
    /// The narrow phase's scratch space.
    pub(crate) narrow_space: Workspace<Stencil>,
    /// The placed vertices of a posed mesh (each side).
    pub(crate) placed: [Vec<Point>; 2],
}

result_buffer!(
    NearPairs,
    NearPair,
    "stencils",
    as_slice: "The stencils of the last successful query, sorted by `(kind, a0, a1, b0, b1)`."
);

impl NearPairs {
    /// Bytes of memory the buffer holds beyond the struct itself: the result, its spare, and
    /// the scratch space of the queries it served.
    pub fn memory_bytes(&self) -> usize {
        heap_bytes(&self.items)
            + heap_bytes(&self.spare)
            + self.nodes.memory_bytes()
            + heap_bytes(&self.found)
            + self.narrow_space.heap_bytes()
            + self.placed.iter().map(heap_bytes).sum::<usize>()
    }
}
