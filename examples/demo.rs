//! The main demonstration: two meshes deform and move through each other; every frame both are
//! refit and queried, and the pairs and counters are printed.
//!
//! `cargo run --release --example demo [-- --frames N] [--a NAME] [--b NAME]`
//!
//! Uses Debian's CGAL demo meshes (armadillo and elephant) when `libcgal-demo` is installed, and
//! built-in meshes (a sphere and a torus) otherwise. Mesh `a` is deformed in place; mesh `b` is
//! deformed and carried through `a` by a rigid pose, which costs no refit.

use dvh::fixtures::{MeshData, Morph, cgal_mesh, icosphere, torus};
use dvh::{BuildOptions, Mesh, Pairs, Pose, QueryMode, QueryOptions, collide};
use nalgebra::{Isometry3, Vector3};
use std::time::Instant;

fn arg(name: &str) -> Option<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

fn load(name: &str, fallback: impl FnOnce() -> MeshData) -> (String, MeshData) {
    match cgal_mesh(name) {
        Ok(m) => (name.to_string(), m),
        Err(e) => {
            eprintln!("note: {e}; using a built-in mesh");
            ("built-in".to_string(), fallback())
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let frames: usize = arg("--frames")
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(24);
    let (name_a, mut rest_a) = load(&arg("--a").unwrap_or_else(|| "armadillo".into()), || {
        icosphere(5)
    });
    let (name_b, mut rest_b) = load(&arg("--b").unwrap_or_else(|| "elephant".into()), || {
        torus(0.5, 0.2, 120, 60)
    });
    rest_a.normalize(1.0);
    rest_b.normalize(0.6);
    let morph_a = Morph::random(&rest_a, 4, 0.06, 7);
    let morph_b = Morph::random(&rest_b, 4, 0.06, 8);

    let options = BuildOptions::default();
    let t = Instant::now();
    let mut a = Mesh::new(&rest_a.positions, &rest_a.triangles, &options)?;
    let mut b = Mesh::new(&rest_b.positions, &rest_b.triangles, &options)?;
    let build_ms = t.elapsed().as_secs_f64() * 1e3;
    for (name, mesh) in [(&name_a, &a), (&name_b, &b)] {
        let s = mesh.tree_stats();
        println!(
            "{name}: {} triangles, {} rings ({:.3} per triangle), {} levels, {} inner nodes",
            s.triangles,
            s.rings,
            s.rings as f64 / s.triangles as f64,
            s.levels,
            s.inner_nodes
        );
    }
    println!("built both in {build_ms:.1} ms ({options:?})\n");
    println!(
        "{:>5} {:>7} {:>6} {:>7} {:>9} {:>9} {:>7} {:>9} {:>9}",
        "frame", "pairs", "first", "leaves", "NV", "NP", "NU", "refit ms", "query ms"
    );

    let mut pairs = Pairs::new();
    let mut coarse = Pairs::new();
    let (mut pa, mut pb) = (rest_a.positions.clone(), rest_b.positions.clone());
    let mut total_pairs = 0;
    for frame in 0..frames {
        let phase = frame as f64 / frames.max(1) as f64;
        morph_a.apply(&rest_a.positions, phase, &mut pa);
        morph_b.apply(&rest_b.positions, phase, &mut pb);
        // b sweeps through a along x while turning about its own vertical axis.
        let x = -1.0 + 2.0 * phase;
        let pose = Pose::from_isometry(&Isometry3::new(
            Vector3::new(x, 0.1, 0.0),
            Vector3::new(0.0, std::f64::consts::TAU * phase, 0.0),
        ))?;

        let t = Instant::now();
        a.refit(&pa)?;
        b.refit(&pb)?;
        let refit_ms = t.elapsed().as_secs_f64() * 1e3;
        let t = Instant::now();
        let stats = collide(
            &a,
            None,
            &b,
            Some(&pose),
            &QueryOptions::default(),
            &mut pairs,
        )?;
        let query_ms = t.elapsed().as_secs_f64() * 1e3;

        collide(
            &a,
            None,
            &b,
            Some(&pose),
            &QueryOptions::with_mode(QueryMode::FirstHit),
            &mut coarse,
        )?;
        let first = !coarse.is_empty();
        collide(
            &a,
            None,
            &b,
            Some(&pose),
            &QueryOptions::with_mode(QueryMode::Leaves),
            &mut coarse,
        )?;
        println!(
            "{frame:>5} {:>7} {:>6} {:>7} {:>9} {:>9} {:>7} {refit_ms:>9.3} {query_ms:>9.3}",
            pairs.len(),
            if first { "hit" } else { "-" },
            coarse.len(),
            stats.bv_tests,
            stats.triangle_tests,
            stats.nodes_refit
        );
        total_pairs += pairs.len();
    }
    println!("\n{total_pairs} intersecting triangle pairs over {frames} frames");
    Ok(())
}
