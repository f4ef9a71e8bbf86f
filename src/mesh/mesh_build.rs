//! Building a [`Mesh`]: input checks, 1-rings, the tree's shape, the volumes, first fit.

use super::input::{check_triangles, scan_positions, to_points};
use super::mesh::{Mesh, Topology};
use super::options::BuildOptions;
use super::rings::build_rings;
use crate::error::{Error, Result};
use crate::geometry::predicates::Point;
use crate::threads;
use crate::tree::{RingTable, Tree};
use crate::volume::REFIT_PARALLEL_MIN_RINGS;
use crate::volume::{RefitStats, VolumeKind, Volumes, assign_centres};
use std::sync::Arc;

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
        let (tree, order) = Tree::build(&centres, options.tree);
        let rings = RingTable::new(
            (&rings.centre, &rings.triangles),
            &order,
            &tris,
            vertex_count,
        );
        let positions = points;
        let centre_vertex = match options.volume {
            VolumeKind::Dvh => assign_centres(&tree, &rings, &positions),
            VolumeKind::Sbv | VolumeKind::Aabb => Vec::new(),
        };
        let volumes = Volumes::new(options.volume, tree.len(), centre_vertex);
        // The wrapped-radius search pushes at most the fan-out per level.
        let depth = options.tree.max_children() * (tree.levels() + 1);
        let threads = if rings.len() >= REFIT_PARALLEL_MIN_RINGS {
            threads::resolve(options.refit_threads)
        } else {
            1
        };
        let scratch = (0..threads).map(|_| Vec::with_capacity(depth)).collect();
        let mut mesh = Mesh {
            spare: positions.clone(),
            positions,
            topology: Arc::new(Topology {
                triangles: tris,
                rings,
                tree,
                blocks: Default::default(),
                patches: Default::default(),
                surface: Default::default(),
                features: Default::default(),
                least_triangles: Default::default(),
            }),
            options: *options,
            volumes,
            max_abs: extent.max_abs,
            in_fast_range: extent.in_fast_range,
            last_refit: RefitStats::default(),
            state: super::mesh::next_state(),
            patch_cache: Default::default(),
            scratch,
            motion: Default::default(),
        };
        mesh.last_refit = mesh.update_volumes();
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
    fn positions_and_centres_of_unusual_numberings() {
        // A strip whose vertices are numbered backwards, with two vertices no triangle uses.
        let points: Vec<Point> = (0..40).map(|i| [i as f64, (i % 3) as f64, 0.5]).collect();
        let (p, mut t) = strip(&points);
        t.iter_mut().for_each(|v| *v = 39 - *v);
        let mut p = p;
        p.extend_from_slice(&[7.0, 7.0, 7.0, -7.0, 0.0, 1.0]);
        for options in BuildOptions::all() {
            let mut mesh = Mesh::new(&p, &t, &options).unwrap();
            let moved: Vec<f64> = p.iter().enumerate().map(|(i, x)| x + i as f64).collect();
            mesh.refit(&moved).unwrap();
            mesh.validate().unwrap();
            assert_eq!(mesh.positions().as_flattened(), &moved[..]);
            // Leaves in ring order: ordered by where their triangles sit in the root's.
            let mut leaves: Vec<u32> = (0..mesh.node_count() as u32)
                .filter(|&n| mesh.node(n).children.is_empty())
                .collect();
            leaves.sort_by_key(|&n| mesh.node_triangles(n).as_ptr() as usize);
            for (&leaf, &c) in leaves.iter().zip(mesh.ring_centres()) {
                let tris = mesh.node_triangles(leaf);
                assert!(tris.iter().any(|&x| t[3 * x as usize..][..3].contains(&c)));
                if let Some(cv) = mesh.node(leaf).centre_vertex {
                    assert_eq!(cv, c);
                }
            }
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
