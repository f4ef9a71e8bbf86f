//! Building a [`Mesh`]: input checks, 1-rings, the top-down split, node centres, first fit.

use super::input::{check_triangles, scan_positions, to_points};
use super::mesh::{BuildOptions, Mesh, Node, RefitStats, TreeKind};
use super::rings::{Rings, build_rings, distinct_corners};
use crate::error::{Error, Result};
use crate::geometry::predicates::Point;
use crate::geometry::sphere::distance_squared;

/// A split that leaves less than this fraction (1/16) of the rings on its smallest side (binary)
/// or more than 15/16 in one octant is redone at the median. Midpoint splits follow the geometry
/// and are what the paper builds; the median guard bounds the depth by `O(log n)` on inputs with
/// wildly uneven spacing, so the build stays `O(n log n)`.
const IMBALANCE: usize = 16;

impl Mesh {
    /// [`Mesh::new`] with each vertex's coordinates given by `position(i)` for `i` in
    /// `0..vertex_count`, for positions stored in another layout (interleaved, `f32`, ...).
    pub fn new_with(
        vertex_count: usize,
        position: impl Fn(usize) -> Point,
        triangles: &[u32],
        options: &BuildOptions,
    ) -> Result<Mesh> {
        if vertex_count > u32::MAX as usize {
            return Err(Error::TooManyVertices {
                count: vertex_count,
            });
        }
        ensure_memory(vertex_count, triangles.len() / 3)?;
        let mut flat = Vec::with_capacity(vertex_count * 3);
        for i in 0..vertex_count {
            flat.extend_from_slice(&position(i));
        }
        Mesh::new(&flat, triangles, options)
    }

    /// Builds the hierarchy of a mesh.
    ///
    /// `positions` holds `x, y, z` per vertex; `triangles` holds three vertex indices per
    /// triangle. Degenerate triangles, repeated indices, boundaries, non-manifold edges, several
    /// components and unreferenced vertices are all accepted.
    ///
    /// Errors: [`crate::Error::PositionsLength`], [`crate::Error::TrianglesLength`],
    /// [`crate::Error::NoTriangles`], [`crate::Error::NonFiniteCoordinate`],
    /// [`crate::Error::IndexOutOfRange`], [`crate::Error::TooManyVertices`],
    /// [`crate::Error::TooManyTriangles`], [`crate::Error::OutOfMemory`] (checked before any
    /// work: a build needs about 60 bytes per triangle at its peak).
    ///
    /// Cost: `O(n log n)` in the number of triangles.
    pub fn new(positions: &[f64], triangles: &[u32], options: &BuildOptions) -> Result<Mesh> {
        let extent = scan_positions(positions)?;
        let vertex_count = positions.len() / 3;
        check_triangles(triangles, vertex_count)?;
        ensure_memory(vertex_count, triangles.len() / 3)?;
        let points = to_points(positions);
        let tris: Vec<[u32; 3]> = triangles
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let rings = build_rings(vertex_count, &tris, &points, options.leftovers);
        let centres: Vec<Point> = rings.centre.iter().map(|&v| points[v as usize]).collect();
        let (mut nodes, order) = split_top_down(&centres, options.tree);
        let layout = RingLayout::new(&rings, &order, &tris, vertex_count);
        let ring_corners = layout.tris.iter().map(|&t| tris[t as usize]).collect();
        assign_centres(&mut nodes, &layout, &points);

        let levels = nodes
            .iter()
            .map(|n| n.depth as usize + 1)
            .max()
            .unwrap_or(1);
        let mut mesh = Mesh {
            positions: points,
            triangles: tris,
            options: *options,
            ring_centre: layout.centre,
            ring_tri_start: layout.tri_start,
            ring_corners,
            ring_tris: layout.tris,
            ring_vert_start: layout.vert_start,
            ring_verts: layout.verts,
            nodes,
            max_abs: extent.max_abs,
            safe: extent.safe,
            last_refit: RefitStats::default(),
            scratch: Vec::with_capacity(8 * levels + 8),
        };
        mesh.last_refit = mesh.update_spheres();
        Ok(mesh)
    }
}

/// Fails with [`Error::OutOfMemory`] unless the build's working memory can be allocated.
///
/// A build allocates many arrays, and Rust aborts the process when an allocation fails; asking
/// once for about twice the measured peak (55-75 bytes per triangle on 1.3M-triangle meshes) and
/// giving it back turns "not enough memory" into an error. Under overcommit this costs one
/// mapping, no page is touched.
fn ensure_memory(vertex_count: usize, triangle_count: usize) -> Result<()> {
    let bytes = vertex_count
        .saturating_mul(64)
        .saturating_add(triangle_count.saturating_mul(128));
    let mut probe: Vec<u8> = Vec::new();
    probe
        .try_reserve_exact(bytes)
        .map_err(|_| Error::OutOfMemory { bytes })
}

/// Splits the rings top-down by their centres. Returns the nodes (breadth-first: children
/// contiguous and after their parent) with ring ranges into the returned order of rings.
fn split_top_down(centres: &[Point], kind: TreeKind) -> (Vec<Node>, Vec<u32>) {
    let count = centres.len() as u32;
    let mut order: Vec<u32> = (0..count).collect();
    let mut nodes = vec![Node {
        ring_start: 0,
        ring_end: count,
        ..Node::default()
    }];
    let mut bounds = Vec::with_capacity(9);
    let mut scratch = Vec::new();
    let mut i = 0;
    while i < nodes.len() {
        let (s, e) = (nodes[i].ring_start as usize, nodes[i].ring_end as usize);
        if e - s > 1 {
            bounds.clear();
            let part = &mut order[s..e];
            match kind {
                TreeKind::Binary => split_binary(part, centres, &mut bounds),
                TreeKind::Octree => split_octree(part, centres, &mut bounds, &mut scratch),
            }
            debug_assert!(bounds.len() >= 3 && bounds.windows(2).all(|w| w[0] < w[1]));
            let first = nodes.len() as u32;
            let depth = nodes[i].depth + 1;
            for w in bounds.windows(2) {
                nodes.push(Node {
                    ring_start: (s + w[0]) as u32,
                    ring_end: (s + w[1]) as u32,
                    depth,
                    ..Node::default()
                });
            }
            nodes[i].first_child = first;
            nodes[i].child_count = (bounds.len() - 1) as u32;
        } else {
            nodes[i].first_child = nodes[i].ring_start;
        }
        i += 1;
    }
    (nodes, order)
}

fn bounding_box(part: &[u32], centres: &[Point]) -> (Point, Point) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &r in part {
        let p = &centres[r as usize];
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

/// Moves the entries with `pred` true to the front; returns how many there are.
fn partition(part: &mut [u32], pred: impl Fn(u32) -> bool) -> usize {
    let mut k = 0;
    for i in 0..part.len() {
        if pred(part[i]) {
            part.swap(i, k);
            k += 1;
        }
    }
    k
}

/// Splits at the median along `axis`; returns the split index (`len / 2`, both sides non-empty
/// for `len >= 2`).
fn median_split(part: &mut [u32], centres: &[Point], axis: usize) -> usize {
    let mid = part.len() / 2;
    if mid > 0 {
        part.select_nth_unstable_by(mid, |&a, &b| {
            centres[a as usize][axis].total_cmp(&centres[b as usize][axis])
        });
    }
    mid
}

fn longest_axis(lo: &Point, hi: &Point) -> usize {
    let extent = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    (0..3)
        .max_by(|&a, &b| extent[a].total_cmp(&extent[b]).then(b.cmp(&a)))
        .unwrap_or(0)
}

fn split_binary(part: &mut [u32], centres: &[Point], bounds: &mut Vec<usize>) {
    let len = part.len();
    let (lo, hi) = bounding_box(part, centres);
    let axis = longest_axis(&lo, &hi);
    // Halves added separately so that huge coordinates cannot overflow.
    let m = 0.5 * lo[axis] + 0.5 * hi[axis];
    let k = partition(part, |r| centres[r as usize][axis] < m);
    let k = if k.min(len - k) * IMBALANCE < len {
        median_split(part, centres, axis)
    } else {
        k
    };
    bounds.extend([0, k, len]);
}

fn split_octree(
    part: &mut [u32],
    centres: &[Point],
    bounds: &mut Vec<usize>,
    scratch: &mut Vec<u32>,
) {
    let len = part.len();
    let (lo, hi) = bounding_box(part, centres);
    let m = [0, 1, 2].map(|a| 0.5 * lo[a] + 0.5 * hi[a]);
    let octant = |r: u32| {
        let p = &centres[r as usize];
        (0..3).fold(0usize, |code, a| code | (usize::from(p[a] >= m[a]) << a))
    };
    let mut counts = [0usize; 8];
    for &r in part.iter() {
        counts[octant(r)] += 1;
    }
    let occupied = counts.iter().filter(|&&c| c > 0).count();
    let largest = counts.iter().copied().max().unwrap_or(0);
    if occupied < 2 || largest * IMBALANCE > len * (IMBALANCE - 1) {
        median_octree(part, centres, bounds);
        return;
    }
    // Counting sort by octant.
    let mut start = [0usize; 9];
    for o in 0..8 {
        start[o + 1] = start[o] + counts[o];
    }
    scratch.clear();
    scratch.resize(len, 0);
    let mut cursor = start;
    for &r in part.iter() {
        let o = octant(r);
        scratch[cursor[o]] = r;
        cursor[o] += 1;
    }
    part.copy_from_slice(scratch);
    bounds.push(0);
    for &b in &start[1..] {
        if b > *bounds.last().unwrap_or(&0) {
            bounds.push(b);
        }
    }
}

/// Eight parts by successive medians on x, then y, then z.
fn median_octree(part: &mut [u32], centres: &[Point], bounds: &mut Vec<usize>) {
    let len = part.len();
    let h = median_split(part, centres, 0);
    let (left, right) = part.split_at_mut(h);
    let q1 = median_split(left, centres, 1);
    let q3 = h + median_split(right, centres, 1);
    let mut cuts = [0, 0, q1, 0, h, 0, q3, 0, len];
    for k in 0..4 {
        let (s, e) = (cuts[2 * k], cuts[2 * k + 2]);
        cuts[2 * k + 1] = s + median_split(&mut part[s..e], centres, 2);
    }
    bounds.push(0);
    for &c in &cuts[1..] {
        if c > *bounds.last().unwrap_or(&0) {
            bounds.push(c);
        }
    }
}

/// Rings renumbered in leaf order, with their triangles and distinct vertices as CSR arrays.
struct RingLayout {
    centre: Vec<u32>,
    tri_start: Vec<u32>,
    tris: Vec<u32>,
    vert_start: Vec<u32>,
    verts: Vec<u32>,
}

impl RingLayout {
    fn new(
        rings: &Rings,
        order: &[u32],
        triangles: &[[u32; 3]],
        vertex_count: usize,
    ) -> RingLayout {
        let mut centre = Vec::with_capacity(order.len());
        let mut tri_start = Vec::with_capacity(order.len() + 1);
        let mut tris = Vec::with_capacity(rings.tris.len());
        let mut vert_start = Vec::with_capacity(order.len() + 1);
        let mut verts = Vec::new();
        let mut seen = vec![u32::MAX; vertex_count];
        tri_start.push(0);
        vert_start.push(0);
        for (new, &old) in order.iter().enumerate() {
            let c = rings.centre[old as usize];
            centre.push(c);
            seen[c as usize] = new as u32;
            for &t in rings.triangles(old as usize) {
                tris.push(t);
                for v in distinct_corners(&triangles[t as usize]) {
                    if seen[v as usize] != new as u32 {
                        seen[v as usize] = new as u32;
                        verts.push(v);
                    }
                }
            }
            tri_start.push(tris.len() as u32);
            vert_start.push(verts.len() as u32);
        }
        RingLayout {
            centre,
            tri_start,
            tris,
            vert_start,
            verts,
        }
    }

    fn vertices(&self, r: usize) -> impl Iterator<Item = u32> + '_ {
        std::iter::once(self.centre[r]).chain(
            self.verts[self.vert_start[r] as usize..self.vert_start[r + 1] as usize]
                .iter()
                .copied(),
        )
    }
}

/// Leaves are centred on their ring's centre; an inner node on the vertex below it nearest to
/// the mean of the (distinct) vertices below it.
fn assign_centres(nodes: &mut [Node], layout: &RingLayout, points: &[Point]) {
    let mut stamp = vec![u32::MAX; points.len()];
    let mut below = Vec::new();
    for (i, node) in nodes.iter_mut().enumerate() {
        if node.is_leaf() {
            node.centre_vertex = layout.centre[node.ring_start as usize];
            continue;
        }
        below.clear();
        for r in node.ring_start..node.ring_end {
            for v in layout.vertices(r as usize) {
                if stamp[v as usize] != i as u32 {
                    stamp[v as usize] = i as u32;
                    below.push(v);
                }
            }
        }
        // Each term divided first so that huge coordinates cannot overflow the sum.
        let w = 1.0 / below.len() as f64;
        let mut mean = [0.0f64; 3];
        for &v in &below {
            let p = &points[v as usize];
            for a in 0..3 {
                mean[a] += p[a] * w;
            }
        }
        node.centre_vertex = below
            .iter()
            .copied()
            .min_by(|&u, &v| {
                distance_squared(&points[u as usize], &mean)
                    .total_cmp(&distance_squared(&points[v as usize], &mean))
                    .then(u.cmp(&v))
            })
            .expect("an inner node has vertices below it");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of triangles `(i, i + 1, i + 2)` over the given points.
    fn strip(points: &[Point]) -> (Vec<f64>, Vec<u32>) {
        let tris = (0..points.len() as u32 - 2)
            .flat_map(|i| [i, i + 1, i + 2])
            .collect();
        (points.as_flattened().to_vec(), tris)
    }

    #[test]
    fn wildly_uneven_spacing_keeps_the_tree_shallow() {
        // Midpoint splits would peel one ring per level off a geometric sequence.
        let points: Vec<Point> = (0..3000)
            .map(|i| [2f64.powf(-(i as f64) / 8.0), (i % 2) as f64 * 1e-3, 0.0])
            .collect();
        let (p, t) = strip(&points);
        for options in BuildOptions::all() {
            let mesh = Mesh::new(&p, &t, &options).unwrap();
            mesh.validate().unwrap();
            let s = mesh.tree_stats();
            let log2 = (s.rings as f64).log2();
            assert!(
                (s.levels as f64) < 12.0 * log2,
                "{options:?}: {} levels for {} rings",
                s.levels,
                s.rings
            );
        }
    }

    #[test]
    fn coincident_vertices_and_single_triangles() {
        let points = vec![[0.25, -1.0, 3.0]; 600];
        let (p, t) = strip(&points);
        for options in BuildOptions::all() {
            let mesh = Mesh::new(&p, &t, &options).unwrap();
            mesh.validate().unwrap();
            assert!(mesh.tree_stats().levels < 40);
            let one = Mesh::new(
                &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
                &[0, 1, 2],
                &options,
            )
            .unwrap();
            one.validate().unwrap();
            assert_eq!((one.node_count(), one.ring_count()), (1, 1));
            assert_eq!(one.node_triangles(0), &[0]);
        }
    }

    #[test]
    fn huge_and_tiny_coordinates_build_valid_trees() {
        for scale in [1e-300, 1e-160, 1e160, 1e300, f64::MAX / 4.0] {
            let points: Vec<Point> = (0..200)
                .map(|i| {
                    [
                        (i as f64).sin() * scale,
                        (i as f64 * 0.7).cos() * scale,
                        -(i as f64 / 200.0) * scale,
                    ]
                })
                .collect();
            let (p, t) = strip(&points);
            for options in BuildOptions::all() {
                let mut mesh = Mesh::new(&p, &t, &options).unwrap();
                mesh.validate().unwrap();
                let moved: Vec<f64> = p.iter().map(|x| -x).collect();
                mesh.refit(&moved).unwrap();
                mesh.validate().unwrap();
            }
        }
    }
}
