//! The pair query: two hierarchies traversed together from their roots.

use super::options::{QueryMode, QueryOptions};
use super::pairs::{Pair, PairKind, Pairs, QueryStats};
use super::sort::sort_pairs;
use super::workspace::{Gathered, GatheredRing, Stamped, Workspace};
use crate::error::{Error, Result, Side};
use crate::geometry::MAX_POSED_MAGNITUDE;
use crate::geometry::pose::Pose;
use crate::geometry::predicates::{Point, is_safe_point};
use crate::geometry::sphere::overlap;
use crate::geometry::tri_tri::{triangles_intersect, triangles_intersect_safe};
use crate::mesh::Mesh;

/// Finds what intersects between mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b`
/// (`None`: the mesh's coordinates are world coordinates), as [`QueryOptions::mode`] asks.
///
/// The result replaces the contents of `out`: pairs `(index in a, index in b)`, sorted and
/// without duplicates, of triangles or of nodes according to [`Pairs::kind`]. The counters are
/// returned.
///
/// With poses, triangles are tested at the world coordinates [`Pose::transform_point`] computes
/// (lazily, only for vertices the traversal reaches), so the answer is exactly that of a brute
/// force over those coordinates; spheres are widened by a bound on the rounding of the
/// transformation so that none is dropped.
///
/// Errors: [`Error::PoseOutOfRange`] when a pose could move coordinates beyond
/// [`MAX_POSED_MAGNITUDE`]; [`Error::OutOfMemory`] when the result cannot grow (set
/// [`QueryOptions::max_pairs`] to bound it). On error `out` still holds the previous result.
///
/// Cost: proportional to the sphere pairs visited plus the triangle pairs tested; allocates
/// nothing once `out` has grown to the scene's needs.
pub fn collide(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    let pose_a = pose_a.filter(|p| !p.is_identity());
    let pose_b = pose_b.filter(|p| !p.is_identity());
    let widen_a = pose_a.map(|p| widening(p, a, Side::A)).transpose()?;
    let widen_b = pose_b.map(|p| widening(p, b, Side::B)).transpose()?;

    let Pairs {
        items,
        spare,
        kind,
        workspace,
    } = out;
    let Workspace {
        stack,
        world_a,
        world_b,
        boxes_a,
        boxes_b,
        ring_a,
        ring_b,
    } = workspace;
    boxes_a.begin(a.ring_count());
    boxes_b.begin(b.ring_count());
    ring_a.ring = u32::MAX;
    ring_b.ring = u32::MAX;
    spare.clear();
    let limit = match options.mode {
        QueryMode::FirstHit => 1,
        _ => usize::MAX,
    };
    let mut ctx = Ctx {
        sink: Sink {
            out: spare,
            limit: options.max_pairs.map_or(limit, |m| m.min(limit)),
            stop: None,
        },
        mode: options.mode,
        max_depth: match options.mode {
            QueryMode::Depth(d) => d,
            _ => u32::MAX,
        },
        check_domain: !(a.safe && b.safe) || pose_a.is_some() || pose_b.is_some(),
        stats: QueryStats::default(),
        stack,
        boxes_a,
        boxes_b,
        ring_a,
        ring_b,
    };
    let local_a = || Local { mesh: a };
    let local_b = || Local { mesh: b };
    match (pose_a.zip(widen_a), pose_b.zip(widen_b)) {
        (None, None) => traverse(&mut local_a(), &mut local_b(), a, b, &mut ctx),
        (Some((pa, wa)), None) => traverse(
            &mut posed(a, pa, wa, world_a),
            &mut local_b(),
            a,
            b,
            &mut ctx,
        ),
        (None, Some((pb, wb))) => traverse(
            &mut local_a(),
            &mut posed(b, pb, wb, world_b),
            a,
            b,
            &mut ctx,
        ),
        (Some((pa, wa)), Some((pb, wb))) => {
            let mut fa = posed(a, pa, wa, world_a);
            let mut fb = posed(b, pb, wb, world_b);
            traverse(&mut fa, &mut fb, a, b, &mut ctx)
        }
    }
    let mut stats = ctx.stats;
    match ctx.sink.stop {
        Some(Stop::OutOfMemory { bytes }) => return Err(Error::OutOfMemory { bytes }),
        Some(Stop::Limit) => stats.truncated = options.mode != QueryMode::FirstHit,
        None => {}
    }
    // The previous result is no longer needed: it serves as the sort's scratch space.
    let b_count = match options.mode {
        QueryMode::Triangles | QueryMode::FirstHit => b.triangle_count(),
        QueryMode::Leaves | QueryMode::Depth(_) => b.node_count(),
    };
    sort_pairs(spare, items, b_count as u64);
    spare.dedup();
    std::mem::swap(items, spare);
    *kind = match options.mode {
        QueryMode::Triangles | QueryMode::FirstHit => PairKind::Triangles,
        QueryMode::Leaves | QueryMode::Depth(_) => PairKind::Nodes,
    };
    stats.pairs = items.len() as u64;
    stats.nodes_refit = a.last_refit.nodes_refit + b.last_refit.nodes_refit;
    Ok(stats)
}

fn posed<'m, 'w>(
    mesh: &'m Mesh,
    pose: &'m Pose,
    (stretch, pad): (f64, f64),
    cache: &'w mut Stamped<Point>,
) -> Posed<'m, 'w> {
    cache.begin(mesh.vertex_count());
    Posed {
        mesh,
        pose,
        cache,
        stretch,
        pad,
    }
}

/// How much to widen a posed mesh's spheres: the rotation's stretch, and twice the rounding
/// bound of the transformation (vertex and centre are each off by at most that much).
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

/// A mesh in the query's common frame.
trait Frame {
    fn vertex(&mut self, v: u32) -> Point;
    fn centre(&mut self, node: u32) -> Point;
    fn radius(&self, node: u32) -> f64;
}

/// A mesh whose coordinates are world coordinates.
struct Local<'m> {
    mesh: &'m Mesh,
}

impl Frame for Local<'_> {
    #[inline(always)]
    fn vertex(&mut self, v: u32) -> Point {
        self.mesh.positions[v as usize]
    }

    #[inline(always)]
    fn centre(&mut self, node: u32) -> Point {
        self.mesh.nodes[node as usize].centre
    }

    #[inline(always)]
    fn radius(&self, node: u32) -> f64 {
        self.mesh.nodes[node as usize].radius
    }
}

/// A mesh moved by a pose; world positions are computed on first use within a query.
struct Posed<'m, 'w> {
    mesh: &'m Mesh,
    pose: &'m Pose,
    cache: &'w mut Stamped<Point>,
    stretch: f64,
    pad: f64,
}

impl Frame for Posed<'_, '_> {
    #[inline(always)]
    fn vertex(&mut self, v: u32) -> Point {
        let (pose, positions) = (self.pose, &self.mesh.positions);
        self.cache
            .get_or(v as usize, || pose.transform_point(&positions[v as usize]))
    }

    #[inline(always)]
    fn centre(&mut self, node: u32) -> Point {
        self.vertex(self.mesh.nodes[node as usize].centre_vertex)
    }

    #[inline(always)]
    fn radius(&self, node: u32) -> f64 {
        self.mesh.nodes[node as usize].radius * self.stretch + self.pad
    }
}

/// Why a traversal stopped early.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stop {
    /// As many pairs as asked for.
    Limit,
    /// The result could not grow.
    OutOfMemory { bytes: usize },
}

/// Where pairs go.
struct Sink<'w> {
    out: &'w mut Vec<Pair>,
    /// Pairs to find before stopping.
    limit: usize,
    stop: Option<Stop>,
}

struct Ctx<'w> {
    sink: Sink<'w>,
    mode: QueryMode,
    max_depth: u32,
    /// Must each triangle pair check that its coordinates suit the fast predicates?
    check_domain: bool,
    stats: QueryStats,
    stack: &'w mut Vec<(u32, u32)>,
    boxes_a: &'w mut Stamped<[Point; 2]>,
    boxes_b: &'w mut Stamped<[Point; 2]>,
    ring_a: &'w mut GatheredRing,
    ring_b: &'w mut GatheredRing,
}

impl Sink<'_> {
    /// Records a pair; returns whether the traversal must stop. The result grows fallibly, so
    /// that a pathological input (say every triangle at one point) ends in an error, not an abort.
    #[inline]
    fn report(&mut self, pair: Pair) -> bool {
        if self.out.len() == self.out.capacity() {
            let extra = self.out.capacity().max(256);
            if self.out.try_reserve(extra).is_err() {
                let bytes = (self.out.capacity() + extra) * std::mem::size_of::<Pair>();
                self.stop = Some(Stop::OutOfMemory { bytes });
                return true;
            }
        }
        self.out.push(pair);
        if self.out.len() >= self.limit {
            self.stop = Some(Stop::Limit);
            return true;
        }
        false
    }
}

/// Depth-first over overlapping node pairs; a child pair is tested before it is pushed.
/// Overlapping pairs descend the node with the larger sphere (a node that cannot descend never
/// is); on equal radii both descend, so that the traversal with `a` and `b` swapped visits the
/// mirrored pairs and the coarse modes are symmetric.
fn traverse<A: Frame, B: Frame>(fa: &mut A, fb: &mut B, ma: &Mesh, mb: &Mesh, ctx: &mut Ctx) {
    ctx.stack.clear();
    ctx.stats.bv_tests += 1;
    if ctx.sink.limit == 0 {
        ctx.sink.stop = Some(Stop::Limit);
        return;
    }
    if !overlap(&fa.centre(0), fa.radius(0), &fb.centre(0), fb.radius(0)) {
        return;
    }
    ctx.stack.push((0, 0));
    while let Some((na, nb)) = ctx.stack.pop() {
        let node_a = &ma.nodes[na as usize];
        let node_b = &mb.nodes[nb as usize];
        let end_a = node_a.is_leaf() || node_a.depth >= ctx.max_depth;
        let end_b = node_b.is_leaf() || node_b.depth >= ctx.max_depth;
        if end_a && end_b {
            ctx.stats.leaf_pairs += 1;
            let stop = match ctx.mode {
                QueryMode::Leaves | QueryMode::Depth(_) => ctx.sink.report(Pair { a: na, b: nb }),
                QueryMode::Triangles | QueryMode::FirstHit => {
                    ring_pair(fa, fb, ma, mb, node_a.ring_start, node_b.ring_start, ctx)
                }
            };
            if stop {
                return;
            }
            continue;
        }
        let (ra, rb) = (fa.radius(na), fb.radius(nb));
        if end_a || (!end_b && rb > ra) {
            let ca = fa.centre(na);
            for ch in node_b.children() {
                ctx.stats.bv_tests += 1;
                if overlap(&ca, ra, &fb.centre(ch), fb.radius(ch)) {
                    ctx.stack.push((na, ch));
                }
            }
        } else if end_b || ra > rb {
            let cb = fb.centre(nb);
            for ch in node_a.children() {
                ctx.stats.bv_tests += 1;
                if overlap(&fa.centre(ch), fa.radius(ch), &cb, rb) {
                    ctx.stack.push((ch, nb));
                }
            }
        } else {
            for x in node_a.children() {
                let (cx, rx) = (fa.centre(x), fa.radius(x));
                for y in node_b.children() {
                    ctx.stats.bv_tests += 1;
                    if overlap(&cx, rx, &fb.centre(y), fb.radius(y)) {
                        ctx.stack.push((x, y));
                    }
                }
            }
        }
    }
}

/// Collects ring `r`'s triangles in the frame, with their boxes, unless already held.
fn gather<F: Frame>(
    frame: &mut F,
    mesh: &Mesh,
    r: u32,
    into: &mut GatheredRing,
    check_domain: bool,
) {
    if into.ring == r {
        return;
    }
    into.ring = r;
    into.tris.clear();
    into.lo = [f64::INFINITY; 3];
    into.hi = [f64::NEG_INFINITY; 3];
    let r = r as usize;
    let range = mesh.ring_tri_start[r] as usize..mesh.ring_tri_start[r + 1] as usize;
    for (&t, &[i, j, k]) in mesh.ring_tris[range.clone()]
        .iter()
        .zip(&mesh.ring_corners[range])
    {
        let corners = [frame.vertex(i), frame.vertex(j), frame.vertex(k)];
        let mut lo = corners[0];
        let mut hi = corners[0];
        for c in &corners[1..] {
            for a in 0..3 {
                lo[a] = lo[a].min(c[a]);
                hi[a] = hi[a].max(c[a]);
            }
        }
        for a in 0..3 {
            into.lo[a] = into.lo[a].min(lo[a]);
            into.hi[a] = into.hi[a].max(hi[a]);
        }
        let safe = !check_domain || corners.iter().all(is_safe_point);
        into.tris.push(Gathered {
            index: t,
            corners,
            lo,
            hi,
            safe,
        });
    }
}

/// The box of ring `r`'s vertices in the frame, computed on first use in the query. Exact: the
/// extremes of the coordinates the triangle test will see.
fn ring_box<F: Frame>(
    frame: &mut F,
    mesh: &Mesh,
    r: u32,
    boxes: &mut Stamped<[Point; 2]>,
) -> [Point; 2] {
    boxes.get_or(r as usize, || {
        let r = r as usize;
        let c = frame.vertex(mesh.ring_centre[r]);
        let (mut lo, mut hi) = (c, c);
        for &v in
            &mesh.ring_verts[mesh.ring_vert_start[r] as usize..mesh.ring_vert_start[r + 1] as usize]
        {
            let p = frame.vertex(v);
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        [lo, hi]
    })
}

#[inline(always)]
fn boxes_apart(lo1: &Point, hi1: &Point, lo2: &Point, hi2: &Point) -> bool {
    (0..3).any(|k| hi1[k] < lo2[k] || hi2[k] < lo1[k])
}

/// Marks the triangles of `ring` whose boxes meet the box `(lo, hi)`.
fn select(ring: &mut GatheredRing, lo: &Point, hi: &Point) {
    ring.selected.clear();
    for (i, t) in ring.tris.iter().enumerate() {
        if !boxes_apart(&t.lo, &t.hi, lo, hi) {
            ring.selected.push(i as u32);
        }
    }
}

/// Triangles of ring `ra` against those of ring `rb`. Boxes of exact coordinates are an exact
/// filter (first each triangle against the other ring's box, then pair by pair); the exact test
/// decides the rest. Returns whether to stop.
fn ring_pair<A: Frame, B: Frame>(
    fa: &mut A,
    fb: &mut B,
    ma: &Mesh,
    mb: &Mesh,
    ra: u32,
    rb: u32,
    ctx: &mut Ctx,
) -> bool {
    let size =
        |m: &Mesh, r: u32| (m.ring_tri_start[r as usize + 1] - m.ring_tri_start[r as usize]) as u64;
    ctx.stats.triangle_candidates += size(ma, ra) * size(mb, rb);
    // Most overlapping leaf spheres hold rings whose boxes are apart (about 70% on scanned
    // meshes): ring boxes, computed once per ring and query, settle them before any triangle is
    // gathered.
    let [la, ha] = ring_box(fa, ma, ra, ctx.boxes_a);
    let [lb, hb] = ring_box(fb, mb, rb, ctx.boxes_b);
    if boxes_apart(&la, &ha, &lb, &hb) {
        return false;
    }
    gather(fa, ma, ra, ctx.ring_a, ctx.check_domain);
    gather(fb, mb, rb, ctx.ring_b, ctx.check_domain);
    let (ga, gb) = (&mut *ctx.ring_a, &mut *ctx.ring_b);
    if boxes_apart(&ga.lo, &ga.hi, &gb.lo, &gb.hi) {
        return false;
    }
    select(ga, &gb.lo, &gb.hi);
    select(gb, &ga.lo, &ga.hi);
    for &i in &ga.selected {
        let ta = &ga.tris[i as usize];
        for &j in &gb.selected {
            let tb = &gb.tris[j as usize];
            if boxes_apart(&ta.lo, &ta.hi, &tb.lo, &tb.hi) {
                continue;
            }
            ctx.stats.triangle_tests += 1;
            let hit = if ta.safe && tb.safe {
                triangles_intersect_safe(&ta.corners, &tb.corners)
            } else {
                triangles_intersect(&ta.corners, &tb.corners)
            };
            if hit
                && ctx.sink.report(Pair {
                    a: ta.index,
                    b: tb.index,
                })
            {
                return true;
            }
        }
    }
    false
}
