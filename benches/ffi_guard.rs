//! What the C boundary costs on the query path: the same query through `dvh_collide` (panic
//! guard, handle tags, the atomic readers-or-writer state of both meshes and of the result
//! buffer) and through the Rust `collide`, on two meshes whose roots do not even overlap (the
//! cheapest query there is: the boundary's cost stands alone) and on two overlapping meshes.
//!
//! `cargo bench --bench ffi_guard`.

use criterion::{Criterion, criterion_group, criterion_main};
use dvh::ffi::{
    DVH_STATUS_OK, DvhMesh, DvhPairs, dvh_collide, dvh_mesh_create, dvh_mesh_free, dvh_pairs_free,
    dvh_pairs_new,
};
use dvh::fixtures::{MeshData, icosphere};
use dvh::{BuildOptions, Mesh, Pairs, QueryOptions, collide};
use std::hint::black_box;

/// `mesh` moved by `dx` along x.
fn shifted(mesh: &MeshData, dx: f64) -> MeshData {
    let mut m = mesh.clone();
    for p in m.positions.chunks_exact_mut(3) {
        p[0] += dx;
    }
    m
}

fn c_mesh(m: &MeshData) -> *mut DvhMesh {
    let mut out = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given; `out` is writable.
    let status = unsafe {
        dvh_mesh_create(
            m.positions.as_ptr(),
            m.positions.len() / 3,
            m.triangles.as_ptr(),
            m.triangles.len() / 3,
            std::ptr::null(),
            &mut out,
        )
    };
    assert_eq!(status, DVH_STATUS_OK);
    out
}

fn boundary(c: &mut Criterion) {
    let sphere = icosphere(4);
    let options = QueryOptions::default();
    let mut group = c.benchmark_group("ffi_guard");
    for (name, dx) in [("apart", 3.0), ("overlapping", 0.5)] {
        let (a, b) = (sphere.clone(), shifted(&sphere, dx));
        let build = BuildOptions::default();
        let (ra, rb) = (
            Mesh::new(&a.positions, &a.triangles, &build).expect("mesh"),
            Mesh::new(&b.positions, &b.triangles, &build).expect("mesh"),
        );
        let mut pairs = Pairs::new();
        group.bench_function(format!("{name}/rust"), |bench| {
            bench.iter(|| {
                collide(&ra, None, &rb, None, &options, &mut pairs).expect("query");
                black_box(pairs.len())
            })
        });
        let (ca, cb) = (c_mesh(&a), c_mesh(&b));
        let out: *mut DvhPairs = dvh_pairs_new();
        group.bench_function(format!("{name}/c"), |bench| {
            bench.iter(|| {
                // SAFETY: live handles, one thread.
                let s = unsafe {
                    dvh_collide(
                        ca,
                        std::ptr::null(),
                        cb,
                        std::ptr::null(),
                        std::ptr::null(),
                        out,
                        std::ptr::null_mut(),
                    )
                };
                black_box(s)
            })
        });
        // SAFETY: live handles, released once.
        unsafe {
            dvh_mesh_free(ca);
            dvh_mesh_free(cb);
            dvh_pairs_free(out);
        }
    }
    group.finish();
}

criterion_group!(benches, boundary);
criterion_main!(benches);
