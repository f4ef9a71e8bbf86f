//! The cost of one exact continuous test, by how far the filters take it: primitives whose
//! swept boxes are apart (the box test decides), that approach without ever being coplanar
//! (the Bernstein coefficients decide), and that meet at a time that is not a double (the
//! interval path decides, and the exact cubic rounds the time).
//!
//! And one step of moving meshes: a cloth sheet draped onto a sphere (the two meshes, every
//! impact or the earliest only), the sheet folding over itself (self), exact and conservative.
//!
//! `cargo bench --bench ccd` (about 10 minutes).

use criterion::{Criterion, criterion_group, criterion_main};
use dvh::exact::{edge_edge_impact, vertex_face_impact};
use dvh::fixtures::{grid, icosphere};
use dvh::{
    BuildOptions, CcdMode, CcdOptions, Impacts, Mesh, continuous_collide, self_continuous_collide,
};
use std::hint::black_box;

type Prim = [[f64; 3]; 4];

/// Vertex-face cases: the vertex, then the triangle's corners.
fn vertex_face_cases() -> [(&'static str, Prim, Prim); 4] {
    let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    [
        (
            "boxes apart",
            [[3.0, 3.0, 1.0], tri[0], tri[1], tri[2]],
            [[3.0, 3.1, 0.9], tri[0], tri[1], tri[2]],
        ),
        (
            "never coplanar",
            [[0.3, 0.3, 0.2], tri[0], tri[1], tri[2]],
            [[0.31, 0.3, 0.1], tri[0], tri[1], tri[2]],
        ),
        (
            "contact at 2/3",
            [[0.3, 0.3, 0.2], tri[0], tri[1], tri[2]],
            [[0.3, 0.3, -0.1], tri[0], tri[1], tri[2]],
        ),
        (
            "contact, every corner moving",
            [
                [0.2, 0.2, 0.5],
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            [
                [0.2, 0.2, 0.5],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 2.0],
            ],
        ),
    ]
}

/// Edge-edge cases: edge a's ends, then edge b's.
fn edge_edge_cases() -> [(&'static str, Prim, Prim); 4] {
    let (a0, a1) = ([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    [
        (
            "boxes apart",
            [a0, a1, [0.0, 3.0, 1.0], [0.0, 4.0, 1.0]],
            [a0, a1, [0.0, 3.0, -1.0], [0.0, 4.0, -1.0]],
        ),
        (
            "never coplanar",
            [a0, a1, [0.0, -1.0, 1.0], [0.0, 1.0, 1.0]],
            [a0, a1, [0.1, -1.0, 0.5], [0.0, 1.0, 0.5]],
        ),
        (
            "contact at 1/3",
            [a0, a1, [0.0, -1.0, 1.0], [0.0, 1.0, 1.0]],
            [a0, a1, [0.0, -1.0, -2.0], [0.0, 1.0, -2.0]],
        ),
        (
            "contact, both edges moving",
            [a0, a1, [0.3, -1.0, 1.0], [0.0, 1.0, 0.5]],
            [
                [-1.0, 0.0, 0.5],
                [1.0, 0.5, 0.0],
                [0.0, -1.0, -1.0],
                [0.2, 1.0, -0.5],
            ],
        ),
    ]
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("ccd");
    for (name, s, e) in vertex_face_cases() {
        g.bench_function(format!("vertex-face, {name}"), |b| {
            b.iter(|| vertex_face_impact(black_box(&s), black_box(&e)).unwrap())
        });
    }
    for (name, s, e) in edge_edge_cases() {
        g.bench_function(format!("edge-edge, {name}"), |b| {
            b.iter(|| edge_edge_impact(black_box(&s), black_box(&e)).unwrap())
        });
    }
    g.finish();
}

/// A 48 x 48 sheet (4,608 triangles) over [-1, 1]^2 falling from z = 0.53 to z = 0.47 with a
/// ripple, through the top of a sphere of radius 0.5 (1,280 triangles) that rises by 0.01; and
/// a 16 x 16 sheet (512 triangles) folding its right half over its left, from flat, its
/// vertices landing on and beside the left half's (degenerate contacts, decided exactly).
fn scenes() -> ((Mesh, Mesh), Mesh) {
    let sheet = grid(48, 2.0);
    let flat: Vec<f64> = sheet
        .positions
        .chunks_exact(3)
        .flat_map(|p| [p[0] - 1.0, p[1] - 1.0, 0.0])
        .collect();
    let at = |z: f64| -> Vec<f64> {
        flat.chunks_exact(3)
            .flat_map(|p| {
                [
                    p[0],
                    p[1],
                    z + 0.01 * (7.0 * p[0]).sin() * (5.0 * p[1]).cos(),
                ]
            })
            .collect()
    };
    let options = BuildOptions::default();
    let mut cloth = Mesh::new(&flat, &sheet.triangles, &options).unwrap();
    cloth.refit_motion(&at(0.53), &at(0.47)).unwrap();
    let ball = icosphere(3);
    let scaled = |dz: f64| -> Vec<f64> {
        ball.positions
            .chunks_exact(3)
            .flat_map(|p| {
                let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                [0.5 * p[0] / n, 0.5 * p[1] / n, 0.5 * p[2] / n + dz]
            })
            .collect()
    };
    let mut sphere = Mesh::new(&scaled(0.0), &ball.triangles, &options).unwrap();
    sphere.refit_motion(&scaled(0.0), &scaled(0.01)).unwrap();
    let small = grid(16, 2.0);
    let small_flat: Vec<f64> = small
        .positions
        .chunks_exact(3)
        .flat_map(|p| [p[0] - 1.0, p[1] - 1.0, 0.0])
        .collect();
    let folded: Vec<f64> = small_flat
        .chunks_exact(3)
        .flat_map(|p| {
            if p[0] > 0.0 {
                [-p[0] + 0.02 * p[1], p[1], 0.03 - 0.04 * p[0]]
            } else {
                [p[0], p[1], 0.0]
            }
        })
        .collect();
    let mut fold = Mesh::new(&small_flat, &small.triangles, &options).unwrap();
    fold.refit_motion(&small_flat, &folded).unwrap();
    ((cloth, sphere), fold)
}

fn bench_meshes(c: &mut Criterion) {
    let ((cloth, sphere), fold) = scenes();
    let mut g = c.benchmark_group("ccd step");
    g.sample_size(10);
    let mut out = Impacts::new();
    for (name, options) in [
        ("exact", CcdOptions::default()),
        (
            "exact, earliest only",
            CcdOptions::default().with_earliest_only(true),
        ),
        (
            "conservative",
            CcdOptions::default().with_mode(CcdMode::Conservative),
        ),
    ] {
        for threads in [1, 0] {
            let options = options.with_threads(threads);
            let label = if threads == 1 {
                "1 thread"
            } else {
                "all cores"
            };
            continuous_collide(&cloth, &sphere, &options, &mut out).unwrap();
            eprintln!("sheet on sphere, {name}: {} impacts", out.len());
            g.bench_function(format!("sheet on sphere, {name}, {label}"), |b| {
                b.iter(|| continuous_collide(&cloth, &sphere, &options, &mut out).unwrap())
            });
            self_continuous_collide(&fold, &options, &mut out).unwrap();
            eprintln!("sheet folding, {name}: {} impacts", out.len());
            g.bench_function(format!("sheet folding, {name}, {label}"), |b| {
                b.iter(|| self_continuous_collide(&fold, &options, &mut out).unwrap())
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench, bench_meshes);
criterion_main!(benches);
