//! What one node keeps of its primitives for a node pair: the positions, boxes and vertices of
//! those whose boxes come within reach of the other node, kept without a branch.

use crate::geometry::aabb::Aabb;

/// One node's primitives, each with its box, in the order of the node's rings: the positions
/// `k` of each list are one primitive, its box at `k` of the boxes.
#[derive(Clone, Copy)]
pub(super) struct Primitives<'p> {
    pub triangle_boxes: &'p [Aabb],
    pub triangles: &'p [u32],
    pub vertex_boxes: &'p [Aabb],
    pub vertices: &'p [u32],
    pub edge_boxes: &'p [Aabb],
    pub edges: &'p [[u32; 2]],
}

/// Some primitives of a [`Primitives`] list: their positions in it, their boxes and their
/// vertices, the first `len` of each list (the lists only grow, so that keeping writes no more
/// than it keeps).
#[derive(Debug, Default)]
pub(super) struct Subset<I> {
    pub at: Vec<u32>,
    pub boxes: Vec<Aabb>,
    pub vertices: Vec<I>,
    pub len: usize,
}

impl<I: Copy + Default> Subset<I> {
    /// Keeps the positions `k` of `boxes` whose box comes within `d` of `near` (all, without
    /// `near`; [`Aabb::reach`] may keep a few more, by rounding), in order, with their boxes
    /// and `vertices(k)`. Written without a branch on the box test: about half are kept, in no
    /// pattern a predictor learns on a scanned mesh, and a mispredicted branch cost more than
    /// the test.
    #[inline(always)]
    pub fn keep(
        &mut self,
        boxes: &[Aabb],
        vertices: impl Fn(usize) -> I,
        near: Option<&Aabb>,
        d: f64,
    ) {
        let n = boxes.len();
        if self.at.len() < n {
            self.at.resize(n, 0);
            self.boxes.resize(n, Aabb::EMPTY);
            self.vertices.resize(n, I::default());
        }
        // Slices, so that the lists' pointers are not reloaded after every store.
        let (at, kept, of) = (
            &mut self.at[..n],
            &mut self.boxes[..n],
            &mut self.vertices[..n],
        );
        let mut m = 0;
        match near {
            None => {
                for (k, x) in at.iter_mut().enumerate() {
                    *x = k as u32;
                }
                m = n;
            }
            Some(o) => {
                let o = o.reach(d);
                for (k, b) in boxes.iter().enumerate() {
                    at[m] = k as u32;
                    m += b.meets(&o) as usize;
                }
            }
        }
        // Then the boxes and vertices of those kept only.
        for ((&k, b), v) in at[..m].iter().zip(&mut kept[..m]).zip(&mut of[..m]) {
            *b = boxes[k as usize];
            *v = vertices(k as usize);
        }
        self.len = m;
    }

    /// The positions kept.
    #[inline(always)]
    pub fn at(&self) -> &[u32] {
        &self.at[..self.len]
    }

    /// Their boxes.
    #[inline(always)]
    pub fn boxes(&self) -> &[Aabb] {
        &self.boxes[..self.len]
    }

    /// Their vertices.
    #[inline(always)]
    pub fn vertices(&self) -> &[I] {
        &self.vertices[..self.len]
    }

    pub fn heap_bytes(&self) -> usize {
        use crate::csr::heap_bytes;
        heap_bytes(&self.at) + heap_bytes(&self.boxes) + heap_bytes(&self.vertices)
    }
}

/// What one node keeps of its primitives for a node pair.
#[derive(Debug, Default)]
pub(super) struct Kept {
    /// With their corners.
    pub triangles: Subset<[u32; 3]>,
    pub vertices: Subset<u32>,
    pub edges: Subset<[u32; 2]>,
}

impl Kept {
    /// Keeps the primitives of `p`, whose triangles' corners are `corners`, whose boxes come
    /// within `d` of `near` (all, without it).
    #[inline(always)]
    pub fn keep(&mut self, p: &Primitives, corners: &[[u32; 3]], near: Option<&Aabb>, d: f64) {
        self.keep_triangles(p, corners, near, d);
        self.vertices
            .keep(p.vertex_boxes, |k| p.vertices[k], near, d);
        self.edges.keep(p.edge_boxes, |k| p.edges[k], near, d);
    }

    /// [`Kept::keep`]'s triangles alone, with their corners.
    #[inline(always)]
    pub fn keep_triangles(
        &mut self,
        p: &Primitives,
        corners: &[[u32; 3]],
        near: Option<&Aabb>,
        d: f64,
    ) {
        let of_triangle = |k: usize| corners[p.triangles[k] as usize];
        self.triangles.keep(p.triangle_boxes, of_triangle, near, d);
    }
}

/// Boxes built for one node pair, when the query's boxes change as it goes (no table).
#[derive(Debug, Default)]
pub(super) struct Built {
    pub triangles: Vec<Aabb>,
    pub vertices: Vec<Aabb>,
    pub edges: Vec<Aabb>,
}

/// A worker's scratch space for one node pair, per side.
#[derive(Debug, Default)]
pub(super) struct Scratch {
    pub kept: [Kept; 2],
    pub built: [Built; 2],
}

impl Scratch {
    pub fn heap_bytes(&self) -> usize {
        use crate::csr::heap_bytes;
        let kept =
            |k: &Kept| k.triangles.heap_bytes() + k.vertices.heap_bytes() + k.edges.heap_bytes();
        let built =
            |b: &Built| heap_bytes(&b.triangles) + heap_bytes(&b.vertices) + heap_bytes(&b.edges);
        self.kept.iter().map(kept).sum::<usize>() + self.built.iter().map(built).sum::<usize>()
    }
}
