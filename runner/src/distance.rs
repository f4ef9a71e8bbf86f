//! The least distance of two deforming meshes, dvh against parry, on the cross-check's scenes and
//! pairs: each object pair as the objects move (`moved`: many pairs meet, distance 0) and with
//! the second object moved apart along x so that a gap of 2% of the pair's diagonal opens
//! between their boxes (`apart`), as the cross-check's distance run places them. Per frame, each
//! method takes both objects' new coordinates and answers: dvh refits and calls
//! `dvh::distance` (exact, then with `rel_err = 0.01`), parry calls `TriMesh::set_vertices`
//! (its bottom-up refit) and `query::distance` on the two meshes (its composite-shape distance,
//! in floating point). Medians per frame of the sums over the scene's pairs; parry's answers
//! are checked against dvh's exact ones, which the cross-check holds to CGAL's exact distances.

use crate::report::{Table, median};
use crate::scene::{self, Scene, Size};
use dvh::{BuildOptions, Distance, DistanceOptions, Mesh};
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::shape::{TriMesh, TriMeshFlags};
use std::time::Instant;

/// One kind of run of one scene: each method's per-frame times and the answers compared.
struct Run {
    dvh: Vec<f64>,
    tolerant: Vec<f64>,
    parry: Vec<f64>,
    pairs: usize,
    meeting: usize,
    /// Frames x pairs where parry's distance is off dvh's exact one by more than 1e-9 of the
    /// pair's diagonal, and the largest difference over the diagonal.
    parry_off: usize,
    parry_worst: f64,
    /// Frames x pairs where dvh's tolerant answer is beyond what `rel_err` allows.
    tolerant_off: usize,
}

fn bounds(w: &[f64]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in w.chunks_exact(3) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// `b` moved along x so that a gap of 2% of the diagonal of both opens after `a`'s box.
fn moved_apart(a: &[f64], b: &mut [f64]) {
    let shift = bounds(a).1[0] - bounds(b).0[0] + 0.02 * diagonal(a, b);
    for p in b.chunks_exact_mut(3) {
        p[0] += shift;
    }
}

/// One frame of dvh: each pair's meshes refit to `coords` and their distance under `options`,
/// with the milliseconds it all took.
fn dvh_frame(
    meshes: &mut [(Mesh, Mesh)],
    coords: &[(Vec<f64>, Vec<f64>)],
    options: &DistanceOptions,
) -> Result<(Vec<Distance>, f64), Box<dyn std::error::Error>> {
    let mut answers = Vec::with_capacity(meshes.len());
    let t = Instant::now();
    for ((ma, mb), (a, b)) in meshes.iter_mut().zip(coords) {
        ma.refit(a)?;
        mb.refit(b)?;
        let mut d = Distance::default();
        dvh::distance(ma, None, mb, None, options, &mut d)?;
        answers.push(d);
    }
    Ok((answers, t.elapsed().as_secs_f64() * 1e3))
}

fn vectors(w: &[f64]) -> Vec<Vector> {
    w.chunks_exact(3)
        .map(|p| Vector::new(p[0], p[1], p[2]))
        .collect()
}

fn diagonal(a: &[f64], b: &[f64]) -> f64 {
    let ((la, ha), (lb, hb)) = (bounds(a), bounds(b));
    (0..3)
        .map(|k| (ha[k].max(hb[k]) - la[k].min(lb[k])).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn run(s: &Scene, apart: bool) -> Result<Run, Box<dyn std::error::Error>> {
    let mut world = vec![Vec::new(); s.objects.len()];
    // Each pair's own coordinates per frame: (first, second), the second moved apart if asked.
    let frame = |f: usize, world: &mut Vec<Vec<f64>>| -> Vec<(Vec<f64>, Vec<f64>)> {
        s.world(f, world);
        s.pairs
            .iter()
            .map(|&(i, j)| {
                let (a, mut b) = (world[i].clone(), world[j].clone());
                if apart {
                    moved_apart(&a, &mut b);
                }
                (a, b)
            })
            .collect()
    };
    let first = frame(0, &mut world);
    let build = BuildOptions::default().with_refit_threads(1);
    let mut meshes = Vec::new();
    let mut parry = Vec::new();
    for (&(i, j), (a, b)) in s.pairs.iter().zip(&first) {
        let (ti, tj) = (&s.objects[i].rest.triangles, &s.objects[j].rest.triangles);
        meshes.push((Mesh::new(a, ti, &build)?, Mesh::new(b, tj, &build)?));
        let tri = |t: &[u32]| t.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        parry.push((
            TriMesh::with_flags(vectors(a), tri(ti), TriMeshFlags::DEFORMABLE)?,
            TriMesh::with_flags(vectors(b), tri(tj), TriMeshFlags::DEFORMABLE)?,
        ));
    }
    let exact = DistanceOptions::default().with_threads(1);
    let tolerant = exact.with_tolerance(0.01, 0.0);
    let mut r = Run {
        dvh: Vec::new(),
        tolerant: Vec::new(),
        parry: Vec::new(),
        pairs: s.pairs.len(),
        meeting: 0,
        parry_off: 0,
        parry_worst: 0.0,
        tolerant_off: 0,
    };
    for f in 0..s.frames {
        let coords = frame(f, &mut world);
        let staged: Vec<_> = coords
            .iter()
            .map(|(a, b)| (vectors(a), vectors(b)))
            .collect();
        let (answers, ms) = dvh_frame(&mut meshes, &coords, &exact)?;
        r.dvh.push(ms);
        let (loose, ms) = dvh_frame(&mut meshes, &coords, &tolerant)?;
        r.tolerant.push(ms);
        let mut theirs = Vec::new();
        let t = Instant::now();
        for ((pa, pb), (va, vb)) in parry.iter_mut().zip(&staged) {
            pa.set_vertices(va);
            pb.set_vertices(vb);
            let d = parry3d_f64::query::distance(&Pose::IDENTITY, &*pa, &Pose::IDENTITY, &*pb)?;
            theirs.push(d.distance);
        }
        r.parry.push(t.elapsed().as_secs_f64() * 1e3);
        for (k, d) in answers.iter().enumerate() {
            if f == 0 && d.intersecting() {
                r.meeting += 1;
            }
            let diag = diagonal(&coords[k].0, &coords[k].1);
            let off = (theirs[k] - d.distance).abs() / diag;
            r.parry_worst = r.parry_worst.max(off);
            r.parry_off += usize::from(off > 1e-9);
            r.tolerant_off += usize::from(loose[k].distance > 1.01 * d.distance * (1.0 + 1e-12));
        }
    }
    Ok(r)
}

/// The distance table of `names` (every scene when empty), as Markdown; an error where dvh's
/// tolerant answers break their tolerance.
pub fn table(size: Size, names: &[String]) -> Result<String, Box<dyn std::error::Error>> {
    let mut t = Table::new(&[
        "scene",
        "kind",
        "object pairs",
        "meeting",
        "dvh exact ms",
        "dvh rel_err 0.01 ms",
        "parry ms",
        "parry ÷ dvh exact",
        "parry ÷ dvh rel_err",
        "parry off (> 1e-9 of the diagonal)",
        "parry's worst ÷ diagonal",
    ]);
    let every: Vec<String> = scene::EVERY.iter().map(|s| s.to_string()).collect();
    for name in if names.is_empty() { &every } else { names } {
        let s = scene::make(name, size).ok_or("a known scene")?;
        for apart in [false, true] {
            eprintln!(
                "distance: {} {}",
                s.name,
                if apart { "apart" } else { "moved" }
            );
            let r = run(&s, apart)?;
            if r.tolerant_off > 0 {
                return Err(format!(
                    "{}: {} answers with rel_err 0.01 beyond the tolerance",
                    s.name, r.tolerant_off
                )
                .into());
            }
            let (d, l, p) = (median(&r.dvh), median(&r.tolerant), median(&r.parry));
            t.row(vec![
                s.name.to_string(),
                if apart { "apart" } else { "moved" }.to_string(),
                r.pairs.to_string(),
                r.meeting.to_string(),
                format!("{d:.2}"),
                format!("{l:.2}"),
                format!("{p:.2}"),
                format!("{:.1}×", p / d),
                format!("{:.1}×", p / l),
                r.parry_off.to_string(),
                format!("{:.1e}", r.parry_worst),
            ]);
        }
    }
    Ok(t.markdown())
}
