//! The least distance in a scene: of the closest allowed pair of objects, or of one object's
//! closest other. Pairs are taken nearest box first; each pair's query looks no farther than
//! the best found so far, and a pair whose boxes lie farther apart is not queried at all.

use super::{Object, Scene};
use crate::error::{Error, Result};
use crate::geometry::aabb::Aabb;
use crate::geometry::nearest::{Primitive, cmp_distance, decide_near};
use crate::geometry::predicates::Point;
use crate::query::{Distance, DistanceOptions, ImpactKind, distance};
use std::cmp::Ordering;

/// The least distance between two objects of a scene: `distance` as [`crate::distance`]
/// reports it for object `object_a`'s mesh first and `object_b`'s second.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneDistance {
    /// The first object: the lower id ([`Scene::distance`]), or the object asked about
    /// ([`Scene::object_distance`]).
    pub object_a: u32,
    /// The other object.
    pub object_b: u32,
    /// The distance, its primitives and closest points (world coordinates).
    pub distance: Distance,
}

/// The squared gap between two boxes in floating point: an order for the pairs, no decision.
fn gap_squared(a: &Aabb, b: &Aabb) -> f64 {
    (0..3)
        .map(|k| {
            let g = (a.lo[k] - b.hi[k]).max(b.lo[k] - a.hi[k]).max(0.0);
            g * g
        })
        .sum()
}

/// The world points of a distance's stencil between objects `a` and `b`, with its kind.
fn stencil_points(a: &Object, b: &Object, d: &Distance) -> (Primitive, [Point; 4]) {
    let at = |o: &Object, v: u32| {
        let p = o.mesh.positions()[v as usize];
        o.pose().map_or(p, |pose| pose.transform_point(&p))
    };
    let corners = |o: &Object, t: u32| o.mesh.triangles()[t as usize].map(|v| at(o, v));
    let s = &d.stencil;
    match s.kind {
        ImpactKind::VertexFace => {
            let [x, y, z] = corners(b, s.b0);
            (Primitive::VertexFace, [at(a, s.a0), x, y, z])
        }
        ImpactKind::FaceVertex => {
            let [x, y, z] = corners(a, s.a0);
            (Primitive::VertexFace, [at(b, s.b0), x, y, z])
        }
        ImpactKind::EdgeEdge => (
            Primitive::EdgeEdge,
            [at(a, s.a0), at(a, s.a1), at(b, s.b0), at(b, s.b1)],
        ),
    }
}

impl Scene {
    /// The closest pair of distinct objects that the filters allow (groups and masks,
    /// exclusions, as [`Scene::collide`]): for each pair, what [`crate::distance`] reports for
    /// the two objects' current geometry and poses (the lower id's mesh first), the least
    /// distance of them all, decided exactly; of several pairs at the least distance, the first
    /// by `(object_a, object_b)`. `None` when no allowed pair lies within
    /// `options.max_distance` (or there is none). Objects given a step are seen at its end.
    ///
    /// Pairs are queried nearest world box first, each only as far as the best found so far, so
    /// that distant objects cost one box comparison. Deformable objects whose positions changed
    /// are refit here, whole, and only those some pair needs.
    ///
    /// Errors: [`Error::InvalidDistanceOption`]; [`Error::OutOfMemory`].
    pub fn distance(&mut self, options: &DistanceOptions) -> Result<Option<SceneDistance>> {
        options.check()?;
        let mut pairs = std::mem::take(&mut self.candidates);
        pairs.clear();
        let live = |o: &Option<Object>| o.is_some();
        for i in 0..self.objects.len() {
            if !live(&self.objects[i]) {
                continue;
            }
            for j in i + 1..self.objects.len() {
                if self.allowed(i as u32, j as u32) {
                    pairs.push((i as u32, j as u32));
                }
            }
        }
        let result = self.least_of(&pairs, options);
        self.candidates = pairs;
        result
    }

    /// The object closest to `object` among those the filters allow it to meet, as
    /// [`Scene::distance`] chooses among pairs (ties to the least other id), with `object`'s
    /// mesh first: `object_a` is `object`. `None` when none lies within `options.max_distance`.
    ///
    /// Errors: [`Error::UnknownObject`]; [`Error::InvalidDistanceOption`];
    /// [`Error::OutOfMemory`].
    pub fn object_distance(
        &mut self,
        object: u32,
        options: &DistanceOptions,
    ) -> Result<Option<SceneDistance>> {
        options.check()?;
        if self
            .objects
            .get(object as usize)
            .is_none_or(|o| o.is_none())
        {
            return Err(Error::UnknownObject { object });
        }
        let mut pairs = std::mem::take(&mut self.candidates);
        pairs.clear();
        pairs.extend(
            (0..self.objects.len() as u32)
                .filter(|&j| j != object && self.allowed(object.min(j), object.max(j)))
                .map(|j| (object, j)),
        );
        let result = self.least_of(&pairs, options);
        self.candidates = pairs;
        result
    }

    /// The least distance over `pairs` (each `(a side, b side)`), ties to the first pair in
    /// `(object_a, object_b)` order.
    fn least_of(
        &mut self,
        pairs: &[(u32, u32)],
        options: &DistanceOptions,
    ) -> Result<Option<SceneDistance>> {
        let mut needed = std::mem::take(&mut self.marks);
        super::select::marks(pairs, self.objects.len(), &mut needed);
        self.refit_stale(|id| needed[id] != 0, options.threads, |_| false);
        self.marks = needed;
        // Nearest boxes first.
        let mut order: Vec<(f64, u32, u32)> = Vec::new();
        order
            .try_reserve_exact(pairs.len())
            .map_err(|_| Error::OutOfMemory {
                bytes: pairs.len() * std::mem::size_of::<(f64, u32, u32)>(),
            })?;
        order.extend(pairs.iter().map(|&(i, j)| {
            (
                gap_squared(&self.boxes[i as usize], &self.boxes[j as usize]),
                i,
                j,
            )
        }));
        order.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let mut best: Option<SceneDistance> = None;
        for &(_, i, j) in &order {
            // Farther than the best, or than the bound: box by box, exactly (per axis).
            let reach = best.map_or(options.max_distance, |b| {
                b.distance
                    .distance
                    .next_up()
                    .next_up()
                    .min(options.max_distance)
            });
            let (bi, bj) = (&self.boxes[i as usize], &self.boxes[j as usize]);
            if reach.is_finite() && !bi.within(bj, reach) {
                continue;
            }
            let (a, b) = (self.candidate(i), self.candidate(j));
            let mut found = Distance::default();
            let pair_options = options.with_max_distance(reach);
            distance(
                &a.mesh,
                a.pose(),
                &b.mesh,
                b.pose(),
                &pair_options,
                &mut found,
            )?;
            if !found.found() {
                continue;
            }
            let candidate = SceneDistance {
                object_a: i,
                object_b: j,
                distance: found,
            };
            let better = match &best {
                None => true,
                Some(b) => match self.compare(&candidate, b) {
                    Ordering::Less => true,
                    Ordering::Equal => (i, j) < (b.object_a, b.object_b),
                    Ordering::Greater => false,
                },
            };
            if better {
                best = Some(candidate);
            }
        }
        Ok(best)
    }

    /// How the exact distances of two pairs' answers compare.
    fn compare(&self, x: &SceneDistance, y: &SceneDistance) -> Ordering {
        let (dx, dy) = (&x.distance, &y.distance);
        if dx.intersecting() || dy.intersecting() {
            return dy.intersecting().cmp(&dx.intersecting());
        }
        // Rounded within a unit of the correctly rounded distance: more than four apart, the
        // rounded order is the exact one.
        if dx.distance.next_up().next_up() < dy.distance.next_down().next_down() {
            return Ordering::Less;
        }
        if dy.distance.next_up().next_up() < dx.distance.next_down().next_down() {
            return Ordering::Greater;
        }
        let points = |s: &SceneDistance| {
            stencil_points(
                self.candidate(s.object_a),
                self.candidate(s.object_b),
                &s.distance,
            )
        };
        let ((px, qx), (py, qy)) = (points(x), points(y));
        let decided = |pair, q: &[Point; 4], d: f64| {
            decide_near(pair, q, d * d).expect("a stencil within its distance")
        };
        cmp_distance(
            (px, &qx, decided(px, &qx, x.distance.distance)),
            (py, &qy, decided(py, &qy, y.distance.distance)),
        )
    }
}
