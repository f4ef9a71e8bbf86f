//! Tests of the simple-polygon test.

use super::*;
use crate::fixtures::Rng;

fn simple(p: &[[f64; 2]]) -> bool {
    is_simple(p, &mut PolygonScratch::default())
}

#[test]
fn polygons() {
    let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    assert!(simple(&square));
    let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
    assert!(!simple(&bow));
    // A corner that turns straight back along its edge, at a turning corner of the order
    // and inside a piece.
    let spike = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    assert!(!simple(&spike));
    let spike_up = [[0.0, 0.0], [0.0, 2.0], [0.0, 1.0], [-1.0, 3.0]];
    assert!(!simple(&spike_up));
    // Touching at a corner.
    let pinch = [
        [0.0, 0.0],
        [2.0, 0.0],
        [1.0, 1.0],
        [2.0, 2.0],
        [0.0, 2.0],
        [1.0, 1.0],
    ];
    assert!(!simple(&pinch));
    // Straight corners are fine; a repeated corner is not.
    let straight = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0]];
    assert!(simple(&straight));
    let repeated = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 1.0]];
    assert!(!simple(&repeated));
    // Long loops: a circle, and the same circle with one vertex pulled out across the far
    // side (its edges cross others), or onto another vertex (they touch).
    let circle: Vec<[f64; 2]> = (0..500)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 500.0;
            [a.cos(), a.sin()]
        })
        .collect();
    assert!(simple(&circle));
    let mut crossed = circle.clone();
    crossed[100] = [-1.5, 0.0];
    assert!(!simple(&crossed));
    let mut touching = circle.clone();
    touching[100] = circle[300];
    assert!(!simple(&touching));
    // A figure-eight: simple but for one crossing in the middle.
    let eight: Vec<[f64; 2]> = (0..400)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 400.0;
            [a.sin(), a.sin() * a.cos()]
        })
        .collect();
    assert!(!simple(&eight));
    // A star of many spikes, cut into more pieces than the pairs take along either axis:
    // the sweep; then one spike pulled across the middle.
    let spikes = 4 * MOST_PIECES;
    let mut star: Vec<[f64; 2]> = (0..2 * spikes)
        .map(|k| {
            let a = k as f64 * std::f64::consts::PI / spikes as f64;
            let r = if k % 2 == 0 { 2.0 } else { 1.0 };
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    assert!(simple(&star));
    star[10] = [-1.5, -0.1];
    assert!(!simple(&star));
}

/// Every pair of edges: the definition of a simple polygon written out.
fn simple_by_pairs(p: &[[f64; 2]]) -> bool {
    let m = p.len();
    let edge = |i: usize| (p[i], p[(i + 1) % m]);
    (0..m).all(|i| {
        let (a, b) = edge(i);
        let c = p[(i + 2) % m];
        let folds = orient2d(a, b, c) == 0 && (c == b || between(a, b, c) || between(b, c, a));
        a != b
            && !folds
            && (i + 2..m).all(|j| {
                (i == 0 && j == m - 1) || {
                    let (c, d) = edge(j);
                    !segments_meet(a, b, c, d)
                }
            })
    })
}

#[test]
fn agrees_with_every_pair() {
    // Wobbly circles, random stars, short loops, scattered corners and combs, on a coarse
    // lattice so that corners tie, touch and cross often; each also through the sweep.
    let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
    let mut next = || rng.unit();
    let (mut simple_count, mut two, mut more, mut more_simple) = (0, 0, 0, 0);
    let mut scratch = PolygonScratch::default();
    for trial in 0..20000 {
        let m = match trial % 5 {
            4 => 3 + trial % 7,
            3 => 2 * (3 + trial % 9),
            1 => 5 + trial % 11,
            _ => 13 + trial % 30,
        };
        let turned = trial % 4 == 3;
        let p: Vec<[f64; 2]> = (0..m)
            .map(|i| {
                if trial % 5 == 4 {
                    return [(next() * 5.0).floor(), (next() * 5.0).floor()];
                }
                if trial % 5 == 3 {
                    // A comb: teeth up and down, some bent over their neighbours.
                    let x = (i / 2) as f64 * 2.0 + (next() * 3.0).floor();
                    let y = if i % 2 == 0 {
                        0.0
                    } else {
                        4.0 + (next() * 3.0).floor()
                    };
                    return if i + 1 == m { [x, -3.0] } else { [x, y] };
                }
                let a = i as f64 * std::f64::consts::TAU / m as f64;
                let r = match trial % 3 {
                    0 => 20.0 + (next() * 2.0).floor(),
                    1 => 6.0 + (next() * 6.0).floor(),
                    _ => 3.0 + (next() * 9.0).floor(),
                };
                let (x, y) = (
                    (r * a.cos()).round(),
                    (r * a.sin() * (1.0 + 0.3 * next())).round(),
                );
                if turned { [x + y, x - y] } else { [x, y] }
            })
            .collect();
        let expected = simple_by_pairs(&p);
        assert_eq!(is_simple(&p, &mut scratch), expected, "{p:?}");
        assert_eq!(sweep(&p, &mut scratch.edges), expected, "sweep: {p:?}");
        let distinct = (0..m).all(|i| p[i] != p[(i + 1) % m]);
        if distinct {
            let pieces = scratch.pieces.len();
            if pieces == 2 {
                two += 1;
            } else if pieces > 2 {
                more += 1;
                more_simple += usize::from(expected);
            }
        }
        simple_count += usize::from(expected);
    }
    // Both answers, loops of two pieces and of more, simple and not, were exercised.
    assert!(
        simple_count > 2000 && simple_count < 19000,
        "{simple_count}"
    );
    assert!(two > 1000, "{two}");
    assert!(
        more > 1000 && more_simple > 300 && more - more_simple > 300,
        "{more} {more_simple}"
    );
}

/// The angle of `d` about `v`, counterclockwise from `base`, as an exact rational
/// "pseudo-angle" in `[0, 4)`: the quadrant plus the fraction of it (small integer vectors).
fn angle_from(v: [i64; 2], base: [i64; 2], d: [i64; 2]) -> (i128, i128) {
    let pseudo = |q: [i64; 2]| -> (i128, i128) {
        let (x, y) = ((q[0] - v[0]) as i128, (q[1] - v[1]) as i128);
        let r = x.abs() + y.abs();
        // In quarters: (quadrant * r + position within it) / r.
        let (quadrant, within) = match (x > 0, y >= 0, x <= 0, y > 0) {
            (true, true, _, _) => (0, y),
            (_, _, true, true) => (1, -x),
            (_, _, true, false) if x < 0 => (2, -y),
            _ => (3, x),
        };
        (quadrant * r + within, r)
    };
    let ((n, d_), (nb, db)) = (pseudo(d), pseudo(base));
    // (n/d - nb/db) mod 4
    let (mut num, den) = (n * db - nb * d_, d_ * db);
    if num < 0 {
        num += 4 * den;
    }
    (num, den)
}

#[test]
fn corners_in_turning_order() {
    // Every ordered pair of lattice directions about a corner, against exact pseudo-angles.
    let dirs: Vec<[i64; 2]> = (-3..=3)
        .flat_map(|x| (-3..=3).map(move |y| [x, y]))
        .filter(|&d| d != [0, 0])
        .collect();
    let v = [0, 0];
    let f = |p: [i64; 2]| [p[0] as f64 + 0.5, p[1] as f64 - 0.25];
    let shift = |p: [i64; 2]| f([p[0] + v[0], p[1] + v[1]]);
    let (mut before, mut after) = (0, 0);
    for &base in &dirs {
        for &d1 in &dirs {
            for &d2 in &dirs {
                let (a1, a2) = (angle_from(v, base, d1), angle_from(v, base, d2));
                let expected = a1.0 > 0 && a2.0 > 0 && a1.0 * a2.1 < a2.0 * a1.1;
                let got = turns_before(shift(v), shift(base), shift(d1), shift(d2));
                assert_eq!(got, expected, "{base:?} {d1:?} {d2:?}");
                before += usize::from(got);
                after += usize::from(!got);
            }
        }
    }
    assert!(before > 10_000 && after > 10_000, "{before} {after}");
}

#[test]
fn loops_at_one_corner_apart_exactly_when_their_regions_meet_only_there() {
    // Two simple counterclockwise lattice loops through the origin, against every pair of
    // edges and the exact pseudo-angles of the four edges at the origin.
    let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
    let mut next = |n: u64| (rng.next_u64() % n) as i64;
    let (mut apart, mut not, mut scratch) = (0, 0, PolygonScratch::default());
    let mut trials = 0;
    while apart < 1500 || not < 1500 {
        trials += 1;
        assert!(trials < 2_000_000, "{apart} {not}");
        let mut lattice_loop = || -> Vec<[i64; 2]> {
            let n = 2 + next(4) as usize;
            std::iter::once([0, 0])
                .chain((0..n).map(|_| [next(7) - 3, next(7) - 3]))
                .collect()
        };
        let (x, y) = (lattice_loop(), lattice_loop());
        let float = |l: &[[i64; 2]]| -> Vec<[f64; 2]> {
            l.iter().map(|p| [p[0] as f64, p[1] as f64]).collect()
        };
        let (fx, fy) = (float(&x), float(&y));
        if !(simple_by_pairs(&fx)
            && simple_by_pairs(&fy)
            && twice_area(&fx) > 0.0
            && twice_area(&fy) > 0.0)
        {
            continue;
        }
        let closed =
            |l: &[[f64; 2]]| -> Vec<[f64; 2]> { l.iter().copied().chain([l[0]]).collect() };
        let (a, b) = (closed(&fx), closed(&fy));
        // Edges apart, but for edges at the origin, which must leave it different ways.
        let edges_ok = (0..a.len() - 1).all(|i| {
            (0..b.len() - 1).all(|j| {
                let (p, q, r, s) = (a[i], a[i + 1], b[j], b[j + 1]);
                let at_origin = |p: [f64; 2], q: [f64; 2]| p == [0.0; 2] || q == [0.0; 2];
                if at_origin(p, q) && at_origin(r, s) {
                    let d1 = if p == [0.0; 2] { q } else { p };
                    let d2 = if r == [0.0; 2] { s } else { r };
                    !(orient2d([0.0; 2], d1, d2) == 0 && d1[0] * d2[0] + d1[1] * d2[1] > 0.0)
                } else {
                    !segments_meet(p, q, r, s)
                }
            })
        });
        let base = x[1];
        let angle = |d: [i64; 2]| angle_from([0, 0], base, d);
        let less = |p: (i128, i128), q: (i128, i128)| p.0 * q.1 < q.0 * p.1;
        let (alpha, b1, b2) = (angle(x[x.len() - 1]), angle(y[1]), angle(y[y.len() - 1]));
        let expected = edges_ok && less(alpha, b1) && less(b1, b2);
        assert_eq!(corner_apart(&a, &b, &mut scratch), expected, "{x:?} {y:?}");
        apart += usize::from(expected);
        not += usize::from(!expected);
    }
}

/// Twice the signed area of the closed polygon `p` (small integers: exact).
fn twice_area(p: &[[f64; 2]]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum()
}

#[test]
fn glued_loops_keep_apart_exactly_when_their_union_is_simple() {
    // Two simple counterclockwise lattice loops sharing a path, walked in opposite
    // directions: their union is simple exactly when the corners at the path's ends keep
    // apart and so do the rest of the loops (the seam test of self-collision).
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut next = |n: u64| (rng.next_u64() % n) as f64;
    let (mut simple, mut not, mut scratch) = (0, 0, PolygonScratch::default());
    let mut trials = 0;
    while simple < 1500 || not < 1500 {
        trials += 1;
        assert!(trials < 2_000_000, "{simple} {not}");
        // The path, then each loop's own stretch (x on one side, y anywhere).
        let path_len = 2 + next(3) as usize;
        let path: Vec<[f64; 2]> = (0..path_len)
            .map(|i| [i as f64 * 2.0, next(3) - 1.0])
            .collect();
        // Mostly on their own sides of the path, sometimes across it.
        let stretch = |n: usize, next: &mut dyn FnMut(u64) -> f64, up: bool| -> Vec<[f64; 2]> {
            (0..n)
                .map(|_| {
                    let y = next(9) - 3.0;
                    [next(9) - 2.0, if up { y } else { -y }]
                })
                .collect()
        };
        let sx = stretch(1 + next(4) as usize, &mut next, true);
        let sy = stretch(1 + next(4) as usize, &mut next, false);
        // x: the path forwards, then its stretch back; y: the path backwards, then its own.
        let x: Vec<[f64; 2]> = path
            .iter()
            .copied()
            .chain(sx.iter().rev().copied())
            .collect();
        let y: Vec<[f64; 2]> = path
            .iter()
            .rev()
            .copied()
            .chain(sy.iter().copied())
            .collect();
        if !(simple_by_pairs(&x)
            && simple_by_pairs(&y)
            && twice_area(&x) > 0.0
            && twice_area(&y) > 0.0)
        {
            continue;
        }
        let (first, last) = (path[0], path[path_len - 1]);
        // The chains as the seam test builds them: x's from the path's last vertex round to
        // its first, y's from the first round to the last.
        let a: Vec<[f64; 2]> = std::iter::once(last)
            .chain(sx.iter().rev().copied())
            .chain([first])
            .collect();
        let b: Vec<[f64; 2]> = std::iter::once(first)
            .chain(sy.iter().copied())
            .chain([last])
            .collect();
        let union: Vec<[f64; 2]> = a[..a.len() - 1]
            .iter()
            .chain(&b[..b.len() - 1])
            .copied()
            .collect();
        let expected = simple_by_pairs(&union);
        let got = turns_before(first, path[1], a[a.len() - 2], b[1])
            && turns_before(last, path[path_len - 2], b[b.len() - 2], a[1])
            && chains_apart(&a, &b, &mut scratch);
        assert_eq!(got, expected, "x {x:?} y {y:?}");
        simple += usize::from(expected);
        not += usize::from(!expected);
    }
}
