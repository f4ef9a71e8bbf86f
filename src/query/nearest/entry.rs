//! The closest-point queries: the traversal with volumes widened by the distance finds the node
//! pairs that may hold stencils; the shared narrow phase decides their primitive pairs exactly,
//! keeping where each stencil's closest points lie; once the stencils are sorted, their values
//! are computed straight into the result, on every thread the query may use.

use super::near_pairs::{NearPair, NearPairs, Stencil};
use crate::error::{Error, Result};
use crate::geometry::Primitive;
use crate::geometry::aabb::Aabb;
use crate::geometry::nearest::{decide_within, values};
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;
use crate::query::engine::node_pairs;
use crate::query::options::{QueryMode, QueryOptions};
use crate::query::pairs::QueryStats;
use crate::query::primitives::{
    self, ImpactKind, Key, Narrow, Owners, PrimitivePair, PrimitiveTest, Side,
};
use crate::query::proximity::{Near, check_distance};
use crate::threads;
use std::mem::MaybeUninit;

/// Every vertex-face and edge-edge pair of mesh `a` placed by `pose_a` and mesh `b` placed by
/// `pose_b` (`None`: the mesh's coordinates are world coordinates) whose distance is at most
/// `distance`, with the distance, the closest point on each primitive and where it lies: every
/// vertex of `a` against every triangle of `b` ([`crate::ImpactKind::VertexFace`]), every triangle of
/// `a` against every vertex of `b` ([`crate::ImpactKind::FaceVertex`]), every edge of `a` against every
/// edge of `b` (an edge is a pair of distinct vertices joined by a triangle side, counted once).
/// Vertices that belong to no triangle are not tested. These are the stencils from which
/// repulsion, barrier and constraint forces are built.
///
/// The decision "distance at most `distance`" is exact for the placed coordinates (those
/// [`Pose::transform_point`] computes, as in [`crate::collide`]), so `distance = 0` gives the
/// touching pairs. The values are those of [`crate::exact::vertex_face_nearest`] and
/// [`crate::exact::edge_edge_nearest`] on the placed coordinates: the distance within one unit
/// in the last place of the correctly rounded one, the points and weights within two, the
/// features classified exactly, with the documented choice where closest points are not unique.
///
/// [`QueryOptions`]: [`QueryMode::Triangles`] reports every stencil; [`QueryMode::FirstHit`]
/// the first found in the traversal's order (the same whatever the thread count), or none.
/// The coarse modes ([`QueryMode::Leaves`], [`QueryMode::Depth`], [`QueryMode::Budget`]) stop
/// the traversal where they say and test every primitive pair under the node pairs it reaches:
/// the stencils are still exact and the same as [`QueryMode::Triangles`]'s, only the split of
/// the work between traversal and primitive tests changes (a budget bounds the traversal only).
/// `max_pairs` stops the query once that many stencils are found (which ones does not depend on
/// the thread count); `threads` shares the work out. The result replaces the contents of `out`,
/// sorted by `(kind, a0, a1, b0, b1)`. In the counters returned,
/// [`QueryStats::triangle_tests`] counts the primitive pairs given to the exact test.
///
/// Errors: [`crate::Error::InvalidDistance`] for a negative, NaN or infinite `distance`;
/// [`crate::Error::PoseOutOfRange`]; [`crate::Error::ZeroBudget`];
/// [`crate::Error::OutOfMemory`]. On error `out` still holds the previous result.
pub fn nearest_features(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    distance: f64,
    options: &QueryOptions,
    out: &mut NearPairs,
) -> Result<QueryStats> {
    stencils(a, pose_a, Some((b, pose_b)), distance, options, out)
}

/// The stencils of one mesh with itself: every vertex against every triangle that does not
/// contain it (reported as [`crate::ImpactKind::VertexFace`], the vertex in `a0`), every pair of edges
/// that share no vertex (`(a0, a1) < (b0, b1)`), at distance at most `distance`. Otherwise as
/// [`nearest_features`].
pub fn self_nearest_features(
    mesh: &Mesh,
    distance: f64,
    options: &QueryOptions,
    out: &mut NearPairs,
) -> Result<QueryStats> {
    stencils(mesh, None, None, distance, options, out)
}

/// Below this many stencils, their values are computed on the calling thread.
const PARALLEL_MIN_VALUES: usize = 4096;
/// Shares of the stencils per thread, for their values.
const SHARES_PER_THREAD: usize = 8;

/// The closest-point test: primitive pairs whose boxes come within `d`, then the exact one.
struct Stencils<'p> {
    a: &'p [Point],
    b: &'p [Point],
    triangles_a: &'p [[u32; 3]],
    triangles_b: &'p [[u32; 3]],
    d: f64,
}

impl Stencils<'_> {
    #[inline]
    fn side(&self, side: Side) -> &[Point] {
        match side {
            Side::A => self.a,
            Side::B => self.b,
        }
    }

    /// The points of the stencil `key` in the order its test took them (the vertex, then the
    /// triangle's corners; or the two edges' ends), and its kind of pair.
    #[inline]
    fn points(&self, (kind, a0, a1, b0, b1): Key) -> (Primitive, [Point; 4]) {
        let (a, b) = (self.a, self.b);
        let at = |p: &[Point], v: u32| p[v as usize];
        match kind {
            ImpactKind::VertexFace => {
                let t = self.triangles_b[b0 as usize];
                let p = [at(a, a0), at(b, t[0]), at(b, t[1]), at(b, t[2])];
                (Primitive::VertexFace, p)
            }
            ImpactKind::FaceVertex => {
                let t = self.triangles_a[a0 as usize];
                let p = [at(b, b0), at(a, t[0]), at(a, t[1]), at(a, t[2])];
                (Primitive::VertexFace, p)
            }
            ImpactKind::EdgeEdge => {
                let p = [at(a, a0), at(a, a1), at(b, b0), at(b, b1)];
                (Primitive::EdgeEdge, p)
            }
        }
    }

    /// The stencil `s` with its values.
    #[inline]
    fn near_pair(&self, s: &Stencil) -> NearPair {
        let (kind, p) = self.points(s.key);
        NearPair::new(s.key, &values(kind, &p, s.decided))
    }

    /// The stencils `found` with their values appended to `out`, which has room for them, on
    /// up to `threads` threads, each writing its share in place.
    fn with_values(&self, found: &[Stencil], threads: usize, out: &mut Vec<NearPair>) {
        let n = found.len();
        debug_assert!(out.capacity() - out.len() >= n);
        if threads <= 1 || n < PARALLEL_MIN_VALUES {
            out.extend(found.iter().map(|s| self.near_pair(s)));
            return;
        }
        let start = out.len();
        // Shares taken in turn by the threads: the values of some stencils cost many times
        // those of others (a corner pair's against an edge's inside).
        let size = n.div_ceil(threads * SHARES_PER_THREAD);
        let shares: Vec<(&[Stencil], &mut [MaybeUninit<NearPair>])> = found
            .chunks(size)
            .zip(out.spare_capacity_mut()[..n].chunks_mut(size))
            .collect();
        threads::in_turns(threads::Step::Values, threads, shares, &|(from, to)| {
            for (s, slot) in from.iter().zip(to.iter_mut()) {
                slot.write(self.near_pair(s));
            }
        });
        // SAFETY: the shares cover the first `n` slots past the length, and each wrote every
        // slot of its own (a panic in one would have unwound past this line).
        unsafe { out.set_len(start + n) };
    }
}

impl PrimitiveTest for Stencils<'_> {
    type Found = Stencil;

    #[inline(always)]
    fn grow(&self, side: Side, v: u32, b: &mut Aabb) {
        b.grow(&self.side(side)[v as usize]);
    }

    #[inline(always)]
    fn reach(&self) -> f64 {
        self.d
    }

    #[inline]
    fn test<const N: usize, const M: usize>(
        &self,
        pair: PrimitivePair<N, M>,
        _: Option<&Stencil>,
    ) -> Option<Stencil> {
        let p = pair.points(self.side(pair.first), self.side(pair.second));
        // The narrow phase gives only primitives whose boxes come within `d` (up to rounding;
        // the decision is exact whatever it gives).
        let decided = decide_within(pair.kind, &p, self.d)?;
        Some(Stencil {
            key: pair.key,
            decided,
        })
    }
}

/// The vertices of `mesh` placed by `pose` into `buf`, or the mesh's own.
fn placed<'p>(mesh: &'p Mesh, pose: Option<&Pose>, buf: &'p mut Vec<Point>) -> &'p [Point] {
    match pose {
        Some(pose) if !pose.is_identity() => {
            buf.clear();
            buf.extend(mesh.positions().iter().map(|p| pose.transform_point(p)));
            buf
        }
        _ => mesh.positions(),
    }
}

/// [`nearest_features`] of `a` and `b`, or [`self_nearest_features`] of `a` (`b` is `None`).
fn stencils(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: Option<(&Mesh, Option<&Pose>)>,
    distance: f64,
    options: &QueryOptions,
    out: &mut NearPairs,
) -> Result<QueryStats> {
    check_distance(distance)?;
    let one_mesh = b.is_none();
    let (b, pose_b) = b.unwrap_or((a, pose_a));
    // The traversal finds node pairs; the stencils are the narrow phase's.
    let broad_mode = match options.mode {
        QueryMode::Triangles | QueryMode::FirstHit => QueryMode::Leaves,
        coarse => coarse,
    };
    let broad_options = QueryOptions::with_mode(broad_mode).with_threads(options.threads);
    let near = Near {
        d: distance,
        one_mesh,
    };
    let other = (!one_mesh).then_some((b, pose_b, None));
    let broad = node_pairs(
        (a, pose_a, None),
        other,
        near,
        &broad_options,
        &mut out.nodes,
    )?;
    let mut limit = options.max_pairs.unwrap_or(usize::MAX);
    if options.mode == QueryMode::FirstHit {
        limit = limit.min(1);
    }
    let NearPairs {
        items,
        spare,
        found,
        nodes,
        narrow_space,
        placed: [buf_a, buf_b],
    } = out;
    let mut stats = QueryStats {
        bv_tests: broad.bv_tests,
        leaf_pairs: broad.leaf_pairs,
        nodes_refit: broad.nodes_refit,
        frontier_pairs: broad.frontier_pairs,
        ..QueryStats::default()
    };
    spare.clear();
    if limit == 0 {
        stats.truncated = options.mode != QueryMode::FirstHit;
        std::mem::swap(items, spare);
        return Ok(stats);
    }
    let (pa, pb) = if one_mesh {
        let p = placed(a, None, buf_a);
        (p, p)
    } else {
        (placed(a, pose_a, buf_a), placed(b, pose_b, buf_b))
    };
    let narrow = Narrow {
        a: Owners::new(a),
        b: Owners::new(b),
        one_mesh,
        test: Stencils {
            a: pa,
            b: pb,
            triangles_a: a.triangles(),
            triangles_b: b.triangles(),
            d: distance,
        },
    };
    found.clear();
    let joined = primitives::test_leaf_pairs(
        &narrow,
        nodes.as_slice(),
        options.threads,
        limit,
        narrow_space,
        found,
        Stencil::key,
    )?;
    if spare.try_reserve(found.len()).is_err() {
        return Err(Error::OutOfMemory {
            bytes: found.len() * std::mem::size_of::<NearPair>(),
        });
    }
    let threads = threads::resolve(options.threads);
    narrow.test.with_values(found, threads, spare);
    stats.triangle_tests = joined.primitive_tests;
    // As the discrete queries: FirstHit stopping at its one stencil is not a cut.
    stats.truncated = joined.truncated && options.mode != QueryMode::FirstHit;
    stats.pairs = spare.len() as u64;
    std::mem::swap(items, spare);
    Ok(stats)
}
