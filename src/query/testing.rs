//! What the query tests share.

use super::pairs::Pair;
use crate::fixtures::{MeshData, Rng};
use crate::mesh::BuildOptions;
use crate::mesh::Mesh;
use crate::volume::VolumeKind;
use std::collections::HashSet;

/// Does every triangle pair of `expected` lie in some node pair of `nodes` (of `a` and `b`; of
/// one mesh, in either order)? The coarse modes' promise.
pub(crate) fn nodes_cover(a: &Mesh, b: &Mesh, one_mesh: bool, nodes: &[Pair], expected: &[Pair]) {
    let mut covered = HashSet::new();
    for p in nodes {
        for &x in a.node_triangles(p.a) {
            for &y in b.node_triangles(p.b) {
                covered.insert((x, y));
                if one_mesh {
                    covered.insert((y, x));
                }
            }
        }
    }
    for p in expected {
        assert!(covered.contains(&(p.a, p.b)), "{p:?} is in no node pair");
    }
}

/// `positions` (three coordinates a vertex) with every vertex moved by `f`.
pub(crate) fn map_vertices(positions: &[f64], f: impl Fn(&[f64]) -> [f64; 3]) -> Vec<f64> {
    positions.chunks_exact(3).flat_map(f).collect()
}

/// The positions of a flat sheet in the plane z = 0 (a unit grid) with its far half (x > 0.5)
/// turned back over the near half: `far(x, y)` is where a vertex of that half goes.
pub(crate) fn folded(positions: &[f64], far: impl Fn(f64, f64) -> [f64; 3]) -> Vec<f64> {
    map_vertices(positions, |p| {
        let (x, y) = (p[0], p[1]);
        if x > 0.5 { far(x, y) } else { [x, y, 0.0] }
    })
}

/// Every volume kind, as the tests run each query with each.
pub(crate) const VOLUMES: [VolumeKind; 3] = [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv];

/// Mesh `m` built with volume kind `volume`.
pub(crate) fn build(m: &MeshData, volume: VolumeKind) -> Mesh {
    Mesh::new(
        &m.positions,
        &m.triangles,
        &BuildOptions::default().with_volume(volume),
    )
    .unwrap()
}

/// `rest` moved by `shift` and jittered by up to `jitter` per coordinate.
pub(crate) fn moved(rest: &[f64], shift: [f64; 3], jitter: f64, rng: &mut Rng) -> Vec<f64> {
    rest.iter()
        .enumerate()
        .map(|(i, x)| x + shift[i % 3] + rng.range(-jitter, jitter))
        .collect()
}
