//! What exactness costs: on the candidate pairs of the exact query (the triangle pairs of
//! overlapping leaves whose boxes meet), the share the floating-point filter of the exact test
//! cannot settle, and the time and the wrong answers of Möller's floating-point test against it.

use crate::moller;
use crate::report::Table;
use crate::scene::Scene;
use dvh::exact::{Triangle, triangles_intersect};
use dvh::fixtures::settled_by_filter;
use dvh::{Aabb, BuildOptions, Mesh, Pairs, QueryMode, QueryOptions, collide};
use std::hint::black_box;
use std::time::Instant;

/// The figures of one scene.
#[derive(Default)]
pub struct Exactness {
    pub scene: &'static str,
    /// Candidate pairs tested, and how many intersect.
    pub candidates: u64,
    pub intersecting: u64,
    /// Candidates on which some predicate needed more than its floating-point stage.
    pub unsettled: u64,
    /// Time of all candidates through each test, in milliseconds.
    pub exact_ms: f64,
    pub moller_ms: f64,
    /// Möller's wrong answers: pairs it calls disjoint that meet, and the reverse.
    pub moller_missed: u64,
    pub moller_false: u64,
}

/// The corners of triangle `t` of a mesh with the given triangles, at `world`.
fn corners(tris: &[u32], world: &[f64], t: u32) -> Triangle {
    let v = [0, 1, 2].map(|k| tris[3 * t as usize + k]);
    v.map(|i| {
        let i = i as usize;
        [world[3 * i], world[3 * i + 1], world[3 * i + 2]]
    })
}

/// Measures `scene` on `frames` with the default build options.
pub fn run(scene: &Scene, frames: &[usize]) -> Exactness {
    let mut out = Exactness {
        scene: scene.name,
        ..Exactness::default()
    };
    let n = scene.objects.len();
    let mut world = vec![Vec::new(); n];
    scene.world(frames[0], &mut world);
    let options = BuildOptions::default();
    let mut meshes: Vec<Mesh> = scene
        .objects
        .iter()
        .zip(&world)
        .map(|(o, w)| Mesh::new(w, &o.rest.triangles, &options).expect("valid scene mesh"))
        .collect();
    let mut pairs = Pairs::new();
    let mut candidates: Vec<(usize, usize, u32, u32)> = Vec::new();
    for &f in frames {
        scene.world(f, &mut world);
        for (m, w) in meshes.iter_mut().zip(&world) {
            m.refit(w).expect("finite coordinates");
        }
        candidates.clear();
        for &(a, b) in &scene.pairs {
            let (ta, tb) = (
                &scene.objects[a].rest.triangles,
                &scene.objects[b].rest.triangles,
            );
            let exact = collide(
                &meshes[a],
                None,
                &meshes[b],
                None,
                &QueryOptions::default(),
                &mut pairs,
            )
            .expect("query");
            collide(
                &meshes[a],
                None,
                &meshes[b],
                None,
                &QueryOptions::with_mode(QueryMode::Leaves),
                &mut pairs,
            )
            .expect("query");
            let before = candidates.len();
            for leaf in pairs.iter() {
                for &x in meshes[a].node_triangles(leaf.a) {
                    let bx = Aabb::of_points(&corners(ta, &world[a], x));
                    for &y in meshes[b].node_triangles(leaf.b) {
                        if bx.meets(&Aabb::of_points(&corners(tb, &world[b], y))) {
                            candidates.push((a, b, x, y));
                        }
                    }
                }
            }
            // These are exactly the pairs the exact query gave its triangle test.
            assert_eq!(
                (candidates.len() - before) as u64,
                exact.triangle_tests,
                "{}: candidates differ from the query's triangle tests",
                scene.name
            );
        }
        let get = |&(a, b, x, y): &(usize, usize, u32, u32)| {
            (
                corners(&scene.objects[a].rest.triangles, &world[a], x),
                corners(&scene.objects[b].rest.triangles, &world[b], y),
            )
        };
        let t = Instant::now();
        let mut hits = 0u64;
        for c in &candidates {
            let (p, q) = get(c);
            hits += u64::from(triangles_intersect(black_box(&p), black_box(&q)));
        }
        out.exact_ms += t.elapsed().as_secs_f64() * 1e3;
        let t = Instant::now();
        let mut moller_hits = 0u64;
        for c in &candidates {
            let (p, q) = get(c);
            moller_hits += u64::from(moller::intersect(black_box(&p), black_box(&q)));
        }
        out.moller_ms += t.elapsed().as_secs_f64() * 1e3;
        black_box((hits, moller_hits));
        for c in &candidates {
            let (p, q) = get(c);
            let (hit, settled) = settled_by_filter(&p, &q);
            let fast = moller::intersect(&p, &q);
            out.candidates += 1;
            out.intersecting += u64::from(hit);
            out.unsettled += u64::from(!settled);
            out.moller_missed += u64::from(hit && !fast);
            out.moller_false += u64::from(!hit && fast);
        }
    }
    out
}

/// One row per scene.
pub fn table(results: &[Exactness]) -> Table {
    let mut t = Table::new(&[
        "scene",
        "candidates",
        "intersecting",
        "not settled by the filter",
        "exact test",
        "Möller",
        "Möller / exact time",
        "Möller missed",
        "Möller false",
    ]);
    for r in results {
        let pct = |x: u64| format!("{:.3}%", 100.0 * x as f64 / r.candidates.max(1) as f64);
        t.row(vec![
            r.scene.to_string(),
            crate::report::count(r.candidates),
            crate::report::count(r.intersecting),
            format!(
                "{} ({})",
                crate::report::count(r.unsettled),
                pct(r.unsettled)
            ),
            format!("{:.1} ms", r.exact_ms),
            format!("{:.1} ms", r.moller_ms),
            format!("{:.2}", r.moller_ms / r.exact_ms),
            format!(
                "{} ({})",
                crate::report::count(r.moller_missed),
                pct(r.moller_missed)
            ),
            format!(
                "{} ({})",
                crate::report::count(r.moller_false),
                pct(r.moller_false)
            ),
        ]);
    }
    t
}
