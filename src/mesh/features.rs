//! Which ring (= leaf) speaks for each vertex, edge and triangle of a mesh in the queries on
//! vertex-face and edge-edge pairs, so that a vertex or an edge shared by several rings'
//! triangles is tested once against each primitive.
//!
//! Every triangle is owned by the first ring that holds it, every vertex and
//! edge by the ring of the first triangle that has it. A primitive pair is tested only where
//! the leaf pair of the owning rings is reported. Nothing is missed: a ring's volume holds its
//! triangles, so a contact puts the owners' volumes in overlap and the traversal reports their
//! pair.

use crate::csr::Csr;
use crate::tree::RingTable;

/// What each ring owns, row by row in ring order (so a node's rings own one contiguous run of
/// each list); depends on the shape only.
#[derive(Clone, Debug, Default)]
pub(crate) struct Features {
    /// Per ring, the triangles it owns.
    pub triangles: Csr<u32>,
    /// Per ring, the vertices it owns.
    pub vertices: Csr<u32>,
    /// Per ring, the edges it owns: pairs of distinct vertices joined by a triangle side, the
    /// lower index first.
    pub edges: Csr<[u32; 2]>,
}

impl Features {
    /// The ownership of `triangles`, whose rings are `rings`.
    pub fn new(triangles: &[[u32; 3]], rings: &RingTable, vertex_count: usize) -> Features {
        let ring_count = rings.centre.len();
        let mut triangle_owner = vec![u32::MAX; triangles.len()];
        for r in 0..ring_count {
            for &t in rings.triangles.row(r) {
                let o = &mut triangle_owner[t as usize];
                if *o == u32::MAX {
                    *o = r as u32;
                }
            }
        }
        debug_assert!(triangle_owner.iter().all(|&r| r != u32::MAX), "rings cover");
        let mut vertex_owner = vec![u32::MAX; vertex_count];
        for (tri, &r) in triangles.iter().zip(&triangle_owner) {
            for &v in tri {
                if vertex_owner[v as usize] == u32::MAX {
                    vertex_owner[v as usize] = r;
                }
            }
        }
        // Sides as (low, high, triangle) in that order, the first of each (low, high) run
        // owning the edge: grouped by their low vertex in two linear passes, then each group
        // (a vertex's few sides) sorted alone, a fraction of one sort of them all.
        let by_low = Csr::from_entries(vertex_count, || {
            triangles.iter().enumerate().flat_map(|(t, tri)| {
                (0..3).filter_map(move |k| {
                    let (u, v) = (tri[k], tri[(k + 1) % 3]);
                    (u != v).then(|| (u.min(v), (u.max(v), t as u32)))
                })
            })
        });
        let mut sides: Vec<(u32, u32, u32)> = Vec::with_capacity(by_low.items().len());
        let mut group = Vec::new();
        for low in 0..vertex_count {
            group.clear();
            group.extend_from_slice(by_low.row(low));
            group.sort_unstable();
            group.dedup_by_key(|s| s.0);
            sides.extend(group.iter().map(|&(high, t)| (low as u32, high, t)));
        }
        Features {
            triangles: Csr::from_entries(ring_count, || {
                triangle_owner
                    .iter()
                    .enumerate()
                    .map(|(t, &r)| (r, t as u32))
            }),
            vertices: Csr::from_entries(ring_count, || {
                vertex_owner
                    .iter()
                    .enumerate()
                    .filter(|&(_, &r)| r != u32::MAX)
                    .map(|(v, &r)| (r, v as u32))
            }),
            edges: Csr::from_entries(ring_count, || {
                sides
                    .iter()
                    .map(|&(u, v, t)| (triangle_owner[t as usize], [u, v]))
            }),
        }
    }

    /// Distinct edges: pairs of distinct vertices joined by a triangle side.
    pub fn edge_count(&self) -> usize {
        self.edges.items().len()
    }

    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        self.triangles.heap_bytes() + self.vertices.heap_bytes() + self.edges.heap_bytes()
    }
}

#[cfg(test)]
mod tests {
    use crate::fixtures::{self, oracle};
    use crate::{BuildOptions, LeftoverPolicy, Mesh};

    /// Every triangle, used vertex and edge is owned once, by a ring that holds it (a
    /// triangle of its row, or one with that vertex or side).
    #[test]
    fn each_primitive_is_owned_once_by_a_ring_that_holds_it() {
        let mut with_degenerate = fixtures::grid(6, 1.0);
        with_degenerate.triangles.extend([0, 0, 1, 2, 2, 2]);
        for data in [
            fixtures::torus(1.0, 0.3, 12, 8),
            fixtures::icosphere(2),
            fixtures::soup(40, 1.0, 0.2, 7),
            with_degenerate,
        ] {
            for policy in [LeftoverPolicy::JoinAdjacent, LeftoverPolicy::ExtraRings] {
                let options = BuildOptions::default().with_leftovers(policy);
                let m = Mesh::new(&data.positions, &data.triangles, &options).unwrap();
                let (f, rings, tris) = (m.features(), m.rings(), m.triangles());
                let rows = rings.centre.len();
                assert_eq!(f.triangles.rows(), rows);
                let mut owned_tris = f.triangles.items().to_vec();
                owned_tris.sort_unstable();
                assert_eq!(owned_tris, (0..tris.len() as u32).collect::<Vec<_>>());
                let mut owned_vertices = f.vertices.items().to_vec();
                owned_vertices.sort_unstable();
                assert_eq!(owned_vertices, oracle::used_vertices(&m));
                let mut owned_edges = f.edges.items().to_vec();
                owned_edges.sort_unstable();
                assert_eq!(owned_edges, oracle::edges(&m));
                let mut owner = vec![0; tris.len()];
                for r in 0..rows {
                    for &t in f.triangles.row(r) {
                        owner[t as usize] = r;
                    }
                }
                for r in 0..rows {
                    // In order, each owned by the ring of the first triangle with that side.
                    let edges = f.edges.row(r);
                    assert!(edges.windows(2).all(|w| w[0] < w[1]), "ring {r}: {edges:?}");
                    for e in edges {
                        let first = tris.iter().position(|t| {
                            (0..3).any(|k| {
                                let (u, w) = (t[k], t[(k + 1) % 3]);
                                [u.min(w), u.max(w)] == *e
                            })
                        });
                        assert_eq!(first.map(|t| owner[t]), Some(r), "edge {e:?}");
                    }
                }
                for r in 0..rows {
                    let held = rings.triangles.row(r);
                    for t in f.triangles.row(r) {
                        assert!(
                            held.contains(t),
                            "ring {r} owns triangle {t} it does not hold"
                        );
                    }
                    for v in f.vertices.row(r) {
                        let has = |&t: &u32| tris[t as usize].contains(v);
                        assert!(held.iter().any(has), "ring {r} owns vertex {v}");
                    }
                    for e in f.edges.row(r) {
                        let has = |&t: &u32| {
                            (0..3).any(|k| {
                                let (u, w) = (tris[t as usize][k], tris[t as usize][(k + 1) % 3]);
                                [u.min(w), u.max(w)] == *e
                            })
                        };
                        assert!(held.iter().any(has), "ring {r} owns edge {e:?}");
                    }
                }
            }
        }
    }
}
