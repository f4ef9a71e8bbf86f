//! 1-ring construction: the leaves of the hierarchy.
//!
//! A 1-ring is a centre vertex and triangles incident to it. The paper (Fig. 2) walks the mesh
//! breadth-first over triangles and makes every unmarked vertex of a popped triangle a centre.
//! We read "mark" as marking the centre *and* its neighbours, so centres form an independent set:
//! no two centres share an edge, hence no triangle belongs to two rings, and a ring holds every
//! triangle incident to its centre. The walk visits every triangle (each popped triangle pushes
//! its vertex-adjacent neighbours), one component after another, seeded at the lowest-numbered
//! unvisited triangle so that builds are deterministic.
//!
//! Triangles none of whose vertices became a centre ("leftovers", about a quarter on scanned
//! meshes) must still be covered, or collisions would be missed. [`LeftoverPolicy`] chooses how.

use crate::csr::Csr;
use crate::geometry::predicates::Point;
use crate::geometry::sphere::distance_squared;
use crate::tree::distinct_corners;
use std::collections::VecDeque;

/// How triangles that touch no ring centre are put into leaves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LeftoverPolicy {
    /// Each joins an adjacent ring, one across an edge of it where there is one (so that leaves
    /// stay disks, which self-collision can prove free of self-intersection), the one whose
    /// centre is nearest (at build-time positions): fewer leaves, somewhat larger leaf spheres.
    #[default]
    JoinAdjacent,
    /// Extra rings are centred on leftover vertices (greedily, the vertex with most uncovered
    /// triangles first), each holding only uncovered triangles: more leaves, tighter spheres.
    ExtraRings,
}

const NONE: u32 = u32::MAX;

/// Rings in construction order: ring `r` is centred on `centre[r]` and holds the triangles
/// `triangles.row(r)`. Every triangle is in exactly one ring.
pub(crate) struct Rings {
    pub centre: Vec<u32>,
    pub triangles: Csr<u32>,
}

/// Vertex to incident triangles: row `v` lists the triangles with `v` as a corner.
fn incidence(vertex_count: usize, triangles: &[[u32; 3]]) -> Csr<u32> {
    Csr::from_entries(vertex_count, || {
        triangles
            .iter()
            .enumerate()
            .flat_map(|(t, tri)| distinct_corners(tri).map(move |v| (v, t as u32)))
    })
}

/// Builds the rings of a mesh. Positions are only used by [`LeftoverPolicy::JoinAdjacent`].
pub(crate) fn build_rings(
    vertex_count: usize,
    triangles: &[[u32; 3]],
    positions: &[Point],
    policy: LeftoverPolicy,
) -> Rings {
    let incidence = incidence(vertex_count, triangles);
    let mut claimed_by = vec![NONE; vertex_count];
    let mut ring_of = vec![NONE; triangles.len()];
    let mut queued = vec![false; triangles.len()];
    let mut popped = Vec::with_capacity(triangles.len());
    let mut centre = Vec::new();
    let mut queue = VecDeque::new();

    for seed in 0..triangles.len() {
        if queued[seed] {
            continue;
        }
        queued[seed] = true;
        queue.push_back(seed as u32);
        while let Some(t) = queue.pop_front() {
            popped.push(t);
            let tri = &triangles[t as usize];
            for v in distinct_corners(tri) {
                if claimed_by[v as usize] != NONE {
                    continue;
                }
                let r = centre.len() as u32;
                centre.push(v);
                claimed_by[v as usize] = r;
                for &t2 in incidence.row(v as usize) {
                    debug_assert_eq!(
                        ring_of[t2 as usize], NONE,
                        "rings of an independent set are disjoint"
                    );
                    ring_of[t2 as usize] = r;
                    for &w in &triangles[t2 as usize] {
                        if claimed_by[w as usize] == NONE {
                            claimed_by[w as usize] = r;
                        }
                    }
                }
            }
            for v in distinct_corners(tri) {
                for &t2 in incidence.row(v as usize) {
                    if !queued[t2 as usize] {
                        queued[t2 as usize] = true;
                        queue.push_back(t2);
                    }
                }
            }
        }
    }

    // Leftovers, in the order the walk met them so that new rings stay spatially coherent.
    for &t in &popped {
        if ring_of[t as usize] != NONE {
            continue;
        }
        let tri = &triangles[t as usize];
        match policy {
            LeftoverPolicy::ExtraRings => {
                let uncovered = |v: u32| {
                    incidence
                        .row(v as usize)
                        .iter()
                        .filter(|&&t2| ring_of[t2 as usize] == NONE)
                        .count()
                };
                let v = distinct_corners(tri)
                    .max_by_key(|&v| (uncovered(v), std::cmp::Reverse(v)))
                    .expect("a triangle has a corner");
                let r = centre.len() as u32;
                centre.push(v);
                for &t2 in incidence.row(v as usize) {
                    if ring_of[t2 as usize] == NONE {
                        ring_of[t2 as usize] = r;
                    }
                }
            }
            LeftoverPolicy::JoinAdjacent => {
                // Every corner of a walked triangle is a centre or claimed by one; none of these
                // is a centre (the triangle would be covered), so each names an adjacent ring.
                let reach = |r: u32| {
                    let c = &positions[centre[r as usize] as usize];
                    tri.iter()
                        .map(|&w| distance_squared(c, &positions[w as usize]))
                        .fold(0.0f64, f64::max)
                };
                // A ring across one of the triangle's edges first: joined by a corner alone, the
                // leaf's patch would be pinched there, not a disk, and self-collision could not
                // prove it free of self-intersection.
                let across = (0..3).filter_map(|k| {
                    let (u, w) = (tri[k], tri[(k + 1) % 3]);
                    incidence.row(u as usize).iter().find_map(|&t2| {
                        let r = ring_of[t2 as usize];
                        (t2 != t && r != NONE && triangles[t2 as usize].contains(&w)).then_some(r)
                    })
                });
                let nearest = |rings: &mut dyn Iterator<Item = u32>| {
                    rings.min_by(|&r1, &r2| reach(r1).total_cmp(&reach(r2)).then(r1.cmp(&r2)))
                };
                let r = nearest(&mut across.into_iter())
                    .or_else(|| nearest(&mut distinct_corners(tri).map(|v| claimed_by[v as usize])))
                    .expect("a triangle has a corner");
                debug_assert_ne!(r, NONE);
                ring_of[t as usize] = r;
            }
        }
    }

    let members = Csr::from_entries(centre.len(), || {
        ring_of.iter().enumerate().map(|(t, &r)| (r, t as u32))
    });
    Rings {
        centre,
        triangles: members,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> (Vec<Point>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                p.push([i as f64, j as f64, 0.0]);
            }
        }
        let mut t = Vec::new();
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (p, t)
    }

    fn check_cover(rings: &Rings, triangles: &[[u32; 3]], policy: LeftoverPolicy) {
        let mut seen = vec![0; triangles.len()];
        for r in 0..rings.centre.len() {
            let c = rings.centre[r];
            for &t in rings.triangles.row(r) {
                seen[t as usize] += 1;
                if policy == LeftoverPolicy::ExtraRings {
                    assert!(
                        triangles[t as usize].contains(&c),
                        "ring {r} holds triangle {t} not incident to its centre"
                    );
                }
            }
        }
        assert!(
            seen.iter().all(|&s| s == 1),
            "every triangle in exactly one ring"
        );
    }

    #[test]
    fn grid_rings_cover_and_are_fewer_than_triangles() {
        let (p, t) = grid(20);
        for policy in [LeftoverPolicy::JoinAdjacent, LeftoverPolicy::ExtraRings] {
            let rings = build_rings(p.len(), &t, &p, policy);
            check_cover(&rings, &t, policy);
            let ratio = rings.centre.len() as f64 / t.len() as f64;
            assert!(ratio < 0.35, "{policy:?}: {ratio}");
        }
    }

    #[test]
    fn odd_inputs() {
        // Two components, a repeated-index triangle, a fully degenerate one, an unreferenced
        // vertex (5) and a non-manifold fan of three triangles on edge 0-1.
        let p: Vec<Point> = (0..9).map(|i| [i as f64, (i * i) as f64, 0.0]).collect();
        let t = vec![
            [0, 1, 2],
            [0, 1, 3],
            [1, 0, 4],
            [6, 6, 7],
            [8, 8, 8],
            [2, 3, 4],
        ];
        for policy in [LeftoverPolicy::JoinAdjacent, LeftoverPolicy::ExtraRings] {
            let rings = build_rings(p.len(), &t, &p, policy);
            check_cover(&rings, &t, policy);
            assert!(!rings.centre.contains(&5));
        }
    }
}
