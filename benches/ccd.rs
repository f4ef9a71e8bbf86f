//! The cost of one exact continuous test, by how far the filters take it: primitives whose
//! swept boxes are apart (the box test decides), that approach without ever being coplanar
//! (the Bernstein coefficients decide), and that meet (exact root isolation decides).
//!
//! `cargo bench --bench ccd`.

use criterion::{Criterion, criterion_group, criterion_main};
use dvh::exact::{edge_edge_impact, vertex_face_impact};
use std::hint::black_box;

type Prim = [[f64; 3]; 4];

fn cases() -> [(&'static str, Prim, Prim); 4] {
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
            "contact",
            [[0.3, 0.3, 0.2], tri[0], tri[1], tri[2]],
            [[0.3, 0.3, -0.1], tri[0], tri[1], tri[2]],
        ),
        (
            "contact, irrational time",
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

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("ccd");
    for (name, s, e) in cases() {
        g.bench_function(format!("vertex-face, {name}"), |b| {
            b.iter(|| vertex_face_impact(black_box(&s), black_box(&e)).unwrap())
        });
        g.bench_function(format!("edge-edge, {name}"), |b| {
            b.iter(|| edge_edge_impact(black_box(&s), black_box(&e)).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
