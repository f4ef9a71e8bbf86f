//! Conservative sphere arithmetic: radii rounded up, overlap tests that never say "apart" for
//! spheres that touch.

use super::aabb::Aabb;
use super::predicates::Point;

/// A closed ball: the bounding volume of the sphere hierarchies (DVH and SBV).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sphere {
    /// The centre.
    pub centre: Point,
    /// The radius: an upper bound, rounded up so that no point it must hold is left out.
    pub radius: f64,
}

impl Sphere {
    /// Might the two balls share a point? Never `false` when they do: the squared distance of the
    /// centres is compared with the squared sum of the radii with a relative slack that covers
    /// the rounding of both.
    #[inline(always)]
    pub fn meets(&self, other: &Sphere) -> bool {
        overlap(&self.centre, self.radius, &other.centre, other.radius)
    }

    /// Might the ball and the closed box share a point? Never `false` when they do: the squared
    /// distance from the centre to the box is computed in floating point and compared with a
    /// relative slack that covers its rounding (the box's own coordinates are exact).
    #[inline(always)]
    pub fn meets_box(&self, b: &Aabb) -> bool {
        let mut d2 = 0.0;
        for (k, &c) in self.centre.iter().enumerate() {
            let below = b.lo[k] - c;
            let above = c - b.hi[k];
            let gap = if below > 0.0 {
                below
            } else if above > 0.0 {
                above
            } else {
                0.0
            };
            d2 += gap * gap;
        }
        d2 <= self.radius * self.radius * OVERLAP_SLACK
    }
}

/// Relative widening of every computed radius: covers the rounding of a square root of a sum of
/// three squares (a few units in the last place) with a wide margin.
const RADIUS_RELATIVE: f64 = 1.0 + f64::EPSILON * 8.0;

/// Absolute floor of every radius. Squares of differences below about `2^-511` can underflow;
/// adding `2^-500` keeps the radius an upper bound there too. It is negligible at any scale where
/// the mesh is not itself below `1e-140`.
pub(crate) const RADIUS_FLOOR: f64 = f64::from_bits((1023 - 500) << 52);

/// Relative slack of the overlap test: covers the rounding of `|a - b|²` and of `(ra + rb)²`.
const OVERLAP_SLACK: f64 = 1.0 + f64::EPSILON * 16.0;

/// Squared Euclidean distance, in floating point.
#[inline(always)]
pub(crate) fn distance_squared(a: &Point, b: &Point) -> f64 {
    let dx = a[0] - b[0];
    let dy = a[1] - b[1];
    let dz = a[2] - b[2];
    dx * dx + dy * dy + dz * dz
}

/// An upper bound of the true distance, from a floating-point distance estimate `d`
/// (a square root of [`distance_squared`], or a sum of such and of radii).
#[inline(always)]
pub(crate) fn round_up(d: f64) -> f64 {
    d * RADIUS_RELATIVE + RADIUS_FLOOR
}

/// Might the balls `(ca, ra)` and `(cb, rb)` share a point? Never `false` when they do (radii must
/// be at least [`RADIUS_FLOOR`], as [`round_up`] makes them). Infinite radii overlap everything.
#[inline(always)]
pub(crate) fn overlap(ca: &Point, ra: f64, cb: &Point, rb: f64) -> bool {
    let s = ra + rb;
    distance_squared(ca, cb) <= s * s * OVERLAP_SLACK
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_spheres_overlap_at_every_scale() {
        for k in [-140, -60, -10, 0, 10, 60, 150] {
            let s = 2f64.powi(k);
            let a = [0.1 * s, 0.2 * s, 0.3 * s];
            let b = [0.1 * s + 0.7 * s, 0.2 * s, 0.3 * s + 0.4 * s];
            let d = distance_squared(&a, &b).sqrt();
            // Split the distance into two radii whose exact sum is at most the distance.
            let ra = round_up(d * 0.25);
            let rb = round_up(d * 0.75);
            assert!(overlap(&a, ra, &b, rb), "scale 2^{k}");
            assert!(!overlap(&a, d * 0.2, &b, d * 0.2), "scale 2^{k}");
        }
    }

    #[test]
    fn ball_against_box_is_conservative_at_every_scale() {
        for k in [-140, -60, 0, 60, 150] {
            let s = 2f64.powi(k);
            let b = Aabb {
                lo: [0.0, 0.0, 0.0],
                hi: [s, s, s],
            };
            // A ball touching the box's corner from outside, radius rounded up as refits do.
            let c = [2.0 * s, 2.0 * s, 2.0 * s];
            let d = (3.0f64).sqrt() * s;
            let touching = Sphere {
                centre: c,
                radius: round_up(d),
            };
            assert!(touching.meets_box(&b), "scale 2^{k}");
            let apart = Sphere {
                centre: c,
                radius: 0.99 * d,
            };
            assert!(!apart.meets_box(&b), "scale 2^{k}");
            let inside = Sphere {
                centre: [0.5 * s; 3],
                radius: RADIUS_FLOOR,
            };
            assert!(inside.meets_box(&b));
        }
    }

    #[test]
    fn infinite_and_huge_values_stay_conservative() {
        let a = [-1e300, 0.0, 0.0];
        let b = [1e300, 0.0, 0.0];
        assert!(overlap(&a, f64::INFINITY, &b, 0.0));
        assert!(overlap(&a, 1.5e300, &b, 1e300));
        // Squares of such distances overflow: the test may then only err towards "overlap".
        assert!(overlap(&a, 1e299, &b, 1e299));
        assert!(!overlap(
            &[-1e150, 0.0, 0.0],
            1e149,
            &[1e150, 0.0, 0.0],
            1e149
        ));
        assert!(round_up(0.0) > 0.0);
    }
}
