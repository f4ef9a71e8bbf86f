//! Which triangle speaks for each vertex and edge of a mesh in continuous collision, and which
//! leaf speaks for each triangle, so that a traversal reporting a triangle pair several times
//! (a triangle lies in up to three rings) tests each vertex-face and edge-edge pair once.
//!
//! Every vertex and edge is owned by the first triangle that has it, every triangle by the first
//! ring that holds it. A primitive pair is tested only where the leaf pair of the owning rings
//! meets the pair of owning triangles. Nothing is missed: an owner's volume holds everything it
//! owns, so a contact puts the owners' volumes in overlap and the traversal reports their pair.

use crate::tree::RingTable;

/// Ownership of a mesh's vertices, edges and triangles; depends on the shape only.
#[derive(Clone, Debug, Default)]
pub(crate) struct Features {
    /// Per triangle, the ring (= leaf) that owns it.
    pub owner_ring: Vec<u32>,
    /// Per triangle: bit `k` (0 to 2) set when it owns its corner `k`, bit `3 + k` when it owns
    /// its side from corner `k` to corner `k + 1` (mod 3).
    pub owned: Vec<u8>,
    /// Distinct edges: pairs of distinct vertices joined by a triangle side.
    pub edge_count: usize,
}

impl Features {
    /// The ownership of `triangles`, whose rings are `rings`.
    pub fn new(triangles: &[[u32; 3]], rings: &RingTable, vertex_count: usize) -> Features {
        let mut owned = vec![0u8; triangles.len()];
        let mut seen = vec![false; vertex_count];
        for (t, tri) in triangles.iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                if !seen[v as usize] {
                    seen[v as usize] = true;
                    owned[t] |= 1 << k;
                }
            }
        }
        // Sides as (low, high, triangle, side), sorted: the first of each run owns the edge.
        let mut sides: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                if u != v {
                    sides.push((u.min(v), u.max(v), t as u32, k as u8));
                }
            }
        }
        sides.sort_unstable();
        let mut edge_count = 0;
        for (i, &(u, v, t, k)) in sides.iter().enumerate() {
            if i == 0 || (sides[i - 1].0, sides[i - 1].1) != (u, v) {
                owned[t as usize] |= 1 << (3 + k);
                edge_count += 1;
            }
        }
        let mut owner_ring = vec![u32::MAX; triangles.len()];
        for r in 0..rings.centre.len() {
            for &t in rings.triangles.row(r) {
                let o = &mut owner_ring[t as usize];
                if *o == u32::MAX {
                    *o = r as u32;
                }
            }
        }
        debug_assert!(owner_ring.iter().all(|&r| r != u32::MAX), "rings cover");
        Features {
            owner_ring,
            owned,
            edge_count,
        }
    }

    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        crate::csr::heap_bytes(&self.owner_ring) + crate::csr::heap_bytes(&self.owned)
    }
}
