//! [`Mesh::validate`]: every invariant of the hierarchy, checked the slow, obvious way.

use super::input::scan_positions;
use super::mesh::Mesh;
use super::rings::distinct_corners;
use crate::geometry::sphere::distance_squared;
use std::fmt;

/// A broken invariant found by [`Mesh::validate`]. Always a bug in dvh, never a user error.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvariantError(pub String);

impl fmt::Display for InvariantError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "dvh invariant broken: {}", self.0)
    }
}

impl std::error::Error for InvariantError {}

macro_rules! ensure {
    ($cond:expr, $($arg:tt)+) => {
        if $cond {
        } else {
            return Err(InvariantError(format!($($arg)+)));
        }
    };
}

impl Mesh {
    /// Checks every invariant: array sizes and indices in range; the tree's shape (children
    /// contiguous and after their parent, ring ranges partitioned among children, depths, one
    /// ring per leaf); every triangle in exactly one ring and every ring triangle incident to
    /// nothing outside the ring's vertex list; sphere centres at their vertices; and every sphere
    /// containing every vertex of every triangle below it. Costs `O(vertices × depth)`; meant for
    /// tests, which call it after every build and refit.
    pub fn validate(&self) -> Result<(), InvariantError> {
        let nv = self.positions.len();
        let nt = self.triangles.len();
        let nr = self.ring_centre.len();
        let nn = self.nodes.len();
        ensure!(
            nr >= 1 && nn >= 1,
            "empty hierarchy: {nr} rings, {nn} nodes"
        );
        ensure!(
            self.ring_tri_start.len() == nr + 1,
            "ring triangle offsets: {} for {nr} rings",
            self.ring_tri_start.len()
        );
        ensure!(
            self.ring_vert_start.len() == nr + 1,
            "ring vertex offsets: {} for {nr} rings",
            self.ring_vert_start.len()
        );
        ensure!(
            self.ring_tri_start[0] == 0 && self.ring_tri_start[nr] as usize == self.ring_tris.len(),
            "ring triangle offsets do not span the list"
        );
        ensure!(
            self.ring_vert_start[0] == 0
                && self.ring_vert_start[nr] as usize == self.ring_verts.len(),
            "ring vertex offsets do not span the list"
        );
        for (t, tri) in self.triangles.iter().enumerate() {
            ensure!(
                tri.iter().all(|&v| (v as usize) < nv),
                "triangle {t} = {tri:?} out of range ({nv} vertices)"
            );
        }

        // Rings: offsets monotone, every triangle exactly once, vertex lists exact.
        let mut covered = vec![0u32; nt];
        let mut in_ring = vec![u32::MAX; nv];
        let mut corner_of = vec![u32::MAX; nv];
        for r in 0..nr {
            let (ts, te) = (self.ring_tri_start[r], self.ring_tri_start[r + 1]);
            let (vs, ve) = (self.ring_vert_start[r], self.ring_vert_start[r + 1]);
            ensure!(ts < te, "ring {r} has no triangles");
            ensure!(vs <= ve, "ring {r} vertex offsets decrease");
            let c = self.ring_centre[r];
            ensure!((c as usize) < nv, "ring {r} centre {c} out of range");
            in_ring[c as usize] = r as u32;
            for &v in &self.ring_verts[vs as usize..ve as usize] {
                ensure!((v as usize) < nv, "ring {r} vertex {v} out of range");
                ensure!(v != c, "ring {r} lists its centre among its vertices");
                ensure!(
                    in_ring[v as usize] != r as u32,
                    "ring {r} lists vertex {v} twice"
                );
                in_ring[v as usize] = r as u32;
            }
            for (k, &t) in self
                .ring_tris
                .iter()
                .enumerate()
                .take(te as usize)
                .skip(ts as usize)
            {
                ensure!((t as usize) < nt, "ring {r} triangle {t} out of range");
                ensure!(
                    self.ring_corners.get(k) == Some(&self.triangles[t as usize]),
                    "ring {r}: stored corners of triangle {t} are stale"
                );
                covered[t as usize] += 1;
                for v in distinct_corners(&self.triangles[t as usize]) {
                    ensure!(
                        in_ring[v as usize] == r as u32,
                        "ring {r}: vertex {v} of triangle {t} missing from its vertex list"
                    );
                    corner_of[v as usize] = r as u32;
                }
            }
            for &v in &self.ring_verts[vs as usize..ve as usize] {
                ensure!(
                    corner_of[v as usize] == r as u32,
                    "ring {r} lists vertex {v}, which is on none of its triangles"
                );
            }
        }
        if let Some(t) = covered.iter().position(|&c| c != 1) {
            return Err(InvariantError(format!(
                "triangle {t} is in {} rings, not exactly one",
                covered[t]
            )));
        }

        // Tree shape.
        let root = &self.nodes[0];
        ensure!(
            root.ring_start == 0 && root.ring_end as usize == nr && root.depth == 0,
            "root does not span every ring at depth 0: {root:?}"
        );
        let mut leaves_seen = 0;
        let mut parent_count = vec![0u32; nn];
        for (i, n) in self.nodes.iter().enumerate() {
            ensure!(
                n.ring_start < n.ring_end && (n.ring_end as usize) <= nr,
                "node {i} ring range {}..{} invalid",
                n.ring_start,
                n.ring_end
            );
            ensure!(
                (n.centre_vertex as usize) < nv,
                "node {i} centre vertex {} out of range",
                n.centre_vertex
            );
            ensure!(
                n.centre == self.positions[n.centre_vertex as usize],
                "node {i} sphere centre is not at its vertex {}",
                n.centre_vertex
            );
            let radius = n.radius;
            ensure!(radius >= 0.0, "node {i} radius {radius} is negative or NaN");
            if n.is_leaf() {
                leaves_seen += 1;
                ensure!(
                    n.ring_end == n.ring_start + 1,
                    "leaf {i} holds {} rings",
                    n.ring_end - n.ring_start
                );
                ensure!(
                    n.centre_vertex == self.ring_centre[n.ring_start as usize],
                    "leaf {i} not centred on its ring's centre"
                );
            } else {
                ensure!(
                    n.first_child as usize > i && (n.first_child + n.child_count) as usize <= nn,
                    "node {i} children {:?} out of order or range",
                    n.children()
                );
                ensure!(n.child_count >= 2, "node {i} has a single child");
                let mut expect = n.ring_start;
                for ch in n.children() {
                    let c = &self.nodes[ch as usize];
                    parent_count[ch as usize] += 1;
                    ensure!(
                        c.depth == n.depth + 1,
                        "node {ch} depth {} under node {i} at depth {}",
                        c.depth,
                        n.depth
                    );
                    ensure!(
                        c.ring_start == expect,
                        "children of node {i} do not partition its rings"
                    );
                    expect = c.ring_end;
                }
                ensure!(
                    expect == n.ring_end,
                    "children of node {i} do not cover its rings"
                );
            }
        }
        ensure!(leaves_seen == nr, "{leaves_seen} leaves for {nr} rings");
        if let Some(i) = (1..nn).find(|&i| parent_count[i] != 1) {
            return Err(InvariantError(format!(
                "node {i} has {} parents",
                parent_count[i]
            )));
        }

        // Containment: every vertex of every triangle below a node is inside its sphere; inner
        // centres are vertices below the node.
        for (i, n) in self.nodes.iter().enumerate() {
            let s = n;
            let mut centre_below = false;
            for r in n.ring_start as usize..n.ring_end as usize {
                let verts = &self.ring_verts
                    [self.ring_vert_start[r] as usize..self.ring_vert_start[r + 1] as usize];
                for &v in std::iter::once(&self.ring_centre[r]).chain(verts) {
                    centre_below |= v == n.centre_vertex;
                    let d = distance_squared(&s.centre, &self.positions[v as usize]).sqrt();
                    ensure!(
                        d <= s.radius,
                        "node {i}: vertex {v} at distance {d:e} outside radius {:e}",
                        s.radius
                    );
                }
            }
            ensure!(
                centre_below,
                "node {i} centre vertex {} is not below it",
                n.centre_vertex
            );
        }

        // Cached extent of the coordinates.
        let extent = scan_positions(self.positions.as_flattened())
            .map_err(|e| InvariantError(e.to_string()))?;
        ensure!(
            extent.max_abs == self.max_abs && extent.safe == self.safe,
            "cached coordinate extent is stale"
        );
        ensure!(
            self.scratch.capacity() >= 8 * self.tree_stats().levels,
            "refit stack not preallocated"
        );
        Ok(())
    }
}
