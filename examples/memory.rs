//! Memory of a built mesh and of a query's result buffer, in bytes per triangle, for each volume
//! kind: Debian's CGAL demo meshes at the sizes of the benchmark scenes, each queried against an
//! exact copy of itself (dense contact: every triangle meets its copy and its neighbours), on
//! one thread and on every core.
//!
//! `cargo run --release --example memory [mesh:triangles ...]` (default: the scenes' meshes).

use dvh::fixtures::cgal_mesh;
use dvh::{BuildOptions, Mesh, Pairs, QueryOptions, VolumeKind, collide};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut wanted: Vec<String> = std::env::args().skip(1).collect();
    if wanted.is_empty() {
        wanted = ["elephant:5000", "bunny00:70000", "refined_elephant:355712"]
            .map(String::from)
            .to_vec();
    }
    println!(
        "{:<24} {:>9} {:<5} {:>10} {:>12} {:>12} {:>12} {:>12}",
        "mesh",
        "triangles",
        "kind",
        "mesh B/tri",
        "pairs/tri",
        "result B/tri",
        "1 thr B/tri",
        "all B/tri"
    );
    for spec in &wanted {
        let (name, size) = spec.split_once(':').unwrap_or((spec, "0"));
        let mut m = cgal_mesh(name)?;
        let size: usize = size.parse()?;
        if size > 0 {
            m = m.subdivided_to(size);
        }
        for volume in [VolumeKind::Aabb, VolumeKind::Dvh, VolumeKind::Sbv] {
            let options = BuildOptions::default().with_volume(volume);
            let mesh = Mesh::new(&m.positions, &m.triangles, &options)?;
            let tris = mesh.triangle_count() as f64;
            // The buffer of a query on one thread, then of one on every core.
            let mut pairs = Pairs::new();
            let one = QueryOptions::default().with_threads(1);
            collide(&mesh, None, &mesh, None, &one, &mut pairs)?;
            let single = pairs.memory_bytes();
            let result = pairs.len() * std::mem::size_of::<dvh::Pair>();
            let mut all = Pairs::new();
            collide(&mesh, None, &mesh, None, &QueryOptions::default(), &mut all)?;
            println!(
                "{:<24} {:>9} {:<5} {:>10.1} {:>12.1} {:>12.1} {:>12.1} {:>12.1}",
                name,
                mesh.triangle_count(),
                format!("{volume:?}"),
                mesh.memory_bytes() as f64 / tris,
                pairs.len() as f64 / tris,
                result as f64 / tris,
                single as f64 / tris,
                all.memory_bytes() as f64 / tris,
            );
        }
    }
    Ok(())
}
