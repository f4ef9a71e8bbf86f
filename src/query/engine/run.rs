//! The run of a query: checks the options and poses, puts each mesh in the query's frame, types
//! both sides by placement and volume kind, runs the traversal with the narrow phase the mode
//! asks for (on the calling thread or shared out), and sorts the result.

use super::narrow::{NodePairs, PairTest};
use super::parallel::{Finish, Job};
use super::side::{LazyBoxVolumes, Local, NodeVolumes, Placement, Posed, View, with_node_volumes};
use super::sink::{Sink, Stop};
use super::sort::sort_pairs;
use super::traverse::best_first;
use super::workspace::{Worker, Workspace};
use crate::error::{Error, Result, Side};
use crate::geometry::MAX_POSED_MAGNITUDE;
use crate::geometry::pose::Pose;
use crate::mesh::Mesh;
use crate::query::options::{QueryMode, QueryOptions};
use crate::query::pairs::{Pair, PairKind, Pairs, QueryStats};
use crate::threads;
use crate::volume::LazyBoxes;

/// A mesh of a query: where it is, and its boxes when they are refit lazily (then the mesh's
/// own volumes are not read, and there is no pose: only deformable scene objects are lazy).
pub(crate) type QueryMesh<'m> = (&'m Mesh, Option<&'m Pose>, Option<&'m LazyBoxes<'m>>);

/// A query of two meshes: `test` asks what of their triangle pairs (intersection, nearness).
pub(crate) fn query<'m, T: PairTest<'m>>(
    a: QueryMesh<'m>,
    b: QueryMesh<'m>,
    test: T,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    run_query(a, Some(b), test, options, out)
}

/// A query of one mesh against itself (no pose, boxes refit): `test` asks what of its
/// triangle pairs.
pub(crate) fn query_one<'m, T: PairTest<'m>>(
    mesh: &'m Mesh,
    test: T,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    debug_assert!(test.own().is_some());
    run_query((mesh, None, None), None, test, options, out)
}

/// A query of `a` and `b`, or of `a` against itself (`b` is `None`).
fn run_query<'m, T: PairTest<'m>>(
    (a, pose_a, lazy_a): QueryMesh<'m>,
    b_side: Option<QueryMesh<'m>>,
    test: T,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    let one_mesh = b_side.is_none();
    let (b, pose_b, lazy_b) = b_side.unwrap_or((a, None, None));
    debug_assert!(lazy_a.is_none() || pose_a.is_none());
    debug_assert!(lazy_b.is_none() || pose_b.is_none());
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
    let limit = match options.mode {
        QueryMode::FirstHit => 1,
        _ => usize::MAX,
    };
    let limit = options.max_pairs.map_or(limit, |m| m.min(limit));
    let mut stats = QueryStats::default();
    let small = a.triangle_count() + b.triangle_count() < PARALLEL_MIN_TRIANGLES;
    let threads = if small || matches!(options.mode, QueryMode::Budget(_)) {
        1
    } else {
        threads::resolve(options.threads)
    };
    let nodes = options.mode.reports_nodes();
    let (a_count, b_count) = if nodes {
        (a.node_count() as u64, b.node_count() as u64)
    } else {
        (a.triangle_count() as u64, b.triangle_count() as u64)
    };
    let (stop, sorted) = if limit == 0 {
        spare.clear();
        (Some(Stop::Limit), false)
    } else {
        let run = Run {
            mode: options.mode,
            test,
            check_domain: !(a.in_fast_range() && b.in_fast_range())
                || pose_a.is_some()
                || pose_b.is_some(),
            limit,
            threads,
            workspace,
            out: spare,
            scratch: items,
            a_count,
            b_count,
            stats: &mut stats,
        };
        let b_side = SideB {
            mesh: b,
            pose: pose_b.zip(place_b),
            lazy: lazy_b,
            run,
        };
        match (pose_a.zip(place_a), lazy_a) {
            // One mesh: both sides are it, in place, with its own volumes.
            _ if one_mesh => with_node_volumes!(a, |kind| b_side.run.run(
                (Local { mesh: a }, test.side_a(kind)),
                (Local { mesh: a }, kind)
            )),
            (None, Some(boxes)) => with_placement_b(
                (Local { mesh: a }, test.side_a(LazyBoxVolumes { boxes })),
                b_side,
            ),
            (None, None) => with_volumes_a(Local { mesh: a }, b_side),
            (Some((pose, (stretch, pad))), _) => with_volumes_a(
                Posed {
                    mesh: a,
                    pose,
                    stretch,
                    pad,
                },
                b_side,
            ),
        }
    };
    match stop {
        Some(Stop::OutOfMemory { bytes }) => return Err(Error::OutOfMemory { bytes }),
        Some(Stop::Limit) => stats.truncated = options.mode != QueryMode::FirstHit,
        None => {}
    }
    if !sorted {
        // The previous result is no longer needed: it serves as the sort's scratch space.
        sort_pairs(
            spare,
            items,
            &mut workspace.sort_counts,
            a_count,
            b_count,
            threads,
        );
    }
    spare.dedup();
    std::mem::swap(items, spare);
    *kind = if nodes {
        PairKind::Nodes
    } else {
        PairKind::Triangles
    };
    stats.pairs = items.len() as u64;
    stats.nodes_refit = a.last_refit().nodes_refit;
    if !one_mesh {
        stats.nodes_refit += b.last_refit().nodes_refit;
    }
    Ok(stats)
}

/// How much to widen a posed mesh's volumes: the rotation's stretch (spheres), and twice the
/// rounding bound of the transformation (vertex and volume are each off by at most that much).
fn widening(pose: &Pose, mesh: &Mesh, side: Side) -> Result<(f64, f64)> {
    let (error, magnitude) = pose.rounding_bound(mesh.max_abs_coordinate());
    let in_range = magnitude <= MAX_POSED_MAGNITUDE;
    if !in_range {
        return Err(Error::PoseOutOfRange {
            side,
            bound: magnitude,
        });
    }
    Ok((pose.stretch(), 2.0 * error))
}

/// The query once both sides are typed: the traversal and narrow phase the mode asks for, on
/// the calling thread or shared out.
struct Run<'q, T> {
    mode: QueryMode,
    test: T,
    check_domain: bool,
    /// Pairs to find before stopping.
    limit: usize,
    /// Threads to use: 1, or more for meshes large enough to share out.
    threads: usize,
    workspace: &'q mut Workspace,
    out: &'q mut Vec<Pair>,
    /// The previous result, scratch for a sort once the query is sure to succeed.
    scratch: &'q mut Vec<Pair>,
    /// Bounds on the pairs' first and second indices.
    a_count: u64,
    b_count: u64,
    stats: &'q mut QueryStats,
}

/// Below this many triangles in the two meshes together, a query runs on the calling thread:
/// handing work out costs more than it saves.
const PARALLEL_MIN_TRIANGLES: usize = 4096;

impl<'m, T: PairTest<'m>> Run<'_, T> {
    /// Runs the query; returns why it stopped early, if it did, and whether the pairs are
    /// sorted already.
    fn run<PA, KA, PB, KB>(self, a: (PA, KA), b: (PB, KB)) -> (Option<Stop>, bool)
    where
        PA: Placement<'m>,
        KA: NodeVolumes<'m>,
        PB: Placement<'m>,
        KB: NodeVolumes<'m>,
    {
        let job = Job {
            a,
            b,
            mode: self.mode,
            test: self.test,
            check_domain: self.check_domain,
            limit: self.limit,
        };
        let threads = self.threads;
        let ws = self.workspace;
        if ws.workers.len() < threads {
            ws.workers.resize_with(threads, Worker::default);
        }
        if threads > 1 {
            let finish = Finish {
                out: self.out,
                scratch: self.scratch,
                a_count: self.a_count,
                b_count: self.b_count,
            };
            return job.share_out(ws, threads, finish, self.stats);
        }
        let w = &mut ws.workers[0];
        self.out.clear();
        let mut sink = Sink {
            out: self.out,
            limit: self.limit,
            stop: None,
        };
        if let Some(stop) = job.begin(&mut w.a, &mut w.b) {
            return (Some(stop), false);
        }
        if let QueryMode::Budget(budget) = self.mode {
            let mut va = View::new(job.a, &mut w.a.world, &mut w.a.ring_boxes);
            let mut vb = View::new(job.b, &mut w.b.world, &mut w.b.ring_boxes);
            let own = job.test.own();
            let mut narrow = NodePairs {
                sink: &mut sink,
                one_mesh: own.is_some(),
            };
            best_first(
                &mut va,
                &mut vb,
                budget,
                own,
                &mut ws.queue,
                self.stats,
                &mut narrow,
            );
        } else {
            w.stats = QueryStats::default();
            job.traverse(w, None, &mut sink);
            self.stats.add(&w.stats);
        }
        (sink.stop, false)
    }
}

/// Mesh `b` of the query, not yet typed, and the query to run once it is.
struct SideB<'m, 'q, T> {
    mesh: &'m Mesh,
    pose: Option<(&'m Pose, (f64, f64))>,
    lazy: Option<&'m LazyBoxes<'m>>,
    run: Run<'q, T>,
}

/// Types side `a` by its volume kind (as the pair test reads it), then side `b`.
fn with_volumes_a<'m, P: Placement<'m>, T: PairTest<'m>>(
    place: P,
    b: SideB<'m, '_, T>,
) -> (Option<Stop>, bool) {
    let test = b.run.test;
    with_node_volumes!(place.mesh(), |kind| with_placement_b(
        (place, test.side_a(kind)),
        b
    ))
}

/// Types side `b` by its placement.
fn with_placement_b<'m, PA: Placement<'m>, KA: NodeVolumes<'m>, T: PairTest<'m>>(
    a: (PA, KA),
    b: SideB<'m, '_, T>,
) -> (Option<Stop>, bool) {
    let SideB {
        mesh,
        pose,
        lazy,
        run,
    } = b;
    match (pose, lazy) {
        (None, Some(boxes)) => run.run(a, (Local { mesh }, LazyBoxVolumes { boxes })),
        (None, None) => with_volumes_b(a, Local { mesh }, run),
        (Some((pose, (stretch, pad))), _) => with_volumes_b(
            a,
            Posed {
                mesh,
                pose,
                stretch,
                pad,
            },
            run,
        ),
    }
}

/// Types side `b` by its volume kind and runs the query.
fn with_volumes_b<'m, PA: Placement<'m>, KA: NodeVolumes<'m>, P: Placement<'m>, T: PairTest<'m>>(
    a: (PA, KA),
    place: P,
    run: Run<'_, T>,
) -> (Option<Stop>, bool) {
    with_node_volumes!(place.mesh(), |kind| run.run(a, (place, kind)))
}
