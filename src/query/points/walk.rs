//! The walks of one mesh's hierarchy for one point: to the nearest triangle in floating point,
//! to every triangle within a distance decided exactly, and along the ray the winding number
//! counts. Each walk visits only the triangles a leaf owns, so every triangle is met once.

use crate::csr::Csr;
use crate::geometry::aabb::Aabb;
use crate::geometry::nearest::{
    Decided, Feature, Primitive, decide_within, point_triangle_estimate, point_triangle_within,
    segments_estimate, triangles_lower_along,
};
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::geometry::sphere::{Sphere, distance_squared, overlap};
use crate::mesh::Mesh;
use crate::query::primitives::{ImpactKind, Key};
use crate::tree::Node;
use crate::volume::Volumes;

/// The node volumes a walk reads: the mesh's own (in its coordinates, which are the world's),
/// or boxes of its placed vertices.
#[derive(Clone, Copy)]
enum Bounds<'q> {
    Boxes(&'q [Aabb]),
    Spheres(&'q [Sphere]),
}

/// Relative slack of the floating-point ray and distance tests of spheres: covers the rounding
/// of a squared distance (as [`Sphere::meets`]).
const SLACK: f64 = 1.0 + f64::EPSILON * 16.0;

impl Bounds<'_> {
    /// A lower bound of the squared distance from `p` to node `n`'s volume, in floating point
    /// (for the nearest-first order: no decision rests on it).
    #[inline]
    fn lower(&self, n: usize, p: &Point) -> f64 {
        match self {
            Bounds::Boxes(b) => box_gap_squared(&b[n], p),
            Bounds::Spheres(s) => {
                let d = distance_squared(&s[n].centre, p).sqrt() - s[n].radius;
                if d > 0.0 { d * d } else { 0.0 }
            }
        }
    }

    /// May node `n`'s volume hold a point within `d` of `p`? Never `false` when it does.
    #[inline]
    fn within(&self, n: usize, p: &Point, d: f64) -> bool {
        match self {
            Bounds::Boxes(b) => box_within(&b[n], p, d),
            Bounds::Spheres(s) => overlap(&s[n].centre, s[n].radius, p, d),
        }
    }

    /// May node `n`'s volume hold a point within `d` of `p`, given `key`, its
    /// [`Bounds::lower`] (which boxes reuse; spheres test again)? Never `false` when it does.
    #[inline]
    fn within_keyed(&self, n: usize, p: &Point, d: f64, key: f64) -> bool {
        match self {
            Bounds::Boxes(b) => gap_within(key, d) && b[n].within(&Aabb::point(p), d),
            Bounds::Spheres(s) => overlap(&s[n].centre, s[n].radius, p, d),
        }
    }

    /// May node `n`'s volume meet the ray from `p` along +x? Never `false` when it does.
    #[inline]
    fn meets_ray(&self, n: usize, p: &Point) -> bool {
        match self {
            Bounds::Boxes(b) => {
                let b = &b[n];
                b.hi[0] >= p[0] && b.lo[1] <= p[1] && p[1] <= b.hi[1] && b.lo[2] <= p[2] && {
                    p[2] <= b.hi[2]
                }
            }
            Bounds::Spheres(s) => {
                let (c, r) = (&s[n].centre, s[n].radius);
                let (dy, dz) = (c[1] - p[1], c[2] - p[2]);
                // The ray's closest point to the centre: its foot when ahead, else `p`.
                let off = if c[0] >= p[0] {
                    dy * dy + dz * dz
                } else {
                    distance_squared(c, p)
                };
                off <= r * r * SLACK
            }
        }
    }
}

/// May box `b` hold a point within `d` of `p`? Never `false` when it does: along every axis
/// (exact, as [`Aabb::within`]), then in Euclidean distance with a margin for every rounding.
/// The Euclidean test is what keeps the exact walk's triangles few: the axes alone admit a
/// cube around `p`, which for a point deep inside a closed surface holds most of it.
#[inline]
fn box_within(b: &Aabb, p: &Point, d: f64) -> bool {
    b.within(&Aabb::point(p), d) && gap_within(box_gap_squared(b, p), d)
}

/// May a box whose squared gap from a point is `gap` in floating point ([`box_gap_squared`])
/// hold a point within `d` of it? Never `false` when it does; always `true` where underflow or
/// overflow could hide a rounding (then the axes, [`Aabb::within`], decide alone).
#[inline]
fn gap_within(gap: f64, d: f64) -> bool {
    let dd = d * d;
    if !(1e-280..=1e280).contains(&dd) {
        return true;
    }
    // Each gap is one rounded subtraction (at most its exact value times 1 + eps), squared and
    // summed in four more roundings; `d d` one: 8 eps covers them, 1e-300 the underflow of
    // a gap's square below the smallest normal.
    gap * (1.0 - 8.0 * f64::EPSILON) - 1e-300 <= dd * (1.0 + 2.0 * f64::EPSILON)
}

/// The squared distance from `p` to box `b` (0 inside), in floating point.
#[inline]
fn box_gap_squared(b: &Aabb, p: &Point) -> f64 {
    box_gap_squared_boxes(b, &Aabb { lo: *p, hi: *p })
}

/// The squared distance between boxes `a` and `b` (0 where they meet), in floating point.
#[inline]
fn box_gap_squared_boxes(a: &Aabb, b: &Aabb) -> f64 {
    let mut d2 = 0.0;
    for (k, (lo, hi)) in a.lo.iter().zip(&a.hi).enumerate() {
        let gap = (lo - b.hi[k]).max(b.lo[k] - hi).max(0.0);
        d2 += gap * gap;
    }
    d2
}

/// A lower bound of the squared distance between node `na`'s volume in `a` and node `nb`'s in
/// `b`, in floating point (an order for the walk, no decision).
#[inline]
fn lower_between(a: &Bounds, na: usize, b: &Bounds, nb: usize) -> f64 {
    let gap = |d: f64| if d > 0.0 { d * d } else { 0.0 };
    match (a, b) {
        (Bounds::Boxes(x), Bounds::Boxes(y)) => box_gap_squared_boxes(&x[na], &y[nb]),
        (Bounds::Spheres(x), Bounds::Spheres(y)) => {
            let (s, t) = (&x[na], &y[nb]);
            gap(distance_squared(&s.centre, &t.centre).sqrt() - s.radius - t.radius)
        }
        (Bounds::Boxes(x), Bounds::Spheres(y)) => {
            gap(box_gap_squared(&x[na], &y[nb].centre).sqrt() - y[nb].radius)
        }
        (Bounds::Spheres(x), Bounds::Boxes(y)) => {
            gap(box_gap_squared(&y[nb], &x[na].centre).sqrt() - x[na].radius)
        }
    }
}

/// May node `na`'s volume in `a` and node `nb`'s in `b` hold points within `d` of each other?
/// Never `false` when they do (boxes as [`box_within`] tests a point; spheres with the sum of
/// the radii and `d` rounded up).
#[inline]
fn pair_within(a: &Bounds, na: usize, b: &Bounds, nb: usize, d: f64) -> bool {
    match (a, b) {
        (Bounds::Boxes(x), Bounds::Boxes(y)) => boxes_within(&x[na], &y[nb], d),
        (Bounds::Spheres(x), Bounds::Spheres(y)) => {
            let (s, t) = (&x[na], &y[nb]);
            overlap(&s.centre, s.radius, &t.centre, (t.radius + d).next_up())
        }
        (Bounds::Boxes(x), Bounds::Spheres(y)) => {
            box_within(&x[na], &y[nb].centre, (y[nb].radius + d).next_up())
        }
        (Bounds::Spheres(x), Bounds::Boxes(y)) => {
            box_within(&y[nb], &x[na].centre, (x[na].radius + d).next_up())
        }
    }
}

/// May boxes `a` and `b` hold points within `d` of each other? Never `false` when they do:
/// along every axis (exact), then in Euclidean distance with [`gap_within`]'s margin (each gap
/// one rounded subtraction, as from a point).
#[inline]
fn boxes_within(a: &Aabb, b: &Aabb, d: f64) -> bool {
    a.within(b, d) && gap_within(box_gap_squared_boxes(a, b), d)
}

/// The scratch of [`Frame::nearest_pair_kept`]: the node pairs still to visit and the triangle
/// pairs kept, `(triangle of the first mesh, of the second, lower bound of their distance)`.
#[derive(Debug, Default)]
pub(crate) struct PairScratch {
    nodes: Vec<(u32, u32, f64)>,
    /// The boxes of a leaf's triangles.
    boxes: Vec<Aabb>,
    /// The triangle pairs the last walk kept.
    pub kept: Vec<(u32, u32, f64)>,
}

/// What [`Frame::nearest_pair_kept`] found.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PairWalk {
    /// The primitive pair whose estimate was least, with its squared estimate.
    pub best: Option<(Key, f64)>,
    /// Every triangle pair within this distance was kept.
    pub reach: f64,
    /// Node volume pairs tested.
    pub volume_tests: u64,
}

/// What the walks read of one mesh, in world coordinates: its shape, its node volumes, its
/// vertices and triangles, and which triangles each leaf owns.
pub(crate) struct Frame<'q> {
    nodes: &'q [Node],
    bounds: Bounds<'q>,
    positions: &'q [Point],
    triangles: &'q [[u32; 3]],
    owned: &'q Csr<u32>,
}

/// A walk's scratch, the nodes still to visit, and the counters of the walks it served.
#[derive(Debug, Default)]
pub(crate) struct Stack {
    nodes: Vec<(u32, f64)>,
    /// Node volumes tested.
    pub volume_tests: u64,
    /// Triangles given to an exact test.
    pub triangle_tests: u64,
}

impl<'q> Frame<'q> {
    /// The frame of `mesh` in its own coordinates.
    pub fn own(mesh: &'q Mesh) -> Frame<'q> {
        let bounds = match mesh.volumes() {
            // A box per node when the mesh keeps one (SBV keeps its boxes beside its spheres):
            // tighter than a ball around a point, and cheaper.
            Volumes::Aabb { boxes } | Volumes::Sbv { boxes, .. } => Bounds::Boxes(boxes),
            Volumes::Dvh { spheres, .. } => Bounds::Spheres(spheres),
        };
        Frame {
            nodes: &mesh.tree().nodes,
            bounds,
            positions: mesh.positions(),
            triangles: mesh.triangles(),
            owned: &mesh.features().triangles,
        }
    }

    /// The frame of `mesh` placed by `pose`: its vertices transformed into `placed` (as
    /// [`Pose::transform_point`] computes them, the coordinates every exact decision uses) and
    /// exact boxes of them into `boxes`.
    pub fn placed(
        mesh: &'q Mesh,
        pose: &Pose,
        placed: &'q mut Vec<Point>,
        boxes: &'q mut Vec<Aabb>,
    ) -> Frame<'q> {
        placed.clear();
        placed.extend(mesh.positions().iter().map(|p| pose.transform_point(p)));
        let nodes = &mesh.tree().nodes;
        let owned = &mesh.features().triangles;
        let triangles = mesh.triangles();
        boxes.clear();
        boxes.resize(nodes.len(), Aabb::EMPTY);
        // Children come after their parents: a reverse sweep sees them first.
        for n in (0..nodes.len()).rev() {
            let node = &nodes[n];
            let mut b = Aabb::EMPTY;
            if node.is_leaf() {
                for &t in owned.row(node.ring_start as usize) {
                    for &v in &triangles[t as usize] {
                        b.grow(&placed[v as usize]);
                    }
                }
            } else {
                for c in node.children() {
                    b.merge(&boxes[c as usize]);
                }
            }
            boxes[n] = b;
        }
        Frame {
            nodes,
            bounds: Bounds::Boxes(boxes),
            positions: placed,
            triangles,
            owned,
        }
    }

    /// Vertex `v`.
    #[inline]
    pub fn vertex(&self, v: u32) -> Point {
        self.positions[v as usize]
    }

    /// Triangle `t`'s vertices.
    #[inline]
    pub fn triangle(&self, t: u32) -> [u32; 3] {
        self.triangles[t as usize]
    }

    /// Triangle `t`'s corners.
    #[inline]
    pub fn corners(&self, t: u32) -> [Point; 3] {
        self.triangles[t as usize].map(|v| self.positions[v as usize])
    }

    /// The owned triangles of leaf `node`.
    #[inline]
    fn leaf_triangles(&self, node: &Node) -> &'q [u32] {
        self.owned.row(node.ring_start as usize)
    }

    /// The triangle nearest `p` in floating point, and every triangle that may be as near,
    /// in one walk: a guess with its squared estimate, into `kept` (cleared first) each
    /// triangle not certainly beyond the reach when it was met, with a certain lower bound of
    /// its distance (`(triangle, bound)`; 0 for those the estimates put within), and the
    /// reach: every triangle within it of `p` is in `kept`, decided by certain bounds (of the
    /// nodes' volumes, the triangles' boxes and the separations along the estimates'
    /// directions), not by estimates.
    ///
    /// The reach starts at `bound` and shrinks to just above the best estimate's root as
    /// nearer triangles are met, through `shrink` (a tolerance's smaller radius, or the
    /// identity), so the exact decisions that follow take only the triangles it keeps when the
    /// guess's exact distance is within it (almost always: the estimate is within a few
    /// units in the last place of the exact distance but for degenerate triangles). `seed`, a
    /// triangle to start from (the previous point's answer), prunes from the start.
    pub fn nearest_kept(
        &self,
        p: &Point,
        bound: f64,
        seed: Option<u32>,
        shrink: impl Fn(f64) -> f64,
        stack: &mut Stack,
        kept: &mut Vec<(u32, f64)>,
    ) -> (Option<(u32, f64)>, f64) {
        kept.clear();
        let mut best: Option<(u32, f64)> = None;
        let mut reach = bound;
        let Stack {
            nodes: stack,
            volume_tests,
            ..
        } = stack;
        let mut meet = |t: u32, best: &mut Option<(u32, f64)>, reach: &mut f64| {
            let [a, b, c] = self.corners(t);
            // The triangle's box is a certain bound, and cheap: what it keeps is decided later.
            if !box_within(&Aabb::of_points([&a, &b, &c]), p, *reach) {
                return;
            }
            // Dropped where a certain bound puts it beyond the reach (the separation along
            // the estimate's own direction, nearly exact); kept otherwise, for the exact
            // decisions to settle.
            let Some((estimate, lower)) = point_triangle_within(p, &a, &b, &c, *reach) else {
                return;
            };
            kept.push((t, lower));
            // A NaN (a degenerate triangle's estimate) never wins.
            if estimate < best.map_or(f64::INFINITY, |b| b.1) {
                *best = Some((t, estimate));
                let near = (estimate.sqrt() * (1.0 + 1.0 / (1u64 << 20) as f64)).next_up();
                *reach = reach.min(shrink(near));
            }
        };
        if let Some(t) = seed {
            meet(t, &mut best, &mut reach);
        }
        stack.clear();
        stack.push((0, self.bounds.lower(0, p)));
        *volume_tests += 1;
        while let Some((n, key)) = stack.pop() {
            if !self.bounds.within_keyed(n as usize, p, reach, key) {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.is_leaf() {
                for &t in self.leaf_triangles(node) {
                    if Some(t) != seed {
                        meet(t, &mut best, &mut reach);
                    }
                }
                continue;
            }
            // Children pushed farthest first, so the nearest is opened first.
            let start = stack.len();
            for c in node.children() {
                *volume_tests += 1;
                let key = self.bounds.lower(c as usize, p);
                if self.bounds.within_keyed(c as usize, p, reach, key) {
                    stack.push((c, key));
                }
            }
            stack[start..].sort_unstable_by(|x, y| y.1.total_cmp(&x.1));
        }
        (best, reach)
    }

    /// The pair of a triangle of `self` and a triangle of `other` nearest each other in floating
    /// point, and every triangle pair that may be as near, in one walk of both hierarchies, as
    /// [`Frame::nearest_kept`] walks one for a point: the guess is the primitive pair
    /// (vertex-face, face-vertex or edge-edge: a key of [`crate::NearPair`]) whose estimate is
    /// least, with its squared estimate; into `kept` (cleared first) goes each triangle pair
    /// not certainly beyond the reach when it was met, with a certain lower bound of its
    /// distance; and the reach: every triangle pair within it is in `kept`, decided by certain
    /// bounds (of the nodes' volumes, the triangles' boxes and the separation along the pair's
    /// estimated direction), not by estimates. The reach starts at `bound` and shrinks through
    /// `shrink` to just above the best estimate's root.
    pub fn nearest_pair_kept(
        &self,
        other: &Frame,
        bound: f64,
        shrink: impl Fn(f64) -> f64,
        scratch: &mut PairScratch,
    ) -> PairWalk {
        let PairScratch {
            nodes: stack,
            boxes: boxes_b,
            kept,
        } = scratch;
        kept.clear();
        let mut walk = PairWalk {
            best: None,
            reach: bound,
            volume_tests: 1,
        };
        stack.clear();
        if !pair_within(&self.bounds, 0, &other.bounds, 0, bound) {
            return walk;
        }
        stack.push((0, 0, lower_between(&self.bounds, 0, &other.bounds, 0)));
        while let Some((na, nb, _)) = stack.pop() {
            if !pair_within(
                &self.bounds,
                na as usize,
                &other.bounds,
                nb as usize,
                walk.reach,
            ) {
                continue;
            }
            let (x, y) = (&self.nodes[na as usize], &other.nodes[nb as usize]);
            if x.is_leaf() && y.is_leaf() {
                let owned_b = other.leaf_triangles(y);
                boxes_b.clear();
                boxes_b.extend(owned_b.iter().map(|&t| {
                    let [a, b, c] = other.corners(t);
                    Aabb::of_points([&a, &b, &c])
                }));
                for &ta in self.leaf_triangles(x) {
                    let ca = self.corners(ta);
                    let box_a = Aabb::of_points([&ca[0], &ca[1], &ca[2]]);
                    for (&tb, box_b) in owned_b.iter().zip(boxes_b.iter()) {
                        if boxes_within(&box_a, box_b, walk.reach) {
                            self.meet_pair(other, (ta, &ca), tb, &mut walk, &shrink, kept);
                        }
                    }
                }
                continue;
            }
            // Open the side whose volume is larger (a leaf never), children farthest first.
            let open_a = !x.is_leaf()
                && (y.is_leaf() || x.ring_end - x.ring_start >= y.ring_end - y.ring_start);
            let start = stack.len();
            let reach = walk.reach;
            if open_a {
                for c in x.children() {
                    walk.volume_tests += 1;
                    if pair_within(&self.bounds, c as usize, &other.bounds, nb as usize, reach) {
                        let l = lower_between(&self.bounds, c as usize, &other.bounds, nb as usize);
                        stack.push((c, nb, l));
                    }
                }
            } else {
                for c in y.children() {
                    walk.volume_tests += 1;
                    if pair_within(&self.bounds, na as usize, &other.bounds, c as usize, reach) {
                        let l = lower_between(&self.bounds, na as usize, &other.bounds, c as usize);
                        stack.push((na, c, l));
                    }
                }
            }
            stack[start..].sort_unstable_by(|p, q| q.2.total_cmp(&p.2));
        }
        walk
    }

    /// Triangle `ta` of `self` (with its corners) and `tb` of `other`, met by
    /// [`Frame::nearest_pair_kept`]: kept unless certainly beyond the reach, and the guess if
    /// its estimate is the least yet.
    #[inline]
    fn meet_pair(
        &self,
        other: &Frame,
        (ta, pa): (u32, &[Point; 3]),
        tb: u32,
        walk: &mut PairWalk,
        shrink: &impl Fn(f64) -> f64,
        kept: &mut Vec<(u32, u32, f64)>,
    ) {
        let pb = other.corners(tb);
        let (key, estimate, u) = self.triangle_pair_estimate(other, (ta, pa), (tb, &pb));
        // The separation along the estimate's direction: nearly the exact distance.
        let lower = triangles_lower_along(pa, &pb, u);
        if lower > walk.reach {
            return;
        }
        kept.push((ta, tb, lower));
        // A NaN (a degenerate triangle's estimate) never wins.
        if estimate < walk.best.map_or(f64::INFINITY, |b| b.1) {
            walk.best = Some((key, estimate));
            let near = (estimate.sqrt() * (1.0 + 1.0 / (1u64 << 20) as f64)).next_up();
            walk.reach = walk.reach.min(shrink(near));
        }
    }

    /// The primitive pair of triangle `ta` of `self` and `tb` of `other` whose estimate is
    /// least: its key, its squared estimate and the direction from its closest point on `tb`
    /// to its closest point on `ta`.
    #[inline]
    fn triangle_pair_estimate(
        &self,
        other: &Frame,
        (ta, pa): (u32, &[Point; 3]),
        (tb, pb): (u32, &[Point; 3]),
    ) -> (Key, f64, Point) {
        let (ia, ib) = (self.triangle(ta), other.triangle(tb));
        // Where every estimate is NaN (degenerate triangles), an infinite estimate that never
        // wins and no direction (a lower bound of 0): the pair is kept for the exact decisions.
        let mut best: (Key, f64, Point) = (
            (ImpactKind::VertexFace, ia[0], 0, tb, 0),
            f64::INFINITY,
            [0.0; 3],
        );
        let mut keep = |key: Key, x: &Point, y: &Point| {
            let u = [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
            let d2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
            if d2 < best.1 {
                best = (key, d2, u);
            }
        };
        for k in 0..3 {
            let e = point_triangle_estimate(&pa[k], &pb[0], &pb[1], &pb[2]);
            keep((ImpactKind::VertexFace, ia[k], 0, tb, 0), &pa[k], &e);
            let e = point_triangle_estimate(&pb[k], &pa[0], &pa[1], &pa[2]);
            keep((ImpactKind::FaceVertex, ta, 0, ib[k], 0), &e, &pb[k]);
        }
        for i in 0..3 {
            let (u, v) = (ia[i], ia[(i + 1) % 3]);
            if u == v {
                continue;
            }
            for j in 0..3 {
                let (w, z) = (ib[j], ib[(j + 1) % 3]);
                if w == z {
                    continue;
                }
                let (x, y) = segments_estimate(&pa[i], &pa[(i + 1) % 3], &pb[j], &pb[(j + 1) % 3]);
                keep(
                    (ImpactKind::EdgeEdge, u.min(v), u.max(v), w.min(z), w.max(z)),
                    &x,
                    &y,
                );
            }
        }
        best
    }

    /// Every triangle within `d` of `p` (the closed triangles; touching counts), decided
    /// exactly, with where its closest point lies, into `out` (cleared first), in the order of
    /// the walk.
    pub fn within(&self, p: &Point, d: f64, stack: &mut Stack, out: &mut Vec<(u32, Decided)>) {
        out.clear();
        self.leaves(
            stack,
            |n| self.bounds.within(n, p, d),
            |t, triangle_tests| {
                let [a, b, c] = self.corners(t);
                if box_within(&Aabb::of_points([&a, &b, &c]), p, d) {
                    *triangle_tests += 1;
                    if let Some(decided) = decide_within(Primitive::VertexFace, &[*p, a, b, c], d) {
                        out.push((t, decided));
                    }
                }
                true
            },
        );
    }

    /// Of the triangles `kept` by [`Frame::nearest_kept`] (whose reach was at least `d`),
    /// every one within `d` of `p`, decided exactly, with where its closest point lies, into
    /// `out` (cleared first).
    pub fn kept_within(
        &self,
        p: &Point,
        d: f64,
        kept: &[(u32, f64)],
        stack: &mut Stack,
        out: &mut Vec<(u32, Decided)>,
    ) {
        out.clear();
        for &(t, lower) in kept {
            if lower > d {
                continue;
            }
            let [a, b, c] = self.corners(t);
            if !box_within(&Aabb::of_points([&a, &b, &c]), p, d) {
                continue;
            }
            stack.triangle_tests += 1;
            if let Some(decided) = decide_within(Primitive::VertexFace, &[*p, a, b, c], d) {
                out.push((t, decided));
            }
        }
    }

    /// Calls `visit` with every triangle whose leaf's volume (and every ancestor's) meets the
    /// ray from `p` along +x: a superset of the triangles the ray meets. Stops, returning
    /// `false`, as soon as `visit` does.
    pub fn along_ray(
        &self,
        p: &Point,
        stack: &mut Stack,
        mut visit: impl FnMut(u32) -> bool,
    ) -> bool {
        self.leaves(
            stack,
            |n| self.bounds.meets_ray(n, p),
            |t, triangle_tests| {
                *triangle_tests += 1;
                visit(t)
            },
        )
    }

    /// Walks the nodes whose volumes (and every ancestor's) pass `enter`, in depth-first order,
    /// calling `leaf` with each triangle of each leaf reached and the triangle-test counter.
    /// Stops, returning `false`, as soon as `leaf` does.
    fn leaves(
        &self,
        stack: &mut Stack,
        enter: impl Fn(usize) -> bool,
        mut leaf: impl FnMut(u32, &mut u64) -> bool,
    ) -> bool {
        let Stack {
            nodes: stack,
            volume_tests,
            triangle_tests,
        } = stack;
        stack.clear();
        stack.push((0, 0.0));
        while let Some((n, _)) = stack.pop() {
            *volume_tests += 1;
            if !enter(n as usize) {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.is_leaf() {
                for &t in self.leaf_triangles(node) {
                    if !leaf(t, triangle_tests) {
                        return false;
                    }
                }
                continue;
            }
            stack.extend(node.children().map(|c| (c, 0.0)));
        }
        true
    }
}

/// The mesh feature holding a closest point on a primitive at its feature `f`: a vertex, an
/// edge (its vertices, lower first) or a triangle. `corners` are the primitive's vertices (one, two
/// or a triangle's three), `face` the triangle's index.
pub(crate) fn mesh_feature(corners: &[u32], face: u32, f: Feature) -> [u32; 3] {
    let none = u32::MAX;
    match f {
        Feature::Vertex0 | Feature::Vertex1 | Feature::Vertex2 => [corners[f as usize], none, none],
        Feature::Interior => [none, none, face],
        edge => {
            let k = edge as usize - Feature::Edge01 as usize;
            let (u, v) = (corners[k], corners[(k + 1) % corners.len()]);
            [u.min(v), u.max(v), none]
        }
    }
}
