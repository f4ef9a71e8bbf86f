//! Exact intersection test for two closed triangles.
//!
//! # Contract
//!
//! [`triangles_intersect`] returns `true` exactly when the two closed triangles, taken as the
//! point sets their `f64` vertices describe, share at least one point. Touching counts: a shared
//! vertex, a vertex on the other's edge or face, an edge crossing an edge, and coplanar overlap
//! all intersect. A triangle of zero area is still a point set, the segment (collinear vertices)
//! or the point (three equal vertices) it covers, and is tested as such. The answer is exact for
//! every finite input: it is decided only by signs of orientation determinants (see
//! [`super::predicates`]), never by a tolerance, so it does not depend on the order of the
//! triangles or of their vertices, and it is unchanged by transformations that are exact in
//! floating point (scaling by powers of two, swapping axes, translations that keep the
//! coordinates exact).
//!
//! # Method
//!
//! First, two triangles with a corner in common (the same coordinates) meet there. Then the usual
//! rejection: all three vertices of one triangle strictly on one side of the other's plane.
//! Then:
//! - Two proper (non-degenerate), non-coplanar triangles each cross the line where the planes
//!   meet in an interval, and intersect iff the intervals overlap; after the triangles are turned
//!   into a canonical form, that takes two more orientation signs (the interval comparison of
//!   Guigue and Devillers).
//! - Two proper coplanar triangles are compared in a coordinate plane onto which they project
//!   one-to-one: they are disjoint iff the line through some edge leaves the other triangle
//!   strictly outside.
//! - With a degenerate triangle, two convex sets intersect iff some edge of one meets the other
//!   (a degenerate triangle is the union of its own edges). An edge that crosses the other's
//!   plane is tested with three signs (its line against the other's edges); one that lies in the
//!   plane is tested in a coordinate plane onto which the triangle projects one-to-one.

use super::predicates::{
    Adaptive, BigExact, EdgeTest, FilterProbe, Orient, Plane, Point, Sign, is_safe_point,
};
use std::marker::PhantomData;
use std::sync::atomic::{AtomicU8, Ordering};

/// A triangle as its three corner points.
pub type Triangle = [Point; 3];

const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// Do the closed triangles `t1` and `t2` share at least one point? Exact for all finite input;
/// see the [module documentation](self) for the full contract.
pub fn triangles_intersect(t1: &Triangle, t2: &Triangle) -> bool {
    if t1.iter().chain(t2.iter()).all(is_safe_point) {
        intersect::<Adaptive>(t1, t2)
    } else {
        intersect::<BigExact>(t1, t2)
    }
}

/// Diagnostics, for measuring what exactness costs: [`triangles_intersect`]'s answer, and whether
/// the floating-point stage of every orientation predicate it evaluated decided its sign, so that
/// no adaptive (or big-integer) arithmetic ran. Coordinates outside the adaptive predicates' safe
/// range are never settled. Slower than [`triangles_intersect`]; not for production queries
/// (served by `dvh::fixtures`).
///
/// [`triangles_intersect`]: crate::exact::triangles_intersect
#[cfg_attr(not(feature = "fixtures"), allow(dead_code))]
pub fn settled_by_filter(t1: &Triangle, t2: &Triangle) -> (bool, bool) {
    if !t1.iter().chain(t2.iter()).all(is_safe_point) {
        return (intersect::<BigExact>(t1, t2), false);
    }
    FilterProbe::take();
    let hit = intersect::<FilterProbe>(t1, t2);
    (hit, !FilterProbe::take())
}

/// A triangle with what the exact test computes of it alone, kept for the many pairs it takes
/// part in: its [`Plane`] at once, and its projection (an axis that keeps it non-degenerate, and
/// its orientation there) on first use. Only for triangles whose coordinates are all safe
/// ([`super::predicates::is_safe_coordinate`]): the test it serves is [`Adaptive`]'s.
#[derive(Debug, Default)]
pub(crate) struct PreparedTriangle {
    pub corners: Triangle,
    plane: Plane,
    /// 0: not yet known; 1: degenerate; otherwise `2 + 2 axis + (orientation > 0)`. Atomic only
    /// so that a query's workspace may be shared between threads once the triangles are tested
    /// (each is prepared and tested by one thread; relaxed loads and stores are plain moves).
    projection: AtomicU8,
}

impl PreparedTriangle {
    /// Prepares `corners` (for [`prepared_triangles_intersect`], which needs them safe).
    #[inline(always)]
    pub fn new(corners: Triangle) -> PreparedTriangle {
        PreparedTriangle {
            corners,
            plane: Plane::of(&corners),
            projection: AtomicU8::new(0),
        }
    }
}

/// [`triangles_intersect`] for two prepared triangles: the same answer, exact under
/// [`PreparedTriangle`]'s precondition.
#[inline]
pub(crate) fn prepared_triangles_intersect(t1: &PreparedTriangle, t2: &PreparedTriangle) -> bool {
    debug_assert!(t1.corners.iter().chain(&t2.corners).all(is_safe_point));
    meet::<Adaptive, _, _>(t1, t2)
}

/// What the test asks of one triangle besides its corners: computed on demand for a bare
/// triangle, or kept by a [`PreparedTriangle`].
trait TriangleSigns<O: Orient> {
    fn corners(&self) -> &Triangle;
    /// The sides of `points` relative to the triangle's plane (all zero when it has none).
    fn plane_sides(&self, points: &Triangle) -> [Sign; 3];
    /// [`projection`] of the triangle.
    fn projection(&self) -> Option<(usize, Sign)>;
    /// The triangle's orientation in the projection dropping axis `k`.
    #[inline(always)]
    fn orientation_on(&self, k: usize) -> Sign {
        orientation_in::<O>(self.corners(), k)
    }
}

/// `t`'s orientation in the projection dropping axis `k`.
#[inline(always)]
fn orientation_in<O: Orient>(t: &Triangle, k: usize) -> Sign {
    O::orient2d(project(&t[0], k), project(&t[1], k), project(&t[2], k))
}

/// A triangle whose facts are computed when asked.
struct Bare<'t, O>(&'t Triangle, PhantomData<O>);

impl<O: Orient> TriangleSigns<O> for Bare<'_, O> {
    #[inline(always)]
    fn corners(&self) -> &Triangle {
        self.0
    }

    #[inline(always)]
    fn plane_sides(&self, points: &Triangle) -> [Sign; 3] {
        O::plane_sides(self.0, points)
    }

    #[inline(always)]
    fn projection(&self) -> Option<(usize, Sign)> {
        projection::<O>(self.0)
    }
}

impl TriangleSigns<Adaptive> for PreparedTriangle {
    #[inline(always)]
    fn corners(&self) -> &Triangle {
        &self.corners
    }

    #[inline(always)]
    fn plane_sides(&self, points: &Triangle) -> [Sign; 3] {
        Adaptive::sides_of_plane(&self.plane, &self.corners, points)
    }

    #[inline]
    fn projection(&self) -> Option<(usize, Sign)> {
        let code = match self.projection.load(Ordering::Relaxed) {
            0 => {
                let code =
                    match projection_with_normal::<Adaptive>(&self.corners, self.plane.normal()) {
                        None => 1,
                        Some((k, inside)) => 2 + 2 * k as u8 + u8::from(inside > 0),
                    };
                self.projection.store(code, Ordering::Relaxed);
                code
            }
            code => code,
        };
        (code > 1).then(|| {
            let k = usize::from((code - 2) / 2);
            (k, if code % 2 == 1 { 1 } else { -1 })
        })
    }

    /// A kept projection on the same axis answers at once; a degenerate triangle is degenerate
    /// in every projection.
    #[inline]
    fn orientation_on(&self, k: usize) -> Sign {
        match self.projection() {
            Some((axis, inside)) if axis == k => inside,
            Some(_) => orientation_in::<Adaptive>(&self.corners, k),
            None => 0,
        }
    }
}

#[inline]
fn strictly_one_side(s: [Sign; 3]) -> bool {
    (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0)
}

#[inline]
fn all_zero(s: [Sign; 3]) -> bool {
    s == [0, 0, 0]
}

pub(crate) fn intersect<O: Orient>(t1: &Triangle, t2: &Triangle) -> bool {
    meet::<O, _, _>(&Bare(t1, PhantomData), &Bare(t2, PhantomData))
}

/// The test itself, on triangles given with their [`TriangleSigns`].
#[inline]
fn meet<O: Orient, F1: TriangleSigns<O>, F2: TriangleSigns<O>>(f1: &F1, f2: &F2) -> bool {
    let (t1, t2) = (f1.corners(), f2.corners());
    // A shared corner is a shared point, settled before any arithmetic: meshes touching copies of
    // themselves, or stitched along seams, meet this way in most of their tested pairs, and the
    // nine comparisons cost little beside one plane test where no corner is shared.
    if shares_a_corner(t1, t2) {
        return true;
    }
    // s2[i]: side of t2[i] relative to the plane of t1 (all zero when t1 has no plane).
    let s2 = f1.plane_sides(t2);
    if strictly_one_side(s2) {
        return false;
    }
    // With every sign zero, `t2` lies in `t1`'s plane if `t1` has one (is proper). Then `t1`'s
    // corners lie on `t2`'s plane too, or `t2` has none: the second plane test is skipped, and
    // `t1`'s projection, one-to-one on the common plane, serves both (a third of a test between
    // coplanar sheets). A degenerate `t1` takes the general route below.
    if all_zero(s2)
        && let Some(projection1) = f1.projection()
    {
        return coplanar_meet::<O, _>(t1, projection1, f2);
    }
    let proper1 = !all_zero(s2);
    let s1 = f2.plane_sides(t1);
    if strictly_one_side(s1) {
        return false;
    }
    if proper1 && !all_zero(s1) {
        // Both triangles proper (a degenerate one has no plane: all its signs would be zero) and
        // not coplanar.
        return crossing_intervals_meet::<O>(t1, s1, t2, s2);
    }
    // Here `t1` is degenerate, or `t2` is: a proper `t1` with `t1` in `t2`'s plane would have
    // had `t2` in its own, and the coplanar route above. A non-zero sign proves the triangle that
    // defines the plane proper.
    let axis2 = if all_zero(s1) {
        f2.projection().map(|p| p.0)
    } else {
        None
    };
    let proper2 = !all_zero(s1) || axis2.is_some();
    debug_assert!(
        !(proper1 && proper2),
        "proper coplanar pairs took the route above"
    );
    match (proper1, proper2) {
        // A degenerate triangle is the union of its edges; the proper one's projection, when
        // already found, serves its in-plane edges.
        (false, true) => edges_meet_triangle::<O>(t1, s1, t2, axis2),
        (true, _) => edges_meet_triangle::<O>(t2, s2, t1, None),
        (false, false) => EDGES.iter().any(|&(i, j)| {
            EDGES
                .iter()
                .any(|&(k, l)| segments_meet_3d::<O>(&t1[i], &t1[j], &t2[k], &t2[l]))
        }),
    }
}

/// Is some corner of `t1` exactly a corner of `t2`? The first coordinates are compared for all
/// nine corner pairs at once (no early exit to mispredict); only a match looks further.
#[inline(always)]
fn shares_a_corner(t1: &Triangle, t2: &Triangle) -> bool {
    let mut any = false;
    for p in t1 {
        for q in t2 {
            any |= p[0] == q[0];
        }
    }
    any && t1.iter().any(|p| t2.contains(p))
}

/// The vertex alone on its side of the other triangle's plane, and which side that is. With
/// signs `(+, +, 0)` the vertex on the plane is the one alone, and counts as on the side opposite
/// the other two.
fn apex(s: [Sign; 3]) -> (usize, Sign) {
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        if s[i] != 0 && s[j] * s[i] <= 0 && s[k] * s[i] <= 0 {
            return (i, s[i]);
        }
    }
    let i = s
        .iter()
        .position(|&x| x == 0)
        .expect("signs not all of one side have a zero");
    (i, -s[(i + 1) % 3])
}

/// Two proper, non-coplanar triangles, each meeting the other's plane: each crosses the line
/// where the planes meet in an interval, and the triangles intersect iff the intervals overlap.
///
/// Each triangle is turned so that its first vertex is the one alone on its side of the other's
/// plane, so the interval's ends lie on its first and last edges from that vertex; swapping the
/// other two vertices of the *other* triangle flips the other plane, so that both lone vertices
/// end up on the positive side. In that form the intervals are `[x1, y1]` and `[y2, x2]` along
/// `n1 × n2`, where `x` ends lie on edges `p q` and `y` ends on edges `p r`, and comparing an end
/// from each triangle is the sign of one orientation of the two edges' endpoints (zero when the
/// ends coincide). The intervals overlap iff `x1 <= x2` and `y2 <= y1`: two more predicates.
/// This is the idea of Guigue and Devillers (2003), rederived for closed triangles.
fn crossing_intervals_meet<O: Orient>(
    t1: &Triangle,
    s1: [Sign; 3],
    t2: &Triangle,
    s2: [Sign; 3],
) -> bool {
    let (i1, side1) = apex(s1);
    let (i2, side2) = apex(s2);
    let (p1, mut q1, mut r1) = (&t1[i1], &t1[(i1 + 1) % 3], &t1[(i1 + 2) % 3]);
    let (p2, mut q2, mut r2) = (&t2[i2], &t2[(i2 + 1) % 3], &t2[(i2 + 2) % 3]);
    if side1 < 0 {
        std::mem::swap(&mut q2, &mut r2);
    }
    if side2 < 0 {
        std::mem::swap(&mut q1, &mut r1);
    }
    O::orient3d(p1, q1, p2, q2) <= 0 && O::orient3d(p1, r1, r2, p2) <= 0
}

/// The proper triangle `t1` and `t2`, which lies in `t1`'s plane, compared in a projection
/// one-to-one on that plane. `(k, inside1)` is [`projection`]`(t1)`: the axis to drop and
/// `t1`'s orientation there; `t2` is proper exactly when it stays so in that projection, and
/// otherwise the union of its edges. Closed convex polygons are disjoint iff a line through an
/// edge of one has the whole other polygon strictly on its outer side (the separating-axis
/// theorem in the plane: the separating direction can be taken normal to an edge, and the
/// edge's own line then separates).
fn coplanar_meet<O: Orient, F2: TriangleSigns<O>>(
    t1: &Triangle,
    (k, inside1): (usize, Sign),
    f2: &F2,
) -> bool {
    let t2 = f2.corners();
    let b = [project(&t2[0], k), project(&t2[1], k), project(&t2[2], k)];
    let inside2 = f2.orientation_on(k);
    if inside2 == 0 {
        return edges_meet_triangle::<O>(t2, [0; 3], t1, Some(k));
    }
    let a = [project(&t1[0], k), project(&t1[1], k), project(&t1[2], k)];
    match O::edge_test(&a, inside1, &b) {
        Some(EdgeTest::Separated) => return false,
        Some(EdgeTest::Inside) => return true,
        Some(EdgeTest::Open) => {}
        None => {
            if separated_by_an_edge::<O>(&a, inside1, &b) {
                return false;
            }
        }
    }
    match O::edge_test(&b, inside2, &a) {
        Some(EdgeTest::Separated) => false,
        Some(EdgeTest::Inside | EdgeTest::Open) => true,
        None => !separated_by_an_edge::<O>(&b, inside2, &a),
    }
}

/// Is all of `other` strictly outside one of the edge lines of the non-degenerate `t`, whose
/// orientation is `inside`?
fn separated_by_an_edge<O: Orient>(t: &[[f64; 2]; 3], inside: Sign, other: &[[f64; 2]; 3]) -> bool {
    EDGES
        .iter()
        .any(|&(i, j)| other.iter().all(|&p| O::orient2d(t[i], t[j], p) == -inside))
}

/// Does an edge of `edges` meet the closed, non-degenerate triangle `tri`? `signs[i]` is the side
/// of `edges[i]` relative to the plane of `tri`; `axis` is [`projection`]`(tri)`'s axis when the
/// caller has it.
fn edges_meet_triangle<O: Orient>(
    edges: &Triangle,
    signs: [Sign; 3],
    tri: &Triangle,
    mut axis: Option<usize>,
) -> bool {
    EDGES.iter().any(|&(i, j)| {
        let (sa, sb) = (signs[i], signs[j]);
        if sa == 0 && sb == 0 {
            let k = *axis.get_or_insert_with(|| projection_axis::<O>(tri));
            segment_meets_triangle_2d::<O>(&edges[i], &edges[j], tri, k)
        } else if sa * sb <= 0 {
            // The segment crosses or touches the plane at exactly one point.
            line_crosses_triangle::<O>(&edges[i], &edges[j], tri)
        } else {
            false
        }
    })
}

/// For a line `ab` that is not parallel to the plane of the non-degenerate triangle `tri`: does it
/// meet the closed triangle? The three signs are the line's side of each edge, all scaled by the
/// same non-zero factor, so the crossing point is inside or on the boundary iff none disagree.
#[inline]
fn line_crosses_triangle<O: Orient>(a: &Point, b: &Point, tri: &Triangle) -> bool {
    let u = O::orient3d(a, b, &tri[0], &tri[1]);
    let v = O::orient3d(a, b, &tri[1], &tri[2]);
    if u * v < 0 {
        return false;
    }
    let w = O::orient3d(a, b, &tri[2], &tri[0]);
    (u >= 0 && v >= 0 && w >= 0) || (u <= 0 && v <= 0 && w <= 0)
}

/// The coordinates of `p` with axis `k` dropped. Dropping a coordinate is exact, and it is
/// one-to-one on any plane that does not contain the direction of axis `k`.
#[inline]
fn project(p: &Point, k: usize) -> [f64; 2] {
    match k {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    }
}

/// Are the three points on one line (or equal)? Exact: the three components of the normal are
/// the three projected orientations.
#[cfg(test)]
fn collinear<O: Orient>(t: &Triangle) -> bool {
    projection::<O>(t).is_none()
}

/// An axis whose projection keeps the non-degenerate triangle `tri` non-degenerate.
fn projection_axis<O: Orient>(tri: &Triangle) -> usize {
    projection::<O>(tri)
        .expect("a non-degenerate triangle has a non-zero projected area on some axis")
        .0
}

/// An axis whose projection keeps `tri` non-degenerate, and `tri`'s orientation in it; `None`
/// when `tri` is degenerate (its points on one line), as every projection then is: the three
/// projected orientations are the components of the normal. The largest component of the
/// floating-point normal is tried first; the exact test decides.
fn projection<O: Orient>(tri: &Triangle) -> Option<(usize, Sign)> {
    projection_with_normal::<O>(tri, Plane::of(tri).normal())
}

/// [`projection`] given `tri`'s floating-point normal, which only orders the axes tried.
fn projection_with_normal<O: Orient>(tri: &Triangle, n: [f64; 3]) -> Option<(usize, Sign)> {
    let n = n.map(f64::abs);
    // The largest first, then the others in turn (a general sort of three cost 6% of a query
    // between coplanar sheets). Which comes first only matters for speed: every axis tried is
    // decided exactly; NaN (from overflowing coordinates) simply compares false.
    let first = if n[0] >= n[1] && n[0] >= n[2] {
        0
    } else if n[1] >= n[2] {
        1
    } else {
        2
    };
    [first, (first + 1) % 3, (first + 2) % 3]
        .into_iter()
        .find_map(|k| {
            let inside = orientation_in::<O>(tri, k);
            (inside != 0).then_some((k, inside))
        })
}

/// Segment `ab` against the closed triangle `tri`, all in the plane of `tri`, compared in the
/// projection that drops axis `k` (one-to-one on that plane).
fn segment_meets_triangle_2d<O: Orient>(a: &Point, b: &Point, tri: &Triangle, k: usize) -> bool {
    let (a, b) = (project(a, k), project(b, k));
    let t = [
        project(&tri[0], k),
        project(&tri[1], k),
        project(&tri[2], k),
    ];
    point_in_triangle_2d::<O>(a, &t)
        || point_in_triangle_2d::<O>(b, &t)
        || EDGES
            .iter()
            .any(|&(i, j)| segments_meet_2d::<O>(a, b, t[i], t[j]))
}

/// Is `x` inside or on the boundary of the non-degenerate triangle `t`?
#[inline]
fn point_in_triangle_2d<O: Orient>(x: [f64; 2], t: &[[f64; 2]; 3]) -> bool {
    let d1 = O::orient2d(t[0], t[1], x);
    let d2 = O::orient2d(t[1], t[2], x);
    let d3 = O::orient2d(t[2], t[0], x);
    (d1 >= 0 && d2 >= 0 && d3 >= 0) || (d1 <= 0 && d2 <= 0 && d3 <= 0)
}

/// For `p` on the line through `a` and `b` (or `a == b`): is it on the closed segment?
#[inline]
fn within_box(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    a[0].min(b[0]) <= p[0]
        && p[0] <= a[0].max(b[0])
        && a[1].min(b[1]) <= p[1]
        && p[1] <= a[1].max(b[1])
}

/// Do the closed segments `ab` and `cd` share a point? Either may be a single point.
fn segments_meet_2d<O: Orient>(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let o1 = O::orient2d(a, b, c);
    let o2 = O::orient2d(a, b, d);
    let o3 = O::orient2d(c, d, a);
    let o4 = O::orient2d(c, d, b);
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    (o1 == 0 && within_box(a, b, c))
        || (o2 == 0 && within_box(a, b, d))
        || (o3 == 0 && within_box(c, d, a))
        || (o4 == 0 && within_box(c, d, b))
}

/// Do the closed segments `ab` and `cd` in space share a point? If the four points are coplanar,
/// some coordinate projection is one-to-one on their plane (or line); the segments meet iff they
/// meet in that projection, and meeting in space implies meeting in every projection, so asking
/// all three projections needs no choice of axis.
fn segments_meet_3d<O: Orient>(a: &Point, b: &Point, c: &Point, d: &Point) -> bool {
    O::orient3d(a, b, c, d) == 0
        && (0..3).all(|k| {
            segments_meet_2d::<O>(project(a, k), project(b, k), project(c, k), project(d, k))
        })
}

#[cfg(test)]
mod tests;
