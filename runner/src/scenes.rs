//! `scenes`: dvh's [`dvh::Scene`] against the same work done pair by pair, on three scenes.
//!
//! - **many** (the paper's scene 1): every object deforms and moves. Pair by pair, each frame
//!   refits every mesh and queries every object pair; the scene takes the positions and queries
//!   once (broad phase, refits only of objects some overlapping pair needs).
//! - **static**: 10,000 rigid objects from 4 shared meshes on a grid, 1% of them given a new
//!   pose each frame. The same scene with every pair filtered out (masks 0) times the broad
//!   phase and the filters alone.
//! - **cloth**: one deforming sheet (cloth-sized) sinking onto 1,000 rigid balls. Pair by pair:
//!   a refit of the sheet and a query of it against every ball.
//! - **many, over a step**: the objects of *many* moving from one frame to the next, asked what a
//!   simulator asks every step: the earliest impact (continuous collision, exact, `earliest_only`)
//!   and the stencils within 1% of the scene's size. Pair by pair: a motion refit (or a refit) of
//!   every mesh and the pairwise query of every object pair, the earliest of their earliest
//!   impacts kept, their stencils joined; the scene takes the motions (positions) and queries
//!   once, its pairs pruned by the earliest impact found so far in any of them.
//!
//! Each frame is run `repeat` times and its fastest time kept; the table gives medians over the
//! frames. Every frame checks that the scene's contacts are the pairwise ones.

use crate::report::median;
use crate::scene::{self, Size};
use dvh::fixtures::{MeshData, Rng, grid, icosphere, torus};
use dvh::{
    BuildOptions, CcdOptions, Contact, Contacts, Impacts, Mesh, NearPairs, Pairs, Pose,
    QueryOptions, Scene, SceneImpact, SceneImpacts, SceneNearPair, SceneNearPairs, collide,
    continuous_collide, nearest_features,
};
use std::fmt::Write;
use std::time::Instant;

/// One row of the table.
struct Row {
    scene: String,
    method: &'static str,
    ms: Vec<f64>,
    nodes_refit: u64,
    pairs_queried: u64,
    contacts: u64,
    /// The scene's bytes (`Scene::memory_bytes`), for the scene's rows.
    memory: Option<usize>,
}

impl Row {
    fn new(scene: String, method: &'static str) -> Row {
        Row {
            scene,
            method,
            ms: Vec::new(),
            nodes_refit: 0,
            pairs_queried: 0,
            contacts: 0,
            memory: None,
        }
    }
}

/// The fastest of `repeat` runs of `f`, in milliseconds, and its last result.
fn fastest<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        last = Some(r);
    }
    (best, last.expect("at least one run"))
}

fn contacts_of(pairs: &Pairs, i: usize, j: usize, out: &mut Vec<Contact>) {
    out.extend(pairs.iter().map(|p| Contact {
        object_a: i as u32,
        object_b: j as u32,
        a: p.a,
        b: p.b,
    }));
}

fn check(scene: &Contacts, pairwise: &[Contact], what: &str) -> Result<(), String> {
    if scene.as_slice() != pairwise {
        return Err(format!(
            "{what}: the scene found {} contacts, pair by pair {}",
            scene.len(),
            pairwise.len()
        ));
    }
    Ok(())
}

/// The paper's scene 1 as a scene, against every pair queried after an eager refit.
fn many(
    size: Size,
    frames: usize,
    repeat: usize,
    threads: u32,
    rows: &mut Vec<Row>,
) -> Result<(), Box<dyn std::error::Error>> {
    let s = scene::make("many", size).expect("a known scene");
    let options = BuildOptions::default().with_refit_threads(threads);
    let query = QueryOptions::default().with_threads(threads);
    let mut world = vec![Vec::new(); s.objects.len()];
    s.world(0, &mut world);
    let mut meshes = s
        .objects
        .iter()
        .zip(&world)
        .map(|(o, w)| Mesh::new(w, &o.rest.triangles, &options))
        .collect::<Result<Vec<_>, _>>()?;
    let mut scene = Scene::new();
    for m in &meshes {
        scene.add_deformable(m, 1, u32::MAX)?;
    }
    // The same scene refitting every object it needs whole: what lazy refit saves.
    let mut eager_scene = scene.clone();
    eager_scene.set_lazy_refit(false);
    let name = format!("many ({} objects)", meshes.len());
    let (mut pairwise, mut together, mut eager) = (
        Row::new(name.clone(), "pair by pair, eager refit"),
        Row::new(name.clone(), "scene"),
        Row::new(name, "scene, eager refit"),
    );
    let mut pairs = Pairs::new();
    let mut contacts = Contacts::new();
    let mut expected = Vec::new();
    for k in 0..frames {
        let f = k * s.frames / frames.max(1);
        s.world(f, &mut world);
        let (ms, r) = fastest(repeat, || -> Result<(u64, Vec<Contact>), dvh::Error> {
            let mut nodes = 0;
            for (m, w) in meshes.iter_mut().zip(&world) {
                nodes += m.refit(w)?.nodes_refit;
            }
            expected.clear();
            for &(i, j) in &s.pairs {
                collide(&meshes[i], None, &meshes[j], None, &query, &mut pairs)?;
                contacts_of(&pairs, i, j, &mut expected);
            }
            Ok((nodes, std::mem::take(&mut expected)))
        });
        let (nodes, found) = r?;
        pairwise.ms.push(ms);
        pairwise.nodes_refit += nodes;
        pairwise.pairs_queried += s.pairs.len() as u64;
        pairwise.contacts += found.len() as u64;
        for (scene, row) in [(&mut scene, &mut together), (&mut eager_scene, &mut eager)] {
            let (ms, st) = fastest(repeat, || -> Result<dvh::SceneStats, dvh::Error> {
                for (id, w) in world.iter().enumerate() {
                    scene.set_positions(id as u32, w)?;
                }
                scene.collide(&query, &mut contacts)
            });
            let st = st?;
            check(&contacts, &found, &format!("many, frame {f}"))?;
            row.ms.push(ms);
            row.nodes_refit += st.nodes_refit;
            row.pairs_queried += st.object_pairs_tested;
            row.contacts += st.contacts;
        }
    }
    together.memory = Some(scene.memory_bytes());
    eager.memory = Some(eager_scene.memory_bytes());
    rows.extend([pairwise, together, eager]);
    Ok(())
}

/// The *many* scene over its steps: the earliest impact and the stencils, pair by pair and by the
/// scene.
fn many_steps(
    size: Size,
    frames: usize,
    repeat: usize,
    threads: u32,
    rows: &mut Vec<Row>,
) -> Result<(), Box<dyn std::error::Error>> {
    let s = scene::make("many", size).expect("a known scene");
    let options = BuildOptions::default().with_refit_threads(threads);
    let query = QueryOptions::default().with_threads(threads);
    let earliest = CcdOptions::default()
        .with_earliest_only(true)
        .with_threads(threads);
    let (mut start, mut end) = (
        vec![Vec::new(); s.objects.len()],
        vec![Vec::new(); s.objects.len()],
    );
    s.world(0, &mut start);
    let mut meshes = s
        .objects
        .iter()
        .zip(&start)
        .map(|(o, w)| Mesh::new(w, &o.rest.triangles, &options))
        .collect::<Result<Vec<_>, _>>()?;
    let mut scene = Scene::new();
    for m in &meshes {
        scene.add_deformable(m, 1, u32::MAX)?;
    }
    // 1% of the scene's size: the diagonal of the box of every object at the start.
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for w in &start {
        for p in w.chunks_exact(3) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    // Stencils at 1% (millions of them: result handling dominates) and at 0.1% (the search).
    let distances = [
        (
            0.01,
            "stencils at 1%, pair by pair",
            "stencils at 1%, scene",
        ),
        (
            0.001,
            "stencils at 0.1%, pair by pair",
            "stencils at 0.1%, scene",
        ),
    ];
    let name = format!("many ({} objects), over a step", meshes.len());
    let mut rows_here = vec![
        Row::new(name.clone(), "earliest impact, pair by pair"),
        Row::new(name.clone(), "earliest impact, scene"),
    ];
    for (_, pairwise, together) in distances {
        rows_here.push(Row::new(name.clone(), pairwise));
        rows_here.push(Row::new(name.clone(), together));
    }
    let (mut impacts, mut scene_impacts) = (Impacts::new(), SceneImpacts::new());
    let (mut near, mut scene_near) = (NearPairs::new(), SceneNearPairs::new());
    for k in 0..frames {
        let f = k * s.frames / frames.max(1);
        s.world(f, &mut start);
        s.world(f + 1, &mut end);
        // The earliest impact over the step from frame f to frame f + 1.
        let (ms, first) = fastest(repeat, || -> Result<Option<SceneImpact>, dvh::Error> {
            for (m, (a, b)) in meshes.iter_mut().zip(start.iter().zip(&end)) {
                m.refit_motion(a, b)?;
            }
            let mut first: Option<SceneImpact> = None;
            for &(i, j) in &s.pairs {
                continuous_collide(&meshes[i], &meshes[j], &earliest, &mut impacts)?;
                if let Some(x) = impacts.iter().next()
                    && first.is_none_or(|f| x.toi < f.impact.toi)
                {
                    first = Some(SceneImpact {
                        object_a: i as u32,
                        object_b: j as u32,
                        impact: *x,
                    });
                }
            }
            Ok(first)
        });
        let first = first?;
        rows_here[0].ms.push(ms);
        rows_here[0].pairs_queried += s.pairs.len() as u64;
        rows_here[0].contacts += u64::from(first.is_some());
        let (ms, st) = fastest(repeat, || -> Result<dvh::CcdStats, dvh::Error> {
            for (id, (a, b)) in start.iter().zip(&end).enumerate() {
                scene.set_motion(id as u32, a, b)?;
            }
            scene.continuous_collide(&earliest, &mut scene_impacts)
        });
        st?;
        if scene_impacts.as_slice() != first.as_slice() {
            return Err(
                format!("many, step {f}: the scene's earliest impact is not the pairs'").into(),
            );
        }
        rows_here[1].ms.push(ms);
        rows_here[1].contacts += scene_impacts.len() as u64;
        // The stencils at the end of the step.
        for (n, &(fraction, _, _)) in distances.iter().enumerate() {
            let d = fraction * diagonal;
            let (pairwise_row, scene_row) = (2 + 2 * n, 3 + 2 * n);
            let (ms, expected) = fastest(repeat, || -> Result<Vec<SceneNearPair>, dvh::Error> {
                for (m, w) in meshes.iter_mut().zip(&end) {
                    m.refit(w)?;
                }
                let mut all = Vec::new();
                for &(i, j) in &s.pairs {
                    nearest_features(&meshes[i], None, &meshes[j], None, d, &query, &mut near)?;
                    all.extend(near.iter().map(|&pair| SceneNearPair {
                        object_a: i as u32,
                        object_b: j as u32,
                        pair,
                    }));
                }
                Ok(all)
            });
            let expected = expected?;
            rows_here[pairwise_row].ms.push(ms);
            rows_here[pairwise_row].pairs_queried += s.pairs.len() as u64;
            rows_here[pairwise_row].contacts += expected.len() as u64;
            let (ms, st) = fastest(repeat, || -> Result<dvh::QueryStats, dvh::Error> {
                for (id, w) in end.iter().enumerate() {
                    scene.set_positions(id as u32, w)?;
                }
                scene.nearest_features(d, &query, &mut scene_near)
            });
            st?;
            if scene_near.as_slice() != &expected[..] {
                return Err(format!(
                    "many, step {f}: the scene found {} stencils, pair by pair {}",
                    scene_near.len(),
                    expected.len()
                )
                .into());
            }
            rows_here[scene_row].ms.push(ms);
            rows_here[scene_row].contacts += scene_near.len() as u64;
        }
    }
    rows.extend(rows_here);
    Ok(())
}

/// A pose turning by `angle` about `axis` (Rodrigues' formula) and moved to `at`.
fn pose(axis: [f64; 3], angle: f64, at: [f64; 3]) -> Pose {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = axis.map(|v| v / n);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    let r = [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ];
    Pose::new(r, at).expect("a rotation")
}

/// 10,000 rigid objects from 4 shared meshes, 1% of them moved each frame.
fn static_objects(
    count: usize,
    frames: usize,
    repeat: usize,
    threads: u32,
    rows: &mut Vec<Row>,
) -> Result<(), Box<dyn std::error::Error>> {
    let shapes: Vec<MeshData> = vec![icosphere(1), icosphere(2), torus(0.4, 0.15, 16, 8), {
        let mut g = grid(6, 0.9);
        g.translate([-0.45, -0.45, 0.0]);
        g
    }];
    let meshes = shapes
        .iter()
        .map(|d| Mesh::new(&d.positions, &d.triangles, &BuildOptions::rigid()))
        .collect::<Result<Vec<_>, _>>()?;
    let side = (count as f64).cbrt().ceil() as usize;
    // Shapes of radius at most 1, 2 apart along x: neighbours' boxes overlap where they turn,
    // and some touch.
    let place = |i: usize, rng: &mut Rng| {
        let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
        let axis = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(0.1, 1.0),
        ];
        pose(
            axis,
            rng.range(0.0, 3.0),
            [2.0 * x as f64, 2.4 * y as f64, 2.4 * z as f64],
        )
    };
    let query = QueryOptions::default().with_threads(threads);
    for (filtered, method) in [
        (false, "scene, 1% moved per frame"),
        (true, "the same, every pair filtered: broad phase alone"),
    ] {
        let mut rng = Rng::new(9);
        let mut scene = Scene::new();
        for i in 0..count {
            let p = place(i, &mut rng);
            scene.add_rigid(
                &meshes[i % meshes.len()],
                Some(&p),
                1,
                if filtered { 0 } else { u32::MAX },
            )?;
        }
        let mut row = Row::new(format!("static ({count} rigid objects)"), method);
        let mut contacts = Contacts::new();
        for _ in 0..frames {
            let moved: Vec<(u32, Pose)> = (0..count / 100)
                .map(|_| {
                    let i = rng.below(count as u64) as usize;
                    (i as u32, place(i, &mut rng))
                })
                .collect();
            let (ms, st) = fastest(repeat, || -> Result<dvh::SceneStats, dvh::Error> {
                for (i, p) in &moved {
                    scene.set_pose(*i, Some(p))?;
                }
                scene.collide(&query, &mut contacts)
            });
            let st = st?;
            row.ms.push(ms);
            row.pairs_queried += st.object_pairs_tested;
            row.contacts += st.contacts;
        }
        row.memory = Some(scene.memory_bytes());
        rows.push(row);
    }
    Ok(())
}

/// A deforming sheet sinking onto 1,000 rigid balls.
fn cloth(
    size: Size,
    frames: usize,
    repeat: usize,
    threads: u32,
    rows: &mut Vec<Row>,
) -> Result<(), Box<dyn std::error::Error>> {
    let n = if size.full { 224 } else { 64 }; // 2 n^2 triangles: 100,352 in full
    let balls = 1000;
    let sheet = grid(n, 40.0);
    let mut ball = icosphere(2);
    ball.scale(0.5);
    let query = QueryOptions::default().with_threads(threads);
    let build = BuildOptions::default().with_refit_threads(threads);
    let mut cloth_mesh = Mesh::new(&sheet.positions, &sheet.triangles, &build)?;
    let ball_mesh = Mesh::new(&ball.positions, &ball.triangles, &BuildOptions::rigid())?;
    let mut rng = Rng::new(5);
    // Balls of radius 0.5 on a 32 x 32 grid 1.25 apart (none touching), their heights varied.
    let poses: Vec<Pose> = (0..balls)
        .map(|i| {
            let (x, y) = ((i % 32) as f64, (i / 32) as f64);
            let at = [0.6 + 1.25 * x, 0.6 + 1.25 * y, rng.range(-0.5, 0.5)];
            pose([0.0, 0.0, 1.0], rng.range(0.0, 6.0), at)
        })
        .collect();
    let mut scene = Scene::new();
    let cloth_id = scene.add_deformable(&cloth_mesh, 1, u32::MAX)?;
    for p in &poses {
        scene.add_rigid(&ball_mesh, Some(p), 1, u32::MAX)?;
    }
    // The sheet sags from height 3 to touch and then pass through the balls' tops.
    let at = |t: f64, out: &mut Vec<f64>| {
        out.clear();
        for v in sheet.positions.chunks_exact(3) {
            let (x, y) = (v[0], v[1]);
            let sag = ((x / 40.0 * std::f64::consts::PI).sin()
                * (y / 40.0 * std::f64::consts::PI).sin())
                * 1.5;
            out.extend([
                x,
                y,
                3.0 - 2.5 * t - sag * t + 0.2 * (x * 0.7 + y * 0.3 + 6.0 * t).sin(),
            ]);
        }
    };
    let name = format!(
        "cloth ({} triangles, {balls} rigid balls)",
        sheet.triangle_count()
    );
    let mut eager_scene = scene.clone();
    eager_scene.set_lazy_refit(false);
    let (mut pairwise, mut together, mut eager) = (
        Row::new(
            name.clone(),
            "pair by pair: refit, sheet against every ball",
        ),
        Row::new(name.clone(), "scene"),
        Row::new(name, "scene, eager refit"),
    );
    let mut positions = Vec::new();
    let mut pairs = Pairs::new();
    let mut contacts = Contacts::new();
    for k in 0..frames {
        at(k as f64 / frames.max(1) as f64, &mut positions);
        let (ms, r) = fastest(repeat, || -> Result<(u64, Vec<Contact>), dvh::Error> {
            let nodes = cloth_mesh.refit(&positions)?.nodes_refit;
            let mut found = Vec::new();
            for (b, p) in poses.iter().enumerate() {
                collide(&cloth_mesh, None, &ball_mesh, Some(p), &query, &mut pairs)?;
                contacts_of(&pairs, cloth_id as usize, b + 1, &mut found);
            }
            Ok((nodes, found))
        });
        let (nodes, found) = r?;
        pairwise.ms.push(ms);
        pairwise.nodes_refit += nodes;
        pairwise.pairs_queried += balls as u64;
        pairwise.contacts += found.len() as u64;
        for (scene, row) in [(&mut scene, &mut together), (&mut eager_scene, &mut eager)] {
            let (ms, st) = fastest(repeat, || -> Result<dvh::SceneStats, dvh::Error> {
                scene.set_positions(cloth_id, &positions)?;
                scene.collide(&query, &mut contacts)
            });
            let st = st?;
            // Balls that touch each other add contacts of their own: compare the sheet's only.
            let sheet_contacts: Vec<Contact> = contacts
                .iter()
                .copied()
                .filter(|c| c.object_a == cloth_id)
                .collect();
            if sheet_contacts != found {
                return Err(format!(
                    "cloth, frame {k}: the scene found {} sheet contacts, pair by pair {}",
                    sheet_contacts.len(),
                    found.len()
                )
                .into());
            }
            row.ms.push(ms);
            row.nodes_refit += st.nodes_refit;
            row.pairs_queried += st.object_pairs_tested;
            row.contacts += st.contacts;
        }
    }
    together.memory = Some(scene.memory_bytes());
    eager.memory = Some(eager_scene.memory_bytes());
    rows.extend([pairwise, together, eager]);
    Ok(())
}

/// Runs the three scenes and returns the table.
pub fn run(
    size: Size,
    frames: usize,
    repeat: usize,
    threads: u32,
) -> Result<String, Box<dyn std::error::Error>> {
    let mut rows = Vec::new();
    many(size, frames, repeat, threads, &mut rows)?;
    many_steps(size, frames, repeat, threads, &mut rows)?;
    static_objects(
        if size.full { 10_000 } else { 1_000 },
        frames,
        repeat,
        threads,
        &mut rows,
    )?;
    cloth(size, frames, repeat, threads, &mut rows)?;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Medians over {frames} frames of each frame's fastest of {repeat} runs; counters are means per frame; threads = {threads}.\n"
    );
    let _ = writeln!(
        out,
        "| scene | method | ms per frame | nodes refit | object pairs queried | contacts | scene memory (MB) |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|");
    let f = frames.max(1) as f64;
    for r in &rows {
        let _ = writeln!(
            out,
            "| {} | {} | {:.3} | {:.0} | {:.0} | {:.0} | {} |",
            r.scene,
            r.method,
            median(&r.ms),
            r.nodes_refit as f64 / f,
            r.pairs_queried as f64 / f,
            r.contacts as f64 / f,
            r.memory
                .map_or("".to_string(), |b| format!("{:.1}", b as f64 / 1e6))
        );
    }
    Ok(out)
}
