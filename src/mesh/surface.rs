//! What the distance and inside-outside queries need of a mesh's topology, found once on first
//! use (the triangles never change): whether the surface is closed, and which triangle speaks
//! for each vertex and edge in a result.
//!
//! Closed means that every directed side `(u, v)` of a triangle is matched by as many sides
//! `(v, u)` of triangles (a side `(u, u)` of a degenerate triangle matches itself): the surface
//! bounds a region, and winding numbers are integers that do not depend on the ray that counts
//! them. Triangles are not required to be non-degenerate, nor the surface free of
//! self-intersection or manifold.

/// A mesh's surface, as the distance queries see it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Surface {
    /// The least directed side `(u, v)` (by `(min(u, v), max(u, v))`) with fewer sides `(v, u)`
    /// than sides `(u, v)`; `None` when the surface is closed.
    pub open_edge: Option<[u32; 2]>,
    /// Per vertex, the least index of a triangle holding it (`u32::MAX`: a vertex of no
    /// triangle).
    pub vertex_triangle: Vec<u32>,
    /// The edges (pairs of distinct vertices joined by a triangle side, the lower first), sorted,
    /// each with the least index of a triangle holding it.
    pub edges: Vec<([u32; 2], u32)>,
}

impl Surface {
    /// The surface of `triangles` over `vertex_count` vertices.
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> Surface {
        let mut vertex_triangle = vec![u32::MAX; vertex_count];
        // Sides as (lower, higher, triangle, direction): +1 from lower to higher, -1 back.
        let mut sides: Vec<([u32; 2], u32, i32)> = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                let first = &mut vertex_triangle[u as usize];
                *first = (*first).min(t as u32);
                if u != v {
                    let way = if u < v { 1 } else { -1 };
                    sides.push(([u.min(v), u.max(v)], t as u32, way));
                }
            }
        }
        sides.sort_unstable();
        let mut edges = Vec::new();
        let mut open_edge = None;
        for run in sides.chunk_by(|x, y| x.0 == y.0) {
            let ([lo, hi], least, _) = run[0];
            edges.push(([lo, hi], least));
            let net: i32 = run.iter().map(|s| s.2).sum();
            if open_edge.is_none() && net != 0 {
                // More sides one way than the other: one of them has no reverse.
                open_edge = Some(if net > 0 { [lo, hi] } else { [hi, lo] });
            }
        }
        Surface {
            open_edge,
            vertex_triangle,
            edges,
        }
    }

    /// The least triangle holding the edge of `u` and `v` (in either order), if it is one.
    pub fn edge_triangle(&self, u: u32, v: u32) -> Option<u32> {
        let key = [u.min(v), u.max(v)];
        self.edges
            .binary_search_by(|e| e.0.cmp(&key))
            .ok()
            .map(|i| self.edges[i].1)
    }

    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        crate::csr::heap_bytes(&self.vertex_triangle) + crate::csr::heap_bytes(&self.edges)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tetrahedron_is_closed_and_loses_it_with_a_face() {
        let tets = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
        let s = Surface::new(&tets, 4);
        assert_eq!(s.open_edge, None);
        assert_eq!(s.vertex_triangle, vec![0, 0, 0, 1]);
        assert_eq!(s.edges.len(), 6);
        assert_eq!(s.edge_triangle(3, 2), Some(2));
        assert_eq!(s.edge_triangle(0, 0), None);
        // Without its last face, the sides of that face lack their reverses: the least is
        // (0, 2) (the missing face ran 2 -> 0).
        let s = Surface::new(&tets[..3], 4);
        assert_eq!(s.open_edge, Some([0, 2]));
        // Doubled faces of opposite orientation close each other; a doubled face of one
        // orientation does not.
        let s = Surface::new(&[[0, 1, 2], [0, 2, 1]], 3);
        assert_eq!(s.open_edge, None);
        let s = Surface::new(&[[0, 1, 2], [0, 1, 2]], 3);
        assert_eq!(s.open_edge, Some([0, 1]));
        // A degenerate side matches itself; an unreferenced vertex belongs to no triangle.
        let s = Surface::new(&[[0, 0, 1], [0, 1, 0]], 3);
        assert_eq!(s.open_edge, None);
        assert_eq!(s.vertex_triangle[2], u32::MAX);
    }
}
