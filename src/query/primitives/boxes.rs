//! The boxes of the primitives each ring owns, as a query's test sees them, computed once per
//! query for the rings below its node pairs. A leaf takes part in several node pairs (about
//! four each on a self query), and building its primitives' boxes anew for each cost more than
//! the primitive tests they spared.

use super::vocabulary::{Owners, PrimitiveTest, Side};
use crate::geometry::aabb::Aabb;
use crate::query::engine::Stamped;
use std::ops::Range;

/// The boxes of one mesh's owned primitives, at the positions of [`crate::mesh::Features`]'
/// items, and of each ring; current only for the rings [`OwnedBoxes::fill`] was asked for.
#[derive(Debug, Default)]
pub(crate) struct OwnedBoxes {
    pub vertices: Vec<Aabb>,
    pub triangles: Vec<Aabb>,
    pub edges: Vec<Aabb>,
    /// Per ring, the box of the triangles it owns, which holds every primitive it owns; current
    /// for the rings asked for this query (the work is theirs, not the mesh's).
    rings: Stamped<Aabb>,
}

/// `v` grown to at least `n` entries; the bytes asked for if it cannot grow.
fn sized(v: &mut Vec<Aabb>, n: usize) -> Result<(), usize> {
    if v.len() < n {
        if v.try_reserve(n - v.len()).is_err() {
            return Err(n * std::mem::size_of::<Aabb>());
        }
        v.resize(n, Aabb::EMPTY);
    }
    Ok(())
}

impl OwnedBoxes {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        use crate::csr::heap_bytes;
        heap_bytes(&self.vertices)
            + heap_bytes(&self.triangles)
            + heap_bytes(&self.edges)
            + self.rings.heap_bytes()
    }

    /// Computes the boxes of the primitives owned by the rings below `nodes` of `owners`, the
    /// mesh on `side` of `test`; those of other rings are stale from here on. Errors: the
    /// bytes that could not be allocated.
    pub fn fill<T: PrimitiveTest>(
        &mut self,
        owners: &Owners,
        side: Side,
        test: &T,
        nodes: impl Iterator<Item = u32>,
    ) -> Result<(), usize> {
        let f = owners.features;
        sized(&mut self.vertices, f.vertices.items().len())?;
        sized(&mut self.triangles, f.triangles.items().len())?;
        sized(&mut self.edges, f.edges.items().len())?;
        self.rings.begin(f.triangles.rows());
        let boxed = |vertices: &[u32]| {
            let mut b = Aabb::EMPTY;
            for &v in vertices {
                test.grow(side, v, &mut b);
            }
            b
        };
        let corners = owners.mesh.triangles();
        let tree = &owners.mesh.tree().nodes;
        for n in nodes {
            let node = &tree[n as usize];
            for r in node.ring_start as usize..node.ring_end as usize {
                let (triangles, vertices, edges) =
                    (&mut self.triangles, &mut self.vertices, &mut self.edges);
                self.rings.get_or(r, || {
                    let mut all = Aabb::EMPTY;
                    for i in f.triangles.span(r..r + 1) {
                        let b = boxed(&corners[f.triangles.items()[i] as usize]);
                        all.merge(&b);
                        triangles[i] = b;
                    }
                    for i in f.vertices.span(r..r + 1) {
                        vertices[i] = boxed(&[f.vertices.items()[i]]);
                    }
                    for i in f.edges.span(r..r + 1) {
                        edges[i] = boxed(&f.edges.items()[i]);
                    }
                    all
                });
            }
        }
        Ok(())
    }

    /// The box of every primitive the rings `rings` own (all filled).
    #[inline]
    pub fn of_rings(&self, rings: Range<usize>) -> Aabb {
        let r = &self.rings;
        debug_assert!(r.stamp[rings.clone()].iter().all(|&s| s == r.current));
        let mut all = Aabb::EMPTY;
        for b in &r.values[rings] {
            all.merge(b);
        }
        all
    }
}
