//! Checking user input before anything is built or changed.

use crate::error::{Error, Result};
use crate::geometry::predicates::{Point, SAFE_MAX, SAFE_MIN};

/// What a scan of the coordinates learned, besides that they are valid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Extent {
    /// Largest coordinate magnitude.
    pub max_abs: f64,
    /// Is every coordinate inside the range where the adaptive predicates are exact?
    pub safe: bool,
}

/// Checks a flat `x, y, z` position array: length a multiple of 3, every value finite.
pub(crate) fn scan_positions(positions: &[f64]) -> Result<Extent> {
    if !positions.len().is_multiple_of(3) {
        return Err(Error::PositionsLength {
            len: positions.len(),
        });
    }
    let count = positions.len() / 3;
    if count > u32::MAX as usize {
        return Err(Error::TooManyVertices { count });
    }
    // One branch-free pass, which the compiler vectorises (every refit pays for it); the first
    // bad value is looked for only when there is one.
    let mut largest = 0.0f64;
    let mut smallest_nonzero = f64::INFINITY;
    let mut finite = true;
    for &v in positions {
        let a = v.abs();
        finite &= a <= f64::MAX;
        largest = if a > largest { a } else { largest };
        let nonzero = if a == 0.0 { f64::INFINITY } else { a };
        smallest_nonzero = if nonzero < smallest_nonzero {
            nonzero
        } else {
            smallest_nonzero
        };
    }
    if !finite {
        let i = positions
            .iter()
            .position(|v| !v.is_finite())
            .expect("a non-finite value");
        return Err(Error::NonFiniteCoordinate {
            vertex: i / 3,
            axis: i % 3,
            value: positions[i],
        });
    }
    Ok(Extent {
        max_abs: largest,
        safe: largest <= SAFE_MAX && smallest_nonzero >= SAFE_MIN,
    })
}

/// [`scan_positions`] for points read one by one.
pub(crate) fn scan_points(count: usize, position: impl Fn(usize) -> Point) -> Result<Extent> {
    let mut largest = 0.0f64;
    let mut smallest_nonzero = f64::INFINITY;
    for i in 0..count {
        let p = position(i);
        for (axis, &v) in p.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::NonFiniteCoordinate {
                    vertex: i,
                    axis,
                    value: v,
                });
            }
            let a = v.abs();
            largest = largest.max(a);
            if a != 0.0 {
                smallest_nonzero = smallest_nonzero.min(a);
            }
        }
    }
    Ok(Extent {
        max_abs: largest,
        safe: largest <= SAFE_MAX && smallest_nonzero >= SAFE_MIN,
    })
}

/// Checks a flat triangle index array against `vertex_count`.
pub(crate) fn check_triangles(triangles: &[u32], vertex_count: usize) -> Result<()> {
    if !triangles.len().is_multiple_of(3) {
        return Err(Error::TrianglesLength {
            len: triangles.len(),
        });
    }
    if triangles.is_empty() {
        return Err(Error::NoTriangles);
    }
    let count = triangles.len() / 3;
    if count > u32::MAX as usize {
        return Err(Error::TooManyTriangles { count });
    }
    for (i, &index) in triangles.iter().enumerate() {
        if index as usize >= vertex_count {
            return Err(Error::IndexOutOfRange {
                triangle: i / 3,
                corner: i % 3,
                index,
                vertex_count,
            });
        }
    }
    Ok(())
}

/// Copies a checked flat array into points.
pub(crate) fn to_points(positions: &[f64]) -> Vec<Point> {
    positions
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_what_is_wrong() {
        assert_eq!(
            scan_positions(&[0.0; 4]),
            Err(Error::PositionsLength { len: 4 })
        );
        let e = scan_positions(&[0.0, 0.0, 0.0, 1.0, f64::INFINITY, 2.0]).unwrap_err();
        assert_eq!(
            e,
            Error::NonFiniteCoordinate {
                vertex: 1,
                axis: 1,
                value: f64::INFINITY
            }
        );
        assert!(e.to_string().contains("vertex 1") && e.to_string().contains("y"));
        assert_eq!(check_triangles(&[], 3), Err(Error::NoTriangles));
        assert_eq!(
            check_triangles(&[0, 1], 3),
            Err(Error::TrianglesLength { len: 2 })
        );
        let e = check_triangles(&[0, 1, 2, 2, 3, 1], 3).unwrap_err();
        assert_eq!(
            e,
            Error::IndexOutOfRange {
                triangle: 1,
                corner: 1,
                index: 3,
                vertex_count: 3
            }
        );
        assert!(e.to_string().contains("triangle 1, corner 1"));
    }

    #[test]
    fn extent_tracks_the_safe_range() {
        let e = scan_positions(&[1.0, -2.0, 0.0]).unwrap();
        assert_eq!(
            e,
            Extent {
                max_abs: 2.0,
                safe: true
            }
        );
        assert!(!scan_positions(&[1e-300, 0.0, 0.0]).unwrap().safe);
        assert!(!scan_positions(&[1e100, 0.0, 0.0]).unwrap().safe);
    }
}
