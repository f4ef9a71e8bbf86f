//! [`RingTable`]: the 1-rings in leaf order, as the refit and the query read them.

use crate::csr::{Csr, heap_bytes};

/// The rings renumbered in leaf order (the rings below any node are a contiguous range), with
/// their triangles and their distinct vertices.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct RingTable {
    /// Ring `r` is centred on vertex `centre[r]`.
    pub centre: Vec<u32>,
    /// Triangles of each ring.
    pub triangles: Csr<u32>,
    /// Corners of `triangles.items()[i]`, stored alongside so that the query reads a ring's
    /// triangles from one contiguous run instead of jumping through the mesh's triangle array.
    pub corners: Vec<[u32; 3]>,
    /// Distinct vertices of each ring's triangles other than its centre.
    pub vertices: Csr<u32>,
    /// The most triangles of any ring (the least room a query's cache of prepared rings needs).
    pub longest: usize,
}

impl RingTable {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        heap_bytes(&self.centre)
            + self.triangles.heap_bytes()
            + heap_bytes(&self.corners)
            + self.vertices.heap_bytes()
    }
}

impl RingTable {
    /// The rings centred on `centre` with triangles `ring_triangles` (rows of indices into
    /// `triangles`), in the order `order` (a permutation of their indices).
    pub fn new(
        (centres, ring_triangles): (&[u32], &Csr<u32>),
        order: &[u32],
        triangles: &[[u32; 3]],
        vertex_count: usize,
    ) -> RingTable {
        let mut centre = Vec::with_capacity(order.len());
        let mut tris = Csr::with_capacity(order.len(), ring_triangles.items().len());
        let mut verts = Csr::with_capacity(order.len(), 0);
        let mut seen = vec![u32::MAX; vertex_count];
        for (new, &old) in order.iter().enumerate() {
            let c = centres[old as usize];
            centre.push(c);
            seen[c as usize] = new as u32;
            for &t in ring_triangles.row(old as usize) {
                tris.push(t);
                for v in distinct_corners(&triangles[t as usize]) {
                    if seen[v as usize] != new as u32 {
                        seen[v as usize] = new as u32;
                        verts.push(v);
                    }
                }
            }
            tris.end_row();
            verts.end_row();
        }
        let corners = tris
            .items()
            .iter()
            .map(|&t| triangles[t as usize])
            .collect();
        let longest = (0..tris.rows()).map(|r| tris.row_len(r)).max().unwrap_or(0);
        RingTable {
            centre,
            longest,
            triangles: tris,
            corners,
            vertices: verts,
        }
    }

    /// Number of rings.
    #[inline]
    pub fn len(&self) -> usize {
        self.centre.len()
    }

    /// Every vertex of ring `r`: its centre first, then the others.
    #[inline]
    pub fn all_vertices(&self, r: usize) -> impl Iterator<Item = u32> + '_ {
        std::iter::once(self.centre[r]).chain(self.vertices.row(r).iter().copied())
    }

    /// [`RingTable::all_vertices`] of ring `r` if it comes before ring `end`.
    #[inline]
    pub fn vertices_of(&self, r: usize, end: usize) -> Option<impl Iterator<Item = u32> + '_> {
        (r < end).then(|| self.all_vertices(r))
    }
}

/// The distinct corners of a triangle (repeated indices are legal input).
#[inline]
pub(crate) fn distinct_corners(t: &[u32; 3]) -> impl Iterator<Item = u32> + '_ {
    t.iter()
        .enumerate()
        .filter(|&(i, v)| !t[..i].contains(v))
        .map(|(_, &v)| v)
}
