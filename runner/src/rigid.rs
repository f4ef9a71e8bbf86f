//! The other scene kind: rigid objects moved by poses and never refit. Each volume kind's
//! queries on the paper's first scene with its deformation switched off, the objects built once
//! in their own coordinates and placed by a pose every frame: where spheres, which a rotation
//! does not loosen, may beat boxes, which it does.

use crate::knobs;
use crate::method::label;
use crate::report::{Table, median, ms, ratio};
use crate::scene::Scene;
use dvh::{BuildOptions, Mesh, Pairs, Pose, QueryOptions, collide};
use std::time::Instant;

/// Median query time per frame for every volume x tree x radius kind.
pub fn run(scene: &Scene) -> Vec<(BuildOptions, f64, f64)> {
    let mut pairs = Pairs::new();
    knobs::options()
        .into_iter()
        .map(|o| {
            let meshes: Vec<Mesh> = scene
                .objects
                .iter()
                .map(|ob| Mesh::new(&ob.rest.positions, &ob.rest.triangles, &o).expect("valid"))
                .collect();
            let (mut times, mut tests) = (Vec::new(), Vec::new());
            for f in 0..scene.frames {
                let t = f as f64 / scene.frames as f64;
                let poses: Vec<Pose> = scene.objects.iter().map(|ob| (ob.motion)(t)).collect();
                let start = Instant::now();
                let mut n = 0;
                for &(a, b) in &scene.pairs {
                    let s = collide(
                        &meshes[a],
                        Some(&poses[a]),
                        &meshes[b],
                        Some(&poses[b]),
                        &QueryOptions::default().with_threads(1),
                        &mut pairs,
                    )
                    .expect("query");
                    n += s.bv_tests;
                }
                times.push(start.elapsed().as_secs_f64() * 1e3);
                tests.push(n as f64);
            }
            (o, median(&times), median(&tests))
        })
        .collect()
}

pub fn table(rows: &[(BuildOptions, f64, f64)]) -> Table {
    let best = rows.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
    let mut t = Table::new(&["options", "query per frame", "volume tests", "ratio"]);
    for (o, time, tests) in rows {
        t.row(vec![
            label(o),
            ms(*time),
            crate::report::count(*tests as u64),
            ratio(time / best),
        ]);
    }
    t
}
