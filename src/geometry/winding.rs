//! What one triangle adds to the winding number of a point: the signed crossing of the ray from
//! the point along +x with the triangle, decided exactly.
//!
//! The winding number of a closed surface about a point not on it is the number of times a ray
//! from the point crosses the surface outwards less the number of times it crosses inwards, for
//! any ray that meets the surface only in triangle interiors. The ray here runs along +x from
//! `p`; where it would meet an edge or a vertex, its origin is moved symbolically to
//! `p + (0, e, e^2)` for an infinitesimal `e` (simulation of simplicity), which meets none and
//! decides every degenerate case the same way for the two triangles of an edge, so each crossing
//! is counted exactly once. In the projection along x onto the (y, z) plane the question is
//! whether the moved origin lies inside the projected triangle (three 2D orientations, each
//! either decided by its exact sign or, when that is zero, by the first nonzero term of its
//! expansion in `e`), and whether the triangle lies ahead of `p` along the ray (a 3D
//! orientation). A triangle parallel to the ray is missed by the moved ray. Every sign is exact
//! for the given doubles.
//!
//! A point that lies on the triangle (the closed triangle: its edges and corners included) is
//! reported as such: its winding number is not defined.

use super::aabb::Aabb;
use super::nearest::{Primitive, decide_within};
use super::predicates::{Point, Sign, orient2d, orient3d};

/// What a triangle adds to a point's winding number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Crossing {
    /// The ray from the point crosses the triangle: +1 where the triangle faces +x (its normal
    /// `(t1 - t0) x (t2 - t0)` has a positive x component), -1 where it faces -x; 0 where it
    /// does not cross.
    Adds(i32),
    /// The point lies on the (closed) triangle.
    OnTriangle,
}

/// The side of the directed edge `u -> v` (projected) on which the moved ray origin `q + (e,
/// e^2)` lies: the sign of `(u - q) x (v - q)` at the moved point, which is affine in it, with
/// the coefficients `u.z - v.z` of `e` and `v.y - u.y` of `e^2`. Zero only when `u` and `v`
/// coincide (then the projected triangle has no area).
#[inline]
fn side_of_edge(q: [f64; 2], u: [f64; 2], v: [f64; 2]) -> Sign {
    let s = orient2d(u, v, q);
    if s != 0 {
        return s;
    }
    // Differences of doubles: their signs are the comparisons'.
    match u[1].partial_cmp(&v[1]) {
        Some(std::cmp::Ordering::Greater) => 1,
        Some(std::cmp::Ordering::Less) => -1,
        _ => match v[0].partial_cmp(&u[0]) {
            Some(std::cmp::Ordering::Greater) => 1,
            Some(std::cmp::Ordering::Less) => -1,
            _ => 0,
        },
    }
}

/// What triangle `t` adds to the winding number of `p` (see the module documentation). Exact for
/// any finite coordinates; degenerate triangles (a segment or a point) add nothing, and report
/// `p` when it lies on them.
#[inline]
pub(crate) fn ray_crossing(p: &Point, t: [&Point; 3]) -> Crossing {
    let [a, b, c] = t;
    if Aabb::of_points([a, b, c]).contains(p)
        && orient3d(a, b, c, p) == 0
        && decide_within(Primitive::VertexFace, &[*p, *a, *b, *c], 0.0).is_some()
    {
        return Crossing::OnTriangle;
    }
    let yz = |x: &Point| [x[1], x[2]];
    let (pa, pb, pc, q) = (yz(a), yz(b), yz(c), yz(p));
    // The sign of the normal's x component: the projected triangle's orientation.
    let facing = orient2d(pa, pb, pc);
    if facing == 0 {
        return Crossing::Adds(0);
    }
    let inside = side_of_edge(q, pa, pb) == facing
        && side_of_edge(q, pb, pc) == facing
        && side_of_edge(q, pc, pa) == facing;
    // Ahead along +x: `orient3d(a, b, c, p)` is the sign of `t n_x` for the ray parameter `t`
    // at the plane (zero: `p` on the plane, and then on the triangle, found above).
    if inside && orient3d(a, b, c, p) == facing {
        Crossing::Adds(i32::from(facing))
    } else {
        Crossing::Adds(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> (Vec<Point>, Vec<[usize; 3]>) {
        // The unit cube, outward faces (normals by the right-hand rule pointing out).
        let v: Vec<Point> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        let quads = [
            [0, 2, 3, 1], // z = 0, facing -z
            [4, 5, 7, 6], // z = 1, facing +z
            [0, 1, 5, 4], // y = 0
            [2, 6, 7, 3], // y = 1
            [0, 4, 6, 2], // x = 0
            [1, 3, 7, 5], // x = 1
        ];
        let t = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        (v, t)
    }

    fn winding(p: &Point, v: &[Point], t: &[[usize; 3]]) -> Option<i32> {
        let mut w = 0;
        for tri in t {
            match ray_crossing(p, [&v[tri[0]], &v[tri[1]], &v[tri[2]]]) {
                Crossing::Adds(k) => w += k,
                Crossing::OnTriangle => return None,
            }
        }
        Some(w)
    }

    #[test]
    fn the_cube_winds_once_around_its_inside_and_not_outside() {
        let (v, t) = cube();
        // Grid points: rays through edges, corners and the diagonals' crossings of every face.
        let steps = [-0.5, 0.0, 0.25, 0.5, 0.75, 1.0, 1.5];
        for &x in &steps {
            for &y in &steps {
                for &z in &steps {
                    let p = [x, y, z];
                    let inside = [x, y, z].iter().all(|&c| c > 0.0 && c < 1.0);
                    let on = [x, y, z].iter().all(|&c| (0.0..=1.0).contains(&c)) && !inside;
                    let expected = if on { None } else { Some(i32::from(inside)) };
                    assert_eq!(winding(&p, &v, &t), expected, "{p:?}");
                }
            }
        }
    }

    #[test]
    fn reversed_faces_wind_negatively() {
        let (v, mut t) = cube();
        for tri in &mut t {
            tri.swap(1, 2);
        }
        assert_eq!(winding(&[0.5, 0.5, 0.5], &v, &t), Some(-1));
        assert_eq!(winding(&[0.5, 0.0, 0.5], &v, &t), None);
        assert_eq!(winding(&[2.0, 0.5, 0.5], &v, &t), Some(0));
    }

    #[test]
    fn a_triangle_parallel_to_the_ray_is_missed_unless_the_point_is_on_it() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(
            ray_crossing(&[-1.0, 0.0, 0.5], [&a, &b, &c]),
            Crossing::Adds(0)
        );
        assert_eq!(
            ray_crossing(&[0.25, 0.0, 0.25], [&a, &b, &c]),
            Crossing::OnTriangle
        );
        // A segment-shaped triangle, and a point-shaped one.
        let d = [2.0, 0.0, 0.0];
        assert_eq!(
            ray_crossing(&[1.5, 0.0, 0.0], [&a, &d, &b]),
            Crossing::OnTriangle
        );
        assert_eq!(
            ray_crossing(&[-1.0, 0.0, 0.0], [&a, &d, &b]),
            Crossing::Adds(0)
        );
        assert_eq!(ray_crossing(&a, [&a, &a, &a]), Crossing::OnTriangle);
    }
}
