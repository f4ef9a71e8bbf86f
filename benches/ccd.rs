//! The cost of one exact continuous test, by how far the filters take it: primitives whose
//! swept boxes are apart (the box test decides), that approach without ever being coplanar
//! (the Bernstein coefficients decide), and that meet at a time that is not a double (the
//! interval path decides, and the exact cubic rounds the time).
//!
//! `cargo bench --bench ccd`.

use criterion::{Criterion, criterion_group, criterion_main};
use dvh::exact::{edge_edge_impact, vertex_face_impact};
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

criterion_group!(benches, bench);
criterion_main!(benches);
