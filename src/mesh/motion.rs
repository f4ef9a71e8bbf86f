//! A mesh moving over a step: every vertex from a start to an end position in a straight line.
//! Its volumes hold the whole motion, so the traversal that serves the discrete queries finds
//! the candidates of continuous collision; its positions are the end positions.

use super::input::{Extent, store_points, store_positions};
use super::mesh::Mesh;
use crate::error::{Error, Instant, Result};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::Point;
use crate::volume::RefitStats;

/// The start positions of a moving mesh, and the room a motion refit checks new ones into.
#[derive(Clone, Debug, Default)]
pub(crate) struct Motion {
    /// The positions at t = 0, when `moving`.
    pub start: Vec<Point>,
    /// Where a motion refit checks the start positions before it knows all of its input is valid.
    pub spare: Vec<Point>,
    /// Per-node scratch for growing spheres.
    pub scratch: Vec<f64>,
    /// Did the last refit give a motion (rather than one set of positions)?
    pub moving: bool,
}

impl Motion {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        crate::csr::heap_bytes(&self.start)
            + crate::csr::heap_bytes(&self.spare)
            + crate::csr::heap_bytes(&self.scratch)
    }
}

impl Mesh {
    /// Takes a motion over one step: every vertex moves in a straight line from its position in
    /// `start` (t = 0) to its position in `end` (t = 1), each `x, y, z` per vertex with the
    /// vertex count of the build. The volumes are refit to hold every vertex's whole path, so
    /// [`crate::continuous_collide`] and [`crate::self_continuous_collide`] find every contact
    /// during the step; the mesh's positions become `end` (the discrete queries see the end of
    /// the step). A plain [`Mesh::refit`] makes the mesh stationary again.
    ///
    /// Errors: [`Error::Motion`], saying which positions, around [`Error::VertexCountMismatch`],
    /// [`Error::PositionsLength`] or [`Error::NonFiniteCoordinate`]. On error the mesh is
    /// exactly as it was.
    ///
    /// Cost: a refit to `end`, then one pass over the tree growing each volume by the start
    /// positions. Allocates only on the first motion (the room for the start positions).
    pub fn refit_motion(&mut self, start: &[f64], end: &[f64]) -> Result<RefitStats> {
        self.take_motion(start, end)?;
        let stats = self.refit_volumes();
        Ok(stats)
    }

    /// [`Mesh::refit_motion`]'s first half: checks the motion and stores it, leaving every
    /// volume as it was until [`Mesh::refit_volumes`] (a scene refits an object only when a
    /// query needs it). Returns the boxes of the start and the end positions. The same errors;
    /// on error the mesh is exactly as it was.
    pub(crate) fn take_motion(&mut self, start: &[f64], end: &[f64]) -> Result<(Aabb, Aabb)> {
        let expected = self.positions.len();
        let check = |p: &[f64], instant: Instant| -> Result<()> {
            let error = if !p.len().is_multiple_of(3) {
                Error::PositionsLength { len: p.len() }
            } else if p.len() != 3 * expected {
                Error::VertexCountMismatch {
                    expected,
                    got: p.len() / 3,
                }
            } else {
                return Ok(());
            };
            Err(Error::Motion {
                instant,
                error: Box::new(error),
            })
        };
        check(start, Instant::Start)?;
        check(end, Instant::End)?;
        let threads = self.scratch.len();
        self.store_motion(
            |room| store_positions(start, room, threads),
            |spare| store_positions(end, spare, threads),
        )
    }

    /// [`Mesh::take_motion`] with each vertex's coordinates at the start and the end given by
    /// `start(i)` and `end(i)` for `i` in `0..vertex_count`, for positions stored in another
    /// layout (`f32`, a stride).
    pub(crate) fn take_motion_with(
        &mut self,
        vertex_count: usize,
        start: impl Fn(usize) -> Point,
        end: impl Fn(usize) -> Point,
    ) -> Result<(Aabb, Aabb)> {
        let expected = self.positions.len();
        if vertex_count != expected {
            return Err(Error::Motion {
                instant: Instant::Start,
                error: Box::new(Error::VertexCountMismatch {
                    expected,
                    got: vertex_count,
                }),
            });
        }
        self.store_motion(
            |room| store_points(&start, room),
            |spare| store_points(&end, spare),
        )
    }

    /// Stores a motion's start (into the room kept for it) and end (into the spare positions),
    /// each checked by its `store`; makes both current only when both are valid.
    fn store_motion(
        &mut self,
        store_start: impl FnOnce(&mut [Point]) -> Result<Extent>,
        store_end: impl FnOnce(&mut [Point]) -> Result<Extent>,
    ) -> Result<(Aabb, Aabb)> {
        let wrap = |instant| {
            move |error| Error::Motion {
                instant,
                error: Box::new(error),
            }
        };
        let mut room = std::mem::take(&mut self.motion.spare);
        room.resize(self.positions.len(), [0.0; 3]);
        let first = match store_start(&mut room) {
            Ok(extent) => extent,
            Err(e) => {
                self.motion.spare = room;
                return Err(wrap(Instant::Start)(e));
            }
        };
        let extent = match store_end(&mut self.spare) {
            Ok(extent) => extent,
            Err(e) => {
                self.motion.spare = room;
                return Err(wrap(Instant::End)(e));
            }
        };
        self.install(extent);
        self.motion.spare = std::mem::replace(&mut self.motion.start, room);
        self.motion.moving = true;
        Ok((first.bounds, extent.bounds))
    }

    /// [`Mesh::refit_motion`] from points.
    pub fn refit_motion_points(&mut self, start: &[Point], end: &[Point]) -> Result<RefitStats> {
        self.refit_motion(start.as_flattened(), end.as_flattened())
    }

    /// The positions at the start of the step of the last [`Mesh::refit_motion`]; the current
    /// positions when the mesh is stationary (built or refit without a motion since).
    pub fn start_positions(&self) -> &[Point] {
        if self.motion.moving {
            &self.motion.start
        } else {
            &self.positions
        }
    }

    /// Was the mesh last given a motion ([`Mesh::refit_motion`]) rather than positions?
    pub fn is_moving(&self) -> bool {
        self.motion.moving
    }
}
