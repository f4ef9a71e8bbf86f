//! Scenes: many objects, rigid or deformable, sharing meshes, with one query per question a
//! simulator asks of a whole frame or step: which triangles intersect ([`Scene::collide`]), when
//! primitives first meet during the step ([`Scene::continuous_collide`]), which features are
//! within a distance ([`Scene::nearest_features`]).
//!
//! An object is a copy of a mesh's state (positions and volumes) that shares the mesh's topology,
//! rings and tree ([`Mesh`] clones share them), with a pose (rigid) or positions of its own
//! (deformable), and a step it moves through (a start and an end pose, or start and end
//! positions). The scene spends work where contact is possible: a broad phase
//! ([`broad::SweepAndPrune`]) over the objects' world boxes (at the end of the step for the
//! discrete queries, over the whole step for continuous collision), collision filters, and
//! refits of deformable objects put off until a query needs their volumes.

mod broad;
mod collide;
mod continuous;
mod distance;
mod nearest;
mod refit;
mod select;
mod share;

pub use collide::{Contact, Contacts, SceneStats};
pub use continuous::{SceneImpact, SceneImpacts};
pub use distance::SceneDistance;
pub use nearest::{SceneNearPair, SceneNearPairs};

use crate::error::{Error, Result};
use crate::geometry::MAX_POSED_MAGNITUDE;
use crate::geometry::aabb::Aabb;
use crate::geometry::pose::Pose;
use crate::mesh::Mesh;
use crate::query::QueryOptions;
use crate::volume::{Freshness, Volumes};
use broad::SweepAndPrune;
use std::collections::{HashMap, HashSet};
use std::sync::{Arc, Weak};

/// What an object is: a rigid body placed by a pose, or a deformable one with positions of its
/// own.
#[derive(Clone, Debug)]
// Objects are few and read on every query: the rigid variant's two poses stay inline.
#[allow(clippy::large_enum_variant)]
enum Body {
    /// Its mesh's positions at the time it was added, as local coordinates, placed by a pose;
    /// never refit. `local` bounds those positions. `start`: the pose at the start of its
    /// step, when it was given one (`pose` is the end's).
    Rigid {
        pose: Pose,
        local: LocalBounds,
        start: Option<Pose>,
    },
    /// Positions of its own, in world coordinates. `fresh`: which of its volumes are current
    /// (none after new positions; boxes are then refit lazily, block by block).
    Deformable { fresh: Freshness },
}

/// One object of a scene.
#[derive(Clone, Debug)]
struct Object {
    /// Shared by the rigid objects made from one state of one mesh; a deformable object's own.
    mesh: Arc<Mesh>,
    body: Body,
    group: u32,
    mask: u32,
    /// Changes whenever the object's geometry or pose does (drawn from [`Scene::stamps`], so an
    /// object that takes a removed one's id never has its stamp).
    stamp: u64,
    /// Are the object's contacts with itself wanted? (Deformable objects only.)
    self_contact: bool,
    /// A posed rigid object's vertices in world coordinates over its step, for continuous
    /// collision (whose primitive tests take world positions), made when a query first needs
    /// them at the object's current stamp.
    world: Option<Box<WorldCopy>>,
}

/// A rigid object's mesh with world positions: at the start and the end of its step (its volumes
/// holding the motion), or at its pose when it has no step.
#[derive(Clone, Debug)]
struct WorldCopy {
    /// The object's stamp when it was made.
    stamp: u64,
    mesh: Mesh,
    /// The world positions at the start and the end of the step, kept for the next placing.
    start: Vec<[f64; 3]>,
    end: Vec<[f64; 3]>,
}

impl Object {
    /// A new object (stamp 0, self-contact off, no world copy yet).
    fn new(mesh: Arc<Mesh>, body: Body, group: u32, mask: u32) -> Object {
        Object {
            mesh,
            body,
            group,
            mask,
            stamp: 0,
            self_contact: false,
            world: None,
        }
    }

    /// The pose to query the object with (`None` for world coordinates).
    fn pose(&self) -> Option<&Pose> {
        match &self.body {
            Body::Rigid { pose, .. } => Some(pose),
            Body::Deformable { .. } => None,
        }
    }

    /// The mesh whose positions (and start positions) are the object's in world coordinates
    /// over its step: a deformable object's own, a rigid object's world copy (its own mesh when
    /// it stands still at the identity). The world copy must be current
    /// ([`Scene::place_rigid`]).
    fn world_mesh(&self) -> &Mesh {
        match &self.body {
            Body::Rigid {
                pose, start: None, ..
            } if pose.is_identity() => &self.mesh,
            Body::Rigid { .. } => {
                let copy = self.world.as_ref().expect("the world copy was made");
                debug_assert_eq!(copy.stamp, self.stamp);
                &copy.mesh
            }
            Body::Deformable { .. } => &self.mesh,
        }
    }
}

/// A set of objects queried together: [`Scene::collide`] finds every contact between every two
/// objects that the collision filters allow and whose world boxes overlap.
///
/// Objects are named by small integer ids, stable until the object is removed; a removed id may
/// be given to a later object. Every method that fails leaves the scene exactly as it was.
///
/// Threads: a scene is changed through `&mut` and queried through `&mut` (the query refits
/// the deformable objects it needs); one scene may be used from one thread at a time, several
/// scenes from several threads at once.
///
/// The README's "Scenes" section shows one in use (tested with the crate's doctests).
#[derive(Clone, Debug, Default)]
pub struct Scene {
    objects: Vec<Option<Object>>,
    /// Removed ids, reused last removed first.
    free: Vec<u32>,
    /// World boxes by id at the end of each object's step (empty for free ids).
    boxes: Vec<Aabb>,
    broad: SweepAndPrune,
    /// World boxes by id over each object's whole step (equal to `boxes` for an object without
    /// one), and their broad phase.
    swept: Vec<Aabb>,
    broad_swept: SweepAndPrune,
    /// The end boxes grown by half the distance of the last nearness query (which the bits of
    /// `near_distance` hold), and their broad phase.
    near_boxes: Vec<Aabb>,
    near: SweepAndPrune,
    near_distance: Option<u64>,
    /// Pairs `(lower id, higher id)` never tested.
    excluded: HashSet<(u32, u32)>,
    /// Candidate pairs of the last query (kept so that queries reuse its memory).
    candidates: Vec<(u32, u32)>,
    /// Per object, what the last query's candidates asked of it (`select::marks`; kept for
    /// its memory).
    marks: Vec<u8>,
    /// The last stamp given to an object.
    stamps: u64,
    /// Object pairs the last query found without contact, with what they were then: such a pair
    /// is not queried again while neither object changes and the options stay the same.
    apart: HashMap<(u32, u32), Apart>,
    /// Scratch for the next `apart`.
    apart_next: HashMap<(u32, u32), Apart>,
    /// The copies rigid objects share, by the [`Mesh::state`] they were made from, with the
    /// bounds of their positions.
    snapshots: HashMap<u64, (Weak<Mesh>, LocalBounds)>,
    /// Refit every deformable object a query needs whole, not block by block.
    eager: bool,
}

/// What an object pair without contact was queried with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Apart {
    stamps: (u64, u64),
    /// The options, their thread count set to 0 (the answer does not depend on it).
    options: QueryOptions,
}

impl Scene {
    /// An empty scene.
    pub fn new() -> Scene {
        Scene::default()
    }

    /// Whether a query refits box volumes lazily, block by block as traversals reach them (the
    /// default, `true`), or every deformable object it needs whole, as before the query starts
    /// (`false`). The results are the same; lazy refit skips the parts of objects no other object
    /// comes near, eager refit costs the same whatever the contact (`BENCHMARKS.md` measures
    /// both).
    pub fn set_lazy_refit(&mut self, lazy: bool) {
        self.eager = !lazy;
    }

    /// Number of objects.
    pub fn len(&self) -> usize {
        self.objects.len() - self.free.len()
    }

    /// No objects?
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Adds a rigid object: `mesh`'s current positions as local coordinates, placed by `pose`
    /// (`None`: the identity). It shares `mesh`'s topology, rings and tree and keeps a copy of
    /// the positions and volumes, so `mesh` may be refit or dropped afterwards; rigid objects
    /// made from the same positions of one mesh share that copy. Objects `i`
    /// and `j` are tested when `group_i & mask_j` and `group_j & mask_i` are both non-zero.
    ///
    /// Errors: [`Error::ObjectPoseOutOfRange`] when the pose could move the mesh's coordinates
    /// beyond [`MAX_POSED_MAGNITUDE`]; [`Error::OutOfMemory`] when the object's copy cannot be
    /// allocated.
    pub fn add_rigid(
        &mut self,
        mesh: &Mesh,
        pose: Option<&Pose>,
        group: u32,
        mask: u32,
    ) -> Result<u32> {
        let pose = pose.copied().unwrap_or_default();
        let shared = self
            .snapshots
            .get(&mesh.state())
            .and_then(|(copy, local)| Some((copy.upgrade()?, *local)));
        self.make_room(if shared.is_some() {
            0
        } else {
            mesh.state_bytes()
        })?;
        let local = shared
            .as_ref()
            .map_or_else(|| LocalBounds::of(mesh.positions()), |s| s.1);
        let world = local.posed(&pose, mesh.max_abs_coordinate())?;
        let mesh = match shared {
            Some((copy, _)) => copy,
            None => {
                let mut copy = mesh.clone();
                // A rigid object is never refit: no room for new positions.
                copy.drop_spare();
                let copy = Arc::new(copy);
                self.snapshots
                    .insert(mesh.state(), (Arc::downgrade(&copy), local));
                copy
            }
        };
        let body = Body::Rigid {
            pose,
            local,
            start: None,
        };
        Ok(self.insert(Object::new(mesh, body, group, mask), world))
    }

    /// Adds a deformable object: `mesh`'s current positions as world coordinates, changed by
    /// [`Scene::set_positions`]. It shares `mesh`'s topology, rings and tree and keeps its own
    /// positions and volumes, so `mesh` may be refit or dropped afterwards. Filters as for
    /// [`Scene::add_rigid`].
    ///
    /// Errors: [`Error::OutOfMemory`] when the object's copy cannot be allocated.
    pub fn add_deformable(&mut self, mesh: &Mesh, group: u32, mask: u32) -> Result<u32> {
        self.make_room(mesh.state_bytes())?;
        let world = Aabb::of_points(mesh.positions());
        let body = Body::Deformable {
            fresh: Freshness::current(),
        };
        Ok(self.insert(
            Object::new(Arc::new(mesh.clone()), body, group, mask),
            world,
        ))
    }

    /// Fails with [`Error::OutOfMemory`] unless a new object's copy of `bytes` and the scene's
    /// tables' growth can be allocated: Rust aborts on a failed allocation, so the copy is
    /// asked for once, fallibly, and given back (under overcommit no page is touched).
    fn make_room(&mut self, bytes: usize) -> Result<()> {
        let oom = |bytes| Error::OutOfMemory { bytes };
        if self.free.is_empty() {
            self.objects.try_reserve(1).map_err(|_| oom(1))?;
            self.boxes.try_reserve(1).map_err(|_| oom(1))?;
            self.swept.try_reserve(1).map_err(|_| oom(1))?;
        }
        let mut probe: Vec<u8> = Vec::new();
        probe.try_reserve_exact(bytes).map_err(|_| oom(bytes))
    }

    /// Object `id`, named by a query's candidate pair (so it is live).
    fn candidate(&self, id: u32) -> &Object {
        self.objects[id as usize]
            .as_ref()
            .expect("a candidate is live")
    }

    fn next_stamp(&mut self) -> u64 {
        self.stamps += 1;
        self.stamps
    }

    fn insert(&mut self, mut object: Object, world: Aabb) -> u32 {
        object.stamp = self.next_stamp();
        let id = match self.free.pop() {
            Some(id) => {
                self.objects[id as usize] = Some(object);
                self.boxes[id as usize] = world;
                self.swept[id as usize] = world;
                id
            }
            None => {
                self.objects.push(Some(object));
                self.boxes.push(world);
                self.swept.push(world);
                (self.objects.len() - 1) as u32
            }
        };
        self.broad.insert(id);
        self.broad_swept.insert(id);
        self.near.insert(id);
        id
    }

    fn object(&self, id: u32) -> Result<&Object> {
        self.objects
            .get(id as usize)
            .and_then(Option::as_ref)
            .ok_or(Error::UnknownObject { object: id })
    }

    fn object_mut(&mut self, id: u32) -> Result<&mut Object> {
        self.objects
            .get_mut(id as usize)
            .and_then(Option::as_mut)
            .ok_or(Error::UnknownObject { object: id })
    }

    /// Is `id` an object of the scene?
    pub fn contains(&self, id: u32) -> bool {
        self.object(id).is_ok()
    }

    /// Number of vertices of object `id`'s mesh.
    ///
    /// Errors: [`Error::UnknownObject`].
    pub fn vertex_count(&self, id: u32) -> Result<usize> {
        Ok(self.object(id)?.mesh.vertex_count())
    }

    /// Is object `id` rigid? (`None` for an unknown id.)
    pub fn is_rigid(&self, id: u32) -> Option<bool> {
        self.object(id)
            .ok()
            .map(|o| matches!(o.body, Body::Rigid { .. }))
    }

    /// Places rigid object `id` by `pose` (`None`: the identity), standing still there: its step,
    /// if it had one, ends.
    ///
    /// Errors: [`Error::UnknownObject`]; [`Error::WrongObjectKind`] for a deformable object;
    /// [`Error::Object`] wrapping [`Error::ObjectPoseOutOfRange`] as for [`Scene::add_rigid`].
    pub fn set_pose(&mut self, id: u32, pose: Option<&Pose>) -> Result<()> {
        self.place(id, None, pose.copied().unwrap_or_default())
    }

    /// Gives rigid object `id` a step: from pose `start` to pose `end` (`None`: the identity),
    /// each vertex moving in a straight line from its start-pose to its end-pose world
    /// position, each computed as [`Scene::collide`] places a vertex
    /// ([`Pose::transform_point`]). The discrete queries see the object at `end`;
    /// [`Scene::continuous_collide`] sees the whole step. The step lasts until the next
    /// [`Scene::set_pose`] or `set_pose_motion`.
    ///
    /// Straight paths are what simulators of the IPC kind assume; they are not the turn itself:
    /// a large rotation in one step shortens the object midway (a half turn passes every vertex
    /// through the axis), so steps should turn little.
    ///
    /// Errors: [`Error::UnknownObject`]; [`Error::WrongObjectKind`] for a deformable object;
    /// [`Error::Object`] wrapping [`Error::ObjectPoseOutOfRange`] for either pose, as for
    /// [`Scene::add_rigid`].
    pub fn set_pose_motion(
        &mut self,
        id: u32,
        start: Option<&Pose>,
        end: Option<&Pose>,
    ) -> Result<()> {
        let first = start.copied().unwrap_or_default();
        self.place(id, Some(first), end.copied().unwrap_or_default())
    }

    /// Places rigid object `id` at pose `end`, with a step from `first` when given (standing
    /// still otherwise): [`Scene::set_pose`] and [`Scene::set_pose_motion`].
    fn place(&mut self, id: u32, first: Option<Pose>, end: Pose) -> Result<()> {
        let stamp = self.stamps + 1;
        let object = self.object_mut(id)?;
        let max_abs = object.mesh.max_abs_coordinate();
        let Body::Rigid { pose, local, start } = &mut object.body else {
            return Err(Error::WrongObjectKind {
                object: id,
                rigid: false,
            });
        };
        let wrap = |e| Error::Object {
            object: id,
            error: Box::new(e),
        };
        let at_start = first
            .as_ref()
            .map(|p| local.posed(p, max_abs))
            .transpose()
            .map_err(wrap)?;
        let world = local.posed(&end, max_abs).map_err(wrap)?;
        *pose = end;
        *start = first;
        object.stamp = stamp;
        let mut swept = at_start.unwrap_or(world);
        swept.merge(&world);
        self.moved(id, stamp, world, swept);
        Ok(())
    }

    /// Gives deformable object `id` new world positions (`x, y, z` per vertex, as many vertices
    /// as its mesh), standing still there: its step, if it had one, ends. They are checked and
    /// stored now; the volumes are recomputed by the next query that needs them, so an object
    /// that no overlapping pair reaches costs no more than taking its positions.
    ///
    /// Errors: [`Error::UnknownObject`]; [`Error::WrongObjectKind`] for a rigid object;
    /// [`Error::Object`] wrapping the errors of [`Mesh::refit`] (a wrong length or vertex count,
    /// a non-finite coordinate).
    pub fn set_positions(&mut self, id: u32, positions: &[f64]) -> Result<()> {
        self.take_positions(id, |mesh| {
            mesh.take_positions(positions).map(|world| (world, world))
        })
    }

    /// [`Scene::set_positions`] with each vertex's coordinates given by `position(i)` for `i` in
    /// `0..vertex_count`, for positions stored in another layout (`f32`, a stride).
    pub fn set_positions_with(
        &mut self,
        id: u32,
        vertex_count: usize,
        position: impl Fn(usize) -> [f64; 3],
    ) -> Result<()> {
        self.take_positions(id, |mesh| {
            mesh.take_points_with(vertex_count, position)
                .map(|world| (world, world))
        })
    }

    /// Gives deformable object `id` a step: every vertex moves in a straight line from its
    /// position in `start` to its position in `end` (`x, y, z` per vertex, as many vertices as
    /// its mesh), as [`Mesh::refit_motion`] takes them. The discrete queries see the object at
    /// `end`; [`Scene::continuous_collide`] sees the whole step. The step lasts until the next
    /// `set_motion` or [`Scene::set_positions`]. Checked and stored now, refit when a query
    /// needs the object.
    ///
    /// Errors: [`Error::UnknownObject`]; [`Error::WrongObjectKind`] for a rigid object;
    /// [`Error::Object`] wrapping the errors of [`Mesh::refit_motion`] ([`Error::Motion`],
    /// saying which positions and what was wrong with them).
    pub fn set_motion(&mut self, id: u32, start: &[f64], end: &[f64]) -> Result<()> {
        self.take_positions(id, |mesh| mesh.take_motion(start, end))
    }

    /// [`Scene::set_motion`] with each vertex's coordinates at the start and the end given by
    /// `start(i)` and `end(i)` for `i` in `0..vertex_count`, for positions stored in another
    /// layout (`f32`, a stride).
    pub fn set_motion_with(
        &mut self,
        id: u32,
        vertex_count: usize,
        start: impl Fn(usize) -> [f64; 3],
        end: impl Fn(usize) -> [f64; 3],
    ) -> Result<()> {
        self.take_positions(id, |mesh| mesh.take_motion_with(vertex_count, start, end))
    }

    /// Stores what `take` checks into deformable object `id`'s mesh; `take` returns the boxes
    /// of the positions at the start and the end of the step (equal when there is no step).
    fn take_positions(
        &mut self,
        id: u32,
        take: impl FnOnce(&mut Mesh) -> Result<(Aabb, Aabb)>,
    ) -> Result<()> {
        let stamp = self.stamps + 1;
        let object = self.object_mut(id)?;
        let Body::Deformable { fresh } = &mut object.body else {
            return Err(Error::WrongObjectKind {
                object: id,
                rigid: true,
            });
        };
        let (at_start, world) =
            take(Arc::make_mut(&mut object.mesh)).map_err(|e| Error::Object {
                object: id,
                error: Box::new(e),
            })?;
        fresh.stale();
        object.stamp = stamp;
        let mut swept = at_start;
        swept.merge(&world);
        self.moved(id, stamp, world, swept);
        Ok(())
    }

    /// Records that object `id` now has stamp `stamp`, world box `world` at the end of its
    /// step and `swept` over the step.
    fn moved(&mut self, id: u32, stamp: u64, world: Aabb, swept: Aabb) {
        self.stamps = stamp;
        self.boxes[id as usize] = world;
        self.broad.touch(id);
        self.swept[id as usize] = swept;
        self.broad_swept.touch(id);
        self.near.touch(id);
    }

    /// Turns object `id`'s self-contact on or off (off when added): when on,
    /// [`Scene::collide`] also reports the object's self-intersecting triangle pairs (as
    /// [`crate::self_collide`] does, with `object_a == object_b`), and
    /// [`Scene::continuous_collide`] and [`Scene::nearest_features`] its self impacts and self
    /// stencils. Groups, masks and exclusions do not gate self-contact; this switch does.
    ///
    /// Errors: [`Error::UnknownObject`]; [`Error::RigidSelfContact`] when turning it on for a
    /// rigid object (turning it off is accepted).
    pub fn set_self_contact(&mut self, id: u32, on: bool) -> Result<()> {
        let object = self.object_mut(id)?;
        if on && matches!(object.body, Body::Rigid { .. }) {
            return Err(Error::RigidSelfContact { object: id });
        }
        object.self_contact = on;
        Ok(())
    }

    /// Is object `id`'s self-contact on? (`None` for an unknown id.)
    pub fn self_contact(&self, id: u32) -> Option<bool> {
        self.object(id).ok().map(|o| o.self_contact)
    }

    /// Removes object `id` (and its pair exclusions); its id may be given to a later object.
    ///
    /// Errors: [`Error::UnknownObject`].
    pub fn remove(&mut self, id: u32) -> Result<()> {
        self.object(id)?;
        self.objects[id as usize] = None;
        self.boxes[id as usize] = Aabb::EMPTY;
        self.swept[id as usize] = Aabb::EMPTY;
        self.free.push(id);
        self.broad.remove(id);
        self.broad_swept.remove(id);
        self.near.remove(id);
        self.excluded.retain(|&(i, j)| i != id && j != id);
        self.snapshots
            .retain(|_, (copy, _)| copy.strong_count() > 0);
        Ok(())
    }

    /// Never tests objects `a` and `b` against each other (until one of them is removed).
    ///
    /// Errors: [`Error::UnknownObject`]; [`Error::SameObject`] when `a == b`.
    pub fn exclude_pair(&mut self, a: u32, b: u32) -> Result<()> {
        self.object(a)?;
        self.object(b)?;
        if a == b {
            return Err(Error::SameObject { object: a });
        }
        self.excluded.insert((a.min(b), a.max(b)));
        Ok(())
    }

    /// Bytes of memory the scene holds beyond the struct itself: each object's own positions,
    /// volumes and scratch (once for the rigid objects that share them), and the scene's tables. Not the topology, rings and tree the objects
    /// share with the meshes they were made from ([`Mesh::memory_bytes`] counts those).
    pub fn memory_bytes(&self) -> usize {
        let mut seen = HashSet::new();
        self.objects
            .iter()
            .flatten()
            .filter(|o| seen.insert(Arc::as_ptr(&o.mesh)))
            .map(|o| o.mesh.state_bytes())
            .sum::<usize>()
            + self
                .objects
                .iter()
                .flatten()
                .filter_map(|o| o.world.as_ref())
                .map(|w| w.mesh.state_bytes())
                .sum::<usize>()
            + self.objects.capacity() * std::mem::size_of::<Option<Object>>()
            + (self.boxes.capacity() + self.swept.capacity()) * std::mem::size_of::<Aabb>()
    }
}

/// What a rigid object keeps to bound itself wherever its pose puts it: the box of its local
/// positions and a ball around them. A turned box's axis-aligned box grows up to `√3` times;
/// the ball's does not, so the world box is the intersection of both (both hold every vertex).
#[derive(Clone, Copy, Debug)]
struct LocalBounds {
    aabb: Aabb,
    centre: [f64; 3],
    radius: f64,
}

impl LocalBounds {
    fn of(points: &[[f64; 3]]) -> LocalBounds {
        let aabb = Aabb::of_points(points);
        let centre = aabb.centre();
        let radius = points
            .iter()
            .map(|p| crate::geometry::sphere::distance_squared(p, &centre))
            .fold(0.0, f64::max)
            .sqrt();
        LocalBounds {
            aabb,
            centre,
            radius: crate::geometry::sphere::round_up(radius),
        }
    }

    /// The world box of the points placed by `pose` (as [`posed_box`], tightened by the ball).
    fn posed(&self, pose: &Pose, max_abs: f64) -> Result<Aabb> {
        let corners = posed_box(pose, &self.aabb, max_abs)?;
        if pose.is_identity() || self.aabb.is_empty() {
            return Ok(corners);
        }
        // The centre moves within `error` of its exact image, every vertex too; the ball's radius
        // grows by the rotation's stretch.
        let (error, _) = pose.rounding_bound(max_abs);
        let c = pose.transform_point(&self.centre);
        let h = (self.radius * pose.stretch() + 2.0 * error) * (1.0 + 64.0 * f64::EPSILON);
        Ok(Aabb {
            lo: [0, 1, 2].map(|k| corners.lo[k].max((c[k] - h).next_down())),
            hi: [0, 1, 2].map(|k| corners.hi[k].min((c[k] + h).next_up())),
        })
    }
}

/// The world box of the points of `local` placed by `pose`: the box of its transformed corners,
/// widened by twice the transformation's rounding bound so that it holds every transformed
/// vertex as the query computes it, and outwards by one unit in the last place for the rounding
/// of the widening itself.
fn posed_box(pose: &Pose, local: &Aabb, max_abs: f64) -> Result<Aabb> {
    let (error, magnitude) = pose.rounding_bound(max_abs);
    if magnitude > MAX_POSED_MAGNITUDE {
        return Err(Error::ObjectPoseOutOfRange { bound: magnitude });
    }
    if pose.is_identity() || local.is_empty() {
        return Ok(*local);
    }
    let mut world = Aabb::EMPTY;
    for corner in 0..8 {
        let p = [0, 1, 2].map(|k| {
            if corner & (1 << k) == 0 {
                local.lo[k]
            } else {
                local.hi[k]
            }
        });
        world.grow(&pose.transform_point(&p));
    }
    let w = 2.0 * error;
    Ok(Aabb {
        lo: world.lo.map(|x| (x - w).next_down()),
        hi: world.hi.map(|x| (x + w).next_up()),
    })
}

/// A box around object `o`'s root volume as a query computes it (moved by the object's pose):
/// if two objects' boxes are apart, a query between them fails the roots' test and reports
/// nothing, in every mode. Spheres are widened by far more than the rounding the overlap tests
/// allow for (16 units in the last place of squared distances).
fn volume_box(o: &Object) -> Aabb {
    let mesh = &o.mesh;
    let pose = o.pose().filter(|p| !p.is_identity());
    let sphere = match mesh.volumes() {
        Volumes::Dvh { spheres, .. } | Volumes::Sbv { spheres, .. } => spheres[0],
        Volumes::Aabb { boxes } => {
            return match pose {
                None => boxes[0],
                Some(p) => posed_box(p, &boxes[0], mesh.max_abs_coordinate()).unwrap_or(Aabb {
                    lo: [f64::NEG_INFINITY; 3],
                    hi: [f64::INFINITY; 3],
                }),
            };
        }
    };
    let (centre, radius) = match pose {
        None => (sphere.centre, sphere.radius),
        Some(p) => {
            let (error, _) = p.rounding_bound(mesh.max_abs_coordinate());
            (
                p.transform_point(&sphere.centre),
                sphere.radius * p.stretch() + 2.0 * error,
            )
        }
    };
    let h = radius * (1.0 + 64.0 * f64::EPSILON);
    Aabb {
        lo: centre.map(|c| (c - h).next_down()),
        hi: centre.map(|c| (c + h).next_up()),
    }
}

#[cfg(test)]
mod step_tests;
#[cfg(test)]
mod tests;
