use super::*;
use crate::fixtures::oracle::continuous_brute_force;
use crate::fixtures::{Rng, grid, icosphere, torus};
use crate::query::testing::{VOLUMES, build, folded, moved};
use crate::threads::{Step, sharing};
use crate::{CcdMode, Error, Instant, Mesh, VolumeKind};

fn run(a: &Mesh, b: Option<&Mesh>, options: &CcdOptions, out: &mut Impacts) -> CcdStats {
    match b {
        Some(b) => continuous_collide(a, b, options, out).unwrap(),
        None => self_continuous_collide(a, options, out).unwrap(),
    }
}

/// Brute force's impacts of `a` and `b` (or `a` with itself), exact and conservative.
type Expected = [Vec<Impact>; 2];

fn brute_force(a: &Mesh, b: Option<&Mesh>) -> Expected {
    [CcdMode::Exact, CcdMode::Conservative].map(|mode| continuous_brute_force(a, b, mode))
}

/// The query against brute force, with every option that must not change the answer, and
/// against the options that cut it. `expected` is brute force's answer for these positions and
/// motions, computed here when `None` (meshes of every volume kind share it: it depends on
/// the coordinates only).
fn check(a: &Mesh, b: Option<&Mesh>, expected: &mut Option<Expected>, what: &str) -> usize {
    let mut out = Impacts::new();
    let expected_by_mode = expected.get_or_insert_with(|| brute_force(a, b));
    for (mode, expected) in [CcdMode::Exact, CcdMode::Conservative]
        .into_iter()
        .zip(expected_by_mode.iter())
    {
        // Meshes this small are queried on the calling thread whatever the thread count: threads
        // are compared on larger ones.
        let threads = 1;
        let options = CcdOptions::default().with_mode(mode).with_threads(threads);
        let stats = run(a, b, &options, &mut out);
        assert_eq!(
            out.as_slice(),
            &expected[..],
            "{what}: {mode:?}, {threads} threads"
        );
        assert!(!stats.truncated);
        assert_eq!(stats.impacts, expected.len() as u64);
        let earliest = expected.iter().map(|i| i.toi).fold(f64::INFINITY, f64::min);
        assert_eq!(stats.earliest_toi, earliest);
        // The earliest alone: the first of the earliest in the result's order.
        let first = expected
            .iter()
            .min_by(|x, y| (x.toi, x.key()).partial_cmp(&(y.toi, y.key())).unwrap());
        run(a, b, &options.with_earliest_only(true), &mut out);
        assert_eq!(out.as_slice().first(), first, "{what}: earliest only");
        assert!(out.len() <= 1);
        if expected.len() > 3 {
            let stats = run(a, b, &options.with_max_impacts(Some(3)), &mut out);
            assert!(stats.truncated && out.len() == 3, "{what}");
            assert!(out.iter().all(|i| expected.contains(i)));
        }
    }
    // Conservative: never misses, never later.
    let [exact, conservative] = expected_by_mode;
    for i in exact.iter() {
        let c = conservative
            .iter()
            .find(|c| c.key() == i.key())
            .unwrap_or_else(|| panic!("{what}: conservative missed {i:?}"));
        assert!(c.toi <= i.toi, "{what}: {c:?} later than {i:?}");
    }
    exact.len()
}

#[test]
fn two_meshes_equal_brute_force() {
    let mut rng = Rng::new(17);
    let s = icosphere(1);
    let t = torus(0.5, 0.2, 12, 6);
    // Each trial's motions, the same for every volume kind.
    let motions: Vec<[Vec<f64>; 4]> = (0..3)
        .map(|trial| {
            [
                moved(
                    &s.positions,
                    [-1.6, 0.1 * trial as f64, 0.0],
                    0.02,
                    &mut rng,
                ),
                moved(&s.positions, [1.6, -0.1, 0.05], 0.02, &mut rng),
                moved(&t.positions, [0.0; 3], 0.03, &mut rng),
                moved(&t.positions, [0.0, 0.0, 0.1], 0.03, &mut rng),
            ]
        })
        .collect();
    // Per trial: a against b and swapped; then b standing still.
    let mut expected = vec![None; 2 * motions.len() + 1];
    let mut found = 0;
    for volume in VOLUMES {
        let mut a = build(&s, volume);
        let mut b = build(&t, volume);
        for (trial, [from, to, from_b, to_b]) in motions.iter().enumerate() {
            a.refit_motion(from, to).unwrap();
            b.refit_motion(from_b, to_b).unwrap();
            a.validate().unwrap();
            let what = format!("{volume:?} {trial}");
            found += check(&a, Some(&b), &mut expected[2 * trial], &what);
            found += check(
                &b,
                Some(&a),
                &mut expected[2 * trial + 1],
                &format!("{what} swapped"),
            );
        }
        // A stationary mesh: contact at the end positions only.
        b.refit(&t.positions).unwrap();
        assert!(!b.is_moving() && a.is_moving());
        let last = expected.len() - 1;
        check(
            &a,
            Some(&b),
            &mut expected[last],
            &format!("{volume:?}, b still"),
        );
    }
    assert!(
        found > 100,
        "the meshes pass through each other ({found} impacts)"
    );
}

#[test]
fn one_mesh_equals_brute_force() {
    let mut rng = Rng::new(5);
    let t = torus(0.5, 0.2, 16, 8);
    let g = grid(8, 1.0);
    let motions: Vec<[Vec<f64>; 2]> = (0..3)
        .map(|trial| {
            let jitter = 0.03 + 0.03 * trial as f64;
            [
                moved(&t.positions, [0.0; 3], jitter, &mut rng),
                moved(&t.positions, [0.0; 3], jitter, &mut rng),
            ]
        })
        .collect();
    // A flat sheet folding over itself: every neighbour coplanar at the start.
    let folded = folded(&g.positions, |x, y| {
        [1.0 - x + 0.03 * y, y, 0.02 - 0.05 * (x - 0.5)]
    });
    // Per trial the torus; then the folding sheet and the flat one.
    let mut expected = vec![None; motions.len() + 2];
    let mut found = 0;
    for volume in VOLUMES {
        let mut m = build(&t, volume);
        for (trial, [from, to]) in motions.iter().enumerate() {
            m.refit_motion(from, to).unwrap();
            let what = format!("torus {volume:?} {trial}");
            found += check(&m, None, &mut expected[trial], &what);
        }
        let mut sheet = build(&g, volume);
        sheet.refit_motion(&g.positions, &folded).unwrap();
        let n = motions.len();
        found += check(&sheet, None, &mut expected[n], &format!("sheet {volume:?}"));
        // Still: neighbours touch, nothing else does.
        sheet.refit(&g.positions).unwrap();
        check(
            &sheet,
            None,
            &mut expected[n + 1],
            &format!("flat sheet {volume:?}"),
        );
    }
    assert!(
        found > 20,
        "the meshes pass through themselves ({found} impacts)"
    );
}

#[test]
fn threads_and_limits_give_one_answer_on_larger_meshes() {
    let mut rng = Rng::new(23);
    let s = icosphere(3);
    let g = grid(40, 2.0);
    let mut a = build(&s, VolumeKind::Aabb);
    let mut b = build(&g, VolumeKind::Dvh);
    let from = moved(&s.positions, [1.0, 1.0, 0.8], 0.005, &mut rng);
    let to = moved(&s.positions, [1.0, 1.0, -0.8], 0.005, &mut rng);
    a.refit_motion(&from, &to).unwrap();
    let from_b = moved(&g.positions, [0.0; 3], 0.001, &mut rng);
    let to_b = moved(&g.positions, [0.0, 0.0, 0.02], 0.001, &mut rng);
    b.refit_motion(&from_b, &to_b).unwrap();
    let mut one = Impacts::new();
    let mut two = Impacts::new();
    let base = CcdOptions::default();
    for options in [
        base,
        base.with_max_impacts(Some(50)),
        base.with_earliest_only(true),
        base.with_mode(CcdMode::Conservative),
    ] {
        let s1 = run(&a, Some(&b), &options.with_threads(1), &mut one);
        // Every option shares the traversal and the narrow phase out: the limits cut only
        // the joined results.
        let what = format!("{options:?}");
        let steps = [Step::Traversal, Step::Pairs];
        let s2 = sharing(&steps, &what, || {
            run(&a, Some(&b), &options.with_threads(2), &mut two)
        });
        assert_eq!(one.as_slice(), two.as_slice(), "{options:?}");
        assert_eq!(s1.truncated, s2.truncated);
        assert!(!one.is_empty());
    }
    run(&a, Some(&b), &base, &mut one);
    assert!(one.len() > 50, "{}", one.len());
    let mut self_one = Impacts::new();
    let mut self_two = Impacts::new();
    run(&b, None, &base.with_threads(1), &mut self_one);
    sharing(&[Step::Traversal, Step::Pairs], "self", || {
        run(&b, None, &base.with_threads(2), &mut self_two)
    });
    assert_eq!(self_one.as_slice(), self_two.as_slice());
}

#[test]
fn a_failed_motion_changes_nothing() {
    let t = torus(0.5, 0.2, 8, 4);
    let mut m = build(&t, VolumeKind::Dvh);
    let moved_up: Vec<f64> = t.positions.iter().map(|x| x + 0.5).collect();
    m.refit_motion(&t.positions, &moved_up).unwrap();
    let before = format!("{m:?}");
    let start = m.start_positions().to_vec();
    let mut bad = t.positions.clone();
    bad[7] = f64::NAN;
    let e = m.refit_motion(&bad, &moved_up).unwrap_err();
    assert!(
        matches!(&e, Error::Motion { instant: Instant::Start, error } if matches!(**error, Error::NonFiniteCoordinate { vertex: 2, axis: 1, .. })),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "start positions: vertex 2: coordinate y is NaN, not a finite number"
    );
    let e = m.refit_motion(&t.positions, &bad).unwrap_err();
    assert!(
        matches!(
            &e,
            Error::Motion {
                instant: Instant::End,
                ..
            }
        ),
        "{e}"
    );
    let e = m.refit_motion(&t.positions, &bad[..6]).unwrap_err();
    assert!(e.to_string().starts_with("end positions: "), "{e}");
    let e = m.refit_motion(&bad[..5], &t.positions).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("start positions: position array has 5"),
        "{e}"
    );
    assert_eq!(format!("{m:?}"), before);
    assert_eq!(m.start_positions(), &start[..]);
    assert!(m.is_moving());
}

#[test]
fn edges_are_counted_once() {
    let t = torus(0.5, 0.2, 8, 4);
    let m = build(&t, VolumeKind::Aabb);
    // A closed torus: E = 3T/2.
    assert_eq!(m.edge_count(), 3 * m.triangle_count() / 2);
}
