//! The pair query's entry point: checks the options and poses, puts each mesh in the query's
//! frame, runs the traversal with the narrow phase the mode asks for, and sorts the result.

use super::narrow::{NodePairs, TrianglePairs};
use super::options::{QueryMode, QueryOptions};
use super::pairs::{PairKind, Pairs, QueryStats};
use super::side::{Boxes, FreeSpheres, Local, Placement, Posed, QuerySide, VertexSpheres, View};
use super::sink::{Sink, Stop};
use super::sort::sort_pairs;
use super::traverse::{best_first, depth_first};
use super::workspace::{GatheredRing, Queued, SideSpace, Stamped, Workspace};
use crate::error::{Error, Result, Side};
use crate::geometry::MAX_POSED_MAGNITUDE;
use crate::geometry::aabb::Aabb;
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;
use crate::volume::Volumes;
use std::collections::BinaryHeap;

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
/// Errors: [`Error::ZeroBudget`] for [`QueryMode::Budget`]`(0)`; [`Error::PoseOutOfRange`] when
/// a pose could move coordinates beyond [`MAX_POSED_MAGNITUDE`]; [`Error::OutOfMemory`] when the
/// result cannot grow (set [`QueryOptions::max_pairs`] to bound it). On error `out` still holds
/// the previous result.
///
/// Cost: proportional to the volume pairs visited plus the triangle pairs tested; allocates
/// nothing once `out` has grown to the scene's needs.
pub fn collide(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    if options.mode == QueryMode::Budget(0) {
        return Err(Error::ZeroBudget);
    }
    let pose_a = pose_a.filter(|p| !p.is_identity());
    let pose_b = pose_b.filter(|p| !p.is_identity());
    let place_a = pose_a.map(|p| widening(p, a, Side::A)).transpose()?;
    let place_b = pose_b.map(|p| widening(p, b, Side::B)).transpose()?;

    let Pairs {
        items,
        spare,
        kind,
        workspace,
    } = out;
    let Workspace {
        stack,
        queue,
        a: space_a,
        b: space_b,
        sort_counts,
    } = workspace;
    space_a.begin(a.vertex_count(), a.ring_count(), pose_a.is_some());
    space_b.begin(b.vertex_count(), b.ring_count(), pose_b.is_some());
    spare.clear();
    let limit = match options.mode {
        QueryMode::FirstHit => 1,
        _ => usize::MAX,
    };
    let mut sink = Sink {
        out: spare,
        limit: options.max_pairs.map_or(limit, |m| m.min(limit)),
        stop: None,
    };
    let mut stats = QueryStats::default();
    if sink.limit == 0 {
        sink.stop = Some(Stop::Limit);
    } else {
        let SideSpace {
            world: world_a,
            ring_boxes: boxes_a,
            ring: ring_a,
        } = space_a;
        let SideSpace {
            world: world_b,
            ring_boxes: boxes_b,
            ring: ring_b,
        } = space_b;
        let run = Run {
            mode: options.mode,
            check_domain: !(a.safe && b.safe) || pose_a.is_some() || pose_b.is_some(),
            sink: &mut sink,
            stats: &mut stats,
            stack,
            queue,
            ring_a,
            ring_b,
        };
        let b_side = SideB {
            mesh: b,
            pose: pose_b.zip(place_b),
            world: world_b,
            ring_boxes: boxes_b,
            run,
        };
        match pose_a.zip(place_a) {
            None => with_volumes_a(Local { mesh: a }, boxes_a, b_side),
            Some((pose, (stretch, pad))) => with_volumes_a(
                Posed {
                    mesh: a,
                    pose,
                    cache: world_a,
                    stretch,
                    pad,
                },
                boxes_a,
                b_side,
            ),
        }
    }
    match sink.stop {
        Some(Stop::OutOfMemory { bytes }) => return Err(Error::OutOfMemory { bytes }),
        Some(Stop::Limit) => stats.truncated = options.mode != QueryMode::FirstHit,
        None => {}
    }
    let nodes = options.mode.reports_nodes();
    // The previous result is no longer needed: it serves as the sort's scratch space.
    let b_count = if nodes {
        b.node_count()
    } else {
        b.triangle_count()
    };
    sort_pairs(spare, items, sort_counts, b_count as u64);
    spare.dedup();
    std::mem::swap(items, spare);
    *kind = if nodes {
        PairKind::Nodes
    } else {
        PairKind::Triangles
    };
    stats.pairs = items.len() as u64;
    stats.nodes_refit = a.last_refit.nodes_refit + b.last_refit.nodes_refit;
    Ok(stats)
}

/// How much to widen a posed mesh's volumes: the rotation's stretch (spheres), and twice the
/// rounding bound of the transformation (vertex and volume are each off by at most that much).
fn widening(pose: &Pose, mesh: &Mesh, side: Side) -> Result<(f64, f64)> {
    let (error, magnitude) = pose.rounding_bound(mesh.max_abs);
    let in_range = magnitude <= MAX_POSED_MAGNITUDE;
    if !in_range {
        return Err(Error::PoseOutOfRange {
            side,
            bound: magnitude,
        });
    }
    Ok((pose.stretch(), 2.0 * error))
}

/// The query once both sides are typed: the traversal and narrow phase the mode asks for.
struct Run<'q, 'w> {
    mode: QueryMode,
    check_domain: bool,
    sink: &'q mut Sink<'w>,
    stats: &'q mut QueryStats,
    stack: &'q mut Vec<(u32, u32)>,
    queue: &'q mut BinaryHeap<Queued>,
    ring_a: &'q mut GatheredRing,
    ring_b: &'q mut GatheredRing,
}

impl Run<'_, '_> {
    fn run<'m, A: QuerySide<'m>, B: QuerySide<'m>>(self, a: &mut A, b: &mut B) {
        let stats = self.stats;
        match self.mode {
            QueryMode::Triangles | QueryMode::FirstHit => {
                let mut narrow = TrianglePairs {
                    sink: self.sink,
                    ring_a: self.ring_a,
                    ring_b: self.ring_b,
                    check_domain: self.check_domain,
                };
                depth_first(a, b, u32::MAX, self.stack, stats, &mut narrow);
            }
            QueryMode::Leaves | QueryMode::Depth(_) => {
                let max_depth = match self.mode {
                    QueryMode::Depth(d) => d,
                    _ => u32::MAX,
                };
                let mut narrow = NodePairs { sink: self.sink };
                depth_first(a, b, max_depth, self.stack, stats, &mut narrow);
            }
            QueryMode::Budget(budget) => {
                let mut narrow = NodePairs { sink: self.sink };
                best_first(a, b, budget, self.queue, stats, &mut narrow);
            }
        }
    }
}

/// Mesh `b` of the query, not yet typed, and the query to run once it is.
struct SideB<'m, 'w, 'q> {
    mesh: &'m Mesh,
    pose: Option<(&'m Pose, (f64, f64))>,
    world: &'w mut Stamped<Point>,
    ring_boxes: &'w mut Stamped<Aabb>,
    run: Run<'q, 'w>,
}

/// Types side `a` by its volume kind, then side `b`.
fn with_volumes_a<'m, P: Placement<'m>>(
    place: P,
    ring_boxes: &mut Stamped<Aabb>,
    b: SideB<'m, '_, '_>,
) {
    match &place.mesh().volumes {
        Volumes::Dvh {
            centre_vertex,
            spheres,
        } => {
            let kind = VertexSpheres {
                centre_vertex,
                spheres,
            };
            with_placement_b(
                View {
                    place,
                    kind,
                    ring_boxes,
                },
                b,
            )
        }
        Volumes::Sbv { spheres, .. } => with_placement_b(
            View {
                place,
                kind: FreeSpheres { spheres },
                ring_boxes,
            },
            b,
        ),
        Volumes::Aabb { boxes } => with_placement_b(
            View {
                place,
                kind: Boxes { boxes },
                ring_boxes,
            },
            b,
        ),
    }
}

/// Types side `b` by its placement.
fn with_placement_b<'m, A: QuerySide<'m>>(mut a: A, b: SideB<'m, '_, '_>) {
    let SideB {
        mesh,
        pose,
        world,
        ring_boxes,
        run,
    } = b;
    match pose {
        None => with_volumes_b(&mut a, Local { mesh }, ring_boxes, run),
        Some((pose, (stretch, pad))) => with_volumes_b(
            &mut a,
            Posed {
                mesh,
                pose,
                cache: world,
                stretch,
                pad,
            },
            ring_boxes,
            run,
        ),
    }
}

/// Types side `b` by its volume kind and runs the query.
fn with_volumes_b<'m, A: QuerySide<'m>, P: Placement<'m>>(
    a: &mut A,
    place: P,
    ring_boxes: &mut Stamped<Aabb>,
    run: Run<'_, '_>,
) {
    match &place.mesh().volumes {
        Volumes::Dvh {
            centre_vertex,
            spheres,
        } => {
            let kind = VertexSpheres {
                centre_vertex,
                spheres,
            };
            run.run(
                a,
                &mut View {
                    place,
                    kind,
                    ring_boxes,
                },
            )
        }
        Volumes::Sbv { spheres, .. } => run.run(
            a,
            &mut View {
                place,
                kind: FreeSpheres { spheres },
                ring_boxes,
            },
        ),
        Volumes::Aabb { boxes } => run.run(
            a,
            &mut View {
                place,
                kind: Boxes { boxes },
                ring_boxes,
            },
        ),
    }
}
