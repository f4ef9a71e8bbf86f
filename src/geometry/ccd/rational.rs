//! The exact path of the continuous tests: the contact condition's polynomials, with integer
//! coefficients, tried at their roots in increasing order in rational arithmetic. Exact for
//! every finite input, and slow: the filters in front of it ([`super::filtered`]) leave it the
//! few queries they cannot decide.

use super::condition::{Condition, GROUPS, Signs, Tri, group_holds, group_range};
use super::poly::{self, Poly, Root, one};
use num_rational::BigRational;

/// The earliest time at or after `from` (before which there is no contact) at which the
/// condition holds, trying the coplanarity polynomial's roots (or, when it vanishes
/// identically, every polynomial's) in increasing order. Only times whose rounding down is at
/// most `until` are searched for (roots up to the next double): a later contact may be
/// answered or not.
pub(crate) fn earliest(c: &Condition<Poly>, from: f64, until: f64) -> Option<f64> {
    let f = &c.polys[0];
    let from = poly::rational(from);
    let upto = if until >= 1.0 {
        one()
    } else {
        poly::rational(until.next_up())
    };
    if f.is_zero() {
        return earliest_of_every_candidate(c, &from, &upto);
    }
    first_holding(c, f.roots_in(&from, &upto))
}

/// The earliest time in `[from, upto]` at which the condition holds, trying `from` and every
/// root of every polynomial there: the contact times form a closed set whose truth changes
/// only at such roots. (With `from` = 0 and `upto` = 1, the oracle.)
pub(crate) fn earliest_of_every_candidate(
    c: &Condition<Poly>,
    from: &BigRational,
    upto: &BigRational,
) -> Option<f64> {
    let at_from: Vec<Signs> = c
        .polys
        .iter()
        .map(|p| Signs::exact(p.sign_at(from)))
        .collect();
    if c.holds(&at_from) == Tri::Yes {
        return Some(poly::floor_f64(from));
    }
    let candidates = c
        .polys
        .iter()
        .filter(|p| !p.is_zero())
        .flat_map(|p| p.roots_in(from, upto))
        .collect();
    first_holding(c, candidates)
}

/// The earliest of the candidate times at which the condition holds, rounded down. Signs are
/// found one polynomial at a time, group by group in the order of [`GROUPS`], the others left
/// open, and a candidate is dropped as soon as the signs known rule contact out.
pub(crate) fn first_holding(c: &Condition<Poly>, mut candidates: Vec<Root>) -> Option<f64> {
    candidates.sort_by(|a, b| a.cmp(b));
    let open = Signs {
        neg: true,
        zero: true,
        pos: true,
    };
    'roots: for mut r in candidates {
        let mut signs = vec![open; c.polys.len()];
        signs[0] = Signs::exact(r.sign_of(&c.polys[0]));
        if signs[0] != Signs::exact(std::cmp::Ordering::Equal) {
            continue;
        }
        for g in 0..GROUPS {
            let range = group_range(c.edges, g);
            for i in range.clone() {
                signs[i] = Signs::exact(r.sign_of(&c.polys[i]));
                if group_holds(c.edges, g, &signs[range.clone()]) == Tri::No {
                    continue 'roots;
                }
            }
        }
        if c.holds(&signs) == Tri::Yes {
            return Some(r.floor_f64());
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::super::filtered::time_of_impact;
    use super::super::interval::{self, Answer};
    use crate::fixtures::Rng;
    use crate::fixtures::ccd_judge::{Primitives, Verdict, judge};
    use crate::geometry::Primitive;

    type Points = [[f64; 3]; 4];

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn minus(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| a[k] - b[k])
    }

    /// A point grazing a turning triangle's plane at a time t* in sixty-fourths: the
    /// coplanarity cubic has a double root there (it touches zero without crossing), the point
    /// then inside the triangle, on an edge, at a corner or just outside. Coordinates on a grid
    /// of thirty-seconds and sixteenths, so that every step is exact in doubles (the normal's
    /// last component, which divides, is a power of two).
    fn grazing(rng: &mut Rng, case: usize) -> (Points, Points) {
        let mut fine =
            |r: u64, d: f64| [0; 3].map(|_| (rng.below(2 * r + 1) as f64 - r as f64) / d);
        loop {
            let ts = (1 + case as u64 % 63) as f64 / 64.0;
            let t = [fine(32, 32.0), fine(32, 32.0), fine(32, 32.0)];
            let mut w = [fine(16, 16.0), fine(16, 16.0), fine(16, 16.0)];
            let n = cross(minus(t[1], t[0]), minus(t[2], t[0]));
            if n[2] == 0.0 || n[2].abs() != 2f64.powi(n[2].abs().log2().round() as i32) {
                continue;
            }
            let (u, v) = [(0.25, 0.375), (0.5, 0.0), (0.0, 0.0), (0.5, -1.0 / 64.0)][case % 4];
            let x = [0, 1, 2].map(|k| t[0][k] + u * (t[1][k] - t[0][k]) + v * (t[2][k] - t[0][k]));
            let dn = [0, 1, 2].map(|k| {
                cross(minus(w[1], w[0]), minus(t[2], t[0]))[k]
                    + cross(minus(t[1], t[0]), minus(w[2], w[0]))[k]
            });
            let mut vel = fine(16, 16.0);
            // f'(t*) = n . (V - A') + n' . (X - A*) = 0, solved for V's last component.
            vel[2] = w[0][2]
                - (dot(dn, minus(x, t[0])) + n[0] * (vel[0] - w[0][0]) + n[1] * (vel[1] - w[0][1]))
                    / n[2];
            if case % 7 == 3 {
                // A corner turning about the contact instead: still a double root.
                w[1] = w[0];
            }
            let s = [
                [0, 1, 2].map(|k| x[k] - ts * vel[k]),
                [0, 1, 2].map(|k| t[0][k] - ts * w[0][k]),
                [0, 1, 2].map(|k| t[1][k] - ts * w[1][k]),
                [0, 1, 2].map(|k| t[2][k] - ts * w[2][k]),
            ];
            let d = [vel, w[0], w[1], w[2]];
            let e = [0, 1, 2, 3].map(|i| [0, 1, 2].map(|k| s[i][k] + d[i][k]));
            return (s, e);
        }
    }

    /// The query at one of five scales: as built, times 2^-500 and 2^500, times 2^-10 moved to
    /// 2^20 (small motion far from the origin), or with a coordinate moved from 0 to ±2^-1000
    /// (exponents a thousand binades apart: integers of over a thousand bits once scaled).
    fn place(s: &mut Points, e: &mut Points, scale: usize, rng: &mut Rng) {
        let map = |p: &mut Points, f: &dyn Fn(f64) -> f64| {
            p.iter_mut().flatten().for_each(|x| *x = f(*x));
        };
        match scale {
            1 => [&mut *s, &mut *e].map(|p| map(p, &|x| x * 2f64.powi(-500))),
            2 => [&mut *s, &mut *e].map(|p| map(p, &|x| x * 2f64.powi(500))),
            3 => [&mut *s, &mut *e].map(|p| map(p, &|x| x * 2f64.powi(-10) + 1048576.0)),
            4 => {
                let (i, k) = (rng.below(4) as usize, rng.below(3) as usize);
                let c = s[i][k];
                for p in [&mut *s, &mut *e] {
                    p.iter_mut().for_each(|q| q[k] -= c);
                }
                s[i][k] = if rng.below(2) == 0 { 1.0 } else { -1.0 } * 2f64.powi(-1000);
                [(), ()]
            }
            _ => [(), ()],
        };
    }

    /// Grazing contacts (double roots of the coplanarity cubic), as vertex-face and, the same
    /// four points taken as two edges, as edge-edge, at five scales: the interval path leaves
    /// most of them to the exact one, whose every answer the independent judge must prove
    /// right, and must not prove right a time one double away or the opposite answer.
    #[test]
    fn grazing_contacts_at_every_scale_agree_with_the_judge() {
        let mut rng = Rng::new(0x6a2a_1e55);
        let (mut exact_path, mut hits, mut right, mut total) = (0, 0, 0, 0);
        for case in 0..300 {
            let (mut s, mut e) = grazing(&mut rng, case);
            place(&mut s, &mut e, (case / 4) % 5, &mut rng);
            let as_edges = |p: &Points| [p[1], p[0], p[2], p[3]];
            for (kind, primitives, s, e) in [
                (Primitive::VertexFace, Primitives::VertexFace, s, e),
                (
                    Primitive::EdgeEdge,
                    Primitives::EdgeEdge,
                    as_edges(&s),
                    as_edges(&e),
                ),
            ] {
                total += 1;
                exact_path += usize::from(matches!(
                    interval::time_of_impact(kind, &s, &e, 1.0),
                    Answer::Unknown(_)
                ));
                let got = time_of_impact(kind, &s, &e, 1.0);
                hits += usize::from(got.is_some());
                match judge(primitives, &s, &e, got) {
                    Verdict::Right => right += 1,
                    Verdict::Undecided(_) => {}
                    Verdict::Wrong(why) => {
                        panic!("case {case} {kind:?}: {got:?} judged wrong: {why}\n{s:?}\n{e:?}")
                    }
                }
                let mut others = vec![if got.is_some() { None } else { Some(0.5) }];
                if let Some(t) = got {
                    others.extend(
                        [t.next_down(), t.next_up()]
                            .into_iter()
                            .filter(|x| (0.0..=1.0).contains(x))
                            .map(Some),
                    );
                }
                for other in others {
                    assert_ne!(
                        judge(primitives, &s, &e, other),
                        Verdict::Right,
                        "case {case} {kind:?}: {other:?} judged right as well as {got:?}"
                    );
                }
            }
        }
        println!(
            "{exact_path} of {total} on the exact path, {right} proved right, {hits} contacts"
        );
        assert!(
            exact_path * 3 > total,
            "{exact_path} of {total} on the exact path"
        );
        assert!(right * 50 >= total * 49, "{right} of {total} proved right");
        assert!(hits * 3 > total, "only {hits} contacts in {total}");
    }
}
