//! Signed distances of many points to a closed mesh: the exact closest distance, negative where
//! the surface winds around the point.

use super::closest::{closest_triangle, with_frame};
use super::options::DistanceOptions;
use super::order::{answer_points, check_points};
use super::winding::{WINDING_ON_SURFACE, winding_number};
use crate::error::Result;
use crate::geometry::nearest::{Primitive, values};
use crate::geometry::pose::Pose;
use crate::geometry::predicates::Point;
use crate::mesh::Mesh;
use crate::query::pairs::QueryStats;

/// For each point of `points`, its signed distance to the closed surface of mesh `mesh` placed
/// by `pose` (`None`: world coordinates), into `out` (one entry per point): the distance to the
/// closest point of the surface ([`crate::closest_points`]'s, decided and rounded the same way),
/// negative inside (where the winding number is not 0: [`crate::winding_numbers`], exact),
/// positive outside, 0 on the surface. A point farther than `max_distance` gets an infinity of
/// its sign. Tolerances and threads as for [`crate::closest_points`]; the sign is always exact.
/// The counters returned are the walks' (as [`crate::closest_points`]'s), `pairs` the points
/// within `max_distance`.
///
/// Errors: [`crate::Error::NotClosed`]; [`crate::Error::InvalidDistanceOption`];
/// [`crate::Error::NonFinitePoint`]; [`crate::Error::ResultLength`]. On error `out` is
/// unchanged.
pub fn signed_distances(
    mesh: &Mesh,
    pose: Option<&Pose>,
    points: &[Point],
    options: &DistanceOptions,
    out: &mut [f64],
) -> Result<QueryStats> {
    options.check()?;
    mesh.check_closed()?;
    check_points(points, out.len())?;
    let mut stats = with_frame(mesh, pose, |frame| {
        answer_points(points, options.threads, out, |w, p| {
            let distance = match closest_triangle(frame, p, options, w) {
                Some((t, decided)) => {
                    w.previous = Some(t);
                    let [a, b, c] = frame.corners(t);
                    values(Primitive::VertexFace, &[*p, a, b, c], decided).distance
                }
                None => {
                    w.previous = None;
                    f64::INFINITY
                }
            };
            let inside = match winding_number(frame, p, w) {
                WINDING_ON_SURFACE => return 0.0,
                0 => false,
                _ => true,
            };
            // Off the surface the distance is above 0, even where it rounds to 0.
            let distance = distance.max(f64::from_bits(1));
            if inside { -distance } else { distance }
        })
    });
    stats.pairs = out.iter().filter(|d| d.is_finite()).count() as u64;
    Ok(stats)
}
