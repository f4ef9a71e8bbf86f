//! Winding numbers of many points about a closed mesh, exactly: each point's ray along +x
//! walked through the hierarchy, each triangle it may meet asked for its signed crossing
//! ([`crate::geometry::winding`]).

use super::order::{Walker, answer_points, check_points};
use super::walk::Frame;
use crate::error::Result;
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::geometry::winding::{Crossing, ray_crossing};
use crate::mesh::Mesh;
use crate::query::pairs::QueryStats;

/// The winding number reported for a point that lies on the surface (on a triangle, its edges
/// and corners included), where no winding number is defined: `i32::MIN`, which no closed
/// surface's winding number reaches.
pub const WINDING_ON_SURFACE: i32 = i32::MIN;

/// The winding number of `p` about the surface `frame`, or [`WINDING_ON_SURFACE`].
pub(super) fn winding_number(frame: &Frame, p: &Point, w: &mut Walker) -> i32 {
    let mut sum: i64 = 0;
    let off = frame.along_ray(p, &mut w.stack, |t| {
        let [a, b, c] = frame.corners(t);
        match ray_crossing(p, [&a, &b, &c]) {
            Crossing::Adds(k) => {
                sum += i64::from(k);
                true
            }
            Crossing::OnTriangle => false,
        }
    });
    if !off {
        return WINDING_ON_SURFACE;
    }
    // At most one per triangle, and triangles are counted by u32: the sum fits unless the
    // surface crosses the ray more than two billion times one way.
    i32::try_from(sum).unwrap_or(if sum > 0 { i32::MAX } else { i32::MIN + 1 })
}

/// For each point of `points`, its winding number about the closed surface of mesh `mesh`
/// placed by `pose` (`None`: the mesh's coordinates are world coordinates), into `out` (one
/// entry per point): how many times the surface winds around the point, counted with sign (a
/// triangle's side is the one its normal `(t1 - t0) x (t2 - t0)` points to, so an outward
/// oriented surface winds once, +1, around its inside, and an inward one -1). 0 outside; 2 in a
/// region a folded surface wraps twice; [`WINDING_ON_SURFACE`] for a point on the surface. Exact for
/// every point: the crossings of a ray from the point are counted by exact orientation
/// predicates, with a symbolic perturbation where the ray meets an edge or a vertex, so no point
/// is ever misclassified. `threads` as [`crate::QueryOptions::threads`]; the answer is the same
/// for every count. The counters returned: the volumes tested, and the triangles whose crossing
/// was decided.
///
/// Errors: [`crate::Error::NotClosed`] for a mesh that is not closed ([`Mesh::is_closed`]), naming
/// the edge; [`crate::Error::NonFinitePoint`]; [`crate::Error::ResultLength`]. On error `out` is
/// unchanged.
pub fn winding_numbers(
    mesh: &Mesh,
    pose: Option<&Pose>,
    points: &[Point],
    threads: u32,
    out: &mut [i32],
) -> Result<QueryStats> {
    mesh.check_closed()?;
    check_points(points, out.len())?;
    Ok(super::closest::with_frame(mesh, pose, |frame| {
        answer_points(points, threads, out, |w, p| winding_number(frame, p, w))
    }))
}
