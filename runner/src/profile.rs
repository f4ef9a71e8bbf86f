//! `profile`: dvh alone (default options) on the named scenes, each frame's refit and query
//! repeated, so that a change can be timed against the previous build on the same frames, and
//! a sampling profiler (`perf record`) sees the query and nothing else for long enough.
//!
//! The scene's frames are spread over its run; each is refit and queried `repeat` times in a
//! row (the first repetition warms the caches, as the next frame of a simulation would). The
//! figures are the means over frames of each frame's fastest repetition: the fastest is the
//! least disturbed by other loads on the machine, and the mean, unlike a median, does not jump
//! between frames of very different contact (the coplanar sheets' frames range from 4,000 to
//! 147,000 pairs).

use crate::scene::Scene;
use dvh::{BuildOptions, Mesh, Pairs, QueryOptions, collide};
use std::time::{Duration, Instant};

/// What one scene measured: per frame, the fastest refit and the fastest query (ms).
pub struct Profile {
    pub refit_ms: Vec<f64>,
    pub query_ms: Vec<f64>,
    /// Pairs reported over the frames (the same every repetition: checked).
    pub pairs: u64,
    /// Per frame, summed over the scene's object pairs: volume tests, leaf pairs, triangle tests.
    pub bv_tests: u64,
    pub leaf_pairs: u64,
    pub triangle_tests: u64,
}

/// Runs `scene`'s frames `frames` (indices into its run), each `repeat` times, on `threads`,
/// idling `pause` before each repetition (the cores then start cold, as after other work).
pub fn run(
    scene: &Scene,
    frames: &[usize],
    repeat: usize,
    threads: u32,
    pause: Duration,
) -> Result<Profile, dvh::Error> {
    let options = BuildOptions::default().with_refit_threads(threads);
    let query = QueryOptions::default().with_threads(threads);
    let mut world = vec![Vec::new(); scene.objects.len()];
    scene.world(0, &mut world);
    let mut meshes = scene
        .objects
        .iter()
        .zip(&world)
        .map(|(o, w)| Mesh::new(w, &o.rest.triangles, &options))
        .collect::<Result<Vec<_>, _>>()?;
    let mut pairs = Pairs::new();
    let mut out = Profile {
        refit_ms: Vec::new(),
        query_ms: Vec::new(),
        pairs: 0,
        bv_tests: 0,
        leaf_pairs: 0,
        triangle_tests: 0,
    };
    for &f in frames {
        scene.world(f, &mut world);
        let (mut refit, mut query_ms) = (f64::INFINITY, f64::INFINITY);
        let (mut reported, mut counts) = (None, [0; 3]);
        for _ in 0..repeat.max(1) {
            if !pause.is_zero() {
                std::thread::sleep(pause);
            }
            let t = Instant::now();
            for (m, w) in meshes.iter_mut().zip(&world) {
                m.refit(w)?;
            }
            refit = refit.min(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            let (mut n, mut c) = (0u64, [0u64; 3]);
            for &(a, b) in &scene.pairs {
                let s = collide(&meshes[a], None, &meshes[b], None, &query, &mut pairs)?;
                n += pairs.len() as u64;
                c[0] += s.bv_tests;
                c[1] += s.leaf_pairs;
                c[2] += s.triangle_tests;
            }
            query_ms = query_ms.min(t.elapsed().as_secs_f64() * 1e3);
            // Repetitions of one frame must agree; a difference is a bug, not noise.
            assert_eq!(
                *reported.get_or_insert(n),
                n,
                "a repetition changed the pairs"
            );
            counts = c;
        }
        out.pairs += reported.unwrap_or(0);
        out.bv_tests += counts[0];
        out.leaf_pairs += counts[1];
        out.triangle_tests += counts[2];
        out.refit_ms.push(refit);
        out.query_ms.push(query_ms);
    }
    Ok(out)
}

/// The mean of `v` (0 for an empty slice).
pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Size, make};

    /// Threads change the time, never the answer: the same pairs and counters on one thread and
    /// on two, every repetition (checked inside `run`).
    #[test]
    fn threads_agree() {
        let size = Size {
            full: false,
            frames: 0,
        };
        for name in ["coplanar", "near-1e-12"] {
            let scene = make(name, size).expect("a known scene");
            let frames = [0, scene.frames / 2];
            let one = run(&scene, &frames, 2, 1, Duration::ZERO).unwrap();
            let two = run(&scene, &frames, 2, 2, Duration::from_millis(1)).unwrap();
            assert!(one.pairs > 0, "{name}: the scene is in contact");
            assert_eq!(
                (one.pairs, one.bv_tests, one.leaf_pairs, one.triangle_tests),
                (two.pairs, two.bv_tests, two.leaf_pairs, two.triangle_tests),
                "{name}"
            );
            assert_eq!(one.query_ms.len(), frames.len());
            assert!(
                one.query_ms
                    .iter()
                    .chain(&one.refit_ms)
                    .all(|t| t.is_finite())
            );
        }
    }
}
