//! A slice of the signed distance field of a deforming mesh, drawn as a picture each frame.
//!
//! A sphere wobbles (its vertices moved radially by travelling waves); each frame the mesh is
//! refit, and the signed distances of a grid of points in the plane z = 0 are computed exactly
//! (negative inside, by the exact winding number; the distance within a unit in the last place)
//! and drawn: blue inside, orange outside, bands every 0.1, black on the surface.
//!
//! `cargo run --release --example sdf_slice [-- --size N] [--frames K] [--out DIR]`
//!
//! Writes DIR/slice_NNN.ppm (binary PPM, N x N pixels) for every frame and prints the time of each
//! frame's refit and query. The default output directory is `target/sdf_slice`.

use dvh::fixtures::icosphere;
use dvh::{BuildOptions, DistanceOptions, Mesh, QueryStats, signed_distances};
use std::time::Instant;

/// A run's settings.
#[derive(Clone, Debug)]
pub struct Settings {
    /// Pixels along each side of the slice.
    pub size: usize,
    /// Frames.
    pub frames: usize,
    /// Where to write the pictures (`None`: nowhere).
    pub out: Option<std::path::PathBuf>,
}

/// What a run computed.
#[derive(Clone, Debug)]
pub struct Report {
    /// The slice's points (x, y, 0), row by row from the top.
    pub points: Vec<[f64; 3]>,
    /// Each frame's positions and signed distances of the points.
    pub frames: Vec<(Vec<f64>, Vec<f64>)>,
    /// The mesh's triangles.
    pub triangles: Vec<u32>,
    /// The counters of the last frame's query.
    pub stats: QueryStats,
}

/// The half-width of the square slice.
const EXTENT: f64 = 1.6;

/// The sphere's vertices at frame time `t`: moved along their radius by travelling waves.
fn wobble(rest: &[f64], t: f64) -> Vec<f64> {
    rest.chunks_exact(3)
        .flat_map(|v| {
            let r = 1.0
                + 0.25 * (3.0 * v[0] + 2.0 * t).sin() * (2.0 * v[1]).cos()
                + 0.1 * (5.0 * v[2] - t).sin();
            [v[0] * r, v[1] * r, v[2] * r]
        })
        .collect()
}

/// The colour of a signed distance `d` for pixels `pixel` wide.
fn colour(d: f64, pixel: f64) -> [u8; 3] {
    if d.abs() <= 0.5 * pixel {
        return [0, 0, 0];
    }
    let band = if (d.abs() / 0.1).fract() < 0.15 {
        0.75
    } else {
        1.0
    };
    let fade = (1.0 - d.abs().min(1.5) / 1.5) * 0.7 + 0.3;
    let (r, g, b) = if d < 0.0 {
        (0.2, 0.45, 1.0)
    } else {
        (1.0, 0.6, 0.2)
    };
    [r, g, b].map(|c| (255.0 * c * fade * band) as u8)
}

/// Runs the wobbling sphere for `settings.frames` frames.
pub fn run(settings: &Settings) -> Result<Report, Box<dyn std::error::Error>> {
    let sphere = icosphere(4);
    let n = settings.size;
    let pixel = 2.0 * EXTENT / n as f64;
    let points: Vec<[f64; 3]> = (0..n * n)
        .map(|i| {
            let (row, col) = (i / n, i % n);
            [
                -EXTENT + (col as f64 + 0.5) * pixel,
                EXTENT - (row as f64 + 0.5) * pixel,
                0.0,
            ]
        })
        .collect();
    let mut mesh = Mesh::new(
        &wobble(&sphere.positions, 0.0),
        &sphere.triangles,
        &BuildOptions::default(),
    )?;
    if let Some(dir) = &settings.out {
        std::fs::create_dir_all(dir)?;
    }
    let mut signed = vec![0.0; points.len()];
    let mut frames = Vec::new();
    let mut stats = QueryStats::default();
    for f in 0..settings.frames {
        let positions = wobble(&sphere.positions, f as f64 * 0.4);
        let start = Instant::now();
        mesh.refit(&positions)?;
        let refit = start.elapsed();
        stats = signed_distances(
            &mesh,
            None,
            &points,
            &DistanceOptions::default(),
            &mut signed,
        )?;
        let query = start.elapsed() - refit;
        println!(
            "frame {f}: refit {:.2} ms, {} signed distances {:.1} ms ({:.2} M points/s, {:.1} exact triangle tests a point)",
            refit.as_secs_f64() * 1e3,
            points.len(),
            query.as_secs_f64() * 1e3,
            points.len() as f64 / query.as_secs_f64() / 1e6,
            stats.triangle_tests as f64 / points.len() as f64
        );
        if let Some(dir) = &settings.out {
            let mut ppm = format!("P6\n{n} {n}\n255\n").into_bytes();
            for d in &signed {
                ppm.extend(colour(*d, pixel));
            }
            std::fs::write(dir.join(format!("slice_{f:03}.ppm")), ppm)?;
        }
        frames.push((positions, signed.clone()));
    }
    Ok(Report {
        points,
        frames,
        triangles: sphere.triangles,
        stats,
    })
}

#[allow(dead_code)] // the test runs `run` alone
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut settings = Settings {
        size: 256,
        frames: 8,
        out: Some("target/sdf_slice".into()),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--size" => settings.size = value()?.parse()?,
            "--frames" => settings.frames = value()?.parse()?,
            "--out" => settings.out = Some(value()?.into()),
            _ => return Err(format!("unknown argument {a}").into()),
        }
    }
    run(&settings)?;
    if let Some(dir) = &settings.out {
        println!("pictures in {}", dir.display());
    }
    Ok(())
}
