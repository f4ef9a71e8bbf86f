//! Which nodes of a mesh's tree cannot intersect themselves, for self-collision: an exact form of
//! the normal-cone test (Volino and Magnenat-Thalmann).
//!
//! A node's triangles form a patch. If the patch is a topological disk, every triangle of it
//! turns the same way when projected along one coordinate axis (its normal has a component of
//! one sign along that axis: an exact `orient2d` of the dropped-axis projection), and its
//! boundary loop projects to a simple polygon, then the projection is one to one on the patch
//! (the boundary winds once around every point inside it, so each has one preimage) and no two
//! triangles of the patch share a point they should not. Such a node's self-test is skipped.
//! The six signed axes stand in for a cone of normals: they are exact where a cone's axis and
//! angle would be rounded, and a patch whose normals lie within 45 degrees of some axis always
//! passes the first part.
//!
//! Two neighbouring nodes always have overlapping volumes (their patches share vertices), so
//! without more the traversal would follow every seam between them down to the leaves and test
//! each pair of neighbouring triangles there. The same argument closes the seams: when both
//! patches are disks glued along one path of their loops, their union is a disk, with a loop
//! made of the rest of the two, and it takes the same test ([`Patches::cannot_intersect_each_other`]).
//!
//! What depends on the shape (which nodes are disks, their loops, which seams glue) is found once
//! per shape; which way the triangles turn ([`Turns`], kept with the mesh until its positions
//! change) and the loops' simplicity are decided from the positions.

use crate::csr::Csr;
use crate::geometry::predicates::{Point, Sign, orient2d};
use crate::mesh::Mesh;
use std::collections::HashMap;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering::Relaxed};

/// The boundary loop of every node whose patch is a disk (an empty row for the others), and
/// what the test of two nodes' patches together needs.
#[derive(Debug, Default)]
pub(crate) struct Patches {
    loops: Csr<u32>,
    /// Per node, its loop's vertices in increasing order, each with its place in the loop.
    sorted: Csr<(u32, u32)>,
    /// Per node: is its patch a disk none of whose inner vertices is used by a triangle outside
    /// it? Only then is the union with a neighbour's patch a disk when their loops share a path.
    sealed: Vec<bool>,
}

impl Patches {
    /// The loops of `mesh`'s nodes.
    pub fn new(mesh: &Mesh) -> Patches {
        let tree = &mesh.shape.tree;
        let rings = &mesh.shape.rings.triangles;
        let tris = &mesh.shape.triangles;
        // How many triangles use each vertex.
        let mut uses = vec![0u32; mesh.positions.len()];
        for t in tris {
            for &v in t {
                uses[v as usize] += 1;
            }
        }
        let mut loops = Csr::with_capacity(tree.len(), 0);
        let mut sorted = Csr::with_capacity(tree.len(), 0);
        let mut sealed = Vec::with_capacity(tree.len());
        for node in &tree.nodes {
            let range = node.ring_start as usize..node.ring_end as usize;
            let own = rings.row_range(range);
            let patch = own.iter().map(|&t| tris[t as usize]);
            let mut is_sealed = false;
            if let Some(l) = disk_loop(patch.clone()) {
                is_sealed = seals(patch, &l, &uses);
                let mut by_vertex: Vec<(u32, u32)> =
                    l.iter().enumerate().map(|(i, &v)| (v, i as u32)).collect();
                by_vertex.sort_unstable();
                for v in l {
                    loops.push(v);
                }
                for e in by_vertex {
                    sorted.push(e);
                }
            }
            loops.end_row();
            sorted.end_row();
            sealed.push(is_sealed);
        }
        Patches {
            loops,
            sorted,
            sealed,
        }
    }

    /// Bytes held on the heap.
    pub fn heap_bytes(&self) -> usize {
        self.loops.heap_bytes() + self.sorted.heap_bytes() + crate::csr::heap_bytes(&self.sealed)
    }

    /// Can node `n`'s patch, at the mesh's positions, have no self-intersection? (`true` only
    /// when sure.)
    pub fn cannot_self_intersect(&self, mesh: &Mesh, n: u32) -> bool {
        let boundary = self.loops.row(n as usize);
        boundary.len() >= 3
            && projects_simply(&mesh.positions, mesh.turns.of(mesh, n), boundary, &[])
    }

    /// Can the patches of nodes `x` and `y` (different, neither below the other), at the mesh's
    /// positions, have no triangles that meet beyond what they share? (`true` only when sure.)
    ///
    /// When both patches are sealed disks whose loops share one path, walked in opposite
    /// directions, and nothing else, their union is a disk whose loop is the rest of the two
    /// loops; the union then takes [`Patches::cannot_self_intersect`]'s test. This closes the
    /// seams between neighbouring nodes, whose volumes always overlap.
    pub fn cannot_intersect_each_other(&self, mesh: &Mesh, x: u32, y: u32) -> bool {
        let (i, j) = (x as usize, y as usize);
        if !(self.sealed[i] && self.sealed[j]) {
            return false;
        }
        let axes = mesh.turns.of(mesh, x) | mesh.turns.of(mesh, y);
        if one_way_axes(axes) == 0 {
            return false;
        }
        let Some([from_x, from_y]) = self.glued(i, j) else {
            return false;
        };
        let [x0, x1] = stretch(self.loops.row(i), from_x);
        let [y0, y1] = stretch(self.loops.row(j), from_y);
        projects_simply(&mesh.positions, axes, x0, &[x1, y0, y1])
    }

    /// Where the union of the patches of `x` and `y` is a disk glued along one shared path (see
    /// [`Patches::cannot_intersect_each_other`]), its loop as two stretches: `(start, length)` in
    /// `x`'s loop (from the path's last vertex round to before its first) and in `y`'s (from the
    /// path's first vertex round to before its last). `None` otherwise, or when the path is
    /// longer than [`LONGEST_SEAM`] (the children's seams are shorter).
    fn glued(&self, x: usize, y: usize) -> Option<[(u32, u32); 2]> {
        let (m, k) = (self.loops.row_len(x), self.loops.row_len(y));
        // The shared vertices, with their places in both loops.
        let mut shared = [(0u32, 0u32); LONGEST_SEAM];
        let mut s = 0;
        let (sx, sy) = (self.sorted.row(x), self.sorted.row(y));
        let (mut i, mut j) = (0, 0);
        while i < sx.len() && j < sy.len() {
            match sx[i].0.cmp(&sy[j].0) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    if s == LONGEST_SEAM {
                        return None;
                    }
                    shared[s] = (sx[i].1, sy[j].1);
                    s += 1;
                    i += 1;
                    j += 1;
                }
            }
        }
        // A path of at least one edge, and each loop keeps a vertex of its own.
        if s < 2 || s >= m || s >= k {
            return None;
        }
        let shared = &mut shared[..s];
        shared.sort_unstable();
        // One run of consecutive places in x's loop (cyclically): exactly one gap, after `last`.
        let gap = |g: usize| (shared[g].0 as usize + 1) % m != shared[(g + 1) % s].0 as usize;
        let mut gaps = (0..s).filter(|&g| gap(g));
        let (Some(last), None) = (gaps.next(), gaps.next()) else {
            return None;
        };
        let first = (last + 1) % s;
        // Walked the other way in y's loop.
        let reversed = (0..s - 1).all(|r| {
            let (now, next) = (shared[(first + r) % s].1, shared[(first + r + 1) % s].1);
            (now as usize + k - 1) % k == next as usize
        });
        reversed.then(|| {
            let s = s as u32;
            [
                (shared[last].0, m as u32 - s + 1),
                (shared[first].1, k as u32 - s + 1),
            ]
        })
    }
}

/// The `(start, length)` stretch of the loop `l`, going round: at most two slices.
fn stretch(l: &[u32], (start, len): (u32, u32)) -> [&[u32]; 2] {
    let (tail, head) = l.split_at(start as usize);
    let a = head.len().min(len as usize);
    [&head[..a], &tail[..len as usize - a]]
}

/// Shared paths longer than this are not glued: such seams are between nodes large enough that
/// their children's seams are tested instead.
const LONGEST_SEAM: usize = 64;

/// Vertex `v` at `positions` without coordinate `drop`.
#[inline]
fn flat(positions: &[Point], v: u32, drop: usize) -> [f64; 2] {
    let p = positions[v as usize];
    [p[(drop + 1) % 3], p[(drop + 2) % 3]]
}

/// Does the loop made of `first` and then the stretches `rest` project to a simple polygon
/// along an axis on which every triangle of its patch turns one way (`axes`, as in [`Turns`])?
fn projects_simply(positions: &[Point], axes: u8, first: &[u32], rest: &[&[u32]]) -> bool {
    let one_way = one_way_axes(axes);
    SCRATCH.with_borrow_mut(|scratch| {
        (0..3).any(|drop| {
            if one_way & (1 << drop) == 0 {
                return false;
            }
            scratch.flat.clear();
            let all = std::iter::once(first).chain(rest.iter().copied()).flatten();
            scratch.flat.extend(all.map(|&v| flat(positions, v, drop)));
            let Scratch { flat, edges } = scratch;
            simple_polygon(flat, edges)
        })
    })
}

/// Room for [`projects_simply`], kept per thread so that the patch tests allocate nothing once
/// warm.
#[derive(Default)]
struct Scratch {
    flat: Vec<[f64; 2]>,
    edges: Vec<EdgeBox>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::default();
}

/// The axes (bit `k` for coordinate `k` left out) along which triangles whose turns are
/// `axes` all turn one strict way.
#[inline]
fn one_way_axes(axes: u8) -> u8 {
    (0..3)
        .filter(|k| matches!((axes >> (2 * k)) & 3, 1 | 2))
        .fold(0, |m, k| m | 1 << k)
}

/// Which way each node's triangles turn in the three coordinate projections, at the mesh's
/// current positions: the normal cones of the nodes, in the exact form the patch test needs.
/// Found on first need (a node from its children), kept until the positions change; nodes no
/// self query reaches cost nothing.
///
/// Per node a byte: two bits per left-out coordinate `k` (bits `2k`, `2k + 1`), `01` when every
/// triangle turns positively, `10` negatively, `11` when they differ or one is flat; the top bit
/// marks the byte as found. The bits of a union of nodes are the `|` of theirs.
#[derive(Debug, Default)]
pub(crate) struct Turns {
    /// Atomic so that queries on several threads share what they find; every thread writes the
    /// same value for a node, so relaxed order is enough.
    bits: OnceLock<Box<[AtomicU8]>>,
}

/// [`Turns`]'s mark of a found byte.
const FOUND: u8 = 0x80;

impl Clone for Turns {
    fn clone(&self) -> Turns {
        let copy = OnceLock::new();
        if let Some(bits) = self.bits.get() {
            let _ = copy.set(
                bits.iter()
                    .map(|b| AtomicU8::new(b.load(Relaxed)))
                    .collect(),
            );
        }
        Turns { bits: copy }
    }
}

impl Turns {
    /// Forgets everything found (the positions changed).
    pub fn clear(&mut self) {
        if let Some(bits) = self.bits.get_mut() {
            bits.iter_mut().for_each(|b| *b.get_mut() = 0);
        }
    }

    /// Bytes held on the heap.
    pub fn heap_bytes(&self) -> usize {
        self.bits.get().map_or(0, |b| b.len())
    }

    /// Node `n`'s turns (see [`Turns`]), without the mark.
    pub fn of(&self, mesh: &Mesh, n: u32) -> u8 {
        let bits = self.bits.get_or_init(|| {
            (0..mesh.shape.tree.len())
                .map(|_| AtomicU8::new(0))
                .collect()
        });
        self.find(bits, mesh, n) & !FOUND
    }

    fn find(&self, bits: &[AtomicU8], mesh: &Mesh, n: u32) -> u8 {
        let known = bits[n as usize].load(Relaxed);
        if known & FOUND != 0 {
            return known;
        }
        let node = &mesh.shape.tree.nodes[n as usize];
        let found = if node.is_leaf() {
            let tris = &mesh.shape.triangles;
            let own = mesh
                .shape
                .rings
                .triangles
                .row_range(node.ring_start as usize..node.ring_end as usize);
            own.iter().fold(FOUND, |acc, &t| {
                let [a, b, c] = tris[t as usize];
                (0..3).fold(acc, |acc, drop| {
                    let at = |v| flat(&mesh.positions, v, drop);
                    let bits = match orient2d(at(a), at(b), at(c)) {
                        1.. => 1,
                        ..0 => 2,
                        0 => 3,
                    };
                    acc | bits << (2 * drop)
                })
            })
        } else {
            node.children()
                .fold(FOUND, |acc, c| acc | self.find(bits, mesh, c))
        };
        bits[n as usize].store(found, Relaxed);
        found
    }
}

/// Does no triangle outside the patch `tris` (a disk with loop `boundary`) use one of its inner
/// vertices? `uses` counts the triangles of the whole mesh at each vertex.
fn seals(tris: impl Iterator<Item = [u32; 3]>, boundary: &[u32], uses: &[u32]) -> bool {
    let mut inner: HashMap<u32, u32> = HashMap::new();
    for t in tris {
        for v in t {
            *inner.entry(v).or_insert(0) += 1;
        }
    }
    for v in boundary {
        inner.remove(v);
    }
    inner.iter().all(|(&v, &count)| uses[v as usize] == count)
}

/// The boundary loop of the triangles `tris` if they form a topological disk: connected, every
/// edge used by one triangle (boundary) or two with opposite directions (interior), one boundary
/// loop through distinct vertices, and Euler characteristic 1.
fn disk_loop(tris: impl Iterator<Item = [u32; 3]> + Clone) -> Option<Vec<u32>> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    let mut faces = 0usize;
    for t in tris.clone() {
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            return None;
        }
        faces += 1;
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    if directed.values().any(|&c| c > 1) {
        return None; // an edge used twice the same way: not an oriented manifold
    }
    // Boundary edges: directed edges whose reverse is absent.
    let mut next: HashMap<u32, u32> = HashMap::new();
    let mut edges = 0usize;
    for &(a, b) in directed.keys() {
        if !directed.contains_key(&(b, a)) && next.insert(a, b).is_some() {
            return None; // two boundary edges leave one vertex: a pinch
        }
        edges += 1;
    }
    let interior = (edges - next.len()) / 2;
    let undirected = interior + next.len();
    let mut vertices: Vec<u32> = tris.flatten().collect();
    vertices.sort_unstable();
    vertices.dedup();
    if vertices.len() + faces != undirected + 1 || next.is_empty() {
        return None;
    }
    // One loop through every boundary edge.
    let &start = next.keys().min().expect("not empty");
    let mut l = vec![start];
    let mut v = next[&start];
    while v != start {
        if l.len() > next.len() {
            return None;
        }
        l.push(v);
        v = *next.get(&v)?;
    }
    if l.len() != next.len() {
        return None; // several loops: not a disk
    }
    // Connected: with one boundary loop and Euler characteristic 1, a surface of several
    // components would need a closed component of characteristic 0 or less beside a disk,
    // which the count above allows (a torus and a disk): check connectivity outright.
    connected(&directed, &vertices).then_some(l)
}

/// Are the vertices joined by the edges one component?
fn connected(directed: &HashMap<(u32, u32), u32>, vertices: &[u32]) -> bool {
    let index = |v: u32| vertices.binary_search(&v).expect("a vertex of the patch");
    let mut parent: Vec<usize> = (0..vertices.len()).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for &(a, b) in directed.keys() {
        let (ra, rb) = (root(&mut parent, index(a)), root(&mut parent, index(b)));
        parent[ra] = rb;
    }
    let r = root(&mut parent, 0);
    (0..vertices.len()).all(|x| root(&mut parent, x) == r)
}

/// Is the closed polygon `p` simple: no two edges meet except consecutive ones at their common
/// corner, and no corner turns back along its incoming edge? Exact.
fn simple_polygon(p: &[[f64; 2]], edges: &mut Vec<EdgeBox>) -> bool {
    // The loops of small patches are often monotone along an axis, which settles it in one pass.
    if let Some(simple) = monotone_simple(p, 0).or_else(|| monotone_simple(p, 1)) {
        return simple;
    }
    let m = p.len();
    let after = |i: usize| if i + 1 == m { 0 } else { i + 1 };
    for i in 0..m {
        let (a, b) = (p[i], p[after(i)]);
        if a == b {
            return false;
        }
        // The corner at b: the next edge must not fold back over this one.
        let c = p[after(after(i))];
        if (c == b || between(a, b, c) || between(b, c, a)) && orient2d(a, b, c) == 0 {
            return false;
        }
    }
    // Edges that are not consecutive must not meet at all. Their boxes, found once, settle
    // most pairs without a predicate.
    edges.clear();
    edges.extend((0..m).map(|i| EdgeBox::new(p[i], p[after(i)], i as u32)));
    let meet = |e: &EdgeBox, f: &EdgeBox| {
        let (i, j) = (e.index.min(f.index) as usize, e.index.max(f.index) as usize);
        let apart = j - i > 1 && !(i == 0 && j == m - 1);
        apart
            && e.lo[1] <= f.hi[1]
            && f.lo[1] <= e.hi[1]
            && segments_meet(p[i], p[after(i)], p[j], p[after(j)])
    };
    if m <= SMALL_LOOP {
        return !(0..m).any(|i| {
            let e = &edges[i];
            edges[i + 1..]
                .iter()
                .any(|f| e.lo[0] <= f.hi[0] && f.lo[0] <= e.hi[0] && meet(e, f))
        });
    }
    // A sweep along x: edges in order of their lower x, each tested only against the edges
    // after it whose lower x is within its span. Loops of patches cross most vertical lines a
    // few times, so this is about linear after the sort.
    edges.sort_unstable_by(|e, f| e.lo[0].total_cmp(&f.lo[0]));
    !(0..m).any(|s| {
        let e = &edges[s];
        edges[s + 1..]
            .iter()
            .take_while(|f| f.lo[0] <= e.hi[0])
            .any(|f| meet(e, f))
    })
}

/// An edge of a polygon, `index`, with its box.
#[derive(Clone, Copy, Debug)]
struct EdgeBox {
    lo: [f64; 2],
    hi: [f64; 2],
    index: u32,
}

impl EdgeBox {
    fn new(a: [f64; 2], b: [f64; 2], index: u32) -> EdgeBox {
        EdgeBox {
            lo: [a[0].min(b[0]), a[1].min(b[1])],
            hi: [a[0].max(b[0]), a[1].max(b[1])],
            index,
        }
    }
}

/// Is the closed polygon `p` simple, when it is strictly monotone along coordinate `k` (`None`
/// when it is not)? Exact.
///
/// Strictly monotone: from the corner with the least coordinate `k` to the one with the
/// greatest, both ways round, that coordinate strictly grows. The two chains are then graphs
/// over the axis, meeting at their ends, and the polygon is simple when one lies strictly on
/// one side of the other at every corner in between (between corners the gap is linear).
fn monotone_simple(p: &[[f64; 2]], k: usize) -> Option<bool> {
    let m = p.len();
    let (mut lo, mut hi) = (0, 0);
    for (i, q) in p.iter().enumerate() {
        if q[k] < p[lo][k] {
            lo = i;
        }
        if q[k] > p[hi][k] {
            hi = i;
        }
    }
    if p[lo][k] == p[hi][k] {
        return None;
    }
    let ahead = |i: usize| if i + 1 == m { 0 } else { i + 1 };
    let behind = |i: usize| if i == 0 { m - 1 } else { i - 1 };
    for forward in [true, false] {
        let mut i = lo;
        while i != hi {
            let j = if forward { ahead(i) } else { behind(i) };
            if p[j][k] <= p[i][k] {
                return None;
            }
            i = j;
        }
    }
    // Walk both chains together: each corner inside one chain against the edge of the other
    // chain over it. The sign of the turn from the forward chain's view is kept by both.
    let turn = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        let t = orient2d(a, b, c);
        if k == 0 { t } else { -t }
    };
    let (mut f, mut b) = (lo, lo);
    let mut side: Sign = 0;
    loop {
        let (fn_, bn) = (ahead(f), behind(b));
        if fn_ == hi && bn == hi {
            return Some(true);
        }
        // The chain whose next corner comes first: that corner against the other's edge.
        let forward_first = bn == hi || (fn_ != hi && p[fn_][k] <= p[bn][k]);
        let s = if forward_first {
            // Forward chain's corner against the backward chain's edge b -> bn.
            let s = turn(p[b], p[bn], p[fn_]);
            f = fn_;
            s
        } else {
            let s = -turn(p[f], p[fn_], p[bn]);
            b = bn;
            s
        };
        if s == 0 || (side != 0 && s != side) {
            return Some(false);
        }
        side = s;
    }
}

/// Loops up to this long are tested pair by pair (boxes first): cheaper than sorting.
const SMALL_LOOP: usize = 32;

/// Is `x` on the segment `[a, b]` (all three collinear)? Coordinates compared exactly.
fn between(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> bool {
    (0..2).all(|k| a[k].min(b[k]) <= x[k] && x[k] <= a[k].max(b[k]))
}

/// Do the closed segments `[a, b]` and `[c, d]` share a point? Exact.
#[inline]
fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (o1, o2) = (orient2d(a, b, c), orient2d(a, b, d));
    let (o3, o4) = (orient2d(c, d, a), orient2d(c, d, b));
    let opposite = |x: Sign, y: Sign| x * y <= 0;
    if o1 == 0 && o2 == 0 {
        // Collinear: overlapping projections on the line.
        return between(a, b, c) || between(a, b, d) || between(c, d, a) || between(c, d, b);
    }
    opposite(o1, o2) && opposite(o3, o4)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn simple_polygon_alone(p: &[[f64; 2]]) -> bool {
        simple_polygon(p, &mut Vec::new())
    }

    #[test]
    fn polygons() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(simple_polygon_alone(&square));
        let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(!simple_polygon_alone(&bow));
        // A corner that turns straight back along its edge.
        let spike = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(!simple_polygon_alone(&spike));
        // Touching at a corner.
        let pinch = [
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 1.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [1.0, 1.0],
        ];
        assert!(!simple_polygon_alone(&pinch));
        // Straight corners are fine.
        let straight = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0]];
        assert!(simple_polygon_alone(&straight));
        // Long loops (the grid of cells): a circle, and the same circle with one vertex pulled
        // out across the far side (its edges cross others), or onto another vertex (they touch).
        let circle: Vec<[f64; 2]> = (0..500)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 500.0;
                [a.cos(), a.sin()]
            })
            .collect();
        assert!(simple_polygon_alone(&circle));
        let mut crossed = circle.clone();
        crossed[100] = [-1.5, 0.0];
        assert!(!simple_polygon_alone(&crossed));
        let mut touching = circle.clone();
        touching[100] = circle[300];
        assert!(!simple_polygon_alone(&touching));
        // A figure-eight: simple but for one crossing in the middle.
        let eight: Vec<[f64; 2]> = (0..400)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 400.0;
                [a.sin(), a.sin() * a.cos()]
            })
            .collect();
        assert!(!simple_polygon_alone(&eight));
    }

    /// Every pair of edges, the definition of a simple polygon written out.
    fn simple_by_pairs(p: &[[f64; 2]]) -> bool {
        let m = p.len();
        let edge = |i: usize| (p[i], p[(i + 1) % m]);
        (0..m).all(|i| {
            let (a, b) = edge(i);
            let c = p[(i + 2) % m];
            let folds = orient2d(a, b, c) == 0 && (c == b || between(a, b, c) || between(b, c, a));
            a != b
                && !folds
                && (i + 2..m).all(|j| {
                    (i == 0 && j == m - 1) || {
                        let (c, d) = edge(j);
                        !segments_meet(a, b, c, d)
                    }
                })
        })
    }

    #[test]
    fn monotone_loops_agree_with_every_pair() {
        // Wobbly circles and random stars, of lengths past the pairwise threshold, on a coarse
        // lattice so that corners tie, touch and cross often.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut simple, mut monotone) = (0, 0);
        for trial in 0..4000 {
            let m = 13 + trial % 30;
            let p: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    let a = i as f64 * std::f64::consts::TAU / m as f64;
                    let r = match trial % 3 {
                        0 => 20.0 + (next() * 2.0).floor(),
                        1 => 6.0 + (next() * 6.0).floor(),
                        _ => 3.0 + (next() * 9.0).floor(),
                    };
                    [
                        (r * a.cos()).round(),
                        (r * a.sin() * (1.0 + 0.3 * next())).round(),
                    ]
                })
                .collect();
            let expected = simple_by_pairs(&p);
            assert_eq!(simple_polygon_alone(&p), expected, "{p:?}");
            for k in 0..2 {
                if let Some(answer) = monotone_simple(&p, k) {
                    monotone += 1;
                    assert_eq!(answer, expected, "{p:?} along {k}");
                }
            }
            simple += usize::from(expected);
        }
        // Both answers, and the monotone path, were exercised.
        assert!(simple > 400 && simple < 3800, "{simple}");
        assert!(monotone > 200, "{monotone}");
    }

    #[test]
    fn disks_and_others() {
        // Two triangles of a square: a disk with a loop of 4.
        let square = [[0, 1, 2], [0, 2, 3]];
        assert_eq!(disk_loop(square.iter().copied()).map(|l| l.len()), Some(4));
        // Inconsistent orientation: not taken.
        let flipped = [[0, 1, 2], [0, 3, 2]];
        assert!(disk_loop(flipped.iter().copied()).is_none());
        // Two triangles sharing a vertex only: a pinch.
        let bowtie = [[0, 1, 2], [0, 3, 4]];
        assert!(disk_loop(bowtie.iter().copied()).is_none());
        // Two separate triangles.
        let apart = [[0, 1, 2], [3, 4, 5]];
        assert!(disk_loop(apart.iter().copied()).is_none());
        // A closed surface (a tetrahedron) has no boundary.
        let tet = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        assert!(disk_loop(tet.iter().copied()).is_none());
    }
}
