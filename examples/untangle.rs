//! Untangling a sheet folded through itself by intersection contour minimisation (Volino and
//! Magnenat-Thalmann 2006): each round, the exact curves along which the sheet crosses itself
//! and the gradient of their length; the vertices step against the gradient, smoothed over the
//! sheet, until no curve is left.
//!
//! The sheet is a square grid whose far half is turned back over the near half, a dent in it
//! poking through the near half: the two layers cross along a closed curve. The curve shrinks
//! as the layers are pushed apart where they cross, and vanishes; the exact self-collision query
//! then confirms that no triangle pair intersects.
//!
//! `cargo run --release --example untangle [-- --cells N] [--rounds K] [--out DIR]`
//!
//! Writes DIR/curves_NNN.obj (the curves of every fifth round, as OBJ polylines),
//! DIR/sheet_start.obj and DIR/sheet_end.obj (the sheet before and after) and DIR/untangle.svg
//! (the curves seen from above at a few rounds, and the curves' total length per round). The
//! default output directory is `target/untangle`.

use dvh::{
    BuildOptions, Curves, Mesh, Pairs, QueryOptions, self_collide, self_intersection_curves,
};
use std::fmt::Write as _;
use std::time::Instant;

/// An untangling's settings.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Cells along each side of the sheet (two triangles each).
    pub cells: usize,
    /// Rounds at most.
    pub rounds: usize,
    /// Where to write the curves, the sheet and the picture (`None`: nowhere).
    pub out: Option<std::path::PathBuf>,
}

/// What an untangling did.
#[derive(Clone, Debug)]
pub struct Report {
    /// The curves' total length before each round, and after the last.
    pub lengths: Vec<f64>,
    /// The number of curves before each round, and after the last.
    pub curves: Vec<usize>,
    /// The intersecting triangle pairs left at the end, by the exact self-collision query.
    pub pairs_left: usize,
    /// Seconds spent in the curve queries (with their gradients).
    pub query_seconds: f64,
    /// The curves of a few rounds, as polylines, for the picture: `(round, polylines)`.
    pub snapshots: Vec<(usize, Vec<Vec<[f64; 3]>>)>,
    /// The sheet's positions at the end, and its triangles.
    pub sheet: (Vec<[f64; 3]>, Vec<[u32; 3]>),
}

/// The folded sheet: vertex positions and triangles. The far half lies over the near half, a
/// little above it, and a dent in it pokes down through the near half.
pub fn folded_sheet(cells: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let n = cells;
    let mut positions = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            let wave = 0.02 * (2.0 * std::f64::consts::PI * y).sin();
            positions.push(if x <= 0.5 {
                [x, y, wave]
            } else {
                // Turned back over the near half: up off the crease, then level 0.08 above it,
                // with a dent 0.16 deep around (0.25, 0.5).
                let u = x - 0.5;
                let fx = 0.5 - 0.9 * u;
                let r2 = (fx - 0.25).powi(2) + (y - 0.5).powi(2);
                let dent = 0.16 * (-r2 / (2.0 * 0.07 * 0.07)).exp();
                [fx, y, wave + 0.08 * (u / 0.05).min(1.0) - dent]
            });
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (positions, triangles)
}

fn flat(p: &[[f64; 3]]) -> Vec<f64> {
    p.iter().flatten().copied().collect()
}

fn polylines(c: &Curves) -> Vec<Vec<[f64; 3]>> {
    (0..c.curves().len())
        .map(|i| {
            let s = c.curve_segments(i);
            s.iter()
                .map(|x| x.start)
                .chain(s.last().map(|x| x.end))
                .collect()
        })
        .collect()
}

/// Untangles the folded sheet as `settings` say.
pub fn untangle(settings: &Settings) -> Report {
    let (mut positions, triangles) = folded_sheet(settings.cells);
    let flat_triangles: Vec<u32> = triangles.iter().flatten().copied().collect();
    let mut mesh = Mesh::new(&flat(&positions), &flat_triangles, &BuildOptions::default())
        .expect("a valid sheet");
    // Each vertex's neighbours, for smoothing the step over the sheet.
    let mut neighbours = vec![Vec::new(); positions.len()];
    for t in &triangles {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            if !neighbours[a].contains(&b) {
                neighbours[a].push(b);
                neighbours[b].push(a);
            }
        }
    }
    let edge = 1.0 / settings.cells as f64;
    let start = positions.clone();
    let options = QueryOptions::default();
    let mut curves = Curves::new();
    let mut gradient = vec![[0.0; 3]; positions.len()];
    let mut step = vec![[0.0; 3]; positions.len()];
    let mut report = Report {
        lengths: Vec::new(),
        curves: Vec::new(),
        pairs_left: 0,
        query_seconds: 0.0,
        snapshots: Vec::new(),
        sheet: (Vec::new(), Vec::new()),
    };
    for round in 0..=settings.rounds {
        let t0 = Instant::now();
        self_intersection_curves(&mesh, &options, &mut curves).expect("curves");
        curves
            .self_length_gradient(&mesh, &mut gradient)
            .expect("gradient");
        report.query_seconds += t0.elapsed().as_secs_f64();
        let length: f64 = (0..curves.curves().len())
            .map(|i| curves.curve_length(i))
            .sum();
        report.lengths.push(length);
        report.curves.push(curves.curves().len());
        if round % 5 == 0 || curves.is_empty() {
            report.snapshots.push((round, polylines(&curves)));
            if let Some(dir) = &settings.out {
                write_curves(&dir.join(format!("curves_{round:03}.obj")), &curves);
            }
        }
        if curves.is_empty() || round == settings.rounds {
            break;
        }
        // The step: against the gradient, spread over the neighbours by a few smoothing passes
        // (so that the sheet moves as a sheet, not as spikes at the curves), scaled so that the
        // largest move is a fifth of an edge.
        for (s, g) in step.iter_mut().zip(&gradient) {
            *s = g.map(|x| -x);
        }
        for _ in 0..4 {
            let prev = step.clone();
            for (v, s) in step.iter_mut().enumerate() {
                let nb = &neighbours[v];
                for k in 0..3 {
                    let mean = nb.iter().map(|&w| prev[w][k]).sum::<f64>() / nb.len() as f64;
                    s[k] = 0.5 * prev[v][k] + 0.5 * mean;
                }
            }
        }
        let largest = step
            .iter()
            .map(|s| (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt())
            .fold(0.0, f64::max);
        if largest == 0.0 {
            break;
        }
        let scale = 0.2 * edge / largest;
        for (p, s) in positions.iter_mut().zip(&step) {
            for k in 0..3 {
                p[k] += scale * s[k];
            }
        }
        mesh.refit(&flat(&positions)).expect("finite positions");
    }
    let mut pairs = Pairs::new();
    self_collide(&mesh, &options, &mut pairs).expect("self-collision");
    report.pairs_left = pairs.len();
    if let Some(dir) = &settings.out {
        write_sheet(&dir.join("sheet_start.obj"), &start, &triangles);
        write_sheet(&dir.join("sheet_end.obj"), &positions, &triangles);
        std::fs::write(dir.join("untangle.svg"), picture(&report)).expect("write the picture");
    }
    report.sheet = (positions, triangles);
    report
}

fn write_curves(path: &std::path::Path, curves: &Curves) {
    let mut s = String::new();
    let mut base = 1;
    for (line, closed) in polylines(curves)
        .iter()
        .zip(curves.curves().iter().map(|c| c.closed))
    {
        let points = if closed {
            &line[..line.len() - 1]
        } else {
            &line[..]
        };
        for p in points {
            let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
        }
        let mut idx: Vec<usize> = (base..base + points.len()).collect();
        if closed {
            idx.push(base);
        }
        let idx: Vec<String> = idx.iter().map(|i| i.to_string()).collect();
        let _ = writeln!(s, "l {}", idx.join(" "));
        base += points.len();
    }
    std::fs::write(path, s).expect("write the curves");
}

fn write_sheet(path: &std::path::Path, positions: &[[f64; 3]], triangles: &[[u32; 3]]) {
    let mut s = String::new();
    for p in positions {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
    }
    for t in triangles {
        let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(path, s).expect("write the sheet");
}

/// The curves seen from above (x right, y up) at the snapshots' rounds, darker the later, and
/// the total length per round.
fn picture(report: &Report) -> String {
    let (w, h) = (760.0, 400.0);
    let mut svg = format!(
        "<svg xmlns='http://www.w3.org/2000/svg' width='{w}' height='{h}' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
    );
    let (x0, y0, side) = (30.0, 40.0, 320.0);
    let _ = writeln!(
        svg,
        "<text x='{x0}' y='24'>intersection curves from above (rounds {})</text>",
        report
            .snapshots
            .iter()
            .map(|(r, _)| r.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        svg,
        "<rect x='{x0}' y='{y0}' width='{side}' height='{side}' fill='none' stroke='#999'/>"
    );
    let n = report.snapshots.len().max(1);
    for (k, (_, lines)) in report.snapshots.iter().enumerate() {
        let shade = 200 - (180 * k / n) as u32;
        for line in lines {
            let _ = write!(
                svg,
                "<path fill='none' stroke='rgb({shade},{},{})' stroke-width='1.5' d='",
                shade / 3,
                shade / 3
            );
            for (i, p) in line.iter().enumerate() {
                let (x, y) = (x0 + p[0] * side, y0 + (1.0 - p[1]) * side);
                let _ = write!(svg, "{}{x:.1},{y:.1}", if i == 0 { "M" } else { "L" });
            }
            let _ = writeln!(svg, "'/>");
        }
    }
    let (px, py, pw, ph) = (400.0, y0, 330.0, side);
    let max = report
        .lengths
        .iter()
        .copied()
        .fold(0.0, f64::max)
        .max(1e-12);
    let _ = writeln!(
        svg,
        "<text x='{px}' y='24'>total curve length per round (max {max:.3})</text>\n<rect x='{px}' y='{py}' width='{pw}' height='{ph}' fill='none' stroke='#999'/>"
    );
    let _ = write!(svg, "<path stroke='#1f77b4' fill='none' d='");
    let last = (report.lengths.len().max(2) - 1) as f64;
    for (i, l) in report.lengths.iter().enumerate() {
        let (x, y) = (px + pw * i as f64 / last, py + ph * (1.0 - l / max));
        let _ = write!(svg, "{}{x:.1},{y:.1}", if i == 0 { "M" } else { "L" });
    }
    let _ = writeln!(svg, "'/>\n</svg>");
    svg
}

#[allow(dead_code)] // the tests include this file for `untangle` alone
fn main() {
    let mut settings = Settings {
        cells: 40,
        rounds: 400,
        out: Some("target/untangle".into()),
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--cells" => settings.cells = value.parse().expect("--cells N"),
            "--rounds" => settings.rounds = value.parse().expect("--rounds K"),
            "--out" => settings.out = Some(value.into()),
            other => panic!("unknown argument {other}"),
        }
        i += 2;
    }
    if let Some(dir) = &settings.out {
        std::fs::create_dir_all(dir).expect("create the output directory");
    }
    let r = untangle(&settings);
    let rounds = r.lengths.len() - 1;
    println!(
        "{} cells a side: {} curves of total length {:.4} at the start; after {rounds} rounds {} curves, {} intersecting pairs left",
        settings.cells, r.curves[0], r.lengths[0], r.curves[rounds], r.pairs_left
    );
    println!(
        "curve queries with their gradients: {:.1} ms a round",
        1e3 * r.query_seconds / (rounds + 1) as f64
    );
    if let Some(dir) = &settings.out {
        println!(
            "wrote {}/curves_NNN.obj, sheet_start.obj, sheet_end.obj, untangle.svg",
            dir.display()
        );
    }
}
