//! The paper's experiment (its Figures 8-10) with the peers: every method refits every object and
//! queries every object pair for all intersecting triangle pairs, frame by frame, on the same
//! world coordinates; time per frame split into refit and query, with the cost model's counters,
//! and every method's pairs compared with the exact ones.

use crate::method::Method;
use crate::report::{Table, count, median, ms, ratio, sums};
use crate::scene::Scene;
use indicatif::{ProgressBar, ProgressStyle};
use std::time::Instant;

/// What one method did over a run.
pub struct MethodRun {
    pub name: String,
    /// Per frame: refit of every object, queries of every pair, in milliseconds.
    pub refit_ms: Vec<f64>,
    pub query_ms: Vec<f64>,
    /// Per frame, where the method counts them: volume tests, triangle tests, nodes refit.
    pub nv: Vec<f64>,
    pub np: Vec<f64>,
    pub nu: Vec<f64>,
    /// Pairs reported over the run.
    pub pairs: u64,
    /// Exact pairs the method missed, and pairs it reported that do not intersect.
    pub missed: u64,
    pub extra: u64,
}

impl MethodRun {
    /// Median of refit + query per frame.
    pub fn total(&self) -> f64 {
        median(&self.totals())
    }

    /// Per-frame totals.
    pub fn totals(&self) -> Vec<f64> {
        sums(&self.refit_ms, &self.query_ms)
    }
}

/// `a` minus `b`, both sorted and distinct: how many of `a` are not in `b`.
fn missing(a: &[u64], b: &[u64]) -> u64 {
    let (mut i, mut j, mut n) = (0, 0, 0);
    while i < a.len() {
        if j == b.len() || a[i] < b[j] {
            n += 1;
            i += 1;
        } else if a[i] == b[j] {
            i += 1;
            j += 1;
        } else {
            j += 1;
        }
    }
    n
}

/// Runs every method on every frame of `scene`. The first method must be exact (a dvh method):
/// its pairs are the reference; every other dvh method must report exactly the same.
pub fn run(scene: &Scene, methods: &mut [Box<dyn Method>]) -> Vec<MethodRun> {
    let n = scene.objects.len();
    let mut world = vec![Vec::new(); n];
    scene.world(0, &mut world);
    for m in methods.iter_mut() {
        m.build(scene, &world);
    }
    let mut runs: Vec<MethodRun> = methods
        .iter()
        .map(|m| MethodRun {
            name: m.name(),
            refit_ms: Vec::new(),
            query_ms: Vec::new(),
            nv: Vec::new(),
            np: Vec::new(),
            nu: Vec::new(),
            pairs: 0,
            missed: 0,
            extra: 0,
        })
        .collect();
    let bar = ProgressBar::new((scene.frames * methods.len()) as u64).with_style(
        ProgressStyle::with_template("{prefix:>9} [{bar:40}] {pos}/{len} {msg} ({eta})")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    bar.set_prefix(scene.name);
    let mut out: Vec<Vec<Vec<u64>>> = vec![vec![Vec::new(); scene.pairs.len()]; methods.len()];
    for f in 0..scene.frames {
        scene.world(f, &mut world);
        // A different method goes first each frame, so that none always finds the caches cold.
        for k in 0..methods.len() {
            let i = (f + k) % methods.len();
            let m = &mut methods[i];
            bar.set_message(runs[i].name.clone());
            for (o, w) in world.iter().enumerate() {
                m.stage(o, w);
            }
            let t = Instant::now();
            let mut nu = None;
            for (o, w) in world.iter().enumerate() {
                if let Some(x) = m.update(o, w) {
                    *nu.get_or_insert(0) += x;
                }
            }
            let refit = t.elapsed().as_secs_f64() * 1e3;
            let t = Instant::now();
            let (mut nv, mut np) = (None, None);
            for (p, &(a, b)) in scene.pairs.iter().enumerate() {
                if let Some(c) = m.collide(a, b, &mut out[i][p]) {
                    *nv.get_or_insert(0) += c.bv_tests;
                    *np.get_or_insert(0) += c.triangle_tests;
                }
            }
            let query = t.elapsed().as_secs_f64() * 1e3;
            let r = &mut runs[i];
            r.refit_ms.push(refit);
            r.query_ms.push(query);
            for (series, value) in [(&mut r.nv, nv), (&mut r.np, np), (&mut r.nu, nu)] {
                if let Some(v) = value {
                    series.push(v as f64);
                }
            }
            bar.inc(1);
        }
        for (run, got) in runs.iter_mut().zip(&out) {
            for (reference, got) in out[0].iter().zip(got) {
                run.pairs += got.len() as u64;
                run.missed += missing(reference, got);
                run.extra += missing(got, reference);
            }
        }
    }
    bar.finish_and_clear();
    runs
}

/// The table of one scene: medians per frame, counters, pairs against the exact ones, and each
/// method's total over the fastest dvh method's (`ratio`).
pub fn table(runs: &[MethodRun]) -> Table {
    let best_dvh = runs
        .iter()
        .filter(|r| r.name.starts_with("dvh"))
        .map(MethodRun::total)
        .fold(f64::INFINITY, f64::min);
    let mut t = Table::new(&[
        "method", "refit", "query", "total", "NV", "NP", "NU", "pairs", "missed", "extra", "ratio",
    ]);
    let opt = |v: &[f64]| {
        if v.is_empty() {
            "—".to_string()
        } else {
            count(median(v) as u64)
        }
    };
    for r in runs {
        t.row(vec![
            r.name.clone(),
            ms(median(&r.refit_ms)),
            ms(median(&r.query_ms)),
            ms(r.total()),
            opt(&r.nv),
            opt(&r.np),
            opt(&r.nu),
            count(r.pairs),
            count(r.missed),
            count(r.extra),
            ratio(r.total() / best_dvh),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_differences() {
        assert_eq!(missing(&[1, 2, 5, 9], &[2, 3, 9]), 2);
        assert_eq!(missing(&[], &[1]), 0);
        assert_eq!(missing(&[4], &[]), 1);
    }
}
