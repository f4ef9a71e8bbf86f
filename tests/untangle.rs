//! The untangling example's short form: a small folded sheet, a dent of it through the other
//! layer, comes apart by following the gradient of its intersection curves' length until no
//! curve is left, as the exact self-collision query and a brute force over every triangle pair
//! confirm.

#[path = "../examples/untangle.rs"]
#[allow(dead_code)]
mod untangle;

use dvh::fixtures::oracle::self_collide_brute_force;
use dvh::{BuildOptions, Mesh};
use untangle::{Settings, folded_sheet, untangle};

#[test]
fn a_folded_sheet_comes_apart_along_its_curves() {
    let settings = Settings {
        cells: 16,
        rounds: 200,
        out: None,
    };
    // The start is tangled, by brute force too.
    let (start, triangles) = folded_sheet(settings.cells);
    let flat_triangles: Vec<u32> = triangles.iter().flatten().copied().collect();
    let mesh = |p: &[[f64; 3]]| {
        let flat: Vec<f64> = p.iter().flatten().copied().collect();
        Mesh::new(&flat, &flat_triangles, &BuildOptions::default()).unwrap()
    };
    assert!(!self_collide_brute_force(&mesh(&start)).is_empty());

    let r = untangle(&settings);
    let rounds = r.lengths.len() - 1;
    assert!(r.curves[0] >= 1 && r.lengths[0] > 0.0);
    assert!(
        rounds < settings.rounds,
        "still tangled after {rounds} rounds"
    );
    assert_eq!(r.curves[rounds], 0);
    assert_eq!(r.pairs_left, 0);
    assert!(self_collide_brute_force(&mesh(&r.sheet.0)).is_empty());
    // The curves shrink: each tenth of the way shorter than the start.
    let tenth = rounds.div_ceil(10).max(1);
    assert!(r.lengths.iter().skip(tenth).all(|&l| l < r.lengths[0]));
}
