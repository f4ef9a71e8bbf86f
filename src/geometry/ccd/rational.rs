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
