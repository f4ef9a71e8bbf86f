//! Refits and steady-state queries allocate nothing: counted with a global allocator.

use dvh::fixtures::{Morph, icosphere, torus};
use dvh::{
    BuildOptions, Mesh, Pairs, Pose, QueryMode, QueryOptions, RadiusKind, TreeKind, VolumeKind,
    collide,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    f();
    ALLOCATIONS.load(Ordering::Relaxed) - before
}

#[test]
fn refit_and_steady_state_queries_do_not_allocate() {
    for tree in [TreeKind::Octree, TreeKind::Binary] {
        for (volume, radius) in [
            (VolumeKind::Dvh, RadiusKind::Wrapped),
            (VolumeKind::Dvh, RadiusKind::Layered),
            (VolumeKind::Sbv, RadiusKind::Wrapped),
            (VolumeKind::Sbv, RadiusKind::Layered),
            (VolumeKind::Aabb, RadiusKind::Layered),
        ] {
            let options = BuildOptions {
                tree,
                radius,
                volume,
                ..BuildOptions::default()
            };
            let sa = icosphere(3);
            let mut sb = torus(0.6, 0.25, 40, 20);
            sb.translate([0.8, 0.0, 0.0]);
            let mut a = Mesh::new(&sa.positions, &sa.triangles, &options).unwrap();
            let mut b = Mesh::new(&sb.positions, &sb.triangles, &options).unwrap();
            let (ma, mb) = (Morph::random(&sa, 3, 0.2, 1), Morph::random(&sb, 3, 0.2, 2));
            let frames: Vec<(Vec<f64>, Vec<f64>)> = (0..6)
                .map(|f| {
                    (
                        ma.at(&sa.positions, f as f64 / 6.0),
                        mb.at(&sb.positions, f as f64 / 6.0),
                    )
                })
                .collect();
            let pose = Pose::new(
                [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
                [0.1, 0.0, 0.0],
            )
            .unwrap();
            let modes = [
                QueryMode::Triangles,
                QueryMode::FirstHit,
                QueryMode::Leaves,
                QueryMode::Depth(2),
                QueryMode::Budget(500),
                QueryMode::Budget(u64::MAX),
            ];
            let mut pairs = Pairs::new();
            let mut found = 0;
            // Warm-up: the buffer grows to the scene's needs over all frames.
            for (pa, pb) in &frames {
                a.refit(pa).unwrap();
                b.refit(pb).unwrap();
                for mode in modes {
                    collide(
                        &a,
                        Some(&pose),
                        &b,
                        None,
                        &QueryOptions::with_mode(mode),
                        &mut pairs,
                    )
                    .unwrap();
                    collide(
                        &a,
                        None,
                        &b,
                        None,
                        &QueryOptions::with_mode(mode),
                        &mut pairs,
                    )
                    .unwrap();
                }
            }
            for (pa, pb) in &frames {
                let n = allocations_during(|| {
                    a.refit(pa).unwrap();
                    b.refit(pb).unwrap();
                    for mode in modes {
                        collide(
                            &a,
                            Some(&pose),
                            &b,
                            None,
                            &QueryOptions::with_mode(mode),
                            &mut pairs,
                        )
                        .unwrap();
                        found += pairs.len();
                        collide(
                            &a,
                            None,
                            &b,
                            None,
                            &QueryOptions::with_mode(mode),
                            &mut pairs,
                        )
                        .unwrap();
                        found += pairs.len();
                    }
                });
                assert_eq!(n, 0, "{options:?}: {n} allocations in a steady-state frame");
            }
            assert!(found > 0, "the scene has contacts");
        }
    }
}
