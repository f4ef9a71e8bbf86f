//! [`Mesh::validate`]: every invariant of the hierarchy, checked the slow, obvious way.

use super::input::scan_positions;
use super::mesh::Mesh;
use crate::geometry::aabb::Aabb;
use crate::geometry::sphere::{Sphere, distance_squared};
use crate::tree::distinct_corners;
use crate::volume::Volumes;
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
    /// nothing outside the ring's vertex list; DVH centres at their vertices and SBV centres at
    /// the midpoints of their boxes; and every volume containing every vertex of every triangle
    /// below it (boxes exactly the boxes of those vertices). Costs `O(vertices × depth)`; meant
    /// for tests, which call it after every build and refit.
    pub fn validate(&self) -> Result<(), InvariantError> {
        self.validate_rings()?;
        self.validate_tree()?;
        self.validate_volumes()?;
        // Cached extent of the coordinates.
        let extent = scan_positions(self.positions.as_flattened())
            .map_err(|e| InvariantError(e.to_string()))?;
        ensure!(
            extent.max_abs == self.max_abs && extent.in_fast_range == self.in_fast_range,
            "cached coordinate extent is stale"
        );
        ensure!(
            self.spare.len() == self.positions.len(),
            "spare positions: {} for {} vertices",
            self.spare.len(),
            self.positions.len()
        );
        ensure!(
            !self.scratch.is_empty()
                && self.scratch.iter().all(|s| {
                    s.capacity() >= self.options.tree.max_children() * self.topology.tree.levels()
                }),
            "refit stack not preallocated"
        );
        Ok(())
    }

    /// Offsets monotone, every triangle in exactly one ring, vertex lists exact.
    fn validate_rings(&self) -> Result<(), InvariantError> {
        let nv = self.positions.len();
        let nt = self.topology.triangles.len();
        let rings = &self.topology.rings;
        let nr = rings.len();
        ensure!(nr >= 1, "no rings");
        for (name, table) in [("triangle", &rings.triangles), ("vertex", &rings.vertices)] {
            let o = table.offsets();
            ensure!(
                table.rows() == nr,
                "ring {name} table has {} rows for {nr} rings",
                table.rows()
            );
            ensure!(
                o[0] == 0 && o[nr] as usize == table.items().len(),
                "ring {name} offsets do not span the list"
            );
            ensure!(
                o.windows(2).all(|w| w[0] <= w[1]),
                "ring {name} offsets decrease"
            );
        }
        ensure!(
            rings.corners.len() == rings.triangles.items().len(),
            "{} stored corners for {} ring triangles",
            rings.corners.len(),
            rings.triangles.items().len()
        );
        for (t, tri) in self.topology.triangles.iter().enumerate() {
            ensure!(
                tri.iter().all(|&v| (v as usize) < nv),
                "triangle {t} = {tri:?} out of range ({nv} vertices)"
            );
        }
        let corners_of = |t: u32| self.topology.triangles[t as usize];
        let mut covered = vec![0u32; nt];
        let mut in_ring = vec![u32::MAX; nv];
        let mut corner_of = vec![u32::MAX; nv];
        for r in 0..nr {
            ensure!(rings.triangles.row_len(r) > 0, "ring {r} has no triangles");
            let c = rings.centre[r];
            ensure!((c as usize) < nv, "ring {r} centre {c} out of range");
            in_ring[c as usize] = r as u32;
            for &v in rings.vertices.row(r) {
                ensure!((v as usize) < nv, "ring {r} vertex {v} out of range");
                ensure!(v != c, "ring {r} lists its centre among its vertices");
                ensure!(
                    in_ring[v as usize] != r as u32,
                    "ring {r} lists vertex {v} twice"
                );
                in_ring[v as usize] = r as u32;
            }
            for k in rings.triangles.span(r..r + 1) {
                let t = rings.triangles.items()[k];
                ensure!((t as usize) < nt, "ring {r} triangle {t} out of range");
                ensure!(
                    rings.corners[k] == corners_of(t),
                    "ring {r}: stored corners of triangle {t} are stale"
                );
                covered[t as usize] += 1;
                for v in distinct_corners(&corners_of(t)) {
                    ensure!(
                        in_ring[v as usize] == r as u32,
                        "ring {r}: vertex {v} of triangle {t} missing from its vertex list"
                    );
                    corner_of[v as usize] = r as u32;
                }
            }
            for &v in rings.vertices.row(r) {
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
        Ok(())
    }

    /// Children contiguous and after their parent, ring ranges partitioned among children,
    /// depths, one ring per leaf, one parent per node.
    fn validate_tree(&self) -> Result<(), InvariantError> {
        let nr = self.topology.rings.len();
        let nodes = &self.topology.tree.nodes;
        let nn = nodes.len();
        ensure!(nn >= 1, "empty hierarchy");
        let root = &nodes[0];
        ensure!(
            root.ring_start == 0 && root.ring_end as usize == nr && root.depth == 0,
            "root does not span every ring at depth 0: {root:?}"
        );
        let mut leaves_seen = 0;
        let mut parent_count = vec![0u32; nn];
        for (i, n) in nodes.iter().enumerate() {
            ensure!(
                n.ring_start < n.ring_end && (n.ring_end as usize) <= nr,
                "node {i} ring range {}..{} invalid",
                n.ring_start,
                n.ring_end
            );
            if n.is_leaf() {
                leaves_seen += 1;
                ensure!(
                    n.ring_end == n.ring_start + 1,
                    "leaf {i} holds {} rings",
                    n.ring_end - n.ring_start
                );
                continue;
            }
            ensure!(
                n.first_child as usize > i && n.children().end as usize <= nn,
                "node {i} children {:?} out of order or range",
                n.children()
            );
            ensure!(n.child_count >= 2, "node {i} has a single child");
            ensure!(
                usize::from(n.child_count) <= self.options.tree.max_children(),
                "node {i} has {} children, more than a {:?} node may",
                n.child_count,
                self.options.tree
            );
            let mut expect = n.ring_start;
            for ch in n.children() {
                let c = &nodes[ch as usize];
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
        ensure!(leaves_seen == nr, "{leaves_seen} leaves for {nr} rings");
        if let Some(i) = (1..nn).find(|&i| parent_count[i] != 1) {
            return Err(InvariantError(format!(
                "node {i} has {} parents",
                parent_count[i]
            )));
        }
        Ok(())
    }

    /// Every vertex of every triangle below a node is inside its volume; DVH centres sit on
    /// vertices below their node (a leaf's on its ring's centre); SBV centres are the midpoints
    /// of the exact boxes of the vertices below.
    fn validate_volumes(&self) -> Result<(), InvariantError> {
        let nn = self.topology.tree.len();
        let sizes = match &self.volumes {
            Volumes::Dvh {
                centre_vertex,
                spheres,
            } => [centre_vertex.len(), spheres.len()],
            Volumes::Sbv { spheres, boxes } => [spheres.len(), boxes.len()],
            Volumes::Aabb { boxes } => [boxes.len(), nn],
        };
        ensure!(
            sizes == [nn, nn],
            "{:?} volumes sized {sizes:?} for {nn} nodes",
            self.volumes.kind()
        );
        for (i, n) in self.topology.tree.nodes.iter().enumerate() {
            let below = || {
                (n.ring_start as usize..n.ring_end as usize)
                    .flat_map(|r| self.topology.rings.all_vertices(r))
            };
            let exact_box = Aabb::of_points(below().map(|v| &self.positions[v as usize]));
            // A moving mesh's volumes hold the start positions too.
            let mut swept_box = exact_box;
            if self.motion.moving {
                for v in below() {
                    swept_box.grow(&self.motion.start[v as usize]);
                }
            }
            match &self.volumes {
                Volumes::Dvh {
                    centre_vertex,
                    spheres,
                } => {
                    let cv = centre_vertex[i];
                    ensure!(
                        (cv as usize) < self.positions.len(),
                        "node {i} centre vertex {cv} out of range"
                    );
                    ensure!(
                        spheres[i].centre == self.positions[cv as usize],
                        "node {i} sphere centre is not at its vertex {cv}"
                    );
                    ensure!(
                        below().any(|v| v == cv),
                        "node {i} centre vertex {cv} is not below it"
                    );
                    if n.is_leaf() {
                        ensure!(
                            cv == self.topology.rings.centre[n.ring_start as usize],
                            "leaf {i} not centred on its ring's centre"
                        );
                    }
                    self.check_sphere(i, &spheres[i], below())?;
                }
                Volumes::Sbv { spheres, boxes } => {
                    ensure!(
                        boxes[i] == exact_box,
                        "node {i}: stored box {:?} is not the box of its vertices {exact_box:?}",
                        boxes[i]
                    );
                    ensure!(
                        spheres[i].centre == exact_box.centre(),
                        "node {i}: sphere centre is not the midpoint of its vertices' box"
                    );
                    self.check_sphere(i, &spheres[i], below())?;
                }
                Volumes::Aabb { boxes } => {
                    ensure!(
                        boxes[i] == swept_box,
                        "node {i}: box {:?} is not the box of its vertices {swept_box:?}",
                        boxes[i]
                    );
                }
            }
        }
        Ok(())
    }

    fn check_sphere(
        &self,
        i: usize,
        s: &Sphere,
        below: impl Iterator<Item = u32>,
    ) -> Result<(), InvariantError> {
        ensure!(
            s.radius >= 0.0,
            "node {i} radius {} is negative or NaN",
            s.radius
        );
        for v in below {
            let d = distance_squared(&s.centre, &self.positions[v as usize]).sqrt();
            ensure!(
                d <= s.radius,
                "node {i}: vertex {v} at distance {d:e} outside radius {:e}",
                s.radius
            );
            if self.motion.moving {
                let d = distance_squared(&s.centre, &self.motion.start[v as usize]).sqrt();
                ensure!(
                    d <= s.radius,
                    "node {i}: vertex {v} at the start of the motion at distance {d:e} outside radius {:e}",
                    s.radius
                );
            }
        }
        Ok(())
    }
}
