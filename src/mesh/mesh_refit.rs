//! Refitting a [`Mesh`] to new vertex positions: the volumes only, no allocation.

use super::input::{scan_points, scan_positions};
use super::mesh::{Mesh, RefitStats};
use crate::error::{Error, Result};
use crate::geometry::predicates::Point;
use crate::volume::RefitInput;

impl Mesh {
    /// Takes new positions for every vertex (`x, y, z` each, same vertex count as at build) and
    /// recomputes every volume. For the DVH's spheres that is the radii only: their centres are
    /// mesh vertices, so they move with the positions.
    ///
    /// Errors: [`Error::VertexCountMismatch`], [`Error::PositionsLength`],
    /// [`Error::NonFiniteCoordinate`]. On error the mesh is exactly as it was.
    ///
    /// Cost: linear in the vertices for the leaves; above them, boxes and
    /// [`crate::RadiusKind::Layered`] radii are linear in the nodes, and
    /// [`crate::RadiusKind::Wrapped`] radii search each node's subtree for its farthest vertex,
    /// pruning subtrees whose spheres cannot hold a farther one (at worst vertices times depth).
    /// Allocates nothing.
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
        self.last_refit = self.update_volumes();
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
        self.last_refit = self.update_volumes();
        Ok(self.last_refit)
    }

    /// [`Mesh::refit`] from points.
    pub fn refit_points(&mut self, positions: &[Point]) -> Result<RefitStats> {
        self.refit(positions.as_flattened())
    }

    /// Recomputes every volume from the current positions.
    pub(crate) fn update_volumes(&mut self) -> RefitStats {
        let input = RefitInput {
            tree: &self.tree,
            rings: &self.rings,
            positions: &self.positions,
            radius: self.options.radius,
        };
        self.volumes.refit(&input, &mut self.scratch)
    }
}
