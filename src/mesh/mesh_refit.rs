//! Refitting a [`Mesh`] to new vertex positions: radii only, no allocation.

use super::input::{scan_points, scan_positions};
use super::mesh::{Mesh, RadiusKind, RefitStats};
use crate::error::{Error, Result};
use crate::geometry::predicates::Point;
use crate::geometry::sphere::{distance_squared, round_up};

impl Mesh {
    /// Takes new positions for every vertex (`x, y, z` each, same vertex count as at build) and
    /// recomputes every radius. Centres are mesh vertices, so they move with the positions.
    ///
    /// Errors: [`Error::VertexCountMismatch`], [`Error::PositionsLength`],
    /// [`Error::NonFiniteCoordinate`]. On error the mesh is exactly as it was.
    ///
    /// Cost: linear in the vertices for the leaves; above them, [`RadiusKind::Layered`] is
    /// linear in the nodes, and [`RadiusKind::Wrapped`] searches each node's subtree for its
    /// farthest vertex, pruning subtrees whose spheres cannot hold a farther one (at worst
    /// vertices times depth). Allocates nothing.
    pub fn refit(&mut self, positions: &[f64]) -> Result<RefitStats> {
        if positions.len() != self.positions.len() * 3 {
            if !positions.len().is_multiple_of(3) {
                return Err(Error::PositionsLength {
                    len: positions.len(),
                });
            }
            return Err(Error::VertexCountMismatch {
                expected: self.positions.len(),
                got: positions.len() / 3,
            });
        }
        let extent = scan_positions(positions)?;
        for (dst, src) in self.positions.iter_mut().zip(positions.chunks_exact(3)) {
            *dst = [src[0], src[1], src[2]];
        }
        self.max_abs = extent.max_abs;
        self.safe = extent.safe;
        self.last_refit = self.update_spheres();
        Ok(self.last_refit)
    }

    /// [`Mesh::refit`] with each vertex's coordinates given by `position(i)` for `i` in
    /// `0..vertex_count`, for positions stored in another layout (interleaved, `f32`, ...). Each
    /// vertex is read twice: once to check every value, once to store it, so a failure leaves the
    /// mesh untouched and nothing is allocated.
    pub fn refit_with(
        &mut self,
        vertex_count: usize,
        position: impl Fn(usize) -> Point,
    ) -> Result<RefitStats> {
        if vertex_count != self.positions.len() {
            return Err(Error::VertexCountMismatch {
                expected: self.positions.len(),
                got: vertex_count,
            });
        }
        let extent = scan_points(vertex_count, &position)?;
        for (i, dst) in self.positions.iter_mut().enumerate() {
            *dst = position(i);
        }
        self.max_abs = extent.max_abs;
        self.safe = extent.safe;
        self.last_refit = self.update_spheres();
        Ok(self.last_refit)
    }

    /// [`Mesh::refit`] from points.
    pub fn refit_points(&mut self, positions: &[Point]) -> Result<RefitStats> {
        self.refit(positions.as_flattened())
    }

    /// Recomputes every sphere from the current positions, children before parents (children
    /// have higher indices).
    pub(crate) fn update_spheres(&mut self) -> RefitStats {
        for n in self.nodes.iter_mut() {
            n.centre = self.positions[n.centre_vertex as usize];
        }
        let mut stack = std::mem::take(&mut self.scratch);
        let mut evaluations = 0u64;
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let radius = if node.is_leaf() {
                let far = self.ring_farthest_squared(
                    &node.centre,
                    node.ring_start as usize,
                    &mut evaluations,
                );
                round_up(far.sqrt())
            } else {
                match self.options.radius {
                    RadiusKind::Wrapped => self.wrapped_radius(i, &mut stack, &mut evaluations),
                    RadiusKind::Layered => self.layered_radius(i, &mut evaluations),
                }
            };
            self.nodes[i].radius = radius;
        }
        self.scratch = stack;
        RefitStats {
            nodes_refit: self.nodes.len() as u64,
            distance_evaluations: evaluations,
        }
    }

    /// Largest squared distance from `c` to a vertex of ring `r`'s triangles.
    #[inline]
    fn ring_farthest_squared(&self, c: &Point, r: usize, evaluations: &mut u64) -> f64 {
        let verts = &self.ring_verts
            [self.ring_vert_start[r] as usize..self.ring_vert_start[r + 1] as usize];
        *evaluations += verts.len() as u64;
        let mut far = 0.0f64;
        for &v in verts {
            let d = distance_squared(c, &self.positions[v as usize]);
            // Not f64::max: its NaN rules cost a dependency chain; distances are never NaN.
            far = if d > far { d } else { far };
        }
        far
    }

    fn layered_radius(&self, i: usize, evaluations: &mut u64) -> f64 {
        let node = self.nodes[i];
        let c = node.centre;
        *evaluations += node.child_count as u64;
        let reach = node
            .children()
            .map(|ch| {
                let s = &self.nodes[ch as usize];
                distance_squared(&c, &s.centre).sqrt() + s.radius
            })
            .fold(0.0f64, f64::max);
        round_up(reach)
    }

    /// Farthest vertex below node `i` from its centre, by branch and bound over the subtree: a
    /// subtree is skipped when its sphere cannot hold a vertex farther than the best found. The
    /// centres of the nodes below are themselves vertices below, so they seed the bound.
    ///
    /// Rounding: every distance here is a floating-point estimate within a few ulps of the truth,
    /// and a subtree is only skipped when its estimated reach is at most the best estimate, so
    /// the true farthest distance is within a few ulps of the result, which [`round_up`] covers.
    fn wrapped_radius(&self, i: usize, stack: &mut Vec<u32>, evaluations: &mut u64) -> f64 {
        let c = self.nodes[i].centre;
        let mut best = 0.0f64;
        stack.clear();
        stack.extend(self.nodes[i].children());
        while let Some(x) = stack.pop() {
            let node = &self.nodes[x as usize];
            // Measured: a square root per node is cheaper than the branches of comparing squares.
            let d = distance_squared(&c, &node.centre).sqrt();
            *evaluations += 1;
            best = best.max(d);
            if d + node.radius <= best {
                continue;
            }
            if node.is_leaf() {
                let far = self.ring_farthest_squared(&c, node.ring_start as usize, evaluations);
                best = best.max(far.sqrt());
            } else {
                stack.extend(node.children());
            }
        }
        round_up(best)
    }
}
