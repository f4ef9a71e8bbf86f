//! Replays the fuzz targets' kept inputs (`fuzz/corpus/<target>/`, a minimised corpus, and
//! `fuzz/regressions/<target>/`, every input that once broke a promise) through the same drivers
//! the targets run, so that `cargo test` on stable keeps every finding fixed.

#[path = "../fuzz/drivers/mod.rs"]
mod drivers;

use std::path::Path;

/// Runs `driver` on every file under `fuzz/<kind>/<target>/` for each kind; returns how many.
fn replay(target: &str, driver: fn(&[u8])) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let mut n = 0;
    for kind in ["corpus", "regressions"] {
        let Ok(dir) = std::fs::read_dir(root.join(kind).join(target)) else {
            continue;
        };
        let mut files: Vec<_> = dir.flatten().map(|e| e.path()).collect();
        files.sort();
        for f in files {
            let data = std::fs::read(&f).expect("readable input");
            let result = std::panic::catch_unwind(|| driver(&data));
            assert!(result.is_ok(), "{} breaks a promise", f.display());
            n += 1;
        }
    }
    n
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
    replay("triangle_oracle", drivers::triangle_oracle);
}

#[test]
fn c_abi_inputs() {
    drivers::c_abi(&[8, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    replay("c_abi", drivers::c_abi);
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
    replay("scene", drivers::scene);
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
    replay("self_collision", drivers::self_collision);
}
