//! What the intersection-curve queries report, and the reusable buffer it goes to.

use crate::csr::heap_bytes;
use crate::geometry::crossing::EndFeature;
use crate::geometry::predicates::Point;
use crate::query::pairs::Pairs;
use std::ops::Range;

/// One segment of an intersection curve: where triangle `triangle_a` of the first mesh crosses
/// triangle `triangle_b` of the second (of one mesh: the lower index, then the higher).
///
/// `start` and `end` are world coordinates, each the exact point rounded to the nearest double
/// coordinate by coordinate (ties to even), so within half a unit in the last place of it; a
/// point that is a mesh vertex keeps the vertex's bits. Every segment that ends at one exact
/// point carries the same bits for it, so within a curve the end of one segment is, bit for bit,
/// the start of the next.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct CurveSegment {
    /// The triangle of the first mesh (of one mesh: the lower index).
    pub triangle_a: u32,
    /// The triangle of the second mesh (of one mesh: the higher index).
    pub triangle_b: u32,
    /// The curve it belongs to (an index into [`Curves::curves`]).
    pub curve: u32,
    /// Always zero: the C layout's padding, written so that results compare byte for byte.
    pub(crate) reserved: u32,
    /// Where the segment starts, in the curve's direction.
    pub start: Point,
    /// Where it ends.
    pub end: Point,
}

/// A curve: a run of consecutive segments of [`Curves::segments`], each starting where the one
/// before ends.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Curve {
    /// Its segments' indices, in chain order.
    pub segments: Range<usize>,
    /// Does the last segment end where the first starts? An open curve ends on a boundary
    /// edge, at a degenerate pair, or where more than two segments meet.
    pub closed: bool,
}

/// Why a pair of intersecting triangles has no segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u32)]
pub enum DegenerateKind {
    /// The triangles meet in one point only (not coplanar; or a triangle degenerate to a
    /// segment or a point crossing the other's plane).
    Point = 0,
    /// Coplanar triangles that meet (in an area, a segment or a point), or a degenerate triangle
    /// that meets the other in its plane.
    Coplanar = 1,
}

/// A pair of intersecting triangles whose intersection is not a segment, reported apart from
/// the curves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(C)]
pub struct DegeneratePair {
    /// The triangle of the first mesh (of one mesh: the lower index).
    pub triangle_a: u32,
    /// The triangle of the second mesh (of one mesh: the higher index).
    pub triangle_b: u32,
    /// What they share.
    pub kind: DegenerateKind,
    /// Always zero: the C layout's padding.
    pub(crate) reserved: u32,
}

/// An end of a segment, named by the mesh features that meet there: the exact point it stands
/// for is decided by these alone, and two segments join exactly where their ends have the same
/// name. Edges are named by their two vertices, the lower first. Of one mesh (self curves),
/// the features are all the mesh's: a vertex is [`CurvePoint::VertexA`], an edge crossing a
/// triangle [`CurvePoint::EdgeA`], two edges [`CurvePoint::Edges`] with the lower edge first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CurvePoint {
    /// A vertex of the first mesh, lying in the second surface (or a vertex of both).
    VertexA(u32),
    /// A vertex of the second mesh, lying in the first surface.
    VertexB(u32),
    /// An edge of the first mesh crossing a triangle of the second where it meets its plane.
    EdgeA {
        /// The edge's vertices, lower first.
        edge: [u32; 2],
        /// The triangle of the second mesh.
        triangle: u32,
    },
    /// An edge of the second mesh crossing a triangle of the first.
    EdgeB {
        /// The triangle of the first mesh.
        triangle: u32,
        /// The edge's vertices, lower first.
        edge: [u32; 2],
    },
    /// An edge of the first mesh meeting an edge of the second at a point that is a vertex of
    /// neither.
    Edges {
        /// The first mesh's edge.
        a: [u32; 2],
        /// The second mesh's edge.
        b: [u32; 2],
    },
}

/// A caller-owned, reusable buffer of intersection curves, with the scratch space the queries
/// need (so that once grown to a scene's needs, a query on one thread allocates nothing). Use
/// one per calling thread.
#[derive(Debug, Default)]
pub struct Curves {
    pub(crate) result: CurveSet,
    /// Where a query writes; swapped with `result` when it succeeds, so a failed query leaves
    /// the previous result in place.
    pub(crate) spare: CurveSet,
    pub(crate) work: CurveWork,
}

/// One query's answer.
#[derive(Debug, Default)]
pub(crate) struct CurveSet {
    pub segments: Vec<CurveSegment>,
    /// The names of each segment's start and end.
    pub points: Vec<[CurvePoint; 2]>,
    pub curves: Vec<Curve>,
    pub degenerate: Vec<DegeneratePair>,
    /// Are these one mesh's self-intersection curves?
    pub one_mesh: bool,
}

impl CurveSet {
    pub(crate) fn clear(&mut self) {
        self.segments.clear();
        self.points.clear();
        self.curves.clear();
        self.degenerate.clear();
    }

    fn heap_bytes(&self) -> usize {
        heap_bytes(&self.segments)
            + heap_bytes(&self.points)
            + heap_bytes(&self.curves)
            + heap_bytes(&self.degenerate)
    }
}

/// A segment as the pairs give it, before chaining: its pair, its ends' names, features in the
/// pair and points (set once per name, after the ends are sorted), in the pair's own direction
/// (`n_a x n_b`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Piece {
    pub triangle_a: u32,
    pub triangle_b: u32,
    pub names: [CurvePoint; 2],
    pub points: [Point; 2],
    pub features: [EndFeature; 2],
}

/// What one intersecting pair gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Found {
    Piece(Piece),
    Degenerate(DegeneratePair),
}

/// The scratch space of the curve queries.
#[derive(Debug, Default)]
pub(crate) struct CurveWork {
    /// The intersecting pairs, and the traversal's scratch space.
    pub pairs: Pairs,
    /// What each pair gives, in the pairs' order.
    pub found: Vec<Found>,
    /// The segments before chaining.
    pub pieces: Vec<Piece>,
    /// Every segment end: its name packed as `(fields, kind << 32 | 2 * piece + which)`,
    /// sorted, so the ends of one name are together.
    pub ends: Vec<(u128, u64)>,
    /// Where each name's group of ends starts in `ends`, then `ends.len()`.
    pub groups: Vec<u32>,
    /// Each group's point.
    pub group_points: Vec<Point>,
    /// For each segment end, the end it joins (`NONE` where a curve ends).
    pub partner: Vec<u32>,
    /// Pieces already put into a curve.
    pub taken: Vec<bool>,
    /// A curve's pieces as they are walked: `(piece, reversed)`.
    pub walk: Vec<(u32, bool)>,
    /// Each curve's least piece and where its walk is in `walk_all`, for ordering the curves.
    pub order: Vec<(u32, u32, u32, bool)>,
    /// Every curve's walk, one after another.
    pub walk_all: Vec<(u32, bool)>,
}

impl CurveWork {
    fn heap_bytes(&self) -> usize {
        self.pairs.memory_bytes()
            + heap_bytes(&self.found)
            + heap_bytes(&self.pieces)
            + heap_bytes(&self.ends)
            + heap_bytes(&self.groups)
            + heap_bytes(&self.group_points)
            + heap_bytes(&self.partner)
            + heap_bytes(&self.taken)
            + heap_bytes(&self.walk)
            + heap_bytes(&self.order)
            + heap_bytes(&self.walk_all)
    }
}

impl Curves {
    /// An empty buffer.
    pub fn new() -> Curves {
        Curves::default()
    }

    /// The segments of the last successful query, curve by curve, each curve's in chain order.
    pub fn segments(&self) -> &[CurveSegment] {
        &self.result.segments
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.result.segments.len()
    }

    /// No segments?
    pub fn is_empty(&self) -> bool {
        self.result.segments.is_empty()
    }

    /// The curves, ordered by their least segment `(triangle_a, triangle_b)`.
    pub fn curves(&self) -> &[Curve] {
        &self.result.curves
    }

    /// The segments of curve `curve`, in chain order.
    ///
    /// # Panics
    ///
    /// When `curve` is not below `curves().len()`.
    pub fn curve_segments(&self, curve: usize) -> &[CurveSegment] {
        &self.result.segments[self.result.curves[curve].segments.clone()]
    }

    /// The names of segment `segment`'s start and end: which features of the meshes meet there.
    ///
    /// # Panics
    ///
    /// When `segment` is not below `len()`.
    pub fn segment_points(&self, segment: usize) -> [CurvePoint; 2] {
        self.result.points[segment]
    }

    /// The intersecting pairs that have no segment, sorted by `(triangle_a, triangle_b)`.
    pub fn degenerate(&self) -> &[DegeneratePair] {
        &self.result.degenerate
    }

    /// The length of curve `curve`: the sum of its segments' lengths, each computed from the
    /// rounded end points.
    ///
    /// # Panics
    ///
    /// When `curve` is not below `curves().len()`.
    pub fn curve_length(&self, curve: usize) -> f64 {
        self.curve_segments(curve)
            .iter()
            .map(|s| super::measure::distance(&s.start, &s.end))
            .sum()
    }

    /// Bytes of memory the buffer holds beyond the struct itself: the result, its spare, and
    /// the scratch space of the queries it served.
    pub fn memory_bytes(&self) -> usize {
        self.result.heap_bytes() + self.spare.heap_bytes() + self.work.heap_bytes()
    }
}
