//! The signed-distance slice example's short form: every pixel's signed distance is the exact
//! closest distance of brute force over every triangle, with the sign of the winding number
//! (inside negative), on every frame of the wobbling sphere.

#[path = "../examples/sdf_slice.rs"]
#[allow(dead_code)]
mod sdf_slice;

use dvh::fixtures::oracle::{closest_triangle_brute_force, winding_by_solid_angles};
use dvh::fixtures::rational::q;
use dvh::{BuildOptions, Mesh};
use sdf_slice::{Settings, run};

#[test]
fn each_pixel_is_the_exact_signed_distance() {
    let dir = std::env::temp_dir().join(format!("dvh-sdf-slice-{}", std::process::id()));
    let settings = Settings {
        size: 8,
        frames: 2,
        out: Some(dir.clone()),
    };
    let report = run(&settings).unwrap();
    assert_eq!(report.frames.len(), 2);
    let mut inside = 0;
    for (f, (positions, signed)) in report.frames.iter().enumerate() {
        let mesh = Mesh::new(positions, &report.triangles, &BuildOptions::default()).unwrap();
        for (p, d) in report.points.iter().zip(signed) {
            let (_, d2) = closest_triangle_brute_force(&mesh, None, p, f64::INFINITY).unwrap();
            let m = d.abs();
            let (lo, hi) = (m.next_down().max(0.0), m.next_up());
            assert!(
                q(lo) * q(lo) <= d2 && d2 <= q(hi) * q(hi),
                "frame {f}, {p:?}: {d}"
            );
            // The pixels lie well off the surface: the solid angles tell the side too.
            let (w, off) = winding_by_solid_angles(&mesh, None, p);
            assert!(off < 1e-6, "{p:?}");
            assert_eq!(
                *d < 0.0,
                w != 0,
                "frame {f}, {p:?}: {d} against winding {w}"
            );
            inside += usize::from(*d < 0.0);
        }
        let ppm = std::fs::read(dir.join(format!("slice_{f:03}.ppm"))).unwrap();
        assert!(ppm.starts_with(b"P6\n8 8\n255\n") && ppm.len() == 11 + 3 * 64);
    }
    assert!(inside > 0 && inside < 2 * 64, "both sides drawn");
    std::fs::remove_dir_all(dir).unwrap();
}
