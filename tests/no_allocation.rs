//! Refits and steady-state queries on one thread allocate nothing; on several threads, a few
//! small jobs per call: counted with a global allocator.

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

/// The query options of `mode` on the calling thread only.
fn one_thread(mode: QueryMode) -> QueryOptions {
    QueryOptions::with_mode(mode).with_threads(1)
}

/// The counter is global: the tests take turns.
static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    f();
    ALLOCATIONS.load(Ordering::Relaxed) - before
}

#[test]
fn refit_and_steady_state_queries_do_not_allocate() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    for tree in [TreeKind::Octree, TreeKind::Binary] {
        for (volume, radius) in [
            (VolumeKind::Dvh, RadiusKind::Wrapped),
            (VolumeKind::Dvh, RadiusKind::Layered),
            (VolumeKind::Sbv, RadiusKind::Wrapped),
            (VolumeKind::Sbv, RadiusKind::Layered),
            (VolumeKind::Aabb, RadiusKind::Layered),
        ] {
            let options = BuildOptions::default()
                .with_tree(tree)
                .with_radius(radius)
                .with_volume(volume)
                .with_refit_threads(1);
            // Large enough that the default options would share the queries out.
            let sa = icosphere(5);
            let mut sb = torus(0.6, 0.25, 120, 40);
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
                    collide(&a, Some(&pose), &b, None, &one_thread(mode), &mut pairs).unwrap();
                    collide(&a, None, &b, None, &one_thread(mode), &mut pairs).unwrap();
                }
            }
            for (pa, pb) in &frames {
                let n = allocations_during(|| {
                    a.refit(pa).unwrap();
                    b.refit(pb).unwrap();
                    for mode in modes {
                        collide(&a, Some(&pose), &b, None, &one_thread(mode), &mut pairs).unwrap();
                        found += pairs.len();
                        collide(&a, None, &b, None, &one_thread(mode), &mut pairs).unwrap();
                        found += pairs.len();
                    }
                });
                assert_eq!(n, 0, "{options:?}: {n} allocations in a steady-state frame");
            }
            assert!(found > 0, "the scene has contacts");
        }
    }
}

/// Shared out over several threads, a steady-state refit or query allocates only the jobs it
/// hands the pool: one per thread beyond the calling one, for each step that is shared out
/// (refit: storing the positions and the subtrees; query: the traversal and the sort). Jobs
/// handed to rayon's pool from outside it queue in its injector, which allocates a block of 63
/// slots every 63 jobs: where that falls depends on every job the process handed the pool
/// before (the other tests' too), so it is allowed once in the measured frames. A query whose
/// buffers grew (a thread took a larger share than in any warm-up round) is not counted.
#[test]
fn threaded_refits_and_queries_allocate_only_their_jobs() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let s = icosphere(6);
    // The torus's tube runs along the sphere's surface: dense contact.
    let t = torus(1.0, 0.05, 200, 100);
    let options = BuildOptions::default().with_refit_threads(2);
    let mut a = Mesh::new(&s.positions, &s.triangles, &options).unwrap();
    let b = Mesh::new(&t.positions, &t.triangles, &options).unwrap();
    let morph = Morph::random(&s, 3, 0.05, 4);
    let frames: Vec<Vec<f64>> = (0..4)
        .map(|f| morph.at(&s.positions, f as f64 / 4.0))
        .collect();
    let threaded = QueryOptions::default().with_threads(2);
    let mut pairs = Pairs::new();
    // Threads take work items as they come free, so the share each thread finds, and the size
    // its own buffers grow to, varies from run to run: a few rounds let every thread's buffers
    // reach the largest share it takes (steady state), as they do in an application's frames.
    for _ in 0..4 {
        for f in &frames {
            a.refit(f).unwrap();
            collide(&a, None, &b, None, &threaded, &mut pairs).unwrap();
        }
    }
    assert!(
        pairs.len() > 1000,
        "{} pairs: not dense enough to share out",
        pairs.len()
    );
    let (mut jobs, mut total, mut steady) = (0usize, 0, 0);
    for f in &frames {
        let refit = allocations_during(|| {
            a.refit(f).unwrap();
        });
        let held = pairs.memory_bytes();
        let query = allocations_during(|| {
            collide(&a, None, &b, None, &threaded, &mut pairs).unwrap();
        });
        // At most one job per step shared out: two for a refit, two for a query; plus, at most
        // once, the injector's block.
        assert!(refit <= 3, "{refit} allocations in a threaded refit");
        jobs += 2;
        total += refit;
        // A thread kept from its core (by another process) leaves a larger share than any
        // warm-up round gave to the other, whose buffers then grow (geometrically: rarely, and
        // less often each time). Such a query is told by the buffer's size and not counted.
        if pairs.memory_bytes() > held {
            assert!(
                query <= 16,
                "{query} allocations in a threaded query that grew"
            );
            continue;
        }
        assert!(query <= 3, "{query} allocations in a threaded query");
        jobs += 2;
        total += query;
        steady += 1;
    }
    assert!(steady > 0, "every measured query grew its buffers");
    let blocks = jobs.div_ceil(63);
    assert!(
        total <= jobs + blocks,
        "{total} allocations in {} threaded frames: more than {jobs} jobs and {blocks} injector block",
        frames.len()
    );
}
