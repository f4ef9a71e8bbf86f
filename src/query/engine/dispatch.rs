//! The run of a query: checks the options and poses, puts each mesh in the query's frame, types
//! both sides by placement and volume kind, runs the traversal with the narrow phase the mode
//! asks for (on the calling thread or shared out), and sorts the result.

use super::parallel::{Descend, Finish, Job, share_out};
use super::query_traits::{Reach, TriangleTest};
use super::side::View;
use super::side::{
    LazyBoxVolumes, Local, MeshVolumes, MixedVolumes, Placement, Posed, Typed, with_node_volumes,
};
use super::sink::{Sink, Stop};
use super::sort::sort_pairs;
use super::terminal::{Coarse, Exact, LeafPairs, LeastPairs, NodePairs, Terminal};
use super::traverse::{OneMesh, best_first, key_pair, least_first, pair_key};
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

/// A query of two meshes, each in place or posed, in any mode: `test` asks what of their
/// triangle pairs (intersection, nearness). With `LAZY`, either mesh may have boxes refit lazily
/// (deformable scene objects); without, neither has, and no traversal of lazy boxes is
/// compiled for the query.
pub(crate) fn query<'m, T: TriangleTest<'m>, const LAZY: bool>(
    a: QueryMesh<'m>,
    b: QueryMesh<'m>,
    test: T,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    debug_assert!(LAZY || (a.2.is_none() && b.2.is_none()));
    run_query(a, Some(b), AnyMode::<T, LAZY>(test), options, out)
}

/// The least pair `(a, b)`, in `(a, b)` order, of triangles of meshes `a` and `b` (each in
/// place or posed) that `test` accepts, as the only pair of `out` (none when `test` accepts
/// none): the first pair of the query of every pair, found without finding the rest, on the
/// calling thread. `bound`, a pair `test` accepts (a first hit), prunes from the start.
pub(crate) fn least_pair<'m, T: TriangleTest<'m>>(
    a: (&'m Mesh, Option<&'m Pose>),
    b: (&'m Mesh, Option<&'m Pose>),
    test: T,
    bound: Option<Pair>,
    out: &mut Pairs,
) -> Result<QueryStats> {
    debug_assert!(test.own().is_none());
    let options = QueryOptions::default().with_threads(1);
    let (a, b) = ((a.0, a.1, None), (b.0, b.1, None));
    run_query(a, Some(b), LeastOf { test, bound }, &options, out)
}

/// A query of one mesh against itself (no pose, boxes refit), in any mode: `test` asks what of
/// its triangle pairs.
pub(crate) fn query_one<'m, T: TriangleTest<'m>>(
    mesh: &'m Mesh,
    test: T,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    debug_assert!(test.own().is_some());
    run_query(
        (mesh, None, None),
        None,
        AnyMode::<T, false>(test),
        options,
        out,
    )
}

/// The node pairs of a coarse mode ([`QueryMode::reports_nodes`]) whose volumes, as `reach`
/// sees them, overlap: of meshes `a` and `b`, each in place or posed, or of `a` against itself
/// (`b` is `None`; then `reach` says so). What a query on primitive pairs starts from.
pub(crate) fn node_pairs<'m, R: Reach<'m>>(
    a: QueryMesh<'m>,
    b: Option<QueryMesh<'m>>,
    reach: R,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    debug_assert_eq!(b.is_none(), reach.own().is_some());
    debug_assert!(a.2.is_none() && b.is_none_or(|b| b.2.is_none()));
    run_query(a, b, NodesOf::<R, true>(reach), options, out)
}

/// The leaf pairs ([`QueryMode::Leaves`]) of meshes `a` and `b` in place (or of `a` against
/// itself) whose volumes, as `reach` sees them, overlap; `threads` as
/// [`QueryOptions::threads`].
pub(crate) fn leaf_pairs<'m, R: Reach<'m>>(
    a: &'m Mesh,
    b: Option<&'m Mesh>,
    reach: R,
    threads: u32,
    out: &mut Pairs,
) -> Result<QueryStats> {
    debug_assert_eq!(b.is_none(), reach.own().is_some());
    let options = QueryOptions::with_mode(QueryMode::Leaves).with_threads(threads);
    let (a, b) = ((a, None, None), b.map(|b| (b, None, None)));
    run_query(a, b, NodesOf::<R, false>(reach), &options, out)
}

/// What a query runs once its sides are typed, and which sides it can have: a side that cannot
/// be posed or lazy is never typed so, and no traversal is compiled for it.
trait Work<'m>: Copy {
    type Reach: Reach<'m>;
    /// May a side be posed?
    const POSED: bool;
    /// May a side have boxes refit lazily?
    const LAZY: bool;

    fn reach(&self) -> Self::Reach;
    /// Runs the query on the typed sides.
    fn run<A: Typed<'m>, B: Typed<'m>>(self, run: Run<'_, 'm>, a: A, b: B) -> (Option<Stop>, bool);
}

/// A query with a triangle test, in the mode its options ask for.
#[derive(Clone, Copy)]
struct AnyMode<T, const LAZY: bool>(T);

impl<'m, T: TriangleTest<'m>, const LAZY: bool> Work<'m> for AnyMode<T, LAZY> {
    type Reach = T;
    const POSED: bool = true;
    const LAZY: bool = LAZY;

    fn reach(&self) -> T {
        self.0
    }

    fn run<A: Typed<'m>, B: Typed<'m>>(self, run: Run<'_, 'm>, a: A, b: B) -> (Option<Stop>, bool) {
        match run.mode {
            mode if mode.reports_nodes() => run.node_pairs(a, b),
            _ => {
                let check_domain = run.check_domain;
                run.run(
                    a,
                    b,
                    Exact {
                        test: self.0,
                        check_domain,
                    },
                )
            }
        }
    }
}

/// The least pair a triangle test accepts ([`least_pair`]).
#[derive(Clone, Copy)]
struct LeastOf<T> {
    test: T,
    bound: Option<Pair>,
}

impl<'m, T: TriangleTest<'m>> Work<'m> for LeastOf<T> {
    type Reach = T;
    const POSED: bool = true;
    const LAZY: bool = false;

    fn reach(&self) -> T {
        self.test
    }

    fn run<A: Typed<'m>, B: Typed<'m>>(self, run: Run<'_, 'm>, a: A, b: B) -> (Option<Stop>, bool) {
        run.least_first(a, b, self.test, self.bound)
    }
}

/// A query of node pairs only, of meshes that may be posed, or are in place.
#[derive(Clone, Copy)]
struct NodesOf<R, const POSED: bool>(R);

impl<'m, R: Reach<'m>, const POSED: bool> Work<'m> for NodesOf<R, POSED> {
    type Reach = R;
    const POSED: bool = POSED;
    const LAZY: bool = false;

    fn reach(&self) -> R {
        self.0
    }

    fn run<A: Typed<'m>, B: Typed<'m>>(self, run: Run<'_, 'm>, a: A, b: B) -> (Option<Stop>, bool) {
        debug_assert!(run.mode.reports_nodes());
        run.node_pairs(a, b)
    }
}

/// A query of `a` and `b`, or of `a` against itself (`b` is `None`).
fn run_query<'m, W: Work<'m>>(
    (a, pose_a, lazy_a): QueryMesh<'m>,
    b_side: Option<QueryMesh<'m>>,
    work: W,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    let one_mesh = b_side.is_none();
    let (b, pose_b, lazy_b) = b_side.unwrap_or((a, None, None));
    debug_assert!(lazy_a.is_none() || pose_a.is_none());
    debug_assert!(lazy_b.is_none() || pose_b.is_none());
    debug_assert!(W::LAZY || (lazy_a.is_none() && lazy_b.is_none()));
    debug_assert!(W::POSED || (pose_a.is_none() && pose_b.is_none()));
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
            max_depth: options.mode.max_depth(),
            own: work.reach().own(),
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
            mixed: lazy_b.is_none() && a.volumes().kind() != b.volumes().kind(),
            run,
            work,
        };
        let side_a = |kind| work.reach().side_a(kind);
        match (pose_a.zip(place_a), lazy_a) {
            // One mesh: both sides are it, in place, with its own volumes.
            _ if one_mesh => {
                let SideB { run, work, .. } = b_side;
                with_node_volumes!(a, |kind| work.run(
                    run,
                    (Local { mesh: a }, work.reach().side_a(kind)),
                    (Local { mesh: a }, kind)
                ))
            }
            (None, Some(boxes)) if W::LAZY => with_any_b(
                (Local { mesh: a }, side_a(LazyBoxVolumes { boxes })),
                SideB {
                    mixed: false,
                    ..b_side
                },
            ),
            (Some((pose, (stretch, pad))), _) if W::POSED => with_volumes_a(
                Posed {
                    mesh: a,
                    pose,
                    stretch,
                    pad,
                },
                b_side,
            ),
            _ => with_volumes_a(Local { mesh: a }, b_side),
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
struct Run<'q, 'm> {
    mode: QueryMode,
    /// The depth at which nodes are no longer opened.
    max_depth: u32,
    /// `Some` when both sides are one mesh.
    own: Option<OneMesh<'m>>,
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

impl<'m> Run<'_, 'm> {
    /// Runs the query, handing terminal pairs to `terminal`; returns why it stopped early, if it
    /// did, and whether the pairs are sorted already.
    fn run<A: Typed<'m>, B: Typed<'m>, N: Terminal<'m>>(
        self,
        a: A,
        b: B,
        terminal: N,
    ) -> (Option<Stop>, bool) {
        let job = Job {
            a,
            b,
            max_depth: self.max_depth,
            terminal,
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
            return share_out(&job, ws, threads, finish, self.stats);
        }
        let w = &mut ws.workers[0];
        let mut sink = Sink::new(self.out, self.limit);
        if let Some(stop) = job.begin(&mut w.a, &mut w.b) {
            return (Some(stop), false);
        }
        w.stats = QueryStats::default();
        job.traverse(w, None, &mut sink);
        self.stats.add(&w.stats);
        (sink.stop, false)
    }

    /// Runs a query of a coarse mode: under its budget of volume tests, or to the end.
    fn node_pairs<A: Typed<'m>, B: Typed<'m>>(self, a: A, b: B) -> (Option<Stop>, bool) {
        match self.mode {
            QueryMode::Budget(budget) => self.best_first(a, b, budget),
            _ => {
                let own = self.own;
                self.run(a, b, Coarse { own })
            }
        }
    }

    /// Runs [`least_pair`]'s search, on the calling thread: the least pair `test` accepts below
    /// `bound`, or `bound`, as the only pair of the result.
    fn least_first<A: Typed<'m>, B: Typed<'m>, T: TriangleTest<'m>>(
        self,
        a: A,
        b: B,
        test: T,
        bound: Option<Pair>,
    ) -> (Option<Stop>, bool) {
        let check_domain = self.check_domain;
        let job = Job {
            a,
            b,
            max_depth: self.max_depth,
            terminal: Exact { test, check_domain },
            limit: usize::MAX,
        };
        let Workspace { workers, queue, .. } = self.workspace;
        if workers.is_empty() {
            workers.push(Worker::default());
        }
        let Worker { a: wa, b: wb, .. } = &mut workers[0];
        let mut sink = Sink::new(self.out, usize::MAX);
        if let Some(stop) = job.begin(wa, wb) {
            return (Some(stop), false);
        }
        let (mut va, mut vb) = (
            View::new(job.a, &mut wa.world, &mut wa.ring_boxes),
            View::new(job.b, &mut wb.world, &mut wb.ring_boxes),
        );
        let least = (
            job.a.place().mesh().least_triangles(),
            job.b.place().mesh().least_triangles(),
        );
        let mut narrow = LeastPairs {
            leaves: LeafPairs {
                test,
                sink: &mut sink,
                rings_a: &mut wa.rings,
                rings_b: &mut wb.rings,
                check_domain,
            },
            least: bound.map_or(u64::MAX, pair_key),
        };
        least_first(&mut va, &mut vb, least, queue, self.stats, &mut narrow);
        let least = narrow.least;
        if sink.stop.is_none() && least != u64::MAX {
            sink.out.push(key_pair(least));
        }
        (sink.stop, false)
    }

    /// Runs the query under a budget of volume tests ([`QueryMode::Budget`]), on the calling
    /// thread, reporting node pairs.
    fn best_first<A: Typed<'m>, B: Typed<'m>>(
        self,
        a: A,
        b: B,
        budget: u64,
    ) -> (Option<Stop>, bool) {
        let job = Job {
            a,
            b,
            max_depth: self.max_depth,
            terminal: Coarse { own: self.own },
            limit: self.limit,
        };
        let ws = self.workspace;
        if ws.workers.is_empty() {
            ws.workers.push(Worker::default());
        }
        let w = &mut ws.workers[0];
        let mut sink = Sink::new(self.out, self.limit);
        if let Some(stop) = job.begin(&mut w.a, &mut w.b) {
            return (Some(stop), false);
        }
        let (mut va, mut vb) = job.views(&mut w.a, &mut w.b);
        let own = self.own;
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
        (sink.stop, false)
    }
}

/// Mesh `b` of the query, not yet typed, and the query to run once it is.
struct SideB<'m, 'q, W> {
    mesh: &'m Mesh,
    pose: Option<(&'m Pose, (f64, f64))>,
    lazy: Option<&'m LazyBoxes<'m>>,
    /// Are the volumes of `a` and `b` (not lazy) of different kinds?
    mixed: bool,
    run: Run<'q, 'm>,
    work: W,
}

/// Types side `a` by its volume kind (as the query reads it: [`MixedVolumes`] when `b`'s kind
/// differs), then side `b`.
fn with_volumes_a<'m, P: Placement<'m>, W: Work<'m>>(
    place: P,
    b: SideB<'m, '_, W>,
) -> (Option<Stop>, bool) {
    let reach = b.work.reach();
    let mesh = place.mesh();
    if b.mixed {
        let kind = MixedVolumes::of(mesh).expect("every kind is mixed");
        return with_placement_b((place, reach.side_a(kind)), b, kind);
    }
    with_node_volumes!(mesh, |kind| with_placement_b(
        (place, reach.side_a(kind)),
        b,
        kind
    ))
}

/// Types side `b` by its placement; its volumes are of kind `K`, as side `a`'s, unless they are
/// refit lazily.
fn with_placement_b<'m, A: Typed<'m>, K: MeshVolumes<'m>, W: Work<'m>>(
    a: A,
    b: SideB<'m, '_, W>,
    _: K,
) -> (Option<Stop>, bool) {
    let SideB {
        mesh,
        pose,
        lazy,
        run,
        work,
        ..
    } = b;
    match (pose, lazy) {
        (None, Some(boxes)) if W::LAZY => {
            work.run(run, a, (Local { mesh }, LazyBoxVolumes { boxes }))
        }
        (Some((pose, (stretch, pad))), _) if W::POSED => with_volumes_b::<_, _, K, _>(
            a,
            Posed {
                mesh,
                pose,
                stretch,
                pad,
            },
            run,
            work,
        ),
        _ => with_volumes_b::<_, _, K, _>(a, Local { mesh }, run, work),
    }
}

/// Types side `b` by its volume kind, `K`, and runs the query.
fn with_volumes_b<'m, A: Typed<'m>, P: Placement<'m>, K: MeshVolumes<'m>, W: Work<'m>>(
    a: A,
    place: P,
    run: Run<'_, 'm>,
    work: W,
) -> (Option<Stop>, bool) {
    let kind = K::of(place.mesh()).expect("side b's volumes are of side a's kind");
    work.run(run, a, (place, kind))
}

/// Types side `b` of a query whose side `a` is refit lazily: by its placement, then its volume
/// kind, whichever it is.
fn with_any_b<'m, A: Typed<'m>, W: Work<'m>>(a: A, b: SideB<'m, '_, W>) -> (Option<Stop>, bool) {
    let mesh = b.mesh;
    with_node_volumes!(mesh, |kind| with_placement_b(a, b, kind))
}
