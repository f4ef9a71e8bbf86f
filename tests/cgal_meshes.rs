//! Real scanned meshes from Debian's `libcgal-demo`: built, deformed over several frames, and
//! checked against the brute-force oracle in every query mode. The test command installs the
//! package and sets `DVH_REQUIRE_CGAL_DATA=1`, which turns a missing archive into a failure.

mod common;

use common::{Body, check_all_modes};
use dvh::fixtures::{cgal_data_archive, cgal_data_available, cgal_mesh};
use dvh::{BuildOptions, LeftoverPolicy, Pairs, Pose, RadiusKind, TreeKind, VolumeKind};

fn data_or_skip() -> bool {
    if cgal_data_available() {
        return true;
    }
    assert!(
        std::env::var_os("DVH_REQUIRE_CGAL_DATA").is_none(),
        "{} is missing (install Debian's libcgal-demo)",
        cgal_data_archive().display()
    );
    eprintln!("skipped: {} not installed", cgal_data_archive().display());
    false
}

#[test]
fn scanned_meshes_deforming_into_each_other() {
    if !data_or_skip() {
        return;
    }
    let scenes = [
        ("armadillo", "elephant"),
        ("dino", "elephant"),
        ("bunny00", "dino"),
    ];
    let sbv = BuildOptions::default()
        .with_tree(TreeKind::Binary)
        .with_radius(RadiusKind::Wrapped)
        .with_leftovers(LeftoverPolicy::ExtraRings)
        .with_volume(VolumeKind::Sbv)
        .with_refit_threads(2);
    let aabb = BuildOptions::default().with_volume(VolumeKind::Aabb);
    // The last scene queries boxes against the DVH's spheres.
    let options = [
        (BuildOptions::default(), BuildOptions::default()),
        (sbv, sbv),
        (aabb, BuildOptions::default()),
    ];
    let mut pairs = Pairs::new();
    for ((first, second), (options_a, options_b)) in scenes.into_iter().zip(&options) {
        let mut ma = cgal_mesh(first).expect("mesh unpacks");
        let mut mb = cgal_mesh(second).expect("mesh unpacks");
        ma.normalize(1.0);
        mb.normalize(0.8);
        // b turned a quarter around y and moved into a's side.
        let pose = Pose::new(
            [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
            [0.3, 0.05, 0.0],
        )
        .unwrap();
        let mut a = Body::new(ma, 1, 0.1, None, options_a);
        let mut b = Body::new(mb, 2, 0.1, Some(pose), options_b);
        let mut contacts = 0;
        for frame in 0..3 {
            let t = f64::from(frame) / 3.0;
            a.deform(t);
            b.deform(t);
            contacts += check_all_modes(&a, &b, 4, &mut pairs).len();
        }
        assert!(contacts > 0, "{first} and {second} should touch");
    }
}
