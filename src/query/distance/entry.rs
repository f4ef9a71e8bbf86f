//! The least distance between two meshes, exactly: the pair of primitives that attains it, the
//! closest points, and for intersecting meshes the least intersecting triangle pair.
//!
//! Meshes that intersect are told by the exact intersection query's first hit; the least
//! intersecting pair is then found below it by a search that opens node pairs by the least
//! triangle pair they may hold, so that a dense contact (a coincident copy) costs a few leaf
//! pairs rather than all of them. Otherwise one walk of both hierarchies finds the primitive pair whose
//! floating-point estimate is least and keeps every triangle pair that certain bounds (the node
//! volumes' and the triangles' boxes in Euclidean distance with a rounding margin, the
//! separation along each pair's estimated direction) cannot put beyond that estimate; the
//! guess's exact distance, rounded up, bounds the least, and exact decisions choose among the
//! vertex-face and edge-edge pairs of the kept triangle pairs within it. Between two closed
//! triangles that do not intersect, the least distance is attained by one of those pairs, so
//! nothing else needs looking at. Where the guess's exact distance is beyond what the walk kept
//! (a degenerate triangle's estimate far too low), the exact stencil query
//! ([`crate::nearest_features`]) to that distance takes over.

use crate::collide;
use crate::error::Result;
use crate::geometry::crossing::{PairIntersection, edge_meets_plane, triangle_pair_intersection};
use crate::geometry::nearest::{Primitive, cmp_distance, decide_near, decide_within, values};
use crate::geometry::pose::Pose;
use crate::geometry::predicates::{Point, orient3d};
use crate::mesh::Mesh;
use crate::query::collide::least_intersecting;
use crate::query::nearest::{NearPair, NearPairs, nearest_features};
use crate::query::options::{QueryMode, QueryOptions};
use crate::query::pairs::{Pairs, QueryStats};
use crate::query::points::DistanceOptions;
use crate::query::points::walk::{Frame, PairScratch, mesh_feature};
use crate::query::primitives::{ImpactKind, Key};
use std::cell::RefCell;
use std::cmp::Ordering;

/// The least distance between two meshes' surfaces, as [`distance`] reports it. The layout is
/// the C ABI's `DvhDistance`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Distance {
    found: u32,
    intersecting: u32,
    /// The triangle of the first mesh the closest point lies on (of several, the least).
    pub triangle_a: u32,
    /// The triangle of the second mesh the closest point lies on (of several, the least).
    pub triangle_b: u32,
    /// The distance, within one unit in the last place of the exact one correctly rounded; 0
    /// for intersecting meshes.
    pub distance: f64,
    /// The closest point of the first mesh, in world coordinates.
    pub closest_a: Point,
    /// The closest point of the second mesh, in world coordinates (for intersecting meshes,
    /// `closest_a` again: a point of both triangles, within rounding).
    pub closest_b: Point,
    /// The vertex-face or edge-edge pair that attains the distance, as
    /// [`crate::nearest_features`] reports it; zero for intersecting meshes.
    pub stencil: NearPair,
}

impl Distance {
    /// Are the meshes within the query's `max_distance`? When not, every field is zero.
    pub fn found(&self) -> bool {
        self.found != 0
    }

    /// Do the meshes intersect (touching counts)? Then the distance is 0.
    pub fn intersecting(&self) -> bool {
        self.intersecting != 0
    }
}

/// The scratch of [`distance`], kept by each thread between calls.
#[derive(Default)]
struct Scratch {
    pairs: Pairs,
    near: NearPairs,
    walk: PairScratch,
    /// The stencils of the kept triangle pairs within the radius, with their values.
    candidates: Vec<NearPair>,
    placed: [(Vec<Point>, Vec<crate::geometry::aabb::Aabb>); 2],
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::default();
}

/// The primitives of stencil `key` of meshes placed as `a` and `b` see them, as the exact tests
/// take them, and their kind of pair.
fn stencil_points(a: &Frame, b: &Frame, (kind, a0, a1, b0, b1): Key) -> (Primitive, [Point; 4]) {
    match kind {
        ImpactKind::VertexFace => {
            let [x, y, z] = b.corners(b0);
            (Primitive::VertexFace, [a.vertex(a0), x, y, z])
        }
        ImpactKind::FaceVertex => {
            let [x, y, z] = a.corners(a0);
            (Primitive::VertexFace, [b.vertex(b0), x, y, z])
        }
        ImpactKind::EdgeEdge => (
            Primitive::EdgeEdge,
            [a.vertex(a0), a.vertex(a1), b.vertex(b0), b.vertex(b1)],
        ),
    }
}

/// The stencil `key`, whose squared distance is about `estimate`, with its values, exactly;
/// `None` beyond the largest double.
fn exact_stencil(a: &Frame, b: &Frame, key: Key, estimate: f64) -> Option<NearPair> {
    let (pair, p) = stencil_points(a, b, key);
    let decided = decide_near(pair, &p, estimate)?;
    Some(NearPair::new(key, &values(pair, &p, decided)))
}

/// The mesh features of both sides of stencil `s` that hold its closest points: two stencils
/// with the same have the same closest points, so the same distance (the common tie: the
/// stencils around the nearest vertex or edge).
fn mesh_features(a: &Frame, b: &Frame, s: &NearPair) -> [[u32; 3]; 2] {
    match s.kind {
        ImpactKind::VertexFace => [
            mesh_feature(&[s.a0], 0, s.feature_a),
            mesh_feature(&b.triangle(s.b0), s.b0, s.feature_b),
        ],
        ImpactKind::FaceVertex => [
            mesh_feature(&a.triangle(s.a0), s.a0, s.feature_a),
            mesh_feature(&[s.b0], 0, s.feature_b),
        ],
        ImpactKind::EdgeEdge => [
            mesh_feature(&[s.a0, s.a1], 0, s.feature_a),
            mesh_feature(&[s.b0, s.b1], 0, s.feature_b),
        ],
    }
}

/// The least of `found` (sorted by key) by exact distance, the first in key order among equals.
fn least(a: &Frame, b: &Frame, found: &[NearPair]) -> Option<NearPair> {
    let mut best: Option<(NearPair, Primitive, [Point; 4])> = None;
    for s in found {
        let (pair, p) = stencil_points(a, b, s.key());
        let closer = match &best {
            None => true,
            Some((t, tpair, tp)) => {
                // Rounded distances within a unit of the correctly rounded: apart by more than
                // four units, their order is the exact one.
                let certain = s.distance.next_up().next_up() < t.distance.next_down().next_down();
                let apart = t.distance.next_up().next_up() < s.distance.next_down().next_down();
                if certain || apart {
                    certain
                } else if mesh_features(a, b, s) == mesh_features(a, b, t) {
                    false
                } else {
                    let x = decide_near(pair, &p, s.distance * s.distance)
                        .expect("found within the reach");
                    let y = decide_near(*tpair, tp, t.distance * t.distance)
                        .expect("found within the reach");
                    cmp_distance((pair, &p, x), (*tpair, tp, y)) == Ordering::Less
                }
            }
        };
        if closer {
            best = Some((*s, pair, p));
        }
    }
    best.map(|b| b.0)
}

/// A point both triangles hold (within rounding), for triangles that meet.
fn shared_point(ta: &[Point; 3], tb: &[Point; 3]) -> Point {
    if let PairIntersection::Segment { start, .. } = triangle_pair_intersection(ta, tb) {
        return start.point;
    }
    // Touching at a point, or coplanar: a vertex-face or edge-edge pair at distance 0 (the
    // distance of two closed triangles that do not cross is attained by one).
    for (x, y) in [(ta, tb), (tb, ta)] {
        for corner in x {
            let p = [*corner, y[0], y[1], y[2]];
            if let Some(d) = decide_within(Primitive::VertexFace, &p, 0.0) {
                return values(Primitive::VertexFace, &p, d).points[0];
            }
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let p = [ta[i], ta[(i + 1) % 3], tb[j], tb[(j + 1) % 3]];
            if let Some(d) = decide_within(Primitive::EdgeEdge, &p, 0.0) {
                return values(Primitive::EdgeEdge, &p, d).points[0];
            }
        }
    }
    // A degenerate triangle (a segment) through the other's interior: where its edge meets
    // the other's plane.
    for (x, y) in [(ta, tb), (tb, ta)] {
        for k in 0..3 {
            let (p, q) = (&x[k], &x[(k + 1) % 3]);
            let (sp, sq) = (
                orient3d(&y[0], &y[1], &y[2], p),
                orient3d(&y[0], &y[1], &y[2], q),
            );
            if sp != sq && sp * sq <= 0 {
                return edge_meets_plane(p, q, y);
            }
        }
    }
    ta[0]
}

/// The least distance between the surfaces of mesh `a` placed by `pose_a` and mesh `b` placed
/// by `pose_b` (`None`: the mesh's coordinates are world coordinates), written to `out`.
///
/// Exact: with no tolerance the reported pair of primitives attains the exact least distance
/// (candidates are ordered by exact comparisons; of several at the least distance, the first in
/// the order `(kind, a0, a1, b0, b1)` of [`crate::nearest_features`] is reported, whatever the
/// thread count), its distance within one unit in the last place of the exact one correctly
/// rounded, its closest points within two units. `triangle_a` and `triangle_b` are the least
/// triangles holding the pair's vertex, edge or face on each side. Meshes that intersect
/// (touching counts) get distance 0, [`Distance::intersecting`], the least intersecting triangle
/// pair in [`crate::collide`]'s order and a point of both triangles (within rounding) as both
/// closest points.
///
/// [`DistanceOptions`]: farther apart than `max_distance` is not [`Distance::found`] (the
/// cheapest query); with `rel_err` or `abs_err`, a pair at distance `d <= (1 + rel_err) m +
/// abs_err` of the least `m` may be reported (its values are still its own; which of those comes may
/// depend on the volume kind, never on the thread count); `threads` shares
/// the work out. Posed coordinates are those [`Pose::transform_point`] computes, as in
/// [`crate::collide`]. The counters returned are the sums of the queries made.
///
/// Errors: [`crate::Error::InvalidDistanceOption`]; [`crate::Error::PoseOutOfRange`];
/// [`crate::Error::OutOfMemory`]. On error `out` is unchanged.
pub fn distance(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    options: &DistanceOptions,
    out: &mut Distance,
) -> Result<QueryStats> {
    options.check()?;
    SCRATCH.with(|s| {
        let s = &mut *s.borrow_mut();
        let (result, stats) = least_distance(a, pose_a, b, pose_b, options, s)?;
        *out = result;
        Ok(stats)
    })
}

fn least_distance(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    options: &DistanceOptions,
    s: &mut Scratch,
) -> Result<(Distance, QueryStats)> {
    let query = QueryOptions::default().with_threads(options.threads);
    let mut stats = collide(
        a,
        pose_a,
        b,
        pose_b,
        &QueryOptions::with_mode(QueryMode::FirstHit).with_threads(options.threads),
        &mut s.pairs,
    )?;
    let [pa_buf, pb_buf] = &mut s.placed;
    let fa = frame_of(a, pose_a, pa_buf);
    let fb = frame_of(b, pose_b, pb_buf);
    if let Some(&hit) = s.pairs.as_slice().first() {
        // Intersecting: the least pair of all, below the first hit.
        let least = least_intersecting((a, pose_a), (b, pose_b), Some(hit), &mut s.pairs)?;
        stats.add(&least);
        let p = s.pairs.as_slice()[0];
        let point = shared_point(&fa.corners(p.a), &fb.corners(p.b));
        let result = Distance {
            found: 1,
            intersecting: 1,
            triangle_a: p.a,
            triangle_b: p.b,
            distance: 0.0,
            closest_a: point,
            closest_b: point,
            stencil: NearPair::default(),
        };
        return Ok((result, stats));
    }
    let max = options.max_distance;
    let shrink = |d: f64| options.improving(d);
    let walk = fa.nearest_pair_kept(&fb, max, shrink, &mut s.walk);
    stats.bv_tests += walk.volume_tests;
    let guess = walk
        .best
        .and_then(|(key, e)| exact_stencil(&fa, &fb, key, e));
    // Every triangle pair within the walk's reach is kept; the exact decisions need the
    // stencils within the guess's exact distance (or the tolerance's radius below it).
    let (radius, accepted) = match guess {
        Some(g) => {
            // Two units up from a distance within one of the correctly rounded: at least the
            // exact distance.
            let exact_bound = g.distance.next_up().next_up();
            if options.tolerant() && exact_bound <= max {
                // Accepted unless something is nearer than the tolerance allows.
                (options.improving(exact_bound), Some(g))
            } else {
                // Widened a little: the guess and the stencils tying with it are then told
                // within by the filters, not in exact arithmetic at the boundary; the few more
                // it may take in are ordered exactly.
                let r = (exact_bound * (1.0 + 1.0 / (1u64 << 30) as f64)).next_up();
                (r.min(max), None)
            }
        }
        // Nothing within the bound by the estimates (or only beyond the largest double): the
        // exact decisions settle it.
        None => (max.min(f64::MAX), None),
    };
    let found = if radius <= walk.reach {
        stats.triangle_tests += kept_within(&fa, &fb, radius, &s.walk.kept, &mut s.candidates);
        match accepted {
            Some(g) if s.candidates.is_empty() => Some(g),
            _ => least(&fa, &fb, &s.candidates),
        }
    } else {
        // The guess's estimate was far below its exact distance (a degenerate triangle): the
        // stencil query to the radius.
        let near = nearest_features(a, pose_a, b, pose_b, radius, &query, &mut s.near)?;
        stats.add(&near);
        match accepted {
            Some(g) if s.near.is_empty() => Some(g),
            _ => least(&fa, &fb, s.near.as_slice()),
        }
    };
    let Some(stencil) = found else {
        return Ok((Distance::default(), stats));
    };
    let (sa, sb) = (a.surface(), b.surface());
    let (triangle_a, triangle_b) = match stencil.kind {
        ImpactKind::VertexFace => (sa.vertex_triangle[stencil.a0 as usize], stencil.b0),
        ImpactKind::FaceVertex => (stencil.a0, sb.vertex_triangle[stencil.b0 as usize]),
        ImpactKind::EdgeEdge => (
            sa.edge_triangle(stencil.a0, stencil.a1)
                .expect("an edge of a"),
            sb.edge_triangle(stencil.b0, stencil.b1)
                .expect("an edge of b"),
        ),
    };
    let result = Distance {
        found: 1,
        intersecting: 0,
        triangle_a,
        triangle_b,
        distance: stencil.distance,
        closest_a: stencil.closest_a,
        closest_b: stencil.closest_b,
        stencil,
    };
    Ok((result, stats))
}

/// The stencils of the triangle pairs the walk kept whose bound is within `radius`, decided
/// exactly within it, with their values, into `candidates`, sorted by key and each once (a
/// vertex or an edge belongs to several triangles). Returns the exact decisions made.
fn kept_within(
    a: &Frame,
    b: &Frame,
    radius: f64,
    kept: &[(u32, u32, f64)],
    candidates: &mut Vec<NearPair>,
) -> u64 {
    candidates.clear();
    let mut tests = 0;
    let mut decide = |key: Key| {
        tests += 1;
        let (pair, p) = stencil_points(a, b, key);
        if let Some(decided) = decide_within(pair, &p, radius) {
            candidates.push(NearPair::new(key, &values(pair, &p, decided)));
        }
    };
    for &(ta, tb, lower) in kept {
        if lower > radius {
            continue;
        }
        let (ia, ib) = (a.triangle(ta), b.triangle(tb));
        for k in 0..3 {
            decide((ImpactKind::VertexFace, ia[k], 0, tb, 0));
            decide((ImpactKind::FaceVertex, ta, 0, ib[k], 0));
        }
        for i in 0..3 {
            let (u, v) = (ia[i], ia[(i + 1) % 3]);
            for j in 0..3 {
                let (w, z) = (ib[j], ib[(j + 1) % 3]);
                if u != v && w != z {
                    decide((ImpactKind::EdgeEdge, u.min(v), u.max(v), w.min(z), w.max(z)));
                }
            }
        }
    }
    candidates.sort_unstable_by_key(|c| c.key());
    candidates.dedup_by_key(|c| c.key());
    tests
}

/// The frame of mesh `m` placed by `pose`: its own, or its vertices placed into `placed`.
fn frame_of<'m>(
    m: &'m Mesh,
    pose: Option<&Pose>,
    placed: &'m mut (Vec<Point>, Vec<crate::geometry::aabb::Aabb>),
) -> Frame<'m> {
    match pose.filter(|p| !p.is_identity()) {
        None => Frame::own(m),
        Some(p) => {
            let (v, b) = placed;
            Frame::placed(m, p, v, b)
        }
    }
}
