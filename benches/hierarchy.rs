//! Build, refit and query of every volume kind on every tree kind, on meshes of about 1K, 16K,
//! 100K and 350K triangles; refits with 0%, 10% and 100% of the vertices moved, quoted against
//! a read-once pass over the same vertex array (the floor no refit can go below).
//!
//! `cargo bench --bench hierarchy` runs all of it (about 15 minutes); a filter narrows it, such
//! as `cargo bench --bench hierarchy -- refit/350K`. Meshes are Debian's CGAL demo meshes when
//! `libcgal-demo` is installed (helmet, lion, elephant subdivided twice, refined_elephant), and
//! icospheres of similar sizes otherwise; the group names say which.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use dvh::fixtures::{MeshData, Morph, Rng, cgal_mesh, icosphere};
use dvh::{BuildOptions, Mesh, Pairs, QueryOptions, TreeKind, VolumeKind, collide};
use std::hint::black_box;
use std::time::Duration;

/// A mesh of one size class, normalised to unit size.
struct Subject {
    /// `1K`, `16K`, `100K` or `350K`.
    class: &'static str,
    mesh: MeshData,
}

fn subjects() -> Vec<Subject> {
    let specs: [(&str, &str, usize, u32); 4] = [
        ("1K", "helmet", 1_000, 3),
        ("16K", "lion", 14_000, 5),
        ("100K", "elephant", 84_000, 6),
        ("350K", "refined_elephant", 350_000, 7),
    ];
    specs
        .into_iter()
        .map(|(class, name, triangles, subdivisions)| {
            let mut mesh = cgal_mesh(name)
                .map(|m| m.subdivided_to(triangles))
                .unwrap_or_else(|_| icosphere(subdivisions));
            mesh.normalize(1.0);
            Subject { class, mesh }
        })
        .collect()
}

/// Every volume kind on every tree kind, with the other options at their defaults.
fn kinds() -> Vec<BuildOptions> {
    let mut all = Vec::new();
    for volume in [VolumeKind::Dvh, VolumeKind::Sbv, VolumeKind::Aabb] {
        for tree in [TreeKind::Octree, TreeKind::Binary] {
            all.push(BuildOptions::default().with_volume(volume).with_tree(tree));
        }
    }
    all
}

fn label(o: &BuildOptions) -> String {
    format!("{:?}-{:?}", o.volume, o.tree).to_lowercase()
}

/// `rest` with a share `fraction` of the vertices moved by up to 1% of the mesh's size (the
/// same vertices and offsets for a given seed).
fn moved(rest: &[f64], fraction: f64, seed: u64) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    let mut out = rest.to_vec();
    for p in out.chunks_exact_mut(3) {
        if rng.unit() < fraction {
            for x in p {
                *x += rng.range(-0.01, 0.01);
            }
        }
    }
    out
}

fn build(c: &mut Criterion) {
    for s in subjects() {
        let mut group = c.benchmark_group(format!("build/{}", s.class));
        group.throughput(Throughput::Elements(s.mesh.triangle_count() as u64));
        group.sample_size(10);
        for o in kinds() {
            group.bench_function(BenchmarkId::from_parameter(label(&o)), |b| {
                b.iter(|| Mesh::new(&s.mesh.positions, &s.mesh.triangles, &o).unwrap())
            });
        }
        group.finish();
    }
}

fn refit(c: &mut Criterion) {
    for s in subjects() {
        let mut group = c.benchmark_group(format!("refit/{}", s.class));
        group.throughput(Throughput::Elements(s.mesh.vertex_count() as u64));
        let rest = &s.mesh.positions;
        // The floor: every coordinate read once, folded so that the compiler cannot skip it
        // and vectorises the loop (a floating-point sum would be bound by addition latency).
        // It alternates between two arrays as the refits do, so that it meets the caches in the
        // same state: on the largest meshes the arrays no longer fit, and memory bandwidth is
        // the floor.
        let second = moved(rest, 1.0, 6);
        let mut flip = false;
        group.bench_function("read-once", |b| {
            b.iter(|| {
                flip = !flip;
                black_box(if flip { &second } else { rest })
                    .iter()
                    .fold(0u64, |acc, x| acc ^ x.to_bits())
            })
        });
        for fraction in [0.0, 0.1, 1.0] {
            let other = moved(rest, fraction, 5);
            for o in kinds() {
                let mut mesh = Mesh::new(rest, &s.mesh.triangles, &o).unwrap();
                let id = format!("{}/moved-{}%", label(&o), (fraction * 100.0) as u32);
                // Alternates between the two arrays, so that every refit sees the share moved.
                let mut flip = false;
                group.bench_function(id, |b| {
                    b.iter(|| {
                        flip = !flip;
                        mesh.refit(if flip { &other } else { rest }).unwrap()
                    })
                });
            }
        }
        group.finish();
    }
}

fn query(c: &mut Criterion) {
    for s in subjects() {
        let mut group = c.benchmark_group(format!("query/{}", s.class));
        // The mesh against a deformed copy shifted by 0.45 of its size: the two interpenetrate
        // over part of their surface, as in the paper's scenes.
        let morph = Morph::random(&s.mesh, 4, 0.08, 2);
        let mut shifted = s.mesh.clone();
        shifted.positions = morph.at(&s.mesh.positions, 0.3);
        shifted.translate([0.45, 0.1, 0.0]);
        for o in kinds() {
            let a = Mesh::new(&s.mesh.positions, &s.mesh.triangles, &o).unwrap();
            let b = Mesh::new(&shifted.positions, &shifted.triangles, &o).unwrap();
            let mut pairs = Pairs::new();
            group.bench_function(label(&o), |bench| {
                bench.iter(|| {
                    collide(&a, None, &b, None, &QueryOptions::default(), &mut pairs).unwrap()
                })
            });
        }
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = build, refit, query
}
criterion_main!(benches);
