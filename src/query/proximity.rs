//! Proximity (issue 11, in progress): every pair of triangles of two placed meshes at distance at
//! most `d`, decided exactly by [`triangles_within`].
//!
//! The one traversal, with side `a`'s volumes widened by `d` (rounded outwards, so no pair within
//! `d` is dropped), hands leaf pairs to [`NearPairs`], which filters by widened ring and
//! triangle boxes before the exact test.
//!
//! Not yet here: self-proximity, the coarse modes, threads, and the C ABI.

// Reached from tests only until the public entry points (Rust and C) land with the rest of
// issue 11.
#![cfg_attr(not(test), allow(dead_code))]

use super::collide::widening;
use super::narrow::{prepare, select};
use super::pairs::{Pair, Pairs, QueryStats};
use super::side::{Kind, Local, Placement, Posed, QuerySide, View, Volume, with_kind};
use super::sink::{Sink, Stop, one_thread};
use super::traverse::{NarrowPhase, depth_first};
use super::workspace::{RingCache, Stamped, Worker};
use crate::error::{Error, Result, Side};
use crate::geometry::aabb::Aabb;
use crate::geometry::distance::triangles_within;
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::geometry::sphere::Sphere;
use crate::mesh::Mesh;

/// A volume grown by a distance, rounded outwards: it holds every point within that distance of
/// the volume.
trait Widen: Volume {
    fn widened(&self, d: f64) -> Self;
}

impl Widen for Aabb {
    fn widened(&self, d: f64) -> Aabb {
        widen_box(self, d)
    }
}

impl Widen for Sphere {
    fn widened(&self, d: f64) -> Sphere {
        Sphere {
            centre: self.centre,
            radius: (self.radius + d).next_up(),
        }
    }
}

/// `b` grown by `d` on every side, rounded outwards.
fn widen_box(b: &Aabb, d: f64) -> Aabb {
    Aabb {
        lo: b.lo.map(|x| (x - d).next_down()),
        hi: b.hi.map(|x| (x + d).next_up()),
    }
}

/// A volume kind whose volumes are grown by `d`.
#[derive(Clone, Copy)]
struct Widened<K> {
    kind: K,
    d: f64,
}

impl<'m, K: Kind<'m>> Kind<'m> for Widened<K>
where
    K::Volume: Widen,
{
    type Volume = K::Volume;
    const LEAF_IS_RING_BOX: bool = false;

    #[inline(always)]
    fn volume<P: Placement<'m>>(&self, place: &P, world: &mut Stamped<Point>, n: u32) -> K::Volume {
        self.kind.volume(place, world, n).widened(self.d)
    }
}

/// Tests the triangles of two leaves' rings for distance at most `d`.
struct NearPairs<'s, 'w> {
    sink: &'s mut Sink<'w>,
    rings_a: &'s mut RingCache,
    rings_b: &'s mut RingCache,
    d: f64,
}

impl<'m, A: QuerySide<'m>, B: QuerySide<'m>> NarrowPhase<'m, A, B> for NearPairs<'_, '_> {
    fn visit(&mut self, a: &mut A, b: &mut B, na: u32, nb: u32, stats: &mut QueryStats) -> bool {
        let ra = a.mesh().shape.tree.nodes[na as usize].ring_start;
        let rb = b.mesh().shape.tree.nodes[nb as usize].ring_start;
        if !widen_box(&a.ring_box(na), self.d).meets(&b.ring_box(nb)) {
            return false;
        }
        // The triangles are prepared without domain checks: the exact test below works for any
        // finite coordinates.
        let (span_a, bounds_a) = prepare(a, ra, self.rings_a, false);
        let (span_b, bounds_b) = prepare(b, rb, self.rings_b, false);
        let (near_a, near_b) = (widen_box(&bounds_a, self.d), widen_box(&bounds_b, self.d));
        if !near_a.meets(&bounds_b) {
            return false;
        }
        let (ca, cb) = (&mut *self.rings_a, &mut *self.rings_b);
        select(&ca.tris[span_a.clone()], &near_b, &mut ca.selected);
        select(&cb.tris[span_b.clone()], &near_a, &mut cb.selected);
        let (tris_a, tris_b) = (&ca.tris[span_a], &cb.tris[span_b]);
        for &i in &ca.selected {
            let ta = &tris_a[i as usize];
            let grown = widen_box(&ta.bounds, self.d);
            for &j in &cb.selected {
                let tb = &tris_b[j as usize];
                if !grown.meets(&tb.bounds) {
                    continue;
                }
                stats.triangle_tests += 1;
                if triangles_within(&ta.tri.corners, &tb.tri.corners, self.d)
                    && self.sink.report(Pair {
                        a: ta.index,
                        b: tb.index,
                    })
                {
                    return true;
                }
            }
        }
        false
    }
}

/// Every pair `(triangle of a, triangle of b)` at distance at most `d` between mesh `a` placed
/// by `pose_a` and mesh `b` placed by `pose_b` (closed triangles; `d = 0` gives exactly the
/// intersecting pairs of [`crate::collide`]). Exact; one thread; stops at `max_pairs` pairs (then
/// `truncated`). Errors: a negative, NaN or infinite `d`; a pose out of range; out of memory.
pub(crate) fn proximity(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    d: f64,
    max_pairs: Option<usize>,
    out: &mut Pairs,
) -> Result<QueryStats> {
    if !(d >= 0.0 && d.is_finite()) {
        return Err(Error::InvalidDistance { distance: d });
    }
    let pose_a = pose_a.filter(|p| !p.is_identity());
    let pose_b = pose_b.filter(|p| !p.is_identity());
    let place_a = pose_a.map(|p| widening(p, a, Side::A)).transpose()?;
    let place_b = pose_b.map(|p| widening(p, b, Side::B)).transpose()?;
    let limit = max_pairs.unwrap_or(usize::MAX);
    one_thread(out, limit, true, |worker, sink, stats| {
        let run = Run {
            b,
            pose_b: pose_b.zip(place_b),
            d,
            worker,
            sink,
            stats,
        };
        match pose_a.zip(place_a) {
            None => run.side_a(Local { mesh: a }),
            Some((pose, (stretch, pad))) => run.side_a(Posed {
                mesh: a,
                pose,
                stretch,
                pad,
            }),
        }
    })
}

/// A proximity query being typed side by side.
struct Run<'m, 'q, 'w> {
    b: &'m Mesh,
    pose_b: Option<(&'m Pose, (f64, f64))>,
    d: f64,
    worker: &'q mut Worker,
    sink: &'q mut Sink<'w>,
    stats: &'q mut QueryStats,
}

impl<'m> Run<'m, '_, '_> {
    fn side_a<PA: Placement<'m>>(self, place: PA) {
        let d = self.d;
        with_kind!(place.mesh(), |kind| self
            .placement_b((place, Widened { kind, d })))
    }

    fn placement_b<PA: Placement<'m>, KA: Kind<'m>>(self, a: (PA, KA)) {
        let mesh = self.b;
        match self.pose_b {
            None => self.side_b(a, Local { mesh }),
            Some((pose, (stretch, pad))) => self.side_b(
                a,
                Posed {
                    mesh,
                    pose,
                    stretch,
                    pad,
                },
            ),
        }
    }

    fn side_b<PA: Placement<'m>, KA: Kind<'m>, PB: Placement<'m>>(self, a: (PA, KA), place: PB) {
        with_kind!(place.mesh(), |kind| self.traverse(a, (place, kind)))
    }

    fn traverse<PA, KA, PB, KB>(self, a: (PA, KA), b: (PB, KB))
    where
        PA: Placement<'m>,
        KA: Kind<'m>,
        PB: Placement<'m>,
        KB: Kind<'m>,
    {
        let (ma, mb) = (a.0.mesh(), b.0.mesh());
        let w = self.worker;
        let begun =
            w.a.begin(
                ma.vertex_count(),
                ma.ring_count(),
                Some(ma.shape.rings.longest),
                !PA::LOCAL,
            )
            .and_then(|()| {
                w.b.begin(
                    mb.vertex_count(),
                    mb.ring_count(),
                    Some(mb.shape.rings.longest),
                    !PB::LOCAL,
                )
            });
        if let Err(bytes) = begun {
            self.sink.stop = Some(Stop::OutOfMemory { bytes });
            return;
        }
        let Worker {
            stack,
            a: sa,
            b: sb,
            ..
        } = w;
        let mut va = View::new(a, &mut sa.world, &mut sa.ring_boxes);
        let mut vb = View::new(b, &mut sb.world, &mut sb.ring_boxes);
        let mut narrow = NearPairs {
            sink: self.sink,
            rings_a: &mut sa.rings,
            rings_b: &mut sb.rings,
            d: self.d,
        };
        depth_first(&mut va, &mut vb, u32::MAX, stack, self.stats, &mut narrow);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{Rng, icosphere, torus};
    use crate::{BuildOptions, VolumeKind, collide};

    /// Every pair tested one by one, in the frame the query sees (poses applied as the query
    /// applies them).
    fn brute_force(a: &Mesh, pa: Option<&Pose>, b: &Mesh, pb: Option<&Pose>, d: f64) -> Vec<Pair> {
        let world = |m: &Mesh, p: Option<&Pose>, v: u32| {
            let x = m.positions[v as usize];
            p.map_or(x, |p| p.transform_point(&x))
        };
        let tri = |m: &Mesh, p: Option<&Pose>, t: [u32; 3]| t.map(|v| world(m, p, v));
        let mut out = Vec::new();
        for (i, &ta) in a.shape.triangles.iter().enumerate() {
            for (j, &tb) in b.shape.triangles.iter().enumerate() {
                if triangles_within(&tri(a, pa, ta), &tri(b, pb, tb), d) {
                    out.push(Pair {
                        a: i as u32,
                        b: j as u32,
                    });
                }
            }
        }
        out
    }

    #[test]
    fn equals_brute_force_for_every_volume_kind_and_pose() {
        let mut rng = Rng::new(8);
        let s = icosphere(1);
        let t = torus(0.5, 0.2, 12, 6);
        let mut pairs = Pairs::new();
        for volume in [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv] {
            let options = BuildOptions {
                volume,
                ..BuildOptions::default()
            };
            let a = Mesh::new(&s.positions, &s.triangles, &options).unwrap();
            let b = Mesh::new(&t.positions, &t.triangles, &options).unwrap();
            for trial in 0..4 {
                let shift = 1.1 + 0.1 * trial as f64;
                let pose = Pose::new(
                    [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
                    [shift, rng.range(-0.2, 0.2), 0.0],
                )
                .unwrap();
                for d in [0.0, 0.01, 0.1, 0.3] {
                    let expected = brute_force(&a, None, &b, Some(&pose), d);
                    assert!(d < 0.3 || !expected.is_empty(), "the meshes come near");
                    let stats = proximity(&a, None, &b, Some(&pose), d, None, &mut pairs).unwrap();
                    assert_eq!(
                        pairs.as_slice(),
                        &expected[..],
                        "{volume:?} {trial} d = {d}"
                    );
                    assert!(!stats.truncated);
                    if d == 0.0 {
                        let mut hits = Pairs::new();
                        collide(&a, None, &b, Some(&pose), &Default::default(), &mut hits).unwrap();
                        assert_eq!(hits.as_slice(), pairs.as_slice());
                    }
                }
            }
        }
    }

    #[test]
    fn bad_distances_and_limits() {
        let s = icosphere(1);
        let a = Mesh::new(&s.positions, &s.triangles, &BuildOptions::default()).unwrap();
        let mut pairs = Pairs::new();
        for d in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                proximity(&a, None, &a, None, d, None, &mut pairs),
                Err(Error::InvalidDistance { .. })
            ));
        }
        let all = proximity(&a, None, &a, None, 0.1, None, &mut pairs).unwrap();
        assert!(all.pairs > 3);
        let cut = proximity(&a, None, &a, None, 0.1, Some(3), &mut pairs).unwrap();
        assert!(cut.truncated && pairs.len() == 3);
    }
}
