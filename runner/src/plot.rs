//! SVG plots: time per frame over a run (the paper's Figures 8-10), dvh against its peers, the
//! time/precision trade of the knobs with its Pareto front, and query time against budget.

use crate::knobs::Row;
use crate::paper::MethodRun;
use crate::report::median;
use dvh::{QueryMode, VolumeKind};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::error::Error;
use std::path::Path;

type Result = std::result::Result<(), Box<dyn Error>>;

const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Draws the legend box every plot uses at `position`.
fn legend<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'a>, CT>,
    position: SeriesLabelPosition,
) -> Result {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(position)
        .draw()?;
    Ok(())
}

/// Time per frame of some runs, one line each, on one panel.
fn lines(
    area: &DrawingArea<SVGBackend, Shift>,
    title: &str,
    runs: &[&MethodRun],
    log: bool,
) -> Result {
    let frames = runs
        .iter()
        .map(|r| r.refit_ms.len())
        .max()
        .unwrap_or(1)
        .max(2);
    let all: Vec<f64> = runs.iter().flat_map(|r| r.totals()).collect();
    let hi = all.iter().copied().fold(0.0f64, f64::max) * 1.1;
    let lo = all.iter().copied().fold(f64::INFINITY, f64::min).max(1e-3) * 0.8;
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(55);
    let x = 0f64..(frames - 1) as f64;
    macro_rules! draw {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc("frame")
                .y_desc("refit + query per frame (ms)")
                .draw()?;
            for (k, r) in runs.iter().enumerate() {
                let colour = COLOURS[k % COLOURS.len()];
                chart
                    .draw_series(LineSeries::new(
                        r.totals()
                            .into_iter()
                            .enumerate()
                            .map(|(f, t)| (f as f64, t)),
                        colour.stroke_width(2),
                    ))?
                    .label(r.name.trim_start_matches("dvh "))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                    });
            }
            legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        }};
    }
    if log {
        draw!(builder.build_cartesian_2d(x, (lo..hi).log_scale())?);
    } else {
        draw!(builder.build_cartesian_2d(x, 0f64..hi)?);
    }
    Ok(())
}

/// Of the dvh runs of one volume kind and tree, the one with the lowest median time.
fn best<'r>(runs: &'r [MethodRun], prefix: &str) -> Option<&'r MethodRun> {
    runs.iter()
        .filter(|r| r.name.starts_with(prefix))
        .min_by(|a, b| a.total().total_cmp(&b.total()))
}

/// The paper's figure for one scene: octree on the left, binary tree on the right, the best
/// radius of each volume kind.
pub fn paper_figure(path: &Path, scene: &str, runs: &[MethodRun]) -> Result {
    let root = SVGBackend::new(path, (1200, 460)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, 2));
    for (panel, tree) in panels.iter().zip(["octree", "binary"]) {
        let chosen: Vec<&MethodRun> = ["AABB", "DVH", "SBV"]
            .iter()
            .filter_map(|v| best(runs, &format!("dvh {v} {tree}")))
            .collect();
        lines(panel, &format!("{scene}: {tree}"), &chosen, false)?;
    }
    root.present()?;
    Ok(())
}

/// dvh's fastest method against FCL and parry over the run (logarithmic time axis).
pub fn peers_figure(path: &Path, scene: &str, runs: &[MethodRun]) -> Result {
    let root = SVGBackend::new(path, (800, 460)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chosen: Vec<&MethodRun> = best(runs, "dvh").into_iter().collect();
    chosen.extend(runs.iter().filter(|r| !r.name.starts_with("dvh")));
    lines(&root, &format!("{scene}: dvh and its peers"), &chosen, true)?;
    root.present()?;
    Ok(())
}

fn volume_name(v: VolumeKind) -> &'static str {
    match v {
        VolumeKind::Dvh => "DVH",
        VolumeKind::Sbv => "SBV",
        VolumeKind::Aabb => "AABB",
        // A kind newer than this runner.
        _ => "?",
    }
}

/// Time per frame against precision for every option and conservative mode of one scene, by
/// volume kind, with the Pareto front (no point both faster and more precise).
pub fn pareto_figure(path: &Path, scene: &str, rows: &[Row]) -> Result {
    let points: Vec<(f64, f64, VolumeKind)> = rows
        .iter()
        .filter(|r| r.conservative())
        .map(|r| {
            (
                r.precision().max(1e-12),
                r.time().max(1e-3),
                r.options.volume,
            )
        })
        .collect();
    let px_lo = points.iter().map(|p| p.0).fold(1.0f64, f64::min) * 0.5;
    let t_lo = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min) * 0.8;
    let t_hi = points.iter().map(|p| p.1).fold(0.0f64, f64::max) * 1.25;
    let root = SVGBackend::new(path, (800, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{scene}: time against precision"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d((px_lo..1.5).log_scale(), (t_lo..t_hi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("precision (share of covered triangle pairs that intersect)")
        .y_desc("refit + query per frame (ms)")
        .draw()?;
    for (k, v) in [VolumeKind::Dvh, VolumeKind::Sbv, VolumeKind::Aabb]
        .into_iter()
        .enumerate()
    {
        let colour = COLOURS[k];
        chart
            .draw_series(
                points
                    .iter()
                    .filter(|p| p.2 == v)
                    .map(|p| Circle::new((p.0, p.1), 3, colour.filled())),
            )?
            .label(volume_name(v))
            .legend(move |(x, y)| Circle::new((x + 9, y), 3, colour.filled()));
    }
    // The front: by decreasing precision, each point faster than every more precise one.
    let mut sorted = points.clone();
    sorted.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.total_cmp(&b.1)));
    let mut front = Vec::new();
    let mut fastest = f64::INFINITY;
    for p in sorted {
        if p.1 < fastest {
            fastest = p.1;
            front.push((p.0, p.1));
        }
    }
    chart
        .draw_series(LineSeries::new(front, BLACK.stroke_width(1)))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK));
    legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present()?;
    Ok(())
}

/// Query time per frame against the budget, one line per scene, for one set of options
/// (logarithmic axes: a line of slope 1 is linear growth).
pub fn budget_figure(path: &Path, rows: &[Row], options: &dvh::BuildOptions) -> Result {
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.scene).collect();
    scenes.dedup();
    let series: Vec<(&str, Vec<(f64, f64)>)> = scenes
        .iter()
        .map(|s| {
            let pts = rows
                .iter()
                .filter(|r| r.scene == *s && r.options == *options)
                .filter_map(|r| match r.mode {
                    QueryMode::Budget(b) => Some((b as f64, median(&r.query_ms).max(1e-4))),
                    _ => None,
                })
                .collect();
            (*s, pts)
        })
        .collect();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.1.clone()).collect();
    if all.is_empty() {
        return Ok(());
    }
    let (b_lo, b_hi) = all.iter().fold((f64::INFINITY, 0.0f64), |(l, h), p| {
        (l.min(p.0), h.max(p.0))
    });
    let (t_lo, t_hi) = all.iter().fold((f64::INFINITY, 0.0f64), |(l, h), p| {
        (l.min(p.1), h.max(p.1))
    });
    let root = SVGBackend::new(path, (800, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("query time against budget", ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(
            (b_lo * 0.8..b_hi * 1.25).log_scale(),
            (t_lo * 0.8..t_hi * 1.25).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("budget (volume tests per object pair)")
        .y_desc("query time per frame (ms)")
        .draw()?;
    for (k, (s, pts)) in series.into_iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        chart
            .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))?
            .label(s)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
            });
        chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 3, colour.filled())))?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present()?;
    Ok(())
}
