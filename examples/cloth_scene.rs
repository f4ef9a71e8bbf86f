//! A cloth simulation kept free of intersections by a dvh scene alone.
//!
//! A square cloth falls onto a rigid paddle that turns about the vertical axis and onto a soft
//! pillow that breathes (a deformable object whose shape is scripted), drapes over both, slides
//! off and folds onto itself on the floor. The scene holds four objects: the floor, the paddle
//! (rigid, given a start and an end pose each step), the pillow (deformable, given a motion each
//! step) and the cloth (deformable, self-contact on). The obstacles are tested only against the
//! cloth (groups and masks); the cloth against everything, itself included.
//!
//! Each step:
//! 1. **Predict** (position-based dynamics, Müller et al. 2007): gravity, then Jacobi passes over
//!    stretch and bending constraints.
//! 2. **Repel** (the stencils): `Scene::nearest_features` at the cloth's thickness at the
//!    predicted positions; every stencil closer than the thickness is pushed apart to it along
//!    the line between its closest points, the move shared over the cloth corners by their
//!    barycentric weights (an obstacle does not give way). A few rounds, interleaved with the
//!    constraints.
//! 3. **Cut** (continuous collision): `Scene::continuous_collide` with `earliest_only`, the
//!    cloth moving from its last positions to the predicted ones while the paddle turns and the
//!    pillow breathes through their own steps; when an impact comes before the end, the cloth's
//!    motion is cut to 80% of the time of impact (a line search), and asked again until the
//!    motion is free; if the cut gets very small, the corners of the impacting primitives stay
//!    where they were instead.
//! 4. **Check**: `Scene::collide` (self-contact on) must find no intersecting triangle pair.
//!
//! Contact is friction-free; the cloth's velocity is the position change over the step.
//!
//! `cargo run --release --example cloth_scene [-- --cells N] [--steps K] [--out DIR]`
//!
//! Writes DIR/frame_NNNN.obj (every tenth step, the cloth and the obstacles) and DIR/cloth.svg
//! (the cloth seen from the side at a few steps, and per step the least distance of the cloth to
//! anything and the number of stencils); prints the time per step spent in the scene's queries
//! and in the rest. The default output directory is `target/cloth_scene`.

use dvh::{
    BuildOptions, CcdOptions, ImpactKind, Mesh, Pose, QueryOptions, Scene, SceneImpacts,
    SceneNearPairs,
};
use nalgebra::{Isometry3, Vector3};
use std::fmt::Write as _;
use std::time::Instant;

/// A simulation's settings.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Cells along each side of the cloth (two triangles each).
    pub cells: usize,
    /// Steps to simulate.
    pub steps: usize,
    /// Threads for the scene's queries (0: every core).
    pub threads: u32,
    /// Where to write frames and the picture (`None`: nowhere).
    pub out: Option<std::path::PathBuf>,
    /// Keep every step's positions in the report (the cloth's, and the obstacles' triangles).
    pub keep_frames: bool,
    /// Cut each step's motion at impacts (turned off only to show that the checks fail
    /// without it).
    pub cut: bool,
}

/// What happened: per step, the least distance from the cloth to anything (itself included) at
/// the end of the step, the stencils found, whether the motion was cut, and the time spent.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Triangles of the cloth.
    pub triangles: usize,
    /// The cloth's thickness: the distance the stencils keep.
    pub thickness: f64,
    /// Per step: the least distance of a stencil at the end of the step (infinity when none
    /// is within the thickness).
    pub least_distance: Vec<f64>,
    /// Per step: the stencils found on the predicted positions (first round).
    pub stencils: Vec<usize>,
    /// Per step: the fraction of the cloth's motion kept by the line search (1: uncut).
    pub kept: Vec<f64>,
    /// Per step: intersecting triangle pairs found by the check (all zero when all is well).
    pub intersecting: Vec<usize>,
    /// Steps where the cut fell back to holding the impacting corners.
    pub held: usize,
    /// Seconds spent in the scene's queries and setters, and in the rest.
    pub collision_seconds: f64,
    /// Of those, in the stencils of the repel rounds.
    pub stencil_seconds: f64,
    /// Of those, in continuous collision (the motions set for it included).
    pub ccd_seconds: f64,
    /// Of those, in the end-of-step check (the exact discrete query and the least distance).
    pub check_seconds: f64,
    /// Seconds spent in the dynamics (prediction, constraints, pushes).
    pub dynamics_seconds: f64,
    /// The cloth's positions after each step (with `keep_frames` or an output directory).
    pub frames: Vec<Vec<[f64; 3]>>,
    /// The obstacles' triangles in world coordinates after each step (with `keep_frames`).
    pub obstacle_frames: Vec<Vec<[[f64; 3]; 3]>>,
    /// The cloth's triangles.
    pub cloth_triangles: Vec<[u32; 3]>,
}

const GRAVITY: f64 = -9.81;
const DT: f64 = 1.0 / 100.0;
const ITERATIONS: usize = 10;
const CONTACT_ROUNDS: usize = 3;
const FLOOR: f64 = -0.3;

/// A grid of `cells` × `cells` quads, `size` wide, flat at height `z`: positions and triangles.
fn grid(cells: usize, size: f64, z: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let n = cells + 1;
    let mut p = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f64 / cells as f64, j as f64 / cells as f64);
            // A slight tilt, so that the cloth slides off to one side and folds as it lands.
            p.push([
                (x - 0.5) * size,
                (y - 0.5) * size,
                z + 0.08 * (x - 0.5) * size,
            ]);
        }
    }
    let mut t = Vec::with_capacity(2 * cells * cells);
    for j in 0..cells {
        for i in 0..cells {
            let a = (j * n + i) as u32;
            let (b, c, d) = (a + 1, a + n as u32 + 1, a + n as u32);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    (p, t)
}

/// A closed box of half-sizes `h`, centred at the origin: 8 corners, 12 triangles.
fn cuboid(h: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let p = (0..8)
        .map(|k| [0, 1, 2].map(|a| if k >> a & 1 == 1 { h[a] } else { -h[a] }))
        .collect();
    let t = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    (p, t)
}

/// A UV sphere of radius 1 with `rings` rings and `2 rings` segments, closed at the poles.
fn sphere(rings: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let segments = 2 * rings;
    let mut p = vec![[0.0, 0.0, 1.0]];
    for r in 1..rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = std::f64::consts::TAU * s as f64 / segments as f64;
            p.push([
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ]);
        }
    }
    p.push([0.0, 0.0, -1.0]);
    let at = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
    let last = (p.len() - 1) as u32;
    let mut t = Vec::new();
    for s in 0..segments {
        t.push([0, at(1, s), at(1, s + 1)]);
        for r in 1..rings - 1 {
            t.push([at(r, s), at(r + 1, s), at(r + 1, s + 1)]);
            t.push([at(r, s), at(r + 1, s + 1), at(r, s + 1)]);
        }
        t.push([at(rings - 1, s), last, at(rings - 1, s + 1)]);
    }
    (p, t)
}

fn flat(p: &[[f64; 3]]) -> &[f64] {
    p.as_flattened()
}

fn tri_flat(t: &[[u32; 3]]) -> &[u32] {
    t.as_flattened()
}

/// The paddle's placement at time `t`: turning about the vertical axis through its centre.
fn paddle_iso(t: f64) -> Isometry3<f64> {
    Isometry3::new(
        Vector3::new(-0.12, 0.0, -0.12),
        Vector3::new(0.0, 0.0, 0.8 * t),
    )
}

/// [`paddle_iso`] as a pose.
fn paddle_pose(t: f64) -> Pose {
    Pose::from_isometry(&paddle_iso(t)).expect("a rotation and a small translation")
}

/// The pillow at time `t`: a squashed sphere on the floor, breathing.
fn pillow_at(rest: &[[f64; 3]], t: f64, out: &mut [[f64; 3]]) {
    let s = 1.0 + 0.15 * (4.0 * t).sin();
    for (o, p) in out.iter_mut().zip(rest) {
        *o = [
            0.3 + 0.16 * s * p[0],
            0.1 + 0.16 * s * p[1],
            FLOOR + 0.1 * s * (p[2] + 1.0),
        ];
    }
}

/// A distance constraint: two vertices and their rest length.
type Length = (u32, u32, f64);

/// Distance constraints: every grid edge and diagonal (stretch), and vertices two apart along a
/// row or a column (bending), with their rest lengths.
fn constraints(cells: usize, p: &[[f64; 3]]) -> (Vec<Length>, Vec<Length>) {
    let n = cells + 1;
    let id = |i: usize, j: usize| (j * n + i) as u32;
    let length = |a: u32, b: u32| dist(&p[a as usize], &p[b as usize]);
    let mut stretch = Vec::new();
    let mut bend = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let add = |list: &mut Vec<_>, b: u32| list.push((id(i, j), b, length(id(i, j), b)));
            if i + 1 < n {
                add(&mut stretch, id(i + 1, j));
            }
            if j + 1 < n {
                add(&mut stretch, id(i, j + 1));
            }
            if i + 1 < n && j + 1 < n {
                add(&mut stretch, id(i + 1, j + 1));
            }
            if i + 2 < n {
                add(&mut bend, id(i + 2, j));
            }
            if j + 2 < n {
                add(&mut bend, id(i, j + 2));
            }
        }
    }
    (stretch, bend)
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// One Jacobi pass over distance constraints, each vertex's corrections averaged.
fn project_lengths(
    p: &mut [[f64; 3]],
    list: &[Length],
    stiffness: f64,
    delta: &mut [[f64; 3]],
    count: &mut [f64],
) {
    delta.fill([0.0; 3]);
    count.fill(0.0);
    for &(a, b, rest) in list {
        let (a, b) = (a as usize, b as usize);
        let d = [0, 1, 2].map(|k| p[b][k] - p[a][k]);
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if l < 1e-12 {
            continue;
        }
        let c = 0.5 * stiffness * (l - rest) / l;
        for k in 0..3 {
            delta[a][k] += c * d[k];
            delta[b][k] -= c * d[k];
        }
        count[a] += 1.0;
        count[b] += 1.0;
    }
    for (x, (d, &n)) in p.iter_mut().zip(delta.iter().zip(count.iter())) {
        if n > 0.0 {
            for k in 0..3 {
                x[k] += d[k] / n;
            }
        }
    }
}

/// The cloth's corners of one side of a stencil or an impact, with their weights (`kind`,
/// the side's indices, whether this side is the first).
fn corners(
    kind: ImpactKind,
    first: bool,
    i0: u32,
    i1: u32,
    tris: &[[u32; 3]],
    w: [f64; 3],
) -> [(u32, f64); 3] {
    let triangle = |t: u32| {
        let c = tris[t as usize];
        [(c[0], w[0]), (c[1], w[1]), (c[2], w[2])]
    };
    match (kind, first) {
        (ImpactKind::VertexFace, true) | (ImpactKind::FaceVertex, false) => {
            [(i0, 1.0), (i0, 0.0), (i0, 0.0)]
        }
        (ImpactKind::VertexFace, false) | (ImpactKind::FaceVertex, true) => triangle(i0),
        (ImpactKind::EdgeEdge, _) => [(i0, w[0]), (i1, w[1]), (i1, 0.0)],
    }
}

/// Runs the simulation.
pub fn simulate(settings: &Settings) -> Result<Report, Box<dyn std::error::Error>> {
    let opts = BuildOptions::default();
    let (mut cloth_p, cloth_t) = grid(settings.cells, 1.0, 0.25);
    let edge = 1.0 / settings.cells as f64;
    let thickness = 0.25 * edge;
    let (stretch, bend) = constraints(settings.cells, &cloth_p);
    let (floor_p, floor_t) = (
        vec![
            [-3.0, -3.0, FLOOR],
            [3.0, -3.0, FLOOR],
            [3.0, 3.0, FLOOR],
            [-3.0, 3.0, FLOOR],
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    let (paddle_p, paddle_t) = cuboid([0.3, 0.05, 0.05]);
    let (pillow_rest, pillow_t) = sphere(10);
    let mut pillow_p = pillow_rest.clone();
    pillow_at(&pillow_rest, 0.0, &mut pillow_p);

    // Obstacles (group 1) meet only the cloth (group 2); the cloth meets everything.
    let (obstacle, cloth_group) = (1, 2);
    let mut scene = Scene::new();
    let floor_mesh = Mesh::new(flat(&floor_p), tri_flat(&floor_t), &opts)?;
    let floor = scene.add_rigid(&floor_mesh, None, obstacle, cloth_group)?;
    let paddle_mesh = Mesh::new(flat(&paddle_p), tri_flat(&paddle_t), &opts)?;
    let paddle = scene.add_rigid(&paddle_mesh, Some(&paddle_pose(0.0)), obstacle, cloth_group)?;
    let pillow_mesh = Mesh::new(flat(&pillow_p), tri_flat(&pillow_t), &opts)?;
    let pillow = scene.add_deformable(&pillow_mesh, obstacle, cloth_group)?;
    let cloth_mesh = Mesh::new(flat(&cloth_p), tri_flat(&cloth_t), &opts)?;
    let cloth = scene.add_deformable(&cloth_mesh, cloth_group, obstacle | cloth_group)?;
    scene.set_self_contact(cloth, true)?;
    let _ = floor;

    let n = cloth_p.len();
    let mut vel = vec![[0.0; 3]; n];
    let mut pred = cloth_p.clone();
    let (mut delta, mut count) = (vec![[0.0; 3]; n], vec![0.0; n]);
    let mut pillow_next = pillow_p.clone();
    let mut near = SceneNearPairs::new();
    let mut impacts = SceneImpacts::new();
    let mut contacts = dvh::Contacts::new();
    let query = QueryOptions::default().with_threads(settings.threads);
    let every = CcdOptions::default().with_threads(settings.threads);
    let earliest = every.with_earliest_only(true);
    let mut report = Report {
        triangles: cloth_t.len(),
        thickness,
        cloth_triangles: cloth_t.clone(),
        ..Report::default()
    };
    for step in 0..settings.steps {
        let (t0, t1) = (step as f64 * DT, (step + 1) as f64 * DT);
        // The obstacles' steps.
        let clock = Instant::now();
        scene.set_pose_motion(paddle, Some(&paddle_pose(t0)), Some(&paddle_pose(t1)))?;
        pillow_at(&pillow_rest, t1, &mut pillow_next);
        scene.set_motion(pillow, flat(&pillow_p), flat(&pillow_next))?;
        report.ccd_seconds += clock.elapsed().as_secs_f64();
        report.collision_seconds += clock.elapsed().as_secs_f64();

        // 1. Predict.
        let clock = Instant::now();
        for (q, (x, v)) in pred.iter_mut().zip(cloth_p.iter().zip(vel.iter_mut())) {
            v[2] += GRAVITY * DT;
            *q = [x[0] + v[0] * DT, x[1] + v[1] * DT, x[2] + v[2] * DT];
        }
        report.dynamics_seconds += clock.elapsed().as_secs_f64();
        for _ in 0..ITERATIONS - CONTACT_ROUNDS {
            project_lengths(&mut pred, &stretch, 1.0, &mut delta, &mut count);
            project_lengths(&mut pred, &bend, 0.1, &mut delta, &mut count);
        }
        report.dynamics_seconds += clock.elapsed().as_secs_f64();
        let mut kept = 1.0;
        let mut rounds = 0;
        loop {
            // 2. Repel: rounds of the stencils at the predicted positions, each after a pass
            // over the constraints.
            for round in 0..CONTACT_ROUNDS {
                let clock = Instant::now();
                project_lengths(&mut pred, &stretch, 1.0, &mut delta, &mut count);
                project_lengths(&mut pred, &bend, 0.1, &mut delta, &mut count);
                report.dynamics_seconds += clock.elapsed().as_secs_f64();
                let clock = Instant::now();
                scene.set_positions(cloth, flat(&pred))?;
                scene.nearest_features(thickness, &query, &mut near)?;
                report.stencil_seconds += clock.elapsed().as_secs_f64();
                report.collision_seconds += clock.elapsed().as_secs_f64();
                if round == 0 && rounds == 0 {
                    report.stencils.push(near.len());
                }
                let clock = Instant::now();
                push_apart(
                    &mut pred, &near, cloth, &cloth_t, thickness, &mut delta, &mut count,
                );
                report.dynamics_seconds += clock.elapsed().as_secs_f64();
            }
            // 3. Cut: the earliest impact of the whole scene over the step.
            let clock = Instant::now();
            scene.set_motion(cloth, flat(&cloth_p), flat(&pred))?;
            let stats = scene.continuous_collide(&earliest, &mut impacts)?;
            report.ccd_seconds += clock.elapsed().as_secs_f64();
            report.collision_seconds += clock.elapsed().as_secs_f64();
            if impacts.is_empty() || !settings.cut {
                break;
            }
            rounds += 1;
            let toi = stats.earliest_toi;
            if std::env::var_os("CLOTH_DEBUG").is_some() {
                let x = impacts.as_slice()[0];
                eprintln!(
                    "step {step} round {rounds}: impact {:?} objects {} {} toi {toi:.4}",
                    x.impact.kind, x.object_a, x.object_b
                );
            }
            let x = impacts.as_slice()[0];
            let against_cloth = x.object_a == cloth && x.object_b == cloth;
            if against_cloth && toi > 1e-3 && rounds < 8 {
                // The cloth against itself: a line search, the cloth going 80% of the way to
                // the impact; the next round repels again from there.
                let alpha = 0.8 * toi;
                for (q, x) in pred.iter_mut().zip(&cloth_p) {
                    *q = [0, 1, 2].map(|k| x[k] + alpha * (q[k] - x[k]));
                }
                kept *= alpha;
            } else {
                // Every impact of the step: the cloth corners of each move as its obstacle does
                // over the step (an obstacle keeps its path whatever the cloth does), or stay
                // where they were against the cloth itself (once the cut got too small) and
                // against the floor.
                scene.continuous_collide(&every, &mut impacts)?;
                for x in impacts.iter() {
                    let i = x.impact;
                    let obstacle = [x.object_a, x.object_b].into_iter().find(|&o| o != cloth);
                    let (mut moved, mut n) = ([0.0; 3], 0.0);
                    if obstacle == Some(pillow) {
                        let (first, i0, i1) = if x.object_a == pillow {
                            (true, i.a0, i.a1)
                        } else {
                            (false, i.b0, i.b1)
                        };
                        for (v, w) in corners(i.kind, first, i0, i1, &pillow_t, [1.0; 3]) {
                            if w > 0.0 {
                                for k in 0..3 {
                                    moved[k] +=
                                        pillow_next[v as usize][k] - pillow_p[v as usize][k];
                                }
                                n += 1.0;
                            }
                        }
                    }
                    let carry = |p: &[f64; 3]| -> [f64; 3] {
                        match obstacle {
                            Some(o) if o == paddle => {
                                let local = paddle_iso(t0).inverse_transform_point(&(*p).into());
                                let q = paddle_iso(t1).transform_point(&local);
                                [q.x, q.y, q.z]
                            }
                            Some(o) if o == pillow => [0, 1, 2].map(|k| p[k] + moved[k] / n),
                            _ => *p,
                        }
                    };
                    for (first, object, i0, i1) in [
                        (true, x.object_a, i.a0, i.a1),
                        (false, x.object_b, i.b0, i.b1),
                    ] {
                        if object != cloth {
                            continue;
                        }
                        for (v, w) in corners(i.kind, first, i0, i1, &cloth_t, [1.0; 3]) {
                            if w > 0.0 {
                                pred[v as usize] = carry(&cloth_p[v as usize]);
                            }
                        }
                    }
                    report.held += 1;
                }
                if rounds > 64 {
                    // Give up on this step (the check below reports what is left).
                    break;
                }
            }
        }
        report.kept.push(kept);
        let clock = Instant::now();
        for ((v, x), q) in vel.iter_mut().zip(cloth_p.iter_mut()).zip(&pred) {
            *v = [0, 1, 2].map(|k| (q[k] - x[k]) / DT * 0.995);
            *x = *q;
        }
        pillow_p.copy_from_slice(&pillow_next);
        report.dynamics_seconds += clock.elapsed().as_secs_f64();

        // 4. Check: nothing intersects at the end of the step.
        let clock = Instant::now();
        scene.set_positions(cloth, flat(&cloth_p))?;
        scene.collide(&query, &mut contacts)?;
        report.intersecting.push(contacts.len());
        if std::env::var_os("CLOTH_DEBUG").is_some() && !contacts.is_empty() {
            let mut by: std::collections::BTreeMap<(u32, u32), usize> = Default::default();
            for c in &contacts {
                *by.entry((c.object_a, c.object_b)).or_default() += 1;
            }
            eprintln!("step {step}: kept {kept:.3}, rounds {rounds}, contacts {by:?}");
        }
        scene.nearest_features(thickness, &query, &mut near)?;
        report.check_seconds += clock.elapsed().as_secs_f64();
        report.collision_seconds += clock.elapsed().as_secs_f64();
        let least = near
            .iter()
            .map(|s| s.pair.distance)
            .fold(f64::INFINITY, f64::min);
        report.least_distance.push(least);
        if settings.out.is_some() || settings.keep_frames {
            report.frames.push(cloth_p.clone());
        }
        if settings.keep_frames {
            let pose = paddle_pose(t1);
            let paddle_w: Vec<[f64; 3]> =
                paddle_p.iter().map(|p| pose.transform_point(p)).collect();
            let mut tris = Vec::new();
            for (p, t) in [
                (&floor_p[..], &floor_t[..]),
                (&paddle_w[..], &paddle_t[..]),
                (&pillow_p[..], &pillow_t[..]),
            ] {
                tris.extend(t.iter().map(|c| c.map(|v| p[v as usize])));
            }
            report.obstacle_frames.push(tris);
        }
    }
    if let Some(dir) = &settings.out {
        write_outputs(dir, &report, &paddle_p, &paddle_t, &pillow_rest, &pillow_t)?;
    }
    Ok(report)
}

/// One projection of every stencil closer than `thickness`: its closest points moved apart to
/// the thickness, the move shared over the cloth's corners by their weights (an obstacle's side
/// does not move, so the cloth's side takes the whole move).
fn push_apart(
    p: &mut [[f64; 3]],
    near: &SceneNearPairs,
    cloth: u32,
    tris: &[[u32; 3]],
    thickness: f64,
    delta: &mut [[f64; 3]],
    count: &mut [f64],
) {
    delta.fill([0.0; 3]);
    count.fill(0.0);
    for s in near {
        let pair = &s.pair;
        let d = pair.distance;
        if !(d > 1e-12 && d < thickness) {
            continue;
        }
        let normal = [0, 1, 2].map(|k| (pair.closest_a[k] - pair.closest_b[k]) / d);
        let sides = [
            (
                s.object_a == cloth,
                true,
                pair.a0,
                pair.a1,
                pair.weights_a,
                1.0,
            ),
            (
                s.object_b == cloth,
                false,
                pair.b0,
                pair.b1,
                pair.weights_b,
                -1.0,
            ),
        ];
        let moving: f64 = sides
            .iter()
            .filter(|s| s.0)
            .map(|s| s.4.iter().map(|w| w * w).sum::<f64>())
            .sum();
        if moving == 0.0 {
            continue;
        }
        let scale = (thickness - d) / moving;
        for (is_cloth, first, i0, i1, w, sign) in sides {
            if !is_cloth {
                continue;
            }
            for (v, wv) in corners(pair.kind, first, i0, i1, tris, w) {
                if wv == 0.0 {
                    continue;
                }
                for k in 0..3 {
                    delta[v as usize][k] += sign * scale * wv * normal[k];
                }
                count[v as usize] += 1.0;
            }
        }
    }
    for (x, (d, &c)) in p.iter_mut().zip(delta.iter().zip(count.iter())) {
        if c > 0.0 {
            for k in 0..3 {
                x[k] += d[k] / c.sqrt();
            }
        }
    }
}

/// A named part of a frame: its positions and triangles.
type Part<'a> = (&'a str, Vec<[f64; 3]>, &'a [[u32; 3]]);

fn write_outputs(
    dir: &std::path::Path,
    report: &Report,
    paddle_p: &[[f64; 3]],
    paddle_t: &[[u32; 3]],
    pillow_rest: &[[f64; 3]],
    pillow_t: &[[u32; 3]],
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut pillow = pillow_rest.to_vec();
    for (step, frame) in report.frames.iter().enumerate() {
        if step % 10 != 9 && step + 1 != report.frames.len() {
            continue;
        }
        let t = (step + 1) as f64 * DT;
        let pose = paddle_pose(t);
        pillow_at(pillow_rest, t, &mut pillow);
        let mut obj = String::new();
        let mut base = 1;
        let parts: [Part; 3] = [
            ("cloth", frame.clone(), &report.cloth_triangles),
            (
                "paddle",
                paddle_p.iter().map(|p| pose.transform_point(p)).collect(),
                paddle_t,
            ),
            ("pillow", pillow.clone(), pillow_t),
        ];
        for (name, p, tris) in parts {
            let _ = writeln!(obj, "o {name}");
            for v in &p {
                let _ = writeln!(obj, "v {} {} {}", v[0], v[1], v[2]);
            }
            for t in tris {
                let _ = writeln!(obj, "f {} {} {}", t[0] + base, t[1] + base, t[2] + base);
            }
            base += p.len() as u32;
        }
        std::fs::write(dir.join(format!("frame_{:04}.obj", step + 1)), obj)?;
    }
    let obstacles = |step: usize| {
        let t = (step + 1) as f64 * DT;
        let pose = paddle_pose(t);
        let mut pillow = pillow_rest.to_vec();
        pillow_at(pillow_rest, t, &mut pillow);
        let mut tris: Vec<[[f64; 3]; 3]> = paddle_t
            .iter()
            .map(|c| c.map(|v| pose.transform_point(&paddle_p[v as usize])))
            .collect();
        tris.extend(pillow_t.iter().map(|c| c.map(|v| pillow[v as usize])));
        tris
    };
    std::fs::write(dir.join("cloth.svg"), picture(report, obstacles))
}

/// The cloth seen from the side (x across, z up) at four steps, and per step the least
/// distance (in thicknesses) and the stencils.
fn picture(report: &Report, obstacles: impl Fn(usize) -> Vec<[[f64; 3]; 3]>) -> String {
    let (w, h) = (900.0, 620.0);
    let mut svg = format!(
        "<svg xmlns='http://www.w3.org/2000/svg' width='{w}' height='{h}' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
    );
    let steps = report.frames.len();
    let picks: Vec<usize> = [
        steps / 5,
        2 * steps / 5,
        3 * steps / 5,
        steps.saturating_sub(1),
    ]
    .into_iter()
    .filter(|&s| s < steps)
    .collect();
    for (k, &s) in picks.iter().enumerate() {
        let (ox, oy, scale) = (20.0 + 220.0 * k as f64, 20.0, 200.0);
        let _ = writeln!(
            svg,
            "<text x='{}' y='{}'>step {}</text>",
            ox,
            oy + 12.0,
            s + 1
        );
        let to = |p: &[f64; 3]| (ox + 100.0 + scale * p[0], oy + 170.0 - scale * (p[2] + 0.3));
        let _ = write!(
            svg,
            "<path stroke='#999' stroke-width='0.3' fill='none' d='"
        );
        for t in obstacles(s) {
            let (a, b, c) = (to(&t[0]), to(&t[1]), to(&t[2]));
            let _ = write!(
                svg,
                "M{:.1},{:.1}L{:.1},{:.1}L{:.1},{:.1}Z",
                a.0, a.1, b.0, b.1, c.0, c.1
            );
        }
        let _ = writeln!(svg, "'/>");
        let _ = write!(
            svg,
            "<path stroke='#1f77b4' stroke-width='0.3' fill='none' d='"
        );
        for t in &report.cloth_triangles {
            let f = &report.frames[s];
            let (a, b) = (to(&f[t[0] as usize]), to(&f[t[1] as usize]));
            let _ = write!(svg, "M{:.1},{:.1}L{:.1},{:.1}", a.0, a.1, b.0, b.1);
        }
        let _ = writeln!(svg, "'/>");
        let _ = writeln!(
            svg,
            "<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='black'/>",
            ox,
            oy + 170.0,
            ox + 200.0,
            oy + 170.0
        );
    }
    // The plots.
    let plot = |svg: &mut String, y0: f64, label: &str, values: &[f64], max: f64| {
        let (x0, pw, ph) = (60.0, 800.0, 150.0);
        let _ = writeln!(svg, "<text x='{x0}' y='{}'>{label}</text>", y0 - 6.0);
        let _ = writeln!(
            svg,
            "<rect x='{x0}' y='{y0}' width='{pw}' height='{ph}' fill='none' stroke='#999'/>"
        );
        let _ = write!(svg, "<path stroke='#d62728' fill='none' d='");
        for (i, v) in values.iter().enumerate() {
            let x = x0 + pw * i as f64 / values.len().max(1) as f64;
            let y = y0 + ph * (1.0 - (v / max).clamp(0.0, 1.0));
            let _ = write!(svg, "{}{x:.1},{y:.1}", if i == 0 { "M" } else { "L" });
        }
        let _ = writeln!(svg, "'/>");
        let _ = writeln!(svg, "<text x='10' y='{}'>{max}</text>", y0 + 10.0);
        let _ = writeln!(svg, "<text x='10' y='{}'>0</text>", y0 + ph);
    };
    let least: Vec<f64> = report
        .least_distance
        .iter()
        .map(|d| {
            if d.is_finite() {
                d / report.thickness
            } else {
                1.0
            }
        })
        .collect();
    plot(
        &mut svg,
        240.0,
        "least distance of the cloth to anything, in thicknesses (1: none closer)",
        &least,
        1.0,
    );
    let stencils: Vec<f64> = report.stencils.iter().map(|&s| s as f64).collect();
    let most = stencils.iter().copied().fold(1.0, f64::max);
    plot(
        &mut svg,
        440.0,
        "stencils within the thickness per step",
        &stencils,
        most,
    );
    svg.push_str("</svg>\n");
    svg
}

#[allow(dead_code)]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let settings = Settings {
        cells: arg("--cells").map(|s| s.parse()).transpose()?.unwrap_or(40),
        steps: arg("--steps")
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(300),
        threads: 0,
        out: Some(
            arg("--out")
                .unwrap_or_else(|| "target/cloth_scene".into())
                .into(),
        ),
        keep_frames: false,
        cut: true,
    };
    let clock = Instant::now();
    let report = simulate(&settings)?;
    let steps = report.kept.len() as f64;
    let bad: usize = report.intersecting.iter().sum();
    println!(
        "{} triangles, {} steps in {:.1} s: scene queries {:.2} ms a step (stencils {:.2}, \
         continuous collision {:.2}, the check {:.2}), the rest {:.2} ms; \
         {} steps cut by an impact, {} held corners; {} intersecting pairs at the ends of steps",
        report.triangles,
        report.kept.len(),
        clock.elapsed().as_secs_f64(),
        1e3 * report.collision_seconds / steps,
        1e3 * report.stencil_seconds / steps,
        1e3 * report.ccd_seconds / steps,
        1e3 * report.check_seconds / steps,
        1e3 * report.dynamics_seconds / steps,
        report.kept.iter().filter(|&&k| k < 1.0).count(),
        report.held,
        bad
    );
    if let Some(dir) = &settings.out {
        println!("frames and cloth.svg in {}", dir.display());
    }
    if bad > 0 {
        return Err("the cloth intersected something".into());
    }
    Ok(())
}
