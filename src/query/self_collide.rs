//! Self-collision: the pairs of triangles of one mesh that intersect, where triangles sharing
//! vertices count only where they meet beyond what they share.
//!
//! The one traversal, of the mesh against itself ([`crate::query::engine::traverse`]): every unordered
//! pair of nodes once, nodes whose patches cannot intersect themselves skipped
//! ([`Patches`], an exact normal-cone test). The leaf narrow phase tests each unordered pair of
//! their rings' triangles once (rings partition the triangles), with [`SelfIntersect`]:
//! [`crate::geometry::adjacent`] for triangles that share vertices.

use super::engine::{NodeVolumes, OneMesh, Prepared, Reach, TriangleTest, query_one};
use super::options::QueryOptions;
use super::pairs::{Pairs, QueryStats};
use crate::error::Result;
use crate::geometry::adjacent::{meet_beyond_edge, meet_beyond_vertex};
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;
use crate::mesh::Patches;

/// The pairs `(a, b)`, `a < b`, of triangles of `mesh` that intersect. Two triangles that share
/// vertices (by index) count only where they meet beyond the vertices and the edge they share
/// (a fold through, a crossing, a coplanar overlap), so an intact surface reports nothing however
/// it bends, and a surface folded through itself reports every crossing. Exact, like
/// [`crate::collide`].
///
/// [`QueryOptions`] apply as in [`crate::collide`]: the coarse modes report node pairs
/// `(lower, higher)`, a node paired with itself included, whose triangles include every
/// intersecting pair; `max_pairs` bounds the result; `threads` shares the work out.
///
/// Cost: a node whose patch is a disk that projects one to one along a coordinate axis (decided
/// exactly per query) is not opened, and neither is a pair of neighbouring nodes whose patches
/// together make such a disk, so a smooth region never reaches the triangle stage. Which way
/// each node's triangles turn is kept with the mesh until its positions change.
///
/// Errors: [`crate::Error::ZeroBudget`]; [`crate::Error::OutOfMemory`]. On error `out` still
/// holds the previous result.
pub fn self_collide(mesh: &Mesh, options: &QueryOptions, out: &mut Pairs) -> Result<QueryStats> {
    self_collide_with(mesh, options, true, out)
}

/// [`self_collide`], with the patch test (`patches`) or without (to measure what it saves).
fn self_collide_with(
    mesh: &Mesh,
    options: &QueryOptions,
    patches: bool,
    out: &mut Pairs,
) -> Result<QueryStats> {
    let patches = patches.then(|| mesh.patches());
    query_one(mesh, SelfIntersect { patches }, options, out)
}

/// Which triangles of one mesh intersect beyond what they share.
#[derive(Clone, Copy)]
struct SelfIntersect<'m> {
    patches: Option<&'m Patches>,
}

impl<'m> Reach<'m> for SelfIntersect<'m> {
    type SideA<K: NodeVolumes<'m>> = K;

    fn side_a<K: NodeVolumes<'m>>(&self, kind: K) -> K {
        kind
    }

    #[inline(always)]
    fn own(&self) -> Option<OneMesh<'m>> {
        Some(OneMesh {
            patches: self.patches,
        })
    }
}

impl<'m> TriangleTest<'m> for SelfIntersect<'m> {
    const CHECKS_DOMAIN: bool = true;

    #[inline]
    fn test(&self, mesh: &Mesh, ta: &Prepared, tb: &Prepared) -> bool {
        let tris = mesh.triangles();
        let (ti, tj) = (tris[ta.index as usize], tris[tb.index as usize]);
        self_pair_intersects(ti, &ta.tri.corners, tj, &tb.tri.corners)
            .unwrap_or_else(|| ta.intersects(tb))
    }
}

/// Do triangles `ti` and `tj` of one mesh (vertex indices, and their corners) intersect beyond
/// the vertices and edge they share? `None` when they share no vertex.
pub(crate) fn self_pair_intersects(
    ti: [u32; 3],
    pi: &[Point; 3],
    tj: [u32; 3],
    pj: &[Point; 3],
) -> Option<bool> {
    // The corners of ti whose vertex tj has (each vertex once), without allocating: this runs
    // for every pair of neighbouring triangles a query meets.
    let mut shared_i = [0usize; 3];
    let mut count = 0;
    for k in 0..3 {
        if tj.contains(&ti[k]) && ti[..k].iter().all(|&v| v != ti[k]) {
            shared_i[count] = k;
            count += 1;
        }
    }
    match count {
        0 => None,
        1 => {
            let k = shared_i[0];
            let l = tj.iter().position(|&v| v == ti[k]).expect("shared");
            let p = &pi[k];
            Some(meet_beyond_vertex(
                p,
                [&pi[(k + 1) % 3], &pi[(k + 2) % 3]],
                [&pj[(l + 1) % 3], &pj[(l + 2) % 3]],
            ))
        }
        2 => {
            let (k1, k2) = (shared_i[0], shared_i[1]);
            let third_i = 3 - k1 - k2;
            let other = |t: [u32; 3], v: u32| t.iter().position(|&x| x == v).expect("shared");
            let (p, q) = (&pi[k1], &pi[k2]);
            let third_j = (0..3)
                .find(|&l| l != other(tj, ti[k1]) && l != other(tj, ti[k2]))
                .expect("a third corner");
            Some(meet_beyond_edge(p, q, &pi[third_i], &pj[third_j]))
        }
        _ => Some(false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::oracle::self_collide_brute_force;
    use crate::fixtures::{Rng, grid, icosphere, torus};
    use crate::mesh::BuildOptions;
    use crate::query::testing::{map_vertices, nodes_cover};
    use crate::query::{Pair, PairKind, QueryMode};
    use crate::threads::{Step, sharing};
    use crate::volume::VolumeKind;

    /// Self-collision of the mesh equals brute force for every volume kind, on 1 and 2 threads;
    /// first hit, the pair limit and the coarse modes keep their promises. Returns the count.
    fn check(positions: &[f64], triangles: &[u32], what: &str) -> usize {
        let mut pairs = Pairs::new();
        let mut count = 0;
        for volume in [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv] {
            let options = BuildOptions {
                volume,
                ..BuildOptions::default()
            };
            let mesh = Mesh::new(positions, triangles, &options).unwrap();
            let expected = self_collide_brute_force(&mesh);
            // Meshes this small are queried on the calling thread whatever the thread count: threads
            // are compared on larger ones (`threads_share_a_large_fold`).
            let threads = 1;
            let q = |mode| QueryOptions {
                mode,
                threads,
                ..QueryOptions::default()
            };
            let stats = self_collide(&mesh, &q(QueryMode::Triangles), &mut pairs).unwrap();
            assert_eq!(pairs.as_slice(), &expected[..], "{what}, {volume:?}");
            assert_eq!(stats.pairs, expected.len() as u64);
            assert_eq!(pairs.kind(), PairKind::Triangles);
            let first = self_collide(&mesh, &q(QueryMode::FirstHit), &mut pairs).unwrap();
            assert_eq!(pairs.len(), expected.len().min(1), "{what}, {volume:?}");
            assert!(pairs.iter().all(|p| expected.contains(p)));
            assert!(!first.truncated);
            if expected.len() > 2 {
                let cut = QueryOptions {
                    max_pairs: Some(2),
                    ..q(QueryMode::Triangles)
                };
                let stats = self_collide(&mesh, &cut, &mut pairs).unwrap();
                assert!(stats.truncated && pairs.len() == 2);
                assert!(pairs.iter().all(|p| expected.contains(p)));
            }
            for mode in [
                QueryMode::Leaves,
                QueryMode::Depth(2),
                QueryMode::Budget(40),
                QueryMode::Budget(1 << 40),
            ] {
                self_collide(&mesh, &q(mode), &mut pairs).unwrap();
                assert_eq!(pairs.kind(), PairKind::Nodes);
                assert!(pairs.iter().all(|p| p.a <= p.b), "{mode:?}");
                nodes_cover(&mesh, &mesh, true, pairs.as_slice(), &expected);
                if mode == QueryMode::Budget(1 << 40) {
                    let leaves = pairs.as_slice().to_vec();
                    self_collide(&mesh, &q(QueryMode::Leaves), &mut pairs).unwrap();
                    assert_eq!(leaves, pairs.as_slice(), "a budget that finishes");
                }
            }
            assert!(matches!(
                self_collide(
                    &mesh,
                    &QueryOptions::with_mode(QueryMode::Budget(0)),
                    &mut pairs
                ),
                Err(crate::error::Error::ZeroBudget)
            ));
            count = expected.len();
        }
        count
    }

    #[test]
    fn threads_share_a_large_fold() {
        // Large enough to be shared out (4,608 triangles): a sheet rolled one and a half turns,
        // its radius shrinking along the roll at one edge and growing at the other, so the turns
        // pass through each other at mid-height.
        let g = grid(48, 1.0);
        let rolled = map_vertices(&g.positions, |v| {
            let t = 3.0 * std::f64::consts::PI * v[0];
            let r = 0.3 + 0.12 * (v[0] - 0.5) * (2.0 * v[1] - 1.0);
            [r * t.cos(), v[1], r * t.sin()]
        });
        let mesh = Mesh::new(&rolled, &g.triangles, &BuildOptions::default()).unwrap();
        let expected = self_collide_brute_force(&mesh);
        assert!(expected.len() > 100, "{} crossings", expected.len());
        let mut pairs = Pairs::new();
        for threads in [1, 2, 0] {
            let options = QueryOptions {
                threads,
                ..QueryOptions::default()
            };
            let steps: &[Step] = if threads == 1 {
                &[]
            } else {
                &[Step::Traversal]
            };
            let what = format!("{threads} threads");
            sharing(steps, &what, || {
                self_collide(&mesh, &options, &mut pairs).unwrap()
            });
            assert_eq!(pairs.as_slice(), &expected[..], "{what}");
            let cut = QueryOptions {
                max_pairs: Some(50),
                ..options
            };
            sharing(steps, &what, || {
                self_collide(&mesh, &cut, &mut pairs).unwrap()
            });
            let first_50: Vec<Pair> = pairs.as_slice().to_vec();
            self_collide(&mesh, &QueryOptions { threads: 1, ..cut }, &mut pairs).unwrap();
            assert_eq!(
                first_50,
                pairs.as_slice(),
                "a cut pair limit is thread-independent"
            );
        }
    }

    #[test]
    fn smooth_patches_never_reach_the_triangle_stage() {
        // A finely subdivided sphere: nodes whose patches face one axis are skipped whole; what
        // remains is the seams between them.
        let s = icosphere(4);
        let mesh = Mesh::new(&s.positions, &s.triangles, &BuildOptions::default()).unwrap();
        let mut pairs = Pairs::new();
        let options = QueryOptions::default();
        let with = self_collide(&mesh, &options, &mut pairs).unwrap();
        assert!(pairs.is_empty());
        let without = self_collide_with(&mesh, &options, false, &mut pairs).unwrap();
        assert!(pairs.is_empty());
        assert!(
            with.triangle_tests * 3 < without.triangle_tests,
            "{} triangle pairs tested with patches, {} without",
            with.triangle_tests,
            without.triangle_tests
        );
    }

    #[test]
    fn intact_surfaces_report_nothing() {
        let s = icosphere(2);
        assert_eq!(check(&s.positions, &s.triangles, "icosphere"), 0);
        let t = torus(0.6, 0.2, 24, 12);
        assert_eq!(check(&t.positions, &t.triangles, "torus"), 0);
        let g = grid(10, 1.0);
        assert_eq!(check(&g.positions, &g.triangles, "flat grid"), 0);
    }

    #[test]
    fn a_sheet_folded_through_itself_reports_its_crossings() {
        // A grid bent along a figure-eight (x, z) = (sin t, sin t cos t), which passes through
        // the origin at t = 0 and t = pi: the sheet crosses itself along a line.
        let g = grid(24, 1.0);
        let folded = map_vertices(&g.positions, |v| {
            let t = -1.0 + (std::f64::consts::PI + 2.0) * v[0];
            [t.sin(), v[1], t.sin() * t.cos()]
        });
        assert!(check(&folded, &g.triangles, "folded sheet") > 0);
    }

    #[test]
    fn a_sheet_folded_flat_onto_itself_overlaps() {
        // The right half of a flat grid reflected onto the left half, in the same plane: the
        // triangles along the fold share edges with their mirror images' neighbours, and the
        // halves overlap everywhere.
        let g = grid(8, 1.0);
        let folded = map_vertices(&g.positions, |v| [0.5 - (v[0] - 0.5).abs(), v[1], 0.0]);
        assert!(check(&folded, &g.triangles, "flat fold") > 0);
    }

    #[test]
    fn random_crumpling_and_degenerate_triangles() {
        let mut rng = Rng::new(5);
        let t = torus(0.6, 0.25, 16, 8);
        for trial in 0..6 {
            let amplitude = [0.05, 0.2, 0.5][trial % 3];
            let mut positions: Vec<f64> = t
                .positions
                .iter()
                .map(|x| x + rng.range(-amplitude, amplitude))
                .collect();
            if trial >= 3 {
                // Collapse some vertices onto others: degenerate and needle triangles.
                for k in 0..10 {
                    let (from, to) = (rng.below(t.vertex_count() as u64) as usize, k);
                    for c in 0..3 {
                        positions[3 * from + c] = positions[3 * to + c];
                    }
                }
            }
            check(&positions, &t.triangles, &format!("crumpled torus {trial}"));
        }
    }
}
