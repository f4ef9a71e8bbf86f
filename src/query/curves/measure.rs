//! Measures of intersection curves.

use super::result::{CurvePoint, Curves};
use crate::error::{Error, Result};
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;

/// The Euclidean distance between `p` and `q`, without overflow or underflow in between.
pub(crate) fn distance(p: &Point, q: &Point) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
    d[0].hypot(d[1]).hypot(d[2])
}

/// `a - b`.
fn sub(a: &Point, b: &Point) -> Point {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: &Point, b: &Point) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: &Point, b: &Point) -> Point {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn add_scaled(to: &mut Point, k: f64, v: &Point) {
    for i in 0..3 {
        to[i] += k * v[i];
    }
}

/// Where a length gradient goes: the two meshes' vertices, or one mesh's.
enum Target<'g> {
    Two(&'g mut [Point], &'g mut [Point]),
    One(&'g mut [Point]),
}

impl Target<'_> {
    /// Vertex `v` of the first mesh (`second: false`) or of the second.
    fn at(&mut self, second: bool, v: u32) -> &mut Point {
        match self {
            Target::Two(a, _) if !second => &mut a[v as usize],
            Target::Two(_, b) => &mut b[v as usize],
            Target::One(x) => &mut x[v as usize],
        }
    }
}

/// The placed meshes of the query whose curves these are.
struct Placed<'m> {
    sides: [(&'m Mesh, Option<&'m Pose>); 2],
}

impl Placed<'_> {
    fn at(&self, second: bool, v: u32) -> Point {
        let (mesh, pose) = self.sides[usize::from(second)];
        let p = mesh.positions()[v as usize];
        pose.map_or(p, |pose| pose.transform_point(&p))
    }

    fn corners(&self, second: bool, t: u32) -> ([u32; 3], [Point; 3]) {
        let c = self.sides[usize::from(second)].0.triangles()[t as usize];
        (c, c.map(|v| self.at(second, v)))
    }

    /// Adds to `out` the derivative of a curve's length through the end point `p`, where edge
    /// `edge` of one side (`second`: the second) crosses triangle `t` of the other, given `g`,
    /// the derivative of the length with respect to `p`. To first order `p` slides along the
    /// edge as the edge's ends move, and as the triangle's plane moves under it (each corner
    /// by its barycentric weight at `p`); with `d` the edge's direction, `m` the plane's unit
    /// normal and `k = (d.g) / (m.d)`, the edge's ends get `(1 - s)` and `s` of `g - k m`, the
    /// triangle's corners `λ_i k m`.
    fn through_edge(
        &self,
        out: &mut Target,
        p: &Point,
        g: &Point,
        second: bool,
        edge: [u32; 2],
        t: u32,
    ) {
        let (u, v) = (self.at(second, edge[0]), self.at(second, edge[1]));
        let (corners, c) = self.corners(!second, t);
        let n = cross(&sub(&c[1], &c[0]), &sub(&c[2], &c[0]));
        let area2 = dot(&n, &n);
        let d = sub(&v, &u);
        let nd = dot(&n, &d);
        if area2 == 0.0 || nd == 0.0 || !area2.is_finite() || !nd.is_finite() {
            return;
        }
        let s = (dot(&n, &sub(&c[0], &u)) / nd).clamp(0.0, 1.0);
        // k m with m = n / |n| is (d.g) / (n.d) n.
        let k = dot(&d, g) / nd;
        let mut along = *g;
        add_scaled(&mut along, -k, &n);
        add_scaled(out.at(second, edge[0]), 1.0 - s, &along);
        add_scaled(out.at(second, edge[1]), s, &along);
        for (i, &corner) in corners.iter().enumerate() {
            // The barycentric weight of `p` at corner i: the sub-triangle opposite it over the
            // whole.
            let (j, l) = ((i + 1) % 3, (i + 2) % 3);
            let w = dot(&cross(&sub(&c[j], p), &sub(&c[l], p)), &n) / area2;
            add_scaled(out.at(!second, corner), w * k, &n);
        }
    }

    /// Adds to `out` the derivative of a curve's length through the end point `p` named
    /// `name`, given `g`, its derivative with respect to `p`.
    fn through(&self, out: &mut Target, name: CurvePoint, p: &Point, g: &Point) {
        match name {
            CurvePoint::VertexA(v) => add_scaled(out.at(false, v), 1.0, g),
            CurvePoint::VertexB(v) => add_scaled(out.at(true, v), 1.0, g),
            CurvePoint::EdgeA { edge, triangle } => {
                self.through_edge(out, p, g, false, edge, triangle)
            }
            CurvePoint::EdgeB { triangle, edge } => {
                self.through_edge(out, p, g, true, edge, triangle)
            }
            CurvePoint::Edges { a, b } => {
                // Where two edges meet the point is pinned by neither triangle's interior: it
                // moves with both edges, half the derivative to each by where it lies on it.
                for (second, e) in [(false, a), (true, b)] {
                    let (u, v) = (self.at(second, e[0]), self.at(second, e[1]));
                    let d = sub(&v, &u);
                    let dd = dot(&d, &d);
                    let s = if dd > 0.0 {
                        (dot(&sub(p, &u), &d) / dd).clamp(0.0, 1.0)
                    } else {
                        0.5
                    };
                    add_scaled(out.at(second, e[0]), 0.5 * (1.0 - s), g);
                    add_scaled(out.at(second, e[1]), 0.5 * s, g);
                }
            }
        }
    }
}

impl Curves {
    /// The gradient of the curves' total length with respect to the world positions of the
    /// vertices of `a` and `b` (placed by `pose_a` and `pose_b`): the meshes and poses of the
    /// [`crate::intersection_curves`] query that gave these curves, unchanged since. Written to
    /// `gradient_a` and `gradient_b` (one entry per vertex, replaced).
    ///
    /// This is the direction of intersection contour minimisation (Volino and Magnenat-Thalmann
    /// 2006): moving the vertices by a small step against it shortens the curves, and surfaces
    /// that cross come apart as the curves shrink to nothing. Each end point slides along the
    /// edge it lies on as that edge and the other triangle's plane move; the gradient is exact
    /// to first order at the rounded points, in doubles. An end at a vertex passes its
    /// derivative to that vertex, one where two edges meet half to each edge.
    ///
    /// Errors: [`Error::GradientLength`] when a gradient's length is not its mesh's vertex
    /// count; [`Error::CurvesKind`] for self-intersection curves; [`Error::ForeignCurves`] when
    /// a curve names a vertex or triangle the meshes do
    /// not have (they are not the query's). On error the gradients are unchanged.
    pub fn length_gradient(
        &self,
        a: &Mesh,
        pose_a: Option<&Pose>,
        b: &Mesh,
        pose_b: Option<&Pose>,
        gradient_a: &mut [Point],
        gradient_b: &mut [Point],
    ) -> Result<()> {
        let placed = Placed {
            sides: [(a, pose_a), (b, pose_b)],
        };
        if self.result.one_mesh && !self.result.points.is_empty() {
            return Err(Error::CurvesKind { self_curves: true });
        }
        self.check(&placed, false)?;
        check_len(a, gradient_a)?;
        check_len(b, gradient_b)?;
        self.gradient(&placed, &mut Target::Two(gradient_a, gradient_b));
        Ok(())
    }

    /// [`Curves::length_gradient`] for the curves of [`crate::self_intersection_curves`] of
    /// `mesh`: the gradient of their total length with respect to its vertices.
    pub fn self_length_gradient(&self, mesh: &Mesh, gradient: &mut [Point]) -> Result<()> {
        let placed = Placed {
            sides: [(mesh, None), (mesh, None)],
        };
        if !self.result.one_mesh && !self.result.points.is_empty() {
            return Err(Error::CurvesKind { self_curves: false });
        }
        self.check(&placed, true)?;
        check_len(mesh, gradient)?;
        self.gradient(&placed, &mut Target::One(gradient));
        Ok(())
    }

    fn gradient(&self, placed: &Placed, out: &mut Target) {
        match out {
            Target::Two(a, b) => {
                a.fill([0.0; 3]);
                b.fill([0.0; 3]);
            }
            Target::One(x) => x.fill([0.0; 3]),
        }
        for (i, s) in self.segments().iter().enumerate() {
            let len = distance(&s.start, &s.end);
            if len == 0.0 || !len.is_finite() {
                continue;
            }
            // d|e - s| / de = (e - s) / |e - s|, and the opposite for s.
            let t = sub(&s.end, &s.start).map(|x| x / len);
            let names = self.segment_points(i);
            placed.through(out, names[0], &s.start, &t.map(|x| -x));
            placed.through(out, names[1], &s.end, &t);
        }
    }

    /// Are the names' vertices and triangles within the meshes?
    fn check(&self, placed: &Placed, one: bool) -> Result<()> {
        let [(a, _), (b, _)] = placed.sides;
        let out_of_range = |mesh: &Mesh, triangle: bool, index: u32| {
            let (what, count) = if triangle {
                ("triangle", mesh.triangle_count())
            } else {
                ("vertex", mesh.vertex_count())
            };
            (index as usize >= count).then_some(Error::ForeignCurves { what, index, count })
        };
        let b = if one { a } else { b };
        for names in &self.result.points {
            for name in names {
                let bad =
                    match *name {
                        CurvePoint::VertexA(v) => out_of_range(a, false, v),
                        CurvePoint::VertexB(v) => out_of_range(b, false, v),
                        CurvePoint::EdgeA { edge, triangle } => out_of_range(a, false, edge[1])
                            .or_else(|| out_of_range(b, true, triangle)),
                        CurvePoint::EdgeB { triangle, edge } => out_of_range(b, false, edge[1])
                            .or_else(|| out_of_range(a, true, triangle)),
                        CurvePoint::Edges { a: ea, b: eb } => {
                            out_of_range(a, false, ea[1]).or_else(|| out_of_range(b, false, eb[1]))
                        }
                    };
                if let Some(e) = bad {
                    return Err(e);
                }
            }
        }
        Ok(())
    }
}

fn check_len(mesh: &Mesh, gradient: &[Point]) -> Result<()> {
    if gradient.len() == mesh.vertex_count() {
        Ok(())
    } else {
        Err(Error::GradientLength {
            expected: mesh.vertex_count(),
            got: gradient.len(),
        })
    }
}
