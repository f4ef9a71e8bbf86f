//! The intersection-curve queries: the intersecting pairs, found as [`crate::collide`] and
//! [`crate::self_collide`] find them; each pair's exact intersection, its segment's ends named
//! by mesh features; the segments chained by those names.

use super::chain::{chain, end_index, link};
use super::result::{CurvePoint, CurveWork, Curves, DegenerateKind, DegeneratePair, Found, Piece};
use crate::error::{Error, Result};
use crate::geometry::crossing::{
    EndFeature, Normals, PairIntersection, end_point_kept, triangle_pair_features,
    triangle_pair_intersection,
};
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::geometry::tri_tri::Triangle;
use crate::mesh::Mesh;
use crate::query::options::{QueryMode, QueryOptions};
use crate::query::pairs::{Pair, QueryStats};
use crate::query::{collide, self_collide};
use crate::threads;
use std::mem::MaybeUninit;

/// The curves along which mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b` (`None`:
/// the mesh's coordinates are world coordinates) cross.
///
/// Every pair of triangles [`crate::collide`] reports gives either a segment (two triangles
/// that are not coplanar and meet in more than one point) or a [`DegeneratePair`] (they meet in
/// a single point, or are coplanar; a degenerate triangle gives one too). A segment's ends are
/// where an edge of one triangle meets the other triangle, or a vertex lying in it, named by
/// those features ([`CurvePoint`]) as the exact predicates decide, and rounded once to doubles
/// (see [`crate::CurveSegment`]). Segments join into curves where their ends have the same
/// name and no third end has it (see [`Curves`]): a curve is closed when it returns to its
/// start; it is open where it ends on a boundary edge, beside a degenerate pair, or at a junction
/// of more than two segments. Where an edge of one mesh lies in the other surface, the pairs on
/// both sides of it give the same segment, and each takes part in the chaining.
///
/// The answer is deterministic: a curve runs along `n_a x n_b` of its least segment's pair
/// (`n` a triangle's normal `(t1 - t0) x (t2 - t0)` in world coordinates, the direction decided
/// exactly), a closed curve starts at its least `(triangle_a, triangle_b)` segment, and curves
/// are ordered by their least segment. With consistently oriented surfaces every segment of a
/// curve runs along its own pair's `n_a x n_b`.
///
/// [`QueryOptions`]: only [`QueryMode::Triangles`] (any other is
/// [`crate::Error::UnsupportedMode`]); `threads` shares the work out (the answer is the same for
/// every thread count); `max_pairs` bounds the segments plus degenerate pairs, taking the pairs
/// [`crate::collide`] would keep. In the counters returned, [`QueryStats::pairs`] counts the
/// intersecting pairs (segments plus degenerate pairs).
///
/// Errors: [`crate::Error::UnsupportedMode`]; [`crate::Error::PoseOutOfRange`];
/// [`crate::Error::OutOfMemory`]. On error `out` still holds the previous result.
///
/// Cost: [`crate::collide`]'s, plus an exact intersection per intersecting pair and a sort of
/// the segments' ends. Once `out` has grown to a scene's needs, a query on one thread allocates
/// nothing.
pub fn intersection_curves(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    options: &QueryOptions,
    out: &mut Curves,
) -> Result<QueryStats> {
    check_mode(options)?;
    let stats = collide(a, pose_a, b, pose_b, options, &mut out.work.pairs)?;
    let sides = Sides {
        a: (a, pose_a.filter(|p| !p.is_identity())),
        b: (b, pose_b.filter(|p| !p.is_identity())),
        one_mesh: false,
    };
    finish(&sides, options, stats, out)
}

/// The curves along which `mesh` crosses itself: those of the pairs [`crate::self_collide`]
/// reports (triangles that share vertices count only where they meet beyond what they share).
/// A pair that shares a vertex gives a segment from that vertex to where the two part; a pair
/// sharing an edge meets beyond it only when coplanar (a degenerate pair).
///
/// Segments are `(lower, higher)` triangle pairs, and ends are named by features of the one
/// mesh ([`CurvePoint::VertexA`], [`CurvePoint::EdgeA`], [`CurvePoint::Edges`] with the lower
/// edge first), so a curve passes from a pair to its neighbour whichever of the two triangles
/// has the lower index; a segment runs against its pair's `n_a x n_b` where the chain needs it
/// to. Otherwise as [`intersection_curves`].
pub fn self_intersection_curves(
    mesh: &Mesh,
    options: &QueryOptions,
    out: &mut Curves,
) -> Result<QueryStats> {
    check_mode(options)?;
    let stats = self_collide(mesh, options, &mut out.work.pairs)?;
    let sides = Sides {
        a: (mesh, None),
        b: (mesh, None),
        one_mesh: true,
    };
    finish(&sides, options, stats, out)
}

fn check_mode(options: &QueryOptions) -> Result<()> {
    match options.mode {
        QueryMode::Triangles => Ok(()),
        mode => Err(Error::UnsupportedMode {
            mode,
            query: "intersection curves",
        }),
    }
}

/// Below this many intersecting pairs, their intersections are computed on the calling thread
/// (256 pairs are about 100 µs of work, worth sharing).
pub(super) const PARALLEL_MIN_PAIRS: usize = 256;
/// Shares of the pairs per thread.
const SHARES_PER_THREAD: usize = 8;

/// The two placed meshes of a query.
struct Sides<'m> {
    a: (&'m Mesh, Option<&'m Pose>),
    b: (&'m Mesh, Option<&'m Pose>),
    one_mesh: bool,
}

impl Sides<'_> {
    /// The world corners of triangle `t` of a side, each placed as [`crate::collide`] places it.
    #[inline]
    fn corners((mesh, pose): (&Mesh, Option<&Pose>), t: [u32; 3]) -> Triangle {
        let p = mesh.positions();
        let at = |v: u32| -> Point {
            let q = &p[v as usize];
            match pose {
                Some(pose) => pose.transform_point(q),
                None => *q,
            }
        };
        [at(t[0]), at(t[1]), at(t[2])]
    }

    /// What the intersecting pair `pair` gives.
    fn found(&self, pair: Pair) -> Found {
        let ta = self.a.0.triangles()[pair.a as usize];
        let tb = self.b.0.triangles()[pair.b as usize];
        let degenerate = |kind| {
            Found::Degenerate(DegeneratePair {
                triangle_a: pair.a,
                triangle_b: pair.b,
                kind,
                reserved: 0,
            })
        };
        let corners_a = Self::corners(self.a, ta);
        let corners_b = Self::corners(self.b, tb);
        // The points come later, once per name (`points_all`).
        match triangle_pair_features(&corners_a, &corners_b) {
            PairIntersection::Segment { start, end } => Found::Piece(Piece {
                triangle_a: pair.a,
                triangle_b: pair.b,
                names: [start.feature, end.feature].map(|f| self.name(f, pair, ta, tb)),
                points: [start.point, end.point],
                features: [start.feature, end.feature],
            }),
            PairIntersection::Point => degenerate(DegenerateKind::Point),
            // `Apart` is not reached: the pair test and the intersection decide alike, on the
            // same doubles (checked in the tests); a pair reported is kept, as coplanar.
            PairIntersection::Coplanar | PairIntersection::Apart => {
                debug_assert!(
                    !matches!(
                        triangle_pair_intersection(&corners_a, &corners_b),
                        PairIntersection::Apart
                    ),
                    "pair {pair:?} reported by the pair test but apart"
                );
                degenerate(DegenerateKind::Coplanar)
            }
        }
    }

    /// The name of an end at `feature` of the pair `pair` (triangles `ta`, `tb`).
    fn name(&self, feature: EndFeature, pair: Pair, ta: [u32; 3], tb: [u32; 3]) -> CurvePoint {
        let edge = |t: [u32; 3], (i, j): (u8, u8)| {
            let (u, v) = (t[i as usize], t[j as usize]);
            [u.min(v), u.max(v)]
        };
        let one = self.one_mesh;
        match feature {
            EndFeature::CornerOfA(k) => CurvePoint::VertexA(ta[k as usize]),
            EndFeature::CornerOfB(k) if one => CurvePoint::VertexA(tb[k as usize]),
            EndFeature::CornerOfB(k) => CurvePoint::VertexB(tb[k as usize]),
            // Of one mesh, two vertices at one point are one only when they are one index;
            // otherwise the lower names it.
            EndFeature::SharedCorner { a, b } if one => {
                CurvePoint::VertexA(ta[a as usize].min(tb[b as usize]))
            }
            EndFeature::SharedCorner { a, .. } => CurvePoint::VertexA(ta[a as usize]),
            EndFeature::EdgeOfA { i, j } => CurvePoint::EdgeA {
                edge: edge(ta, (i, j)),
                triangle: pair.b,
            },
            EndFeature::EdgeOfB { i, j } if one => CurvePoint::EdgeA {
                edge: edge(tb, (i, j)),
                triangle: pair.a,
            },
            EndFeature::EdgeOfB { i, j } => CurvePoint::EdgeB {
                triangle: pair.a,
                edge: edge(tb, (i, j)),
            },
            EndFeature::Edges { a, b } => {
                let (ea, eb) = (edge(ta, a), edge(tb, b));
                if one {
                    CurvePoint::Edges {
                        a: ea.min(eb),
                        b: ea.max(eb),
                    }
                } else {
                    CurvePoint::Edges { a: ea, b: eb }
                }
            }
        }
    }

    /// What each of `pairs` gives, into `found` (cleared first), on up to `threads` threads.
    fn found_all(&self, pairs: &[Pair], threads: usize, found: &mut Vec<Found>) -> Result<()> {
        found.clear();
        let n = pairs.len();
        found.try_reserve(n).map_err(|_| Error::OutOfMemory {
            bytes: n * std::mem::size_of::<Found>(),
        })?;
        if threads <= 1 || n < PARALLEL_MIN_PAIRS {
            found.extend(pairs.iter().map(|&p| self.found(p)));
            return Ok(());
        }
        // Shares taken in turn: a pair in exact rationals costs many times one in doubles.
        let size = n.div_ceil(threads * SHARES_PER_THREAD);
        let shares: Vec<(&[Pair], &mut [MaybeUninit<Found>])> = pairs
            .chunks(size)
            .zip(found.spare_capacity_mut()[..n].chunks_mut(size))
            .collect();
        threads::in_turns(threads::Step::Crossings, threads, shares, &|(from, to)| {
            for (&p, slot) in from.iter().zip(to.iter_mut()) {
                slot.write(self.found(p));
            }
        });
        // SAFETY: the shares cover the first `n` slots, and each wrote every slot of its own
        // (a panic in one would have unwound past this line).
        unsafe { found.set_len(n) };
        Ok(())
    }
}

impl Sides<'_> {
    /// The point of end `which` of `piece`, rounded once from its features.
    fn point(&self, piece: &Piece, which: usize, normals: &mut Normals) -> Point {
        let ta = self.a.0.triangles()[piece.triangle_a as usize];
        let tb = self.b.0.triangles()[piece.triangle_b as usize];
        end_point_kept(
            &Self::corners(self.a, ta),
            &Self::corners(self.b, tb),
            piece.features[which],
            (piece.triangle_a, piece.triangle_b),
            normals,
        )
    }

    /// Each name's point, computed once from its group's first end (every end of a group is the
    /// same exact point, so any would round to the same bits), written to every piece end of the
    /// group; on up to `threads` threads.
    fn points_all(&self, work: &mut CurveWork, threads: usize) -> Result<()> {
        let CurveWork {
            pieces,
            ends,
            groups,
            group_points,
            ..
        } = work;
        let n = groups.len().saturating_sub(1);
        group_points.clear();
        group_points
            .try_reserve(n)
            .map_err(|_| Error::OutOfMemory {
                bytes: n * std::mem::size_of::<Point>(),
            })?;
        // In name order, so that the points of one plane come one after another.
        let first = |g: usize, normals: &mut Normals| {
            let e = end_index(ends[groups[g] as usize].1);
            self.point(&pieces[(e / 2) as usize], (e % 2) as usize, normals)
        };
        if threads <= 1 || n < PARALLEL_MIN_PAIRS {
            let mut normals = Normals::default();
            group_points.extend((0..n).map(|g| first(g, &mut normals)));
        } else {
            let size = n.div_ceil(threads * SHARES_PER_THREAD);
            let shares: Vec<(usize, &mut [MaybeUninit<Point>])> = group_points.spare_capacity_mut()
                [..n]
                .chunks_mut(size)
                .enumerate()
                .map(|(k, to)| (k * size, to))
                .collect();
            threads::in_turns(threads::Step::Crossings, threads, shares, &|(from, to)| {
                let mut normals = Normals::default();
                for (k, slot) in to.iter_mut().enumerate() {
                    slot.write(first(from + k, &mut normals));
                }
            });
            // SAFETY: the shares cover the first `n` slots, and each wrote every slot of its
            // own (a panic in one would have unwound past this line).
            unsafe { group_points.set_len(n) };
        }
        for (g, point) in group_points.iter().enumerate() {
            for &(_, e) in &ends[groups[g] as usize..groups[g + 1] as usize] {
                let e = end_index(e);
                pieces[(e / 2) as usize].points[(e % 2) as usize] = *point;
            }
        }
        Ok(())
    }
}

/// From the intersecting pairs in `out.work.pairs` to the curves in `out`.
fn finish(
    sides: &Sides,
    options: &QueryOptions,
    mut stats: QueryStats,
    out: &mut Curves,
) -> Result<QueryStats> {
    let Curves {
        result,
        spare,
        work,
    } = out;
    sides.found_all(
        work.pairs.as_slice(),
        threads::resolve(options.threads),
        &mut work.found,
    )?;
    let n = work.found.len();
    work.pieces.clear();
    work.pieces.try_reserve(n).map_err(|_| Error::OutOfMemory {
        bytes: n * std::mem::size_of::<Piece>(),
    })?;
    let mut degenerate = 0;
    for f in &work.found {
        match f {
            Found::Piece(p) => work.pieces.push(*p),
            Found::Degenerate(_) => degenerate += 1,
        }
    }
    let threads = threads::resolve(options.threads);
    link(work);
    sides.points_all(work, threads)?;
    chain(work, spare)?;
    spare
        .degenerate
        .try_reserve(degenerate)
        .map_err(|_| Error::OutOfMemory {
            bytes: degenerate * std::mem::size_of::<DegeneratePair>(),
        })?;
    spare
        .degenerate
        .extend(work.found.iter().filter_map(|f| match f {
            Found::Degenerate(d) => Some(*d),
            Found::Piece(_) => None,
        }));
    spare.one_mesh = sides.one_mesh;
    std::mem::swap(result, spare);
    stats.pairs = (result.segments.len() + result.degenerate.len()) as u64;
    Ok(stats)
}
