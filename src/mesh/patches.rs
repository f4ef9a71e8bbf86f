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
//! patches are disks glued along one path of their loops, their union is a disk, and it projects
//! one to one when both patches do along one axis, on opposite sides of the path, and the rest of
//! their loops keep apart ([`Patches::cannot_intersect_each_other`]); two disks whose loops share
//! one vertex pass when their projections meet only there. A node's own test is made once per
//! positions and shared by all its seams.
//!
//! What depends on the shape (which nodes are disks, their loops, which seams glue) is found once
//! per shape; which way the triangles turn and whether each loop projects simply ([`PatchCache`], kept
//! with the mesh until its positions change) are decided from the positions.

use super::Mesh;
use crate::csr::Csr;
use crate::geometry::polygon::{
    PolygonScratch, chains_apart, corner_apart, is_simple, turns_before,
};
use crate::geometry::predicates::{Point, projected_orientations};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU16, AtomicUsize, Ordering::Relaxed};

/// The boundary loop of every node whose patch is a disk (an empty row for the others), and
/// what the test of two nodes' patches together needs.
#[derive(Debug, Default)]
pub(crate) struct Patches {
    loops: Csr<u32>,
    /// Per node, its loop's vertices in increasing order, each with its place in the loop.
    sorted: Csr<(u32, u32)>,
    /// Per node whose patch is a disk none of whose inner vertices is used by a triangle outside
    /// it (only then is the union with a neighbour's patch a disk when their loops share a
    /// path): a summary of its loop's vertices, bit `v % 64` for vertex `v`, never zero. Zero
    /// for the other nodes. Loops whose summaries share no bit share no vertex.
    sealed: Vec<u64>,
    /// Per node: is it the first of exactly two children? Then it and the next node make up
    /// their parent's patch, and the traversal only meets the pair when the parent failed the
    /// same test.
    first_of_two: Vec<bool>,
}

impl Patches {
    /// The loops of `mesh`'s nodes.
    pub fn new(mesh: &Mesh) -> Patches {
        let tree = &mesh.topology.tree;
        let rings = &mesh.topology.rings.triangles;
        let tris = &mesh.topology.triangles;
        // How many triangles use each vertex.
        let mut uses = vec![0u32; mesh.positions.len()];
        for t in tris {
            for &v in t {
                uses[v as usize] += 1;
            }
        }
        let mut finder = LoopFinder::new(tris, mesh.positions.len());
        let mut loops = Csr::with_capacity(tree.len(), 0);
        let mut sorted = Csr::with_capacity(tree.len(), 0);
        let mut sealed = Vec::with_capacity(tree.len());
        let mut by_vertex: Vec<(u32, u32)> = Vec::new();
        for (n, node) in tree.nodes.iter().enumerate() {
            let own = rings.row_range(node.ring_start as usize..node.ring_end as usize);
            let mut summary = 0;
            if finder.disk_loop(own, n as u32 + 1) {
                let l = &finder.boundary;
                if finder.seals(&uses, n as u32 + 1) {
                    summary = l.iter().fold(0u64, |s, &v| s | 1 << (v % 64));
                }
                by_vertex.clear();
                by_vertex.extend(l.iter().enumerate().map(|(i, &v)| (v, i as u32)));
                by_vertex.sort_unstable();
                for &v in l {
                    loops.push(v);
                }
                for &e in &by_vertex {
                    sorted.push(e);
                }
            }
            loops.end_row();
            sorted.end_row();
            sealed.push(summary);
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

    /// Can node `n`'s patch be part of a union that passes
    /// [`Patches::cannot_intersect_each_other`]: is it a sealed disk whose triangles all turn one
    /// way along some axis?
    pub fn may_join(&self, mesh: &Mesh, n: u32) -> bool {
        self.sealed[n as usize] != 0 && one_way_axes(mesh.patch_cache.turns(mesh, n)) != 0
    }

    /// Can node `n`'s patch, at the mesh's positions, have no self-intersection? (`true` only
    /// when sure.)
    pub fn cannot_self_intersect(&self, mesh: &Mesh, n: u32) -> bool {
        let axes = one_way_axes(mesh.patch_cache.turns(mesh, n));
        (0..3).any(|k| axes & 1 << k != 0 && self.projects_simply(mesh, n, k))
    }

    /// Does node `n`'s loop (three corners or more) project to a simple polygon along axis `k`?
    /// Decided once per positions ([`PatchCache`]).
    fn projects_simply(&self, mesh: &Mesh, n: u32, k: usize) -> bool {
        mesh.patch_cache.simple(mesh, n, k, || {
            let boundary = self.loops.row(n as usize);
            boundary.len() >= 3
                && with_scratch(|scratch| {
                    let Scratch { flat, polygon, .. } = scratch;
                    flat.clear();
                    flat.extend(boundary.iter().map(|&v| project(&mesh.positions, v, k)));
                    is_simple(flat, polygon)
                })
        })
    }

    /// Can the patches of nodes `x` and `y` (different, neither below the other), at the mesh's
    /// positions, have no triangles that meet beyond what they share? (`true` only when sure.)
    ///
    /// When both patches are sealed disks whose loops share one path, walked in opposite
    /// directions, and nothing else, their union is a disk whose loop is the rest of the two
    /// loops (their stretches). Along an axis on which every triangle of both turns one way and
    /// both loops project simply, the two projected patches lie on opposite sides of the path
    /// near it; the union projects one to one exactly when, besides, neither stretch leaves
    /// either end of the path into the other patch's corner there, and the two stretches do not
    /// meet elsewhere (a stretch that stays outside the other patch near the path's end and
    /// never crosses its loop stays outside it, and two overlapping regions would need a
    /// boundary inside the path). This closes the seams between neighbouring nodes, whose volumes
    /// always overlap, at the cost of the stretches near each other.
    ///
    /// Patches whose loops share one vertex and nothing else (nodes meeting at a corner) pass
    /// the same way when, along such an axis, their projected regions meet only there
    /// ([`corner_apart`]): each projects one to one, so only that vertex projects to that point.
    pub fn cannot_intersect_each_other(&self, mesh: &Mesh, x: u32, y: u32) -> bool {
        let (i, j) = (x as usize, y as usize);
        if self.sealed[i] & self.sealed[j] == 0 {
            return false;
        }
        let turns = mesh.patch_cache.turns(mesh, x) | mesh.patch_cache.turns(mesh, y);
        let axes = one_way_axes(turns);
        if axes == 0 {
            return false;
        }
        let Some(seam) = self.glued(i, j) else {
            return false;
        };
        // Two children that make up their parent's patch along a path: the traversal meets
        // them only when the parent failed the same test.
        let twins = (i.min(j) + 1 == i.max(j)) && self.first_of_two[i.min(j)];
        if twins && !seam.corner {
            return false;
        }
        (0..3).any(|k| {
            axes & 1 << k != 0
                && self.projects_simply(mesh, x, k)
                && self.projects_simply(mesh, y, k)
                && self.seam_closes(mesh, &seam, k, (turns >> (2 * k)) & 3 == 2)
        })
    }

    /// Along axis `k`, with both loops simple there: do the stretches of `seam` keep apart and
    /// out of each other's corners at the path's ends? `mirrored` when the triangles turn
    /// negatively along `k`: the projection is then mirrored so that the loops run
    /// counterclockwise.
    fn seam_closes(&self, mesh: &Mesh, seam: &Seam, k: usize, mirrored: bool) -> bool {
        let at = |v: u32| {
            let q = project(&mesh.positions, v, k);
            if mirrored { [q[1], q[0]] } else { q }
        };
        let (lx, ly) = (
            self.loops.row(seam.x as usize),
            self.loops.row(seam.y as usize),
        );
        let [x0, x1] = stretch(lx, seam.from_x);
        let [y0, y1] = stretch(ly, seam.from_y);
        with_scratch(|scratch| {
            // The stretches as chains, each closed by the other's first corner: `x`'s runs from
            // the path's last vertex round to its first, `y`'s from the first to the last.
            let Scratch {
                flat,
                other,
                polygon,
            } = scratch;
            flat.clear();
            flat.extend(x0.iter().chain(x1).map(|&v| at(v)));
            other.clear();
            other.extend(y0.iter().chain(y1).map(|&v| at(v)));
            let (first, last) = (other[0], flat[0]);
            flat.push(first);
            other.push(last);
            // At the path's first vertex, going counterclockwise from the path: `x`'s corner
            // reaches back to its stretch before `y`'s corner starts; at the last vertex, the
            // other way round.
            let (a, b) = (&flat[..], &other[..]);
            if seam.corner {
                return corner_apart(a, b, polygon);
            }
            turns_before(first, at(seam.after_first), a[a.len() - 2], b[1])
                && turns_before(last, at(seam.before_last), b[b.len() - 2], a[1])
                && chains_apart(a, b, polygon)
        })
    }

    /// Where the union of the patches of `x` and `y` is a disk glued along one shared path (see
    /// [`Patches::cannot_intersect_each_other`]), the path and the two stretches; where their
    /// loops share one vertex only, that corner. `None` otherwise, or when the path is longer than [`LONGEST_SEAM`] (the children's seams are
    /// shorter).
    fn glued(&self, x: usize, y: usize) -> Option<Seam> {
        let (m, k) = (self.loops.row_len(x), self.loops.row_len(y));
        // The shared vertices, with their places in both loops.
        let mut shared = [(0u32, 0u32); LONGEST_SEAM];
        let mut s = 0;
        let (sx, sy) = (self.sorted.row(x), self.sorted.row(y));
        let (mut i, mut j) = (0, 0);
        while i < sx.len() && j < sy.len() {
            let ((u, pu), (v, pv)) = (sx[i], sy[j]);
            if u == v {
                if s == LONGEST_SEAM {
                    return None;
                }
                shared[s] = (pu, pv);
                s += 1;
            }
            // Without branches on which side steps: the merge's order is unpredictable.
            i += usize::from(u <= v);
            j += usize::from(v <= u);
        }
        if s == 1 {
            // One corner: both loops whole, each starting there.
            let (px, py) = shared[0];
            let v = self.loops.row(x)[px as usize];
            return Some(Seam {
                x: x as u32,
                y: y as u32,
                from_x: (px, m as u32),
                from_y: (py, k as u32),
                after_first: v,
                before_last: v,
                corner: true,
            });
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
            let lx = self.loops.row(x);
            let from_x = (shared[last].0, m as u32 - s + 1);
            let place = |p: u32| lx[(p as usize) % m];
            Seam {
                x: x as u32,
                y: y as u32,
                from_x,
                from_y: (shared[first].1, k as u32 - s + 1),
                // In `x`'s loop the path runs from its first vertex, right after the stretch,
                // to its last, where the stretch starts.
                after_first: place(from_x.0 + from_x.1 + 1),
                before_last: place(from_x.0 + m as u32 - 1),
                corner: false,
            }
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

/// Vertex `v` at `positions` projected along axis `k`: coordinates `k + 1` and `k + 2`.
#[inline]
fn project(positions: &[Point], v: u32, k: usize) -> [f64; 2] {
    let p = positions[v as usize];
    [p[(k + 1) % 3], p[(k + 2) % 3]]
}

/// A seam between two nodes' patches (see [`Patches::glued`]): the stretches `(start,
/// length)` of `x`'s loop (from the path's last vertex round to before its first) and of `y`'s
/// (from the path's first vertex round to before its last), and the vertices next to the path's
/// ends along it.
struct Seam {
    x: u32,
    y: u32,
    from_x: (u32, u32),
    from_y: (u32, u32),
    /// The path's vertex after its first.
    after_first: u32,
    /// The path's vertex before its last.
    before_last: u32,
    /// The loops share one corner, not a path: the stretches are the whole loops, from it
    /// round to it, and the patches must keep apart in projection but for it.
    corner: bool,
}

/// Room for the patch tests, kept per thread so that they allocate nothing once warm.
#[derive(Default)]
struct Scratch {
    flat: Vec<[f64; 2]>,
    other: Vec<[f64; 2]>,
    polygon: PolygonScratch,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::default();
}

/// Patch tests whose thread's scratch had to grow, over the process's life.
static SCRATCH_GROWTHS: AtomicUsize = AtomicUsize::new(0);

/// Runs `f` with this thread's scratch, counting the calls that grew it.
fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    SCRATCH.with_borrow_mut(|scratch| {
        let room = |s: &Scratch| s.flat.capacity() + s.other.capacity() + s.polygon.room();
        let before = room(scratch);
        let result = f(scratch);
        if room(scratch) > before {
            SCRATCH_GROWTHS.fetch_add(1, Relaxed);
        }
        result
    })
}

/// How many patch tests so far had to grow their thread's scratch. The scratch is kept per
/// thread, not in a query's workspace: a query whose patch tests ran on a pool thread that had
/// done none as large allocates, however warm its workspace. Tests of allocation count them.
pub fn scratch_growths() -> usize {
    SCRATCH_GROWTHS.load(Relaxed)
}

/// The axes (bit `k` for coordinate `k` left out) along which triangles whose turns are
/// `turns` (as in [`PatchCache`]) all turn one strict way.
#[inline]
fn one_way_axes(turns: u8) -> u8 {
    (0..3)
        .filter(|k| matches!((turns >> (2 * k)) & 3, 1 | 2))
        .fold(0, |m, k| m | 1 << k)
}

/// What self-collision finds about each node at the mesh's current positions, on first need,
/// kept until the positions change; nodes no self query reaches cost nothing.
///
/// Per node sixteen bits. The low six say which way its triangles turn in the three coordinate
/// projections (the normal cone, in the exact form the patch test needs): two bits per left-out
/// coordinate `k` (bits `2k`, `2k + 1`), `01` when every triangle turns positively, `10`
/// negatively, `11` when they differ or one is flat; the turns of a union of nodes are the `|`
/// of theirs. Bit [`TURNS_FOUND`] marks them found. Bits `8 + k` mark the node's loop tested
/// along axis `k`, and bits `12 + k` record that it projects simply there.
#[derive(Debug, Default)]
pub(crate) struct PatchCache {
    /// Atomic so that queries on several threads share what they find; every thread finds the
    /// same value, so relaxed order is enough.
    bits: OnceLock<Box<[AtomicU16]>>,
}

/// [`PatchCache`]' turns of triangles that differ along every axis: no more can change them.
const MIXED: u8 = 0x3f;

/// [`PatchCache`]' mark of a node's turns found.
const TURNS_FOUND: u16 = 1 << 7;

/// [`PatchCache`]' first bit of "tested along axis `k`"; the result is four bits up.
const TESTED: u16 = 1 << 8;

impl Clone for PatchCache {
    fn clone(&self) -> PatchCache {
        let copy = OnceLock::new();
        if let Some(bits) = self.bits.get() {
            let _ = copy.set(
                bits.iter()
                    .map(|b| AtomicU16::new(b.load(Relaxed)))
                    .collect(),
            );
        }
        PatchCache { bits: copy }
    }
}

impl PatchCache {
    /// Forgets everything found (the positions changed).
    pub fn clear(&mut self) {
        if let Some(bits) = self.bits.get_mut() {
            bits.iter_mut().for_each(|b| *b.get_mut() = 0);
        }
    }

    /// Bytes held on the heap.
    pub fn heap_bytes(&self) -> usize {
        self.bits.get().map_or(0, |b| std::mem::size_of_val(&**b))
    }

    fn bits(&self, mesh: &Mesh) -> &[AtomicU16] {
        self.bits.get_or_init(|| {
            (0..mesh.topology.tree.len())
                .map(|_| AtomicU16::new(0))
                .collect()
        })
    }

    /// Node `n`'s turns (see [`PatchCache`]).
    pub fn turns(&self, mesh: &Mesh, n: u32) -> u8 {
        self.find_turns(self.bits(mesh), mesh, n)
    }

    /// Whether node `n`'s loop projects simply along axis `k`, found by `test` the first time.
    fn simple(&self, mesh: &Mesh, n: u32, k: usize, test: impl FnOnce() -> bool) -> bool {
        let bits = self.bits(mesh);
        let (tested, simple) = (TESTED << k, TESTED << (k + 4));
        let known = bits[n as usize].load(Relaxed);
        if known & tested != 0 {
            return known & simple != 0;
        }
        let answer = test();
        bits[n as usize].fetch_or(tested | if answer { simple } else { 0 }, Relaxed);
        answer
    }

    fn find_turns(&self, bits: &[AtomicU16], mesh: &Mesh, n: u32) -> u8 {
        let known = bits[n as usize].load(Relaxed);
        if known & TURNS_FOUND != 0 {
            return known as u8 & 0x3f;
        }
        let node = &mesh.topology.tree.nodes[n as usize];
        let found = if node.is_leaf() {
            // The ring-ordered corners: one contiguous run, not a jump per triangle.
            let rings = &mesh.topology.rings;
            let own = &rings.corners[rings
                .triangles
                .span(node.ring_start as usize..node.ring_end as usize)];
            let at = |v: u32| &mesh.positions[v as usize];
            // Once every axis is mixed, more triangles change nothing: stop.
            own.iter().try_fold(0, |acc, &[a, b, c]| {
                if acc == MIXED {
                    return Err(acc);
                }
                let signs = projected_orientations(at(a), at(b), at(c));
                Ok((0..3).fold(acc, |acc, k| {
                    let bits = match signs[k] {
                        1.. => 1,
                        ..0 => 2,
                        0 => 3,
                    };
                    acc | bits << (2 * k)
                }))
            })
        } else {
            node.children().try_fold(0, |acc, c| {
                if acc == MIXED {
                    return Err(acc);
                }
                Ok(acc | self.find_turns(bits, mesh, c))
            })
        }
        .unwrap_or_else(|mixed| mixed);
        // `|`, not a store: another thread may have tested the node's loop meanwhile.
        bits[n as usize].fetch_or(u16::from(found) | TURNS_FOUND, Relaxed);
        found
    }
}

const NONE: u32 = u32::MAX;

/// Finds the boundary loops of patches with arrays indexed by vertex and half-edge, marked per
/// patch, rather than hashing each patch's edges: every node of the tree is a patch, so the
/// work is the mesh's size times the tree's depth, and hashing made the first self-query of a
/// new mesh several times slower than its later ones.
struct LoopFinder<'a> {
    tris: &'a [[u32; 3]],
    /// Per half-edge `3t + k` (from corner `k` of triangle `t` to corner `k + 1`): the first
    /// half-edge of the mesh with the same start and end, which names the directed edge.
    name: Vec<u32>,
    /// Per half-edge: the name of the reverse directed edge, [`NONE`] where no triangle has it.
    reverse: Vec<u32>,
    /// Per directed edge name: the patch that last used it.
    edge_mark: Vec<u32>,
    /// Per vertex: the patch that last used it, its index among that patch's vertices and how
    /// many of the patch's triangles use it.
    vertex_mark: Vec<u32>,
    local: Vec<u32>,
    count: Vec<u32>,
    /// Per vertex: the patch whose boundary last left it, and where to.
    next_mark: Vec<u32>,
    next: Vec<u32>,
    /// The current patch's vertices, union-find parents over them, and its loop.
    vertices: Vec<u32>,
    parent: Vec<u32>,
    boundary: Vec<u32>,
}

impl<'a> LoopFinder<'a> {
    fn new(tris: &'a [[u32; 3]], vertex_count: usize) -> LoopFinder<'a> {
        let half = |h: usize| {
            let t = &tris[h / 3];
            (t[h % 3], t[(h + 1) % 3])
        };
        // Half-edges by start vertex, each with its end, in increasing order in each row.
        let leaving = Csr::from_entries(vertex_count, || {
            (0..tris.len() * 3).map(|h| {
                let (a, b) = half(h);
                (a, (b, h as u32))
            })
        });
        let first_from_to = |a: u32, b: u32| {
            leaving
                .row(a as usize)
                .iter()
                .find(|&&(end, _)| end == b)
                .map(|&(_, g)| g)
        };
        let mut name = Vec::with_capacity(tris.len() * 3);
        let mut reverse = Vec::with_capacity(tris.len() * 3);
        for t in tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                name.push(first_from_to(a, b).expect("the half-edge itself"));
                reverse.push(first_from_to(b, a).unwrap_or(NONE));
            }
        }
        LoopFinder {
            tris,
            name,
            reverse,
            edge_mark: vec![0; tris.len() * 3],
            vertex_mark: vec![0; vertex_count],
            local: vec![0; vertex_count],
            count: vec![0; vertex_count],
            next_mark: vec![0; vertex_count],
            next: vec![0; vertex_count],
            vertices: Vec::new(),
            parent: Vec::new(),
            boundary: Vec::new(),
        }
    }

    /// Is the patch of triangles `patch` a topological disk: connected, every edge used by one
    /// triangle (boundary) or two with opposite directions (interior), one boundary loop through
    /// distinct vertices, and Euler characteristic 1? If so its loop, starting at its least
    /// vertex, is left in `boundary`. `mark` names the patch: a value no earlier call used, not 0.
    fn disk_loop(&mut self, patch: &[u32], mark: u32) -> bool {
        let tris = self.tris;
        let corners = || patch.iter().map(|&t| tris[t as usize]);
        if corners().any(|t| t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
            return false;
        }
        let half_edges = || {
            patch
                .iter()
                .flat_map(|&t| (0..3).map(move |k| 3 * t as usize + k))
        };
        for h in half_edges() {
            let g = self.name[h] as usize;
            if self.edge_mark[g] == mark {
                return false; // an edge used twice the same way: not an oriented manifold
            }
            self.edge_mark[g] = mark;
        }
        self.vertices.clear();
        for v in corners().flatten() {
            let i = v as usize;
            if self.vertex_mark[i] != mark {
                self.vertex_mark[i] = mark;
                self.local[i] = self.vertices.len() as u32;
                self.count[i] = 0;
                self.vertices.push(v);
            }
            self.count[i] += 1;
        }
        // Boundary edges: directed edges whose reverse is absent.
        let (mut boundary, mut start) = (0usize, NONE);
        for h in half_edges() {
            let r = self.reverse[h];
            if r == NONE || self.edge_mark[r as usize] != mark {
                let t = &tris[h / 3];
                let (a, b) = (t[h % 3], t[(h + 1) % 3]);
                if self.next_mark[a as usize] == mark {
                    return false; // two boundary edges leave one vertex: a pinch
                }
                self.next_mark[a as usize] = mark;
                self.next[a as usize] = b;
                boundary += 1;
                start = start.min(a);
            }
        }
        let edges = 3 * patch.len();
        let undirected = (edges - boundary) / 2 + boundary;
        if self.vertices.len() + patch.len() != undirected + 1 || boundary == 0 {
            return false;
        }
        // One loop through every boundary edge.
        self.boundary.clear();
        self.boundary.push(start);
        let mut v = self.next[start as usize];
        while v != start {
            if self.boundary.len() > boundary || self.next_mark[v as usize] != mark {
                return false;
            }
            self.boundary.push(v);
            v = self.next[v as usize];
        }
        if self.boundary.len() != boundary {
            return false; // several loops: not a disk
        }
        // Connected: with one boundary loop and Euler characteristic 1, a surface of several
        // components would need a closed component of characteristic 0 or less beside a disk,
        // which the count above allows (a torus and a disk): check connectivity outright.
        self.parent.clear();
        self.parent.extend(0..self.vertices.len() as u32);
        fn root(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                parent[x as usize] = parent[parent[x as usize] as usize];
                x = parent[x as usize];
            }
            x
        }
        for t in corners() {
            for k in 0..3 {
                let (a, b) = (
                    self.local[t[k] as usize],
                    self.local[t[(k + 1) % 3] as usize],
                );
                let (ra, rb) = (root(&mut self.parent, a), root(&mut self.parent, b));
                self.parent[ra as usize] = rb;
            }
        }
        let r = root(&mut self.parent, 0);
        (0..self.vertices.len() as u32).all(|x| root(&mut self.parent, x) == r)
    }

    /// After [`LoopFinder::disk_loop`] found a disk: does no triangle outside it use one of its
    /// inner vertices? `uses` counts the triangles of the whole mesh at each vertex.
    fn seals(&self, uses: &[u32], mark: u32) -> bool {
        self.vertices.iter().all(|&v| {
            let i = v as usize;
            self.next_mark[i] == mark || uses[i] == self.count[i]
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{Rng, grid, icosphere, torus};
    use crate::{BuildOptions, TreeKind};
    use std::collections::HashMap;

    /// The disk test as its definition reads, with hash maps: the oracle for [`LoopFinder`].
    fn reference_disk_loop(tris: &[[u32; 3]]) -> Option<Vec<u32>> {
        let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
        for t in tris {
            if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
                return None;
            }
            for k in 0..3 {
                *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        if directed.values().any(|&c| c > 1) {
            return None;
        }
        let mut next: HashMap<u32, u32> = HashMap::new();
        for &(a, b) in directed.keys() {
            if !directed.contains_key(&(b, a)) && next.insert(a, b).is_some() {
                return None;
            }
        }
        let undirected = (directed.len() - next.len()) / 2 + next.len();
        let mut vertices: Vec<u32> = tris.iter().flatten().copied().collect();
        vertices.sort_unstable();
        vertices.dedup();
        if vertices.len() + tris.len() != undirected + 1 || next.is_empty() {
            return None;
        }
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
            return None;
        }
        // Connected, by a flood over the edges.
        let mut seen = vec![vertices[0]];
        let mut stack = vec![vertices[0]];
        while let Some(v) = stack.pop() {
            for &(a, b) in directed.keys() {
                for (from, to) in [(a, b), (b, a)] {
                    if from == v && !seen.contains(&to) {
                        seen.push(to);
                        stack.push(to);
                    }
                }
            }
        }
        (seen.len() == vertices.len()).then_some(l)
    }

    /// Does no triangle outside the disk `tris` with loop `boundary` use an inner vertex?
    fn reference_seals(tris: &[[u32; 3]], boundary: &[u32], uses: &[u32]) -> bool {
        let mut inner: HashMap<u32, u32> = HashMap::new();
        for &v in tris.iter().flatten() {
            *inner.entry(v).or_insert(0) += 1;
        }
        for v in boundary {
            inner.remove(v);
        }
        inner.iter().all(|(&v, &count)| uses[v as usize] == count)
    }

    /// The loop [`LoopFinder`] finds for the first `patch` triangles of the mesh `tris` of
    /// `vertices` vertices, and whether it seals.
    fn found_in(tris: &[[u32; 3]], patch: usize, vertices: usize) -> Option<(Vec<u32>, bool)> {
        let mut finder = LoopFinder::new(tris, vertices);
        let all: Vec<u32> = (0..patch as u32).collect();
        let mut uses = vec![0; vertices];
        tris.iter().flatten().for_each(|&v| uses[v as usize] += 1);
        finder
            .disk_loop(&all, 1)
            .then(|| (finder.boundary.clone(), finder.seals(&uses, 1)))
    }

    /// [`found_in`] with the whole mesh as the patch.
    fn found(tris: &[[u32; 3]], vertices: usize) -> Option<(Vec<u32>, bool)> {
        found_in(tris, tris.len(), vertices)
    }

    #[test]
    fn disks_and_others() {
        // Two triangles of a square: a disk with a loop of 4.
        let square = [[0, 1, 2], [0, 2, 3]];
        assert_eq!(found(&square, 4).map(|l| l.0.len()), Some(4));
        // Inconsistent orientation: not taken.
        assert!(found(&[[0, 1, 2], [0, 3, 2]], 4).is_none());
        // Two triangles sharing a vertex only: a pinch.
        assert!(found(&[[0, 1, 2], [0, 3, 4]], 5).is_none());
        // Two separate triangles.
        assert!(found(&[[0, 1, 2], [3, 4, 5]], 6).is_none());
        // A closed surface (a tetrahedron) has no boundary.
        assert!(found(&[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], 4).is_none());
        // A repeated corner, and a triangle repeated.
        assert!(found(&[[0, 1, 1]], 2).is_none());
        assert!(found(&[[0, 1, 2], [0, 1, 2]], 3).is_none());
        // A closed torus beside a triangle: one loop and Euler characteristic 1, but two pieces.
        let mut apart: Vec<[u32; 3]> = torus(1.0, 0.3, 3, 3)
            .triangles
            .chunks(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        apart.push([9, 10, 11]);
        assert!(found(&apart, 12).is_none());
        // A fan round vertex 0: a disk that seals, unless a triangle outside it uses vertex 0.
        let fan = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1], [0, 5, 6]];
        assert_eq!(found_in(&fan, 4, 7), Some((vec![1, 2, 3, 4], false)));
        assert_eq!(found_in(&fan[..4], 4, 7), Some((vec![1, 2, 3, 4], true)));
    }

    /// Meshes whose patches are disks, and the same meshes spoilt in every way the disk test
    /// must notice: triangles turned over, repeated, removed, or given another mesh's vertex
    /// (pinches, non-manifold edges, handles, several components).
    fn meshes() -> Vec<(Vec<f64>, Vec<u32>)> {
        let mut rng = Rng::new(7);
        let mut out = Vec::new();
        for m in [grid(12, 1.0), icosphere(2), torus(1.0, 0.3, 12, 8)] {
            out.push((m.positions.clone(), m.triangles.clone()));
            let n = m.positions.len() / 3;
            for spoil in 0..4 {
                let mut tris: Vec<[u32; 3]> =
                    m.triangles.chunks(3).map(|t| [t[0], t[1], t[2]]).collect();
                for _ in 0..1 + rng.below(6) {
                    let t = rng.below(tris.len() as u64) as usize;
                    match spoil {
                        0 => tris[t].swap(0, 1),
                        1 => tris.push(tris[t]),
                        2 => drop(tris.swap_remove(t)),
                        _ => tris[t][rng.below(3) as usize] = rng.below(n as u64) as u32,
                    }
                }
                out.push((m.positions.clone(), tris.into_iter().flatten().collect()));
            }
        }
        out
    }

    #[test]
    fn the_loop_finder_agrees_with_the_definition_on_every_node() {
        let (mut disks, mut sealed) = (0, 0);
        for (positions, triangles) in meshes() {
            for tree in [TreeKind::Binary, TreeKind::Octree] {
                let options = BuildOptions::default().with_tree(tree);
                let Ok(mesh) = Mesh::new(&positions, &triangles, &options) else {
                    continue;
                };
                let patches = Patches::new(&mesh);
                let tris = &mesh.topology.triangles;
                let mut uses = vec![0; mesh.positions.len()];
                tris.iter().flatten().for_each(|&v| uses[v as usize] += 1);
                for (n, node) in mesh.topology.tree.nodes.iter().enumerate() {
                    let own: Vec<[u32; 3]> = mesh
                        .topology
                        .rings
                        .triangles
                        .row_range(node.ring_start as usize..node.ring_end as usize)
                        .iter()
                        .map(|&t| tris[t as usize])
                        .collect();
                    let expected = reference_disk_loop(&own);
                    let seals = expected
                        .as_ref()
                        .is_some_and(|l| reference_seals(&own, l, &uses));
                    assert_eq!(patches.loops.row(n), expected.as_deref().unwrap_or(&[]));
                    assert_eq!(patches.sealed[n] != 0, seals, "node {n}");
                    disks += usize::from(expected.is_some());
                    sealed += usize::from(seals);
                }
            }
        }
        // The meshes exercise both answers of both tests.
        assert!(
            disks > 100 && sealed > 50 && sealed < disks,
            "{disks} {sealed}"
        );
    }
}
