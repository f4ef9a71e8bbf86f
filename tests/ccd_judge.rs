//! The exact continuous tests (`dvh::exact::vertex_face_impact`, `edge_edge_impact`) judged by
//! an independent judge (`dvh::fixtures::ccd_judge`, which shares no code with them) on
//! thousands of random, constructed and degenerate motions at every scale: every answer must
//! be proved right, none proved wrong, and the cases the judge cannot settle must stay few. The
//! judge is also shown each answer moved by one double and the opposite answer, and must not
//! call those right.

use dvh::exact::{edge_edge_impact, vertex_face_impact};
use dvh::fixtures::Rng;
use dvh::fixtures::ccd_judge::{Primitives, Verdict, judge};

type Points = [[f64; 3]; 4];

/// What the library answers.
fn answer(primitives: Primitives, s: &Points, e: &Points) -> Option<f64> {
    match primitives {
        Primitives::VertexFace => vertex_face_impact(s, e),
        Primitives::EdgeEdge => edge_edge_impact(s, e),
    }
    .expect("finite coordinates")
}

/// Right, undecided and hit counts over a set of cases.
#[derive(Default, Debug)]
struct Tally {
    right: usize,
    undecided: usize,
    hits: usize,
}

impl Tally {
    /// Judges the library's answer (it must not be wrong); with `others`, also that a time one
    /// double away and the opposite answer are not judged right.
    fn check(&mut self, what: &str, primitives: Primitives, s: &Points, e: &Points, others: bool) {
        let got = answer(primitives, s, e);
        self.hits += usize::from(got.is_some());
        match judge(primitives, s, e, got) {
            Verdict::Right => self.right += 1,
            Verdict::Undecided(_) => self.undecided += 1,
            Verdict::Wrong(why) => {
                panic!("{what} {primitives:?}: answer {got:?} judged wrong: {why}\n{s:?}\n{e:?}")
            }
        }
        if !others {
            return;
        }
        let mut alternatives = vec![if got.is_some() { None } else { Some(0.5) }];
        if let Some(t) = got {
            alternatives.extend(
                [t.next_down(), t.next_up()]
                    .into_iter()
                    .filter(|x| (0.0..=1.0).contains(x))
                    .map(Some),
            );
        }
        for alternative in alternatives {
            let v = judge(primitives, s, e, alternative);
            assert!(
                v != Verdict::Right,
                "{what} {primitives:?}: {alternative:?} judged right as well as {got:?}\n{s:?}\n{e:?}"
            );
        }
    }

    /// At most `percent` of the cases undecided, and at least `hits` contacts among them.
    fn assert_settled(&self, what: &str, percent: usize, hits: usize) {
        println!("{what}: {self:?}");
        let total = self.right + self.undecided;
        assert!(
            self.undecided * 100 <= percent * total,
            "{what}: {} of {total} undecided",
            self.undecided
        );
        assert!(
            self.hits >= hits,
            "{what}: only {} contacts in {total}",
            self.hits
        );
    }
}

/// A random motion: coordinates on a grid of `1/grid` in [-1, 1], shaped by `case` into the
/// degenerate configurations simulations meet: motion in one plane, a point not moving, corners
/// shared or repeated (a triangle or edge collapsed), parallel edges, a point starting on the
/// other primitive's plane.
fn random_motion(rng: &mut Rng, case: usize, grid: u64) -> (Points, Points) {
    let mut coord = || (rng.below(2 * grid + 1)) as f64 / grid as f64 - 1.0;
    let mut s = [[0.0; 3]; 4];
    let mut e = [[0.0; 3]; 4];
    for i in 0..4 {
        for k in 0..3 {
            s[i][k] = coord();
            e[i][k] = coord();
        }
    }
    match case % 9 {
        1 => (0..4).for_each(|i| {
            s[i][2] = 0.0;
            e[i][2] = 0.0;
        }),
        2 => e[0] = s[0],
        3 => s[0] = s[1],
        4 => {
            s[2] = s[3];
            e[2] = e[3];
        }
        5 => {
            let d = [0, 1, 2].map(|k| s[1][k] - s[0][k]);
            s[3] = [0, 1, 2].map(|k| s[2][k] + d[k]);
            e[3] = [0, 1, 2].map(|k| e[2][k] + (e[1][k] - e[0][k]));
        }
        6 => (1..4).for_each(|i| e[i] = s[i]),
        7 => {
            // Everything on one line at the start.
            for p in &mut s {
                p[1] = 0.0;
                p[2] = 0.0;
            }
        }
        _ => {}
    }
    (s, e)
}

#[test]
fn random_and_degenerate_motions_on_grids() {
    let mut rng = Rng::new(0x00de_c1de);
    let mut tally = Tally::default();
    for case in 0..2400 {
        let grid = [2, 4, 8, 1 << 20][case % 4];
        let (s, e) = random_motion(&mut rng, case, grid);
        for p in [Primitives::VertexFace, Primitives::EdgeEdge] {
            tally.check(&format!("case {case}"), p, &s, &e, case % 4 == 0);
        }
    }
    tally.assert_settled("grids", 2, 400);
}

/// Contacts made to happen: a point that passes through a chosen point of a moving face at a
/// chosen time, two edges through a common point, exactly, or missing by one double.
#[test]
fn constructed_contacts_and_near_misses() {
    let mut rng = Rng::new(0xc0_27ac7);
    let mut tally = Tally::default();
    for case in 0..800 {
        let mut coord = || rng.below(33) as f64 / 16.0 - 1.0;
        let from = [coord(), coord(), coord()];
        let mut s = [[0.0; 3]; 4];
        let mut e = [[0.0; 3]; 4];
        for i in 1..4 {
            s[i] = [coord(), coord(), coord()];
            e[i] = [coord(), coord(), coord()];
        }
        // At time t (a sixteenth), the first point is at the combination w of the others.
        let t = (1 + case as u64 % 15) as f64 / 16.0;
        let w = match case % 4 {
            0 => [0.25, 0.25, 0.5],
            1 => [0.5, 0.5, 0.0], // on an edge
            2 => [1.0, 0.0, 0.0], // on a corner
            _ => [0.75, 0.125, 0.125],
        };
        let at = |i: usize, k: usize| s[i][k] + t * (e[i][k] - s[i][k]);
        let target = [0, 1, 2].map(|k| w[0] * at(1, k) + w[1] * at(2, k) + w[2] * at(3, k));
        // p(t) = target: p(0) = from, p(1) = from + (target - from) / t.
        s[0] = from;
        e[0] = [0, 1, 2].map(|k| from[k] + (target[k] - from[k]) / t);
        if case % 3 == 1 {
            // Missing by one double somewhere.
            let k = (case / 3) % 3;
            e[0][k] = e[0][k].next_up();
        }
        tally.check(
            &format!("constructed {case}"),
            Primitives::VertexFace,
            &s,
            &e,
            case % 2 == 0,
        );
        // The same four points as two edges: the first edge ends at the point.
        let (s2, e2) = ([s[1], s[0], s[2], s[3]], [e[1], e[0], e[2], e[3]]);
        tally.check(
            &format!("constructed {case}"),
            Primitives::EdgeEdge,
            &s2,
            &e2,
            case % 2 == 0,
        );
    }
    tally.assert_settled("constructed", 2, 300);
}

/// Free doubles (irrational times of contact almost always) and the grids' motions scaled by
/// powers of two from 2^-1000 to 2^1000 and moved 2^40 away, where an exact answer changes not
/// at all.
#[test]
fn general_position_and_every_scale() {
    let mut rng = Rng::new(0x005c_a1e5);
    let mut tally = Tally::default();
    for case in 0..600 {
        let (mut s, mut e) = random_motion(&mut rng, case, 8);
        if case % 3 == 0 {
            for p in s.iter_mut().chain(e.iter_mut()) {
                *p = p.map(|_| rng.range(-1.0, 1.0));
            }
        }
        let (scale, shift) = [
            (1.0, 0.0),
            (2f64.powi(-1000), 0.0),
            (2f64.powi(1000), 0.0),
            (1.0, 2f64.powi(40)),
            (2f64.powi(-60), 0.0),
        ][case % 5];
        if case % 3 != 0 || shift == 0.0 {
            let f = |p: &Points| p.map(|v| v.map(|x| x * scale + shift));
            (s, e) = (f(&s), f(&e));
        }
        for p in [Primitives::VertexFace, Primitives::EdgeEdge] {
            tally.check(
                &format!("case {case} x{scale:e}+{shift:e}"),
                p,
                &s,
                &e,
                case % 6 == 0,
            );
        }
    }
    tally.assert_settled("every scale", 2, 150);
}
