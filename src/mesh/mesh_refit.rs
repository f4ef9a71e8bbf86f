//! Refitting a [`Mesh`] to new vertex positions: the volumes only, no allocation.

use super::input::{Extent, store_points, store_positions};
use super::mesh::Mesh;
use crate::error::{Error, Result};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::volume::{Blocks, Freshness, RefitStats, Volumes};

impl Mesh {
    /// Takes new positions for every vertex (`x, y, z` each, same vertex count as at build) and
    /// recomputes every volume. The input is read once, in order: checked and stored in one
    /// pass (into a spare buffer, so that a failure changes nothing), then the volumes are
    /// computed from the stored copy. For the DVH's spheres that is the radii only: their centres are
    /// mesh vertices, so they move with the positions.
    ///
    /// Errors: [`Error::VertexCountMismatch`], [`Error::PositionsLength`],
    /// [`Error::NonFiniteCoordinate`]. On error the mesh is exactly as it was.
    ///
    /// Cost: linear in the vertices for the leaves; above them, boxes and
    /// [`crate::RadiusKind::Layered`] radii are linear in the nodes, and
    /// [`crate::RadiusKind::Wrapped`] radii search each node's subtree for its farthest vertex,
    /// pruning subtrees whose spheres cannot hold a farther one (at worst vertices times depth).
    ///
    /// Threads: as many as [`crate::BuildOptions::refit_threads`] allows, for meshes of 8,192
    /// rings or more (the positions are stored in halves, the subtrees of a cut through the
    /// tree refit at once); the volumes are the same whatever the count. On one thread nothing
    /// is allocated; on more, one small job per extra thread and step.
    pub fn refit(&mut self, positions: &[f64]) -> Result<RefitStats> {
        self.take_positions(positions)?;
        self.last_refit = self.update_volumes();
        Ok(self.last_refit)
    }

    /// [`Mesh::refit`]'s first half: checks `positions` and makes them current, leaving every
    /// volume as it was until [`Mesh::update_volumes`] (a scene refits an object only when a
    /// query needs it). Returns their box. The same errors; on error the mesh is exactly as it
    /// was.
    pub(crate) fn take_positions(&mut self, positions: &[f64]) -> Result<Aabb> {
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
        let extent = store_positions(positions, &mut self.spare, self.scratch.len())?;
        self.install(extent);
        Ok(extent.bounds)
    }

    /// [`Mesh::refit`] with each vertex's coordinates given by `position(i)` for `i` in
    /// `0..vertex_count`, for positions stored in another layout (interleaved, `f32`, ...). Each
    /// vertex is read once; a failure leaves the mesh untouched; nothing is allocated.
    pub fn refit_with(
        &mut self,
        vertex_count: usize,
        position: impl Fn(usize) -> Point,
    ) -> Result<RefitStats> {
        self.take_points_with(vertex_count, position)?;
        self.last_refit = self.update_volumes();
        Ok(self.last_refit)
    }

    /// [`Mesh::take_positions`] for [`Mesh::refit_with`]'s input.
    pub(crate) fn take_points_with(
        &mut self,
        vertex_count: usize,
        position: impl Fn(usize) -> Point,
    ) -> Result<Aabb> {
        if vertex_count != self.positions.len() {
            return Err(Error::VertexCountMismatch {
                expected: self.positions.len(),
                got: vertex_count,
            });
        }
        let extent = store_points(position, &mut self.spare)?;
        self.install(extent);
        Ok(extent.bounds)
    }

    /// [`Mesh::refit`] from points.
    pub fn refit_points(&mut self, positions: &[Point]) -> Result<RefitStats> {
        self.refit(positions.as_flattened())
    }

    /// Makes the checked positions in the spare buffer current.
    pub(super) fn install(&mut self, extent: Extent) {
        std::mem::swap(&mut self.positions, &mut self.spare);
        self.motion.moving = false;
        self.max_abs = extent.max_abs;
        self.in_fast_range = extent.in_fast_range;
        self.state = super::mesh::next_state();
        self.patch_cache.clear();
    }

    /// Recomputes every volume from the current positions.
    pub(crate) fn update_volumes(&mut self) -> RefitStats {
        let input = self
            .topology
            .refit_input(self.options.radius, &self.positions);
        self.volumes.refit(&input, &mut self.scratch)
    }

    /// Recomputes every volume from the current positions, grown to hold the motion's start
    /// positions when the mesh was given a motion, and records the counters.
    pub(crate) fn refit_volumes(&mut self) -> RefitStats {
        let stats = self.update_volumes();
        if self.motion.moving {
            let input = self
                .topology
                .refit_input(self.options.radius, &self.positions);
            self.volumes
                .hold_start(&input, &self.motion.start, &mut self.motion.scratch);
        }
        self.last_refit = stats;
        stats
    }

    /// With box volumes, refits only the top of the tree, the blocks below it refit as a query
    /// first reads them (`fresh` says which are current); `false`, and nothing done, for spheres.
    pub(crate) fn refit_top(&mut self, fresh: &mut Freshness) -> bool {
        let Volumes::Aabb { boxes } = &mut self.volumes else {
            return false;
        };
        let input = self
            .topology
            .refit_input(self.options.radius, &self.positions);
        let blocks = self
            .topology
            .blocks
            .get_or_init(|| Blocks::new(&input, self.positions.len()));
        fresh.fit_top(blocks, &input, boxes);
        true
    }
}
