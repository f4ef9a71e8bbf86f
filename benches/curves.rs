//! Intersection curves against the pair query they start from, per frame of two deforming CGAL
//! demo meshes (an elephant through a mannequin) and of an elephant folded through itself:
//! refit + `collide` against refit + `intersection_curves` (and the self queries), one thread
//! and every core. What the curves add is one exact intersection per intersecting pair and a
//! sort of the segments' ends.
//!
//! `cargo bench --bench curves` (about 2 minutes; needs Debian's libcgal-demo for the meshes).

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, criterion_group, criterion_main};
use dvh::fixtures::{Morph, cgal_data_available, cgal_mesh};
use dvh::{
    BuildOptions, Curves, Mesh, Pairs, QueryOptions, collide, intersection_curves, self_collide,
    self_intersection_curves,
};
use std::hint::black_box;

const FRAMES: usize = 8;

/// A CGAL demo mesh scaled to unit size, centred at `at`, with `FRAMES` deformed frames.
fn deforming(name: &str, at: [f64; 3], seed: u64) -> (Mesh, Vec<Vec<f64>>) {
    let mut m = cgal_mesh(name).expect("CGAL demo mesh");
    m.normalize(1.0);
    m.translate(at);
    let morph = Morph::random(&m, 6, 0.04, seed);
    let frames = (0..FRAMES)
        .map(|f| morph.at(&m.positions, f as f64 / FRAMES as f64))
        .collect();
    let mesh = Mesh::new(&m.positions, &m.triangles, &BuildOptions::default()).unwrap();
    (mesh, frames)
}

/// The elephant folded about a vertical plane through its middle: the far half turned back
/// through the near half.
fn folded(name: &str) -> (Mesh, Vec<Vec<f64>>) {
    let mut m = cgal_mesh(name).expect("CGAL demo mesh");
    m.normalize(1.0);
    let b = m.bounds();
    let mid = 0.5 * (b.lo[0] + b.hi[0]);
    for p in m.positions.chunks_exact_mut(3) {
        if p[0] > mid {
            // Turned by 150 degrees about the vertical axis through the middle.
            let (c, s) = (150f64.to_radians().cos(), 150f64.to_radians().sin());
            let (dx, dz) = (p[0] - mid, p[2]);
            p[0] = mid + c * dx - s * dz;
            p[2] = s * dx + c * dz;
        }
    }
    let morph = Morph::random(&m, 6, 0.02, 9);
    let frames = (0..FRAMES)
        .map(|f| morph.at(&m.positions, f as f64 / FRAMES as f64))
        .collect();
    let mesh = Mesh::new(&m.positions, &m.triangles, &BuildOptions::default()).unwrap();
    (mesh, frames)
}

/// Times `step` over the frames in turn: it refits to frame `f`, queries and returns the
/// result's size.
fn over_frames(
    g: &mut BenchmarkGroup<'_, WallTime>,
    label: String,
    mut step: impl FnMut(usize) -> usize,
) {
    let mut frame = 0;
    g.bench_function(label, |bench| {
        bench.iter(|| {
            frame = (frame + 1) % FRAMES;
            black_box(step(frame))
        })
    });
}

fn two_meshes(c: &mut Criterion) {
    let (mut a, fa) = deforming("elephant", [0.0; 3], 1);
    let (mut b, fb) = deforming("mannequin-devil", [0.25, 0.05, 0.0], 2);
    let mut first = Curves::new();
    intersection_curves(&a, None, &b, None, &QueryOptions::default(), &mut first).unwrap();
    let mut g = c.benchmark_group(format!(
        "curves/elephant {} x mannequin {}, {} segments",
        a.triangle_count(),
        b.triangle_count(),
        first.len()
    ));
    g.sample_size(20);
    for threads in [1, 0] {
        let options = QueryOptions::default().with_threads(threads);
        let mut pairs = Pairs::new();
        over_frames(&mut g, format!("refit + collide, threads {threads}"), |f| {
            a.refit(&fa[f]).unwrap();
            b.refit(&fb[f]).unwrap();
            collide(&a, None, &b, None, &options, &mut pairs).unwrap();
            pairs.len()
        });
        let mut curves = Curves::new();
        over_frames(&mut g, format!("refit + curves, threads {threads}"), |f| {
            a.refit(&fa[f]).unwrap();
            b.refit(&fb[f]).unwrap();
            intersection_curves(&a, None, &b, None, &options, &mut curves).unwrap();
            curves.len()
        });
    }
    g.finish();
}

fn self_curves(c: &mut Criterion) {
    let (mut m, frames) = folded("elephant");
    let mut first = Curves::new();
    self_intersection_curves(&m, &QueryOptions::default(), &mut first).unwrap();
    let mut g = c.benchmark_group(format!(
        "curves/folded elephant {}, {} segments",
        m.triangle_count(),
        first.len()
    ));
    g.sample_size(20);
    for threads in [1, 0] {
        let options = QueryOptions::default().with_threads(threads);
        let mut pairs = Pairs::new();
        over_frames(
            &mut g,
            format!("refit + self_collide, threads {threads}"),
            |f| {
                m.refit(&frames[f]).unwrap();
                self_collide(&m, &options, &mut pairs).unwrap();
                pairs.len()
            },
        );
        let mut curves = Curves::new();
        over_frames(
            &mut g,
            format!("refit + self curves, threads {threads}"),
            |f| {
                m.refit(&frames[f]).unwrap();
                self_intersection_curves(&m, &options, &mut curves).unwrap();
                curves.len()
            },
        );
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    if !cgal_data_available() {
        eprintln!("curves benchmark skipped: Debian's libcgal-demo is not installed");
        return;
    }
    two_meshes(c);
    self_curves(c);
}

criterion_group!(group, benches);
criterion_main!(group);
