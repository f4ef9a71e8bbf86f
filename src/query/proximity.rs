//! Proximity: every pair of triangles of two placed meshes at distance at most `d`, and of one
//! mesh's triangles that share no vertex, decided exactly by [`triangles_within`].
//!
//! The one traversal, with side `a`'s volumes widened by `d` (rounded outwards, so no pair within
//! `d` is dropped: [`Widened`]), hands leaf pairs to the leaf narrow phase, which filters by ring
//! and triangle boxes widened by `d` before the exact test ([`Near`]).

use super::engine::{
    NodeVolumes, OneMesh, Prepared, Reach, TriangleTest, Widened, query, query_one,
};
use super::options::QueryOptions;
use super::pairs::{Pairs, QueryStats};
use crate::error::{Error, Result};
use crate::geometry::aabb::Aabb;
use crate::geometry::distance::triangles_within;
use crate::geometry::pose::Pose;
use crate::mesh::Mesh;

/// Every pair `(triangle of a, triangle of b)` of closed triangles at Euclidean distance at most
/// `distance` between mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b` (`None`: the
/// mesh's coordinates are world coordinates). Exact for the given doubles: the decision is made
/// without rounding error (an interval filter first, big integers when it cannot decide), so
/// `distance = 0` gives exactly [`crate::collide`]'s pairs, and a pair whose distance equals
/// `distance` is reported. Posed coordinates are those [`Pose::transform_point`] computes, as in
/// [`crate::collide`].
///
/// [`QueryOptions`] apply as in [`crate::collide`]: the coarse modes report node pairs whose
/// volumes come within `distance` (conservative: their triangles include every pair within
/// `distance`), `max_pairs` bounds the result, `threads` shares the work out.
///
/// Errors: [`Error::InvalidDistance`] for a negative, NaN or infinite `distance`; the errors of
/// [`crate::collide`]. On error `out` still holds the previous result.
pub fn proximity(
    a: &Mesh,
    pose_a: Option<&Pose>,
    b: &Mesh,
    pose_b: Option<&Pose>,
    distance: f64,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    check_distance(distance)?;
    query::<_, false>(
        (a, pose_a, None),
        (b, pose_b, None),
        Near {
            d: distance,
            one_mesh: false,
        },
        options,
        out,
    )
}

/// The pairs `(a, b)`, `a < b`, of triangles of `mesh` that share no vertex (by index) and lie
/// at Euclidean distance at most `distance` from each other: what keeps a cloth or a soft body
/// a thickness apart from itself. Exact, like [`proximity`]; [`QueryOptions`] apply as in
/// [`crate::collide`] (the coarse modes report node pairs `(lower, higher)`, a node paired with
/// itself included).
///
/// Errors: [`Error::InvalidDistance`] for a negative, NaN or infinite `distance`;
/// [`Error::ZeroBudget`]; [`Error::OutOfMemory`]. On error `out` still holds the previous result.
pub fn self_proximity(
    mesh: &Mesh,
    distance: f64,
    options: &QueryOptions,
    out: &mut Pairs,
) -> Result<QueryStats> {
    check_distance(distance)?;
    query_one(
        mesh,
        Near {
            d: distance,
            one_mesh: true,
        },
        options,
        out,
    )
}

/// A distance must be finite and not negative.
pub(crate) fn check_distance(d: f64) -> Result<()> {
    if d >= 0.0 && d.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidDistance { distance: d })
    }
}

/// Which triangles lie within `d` of each other: of two meshes, or of one (pairs sharing no
/// vertex).
#[derive(Clone, Copy)]
pub(crate) struct Near {
    pub d: f64,
    pub one_mesh: bool,
}

impl<'m> Reach<'m> for Near {
    type SideA<K: NodeVolumes<'m>> = Widened<K>;

    fn side_a<K: NodeVolumes<'m>>(&self, kind: K) -> Widened<K> {
        Widened { kind, d: self.d }
    }

    #[inline(always)]
    fn own(&self) -> Option<OneMesh<'m>> {
        self.one_mesh.then_some(OneMesh { patches: None })
    }

    #[inline(always)]
    fn widen(&self, b: &Aabb) -> Aabb {
        b.widened(self.d)
    }
}

impl<'m> TriangleTest<'m> for Near {
    // The exact distance test works for any finite coordinates.
    const CHECKS_DOMAIN: bool = false;

    #[inline]
    fn skips(&self, mesh: &Mesh, ta: &Prepared, tb: &Prepared) -> bool {
        if !self.one_mesh {
            return false;
        }
        let tris = mesh.triangles();
        let (va, vb) = (tris[ta.index as usize], tris[tb.index as usize]);
        va.iter().any(|v| vb.contains(v))
    }

    #[inline]
    fn test(&self, _mesh: &Mesh, ta: &Prepared, tb: &Prepared) -> bool {
        triangles_within(&ta.tri.corners, &tb.tri.corners, self.d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::oracle::{proximity_brute_force, self_proximity_brute_force};
    use crate::fixtures::{Rng, grid, icosphere, torus};
    use crate::mesh::BuildOptions;
    use crate::query::testing::{map_vertices, nodes_cover};
    use crate::query::{Pair, PairKind, QueryMode, collide};
    use crate::volume::VolumeKind;

    fn modes() -> [QueryMode; 5] {
        [
            QueryMode::FirstHit,
            QueryMode::Leaves,
            QueryMode::Depth(2),
            QueryMode::Budget(30),
            QueryMode::Budget(1 << 40),
        ]
    }

    /// The other modes against the exact answer `expected` (`run` queries with the options).
    fn check_modes(
        a: &Mesh,
        b: &Mesh,
        one_mesh: bool,
        expected: &[Pair],
        mut run: impl FnMut(&QueryOptions, &mut Pairs) -> QueryStats,
    ) {
        let mut pairs = Pairs::new();
        for mode in modes() {
            run(&QueryOptions::with_mode(mode), &mut pairs);
            if mode == QueryMode::FirstHit {
                assert_eq!(pairs.len(), expected.len().min(1));
                assert!(pairs.iter().all(|p| expected.contains(p)));
            } else {
                assert_eq!(pairs.kind(), PairKind::Nodes);
                nodes_cover(a, b, one_mesh, pairs.as_slice(), expected);
            }
        }
        if expected.len() > 3 {
            let cut = QueryOptions {
                max_pairs: Some(3),
                ..QueryOptions::default()
            };
            let stats = run(&cut, &mut pairs);
            assert!(stats.truncated && pairs.len() == 3);
            assert!(pairs.iter().all(|p| expected.contains(p)));
        }
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
                    let expected = proximity_brute_force(&a, None, &b, Some(&pose), d);
                    assert!(d < 0.3 || !expected.is_empty(), "the meshes come near");
                    let q = QueryOptions::default();
                    let stats = proximity(&a, None, &b, Some(&pose), d, &q, &mut pairs).unwrap();
                    assert_eq!(
                        pairs.as_slice(),
                        &expected[..],
                        "{volume:?} {trial} d = {d}"
                    );
                    assert!(!stats.truncated);
                    if d == 0.0 {
                        let mut hits = Pairs::new();
                        collide(&a, None, &b, Some(&pose), &q, &mut hits).unwrap();
                        assert_eq!(hits.as_slice(), pairs.as_slice());
                    }
                    if trial == 0 {
                        check_modes(&a, &b, false, &expected, |q, out| {
                            proximity(&a, None, &b, Some(&pose), d, q, out).unwrap()
                        });
                    }
                }
            }
        }
    }

    #[test]
    fn self_proximity_equals_brute_force() {
        let mut rng = Rng::new(3);
        let t = torus(0.5, 0.2, 16, 8);
        let crumpled: Vec<f64> = t
            .positions
            .iter()
            .map(|x| x + rng.range(-0.08, 0.08))
            .collect();
        for volume in [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv] {
            let options = BuildOptions {
                volume,
                ..BuildOptions::default()
            };
            let m = Mesh::new(&crumpled, &t.triangles, &options).unwrap();
            for d in [0.0, 0.02, 0.1, 0.25] {
                let expected = self_proximity_brute_force(&m, d);
                assert!(d < 0.1 || !expected.is_empty());
                let mut pairs = Pairs::new();
                // Meshes this small are queried on the calling thread whatever the thread count: threads
                // are compared on larger ones (tests/threads.rs).
                let threads = 1;
                let q = QueryOptions {
                    threads,
                    ..QueryOptions::default()
                };
                self_proximity(&m, d, &q, &mut pairs).unwrap();
                assert_eq!(pairs.as_slice(), &expected[..], "{volume:?} d = {d}");
                check_modes(&m, &m, true, &expected, |q, out| {
                    self_proximity(&m, d, q, out).unwrap()
                });
            }
        }
    }

    #[test]
    fn distances_met_exactly() {
        // A flat grid of cells 1/4 wide: triangles two cells apart are exactly 1/4 from each
        // other, so the answer changes between d = 1/4 and the double below it.
        let g = grid(8, 2.0);
        let m = Mesh::new(&g.positions, &g.triangles, &BuildOptions::default()).unwrap();
        let mut pairs = Pairs::new();
        let q = QueryOptions::default();
        self_proximity(&m, 0.25, &q, &mut pairs).unwrap();
        let at = pairs.as_slice().to_vec();
        assert_eq!(at, self_proximity_brute_force(&m, 0.25));
        self_proximity(&m, 0.25f64.next_down(), &q, &mut pairs).unwrap();
        assert_eq!(
            pairs.as_slice(),
            self_proximity_brute_force(&m, 0.25f64.next_down())
        );
        assert!(
            pairs.len() < at.len(),
            "{} at 1/4, {} below",
            at.len(),
            pairs.len()
        );
        // Two parallel sheets exactly 1/4 apart: every facing pair within 1/4, none below.
        let lifted = map_vertices(&g.positions, |v| [v[0], v[1], 0.25]);
        let b = Mesh::new(&lifted, &g.triangles, &BuildOptions::default()).unwrap();
        proximity(&m, None, &b, None, 0.25, &q, &mut pairs).unwrap();
        assert_eq!(
            pairs.as_slice(),
            proximity_brute_force(&m, None, &b, None, 0.25)
        );
        assert!(pairs.len() >= m.triangle_count());
        proximity(&m, None, &b, None, 0.25f64.next_down(), &q, &mut pairs).unwrap();
        assert!(pairs.is_empty());
    }

    #[test]
    fn bad_distances_and_limits() {
        let s = icosphere(1);
        let a = Mesh::new(&s.positions, &s.triangles, &BuildOptions::default()).unwrap();
        let mut pairs = Pairs::new();
        let q = QueryOptions::default();
        proximity(&a, None, &a, None, 0.1, &q, &mut pairs).unwrap();
        let before = pairs.as_slice().to_vec();
        for d in [-1.0, (-0.0f64).next_down(), f64::NAN, f64::INFINITY] {
            assert!(matches!(
                proximity(&a, None, &a, None, d, &q, &mut pairs),
                Err(Error::InvalidDistance { .. })
            ));
            assert!(matches!(
                self_proximity(&a, d, &q, &mut pairs),
                Err(Error::InvalidDistance { .. })
            ));
            assert_eq!(pairs.as_slice(), before, "a failed query keeps the result");
        }
        assert!(matches!(
            self_proximity(
                &a,
                0.1,
                &QueryOptions::with_mode(QueryMode::Budget(0)),
                &mut pairs
            ),
            Err(Error::ZeroBudget)
        ));
    }
}
