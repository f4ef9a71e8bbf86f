//! Whole-frame figures for two deforming meshes colliding: refit and query times (medians over
//! the frames) and the counters, for every build option. A quick look, not a benchmark: the
//! criterion benchmarks and the cross-check are the measured claims.
//!
//! `cargo run --release --example frame_timing [mesh] [frames] [offset] [amplitude]` (defaults:
//! armadillo, 60 frames, the second copy shifted by 0.45 of the mesh size, deformation amplitude
//! 0.08 of the mesh size).
//! Uses Debian's CGAL demo meshes when installed, an icosphere of similar size otherwise.

use dvh::fixtures::{MeshData, Morph, cgal_mesh, icosphere};
use dvh::{BuildOptions, Mesh, Pairs, QueryMode, QueryOptions, collide};
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let name = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "armadillo".into());
    let frames: usize = std::env::args()
        .nth(2)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(60);
    let mut rest = cgal_mesh(&name).unwrap_or_else(|e| {
        eprintln!("{e}; using an icosphere instead");
        icosphere(6).subdivided_to(50_000)
    });
    rest.normalize(1.0);
    // Two copies, the second shifted so that they interpenetrate over part of their surface.
    let mut rest_b: MeshData = rest.clone();
    let offset: f64 = std::env::args()
        .nth(3)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(0.45);
    rest_b.translate([offset, 0.1, 0.0]);
    let amplitude: f64 = std::env::args()
        .nth(4)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(0.08);
    let morph_a = Morph::random(&rest, 4, amplitude, 1);
    let morph_b = Morph::random(&rest_b, 4, amplitude, 2);
    let positions: Vec<(Vec<f64>, Vec<f64>)> = (0..frames)
        .map(|f| {
            let t = f as f64 / frames as f64;
            (
                morph_a.at(&rest.positions, t),
                morph_b.at(&rest_b.positions, t),
            )
        })
        .collect();
    println!(
        "{name}: {} triangles each, {frames} frames; medians per frame (ms)",
        rest.triangle_count()
    );
    println!(
        "{:<8} {:<8} {:<13} {:>8} {:>9} {:>9} {:>9} {:>10} {:>9} {:>7}",
        "tree",
        "radius",
        "leftovers",
        "build",
        "refit×2",
        "exact",
        "leaves",
        "bv tests",
        "tri tests",
        "pairs"
    );
    for options in BuildOptions::all() {
        let (tree, radius, leftovers) = (options.tree, options.radius, options.leftovers);
        let t0 = Instant::now();
        let mut a = Mesh::new(&rest.positions, &rest.triangles, &options)?;
        let mut b = Mesh::new(&rest_b.positions, &rest_b.triangles, &options)?;
        let build = t0.elapsed().as_secs_f64() * 500.0;
        let mut pairs = Pairs::new();
        let (mut refit, mut exact, mut leaves) = (Vec::new(), Vec::new(), Vec::new());
        let (mut bv, mut tri, mut found) = (Vec::new(), Vec::new(), Vec::new());
        for (pa, pb) in &positions {
            let t = Instant::now();
            a.refit(pa)?;
            b.refit(pb)?;
            refit.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            let s = collide(&a, None, &b, None, &QueryOptions::default(), &mut pairs)?;
            exact.push(t.elapsed().as_secs_f64() * 1e3);
            bv.push(s.bv_tests as f64);
            tri.push(s.triangle_tests as f64);
            found.push(s.pairs as f64);
            let t = Instant::now();
            collide(
                &a,
                None,
                &b,
                None,
                &QueryOptions::with_mode(QueryMode::Leaves),
                &mut pairs,
            )?;
            leaves.push(t.elapsed().as_secs_f64() * 1e3);
        }
        println!(
            "{:<8} {:<8} {:<13} {:>8.1} {:>9.3} {:>9.3} {:>9.3} {:>10.0} {:>9.0} {:>7.0}",
            format!("{tree:?}"),
            format!("{radius:?}"),
            format!("{leftovers:?}"),
            build,
            median(refit),
            median(exact),
            median(leaves),
            median(bv),
            median(tri),
            median(found)
        );
    }
    Ok(())
}
