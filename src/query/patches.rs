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
    /// Per node: is it the first of exactly two children? Then it and the next node make up
    /// their parent's patch, and the traversal only meets the pair when the parent failed the
    /// same test.
    first_of_two: Vec<bool>,
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
        let mut first_of_two = vec![false; tree.len()];
        for node in &tree.nodes {
            if node.child_count == 2 {
                first_of_two[node.first_child as usize] = true;
            }
        }
        Patches {
            loops,
            sorted,
            sealed,
            first_of_two,
        }
    }

    /// Bytes held on the heap.
    pub fn heap_bytes(&self) -> usize {
        self.loops.heap_bytes()
            + self.sorted.heap_bytes()
            + crate::csr::heap_bytes(&self.sealed)
            + crate::csr::heap_bytes(&self.first_of_two)
    }

    /// Can node `n`'s patch, at the mesh's positions, have no self-intersection? (`true` only
    /// when sure.)
    pub fn cannot_self_intersect(&self, mesh: &Mesh, n: u32) -> bool {
        let boundary = self.loops.row(n as usize);
        boundary.len() >= 3
            && (mesh.turns.proved(n)
                || projects_simply(&mesh.positions, mesh.turns.of(mesh, n), boundary, &[]))
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
        let twins = (i.min(j) + 1 == i.max(j)) && self.first_of_two[i.min(j)];
        if twins || !(self.sealed[i] && self.sealed[j]) {
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
        let apart = projects_simply(&mesh.positions, axes, x0, &[x1, y0, y1]);
        if apart {
            // The union projects one to one, so each part does: their own tests are settled
            // (the traversal asks them after their pairs).
            mesh.turns.prove(x);
            mesh.turns.prove(y);
        }
        apart
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
            let Scratch { flat, polygon } = scratch;
            simple_polygon(flat, polygon)
        })
    })
}

/// Room for [`projects_simply`], kept per thread so that the patch tests allocate nothing once
/// warm.
#[derive(Default)]
struct Scratch {
    flat: Vec<[f64; 2]>,
    polygon: PolygonScratch,
}

/// Room for [`simple_polygon`].
#[derive(Default)]
struct PolygonScratch {
    edges: Vec<EdgeBox>,
    keys: Vec<(f64, f64)>,
    turns: Vec<u32>,
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
/// marks the byte as found. The bits of a union of nodes are the `|` of theirs. One more bit,
/// [`PROVED`], records that a union holding the node passed the patch test, which settles the
/// node's own test at these positions.
#[derive(Debug, Default)]
pub(crate) struct Turns {
    /// Atomic so that queries on several threads share what they find; every thread writes the
    /// same value for a node, so relaxed order is enough.
    bits: OnceLock<Box<[AtomicU8]>>,
}

/// [`Turns`]'s mark of a found byte.
const FOUND: u8 = 0x80;

/// [`Turns`]'s mark of a node proved free of self-intersection at the current positions.
const PROVED: u8 = 0x40;

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
        self.find(bits, mesh, n) & !(FOUND | PROVED)
    }

    /// Has node `n` been proved free of self-intersection (see [`Turns::prove`])?
    pub fn proved(&self, n: u32) -> bool {
        self.bits
            .get()
            .is_some_and(|bits| bits[n as usize].load(Relaxed) & PROVED != 0)
    }

    /// Records that node `n`'s patch cannot intersect itself at the current positions; its
    /// turns must be found already.
    pub fn prove(&self, n: u32) {
        if let Some(bits) = self.bits.get() {
            bits[n as usize].fetch_or(PROVED, Relaxed);
        }
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
                .fold(FOUND, |acc, c| acc | (self.find(bits, mesh, c) & !PROVED))
        };
        // `|`, not a store: another thread may have proved the node meanwhile.
        bits[n as usize].fetch_or(found, Relaxed);
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
fn simple_polygon(p: &[[f64; 2]], scratch: &mut PolygonScratch) -> bool {
    let PolygonScratch { edges, keys, turns } = scratch;
    // The loops of patches are mostly a few monotone pieces along some direction, which
    // settles it in a few passes.
    if let Some(simple) = monotone_pieces(p, keys, turns) {
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

/// Where [`monotone_pieces`] looks for a loop's pieces, as exact keys of a projected point: the
/// rounded value and Knuth's two-sum error, compared in lexicographic order (rounding to nearest
/// never reverses an order, and equal rounded values leave the errors to decide).
const KEY_DIRECTIONS: usize = 4;

/// Point `q`'s key along direction `d` of [`KEY_DIRECTIONS`]: `x`, `y`, `x + y`, `x - y`.
#[inline]
fn key(q: [f64; 2], d: usize) -> (f64, f64) {
    let (a, b) = match d {
        0 => return (q[0], 0.0),
        1 => return (q[1], 0.0),
        2 => (q[0], q[1]),
        _ => (q[0], -q[1]),
    };
    let s = a + b;
    let back = s - a;
    (s, (a - (s - back)) + (b - back))
}

/// Loops with more pieces than this are left to the sweep.
const MOST_PIECES: usize = 8;

/// Is the closed polygon `p` simple, decided from its pieces that are strictly monotone along
/// one direction (`None` when no direction of [`KEY_DIRECTIONS`] cuts it into at most
/// [`MOST_PIECES`] of them, or an edge is level in all)? Exact.
///
/// Cut at the corners where the key turns, the loop is a ring of pieces along each of which the
/// key strictly grows or falls: each piece is the graph of a function over the key, so it
/// cannot meet itself. Two pieces do not meet (but at the extreme corner that neighbours share)
/// exactly when, over the range of keys they share, one lies strictly to one side of the other;
/// the gap between them is linear between corners, so its sign at the corners of both decides.
/// A loop monotone along the direction is two pieces and one such walk.
fn monotone_pieces(
    p: &[[f64; 2]],
    keys: &mut Vec<(f64, f64)>,
    turns: &mut Vec<u32>,
) -> Option<bool> {
    let m = p.len();
    // The direction with the fewest pieces (two at best).
    let mut best: Option<(usize, usize)> = None;
    for d in 0..KEY_DIRECTIONS {
        keys.clear();
        keys.extend(p.iter().map(|&q| key(q, d)));
        if let Some(pieces) = count_turns(keys) {
            if best.is_none_or(|(_, b)| pieces < b) {
                best = Some((d, pieces));
            }
            if pieces == 2 {
                break;
            }
        }
    }
    let (d, pieces) = best?;
    if pieces > MOST_PIECES {
        return None;
    }
    keys.clear();
    keys.extend(p.iter().map(|&q| key(q, d)));
    turns.clear();
    let behind = |i: usize| if i == 0 { m - 1 } else { i - 1 };
    let ahead = |i: usize| if i + 1 == m { 0 } else { i + 1 };
    turns.extend((0..m as u32).filter(|&i| {
        let i = i as usize;
        below(keys[behind(i)], keys[i]) == below(keys[ahead(i)], keys[i])
    }));
    // Each piece as (first corner, steps, step): from its lowest key up.
    let piece = |t: usize| {
        let (from, to) = (turns[t] as usize, turns[(t + 1) % turns.len()] as usize);
        let steps = (to + m - from) % m;
        if below(keys[from], keys[to]) {
            (from, steps, true)
        } else {
            (to, steps, false)
        }
    };
    let at = |(first, _, forward): (usize, usize, bool), r: usize| {
        let i = if forward { first + r } else { first + m - r };
        if i >= m { i - m } else { i }
    };
    for s in 0..pieces {
        for t in s + 1..pieces {
            let (a, b) = (piece(s), piece(t));
            let (a_lo, a_hi, b_lo, b_hi) = (at(a, 0), at(a, a.1), at(b, 0), at(b, b.1));
            let lo = if below(keys[a_lo], keys[b_lo]) {
                keys[b_lo]
            } else {
                keys[a_lo]
            };
            let hi = if below(keys[a_hi], keys[b_hi]) {
                keys[a_hi]
            } else {
                keys[b_hi]
            };
            if below(hi, lo) {
                continue; // no key in common
            }
            // The corners of each piece in the common range against the other's edge over
            // them; from `b`'s side, the turn is the other way round.
            let mut side: Sign = 0;
            for (x, y, flip) in [(a, b, 1), (b, a, -1)] {
                let (y_lo, y_hi) = (at(y, 0), at(y, y.1));
                let mut e = 0;
                for r in 0..=x.1 {
                    let c = at(x, r);
                    if below(keys[c], lo) || c == y_lo || c == y_hi {
                        continue; // below the range, or the corner both pieces end at
                    }
                    if below(hi, keys[c]) {
                        break;
                    }
                    while below(keys[at(y, e + 1)], keys[c]) {
                        e += 1;
                    }
                    let s = flip * orient2d(p[at(y, e)], p[at(y, e + 1)], p[c]);
                    if s == 0 || (side != 0 && s != side) {
                        return Some(false);
                    }
                    side = s;
                }
            }
        }
    }
    Some(true)
}

/// How many corners of the loop with keys `keys` are turning points of the key (so how many
/// monotone pieces it has), or `None` when two neighbouring corners have equal keys.
fn count_turns(keys: &[(f64, f64)]) -> Option<usize> {
    let m = keys.len();
    let mut turns = 0;
    let mut rising = below(keys[m - 1], keys[0]);
    if keys[0] == keys[m - 1] {
        return None;
    }
    for i in 0..m {
        let next = keys[if i + 1 == m { 0 } else { i + 1 }];
        if next == keys[i] {
            return None;
        }
        let up = below(keys[i], next);
        turns += usize::from(up != rising);
        rising = up;
    }
    Some(turns)
}

/// Does key `a` come before key `b` (see [`key`])?
#[inline(always)]
fn below(a: (f64, f64), b: (f64, f64)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
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
        simple_polygon(p, &mut PolygonScratch::default())
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
    fn monotone_pieces_agree_with_every_pair() {
        // Wobbly circles, random stars, short lattice loops and scattered corners (some turned by 45 degrees, so
        // that the diagonal keys matter), of lengths either side of the pairwise threshold, on
        // a coarse lattice so that corners tie, touch and cross often.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut simple, mut two, mut more, mut more_simple) = (0, 0, 0, 0);
        for trial in 0..20000 {
            let short = trial % 2 == 1;
            let m = if short {
                5 + trial % 11
            } else {
                13 + trial % 30
            };
            let turned = trial % 4 == 3;
            let scattered = trial % 5 == 4;
            let m = if scattered { 4 + trial % 6 } else { m };
            let p: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    if scattered {
                        return [(next() * 5.0).floor(), (next() * 5.0).floor()];
                    }
                    let a = i as f64 * std::f64::consts::TAU / m as f64;
                    let r = match trial % 3 {
                        0 => 20.0 + (next() * 2.0).floor(),
                        1 => 6.0 + (next() * 6.0).floor(),
                        _ => 3.0 + (next() * 9.0).floor(),
                    };
                    let (x, y) = (
                        (r * a.cos()).round(),
                        (r * a.sin() * (1.0 + 0.3 * next())).round(),
                    );
                    if turned { [x + y, x - y] } else { [x, y] }
                })
                .collect();
            let expected = simple_by_pairs(&p);
            assert_eq!(simple_polygon_alone(&p), expected, "{p:?}");
            if let Some(answer) = monotone_pieces(&p, &mut Vec::new(), &mut Vec::new()) {
                assert_eq!(answer, expected, "{p:?}");
                let pieces = (0..KEY_DIRECTIONS)
                    .filter_map(|d| count_turns(&p.iter().map(|&q| key(q, d)).collect::<Vec<_>>()))
                    .min()
                    .expect("some direction");
                if pieces == 2 {
                    two += 1;
                } else {
                    more += 1;
                    more_simple += usize::from(expected);
                }
            }
            simple += usize::from(expected);
        }
        // Both answers, loops of two pieces and of more, simple and not, were exercised.
        assert!(simple > 2000 && simple < 19000, "{simple}");
        assert!(two > 1000, "{two}");
        assert!(
            more > 1000 && more_simple > 300 && more - more_simple > 300,
            "{more} {more_simple}"
        );
    }

    #[test]
    fn keys_compare_exactly() {
        // Sums that round to the same value still order by their errors.
        let (a, b) = ([1.0, 1e-17], [1.0, 2e-17]);
        assert_eq!(key(a, 2).0, key(b, 2).0);
        assert!(below(key(a, 2), key(b, 2)));
        assert!(below(key(b, 3), key(a, 3)));
        assert_eq!(key([0.5, 0.25], 2), (0.75, 0.0));
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
