//! The simulation example's short form: a small cloth over the turning paddle, the breathing
//! pillow and the floor stays free of intersections with the scene's queries alone, by the
//! scene's own check and by a brute force over every triangle pair with the exact triangle test;
//! and without the step's cut at impacts, both checks find the intersections.

#[path = "../examples/cloth_scene.rs"]
#[allow(dead_code)]
mod cloth_scene;

use cloth_scene::{Report, Settings, simulate};
use dvh::exact::triangles_intersect;

fn settings(cut: bool) -> Settings {
    Settings {
        cells: 10,
        steps: 160,
        threads: 0,
        out: None,
        keep_frames: true,
        cut,
    }
}

/// Intersecting triangle pairs after step `k`, by brute force: every cloth triangle against
/// every obstacle triangle and every cloth triangle sharing no vertex with it.
fn brute_force(report: &Report, k: usize) -> usize {
    let p = &report.frames[k];
    let tris = &report.cloth_triangles;
    let world: Vec<[[f64; 3]; 3]> = tris.iter().map(|t| t.map(|v| p[v as usize])).collect();
    let mut found = 0;
    for (i, a) in world.iter().enumerate() {
        for (j, b) in world.iter().enumerate().skip(i + 1) {
            let shares = tris[i].iter().any(|v| tris[j].contains(v));
            if !shares && triangles_intersect(a, b) {
                found += 1;
            }
        }
        found += report.obstacle_frames[k]
            .iter()
            .filter(|o| triangles_intersect(a, o))
            .count();
    }
    found
}

#[test]
fn the_cloth_never_intersects_anything() {
    let report = simulate(&settings(true)).unwrap();
    assert_eq!(report.frames.len(), 160);
    for k in 0..report.frames.len() {
        assert_eq!(report.intersecting[k], 0, "step {k}: the scene's check");
        assert_eq!(brute_force(&report, k), 0, "step {k}: brute force");
    }
    // Not vacuous: the cloth came into contact, and the step was cut or corners held.
    let touching = report.stencils.iter().filter(|&&s| s > 0).count();
    assert!(touching > 50, "{touching} steps with stencils");
    let cut = report.kept.iter().filter(|&&k| k < 1.0).count();
    assert!(cut + report.held > 0);
}

#[test]
fn without_the_cut_the_checks_find_intersections() {
    let report = simulate(&settings(false)).unwrap();
    let scene: usize = report.intersecting.iter().sum();
    let brute: usize = (0..report.frames.len())
        .map(|k| brute_force(&report, k))
        .sum();
    assert!(scene > 0 && brute > 0, "{scene} {brute}");
}
