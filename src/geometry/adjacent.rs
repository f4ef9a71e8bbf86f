//! Exact tests for triangles of one mesh that share vertices: do they meet anywhere other than
//! what they share? Self-collision reports such pairs only then, so an intact surface
//! reports nothing however it bends while a fold through itself reports every crossing.
//!
//! Both tests reduce to cones at a shared vertex, decided by orientation signs alone:
//!
//! - **One shared vertex `p`**, triangles `(p, q, r)` and `(p, b, c)`. Near `p` each triangle
//!   coincides with its cone `K = {p + s(q - p) + t(r - p) : s, t >= 0}`, so the triangles share a
//!   point other than `p` exactly when the two cones share a direction. When the five points are
//!   not coplanar, the directions `s1 u1 + t1 w1 = s2 u2 + t2 w2` form the null space of a 3 x 4
//!   matrix, spanned by its four 3 x 3 minors; those are orientations of `p` with three of
//!   `q, r, b, c`, and a non-negative solution exists exactly when their signs (alternated)
//!   agree. Coplanar cones are angles in their plane, which meet exactly when one holds a side
//!   of the other. Degenerate triangles (a segment or a point) have cones made of rays.
//! - **A shared edge `p q`**, triangles `(p, q, a)` and `(p, q, b)`. Triangles in different
//!   planes meet only on the line `p q`, and each meets that line in the edge alone unless it is
//!   degenerate. So they meet beyond the edge only when coplanar, with `a` and `b` on the same
//!   side of the line, or both on the line and beyond the same end of the edge.
//!
//! Every sign comes from the exact predicates ([`orient3d`], [`orient2d`]) or from comparing
//! coordinates, so the answers are exact for any finite input.

use super::predicates::{Point, Sign, orient2d, orient3d};

/// Do triangles `(p, q, r)` and `(p, b, c)`, which share the vertex `p` (and no other vertex of
/// the mesh), have a common point other than `p`?
pub fn meet_beyond_vertex(p: &Point, [q, r]: [&Point; 2], [b, c]: [&Point; 2]) -> bool {
    let flat1 = collinear(p, q, r);
    let flat2 = collinear(p, b, c);
    match (flat1, flat2) {
        (false, false) => {
            // The minors of [u1 w1 -u2 -w2], up to signs chosen so that a common direction is a
            // non-negative combination exactly when all four agree.
            let m = [
                orient3d(r, b, c, p),
                -orient3d(q, b, c, p),
                -orient3d(q, r, c, p),
                orient3d(q, r, b, p),
            ];
            if m.iter().any(|&s| s != 0) {
                return m.iter().all(|&s| s >= 0) || m.iter().all(|&s| s <= 0);
            }
            // Coplanar: angles of less than a half turn meet when one holds a side of the other.
            let plane = Projection::of(p, q, r);
            [b, c].iter().any(|g| plane.in_angle(p, [q, r], g))
                || [q, r].iter().any(|g| plane.in_angle(p, [b, c], g))
        }
        (true, false) => rays(p, [q, r]).any(|g| in_cone(p, [b, c], g)),
        (false, true) => rays(p, [b, c]).any(|g| in_cone(p, [q, r], g)),
        (true, true) => rays(p, [q, r]).any(|g| rays(p, [b, c]).any(|h| same_ray(p, g, h))),
    }
}

/// Do triangles `(p, q, a)` and `(p, q, b)`, which share the edge `p q`, have a common point
/// off the segment `[p, q]`?
pub fn meet_beyond_edge(p: &Point, q: &Point, a: &Point, b: &Point) -> bool {
    if p == q {
        // The edge is a point: the triangles share a vertex.
        return meet_beyond_vertex(p, [q, a], [q, b]);
    }
    if orient3d(p, q, a, b) != 0 {
        return false;
    }
    let (flat_a, flat_b) = (collinear(p, q, a), collinear(p, q, b));
    match (flat_a, flat_b) {
        (false, false) => {
            let plane = Projection::of(p, q, a);
            plane.orient(p, q, a) == plane.orient(p, q, b)
        }
        // A triangle that is not flat meets the line p q in the edge alone, and the flat one
        // lies on that line.
        (true, false) | (false, true) => false,
        (true, true) => {
            // All on one line: the segments hull(p, q, a) and hull(p, q, b) share a point off
            // [p, q] when a and b lie beyond the same end.
            let k = (0..3).find(|&k| p[k] != q[k]).expect("p and q differ");
            let dir = (q[k] - p[k]).signum();
            let beyond_q = |x: &Point| (x[k] - q[k]) * dir > 0.0;
            let beyond_p = |x: &Point| (p[k] - x[k]) * dir > 0.0;
            (beyond_q(a) && beyond_q(b)) || (beyond_p(a) && beyond_p(b))
        }
    }
}

/// Are `a`, `b`, `c` on one line (or not all distinct)?
fn collinear(a: &Point, b: &Point, c: &Point) -> bool {
    (0..3).all(|k| Projection { drop: k }.orient(a, b, c) == 0)
}

/// The non-zero generators of the cone at `p` spanned by `ends` (as their end points).
fn rays<'a>(p: &'a Point, ends: [&'a Point; 2]) -> impl Iterator<Item = &'a Point> + 'a {
    ends.into_iter().filter(move |g| *g != p)
}

/// Is the direction from `p` to `g` in the cone at `p` spanned by `ends`, which is not flat?
fn in_cone(p: &Point, ends: [&Point; 2], g: &Point) -> bool {
    orient3d(p, ends[0], ends[1], g) == 0
        && Projection::of(p, ends[0], ends[1]).in_angle(p, ends, g)
}

/// Do the directions from `p` to `g` and to `h` (both away from `p`) coincide?
fn same_ray(p: &Point, g: &Point, h: &Point) -> bool {
    if !collinear(p, g, h) {
        return false;
    }
    // On one line through p: the same side of p along an axis where g differs from p.
    let k = (0..3).find(|&k| g[k] != p[k]).expect("g differs from p");
    (g[k] - p[k]).signum() == (h[k] - p[k]).signum() && h[k] != p[k]
}

/// A coordinate plane (the one without axis `drop`) onto which a plane projects one to one, so
/// that orientations of its points keep one sign convention.
#[derive(Clone, Copy)]
struct Projection {
    drop: usize,
}

impl Projection {
    /// A projection in which the triangle `a, b, c` (not flat) keeps its area.
    fn of(a: &Point, b: &Point, c: &Point) -> Projection {
        (0..3)
            .map(|drop| Projection { drop })
            .find(|pr| pr.orient(a, b, c) != 0)
            .expect("a triangle that is not flat projects onto some coordinate plane")
    }

    fn flat(&self, p: &Point) -> [f64; 2] {
        match self.drop {
            0 => [p[1], p[2]],
            1 => [p[2], p[0]],
            _ => [p[0], p[1]],
        }
    }

    /// The orientation of `a, b, c` in this projection.
    fn orient(&self, a: &Point, b: &Point, c: &Point) -> Sign {
        orient2d(self.flat(a), self.flat(b), self.flat(c))
    }

    /// Is the direction from `p` to `g` (a point of the plane, not `p`) inside the closed angle
    /// at `p` from `ends[0]` to `ends[1]`, which is less than a half turn and not flat?
    fn in_angle(&self, p: &Point, ends: [&Point; 2], g: &Point) -> bool {
        if g == p {
            return false;
        }
        let turn = self.orient(p, ends[0], ends[1]);
        self.orient(p, ends[0], g) * turn >= 0 && self.orient(p, g, ends[1]) * turn >= 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::tri_tri::triangles_intersect;
    use proptest::prelude::*;

    const O: Point = [0.0, 0.0, 0.0];

    #[test]
    fn a_smooth_fan_does_not_meet() {
        // Two triangles of a fan around the origin, bent along their shared vertex only.
        assert!(!meet_beyond_vertex(
            &O,
            [&[1.0, 0.0, 0.0], &[1.0, 1.0, 0.1]],
            [&[-1.0, 1.0, 0.0], &[-1.0, -1.0, 0.2]],
        ));
    }

    #[test]
    fn a_fold_through_the_shared_vertex_meets() {
        // The second triangle passes through the first's interior near the origin.
        assert!(meet_beyond_vertex(
            &O,
            [&[2.0, 0.0, 0.0], &[0.0, 2.0, 0.0]],
            [&[1.0, 1.0, 1.0], &[1.0, 1.0, -1.0]],
        ));
        // Tilted away: they touch only at the origin.
        assert!(!meet_beyond_vertex(
            &O,
            [&[2.0, 0.0, 0.0], &[0.0, 2.0, 0.0]],
            [&[-1.0, -1.0, 1.0], &[-1.0, -1.0, -1.0]],
        ));
    }

    #[test]
    fn coplanar_fans() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // Overlapping angles in one plane.
        assert!(meet_beyond_vertex(
            &O,
            [&x, &y],
            [&[1.0, 1.0, 0.0], &[-1.0, 2.0, 0.0]]
        ));
        // Angles that only touch along a side: they share a segment, beyond the vertex.
        assert!(meet_beyond_vertex(&O, [&x, &y], [&y, &[-1.0, 0.0, 0.0]]));
        // Angles apart.
        assert!(!meet_beyond_vertex(
            &O,
            [&x, &y],
            [&[-1.0, 0.0, 0.0], &[0.0, -1.0, 0.0]]
        ));
    }

    #[test]
    fn degenerate_triangles() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // A needle along x against a triangle holding x: they share a segment.
        assert!(meet_beyond_vertex(
            &O,
            [&[2.0, 0.0, 0.0], &[3.0, 0.0, 0.0]],
            [&x, &y]
        ));
        // A needle pointing away.
        assert!(!meet_beyond_vertex(
            &O,
            [&[-2.0, 0.0, 0.0], &[-3.0, 0.0, 0.0]],
            [&x, &y]
        ));
        // A needle through the vertex (a segment with p inside) against a plane it crosses.
        assert!(!meet_beyond_vertex(
            &O,
            [&[0.2, 0.2, 1.0], &[-0.2, -0.2, -1.0]],
            [&x, &y],
        ));
        // ... and against a triangle it lies in.
        assert!(meet_beyond_vertex(
            &O,
            [&[0.2, 0.2, 0.0], &[-0.2, -0.2, 0.0]],
            [&x, &y]
        ));
        // Triangles collapsed to their shared vertex meet nothing else.
        assert!(!meet_beyond_vertex(&O, [&O, &O], [&x, &y]));
        // Two needles on one line: the same way, or opposite ways.
        assert!(meet_beyond_vertex(&O, [&x, &x], [&[5.0, 0.0, 0.0], &O]));
        assert!(!meet_beyond_vertex(&O, [&x, &x], [&[-5.0, 0.0, 0.0], &O]));
    }

    #[test]
    fn shared_edges() {
        let (p, q) = (O, [1.0, 0.0, 0.0]);
        // A crease, however sharp: only the edge.
        assert!(!meet_beyond_edge(
            &p,
            &q,
            &[0.5, 1.0, 0.0],
            &[0.5, -1.0, 1e-300]
        ));
        assert!(!meet_beyond_edge(
            &p,
            &q,
            &[0.5, 1.0, 0.0],
            &[0.5, 1.0, 1e-300]
        ));
        // Flat and unfolded: only the edge. Folded flat onto each other: they overlap.
        assert!(!meet_beyond_edge(
            &p,
            &q,
            &[0.5, 1.0, 0.0],
            &[0.5, -1.0, 0.0]
        ));
        assert!(meet_beyond_edge(&p, &q, &[0.5, 1.0, 0.0], &[3.0, 0.1, 0.0]));
        // A degenerate triangle along the edge's line beside a proper one: only the edge.
        assert!(!meet_beyond_edge(
            &p,
            &q,
            &[2.0, 0.0, 0.0],
            &[0.5, 1.0, 0.0]
        ));
        // Two degenerate ones beyond the same end overlap; beyond different ends they do not.
        assert!(meet_beyond_edge(&p, &q, &[2.0, 0.0, 0.0], &[3.0, 0.0, 0.0]));
        assert!(!meet_beyond_edge(
            &p,
            &q,
            &[2.0, 0.0, 0.0],
            &[-3.0, 0.0, 0.0]
        ));
        assert!(!meet_beyond_edge(
            &p,
            &q,
            &[0.5, 0.0, 0.0],
            &[0.7, 0.0, 0.0]
        ));
    }

    /// A small integer coordinate.
    fn coord() -> impl Strategy<Value = f64> {
        (-4i32..=4).prop_map(f64::from)
    }

    /// A point with small integer coordinates; one time in two on the plane x + y + z = 1, so
    /// that coplanar configurations are common.
    fn point() -> impl Strategy<Value = Point> {
        prop_oneof![
            [coord(), coord(), coord()],
            (coord(), coord()).prop_map(|(x, y)| [x, y, 1.0 - x - y]),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 4000, ..ProptestConfig::default() })]

        /// Against the exact triangle test: two triangles sharing `p` meet elsewhere exactly
        /// when the first one's edge opposite `p` meets the second's cone. The cone is stood in
        /// for by the second triangle grown 2^20 times about `p`: with coordinates below 5, a
        /// point of that edge in the cone is within 2^20 of `p` along the cone's sides.
        #[test]
        fn shared_vertex_agrees_with_the_triangle_test(
            p in point(), q in point(), r in point(), b in point(), c in point(),
        ) {
            prop_assume!(!collinear(&p, &q, &r) && !collinear(&p, &b, &c));
            let grow = |x: &Point| [0, 1, 2].map(|k| p[k] + (x[k] - p[k]) * 1048576.0);
            let far = [p, grow(&b), grow(&c)];
            let expected = triangles_intersect(&[q, r, r], &far);
            prop_assert_eq!(meet_beyond_vertex(&p, [&q, &r], [&b, &c]), expected);
            // Symmetric in the two triangles and in each one's other corners.
            prop_assert_eq!(meet_beyond_vertex(&p, [&c, &b], [&r, &q]), expected);
        }

        /// Two proper triangles sharing an edge meet off the edge exactly when they are
        /// coplanar with their normals the same way round (folded flat onto each other),
        /// computed here in integers.
        #[test]
        fn shared_edge_agrees_with_integer_arithmetic(
            p in point(), q in point(), a in point(), b in point(),
        ) {
            prop_assume!(!collinear(&p, &q, &a) && !collinear(&p, &q, &b));
            let v = |x: &Point| [0, 1, 2].map(|k| (x[k] - p[k]) as i64);
            let cross = |x: [i64; 3], y: [i64; 3]| {
                [x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]]
            };
            let dot = |x: [i64; 3], y: [i64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
            let (na, nb) = (cross(v(&q), v(&a)), cross(v(&q), v(&b)));
            let expected = dot(na, v(&b)) == 0 && dot(na, nb) > 0;
            prop_assert_eq!(meet_beyond_edge(&p, &q, &a, &b), expected);
            prop_assert_eq!(meet_beyond_edge(&q, &p, &b, &a), expected);
        }
    }
}
