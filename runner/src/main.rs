//! dvh-runner: the paper's experiment and the knob measurements, with FCL and parry measured in
//! the same run, as tables (printed, and written as Markdown and CSV) and SVG plots.
//!
//! ```text
//! dvh-runner [paper|knobs|exactness|rigid|all|checksums|profile|scenes|self|distance] [--full] [--scene NAME]...
//!            [--frames N] [--knob-frames N] [--repeat N] [--threads N] [--pause MS] [--out DIR]
//! ```
//!
//! - `paper`: the paper's three scenes (or those named): every method (dvh with each volume x
//!   tree x radius kind, FCL's two configurations, parry) refits every object and queries every
//!   object pair, every frame; medians per frame, counters, pairs against the exact ones, ratios,
//!   and the time-per-frame figures.
//! - `knobs`: every volume x tree x radius kind and every query mode (exact, first hit, leaves,
//!   each depth, budgets) on the paper's scenes and the dense-contact ones: time per frame,
//!   recall, precision, object-level answers, the time/precision plot and the budget plot.
//! - `exactness`: on the exact query's candidate pairs, the share the floating-point filter
//!   leaves undecided, and Möller's floating-point test against the exact one.
//! - `rigid`: the first scene's objects rigid (never refit), placed by poses: each volume kind's
//!   query time, for the other kind of scene.
//! - `all`: all of these; `checksums`: a hash of every scene's world coordinates at its first and
//!   last frame, to compare with the cross-check harness's (`dvh_cross_check --checksums`).
//! - `self`: self-collision against the naive route (the mesh against itself, then filtered)
//!   and self-proximity at three distances, on a folding sheet and a bent scanned mesh.
//! - `distance`: the least distance of each object pair of the scenes, as the objects move and
//!   moved apart: dvh (exact, and with `rel_err = 0.01`) against parry's `query::distance`, per
//!   frame refit + query; times and parry's differences from dvh's exact answers.
//! - `profile`: dvh alone, default options, on `--threads` threads (default 1): each of
//!   `--frames` frames (default 10) spread over the scene's run, refit and queried `--repeat`
//!   times (default 5); the mean over frames of each frame's fastest refit and query. For
//!   timing one build against another on the same frames, and for `perf record`. `--pause MS`
//!   idles before each repetition, so that the cores start cold, as after other work.
//!
//! Without `--full`, small meshes and few frames (the short run the test suite makes); with it,
//! the paper's sizes and 200 frames. Debian's CGAL demo meshes are used when installed
//! (`libcgal-demo`), built-in meshes otherwise. Output goes to `--out` (default
//! `target/dvh-runner`): `summary.md`, CSV files and SVG plots.

mod distance;
mod exactness;
#[cfg(fcl)]
mod fcl;
mod knobs;
mod method;
mod moller;
mod paper;
mod peer_parry;
mod plot;
mod profile;
mod report;
mod rigid;
mod scene;
mod scenes;
mod self_scenes;

use method::Method;
use scene::{Scene, Size};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Command {
    Paper,
    Knobs,
    Exactness,
    Rigid,
    All,
    Checksums,
    Profile,
    Scenes,
    SelfCollision,
    Distance,
}

struct Args {
    command: Command,
    size: Size,
    scenes: Vec<String>,
    knob_frames: usize,
    repeat: usize,
    threads: u32,
    pause_ms: u64,
    out: PathBuf,
    /// `self` without its proximity rows.
    no_proximity: bool,
}

fn usage() -> String {
    "usage: dvh-runner [paper|knobs|exactness|rigid|all|checksums|profile|scenes|self|distance] [--full] \
     [--scene NAME]... [--frames N] [--knob-frames N] [--repeat N] [--threads N] [--pause MS] [--out DIR] [--no-proximity]"
        .to_string()
}

/// The value of option `name` as a number.
fn number<T: std::str::FromStr>(name: &str, value: String) -> Result<T, String>
where
    T::Err: std::fmt::Display,
{
    value.parse().map_err(|e| format!("{name}: {e}"))
}

fn parse() -> Result<Args, String> {
    let mut args = Args {
        command: Command::All,
        size: Size {
            full: false,
            frames: 0,
        },
        scenes: Vec::new(),
        knob_frames: 0,
        repeat: 5,
        threads: 1,
        pause_ms: 0,
        out: PathBuf::from("target/dvh-runner"),
        no_proximity: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "paper" => args.command = Command::Paper,
            "knobs" => args.command = Command::Knobs,
            "exactness" => args.command = Command::Exactness,
            "rigid" => args.command = Command::Rigid,
            "all" => args.command = Command::All,
            "checksums" => args.command = Command::Checksums,
            "profile" => args.command = Command::Profile,
            "scenes" => args.command = Command::Scenes,
            "self" => args.command = Command::SelfCollision,
            "distance" => args.command = Command::Distance,
            "--full" => args.size.full = true,
            "--scene" => args.scenes.push(value("--scene")?),
            "--frames" => args.size.frames = number("--frames", value("--frames")?)?,
            "--knob-frames" => args.knob_frames = number("--knob-frames", value("--knob-frames")?)?,
            "--repeat" => args.repeat = number("--repeat", value("--repeat")?)?,
            "--threads" => args.threads = number("--threads", value("--threads")?)?,
            "--pause" => args.pause_ms = number("--pause", value("--pause")?)?,
            "--out" => args.out = PathBuf::from(value("--out")?),
            "--no-proximity" => args.no_proximity = true,
            "-h" | "--help" => return Err(usage()),
            other => return Err(format!("unknown argument {other:?}\n{}", usage())),
        }
    }
    for s in &args.scenes {
        if args.command == Command::SelfCollision {
            if !self_scenes::NAMES.contains(&s.as_str()) {
                return Err(format!(
                    "unknown scene {s:?} for self: one of {:?}",
                    self_scenes::NAMES
                ));
            }
        } else if !scene::EVERY.contains(&s.as_str()) && !scene::EXTRA.contains(&s.as_str()) {
            return Err(format!(
                "unknown scene {s:?}: one of {:?} or {:?}",
                scene::EVERY,
                scene::EXTRA
            ));
        }
    }
    Ok(args)
}

/// `count` frames spread evenly over the scene's run.
fn spread(scene: &Scene, count: usize) -> Vec<usize> {
    let count = count.clamp(1, scene.frames);
    (0..count).map(|k| k * scene.frames / count).collect()
}

/// The methods of the paper's comparison: dvh on one thread with every volume x tree x radius
/// kind first (the first is exact and serves as the reference), the defaults on every core,
/// then the peers (one thread each).
fn methods() -> Vec<Box<dyn Method>> {
    let mut all: Vec<Box<dyn Method>> = knobs::options()
        .into_iter()
        .map(|o| Box::new(method::Dvh::new(o)) as Box<dyn Method>)
        .collect();
    all.push(Box::new(method::Dvh::threaded(
        dvh::BuildOptions::default(),
        0,
    )));
    #[cfg(fcl)]
    {
        all.push(Box::new(fcl::Fcl::new(fcl::Kind::Obbrss)));
        all.push(Box::new(fcl::Fcl::new(fcl::Kind::Aabb)));
    }
    all.push(Box::new(peer_parry::Parry::default()));
    all
}

fn heading(summary: &mut String, scene: &Scene) {
    let _ = writeln!(
        summary,
        "\n### {}: {}, {} frames{}\n",
        scene.name,
        scene.description,
        scene.frames,
        if scene.built_in {
            " (built-in meshes: Debian's CGAL data is not installed)"
        } else {
            ""
        }
    );
}

fn run(args: &Args) -> Result<bool, Box<dyn std::error::Error>> {
    std::fs::create_dir_all(&args.out)?;
    let mut summary = String::new();
    let mut ok = true;
    let pick = |defaults: &[&'static str]| -> Vec<String> {
        if args.scenes.is_empty() {
            defaults.iter().map(|s| s.to_string()).collect()
        } else {
            args.scenes.clone()
        }
    };
    let _ = writeln!(
        summary,
        "# dvh-runner {} run, dvh {}{}",
        if args.size.full { "full" } else { "short" },
        env!("CARGO_PKG_VERSION"),
        if cfg!(fcl) {
            ""
        } else {
            " (FCL not installed: not measured)"
        }
    );

    if args.command == Command::Checksums {
        for name in pick(&scene::EVERY) {
            let s = scene::make(&name, args.size).expect("a known scene");
            let mut world = vec![Vec::new(); s.objects.len()];
            for f in [0, s.frames - 1] {
                s.world(f, &mut world);
                println!("{} frame {f}: {:016x}", s.name, scene::checksum(&world));
            }
        }
        return Ok(true);
    }

    if args.command == Command::Scenes {
        let frames = if args.size.frames > 0 {
            args.size.frames
        } else {
            10
        };
        print!(
            "{}",
            scenes::run(args.size, frames, args.repeat, args.threads)?
        );
        return Ok(true);
    }
    if args.command == Command::Distance {
        print!("{}", distance::table(args.size, &args.scenes)?);
        return Ok(true);
    }
    if args.command == Command::SelfCollision {
        let frames = if args.size.frames > 0 {
            args.size.frames
        } else if args.size.full {
            200
        } else {
            4
        };
        print!(
            "{}",
            self_scenes::run(
                args.size,
                &args.scenes,
                frames,
                args.repeat,
                args.threads,
                !args.no_proximity
            )?
        );
        return Ok(true);
    }
    if args.command == Command::Profile {
        let frames = if args.size.frames > 0 {
            args.size.frames
        } else {
            10
        };
        let mut full = args.size;
        full.frames = 0;
        println!("Per frame: the mean over frames of each frame's fastest repetition.\n");
        println!(
            "| scene | frames x repeat | threads | refit ms | query ms | pairs | volume tests | \
             leaf pairs | triangle tests |"
        );
        println!("|---|---|---|---|---|---|---|---|---|");
        for name in pick(&scene::EVERY) {
            let s = scene::make(&name, full).expect("a known scene");
            let chosen = spread(&s, frames);
            let pause = std::time::Duration::from_millis(args.pause_ms);
            let p = profile::run(&s, &chosen, args.repeat, args.threads, pause)?;
            let n = chosen.len() as f64;
            println!(
                "| {} | {} x {} | {} | {:.3} | {:.3} | {:.0} | {:.0} | {:.0} | {:.0} |",
                s.name,
                chosen.len(),
                args.repeat,
                args.threads,
                profile::mean(&p.refit_ms),
                profile::mean(&p.query_ms),
                p.pairs as f64 / n,
                p.bv_tests as f64 / n,
                p.leaf_pairs as f64 / n,
                p.triangle_tests as f64 / n
            );
        }
        return Ok(true);
    }

    if matches!(args.command, Command::Paper | Command::All) {
        let _ = writeln!(summary, "\n## The paper's scenes, every method\n");
        for name in pick(&scene::PAPER) {
            let s = scene::make(&name, args.size).expect("a known scene");
            eprintln!(
                "paper: {} ({} triangles, {} frames)",
                s.name,
                s.triangles(),
                s.frames
            );
            let mut ms = methods();
            let runs = paper::run(&s, &mut ms);
            let table = paper::table(&runs);
            heading(&mut summary, &s);
            summary.push_str(&table.markdown());
            println!("\n{}: {}\n{}", s.name, s.description, table.markdown());
            table.write_csv(&args.out.join(format!("paper-{}.csv", s.name)))?;
            plot::paper_figure(
                &args.out.join(format!("paper-{}.svg", s.name)),
                s.name,
                &runs,
            )?;
            plot::peers_figure(
                &args.out.join(format!("peers-{}.svg", s.name)),
                s.name,
                &runs,
            )?;
            for r in runs.iter().filter(|r| r.name.starts_with("dvh")) {
                if r.missed != 0 || r.extra != 0 {
                    eprintln!(
                        "ERROR: {} differs from the exact pairs on {}: {} missed, {} extra",
                        r.name, s.name, r.missed, r.extra
                    );
                    ok = false;
                }
            }
        }
    }

    if matches!(args.command, Command::Knobs | Command::All) {
        let _ = writeln!(summary, "\n## What each knob buys\n");
        let frames = if args.knob_frames > 0 {
            args.knob_frames
        } else if args.size.full {
            8
        } else {
            2
        };
        let mut all_rows = Vec::new();
        for name in pick(&scene::ALL) {
            let s = scene::make(&name, args.size).expect("a known scene");
            let chosen = spread(&s, frames);
            eprintln!(
                "knobs: {} ({} frames of {})",
                s.name,
                chosen.len(),
                s.frames
            );
            let rows = knobs::run(&s, &chosen, &knobs::options());
            heading(&mut summary, &s);
            let options = knobs::options_table(&rows);
            let modes = knobs::modes_table(&rows, &dvh::BuildOptions::default());
            let _ = writeln!(summary, "Per option:\n\n{}", options.markdown());
            let _ = writeln!(
                summary,
                "\nEvery mode, default options:\n\n{}",
                modes.markdown()
            );
            println!("\n{} per option\n{}", s.name, options.markdown());
            println!(
                "{} every mode, default options\n{}",
                s.name,
                modes.markdown()
            );
            plot::pareto_figure(
                &args.out.join(format!("pareto-{}.svg", s.name)),
                s.name,
                &rows,
            )?;
            all_rows.extend(rows);
        }
        knobs::full_table(&all_rows).write_csv(&args.out.join("knobs.csv"))?;
        plot::budget_figure(
            &args.out.join("budget.svg"),
            &all_rows,
            &dvh::BuildOptions::default(),
        )?;
    }

    if matches!(args.command, Command::Rigid | Command::All) {
        let s = scene::make("many", args.size).expect("a known scene");
        eprintln!("rigid: {} (posed, never refit)", s.name);
        let table = rigid::table(&rigid::run(&s));
        let _ = writeln!(
            summary,
            "\n## Rigid objects: the first scene without deformation, placed by poses ({} frames)\n\n{}",
            s.frames,
            table.markdown()
        );
        println!("\nrigid {}\n{}", s.name, table.markdown());
    }

    if matches!(args.command, Command::Exactness | Command::All) {
        let frames = if args.size.full { 5 } else { 2 };
        let mut results = Vec::new();
        for name in pick(&scene::EVERY) {
            let s = scene::make(&name, args.size).expect("a known scene");
            eprintln!("exactness: {}", s.name);
            results.push(exactness::run(&s, &spread(&s, frames)));
        }
        let table = exactness::table(&results);
        let _ = writeln!(
            summary,
            "\n## What exactness costs (default options, {frames} frames per scene)\n\n{}",
            table.markdown()
        );
        println!("\nexactness\n{}", table.markdown());
    }

    std::fs::write(args.out.join("summary.md"), summary)?;
    eprintln!("wrote {}", args.out.display());
    Ok(ok)
}

fn main() -> ExitCode {
    let args = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    match run(&args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
