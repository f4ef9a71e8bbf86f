//! Which features of two primitives hold their closest points, and whether they are within a
//! distance: signs of polynomials in the coordinates, in whatever arithmetic `T` can tell them.

use super::{Choice, Primitive, corners};
use crate::geometry::distance::{Num, V, at_most, cross, dot, sub};

/// A candidate: its squared distance `num / den` (`den > 0`) and what it is.
struct Candidate<T> {
    num: T,
    den: T,
    choice: Choice,
}

/// Is `x` strictly closer than `y`, if the arithmetic can tell?
fn closer<T: Num>(x: &Candidate<T>, y: &Candidate<T>) -> Option<bool> {
    if corners(x.choice).is_some() && corners(x.choice) == corners(y.choice) {
        // The same two corners, reached from two edges: equal exactly (an interval could not
        // tell, and the exact arithmetic would be asked for nothing).
        return Some(false);
    }
    Some((x.num.clone() * y.den.clone() - y.num.clone() * x.den.clone()).sign()? < 0)
}

/// Keeps `c` in `best` when it is strictly closer (or the first): of equals, the first stays.
/// `None` when the arithmetic cannot tell.
fn keep_closer<T: Num>(best: &mut Option<Candidate<T>>, c: Candidate<T>) -> Option<()> {
    if best.as_ref().map_or(Some(true), |b| closer(&c, b))? {
        *best = Some(c);
    }
    Some(())
}

/// The closest point of segment `[a, b]` to `p`: at `a` (`Some(0)`), at `b` (`Some(1)`), or
/// inside (`None`); with its squared distance.
fn point_segment<T: Num>(p: &V<T>, a: &V<T>, b: &V<T>, one: &T) -> Option<(Option<usize>, T, T)> {
    let (u, w) = (sub(b, a), sub(p, a));
    let (uu, along) = (dot(&u, &u), dot(&w, &u));
    if uu.sign()? == 0 || along.sign()? <= 0 {
        return Some((Some(0), dot(&w, &w), one.clone()));
    }
    if (along - uu.clone()).sign()? >= 0 {
        let x = sub(p, b);
        return Some((Some(1), dot(&x, &x), one.clone()));
    }
    let c = cross(&w, &u);
    Some((None, dot(&c, &c), uu))
}

/// The vertex-face choice for point `p` and triangle `t`, if the arithmetic can tell.
///
/// For a triangle that is not flat, the closest feature is found by signs alone (no distances
/// compared), from the six products of the edges from corner 0 with the point's offsets from
/// the corners (as in Ericson, *Real-Time Collision Detection*, 5.1.5): the closest point is
/// corner `k` exactly when the point lies at 90 degrees or more from both edges at `k`; inside
/// an edge exactly when it projects strictly inside the edge and lies on or outside its line;
/// else inside the triangle. The three "outside" tests are `n.(e x w)` for the edge `e`, the
/// point's offset `w` from its start and the normal `n`, written as differences of products of
/// the six; they sum to `n.n`, which tells a flat triangle.
fn vertex_face<T: Num>(p: &V<T>, t: &[V<T>; 3], one: &T) -> Option<Choice> {
    let (ab, ac) = (sub(&t[1], &t[0]), sub(&t[2], &t[0]));
    let (ap, bp, cp) = (sub(p, &t[0]), sub(p, &t[1]), sub(p, &t[2]));
    let (d1, d2) = (dot(&ab, &ap), dot(&ac, &ap));
    let (d3, d4) = (dot(&ab, &bp), dot(&ac, &bp));
    let (d5, d6) = (dot(&ab, &cp), dot(&ac, &cp));
    // n.(bc x bp), n.(ca x cp) and n.(ab x ap), by Lagrange's identity.
    let va = d3.clone() * d6.clone() - d5.clone() * d4.clone();
    let vb = d5.clone() * d2.clone() - d1.clone() * d6.clone();
    let vc = d1.clone() * d4.clone() - d3.clone() * d2.clone();
    if (va.clone() + vb.clone() + vc.clone()).sign()? > 0 {
        let [s1, s2, s3, s6] = [&d1, &d2, &d3, &d6].map(|x| x.sign());
        let (s1, s2, s3, s6) = (s1?, s2?, s3?, s6?);
        // Past corner 1 towards corner 2, and past corner 2 towards corner 1 (`bc.bp`, `cb.cp`).
        let (b_in, c_in) = ((d4 - d3).sign()?, (d5 - d6).sign()?);
        // Corners: `p` at 90 degrees or more from both edges there (closed).
        if s1 <= 0 && s2 <= 0 {
            return Some(Choice::FaceCorner(0));
        }
        if s3 >= 0 && b_in <= 0 {
            return Some(Choice::FaceCorner(1));
        }
        if s6 >= 0 && c_in <= 0 {
            return Some(Choice::FaceCorner(2));
        }
        // Edges: on or outside the line, strictly between its ends' perpendiculars.
        let (a, b, c) = (va.sign()?, vb.sign()?, vc.sign()?);
        if c <= 0 && s1 > 0 && s3 < 0 {
            return Some(Choice::FaceEdge(0));
        }
        if a <= 0 && b_in > 0 && c_in > 0 {
            return Some(Choice::FaceEdge(1));
        }
        if b <= 0 && s2 > 0 && s6 < 0 {
            return Some(Choice::FaceEdge(2));
        }
        // No corner or edge claims the point: it projects strictly inside every edge's line.
        debug_assert!(a > 0 && b > 0 && c > 0);
        return Some(Choice::FaceInterior);
    }
    // A flat triangle: the closest of the edges' closest points.
    let mut best: Option<Candidate<T>> = None;
    for k in 0..3 {
        let (on, num, den) = point_segment(p, &t[k], &t[(k + 1) % 3], one)?;
        let choice = match on {
            Some(j) => Choice::FaceCorner((k + j) % 3),
            None => Choice::FaceEdge(k),
        };
        keep_closer(&mut best, Candidate { num, den, choice })?;
    }
    best.map(|c| c.choice)
}

/// The edge-edge choice for segments `[q[0], q[1]]` and `[q[2], q[3]]`, if the arithmetic can
/// tell.
fn edge_edge<T: Num>(q: &[V<T>; 4], one: &T) -> Option<Choice> {
    let (u, v, w) = (sub(&q[1], &q[0]), sub(&q[3], &q[2]), sub(&q[0], &q[2]));
    let dots = Dots {
        uu: dot(&u, &u),
        uv: dot(&u, &v),
        vv: dot(&v, &v),
        uw: dot(&u, &w),
        vw: dot(&v, &w),
    };
    let Dots { uu, uv, vv, uw, vw } = &dots;
    // |u x v|^2, by Lagrange's identity: zero exactly for parallel segments.
    let nn = uu.clone() * vv.clone() - uv.clone() * uv.clone();
    if nn.sign()? > 0 {
        let s = uv.clone() * vw.clone() - vv.clone() * uw.clone();
        let t = uu.clone() * vw.clone() - uv.clone() * uw.clone();
        let mut inside = true;
        for x in [s, t] {
            if x.sign()? <= 0 || (x - nn.clone()).sign()? >= 0 {
                inside = false;
            }
        }
        if inside {
            return Some(Choice::BothInside);
        }
        if let Some(c) = by_slopes(&dots)? {
            return Some(c);
        }
    }
    // Parallel segments: the closest of the ends' candidates, the first of equals.
    let mut best: Option<Candidate<T>> = None;
    for p in 0..4 {
        let (a, b) = if p < 2 {
            (&q[2], &q[3])
        } else {
            (&q[0], &q[1])
        };
        let (on, num, den) = point_segment(&q[p], a, b, one)?;
        let choice = Choice::End { p, on };
        keep_closer(&mut best, Candidate { num, den, choice })?;
    }
    best.map(|c| c.choice)
}

/// The end pair of two segments that are not parallel, found by signs alone (no distances
/// compared), for segments whose lines' closest points are not both inside them. The squared
/// distance is strictly convex in the two parameters, so its minimum over the segments is at one
/// pair of points, on the side of the parameter square of the first end `p` (in the order of
/// [`Choice::End`]) from which moving into its own segment brings it no closer to its closest
/// point on the other: the same choice as comparing the four ends' candidates. `dots` holds the
/// products of the directions `u = q[1] - q[0]`, `v = q[3] - q[2]` and `w = q[0] - q[2]`.
/// `Some(None)` if no end qualifies (exactly, one always does).
fn by_slopes<T: Num>(dots: &Dots<T>) -> Option<Option<Choice>> {
    let Dots { uu, uv, vv, uw, vw } = dots;
    for p in 0..4 {
        // With `x` the end less the other segment's start, `g` that segment's direction and `e`
        // the end's own: each product of them is one of `dots` or a sum of two or three, since
        // `x` is `w`, `w + u`, `-w` or `v - w` and `e.g` is `uv`. At `p = 2` the products `x`
        // enters are kept unnegated and their signs flipped.
        let flip = p == 2;
        let signed = |x: &T| Some(if flip { -x.sign()? } else { x.sign()? });
        let gg = if p < 2 { vv } else { uu };
        // g.x, and e.x (each flipped at 2).
        let along = match p {
            0 => vw.clone(),
            1 => vw.clone() + uv.clone(),
            2 => uw.clone(),
            _ => uv.clone() - uw.clone(),
        };
        let ex = || match p {
            0 => uw.clone(),
            1 => uw.clone() + uu.clone(),
            2 => vw.clone(),
            _ => vv.clone() - vw.clone(),
        };
        // The slope of the squared distance as end `p` moves into its segment, up to a positive
        // factor, against its closest point on the other segment: at its start, `e.x`; at its
        // end, `e.(x - g)`; inside, `e.x g.g - g.x e.g`.
        // g.x - g.g, flipped at 2.
        let past = if flip {
            along.clone() + gg.clone()
        } else {
            along.clone() - gg.clone()
        };
        let (on, sign) = if signed(&along)? <= 0 {
            (Some(0), signed(&ex())?)
        } else if signed(&past)? >= 0 {
            let slope = if flip {
                ex() + uv.clone()
            } else {
                ex() - uv.clone()
            };
            (Some(1), signed(&slope)?)
        } else if flip {
            (
                None,
                (uw.clone() * uv.clone() - vw.clone() * uu.clone()).sign()?,
            )
        } else {
            (None, (ex() * gg.clone() - along * uv.clone()).sign()?)
        };
        // Moving in from end 0 is along the direction, from end 1 against it.
        if (p % 2 == 0 && sign < 0) || (p % 2 == 1 && sign > 0) {
            continue;
        }
        return Some(Some(Choice::End { p, on }));
    }
    Some(None)
}

/// The products of two segments' directions `u`, `v` and the vector `w` from the second's start
/// to the first's, as [`edge_edge`] names them.
struct Dots<T> {
    uu: T,
    uv: T,
    vv: T,
    uw: T,
    vw: T,
}

/// The choice and the decision "distance at most `d`" for the points `v` (12 coordinates) and
/// `d`, in the arithmetic `T`; the decision is not computed again when `within` is already
/// known.
pub(super) fn decide<T: Num>(
    pair: Primitive,
    v: &[T; 13],
    one: &T,
    within: bool,
) -> Option<(Choice, bool)> {
    let point =
        |k: usize| -> V<T> { [v[3 * k].clone(), v[3 * k + 1].clone(), v[3 * k + 2].clone()] };
    let q = [point(0), point(1), point(2), point(3)];
    let choice = match pair {
        Primitive::VertexFace => {
            vertex_face(&q[0], &[q[1].clone(), q[2].clone(), q[3].clone()], one)?
        }
        Primitive::EdgeEdge => edge_edge(&q, one)?,
    };
    if within {
        return Some((choice, true));
    }
    let (num, den) = squared(&q, choice, one);
    let dd = v[12].clone() * v[12].clone();
    Some((choice, at_most(num, dd * den)?))
}

/// The squared distance of `choice`'s closest points among `q` (the point and the triangle's
/// corners, or the two segments' ends), as `num / den`.
fn squared<T: Num>(q: &[V<T>; 4], choice: Choice, one: &T) -> (T, T) {
    // The height over a plane through `o` spanned by `u` and `v`, squared, over `|u x v|^2`.
    let height = |x: &V<T>, o: &V<T>, u: V<T>, v: V<T>| {
        let n = cross(&u, &v);
        let h = dot(&n, &sub(x, o));
        (h.clone() * h, dot(&n, &n))
    };
    // Point `x` against the line through `a` and `b`.
    let to_line = |x: &V<T>, a: &V<T>, b: &V<T>| {
        let u = sub(b, a);
        let c = cross(&sub(x, a), &u);
        (dot(&c, &c), dot(&u, &u))
    };
    if let Some((i, j)) = corners(choice) {
        let x = sub(&q[i], &q[j]);
        return (dot(&x, &x), one.clone());
    }
    match choice {
        Choice::FaceInterior => height(&q[0], &q[1], sub(&q[2], &q[1]), sub(&q[3], &q[1])),
        Choice::FaceEdge(k) => to_line(&q[0], &q[1 + k], &q[1 + (k + 1) % 3]),
        Choice::BothInside => height(&q[0], &q[2], sub(&q[1], &q[0]), sub(&q[3], &q[2])),
        Choice::End { p, on: None } => {
            let other = 1 - p / 2;
            to_line(&q[p], &q[2 * other], &q[2 * other + 1])
        }
        _ => unreachable!("corners are taken above"),
    }
}
