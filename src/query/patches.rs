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
//! What depends on the shape (which nodes are disks, and their boundary loops) is found once
//! per shape; the axes and the loop's simplicity are decided per query, from the positions.

use crate::csr::Csr;
use crate::geometry::predicates::{Point, Sign, orient2d};
use crate::mesh::Mesh;
use std::collections::HashMap;

/// The boundary loop of every node whose patch is a disk (an empty row for the others).
#[derive(Debug, Default)]
pub(crate) struct Patches {
    loops: Csr<u32>,
}

impl Patches {
    /// The loops of `mesh`'s nodes.
    pub fn new(mesh: &Mesh) -> Patches {
        let tree = &mesh.shape.tree;
        let rings = &mesh.shape.rings.triangles;
        let tris = &mesh.shape.triangles;
        let mut loops = Csr::with_capacity(tree.len(), 0);
        for node in &tree.nodes {
            let range = node.ring_start as usize..node.ring_end as usize;
            let own = rings.row_range(range);
            if let Some(l) = disk_loop(own.iter().map(|&t| tris[t as usize])) {
                for v in l {
                    loops.push(v);
                }
            }
            loops.end_row();
        }
        Patches { loops }
    }

    /// Can node `n`'s patch, at `positions`, have no self-intersection? (`true` only when sure.)
    pub fn cannot_self_intersect(&self, mesh: &Mesh, n: u32, positions: &[Point]) -> bool {
        let boundary = self.loops.row(n as usize);
        if boundary.len() < 3 {
            return false;
        }
        let node = &mesh.shape.tree.nodes[n as usize];
        let own = mesh
            .shape
            .rings
            .triangles
            .row_range(node.ring_start as usize..node.ring_end as usize);
        let tris = &mesh.shape.triangles;
        (0..3).any(|drop| {
            let flat = |v: u32| {
                let p = positions[v as usize];
                [p[(drop + 1) % 3], p[(drop + 2) % 3]]
            };
            let turn = |t: [u32; 3]| orient2d(flat(t[0]), flat(t[1]), flat(t[2]));
            let first = turn(tris[own[0] as usize]);
            first != 0
                && own.iter().all(|&t| turn(tris[t as usize]) == first)
                && simple_polygon(&boundary.iter().map(|&v| flat(v)).collect::<Vec<_>>())
        })
    }
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
fn simple_polygon(p: &[[f64; 2]]) -> bool {
    let m = p.len();
    let edge = |i: usize| (p[i], p[(i + 1) % m]);
    for i in 0..m {
        let (a, b) = edge(i);
        if a == b {
            return false;
        }
        // The corner at b: the next edge must not fold back over this one.
        let c = p[(i + 2) % m];
        if orient2d(a, b, c) == 0 && (c == b || between(a, b, c) || between(b, c, a)) {
            return false;
        }
    }
    // Edges that are not consecutive must not meet at all.
    let apart = |i: usize, j: usize| {
        let (lo, hi) = (i.min(j), i.max(j));
        hi - lo > 1 && !(lo == 0 && hi == m - 1)
    };
    let meet = |i: usize, j: usize| {
        let ((a, b), (c, d)) = (edge(i), edge(j));
        segments_meet(a, b, c, d)
    };
    if m <= SMALL_LOOP {
        return !(0..m).any(|i| (i + 1..m).any(|j| apart(i, j) && meet(i, j)));
    }
    // Long loops: the edges are put in the cells of a grid over the loop's box that their boxes
    // cover, and only edges sharing a cell are tested; about linear for the loops of patches.
    // Cells are found by rounded arithmetic that only grows with the coordinate, so two edges
    // that share a point share that point's cell.
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for q in p {
        for k in 0..2 {
            (lo[k], hi[k]) = (lo[k].min(q[k]), hi[k].max(q[k]));
        }
    }
    let side = (m as f64).sqrt().ceil() as usize;
    let scale = [0, 1].map(|k| {
        let w = hi[k] - lo[k];
        if w > 0.0 && w.is_finite() {
            side as f64 / w
        } else {
            0.0
        }
    });
    let cell = |k: usize, x: f64| (((x - lo[k]) * scale[k]) as usize).min(side - 1);
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); side * side];
    for i in 0..m {
        let (a, b) = edge(i);
        let (x0, x1) = (cell(0, a[0].min(b[0])), cell(0, a[0].max(b[0])));
        let (y0, y1) = (cell(1, a[1].min(b[1])), cell(1, a[1].max(b[1])));
        for y in y0..=y1 {
            for x in x0..=x1 {
                cells[y * side + x].push(i as u32);
            }
        }
    }
    !cells.iter().any(|c| {
        (0..c.len()).any(|s| {
            (s + 1..c.len()).any(|t| {
                let (i, j) = (c[s] as usize, c[t] as usize);
                apart(i, j) && meet(i, j)
            })
        })
    })
}

/// Loops up to this long are tested pair by pair.
const SMALL_LOOP: usize = 32;

/// Is `x` on the segment `[a, b]` (all three collinear)? Coordinates compared exactly.
fn between(a: [f64; 2], b: [f64; 2], x: [f64; 2]) -> bool {
    (0..2).all(|k| a[k].min(b[k]) <= x[k] && x[k] <= a[k].max(b[k]))
}

/// Do the closed segments `[a, b]` and `[c, d]` share a point? Exact.
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

    #[test]
    fn polygons() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(simple_polygon(&square));
        let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(!simple_polygon(&bow));
        // A corner that turns straight back along its edge.
        let spike = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(!simple_polygon(&spike));
        // Touching at a corner.
        let pinch = [
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 1.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [1.0, 1.0],
        ];
        assert!(!simple_polygon(&pinch));
        // Straight corners are fine.
        let straight = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0]];
        assert!(simple_polygon(&straight));
        // Long loops (the grid of cells): a circle, and the same circle with one vertex pulled
        // out across the far side (its edges cross others), or onto another vertex (they touch).
        let circle: Vec<[f64; 2]> = (0..500)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 500.0;
                [a.cos(), a.sin()]
            })
            .collect();
        assert!(simple_polygon(&circle));
        let mut crossed = circle.clone();
        crossed[100] = [-1.5, 0.0];
        assert!(!simple_polygon(&crossed));
        let mut touching = circle.clone();
        touching[100] = circle[300];
        assert!(!simple_polygon(&touching));
        // A figure-eight: simple but for one crossing in the middle.
        let eight: Vec<[f64; 2]> = (0..400)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 400.0;
                [a.sin(), a.sin() * a.cos()]
            })
            .collect();
        assert!(!simple_polygon(&eight));
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
