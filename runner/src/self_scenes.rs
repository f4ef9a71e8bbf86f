//! `self`: self-collision and self-proximity on two deforming meshes.
//!
//! - **sheet**: a cloth-like sheet (100,352 triangles with `--full`, 3,200 without), rippled,
//!   falling while it folds over a crease line that tilts across it; past 180 degrees the flap
//!   passes through the rest of the sheet.
//! - **bent**: a scanned mesh (the CGAL armadillo, 52,000 triangles, with `--full`; the
//!   elephant, 5,558, without; a built-in mesh without Debian's data) bent around a cylinder
//!   until its ends cross.
//!
//! Each mesh is built as an octree (the default) and as a binary tree. Every frame is refit, then
//! queried `repeat` times (the fastest kept) by: `self_collide`; the naive route, `collide` of
//! the mesh with itself and the pairs of triangles sharing a vertex (and the mirrored pairs)
//! dropped afterwards; and, with the octree, on a few frames spread over the run (unless
//! `--no-proximity`), `self_proximity` at 0.1%, 1% and 5% of the mesh's size (its box's
//! diagonal), and `self_nearest_features` (the vertex-face and edge-edge stencils with their
//! closest points) at the same distances on the same frames, its time also given as a ratio to
//! `self_proximity`'s. The table gives medians per frame. Every frame checks that `self_collide`'s pairs
//! of triangles sharing no vertex are exactly the naive route's.

use crate::report::median;
use crate::scene::{Size, mesh};
use dvh::fixtures::{MeshData, grid};
use dvh::{
    BuildOptions, Mesh, NearPairs, Pair, Pairs, QueryOptions, TreeKind, collide, self_collide,
    self_nearest_features, self_proximity,
};
use std::f64::consts::PI;
use std::fmt::Write;
use std::time::Instant;

/// The meshes, for `--scene`.
pub const NAMES: [&str; 2] = ["sheet", "bent"];

/// One deforming mesh: its rest shape and where it is at time `t` in `[0, 1)`.
struct Deforming {
    name: &'static str,
    rest: MeshData,
    at: fn(&MeshData, f64) -> Vec<f64>,
}

/// The sheet: `n` x `n` cells, 1 wide.
fn sheet(n: usize) -> Deforming {
    Deforming {
        name: "sheet",
        rest: grid(n, 1.0),
        at: |m: &MeshData, t: f64| {
            let radius = 0.02;
            m.positions
                .chunks_exact(3)
                .flat_map(|v| {
                    let (x, y) = (v[0], v[1]);
                    // Ripples, as a cloth has; the fold angle grows to 200 degrees, more at one
                    // side than the other, so the crossing line sweeps across the sheet.
                    let ripple = 0.004 * (23.0 * x).sin() * (17.0 * y).sin();
                    let angle = PI * 1.12 * t * (0.9 + 0.2 * y);
                    let crease = 0.45;
                    let arc = radius * angle;
                    let (px, pz) = if x <= crease {
                        (x, ripple)
                    } else if x <= crease + arc {
                        // On the crease's cylinder.
                        let a = (x - crease) / radius;
                        (
                            crease + (radius - ripple) * a.sin(),
                            radius - (radius - ripple) * a.cos(),
                        )
                    } else {
                        // Straight past it, at the fold angle.
                        let s = x - crease - arc;
                        let (sin, cos) = angle.sin_cos();
                        let (cx, cz) = (crease + radius * sin, radius - radius * cos);
                        (cx + s * cos - ripple * sin, cz + s * sin + ripple * cos)
                    };
                    [px, y, pz - 0.5 * t]
                })
                .collect()
        },
    }
}

/// A scanned mesh bent around a cylinder along its longest axis, the bend growing to 2.3 turns'
/// worth of angle, so its ends meet and cross.
fn bent(full: bool) -> Deforming {
    let mut built_in = false;
    let (name, triangles) = if full {
        ("armadillo", 50_000)
    } else {
        ("elephant", 4_000)
    };
    let rest = mesh(name, triangles, 1.0, &mut built_in);
    Deforming {
        name: if built_in { "bent (built-in)" } else { "bent" },
        rest,
        at: |m: &MeshData, t: f64| {
            let b = m.bounds();
            let length = b.hi[0] - b.lo[0];
            let bend = (1e-6 + 2.3 * PI * t).min(2.3 * PI);
            let radius = length / bend;
            m.positions
                .chunks_exact(3)
                .flat_map(|v| {
                    let a = (v[0] - b.lo[0]) / length * bend - bend / 2.0;
                    let r = radius - (v[2] - 0.5 * (b.lo[2] + b.hi[2]));
                    [r * a.sin(), v[1], radius - r * a.cos()]
                })
                .collect()
        },
    }
}

/// The fastest of `repeat` runs of `f` on `mesh`, in milliseconds, each after an untimed refit
/// to `positions`, so that no run finds anything an earlier one left (a query keeps what it
/// finds about the positions until they change, as a frame's first query would not have it).
fn fastest(
    repeat: usize,
    mesh: &mut Mesh,
    positions: &[f64],
    mut f: impl FnMut(&Mesh),
) -> Result<f64, dvh::Error> {
    let mut best = f64::INFINITY;
    for _ in 0..repeat.max(1) {
        mesh.refit(positions)?;
        let t = Instant::now();
        f(mesh);
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
    }
    Ok(best)
}

/// The naive route's filter: pairs `a < b` of triangles sharing no vertex.
fn apart(tris: &[u32], pairs: &[Pair], out: &mut Vec<Pair>) {
    out.clear();
    let tri = |t: u32| &tris[3 * t as usize..3 * t as usize + 3];
    out.extend(pairs.iter().copied().filter(|p| {
        p.a < p.b && {
            let (x, y) = (tri(p.a), tri(p.b));
            !x.iter().any(|v| y.contains(v))
        }
    }));
}

/// Runs the `self` command; returns the Markdown table.
pub fn run(
    size: Size,
    names: &[String],
    frames: usize,
    repeat: usize,
    threads: u32,
    proximity: bool,
) -> Result<String, Box<dyn std::error::Error>> {
    let frames = frames.max(2);
    let chosen = |name: &str| names.is_empty() || names.iter().any(|n| n == name);
    let mut meshes = Vec::new();
    if chosen("sheet") {
        meshes.push(sheet(if size.full { 224 } else { 40 }));
    }
    if chosen("bent") {
        meshes.push(bent(size.full));
    }
    let options = QueryOptions::default().with_threads(threads);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Medians over {frames} frames (proximity: over {} frames spread over them) of each \
         frame's fastest of {repeat} queries; threads = {threads}.\n",
        frames.min(10)
    );
    let _ = writeln!(
        out,
        "| mesh | triangles | tree | query | ms per frame | ratio to self_collide | pairs (stencils) per frame | triangle (primitive) tests per frame |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|");
    for (m, tree) in meshes
        .iter()
        .flat_map(|m| [(m, TreeKind::Octree), (m, TreeKind::Binary)])
    {
        let proximity = proximity && tree == TreeKind::Octree;
        let build = BuildOptions::default().with_tree(tree);
        let mut mesh = Mesh::new(&m.rest.positions, &m.rest.triangles, &build)?;
        let b = m.rest.bounds();
        let diagonal = (0..3)
            .map(|k| (b.hi[k] - b.lo[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let fractions = [0.001, 0.01, 0.05];
        // (ms, pairs, triangle tests) per frame: self, naive, and each distance.
        let mut rows: Vec<(String, Vec<f64>, u64, u64)> =
            ["self_collide", "naive: collide with itself, filtered"]
                .iter()
                .map(|s| (s.to_string(), Vec::new(), 0, 0))
                .chain(fractions.iter().map(|f| {
                    (
                        format!("self_proximity at {:.1}% ({:.2e})", f * 100.0, f * diagonal),
                        Vec::new(),
                        0,
                        0,
                    )
                }))
                .chain(fractions.iter().map(|f| {
                    (
                        format!(
                            "self_nearest_features at {:.1}% ({:.2e})",
                            f * 100.0,
                            f * diagonal
                        ),
                        Vec::new(),
                        0,
                        0,
                    )
                }))
                .collect();
        let (mut own, mut all, mut filtered) = (Pairs::new(), Pairs::new(), Vec::new());
        // The first query also finds what depends on the shape alone (the patches' loops).
        let start = Instant::now();
        self_collide(&mesh, &options, &mut own)?;
        rows.push((
            "self_collide at rest, first call (finds the patches)".to_string(),
            vec![start.elapsed().as_secs_f64() * 1e3],
            own.len() as u64,
            0,
        ));
        let mut near = Pairs::new();
        let mut stencils = NearPairs::new();
        let sampled = frames.min(10);
        let mut self_on_sampled = Vec::new();
        for f in 0..frames {
            let t = f as f64 / frames as f64;
            let positions = (m.at)(&m.rest, t);
            let mut stats = Default::default();
            let ms = fastest(repeat, &mut mesh, &positions, |mesh| {
                stats = self_collide(mesh, &options, &mut own).expect("self_collide");
            })?;
            rows[0].1.push(ms);
            rows[0].2 += own.len() as u64;
            rows[0].3 += stats.triangle_tests;
            let ms = fastest(repeat, &mut mesh, &positions, |mesh| {
                stats = collide(mesh, None, mesh, None, &options, &mut all).expect("collide");
                apart(&m.rest.triangles, all.as_slice(), &mut filtered);
            })?;
            rows[1].1.push(ms);
            rows[1].2 += filtered.len() as u64;
            rows[1].3 += stats.triangle_tests;
            let mut own_apart = Vec::new();
            apart(&m.rest.triangles, own.as_slice(), &mut own_apart);
            if own_apart != filtered {
                return Err(format!(
                    "{} frame {f}: self_collide has {} pairs sharing no vertex, the naive route {}",
                    m.name,
                    own_apart.len(),
                    filtered.len()
                )
                .into());
            }
            if proximity && (f * sampled) % frames < sampled {
                self_on_sampled.push(rows[0].1[f]);
                for (k, fraction) in fractions.iter().enumerate() {
                    let d = fraction * diagonal;
                    let ms = fastest(repeat, &mut mesh, &positions, |mesh| {
                        stats = self_proximity(mesh, d, &options, &mut near).expect("proximity");
                    })?;
                    rows[2 + k].1.push(ms);
                    rows[2 + k].2 += near.len() as u64;
                    rows[2 + k].3 += stats.triangle_tests;
                    let ms = fastest(repeat, &mut mesh, &positions, |mesh| {
                        stats = self_nearest_features(mesh, d, &options, &mut stencils)
                            .expect("nearest features");
                    })?;
                    rows[5 + k].1.push(ms);
                    rows[5 + k].2 += stencils.len() as u64;
                    rows[5 + k].3 += stats.triangle_tests;
                }
            }
        }
        let base = median(&rows[0].1);
        let base_sampled = median(&self_on_sampled);
        for (k, (what, ms, pairs, tests)) in rows.iter().enumerate() {
            if ms.is_empty() {
                continue;
            }
            let n = ms.len() as f64;
            let what = if (5..8).contains(&k) {
                format!(
                    "{what}; {:.2}x self_proximity, {} bytes per stencil",
                    median(ms) / median(&rows[k - 3].1),
                    std::mem::size_of::<dvh::NearPair>()
                )
            } else {
                what.clone()
            };
            let reference = if (2..8).contains(&k) {
                base_sampled
            } else {
                base
            };
            let _ = writeln!(
                out,
                "| {} | {} | {tree:?} | {} | {:.3} | {:.2} | {:.0} | {:.0} |",
                m.name,
                m.rest.triangle_count(),
                what,
                median(ms),
                median(ms) / reference,
                *pairs as f64 / n,
                *tests as f64 / n,
            );
        }
    }
    Ok(out)
}
