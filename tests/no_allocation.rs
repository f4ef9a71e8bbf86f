//! Refits and steady-state queries on one thread allocate nothing; on several threads, a few
//! small jobs per call: counted with a global allocator.

use dvh::fixtures::{MeshData, Morph, icosphere, torus};
use dvh::{
    BuildOptions, CcdMode, CcdOptions, Contacts, Curves, Impacts, Mesh, NearPairs, Pairs, Pose,
    QueryMode, QueryOptions, RadiusKind, Scene, TreeKind, VolumeKind, collide, continuous_collide,
    intersection_curves, nearest_features, proximity, self_collide, self_continuous_collide,
    self_intersection_curves, self_nearest_features, self_proximity,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    // Const-initialised: counting here allocates nothing and registers no destructor.
    static HERE: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        let _ = HERE.try_with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        let _ = HERE.try_with(|c| c.set(c.get() + 1));
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

/// Allocations made by the calling thread alone while `f` runs: for calls on one thread, which
/// the pool's threads (still winding down from another test's work) must not be counted against.
fn allocations_here(f: impl FnOnce()) -> usize {
    let before = HERE.with(|c| c.get());
    f();
    HERE.with(|c| c.get()) - before
}

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
    assert!(dvh::testing::at_least_two_threads() >= 2);
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
        let before = jobs_handed();
        let refit = allocations_during(|| {
            a.refit(f).unwrap();
        });
        // The refit shares out its positions and its subtrees.
        assert!(
            jobs_handed() >= before + 2,
            "the refit ran on the calling thread alone"
        );
        let held = pairs.memory_bytes();
        let before = jobs_handed();
        let query = allocations_during(|| {
            collide(&a, None, &b, None, &threaded, &mut pairs).unwrap();
        });
        assert!(
            jobs_handed() > before,
            "the query ran on the calling thread alone"
        );
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

/// What a frame counts apart: the motion refits, then each query kind beyond `collide`, in
/// the order [`Frames::run`] runs them.
const KINDS: [&str; 9] = [
    "refit_motion",
    "self_collide",
    "proximity",
    "self_proximity",
    "nearest_features",
    "self_nearest_features",
    "continuous_collide",
    "self_continuous_collide",
    "scene",
];

/// A frame's work for every query kind: allocations counted apart, per kind.
struct Frames {
    /// Per frame: the positions of `a`, of `b`, and of `ab`.
    frames: Vec<[Vec<f64>; 3]>,
    a: Mesh,
    b: Mesh,
    /// `a` and `b` in one mesh, for the self queries: they find the pairs between its parts.
    ab: Mesh,
    scene: Scene,
    ids: [u32; 2],
    pairs: Pairs,
    near: NearPairs,
    impacts: Impacts,
    contacts: Contacts,
    found: [usize; 9],
    /// Per kind, in the last frame run: did the result buffers grow?
    grew: [bool; 9],
}

impl Frames {
    fn new() -> Frames {
        let options = BuildOptions::default().with_refit_threads(1);
        let sa = icosphere(4);
        let mut sb = torus(0.6, 0.25, 80, 30);
        sb.translate([0.8, 0.0, 0.0]);
        let a = Mesh::new(&sa.positions, &sa.triangles, &options).unwrap();
        let b = Mesh::new(&sb.positions, &sb.triangles, &options).unwrap();
        let mut both: MeshData = sa.clone();
        both.append(&sb);
        let ab = Mesh::new(&both.positions, &both.triangles, &options).unwrap();
        let (ma, mb) = (Morph::random(&sa, 3, 0.1, 1), Morph::random(&sb, 3, 0.1, 2));
        let frames = (0..6)
            .map(|f| {
                let t = f as f64 / 12.0;
                let (pa, pb) = (ma.at(&sa.positions, t), mb.at(&sb.positions, t));
                let pab = [&pa[..], &pb[..]].concat();
                [pa, pb, pab]
            })
            .collect();
        let mut scene = Scene::new();
        let ids = [
            scene.add_deformable(&a, 1, u32::MAX).unwrap(),
            scene.add_deformable(&b, 1, u32::MAX).unwrap(),
        ];
        Frames {
            frames,
            a,
            b,
            ab,
            scene,
            ids,
            pairs: Pairs::new(),
            near: NearPairs::new(),
            impacts: Impacts::new(),
            contacts: Contacts::new(),
            found: [0; 9],
            grew: [false; 9],
        }
    }

    /// Runs frame `f` (a motion from frame `f` to the next, then every query kind) with
    /// `threads`, and `count` around each kind; returns each kind's count.
    fn run(
        &mut self,
        f: usize,
        threads: u32,
        ccd: CcdMode,
        count: &dyn Fn(&mut dyn FnMut()) -> usize,
    ) -> [usize; 9] {
        let q = QueryOptions::default().with_threads(threads);
        let c = CcdOptions::default().with_mode(ccd).with_threads(threads);
        let next = (f + 1) % self.frames.len();
        let (from, to) = (&self.frames[f], &self.frames[next]);
        let d = 0.02;
        let mut n = [0; 9];
        let found = &mut self.found;
        let (a, b, ab) = (&mut self.a, &mut self.b, &mut self.ab);
        let (pairs, near, impacts) = (&mut self.pairs, &mut self.near, &mut self.impacts);
        let grew = &mut self.grew;
        // What the query keeps: its buffers' bytes, and (as a count, which only grows) the patch
        // tests' scratch, kept per thread, that grew on a pool thread new to such work.
        let held = |p: &Pairs, n: &NearPairs, i: &Impacts| {
            p.memory_bytes()
                + n.memory_bytes()
                + i.memory_bytes()
                + dvh::testing::patch_scratch_growths()
        };
        n[0] = count(&mut || {
            a.refit_motion(&from[0], &to[0]).unwrap();
            b.refit_motion(&from[1], &to[1]).unwrap();
            ab.refit_motion(&from[2], &to[2]).unwrap();
        });
        let before = held(pairs, near, impacts);
        n[1] = count(&mut || {
            self_collide(ab, &q, pairs).unwrap();
            found[1] += pairs.len();
        });
        grew[1] = held(pairs, near, impacts) > before;
        let before = held(pairs, near, impacts);
        n[2] = count(&mut || {
            proximity(a, None, b, None, d, &q, pairs).unwrap();
            found[2] += pairs.len();
        });
        grew[2] = held(pairs, near, impacts) > before;
        let before = held(pairs, near, impacts);
        n[3] = count(&mut || {
            self_proximity(ab, d, &q, pairs).unwrap();
            found[3] += pairs.len();
        });
        grew[3] = held(pairs, near, impacts) > before;
        let before = held(pairs, near, impacts);
        n[4] = count(&mut || {
            nearest_features(a, None, b, None, d, &q, near).unwrap();
            found[4] += near.len();
        });
        grew[4] = held(pairs, near, impacts) > before;
        let before = held(pairs, near, impacts);
        n[5] = count(&mut || {
            self_nearest_features(ab, d, &q, near).unwrap();
            found[5] += near.len();
        });
        grew[5] = held(pairs, near, impacts) > before;
        let before = held(pairs, near, impacts);
        n[6] = count(&mut || {
            continuous_collide(a, b, &c, impacts).unwrap();
            found[6] += impacts.len();
        });
        grew[6] = held(pairs, near, impacts) > before;
        let before = held(pairs, near, impacts);
        n[7] = count(&mut || {
            self_continuous_collide(ab, &c, impacts).unwrap();
            found[7] += impacts.len();
        });
        grew[7] = held(pairs, near, impacts) > before;
        let (scene, ids, contacts) = (&mut self.scene, self.ids, &mut self.contacts);
        n[8] = count(&mut || {
            scene.set_positions(ids[0], &to[0]).unwrap();
            scene.set_positions(ids[1], &to[1]).unwrap();
            scene.collide(&q, contacts).unwrap();
            found[8] += contacts.len();
        });
        n
    }
}

/// A scene query allocates a few small vectors a call (the objects it needs, their shares of
/// the refit, their lazy views), however large the meshes and however many the contacts.
const SCENE_ALLOCATIONS: usize = 12;

/// Every query kind beyond `collide`, in steady state on one thread: frames of deforming meshes
/// (a motion over each step for the continuous queries), every kind warmed up over them, then
/// counted frame by frame. The continuous queries in `CcdMode::Conservative`: in
/// `CcdMode::Exact`, the time of each impact strictly inside the step is rounded in big-integer
/// arithmetic, which allocates; without such impacts the exact mode allocates nothing either.
#[test]
fn every_query_kind_in_steady_state_allocates_nothing() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let mut frames = Frames::new();
    let plain = |f: &mut dyn FnMut()| {
        f();
        0
    };
    let counted = |f: &mut dyn FnMut()| allocations_during(f);
    let count = frames.frames.len();
    for f in 0..count {
        frames.run(f, 1, CcdMode::Conservative, &plain);
    }
    for f in 0..count {
        let n = frames.run(f, 1, CcdMode::Conservative, &counted);
        for (kind, n) in KINDS.iter().zip(n) {
            if *kind == "scene" {
                assert!(
                    n <= SCENE_ALLOCATIONS,
                    "frame {f}: {n} allocations in {kind}"
                );
            } else {
                assert_eq!(n, 0, "frame {f}: {n} allocations in {kind}");
            }
        }
    }
    for (kind, found) in KINDS.iter().zip(frames.found) {
        assert!(found > 0 || *kind == "refit_motion", "{kind} found nothing");
    }

    // The exact mode where no impact falls strictly inside the step: one part deforming
    // without touching itself (its neighbouring triangles tested all the same).
    let mut impacts = Impacts::new();
    let exact = CcdOptions::default().with_threads(1);
    let mut tested = 0;
    for f in 0..2 * count {
        let (from, to) = (&frames.frames[f % count], &frames.frames[(f + 1) % count]);
        let n = allocations_during(|| {
            frames.a.refit_motion(&from[0], &to[0]).unwrap();
            let stats = self_continuous_collide(&frames.a, &exact, &mut impacts).unwrap();
            tested += stats.primitive_tests;
        });
        assert!(impacts.is_empty(), "the part does not touch itself");
        assert!(
            f < count || n == 0,
            "frame {f}: {n} allocations in the exact mode"
        );
    }
    assert!(tested > 0);
}

/// Jobs handed to the pool so far by the calling thread: one per step shared out on two
/// threads.
fn jobs_handed() -> u64 {
    use dvh::testing::{Step, shared_count};
    [
        Step::Traversal,
        Step::Pairs,
        Step::Sort,
        Step::PairSort,
        Step::Values,
        Step::Refit,
        Step::Store,
        Step::SceneRefit,
        Step::ScenePairs,
    ]
    .map(shared_count)
    .iter()
    .sum()
}

/// Every query kind beyond `collide` in steady state on two threads allocates only the jobs it
/// hands the pool (one per step shared out), and rayon's injector block once every 63 jobs, as
/// `threaded_refits_and_queries_allocate_only_their_jobs` counts them. A query whose buffers
/// grew (a thread kept from its core left the other a larger share than in any warm-up round)
/// is not counted, nor one whose self-collision patch tests grew their scratch, which is kept
/// per thread (the job went to a pool thread that had run none as large). The scene allocates
/// its few vectors as on one thread.
#[test]
fn every_query_kind_threaded_allocates_only_its_jobs() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    assert!(dvh::testing::at_least_two_threads() >= 2);
    let mut frames = Frames::new();
    let plain = |f: &mut dyn FnMut()| {
        f();
        0
    };
    let count = frames.frames.len();
    for _ in 0..3 {
        for f in 0..count {
            frames.run(f, 2, CcdMode::Conservative, &plain);
        }
    }
    let (mut total, mut total_jobs, mut calls) = (0, 0, 0);
    for f in 0..count {
        let handed = std::cell::RefCell::new(Vec::new());
        let n = frames.run(f, 2, CcdMode::Conservative, &|g: &mut dyn FnMut()| {
            let before = jobs_handed();
            let n = allocations_during(g);
            handed.borrow_mut().push(jobs_handed() - before);
            n
        });
        let handed = handed.into_inner();
        for (k, ((kind, n), jobs)) in KINDS.iter().zip(n).zip(handed).enumerate() {
            let jobs = jobs as usize;
            if *kind == "scene" {
                assert!(
                    n <= SCENE_ALLOCATIONS + jobs + 4,
                    "frame {f}: {n} allocations in {kind}, {jobs} jobs"
                );
                continue;
            }
            if *kind != "refit_motion" {
                assert!(jobs > 0, "frame {f}: {kind} shared nothing out");
            }
            if frames.grew[k] {
                continue;
            }
            assert!(
                n <= jobs + 1,
                "frame {f}: {n} allocations in {kind}, {jobs} jobs"
            );
            total += n;
            total_jobs += jobs;
            calls += 1;
        }
    }
    assert!(
        total <= total_jobs + total_jobs.div_ceil(63),
        "{total} allocations in {calls} threaded calls: more than their {total_jobs} jobs and the injector's blocks"
    );
    assert!(calls > 0, "every measured query grew its buffers");
}

/// A scene over its steps, once warmed up, on one thread: giving a rigid object a pose motion
/// and a deformable one a motion, and the scene's continuous collision (exact, without impacts;
/// the conservative mode) and stencils (within a distance where the objects come near), with
/// self-contact on, allocate nothing.
#[test]
fn scene_steps_allocate_nothing() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    use dvh::{SceneImpacts, SceneNearPairs};
    let ball = icosphere(2);
    let mesh = Mesh::new(&ball.positions, &ball.triangles, &BuildOptions::default()).unwrap();
    let mut scene = Scene::new();
    let rigid = scene.add_rigid(&mesh, None, 1, u32::MAX).unwrap();
    let soft = scene.add_deformable(&mesh, 1, u32::MAX).unwrap();
    scene.set_self_contact(soft, true).unwrap();
    // The soft ball turned about a skew axis (no symmetry shared with the other, whose exact
    // ties would be decided in big integers), 2.05 to the right, breathing a little.
    let turn = Pose::from_isometry(&nalgebra::Isometry3::new(
        nalgebra::Vector3::new(2.05, 0.01, -0.02),
        nalgebra::Vector3::new(0.3, 0.7, 1.1),
    ))
    .unwrap();
    let at = |step: usize, t: f64| -> Vec<f64> {
        let s = 1.0 + 0.01 * (step as f64 + t).sin();
        ball.positions
            .chunks_exact(3)
            .flat_map(|p| turn.transform_point(&[s * p[0], s * p[1], s * p[2]]))
            .collect()
    };
    let pose = |step: usize| {
        let a = 0.01 * step as f64;
        Pose::new(
            [
                [a.cos(), -a.sin(), 0.0],
                [a.sin(), a.cos(), 0.0],
                [0.0, 0.0, 1.0],
            ],
            [0.0; 3],
        )
        .unwrap()
    };
    let mut impacts = SceneImpacts::new();
    let mut near = SceneNearPairs::new();
    let exact = CcdOptions::default().with_threads(1);
    let queries = [
        exact,
        exact.with_earliest_only(true),
        exact.with_mode(CcdMode::Conservative),
    ];
    let mut found = 0;
    for step in 0..8 {
        let (s, e) = (at(step, 0.0), at(step, 1.0));
        let n = allocations_here(|| {
            scene
                .set_pose_motion(rigid, Some(&pose(step)), Some(&pose(step + 1)))
                .unwrap();
            scene.set_motion(soft, &s, &e).unwrap();
            for q in &queries {
                scene.continuous_collide(q, &mut impacts).unwrap();
                assert!(impacts.is_empty(), "step {step}: the balls stay apart");
            }
            scene
                .nearest_features(0.2, &QueryOptions::default().with_threads(1), &mut near)
                .unwrap();
            found += near.len();
        });
        // Two steps to warm up: a result buffer's two halves take turns.
        assert!(step < 3 || n == 0, "step {step}: {n} allocations");
    }
    assert!(found > 0, "stencils between the balls");
}

#[test]
fn intersection_curves_in_steady_state_allocate_nothing() {
    // A sphere through a torus, and both as one mesh, deforming: refit, the curves of the two
    // and of the one, and their length gradients, frame after frame on one thread, once every
    // buffer has met every frame.
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let options = BuildOptions::default().with_refit_threads(1);
    let sa = icosphere(3);
    let mut sb = torus(0.6, 0.25, 48, 20);
    sb.translate([0.8, 0.0, 0.0]);
    let mut both: MeshData = sa.clone();
    both.append(&sb);
    let mut a = Mesh::new(&sa.positions, &sa.triangles, &options).unwrap();
    let mut b = Mesh::new(&sb.positions, &sb.triangles, &options).unwrap();
    let mut ab = Mesh::new(&both.positions, &both.triangles, &options).unwrap();
    let (ma, mb) = (Morph::random(&sa, 3, 0.1, 1), Morph::random(&sb, 3, 0.1, 2));
    let frames: Vec<[Vec<f64>; 3]> = (0..6)
        .map(|f| {
            let t = f as f64 / 12.0;
            let (pa, pb) = (ma.at(&sa.positions, t), mb.at(&sb.positions, t));
            let pab = [&pa[..], &pb[..]].concat();
            [pa, pb, pab]
        })
        .collect();
    let q = QueryOptions::default().with_threads(1);
    let (mut two, mut one) = (Curves::new(), Curves::new());
    let mut ga = vec![[0.0; 3]; a.vertex_count()];
    let mut gb = vec![[0.0; 3]; b.vertex_count()];
    let mut gab = vec![[0.0; 3]; ab.vertex_count()];
    let mut segments = 0;
    for pass in 0..2 {
        for p in &frames {
            let n = allocations_here(|| {
                a.refit(&p[0]).unwrap();
                b.refit(&p[1]).unwrap();
                ab.refit(&p[2]).unwrap();
                intersection_curves(&a, None, &b, None, &q, &mut two).unwrap();
                two.length_gradient(&a, None, &b, None, &mut ga, &mut gb)
                    .unwrap();
                self_intersection_curves(&ab, &q, &mut one).unwrap();
                one.self_length_gradient(&ab, &mut gab).unwrap();
            });
            segments += two.len() + one.len();
            assert!(pass == 0 || n == 0, "{n} allocations in a steady frame");
        }
    }
    assert!(segments > 0);
}

/// The distance of two deforming meshes and the point queries of many points on one, on one
/// thread: each frame's refits and queries allocate nothing once the scratch (kept per thread)
/// is large enough for the frame: counted on each frame's third run (a new frame allocates
/// only where a scratch buffer must grow, which a steady state ends; the stencil buffer's two
/// halves take turns, so two runs warm it).
#[test]
fn distances_and_point_queries_in_steady_state_allocate_nothing() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let options = BuildOptions::default().with_refit_threads(1);
    let sa = icosphere(3);
    let mut sb = torus(0.6, 0.25, 40, 16);
    sb.translate([2.2, 0.0, 0.0]);
    let mut a = Mesh::new(&sa.positions, &sa.triangles, &options).unwrap();
    let mut b = Mesh::new(&sb.positions, &sb.triangles, &options).unwrap();
    let (ma, mb) = (Morph::random(&sa, 3, 0.1, 5), Morph::random(&sb, 3, 0.1, 6));
    let mut rng = dvh::fixtures::Rng::new(9);
    let points: Vec<[f64; 3]> = (0..300)
        .map(|_| std::array::from_fn(|_| rng.range(-1.5, 1.5)))
        .collect();
    let one = dvh::DistanceOptions::default().with_threads(1);
    let mut d = dvh::Distance::default();
    let mut closest = vec![dvh::ClosestPoint::default(); points.len()];
    let mut winding = vec![0; points.len()];
    let mut signed = vec![0.0; points.len()];
    for f in 0..8 {
        let t = f as f64 / 16.0;
        let (pa, pb) = (ma.at(&sa.positions, t), mb.at(&sb.positions, t));
        for round in 0..3 {
            let n = [
                allocations_here(|| {
                    a.refit(&pa).unwrap();
                    b.refit(&pb).unwrap();
                }),
                allocations_here(|| {
                    dvh::distance(&a, None, &b, None, &one, &mut d).unwrap();
                }),
                allocations_here(|| {
                    dvh::closest_points(&a, None, &points, &one, &mut closest).unwrap();
                }),
                allocations_here(|| {
                    dvh::winding_numbers(&a, None, &points, 1, &mut winding).unwrap();
                }),
                allocations_here(|| {
                    dvh::signed_distances(&a, None, &points, &one, &mut signed).unwrap();
                }),
            ];
            assert!(d.found() && !d.intersecting() && d.distance > 0.0);
            assert!(winding.contains(&1) && winding.contains(&0));
            // Refit, distance, closest points, winding numbers, signed distances.
            assert!(round < 2 || n == [0; 5], "frame {f}: allocations {n:?}");
        }
    }
}
