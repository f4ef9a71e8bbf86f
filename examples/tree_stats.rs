//! Rings per triangle, levels and inner nodes of the hierarchy for Debian's CGAL demo meshes,
//! with every build option: the figures of the paper's Tables 1 and 2.
//!
//! `cargo run --release --example tree_stats [mesh ...]` (default: armadillo bunny00 dino elephant).

use dvh::fixtures::cgal_mesh;
use dvh::{BuildOptions, LeftoverPolicy, Mesh, TreeKind};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut names: Vec<String> = std::env::args().skip(1).collect();
    if names.is_empty() {
        names = ["armadillo", "bunny00", "dino", "elephant"]
            .map(String::from)
            .to_vec();
    }
    println!(
        "{:<12} {:>9} {:<13} {:>8} {:>8} {:>8} {:>7} {:>7}",
        "mesh", "triangles", "leftovers", "rings", "ring/tri", "max tri", "levels", "inner"
    );
    for name in &names {
        let m = cgal_mesh(name)?;
        for leftovers in [LeftoverPolicy::JoinAdjacent, LeftoverPolicy::ExtraRings] {
            for tree in [TreeKind::Binary, TreeKind::Octree] {
                let options = BuildOptions::default()
                    .with_tree(tree)
                    .with_leftovers(leftovers);
                let mesh = Mesh::new(&m.positions, &m.triangles, &options)?;
                let s = mesh.tree_stats();
                println!(
                    "{:<12} {:>9} {:<13} {:>8} {:>8.3} {:>8} {:>7} {:>7}  {:?}",
                    name,
                    s.triangles,
                    format!("{leftovers:?}"),
                    s.rings,
                    s.rings as f64 / s.triangles as f64,
                    s.max_ring_triangles,
                    s.levels,
                    s.inner_nodes,
                    tree
                );
            }
        }
    }
    Ok(())
}
