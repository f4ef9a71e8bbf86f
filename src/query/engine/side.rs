//! One mesh of a query as the traversal and the narrow phase see it: its shape, and its
//! vertices and volumes in the query's common frame.
//!
//! A side is a placement (the mesh's own coordinates, or moved by a pose) times a volume kind
//! (vertex-centred spheres, free spheres, boxes). Both are static types, so the traversal is
//! compiled once per combination with every volume test inlined. Two meshes of different kinds
//! meet through [`MixedVolumes`], which decides the kind per volume at run time: such queries
//! are rare, and typing them too would compile the traversal for six more pairs of kinds per
//! pair of placements (most of the library's build time).

use super::workspace::Stamped;
use crate::geometry::aabb::Aabb;
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::geometry::sphere::Sphere;
use crate::mesh::Mesh;
use crate::tree::Node;
use crate::volume::{LazyBoxes, Volumes};

/// A bounding volume in the query frame: what the traversal tests and compares.
pub(crate) trait Volume: Copy {
    /// A size comparable across kinds: the squared radius of a ball that holds the volume.
    fn size_squared(&self) -> f64;
    /// Might this volume share a point with the ball `s`? Never `false` when it does.
    fn meets_sphere(&self, s: &Sphere) -> bool;
    /// Might this volume share a point with the box `b`? Never `false` when it does.
    fn meets_box(&self, b: &Aabb) -> bool;
    /// Might the two volumes share a point? Never `false` when they do.
    fn overlaps<V: Volume>(&self, other: &V) -> bool;
    /// The volume grown by `d >= 0`, rounded outwards: it holds every point within distance `d`
    /// of this volume.
    fn widened(&self, d: f64) -> Self;
}

impl Volume for Sphere {
    #[inline(always)]
    fn size_squared(&self) -> f64 {
        self.radius * self.radius
    }

    #[inline(always)]
    fn meets_sphere(&self, s: &Sphere) -> bool {
        self.meets(s)
    }

    #[inline(always)]
    fn meets_box(&self, b: &Aabb) -> bool {
        Sphere::meets_box(self, b)
    }

    #[inline(always)]
    fn overlaps<V: Volume>(&self, other: &V) -> bool {
        other.meets_sphere(self)
    }

    #[inline(always)]
    fn widened(&self, d: f64) -> Sphere {
        Sphere {
            centre: self.centre,
            radius: (self.radius + d).next_up(),
        }
    }
}

impl Volume for Aabb {
    #[inline(always)]
    fn size_squared(&self) -> f64 {
        self.half_diagonal_squared()
    }

    #[inline(always)]
    fn meets_sphere(&self, s: &Sphere) -> bool {
        s.meets_box(self)
    }

    #[inline(always)]
    fn meets_box(&self, b: &Aabb) -> bool {
        self.meets(b)
    }

    #[inline(always)]
    fn overlaps<V: Volume>(&self, other: &V) -> bool {
        other.meets_box(self)
    }

    #[inline(always)]
    fn widened(&self, d: f64) -> Aabb {
        Aabb::widened(self, d)
    }
}

/// Where a mesh's coordinates are in the query frame.
///
/// A placement is a small value shared by every thread of a query; what it computes lazily (the
/// world positions of a posed mesh's vertices) goes to the calling thread's cache, `world`.
pub(crate) trait Placement<'m>: Copy + Send + Sync {
    /// Are the mesh's own coordinates the frame's (no pose)?
    const LOCAL: bool;
    /// The mesh.
    fn mesh(&self) -> &'m Mesh;
    /// Vertex `v` in the frame: exactly the coordinates the triangle test sees.
    fn vertex(&self, world: &mut Stamped<Point>, v: u32) -> Point;
    /// A sphere centred on vertex `v`, in the frame.
    fn vertex_sphere(&self, world: &mut Stamped<Point>, s: &Sphere, v: u32) -> Sphere;
    /// A sphere centred anywhere, in the frame.
    fn sphere(&self, s: &Sphere) -> Sphere;
    /// A box, in the frame (for a pose, a box holding the moved one).
    fn aabb(&self, b: &Aabb) -> Aabb;
}

/// A mesh whose coordinates are world coordinates.
#[derive(Clone, Copy)]
pub(crate) struct Local<'m> {
    pub mesh: &'m Mesh,
}

impl<'m> Placement<'m> for Local<'m> {
    const LOCAL: bool = true;

    #[inline(always)]
    fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    #[inline(always)]
    fn vertex(&self, _world: &mut Stamped<Point>, v: u32) -> Point {
        self.mesh.positions()[v as usize]
    }

    #[inline(always)]
    fn vertex_sphere(&self, _world: &mut Stamped<Point>, s: &Sphere, _v: u32) -> Sphere {
        *s
    }

    #[inline(always)]
    fn sphere(&self, s: &Sphere) -> Sphere {
        *s
    }

    #[inline(always)]
    fn aabb(&self, b: &Aabb) -> Aabb {
        *b
    }
}

/// A mesh moved by a pose; world positions are computed on first use within a query.
///
/// Soundness: the triangle test sees the world coordinates [`Pose::transform_point`] computes,
/// which are within `error` (the pose's rounding bound for the mesh's coordinates) of the exact
/// `R p + t`. A sphere's centre moved in floating point is off by at most the same bound (it is
/// within the mesh's coordinate range too), so widening every moved sphere by `pad = 2 error`
/// keeps it around the coordinates the triangle test sees; spheres are also scaled by the
/// rotation's `stretch` (its departure from orthonormality). Boxes need no widening (see
/// [`Placement::aabb`] for [`Posed`]).
#[derive(Clone, Copy)]
pub(crate) struct Posed<'m> {
    pub mesh: &'m Mesh,
    pub pose: &'m Pose,
    pub stretch: f64,
    pub pad: f64,
}

impl<'m> Placement<'m> for Posed<'m> {
    const LOCAL: bool = false;

    #[inline(always)]
    fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    #[inline(always)]
    fn vertex(&self, world: &mut Stamped<Point>, v: u32) -> Point {
        let (pose, positions) = (self.pose, self.mesh.positions());
        world.get_or(v as usize, || pose.transform_point(&positions[v as usize]))
    }

    #[inline(always)]
    fn vertex_sphere(&self, world: &mut Stamped<Point>, s: &Sphere, v: u32) -> Sphere {
        Sphere {
            centre: self.vertex(world, v),
            radius: s.radius * self.stretch + self.pad,
        }
    }

    #[inline(always)]
    fn sphere(&self, s: &Sphere) -> Sphere {
        Sphere {
            centre: self.pose.transform_point(&s.centre),
            radius: s.radius * self.stretch + self.pad,
        }
    }

    /// Each world bound is `((m_0 + m_1) + m_2) + t_i` with `m_j` the smaller (or larger) of
    /// `R_ij lo_j` and `R_ij hi_j`: the same operations, in the same order, as
    /// [`Pose::transform_point`] applies to a vertex. Rounded multiplication and addition are
    /// monotone, so for every vertex `p` in the box each computed term is between the box's, and
    /// the transformed `p` the triangle test sees lies in the computed box exactly: no widening.
    #[inline]
    fn aabb(&self, b: &Aabb) -> Aabb {
        let r = self.pose.rotation();
        let t = self.pose.translation();
        let mut out = Aabb::EMPTY;
        for i in 0..3 {
            let (mut lo, mut hi) = (0.0, 0.0);
            for (j, &rij) in r[i].iter().enumerate() {
                let (u, v) = (rij * b.lo[j], rij * b.hi[j]);
                let (small, large) = if u < v { (u, v) } else { (v, u) };
                lo += small;
                hi += large;
            }
            out.lo[i] = lo + t[i];
            out.hi[i] = hi + t[i];
        }
        out
    }
}

/// A volume kind as the query reads it: the per-node arrays of one mesh.
pub(crate) trait NodeVolumes<'m>: Copy + Send + Sync {
    type Volume: Volume;
    /// Is a leaf's volume, in the mesh's own coordinates, exactly the box of its ring?
    const LEAF_IS_RING_BOX: bool;
    /// Node `n`'s volume in the frame of `place`.
    fn volume<P: Placement<'m>>(
        &self,
        place: &P,
        world: &mut Stamped<Point>,
        n: u32,
    ) -> Self::Volume;
    /// Node `n`'s box (only called when [`NodeVolumes::LEAF_IS_RING_BOX`]).
    fn leaf_box(&self, _n: u32) -> Aabb {
        unreachable!("only box volumes are ring boxes")
    }
}

/// The DVH's vertex-centred spheres.
#[derive(Clone, Copy)]
pub(crate) struct VertexSpheres<'m> {
    pub centre_vertex: &'m [u32],
    pub spheres: &'m [Sphere],
}

impl<'m> NodeVolumes<'m> for VertexSpheres<'m> {
    type Volume = Sphere;
    const LEAF_IS_RING_BOX: bool = false;

    #[inline(always)]
    fn volume<P: Placement<'m>>(&self, place: &P, world: &mut Stamped<Point>, n: u32) -> Sphere {
        place.vertex_sphere(
            world,
            &self.spheres[n as usize],
            self.centre_vertex[n as usize],
        )
    }
}

/// SBV's spheres, centred anywhere.
#[derive(Clone, Copy)]
pub(crate) struct FreeSpheres<'m> {
    pub spheres: &'m [Sphere],
}

impl<'m> NodeVolumes<'m> for FreeSpheres<'m> {
    type Volume = Sphere;
    const LEAF_IS_RING_BOX: bool = false;

    #[inline(always)]
    fn volume<P: Placement<'m>>(&self, place: &P, _world: &mut Stamped<Point>, n: u32) -> Sphere {
        place.sphere(&self.spheres[n as usize])
    }
}

/// Axis-aligned boxes.
#[derive(Clone, Copy)]
pub(crate) struct Boxes<'m> {
    pub boxes: &'m [Aabb],
}

impl<'m> NodeVolumes<'m> for Boxes<'m> {
    type Volume = Aabb;
    const LEAF_IS_RING_BOX: bool = true;

    #[inline(always)]
    fn volume<P: Placement<'m>>(&self, place: &P, _world: &mut Stamped<Point>, n: u32) -> Aabb {
        place.aabb(&self.boxes[n as usize])
    }

    #[inline(always)]
    fn leaf_box(&self, n: u32) -> Aabb {
        self.boxes[n as usize]
    }
}

/// Boxes refit block by block as the traversal first reads them (a deformable scene object's).
#[derive(Clone, Copy)]
pub(crate) struct LazyBoxVolumes<'m> {
    pub boxes: &'m LazyBoxes<'m>,
}

impl<'m> NodeVolumes<'m> for LazyBoxVolumes<'m> {
    type Volume = Aabb;
    const LEAF_IS_RING_BOX: bool = true;

    #[inline(always)]
    fn volume<P: Placement<'m>>(&self, place: &P, _world: &mut Stamped<Point>, n: u32) -> Aabb {
        place.aabb(&self.boxes.get(n))
    }

    #[inline(always)]
    fn leaf_box(&self, n: u32) -> Aabb {
        self.boxes.get(n)
    }
}

/// A volume kind whose volumes are grown by a distance `d` (proximity's side `a`: a volume of
/// `a` overlaps one of `b` whenever the two hold points within `d`).
#[derive(Clone, Copy)]
pub(crate) struct Widened<K> {
    pub kind: K,
    pub d: f64,
}

impl<'m, K: NodeVolumes<'m>> NodeVolumes<'m> for Widened<K> {
    type Volume = K::Volume;
    // Leaves are widened too, so they are not the ring boxes.
    const LEAF_IS_RING_BOX: bool = false;

    #[inline(always)]
    fn volume<P: Placement<'m>>(&self, place: &P, world: &mut Stamped<Point>, n: u32) -> K::Volume {
        self.kind.volume(place, world, n).widened(self.d)
    }
}

/// A volume kind that the volumes of a mesh may have, typed.
pub(crate) trait MeshVolumes<'m>: NodeVolumes<'m> {
    /// `mesh`'s volumes, when they are of this kind.
    fn of(mesh: &'m Mesh) -> Option<Self>;
}

impl<'m> MeshVolumes<'m> for VertexSpheres<'m> {
    fn of(mesh: &'m Mesh) -> Option<Self> {
        match mesh.volumes() {
            Volumes::Dvh {
                centre_vertex,
                spheres,
            } => Some(VertexSpheres {
                centre_vertex,
                spheres,
            }),
            _ => None,
        }
    }
}

impl<'m> MeshVolumes<'m> for FreeSpheres<'m> {
    fn of(mesh: &'m Mesh) -> Option<Self> {
        match mesh.volumes() {
            Volumes::Sbv { spheres, .. } => Some(FreeSpheres { spheres }),
            _ => None,
        }
    }
}

impl<'m> MeshVolumes<'m> for Boxes<'m> {
    fn of(mesh: &'m Mesh) -> Option<Self> {
        match mesh.volumes() {
            Volumes::Aabb { boxes } => Some(Boxes { boxes }),
            _ => None,
        }
    }
}

/// The volumes of either mesh of a query whose two meshes have volumes of different kinds: the
/// kind is decided per volume at run time (a predictable branch), so that one traversal serves
/// every such pair of kinds.
#[derive(Clone, Copy)]
pub(crate) enum MixedVolumes<'m> {
    Vertex(VertexSpheres<'m>),
    Free(FreeSpheres<'m>),
    Boxes(Boxes<'m>),
}

/// A volume of [`MixedVolumes`].
#[derive(Clone, Copy)]
pub(crate) enum MixedVolume {
    Sphere(Sphere),
    Box(Aabb),
}

impl Volume for MixedVolume {
    #[inline(always)]
    fn size_squared(&self) -> f64 {
        match self {
            MixedVolume::Sphere(s) => s.size_squared(),
            MixedVolume::Box(b) => b.size_squared(),
        }
    }

    #[inline(always)]
    fn meets_sphere(&self, s: &Sphere) -> bool {
        match self {
            MixedVolume::Sphere(x) => x.meets_sphere(s),
            MixedVolume::Box(b) => b.meets_sphere(s),
        }
    }

    #[inline(always)]
    fn meets_box(&self, other: &Aabb) -> bool {
        match self {
            MixedVolume::Sphere(s) => s.meets_box(other),
            MixedVolume::Box(b) => b.meets_box(other),
        }
    }

    #[inline(always)]
    fn overlaps<V: Volume>(&self, other: &V) -> bool {
        match self {
            MixedVolume::Sphere(s) => s.overlaps(other),
            MixedVolume::Box(b) => b.overlaps(other),
        }
    }

    #[inline(always)]
    fn widened(&self, d: f64) -> MixedVolume {
        match self {
            MixedVolume::Sphere(s) => MixedVolume::Sphere(s.widened(d)),
            MixedVolume::Box(b) => MixedVolume::Box(Volume::widened(b, d)),
        }
    }
}

impl<'m> NodeVolumes<'m> for MixedVolumes<'m> {
    type Volume = MixedVolume;
    // A ring's box is computed from its vertices even where the leaf's box is it: the same box.
    const LEAF_IS_RING_BOX: bool = false;

    #[inline(always)]
    fn volume<P: Placement<'m>>(
        &self,
        place: &P,
        world: &mut Stamped<Point>,
        n: u32,
    ) -> MixedVolume {
        match self {
            MixedVolumes::Vertex(k) => MixedVolume::Sphere(k.volume(place, world, n)),
            MixedVolumes::Free(k) => MixedVolume::Sphere(k.volume(place, world, n)),
            MixedVolumes::Boxes(k) => MixedVolume::Box(k.volume(place, world, n)),
        }
    }
}

impl<'m> MeshVolumes<'m> for MixedVolumes<'m> {
    fn of(mesh: &'m Mesh) -> Option<Self> {
        Some(match mesh.volumes() {
            Volumes::Dvh { .. } => MixedVolumes::Vertex(VertexSpheres::of(mesh)?),
            Volumes::Sbv { .. } => MixedVolumes::Free(FreeSpheres::of(mesh)?),
            Volumes::Aabb { .. } => MixedVolumes::Boxes(Boxes::of(mesh)?),
        })
    }
}

/// The volume kind of `mesh` as the query reads it, typed, passed to `then`.
macro_rules! with_node_volumes {
    ($mesh:expr, |$kind:ident| $then:expr) => {
        match $mesh.volumes() {
            $crate::volume::Volumes::Dvh {
                centre_vertex,
                spheres,
            } => {
                let $kind = $crate::query::engine::side::VertexSpheres {
                    centre_vertex,
                    spheres,
                };
                $then
            }
            $crate::volume::Volumes::Sbv { spheres, .. } => {
                let $kind = $crate::query::engine::side::FreeSpheres { spheres };
                $then
            }
            $crate::volume::Volumes::Aabb { boxes } => {
                let $kind = $crate::query::engine::side::Boxes { boxes };
                $then
            }
        }
    };
}
pub(crate) use with_node_volumes;

/// One side of a query once typed, as the threads share it: where its mesh is and how its node
/// volumes are read. A pair `(placement, volumes)`.
pub(crate) trait Typed<'m>: Copy + Send + Sync {
    type Place: Placement<'m>;
    type Kind: NodeVolumes<'m>;
    /// The placement.
    fn place(&self) -> Self::Place;
    /// The volume kind.
    fn kind(&self) -> Self::Kind;
}

impl<'m, P: Placement<'m>, K: NodeVolumes<'m>> Typed<'m> for (P, K) {
    type Place = P;
    type Kind = K;
    #[inline(always)]
    fn place(&self) -> P {
        self.0
    }
    #[inline(always)]
    fn kind(&self) -> K {
        self.1
    }
}

/// The view of typed side `S` by one thread.
pub(crate) type ViewOf<'w, 'm, S> = View<'w, <S as Typed<'m>>::Place, <S as Typed<'m>>::Kind>;

/// One mesh of a query, as the traversal and the narrow phase use it.
pub(crate) trait QuerySide<'m> {
    type Volume: Volume;
    /// The mesh.
    fn mesh(&self) -> &'m Mesh;
    /// The shape's nodes.
    fn nodes(&self) -> &'m [Node];
    /// Node `n`'s volume in the frame.
    fn volume(&mut self, n: u32) -> Self::Volume;
    /// Vertex `v` in the frame.
    fn vertex(&mut self, v: u32) -> Point;
    /// The exact box, in the frame, of the vertices of the ring of leaf `n`.
    fn ring_box(&mut self, n: u32) -> Aabb;
}

/// A mesh viewed in the query frame by one thread: a placement and a volume kind, shared by
/// the threads, with this thread's caches of world positions and ring boxes.
pub(crate) struct View<'w, P, K> {
    pub place: P,
    pub kind: K,
    pub world: &'w mut Stamped<Point>,
    pub ring_boxes: &'w mut Stamped<Aabb>,
}

impl<'w, 'm, P: Placement<'m>, K: NodeVolumes<'m>> View<'w, P, K> {
    /// The view of a typed side with a thread's caches.
    pub fn new<S: Typed<'m, Place = P, Kind = K>>(
        side: S,
        world: &'w mut Stamped<Point>,
        ring_boxes: &'w mut Stamped<Aabb>,
    ) -> Self {
        View {
            place: side.place(),
            kind: side.kind(),
            world,
            ring_boxes,
        }
    }
}

impl<'m, P: Placement<'m>, K: NodeVolumes<'m>> QuerySide<'m> for View<'_, P, K> {
    type Volume = K::Volume;

    #[inline(always)]
    fn mesh(&self) -> &'m Mesh {
        self.place.mesh()
    }

    #[inline(always)]
    fn nodes(&self) -> &'m [Node] {
        &self.place.mesh().tree().nodes
    }

    #[inline(always)]
    fn volume(&mut self, n: u32) -> K::Volume {
        self.kind.volume(&self.place, self.world, n)
    }

    #[inline(always)]
    fn vertex(&mut self, v: u32) -> Point {
        self.place.vertex(self.world, v)
    }

    /// Boxes of unposed box volumes are the ring boxes themselves; otherwise the box is computed
    /// on first use in the query from the vertices in the frame.
    #[inline]
    fn ring_box(&mut self, n: u32) -> Aabb {
        if P::LOCAL && K::LEAF_IS_RING_BOX {
            return self.kind.leaf_box(n);
        }
        let mesh = self.place.mesh();
        let r = mesh.tree().nodes[n as usize].ring_start as usize;
        let (place, world) = (&self.place, &mut *self.world);
        self.ring_boxes.get_or(r, || {
            let mut b = Aabb::point(&place.vertex(world, mesh.rings().centre[r]));
            for &v in mesh.rings().vertices.row(r) {
                b.grow(&place.vertex(world, v));
            }
            b
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::Rng;
    use crate::mesh::BuildOptions;
    use crate::volume::VolumeKind;

    /// A posed box holds the coordinates the triangle test sees for every point it bounds, even
    /// when those points sit within an ulp of the box's faces: no widening is needed, because
    /// the bound and the point are rounded by the same monotone operations.
    #[test]
    fn posed_boxes_hold_the_transformed_points() {
        let mut rng = Rng::new(31);
        let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let options = BuildOptions {
            volume: VolumeKind::Aabb,
            ..BuildOptions::default()
        };
        let mesh = Mesh::new(&tri, &[0, 1, 2], &options).unwrap();
        for trial in 0..20_000 {
            let angle = rng.range(0.0, 6.3);
            let axis = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ];
            let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
            let (x, y, z) = (axis[0] / n, axis[1] / n, axis[2] / n);
            let (s, c) = angle.sin_cos();
            let k = 1.0 - c;
            let rotation = [
                [c + x * x * k, x * y * k - z * s, x * z * k + y * s],
                [y * x * k + z * s, c + y * y * k, y * z * k - x * s],
                [z * x * k - y * s, z * y * k + x * s, c + z * z * k],
            ];
            let scale = [1.0, 1e3, 1e-3, 7e5][trial % 4];
            let t = [0; 3].map(|_| rng.range(-1.0, 1.0) * scale * 10.0);
            let pose = Pose::new(rotation, t).unwrap();
            // Points within a few ulps of each other, so that each face of their box is within
            // an ulp of several of them.
            let base = [0; 3].map(|_| rng.range(-1.0, 1.0) * scale);
            let points: Vec<Point> = (0..6)
                .map(|_| {
                    base.map(|b| {
                        let ulp = f64::from_bits(b.to_bits() + 1) - b;
                        b + ulp * (rng.below(5) as f64 - 2.0)
                    })
                })
                .collect();
            let b = Aabb::of_points(&points);
            let posed = Posed {
                mesh: &mesh,
                pose: &pose,
                stretch: pose.stretch(),
                pad: 0.0,
            };
            let world = posed.aabb(&b);
            for p in &points {
                let w = pose.transform_point(p);
                assert!(world.contains(&w), "trial {trial}: {w:?} outside {world:?}");
            }
        }
    }
}
