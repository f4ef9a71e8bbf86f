//! Soak: many frames of random deformation through the C ABI, answers compared with
//! brute force at sampled frames, resident memory measured after a warm-up and at the end.
//!
//! 1. A mesh pair: a torus and a sphere, both deformed every frame (a smooth morph plus random
//!    jitter of every vertex), the sphere also moved by a pose; every frame refits both and
//!    runs `dvh_collide`, `dvh_self_collide` and `dvh_proximity` in a mode that cycles through
//!    all five. At sampled frames, the three in exact mode against brute force.
//! 2. A scene of `--objects` objects (half rigid, moved by poses; half deformable, morphed),
//!    filters and pair exclusions, objects removed and added again, lazy refit switched on and
//!    off; `dvh_scene_collide` every frame, against brute force over every allowed object pair at
//!    sampled frames.
//! 3. A mesh of `--big` triangles (a rippled sheet): build, refit, a query against a small sphere
//!    through it (against a direct test of every triangle near the sphere), self-collision (a
//!    height field cannot touch itself: none).
//!
//! Exits non-zero on any wrong answer, any failed call, or resident memory that grew between the
//! end of the warm-up (a tenth of the frames) and the end by more than 1% + 1 MiB (unless
//! `--no-memory-check`, for runs under valgrind).
//!
//! `cargo run --release --example soak -- [--frames 10000] [--objects 100] [--check-every 500]
//! [--big 10000000] [--no-memory-check]`; `scripts/soak.sh` runs it and a shorter run under
//! valgrind.

use dvh::exact::triangles_intersect;
use dvh::ffi::*;
use dvh::fixtures::oracle::{proximity_brute_force, self_collide_brute_force};
use dvh::fixtures::{MeshData, Morph, Rng, grid, icosphere, torus};
use dvh::{BuildOptions, Mesh, Pair, Pose, brute_force};
use nalgebra::{Isometry3, Vector3};
use std::collections::{BTreeMap, HashSet};
use std::time::Instant;

type Failure = Box<dyn std::error::Error>;

fn arg(name: &str, default: usize) -> Result<usize, Failure> {
    let args: Vec<String> = std::env::args().collect();
    match args.iter().position(|a| a == name) {
        Some(i) => Ok(args
            .get(i + 1)
            .ok_or(format!("{name} needs a value"))?
            .parse()?),
        None => Ok(default),
    }
}

/// Resident and peak resident memory of this process in KiB (`/proc/self/status`; 0 where
/// there is none).
fn memory_kib() -> (u64, u64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(0)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

/// Fails with the library's message unless the call succeeded.
fn ok(status: DvhStatus, call: &str) -> Result<(), Failure> {
    if status == DVH_STATUS_OK {
        return Ok(());
    }
    let mut buf = vec![0u8; 512];
    // SAFETY: a writable buffer of the capacity given.
    let n = unsafe { dvh_last_error_message(buf.as_mut_ptr().cast(), buf.len()) };
    buf.truncate(n.min(buf.len()));
    let message = String::from_utf8_lossy(&buf)
        .trim_end_matches('\0')
        .to_string();
    Err(format!("{call}: status {status}: {message}").into())
}

fn c_mesh(m: &MeshData, options: &DvhBuildOptions) -> Result<*mut DvhMesh, Failure> {
    let mut mesh = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given; the out-parameter is writable.
    let status = unsafe {
        dvh_mesh_create(
            m.positions.as_ptr(),
            m.vertex_count(),
            m.triangles.as_ptr(),
            m.triangle_count(),
            options,
            &mut mesh,
        )
    };
    ok(status, "dvh_mesh_create")?;
    Ok(mesh)
}

fn c_pose(p: &Pose) -> DvhPose {
    let r = p.rotation();
    DvhPose {
        rotation: std::array::from_fn(|k| r[k / 3][k % 3]),
        translation: p.translation(),
    }
}

fn pairs_of(pairs: *const DvhPairs) -> Vec<Pair> {
    // SAFETY: a live buffer, used by this thread only.
    let mut v: Vec<Pair> = unsafe {
        let (n, data) = (dvh_pairs_len(pairs), dvh_pairs_data(pairs));
        (0..n)
            .map(|i| *data.add(i))
            .map(|p| Pair { a: p.a, b: p.b })
            .collect()
    };
    v.sort_unstable();
    v
}

fn random_pose(rng: &mut Rng, centre: [f64; 3], reach: f64) -> Pose {
    let axis = Vector3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    let t = Vector3::from(centre) + Vector3::new(rng.range(-reach, reach), 0.0, 0.0);
    Pose::from_isometry(&Isometry3::new(t, axis * 3.0)).expect("a rotation")
}

/// Adds uniform noise of `amplitude` to every coordinate.
fn jitter(positions: &mut [f64], rng: &mut Rng, amplitude: f64) {
    for x in positions {
        *x += rng.range(-amplitude, amplitude);
    }
}

/// Fails when a query's answer at `frame` is not brute force's.
fn same<T: PartialEq>(frame: usize, what: &str, got: &[T], expected: &[T]) -> Result<(), Failure> {
    if got == expected {
        return Ok(());
    }
    let (n, m) = (got.len(), expected.len());
    Err(format!("frame {frame}: {what} {n} pairs, brute force {m}").into())
}

/// Memory figures of one phase.
struct Memory {
    start: u64,
    warm: u64,
    end: u64,
    peak: u64,
}

impl Memory {
    fn check(&self, what: &str) -> Result<(), Failure> {
        // Under valgrind the process's memory is valgrind's; it checks leaks itself.
        if std::env::args().any(|a| a == "--no-memory-check") {
            return Ok(());
        }
        println!(
            "{what}: resident memory {} KiB at the start, {} KiB after the warm-up, {} KiB at the end (peak {} KiB)",
            self.start, self.warm, self.end, self.peak
        );
        if self.end > self.warm + self.warm / 100 + 1024 {
            return Err(format!(
                "{what}: resident memory grew from {} to {} KiB",
                self.warm, self.end
            )
            .into());
        }
        Ok(())
    }
}

fn mesh_pair(frames: usize, check_every: usize, rng: &mut Rng) -> Result<(), Failure> {
    let rest_a = torus(0.4, 0.15, 40, 20);
    let mut rest_b = icosphere(3);
    rest_b.scale(0.3);
    let (morph_a, morph_b) = (
        Morph::random(&rest_a, 6, 0.35, 1),
        Morph::random(&rest_b, 3, 0.1, 2),
    );
    let options = dvh_build_options_default();
    let (a, b) = (c_mesh(&rest_a, &options)?, c_mesh(&rest_b, &options)?);
    let pairs = dvh_pairs_new();
    let (mut pa, mut pb) = (rest_a.positions.clone(), rest_b.positions.clone());
    let (mut shadow_a, mut shadow_b) = (
        Mesh::new(&pa, &rest_a.triangles, &BuildOptions::default())?,
        Mesh::new(&pb, &rest_b.triangles, &BuildOptions::default())?,
    );
    let mut memory = Memory {
        start: memory_kib().0,
        warm: 0,
        end: 0,
        peak: 0,
    };
    let (mut checks, mut found) = (0, [0usize; 3]);
    let started = Instant::now();
    for frame in 0..frames {
        let t = frame as f64 / 200.0;
        morph_a.apply(&rest_a.positions, t, &mut pa);
        morph_b.apply(&rest_b.positions, t * 1.3, &mut pb);
        jitter(&mut pa, rng, 0.002);
        jitter(&mut pb, rng, 0.002);
        let pose = random_pose(rng, [0.4, 0.0, 0.0], 0.1);
        let mut query = dvh_query_options_default();
        let check = frame % check_every == check_every - 1 || frame + 1 == frames;
        if !check {
            query.mode = (frame % 5) as u32;
            query.max_depth = 3;
            query.budget = 200;
        }
        let mut stats = DvhQueryStats::default();
        // SAFETY: live handles, arrays of the meshes' vertex counts, one thread.
        unsafe {
            ok(
                dvh_mesh_refit(a, pa.as_ptr(), rest_a.vertex_count()),
                "dvh_mesh_refit a",
            )?;
            ok(
                dvh_mesh_refit(b, pb.as_ptr(), rest_b.vertex_count()),
                "dvh_mesh_refit b",
            )?;
            let cp = c_pose(&pose);
            ok(
                dvh_collide(a, std::ptr::null(), b, &cp, &query, pairs, &mut stats),
                "dvh_collide",
            )?;
            let hits = pairs_of(pairs);
            ok(
                dvh_self_collide(a, &query, pairs, &mut stats),
                "dvh_self_collide",
            )?;
            let self_hits = pairs_of(pairs);
            let d = 0.01;
            ok(
                dvh_proximity(a, std::ptr::null(), b, &cp, d, &query, pairs, &mut stats),
                "dvh_proximity",
            )?;
            let near = pairs_of(pairs);
            if check {
                shadow_a.refit(&pa)?;
                shadow_b.refit(&pb)?;
                let expected = brute_force(&shadow_a, None, &shadow_b, Some(&pose));
                same(frame, "collide", &hits, &expected)?;
                let expected_self = self_collide_brute_force(&shadow_a);
                same(frame, "self", &self_hits, &expected_self)?;
                let expected_near =
                    proximity_brute_force(&shadow_a, None, &shadow_b, Some(&pose), d);
                same(frame, "proximity", &near, &expected_near)?;
                checks += 1;
                found[0] += hits.len();
                found[1] += self_hits.len();
                found[2] += near.len();
            }
        }
        if frame + 1 == frames.div_ceil(10) {
            memory.warm = memory_kib().0;
        }
    }
    (memory.end, memory.peak) = memory_kib();
    println!(
        "mesh pair ({} and {} triangles): {frames} frames in {:.1} s, {checks} frames checked against brute force ({} pairs, {} self pairs, {} near pairs in all), all equal",
        rest_a.triangle_count(),
        rest_b.triangle_count(),
        started.elapsed().as_secs_f64(),
        found[0],
        found[1],
        found[2]
    );
    // SAFETY: live handles, released once.
    unsafe {
        dvh_pairs_free(pairs);
        dvh_mesh_free(a);
        dvh_mesh_free(b);
    }
    memory.check("mesh pair")
}

/// One scene object as the soak moves it.
struct Object {
    shape: usize,
    rigid: bool,
    centre: [f64; 3],
    velocity: [f64; 3],
    group: u32,
    mask: u32,
}

fn scene(frames: usize, count: usize, check_every: usize, rng: &mut Rng) -> Result<(), Failure> {
    let mut shapes = [icosphere(1), torus(0.3, 0.1, 12, 6), grid(4, 0.7)];
    shapes[0].scale(0.35);
    let morphs: Vec<Morph> = shapes
        .iter()
        .enumerate()
        .map(|(i, s)| Morph::random(s, 2, 0.1, i as u64))
        .collect();
    let options = dvh_build_options_default();
    let meshes = shapes
        .iter()
        .map(|s| c_mesh(s, &options))
        .collect::<Result<Vec<_>, _>>()?;
    let shadows = shapes
        .iter()
        .map(|s| Mesh::new(&s.positions, &s.triangles, &BuildOptions::default()))
        .collect::<Result<Vec<_>, _>>()?;
    let mut scene = std::ptr::null_mut();
    // SAFETY: a writable out-parameter.
    ok(unsafe { dvh_scene_create(&mut scene) }, "dvh_scene_create")?;
    let contacts = dvh_contacts_new();
    // The box the objects move in: about 4 objects across per unit of side at 100 objects.
    let side = (count as f64).cbrt() * 0.9;
    let mut objects: BTreeMap<u32, Object> = BTreeMap::new();
    let mut excluded: HashSet<(u32, u32)> = HashSet::new();
    let add = |objects: &mut BTreeMap<u32, Object>,
               rng: &mut Rng,
               i: usize|
     -> Result<(), Failure> {
        let shape = i % shapes.len();
        let rigid = i.is_multiple_of(2);
        let (group, mask) = if i % 10 == 3 { (2, 1) } else { (1, u32::MAX) };
        let mut id = 0;
        // SAFETY: live handles, a writable out-parameter.
        let status = unsafe {
            if rigid {
                dvh_scene_add_rigid(scene, meshes[shape], std::ptr::null(), group, mask, &mut id)
            } else {
                dvh_scene_add_deformable(scene, meshes[shape], group, mask, &mut id)
            }
        };
        ok(status, "dvh_scene_add")?;
        let centre = [0; 3].map(|_| rng.range(0.0, side));
        let velocity = [0; 3].map(|_| rng.range(-0.01, 0.01));
        objects.insert(
            id,
            Object {
                shape,
                rigid,
                centre,
                velocity,
                group,
                mask,
            },
        );
        Ok(())
    };
    for i in 0..count {
        add(&mut objects, rng, i)?;
    }
    let mut memory = Memory {
        start: memory_kib().0,
        warm: 0,
        end: 0,
        peak: 0,
    };
    let mut poses: BTreeMap<u32, Option<Pose>> = BTreeMap::new();
    let mut world: BTreeMap<u32, Vec<f64>> = BTreeMap::new();
    let (mut checks, mut found, mut removed) = (0, 0usize, 0);
    let started = Instant::now();
    for frame in 0..frames {
        // Every 50 frames an object leaves and another comes (ids are reused).
        if frame % 50 == 49 {
            let ids: Vec<u32> = objects.keys().copied().collect();
            let gone = ids[rng.below(ids.len() as u64) as usize];
            // SAFETY: a live scene.
            ok(unsafe { dvh_scene_remove(scene, gone) }, "dvh_scene_remove")?;
            objects.remove(&gone);
            excluded.retain(|&(x, y)| x != gone && y != gone);
            add(&mut objects, rng, frame)?;
            removed += 1;
        }
        if frame % 100 == 0 {
            let ids: Vec<u32> = objects.keys().copied().collect();
            let (x, y) = (
                ids[rng.below(ids.len() as u64) as usize],
                ids[rng.below(ids.len() as u64) as usize],
            );
            if x != y {
                // SAFETY: a live scene.
                ok(
                    unsafe { dvh_scene_exclude_pair(scene, x, y) },
                    "dvh_scene_exclude_pair",
                )?;
                excluded.insert((x.min(y), x.max(y)));
            }
        }
        if frame % 1000 == 0 {
            // SAFETY: a live scene.
            ok(
                unsafe { dvh_scene_set_lazy_refit(scene, frame % 2000 == 0) },
                "dvh_scene_set_lazy_refit",
            )?;
        }
        let t = frame as f64 / 100.0;
        for (&id, o) in objects.iter_mut() {
            for k in 0..3 {
                o.centre[k] += o.velocity[k];
                if o.centre[k] < 0.0 || o.centre[k] > side {
                    o.velocity[k] = -o.velocity[k];
                }
            }
            if o.rigid {
                let pose = random_pose(rng, o.centre, 0.0);
                // SAFETY: a live scene, a readable pose.
                ok(
                    unsafe { dvh_scene_set_pose(scene, id, &c_pose(&pose)) },
                    "dvh_scene_set_pose",
                )?;
                poses.insert(id, Some(pose));
            } else {
                let rest = &shapes[o.shape].positions;
                let mut p = vec![0.0; rest.len()];
                morphs[o.shape].apply(rest, t + f64::from(id) * 0.1, &mut p);
                jitter(&mut p, rng, 0.001);
                for v in p.chunks_mut(3) {
                    for (x, c) in v.iter_mut().zip(o.centre) {
                        *x += c;
                    }
                }
                // SAFETY: a live scene, as many vertices as the object's mesh.
                ok(
                    unsafe { dvh_scene_set_positions(scene, id, p.as_ptr(), p.len() / 3) },
                    "dvh_scene_set_positions",
                )?;
                poses.insert(id, None);
                world.insert(id, p);
            }
        }
        poses.retain(|id, _| objects.contains_key(id));
        world.retain(|id, _| objects.contains_key(id));
        let check = frame % check_every == check_every - 1 || frame + 1 == frames;
        let mut query = dvh_query_options_default();
        if !check {
            query.mode = [
                DVH_QUERY_MODE_TRIANGLES,
                DVH_QUERY_MODE_FIRST_HIT,
                DVH_QUERY_MODE_LEAVES,
            ][frame % 3];
        }
        let mut stats = DvhSceneStats::default();
        // SAFETY: live handles.
        ok(
            unsafe { dvh_scene_collide(scene, &query, contacts, &mut stats) },
            "dvh_scene_collide",
        )?;
        if check {
            // SAFETY: a live buffer.
            let got: Vec<(u32, u32, u32, u32)> = unsafe {
                let (n, data) = (dvh_contacts_len(contacts), dvh_contacts_data(contacts));
                (0..n)
                    .map(|i| {
                        let c = &*data.add(i);
                        (c.object_a, c.object_b, c.a, c.b)
                    })
                    .collect()
            };
            // Each object's geometry for brute force: the rigid ones' meshes at rest with their
            // poses, the deformable ones' world positions.
            let geometry: BTreeMap<u32, (Mesh, Option<Pose>)> = objects
                .iter()
                .map(|(&id, o)| {
                    let mut m = shadows[o.shape].clone();
                    if let Some(p) = world.get(&id) {
                        m.refit(p).expect("finite");
                    }
                    (id, (m, poses[&id]))
                })
                .collect();
            let mut expected = Vec::new();
            for (&i, oi) in &objects {
                for (&j, oj) in objects.range(i + 1..) {
                    if oi.group & oj.mask == 0
                        || oj.group & oi.mask == 0
                        || excluded.contains(&(i, j))
                    {
                        continue;
                    }
                    let ((mi, pi), (mj, pj)) = (&geometry[&i], &geometry[&j]);
                    expected.extend(
                        brute_force(mi, pi.as_ref(), mj, pj.as_ref())
                            .into_iter()
                            .map(|p| (i, j, p.a, p.b)),
                    );
                }
            }
            same(frame, "scene", &got, &expected)?;
            checks += 1;
            found += got.len();
        }
        if frame + 1 == frames.div_ceil(10) {
            memory.warm = memory_kib().0;
        }
    }
    (memory.end, memory.peak) = memory_kib();
    println!(
        "scene ({count} objects, half rigid; {removed} removed and replaced): {frames} frames in {:.1} s, {checks} frames checked against brute force ({found} contacts in all), all equal",
        started.elapsed().as_secs_f64()
    );
    // SAFETY: live handles, released once.
    unsafe {
        dvh_contacts_free(contacts);
        dvh_scene_free(scene);
        for m in meshes {
            dvh_mesh_free(m);
        }
    }
    memory.check("scene")
}

fn big(triangles: usize) -> Result<(), Failure> {
    let n = ((triangles as f64 / 2.0).sqrt().ceil() as usize).max(1);
    let mut sheet = grid(n, 1.0);
    let ripple = |x: f64, y: f64| 0.01 * (40.0 * x).sin() * (30.0 * y).cos();
    let started = Instant::now();
    let mesh = c_mesh(&sheet, &dvh_build_options_default())?;
    let built = started.elapsed().as_secs_f64();
    for v in sheet.positions.chunks_mut(3) {
        v[2] = ripple(v[0], v[1]);
    }
    let started = Instant::now();
    // SAFETY: a live mesh, its vertex count.
    ok(
        unsafe { dvh_mesh_refit(mesh, sheet.positions.as_ptr(), sheet.vertex_count()) },
        "dvh_mesh_refit",
    )?;
    let refit = started.elapsed().as_secs_f64();
    // A small sphere through the sheet's middle.
    let mut ball = icosphere(3);
    ball.scale(0.02);
    ball.translate([0.5, 0.5, ripple(0.5, 0.5)]);
    let small = c_mesh(&ball, &dvh_build_options_default())?;
    let pairs = dvh_pairs_new();
    let mut stats = DvhQueryStats::default();
    let query = dvh_query_options_default();
    let started = Instant::now();
    // SAFETY: live handles.
    ok(
        unsafe {
            dvh_collide(
                mesh,
                std::ptr::null(),
                small,
                std::ptr::null(),
                &query,
                pairs,
                &mut stats,
            )
        },
        "dvh_collide",
    )?;
    let collide = started.elapsed().as_secs_f64();
    let got = pairs_of(pairs);
    // Every sheet triangle whose box meets the ball's, against every ball triangle.
    let corner = |m: &MeshData, t: usize, k: usize| {
        let v = m.triangles[3 * t + k] as usize;
        [
            m.positions[3 * v],
            m.positions[3 * v + 1],
            m.positions[3 * v + 2],
        ]
    };
    let bounds = ball.bounds();
    let mut expected = Vec::new();
    for s in 0..sheet.triangle_count() {
        let ts = [0, 1, 2].map(|k| corner(&sheet, s, k));
        let near = (0..3).all(|k| {
            let lo = ts.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
            let hi = ts.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
            lo <= bounds.hi[k] && hi >= bounds.lo[k]
        });
        if near {
            for b in 0..ball.triangle_count() {
                if triangles_intersect(&ts, &[0, 1, 2].map(|k| corner(&ball, b, k))) {
                    expected.push(Pair {
                        a: s as u32,
                        b: b as u32,
                    });
                }
            }
        }
    }
    expected.sort_unstable();
    if got != expected || got.is_empty() {
        return Err(format!(
            "big mesh: {} pairs, the direct test {}",
            got.len(),
            expected.len()
        )
        .into());
    }
    // Self-collision twice: the first query on a mesh finds its patches; the second, after a
    // refit (the ripple moved), only redoes what depends on the positions.
    let mut self_times = [0.0; 2];
    for (round, time) in self_times.iter_mut().enumerate() {
        if round == 1 {
            for v in sheet.positions.chunks_mut(3) {
                v[2] = ripple(v[0] + 0.01, v[1]);
            }
            // SAFETY: a live mesh, its vertex count.
            let status =
                unsafe { dvh_mesh_refit(mesh, sheet.positions.as_ptr(), sheet.vertex_count()) };
            ok(status, "dvh_mesh_refit")?;
        }
        let started = Instant::now();
        // SAFETY: live handles.
        let status = unsafe { dvh_self_collide(mesh, &query, pairs, &mut stats) };
        ok(status, "dvh_self_collide")?;
        *time = started.elapsed().as_secs_f64();
        // SAFETY: a live buffer.
        let self_pairs = unsafe { dvh_pairs_len(pairs) };
        if self_pairs != 0 {
            let message = format!("big mesh: a height field reported {self_pairs} self-collisions");
            return Err(message.into());
        }
    }
    println!(
        "big mesh ({} triangles): built in {built:.1} s, refit in {refit:.2} s, a query with {} pairs in {collide:.3} s (equal to the direct test), self-collision (none) in {:.1} s (first query), {:.1} s (after a refit); peak resident memory {} MiB",
        sheet.triangle_count(),
        got.len(),
        self_times[0],
        self_times[1],
        memory_kib().1 / 1024
    );
    // SAFETY: live handles, released once.
    unsafe {
        dvh_pairs_free(pairs);
        dvh_mesh_free(small);
        dvh_mesh_free(mesh);
    }
    Ok(())
}

fn main() -> Result<(), Failure> {
    let frames = arg("--frames", 10_000)?;
    let objects = arg("--objects", 100)?.max(2);
    let check_every = arg("--check-every", 500)?.max(1);
    let triangles = arg("--big", 10_000_000)?;
    let mut rng = Rng::new(12);
    mesh_pair(frames, check_every, &mut rng)?;
    scene(frames, objects, check_every, &mut rng)?;
    if triangles > 0 {
        big(triangles)?;
    }
    println!("soak passed");
    Ok(())
}
