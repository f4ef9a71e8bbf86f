//! Property tests: every query mode against the brute-force exact oracle, on random meshes under
//! random deformations and poses, with every build option on either side (the two meshes' volume
//! kinds may differ).

mod common;

use common::{Body, all_build_options, check_all_modes, random_pose, random_shape};
use dvh::Pairs;
use dvh::fixtures::Rng;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]

    #[test]
    fn queries_match_brute_force(
        kind_a in 0u8..5, kind_b in 0u8..5,
        detail_a in 0u8..48, detail_b in 0u8..48,
        seed in any::<u64>(),
        options_a in 0usize..20,
        options_b in 0usize..20,
        posed in 0u8..4,
        amplitude in 0.0f64..0.3,
        depth in 0u32..6,
    ) {
        let all = all_build_options();
        let (options_a, options_b) = (all[options_a % all.len()], all[options_b % all.len()]);
        let mut rng = Rng::new(seed);
        let pose_a = (posed & 1 == 1).then(|| random_pose(&mut rng, 0.6));
        let pose_b = (posed & 2 == 2).then(|| random_pose(&mut rng, 0.6));
        let mut shape_b = random_shape(kind_b, detail_b, seed ^ 1);
        if pose_b.is_none() {
            // Without a pose, offset b so that overlaps are partial.
            shape_b.translate([rng.range(-0.6, 0.6), rng.range(-0.6, 0.6), rng.range(-0.6, 0.6)]);
        }
        let mut a = Body::new(random_shape(kind_a, detail_a, seed), seed ^ 2, amplitude, pose_a, &options_a);
        let mut b = Body::new(shape_b, seed ^ 3, amplitude, pose_b, &options_b);
        let mut pairs = Pairs::new();
        check_all_modes(&a, &b, depth, &mut pairs);
        for frame in 1..4 {
            let t = f64::from(frame) * 0.17;
            a.deform(t);
            b.deform(t + 0.3);
            check_all_modes(&a, &b, depth, &mut pairs);
        }
    }
}
