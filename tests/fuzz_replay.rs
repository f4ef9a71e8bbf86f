//! Replays the fuzz targets' kept inputs through the same drivers the targets run, so that
//! `cargo test` on stable keeps every finding fixed: `fuzz/regressions/<target>/` (every input
//! that once broke a promise, named for what it caught) and `fuzz/seeds/<target>/` (a small
//! seed set). With `DVH_FUZZ_CORPUS` set to a directory (`scripts/test.sh --full` sets it to
//! `fuzz/corpus`), the full corpora under it (`<dir>/<target>/`, rebuilt by `scripts/fuzz.sh`,
//! never committed) are replayed too.

#[path = "../fuzz/drivers/mod.rs"]
mod drivers;

use std::path::Path;

/// Runs `driver` on every file of the target's kept inputs (and of the full corpus when
/// `DVH_FUZZ_CORPUS` names one, where the target must have a directory); prints what it ran
/// and returns how many.
fn replay(target: &str, driver: fn(&[u8])) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let mut dirs = vec![
        ("regressions", root.join("regressions"), false),
        ("seeds", root.join("seeds"), true),
    ];
    if let Some(corpus) = std::env::var_os("DVH_FUZZ_CORPUS") {
        let corpus = root.parent().expect("the repository").join(corpus);
        dirs.push(("corpus", corpus, true));
    }
    let mut counts = Vec::new();
    for (what, dir, required) in dirs {
        let dir = dir.join(target);
        let entries = match std::fs::read_dir(&dir) {
            Ok(entries) => entries,
            // A target may have no regressions; seeds and a named corpus it must have.
            Err(_) if !required => {
                counts.push(format!("0 {what}"));
                continue;
            }
            Err(e) => panic!("{target}: no {what} at {}: {e}", dir.display()),
        };
        let mut files: Vec<_> = entries
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.is_file() && p.extension().is_none_or(|e| e != "md"))
            .collect();
        files.sort();
        assert!(
            !required || !files.is_empty(),
            "{target}: {} is empty",
            dir.display()
        );
        for f in &files {
            let data = std::fs::read(f).expect("readable input");
            let result = std::panic::catch_unwind(|| driver(&data));
            assert!(result.is_ok(), "{} breaks a promise", f.display());
        }
        counts.push(format!("{} {what}", files.len()));
    }
    println!("fuzz target {target}: replayed {}", counts.join(", "));
    counts
        .iter()
        .map(|c| {
            c.split(' ')
                .next()
                .and_then(|n| n.parse::<usize>().ok())
                .unwrap_or(0)
        })
        .sum()
}

#[test]
fn triangle_oracle_inputs() {
    // Hand-made inputs first: touching at a corner, coplanar overlap, apart.
    let grid = |v: [i8; 18]| -> Vec<u8> { v.iter().flat_map(|&x| [2u8, (x + 2) as u8]).collect() };
    for v in [
        [0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 2, 0, 0, 1, 1, 0],
        [0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 1, 0, -1, 1, 0, 1, -1, 0],
        [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 2, 1, 0, 2, 0, 1, 2],
    ] {
        drivers::triangle_oracle(&grid(v));
    }
    assert!(
        replay("triangle_oracle", drivers::triangle_oracle) > 0,
        "no kept inputs for triangle_oracle"
    );
}

#[test]
fn c_abi_inputs() {
    drivers::c_abi(&[8, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    assert!(
        replay("c_abi", drivers::c_abi) > 0,
        "no kept inputs for c_abi"
    );
}

#[test]
fn scene_inputs() {
    // Two meshes of one triangle, both kinds of object, a query.
    let mesh = [
        2u8, 1, 2, 4, 2, 4, 2, 4, 2, 6, 2, 4, 2, 4, 2, 4, 2, 6, 2, 4, 0, 1, 2, 0, 0, 0, 0, 0,
    ];
    let mut input = vec![2u8];
    input.extend(mesh);
    input.extend(mesh);
    input.extend([0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0]);
    drivers::scene(&input);
    assert!(
        replay("scene", drivers::scene) > 0,
        "no kept inputs for scene"
    );
}

#[test]
fn the_oracle_is_right_on_known_cases() {
    let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let shifted = |d: [f64; 3]| t.map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]]);
    assert!(drivers::oracle(&t, &t));
    assert!(drivers::oracle(&t, &shifted([1.0, 0.0, 0.0]))); // touching at a corner
    assert!(!drivers::oracle(&t, &shifted([1.0 + 1e-12, 0.0, 0.0])));
    assert!(!drivers::oracle(&t, &shifted([0.0, 0.0, 1e-300])));
    // A triangle through another's interior, and a segment (degenerate) through it.
    let upright = [[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.2, 1.0]];
    assert!(drivers::oracle(&t, &upright));
    let needle = [[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.2, 0.2, 1.0]];
    assert!(drivers::oracle(&t, &needle));
    let beside = [[0.6, 0.6, -1.0], [0.6, 0.6, 1.0], [0.6, 0.6, 1.0]];
    assert!(!drivers::oracle(&t, &beside));
}

#[test]
fn self_collision_inputs() {
    // A sheet folded over itself, then queried.
    drivers::self_collision(&[0, 4, 1, 0, 0, 0, 8, 16, 0, 0, 0, 0, 0, 0, 0]);
    assert!(
        replay("self_collision", drivers::self_collision) > 0,
        "no kept inputs for self_collision"
    );
}

#[test]
fn ccd_primitive_inputs() {
    // A point falling through a triangle; two edges crossing; everything at one point.
    drivers::ccd_primitive(&[
        0, 4, 4, 16, 0, 0, 0, 16, 0, 0, 0, 16, 0, 4, 4, 240, 0, 0, 0, 16,
    ]);
    drivers::ccd_primitive(&[
        1, 0, 8, 8, 16, 8, 8, 8, 0, 0, 8, 16, 0, 8, 8, 248, 16, 8, 248,
    ]);
    drivers::ccd_primitive(&[6]);
    assert!(
        replay("ccd_primitive", drivers::ccd_primitive) > 0,
        "no kept inputs for ccd_primitive"
    );
}

#[test]
fn ccd_mesh_inputs() {
    // A sheet folding through itself; a torus with a vertex pushed through.
    drivers::ccd_mesh(&[2, 0, 0, 17, 0, 3, 4, 0, 12, 2]);
    drivers::ccd_mesh(&[1, 0, 2, 3, 8, 8, 8, 0, 0, 1, 1, 1]);
    assert!(
        replay("ccd_mesh", drivers::ccd_mesh) > 0,
        "no kept inputs for ccd_mesh"
    );
}

#[test]
fn nearest_mesh_inputs() {
    // A sheet folded over itself, queried at 1/4; a torus with a vertex pushed in, placed by a
    // quarter turn.
    drivers::nearest_mesh(&[2, 3, 2, 0, 2, 4, 0]);
    drivers::nearest_mesh(&[1, 0, 1, 3, 8, 8, 8, 1, 32, 1, 64, 0, 0, 0, 0]);
    assert!(
        replay("nearest_mesh", drivers::nearest_mesh) > 0,
        "no kept inputs for nearest_mesh"
    );
}

#[test]
fn curves_inputs() {
    // A sheet through a torus turned a quarter; a sphere against a sheet, folded and pinched.
    drivers::curves(&[0, 3, 1, 2, 4, 0, 0, 0, 0, 3, 0, 8, 0, 0, 0]);
    drivers::curves(&[
        2, 1, 0, 4, 1, 8, 8, 8, 1, 5, 2, 8, 4, 0, 1, 2, 7, 3, 9, 0, 1, 0,
    ]);
    assert!(
        replay("curves", drivers::curves) > 0,
        "no kept inputs for curves"
    );
}

#[test]
fn distance_mesh_inputs() {
    // Hand-made inputs first: a torus and a sheet apart, posed, with a bound.
    drivers::distance_mesh(&[1, 0, 0, 2, 0, 0, 16, 16, 16, 0, 1, 3, 40]);
    drivers::distance_mesh(&[2, 1, 9, 0, 3, 0, 0, 0, 8, 1, 1, 4, 7, 1, 4, 3]);
    assert!(
        replay("distance_mesh", drivers::distance_mesh) > 0,
        "no kept inputs for distance_mesh"
    );
}

#[test]
fn points_inputs() {
    // Hand-made inputs first: a torus with points on its grid, two tori through each other.
    drivers::points(&[
        1, 0, 0, 1, 0, 0, 8, 3, 1, 2, 3, 4, 5, 6, 0, 0, 0, 1, 2, 3, 4, 5, 0,
    ]);
    drivers::points(&[
        3, 0, 0, 0, 4, 0, 0, 0, 0, 6, 4, 8, 8, 0, 4, 0, 0, 0, 2, 0, 3, 0,
    ]);
    assert!(
        replay("points", drivers::points) > 0,
        "no kept inputs for points"
    );
}
