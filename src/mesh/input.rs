//! Checking user input before anything is built or changed.

use crate::error::{Error, Result};
use crate::geometry::aabb::Aabb;
use crate::geometry::predicates::{Point, SAFE_MAX, SAFE_MIN};

/// What a scan of the coordinates learned, besides that they are valid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Extent {
    /// Largest coordinate magnitude.
    pub max_abs: f64,
    /// Is every coordinate inside the range where the adaptive predicates are exact?
    pub in_fast_range: bool,
    /// The box of the points (a scene's broad phase reads it; the scan has every coordinate
    /// at hand, where a second pass would read the positions again).
    pub bounds: Aabb,
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
    let mut scan = Scan::new();
    let chunks = positions.chunks_exact(SCAN_LANES);
    let tail = chunks.remainder();
    for c in chunks {
        for (lane, &v) in c.iter().enumerate() {
            scan.fold(lane, v);
        }
    }
    for (lane, &v) in tail.iter().enumerate() {
        scan.fold(lane, v);
    }
    if !scan.finite() {
        return Err(first_non_finite(count, |v| {
            [positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]]
        }));
    }
    Ok(scan.extent())
}

/// Lanes of [`Scan`]: two vertices' coordinates, so that no running extreme waits on the last.
const SCAN_LANES: usize = 6;

/// A running check of coordinates: largest magnitude, smallest non-zero magnitude, and a sum of
/// `v - v` (0 for a finite value, NaN otherwise, and a NaN stays), in independent lanes that
/// the compiler keeps in SIMD registers.
struct Scan {
    largest: [f64; SCAN_LANES],
    smallest: [f64; SCAN_LANES],
    poison: [f64; SCAN_LANES],
    /// Least and greatest value per lane (lane `k` holds axis `k % 3`).
    lo: [f64; SCAN_LANES],
    hi: [f64; SCAN_LANES],
}

impl Scan {
    fn new() -> Scan {
        Scan {
            largest: [0.0; SCAN_LANES],
            smallest: [f64::INFINITY; SCAN_LANES],
            poison: [0.0; SCAN_LANES],
            lo: [f64::INFINITY; SCAN_LANES],
            hi: [f64::NEG_INFINITY; SCAN_LANES],
        }
    }

    #[inline(always)]
    fn fold(&mut self, k: usize, v: f64) {
        let a = v.abs();
        self.largest[k] = if a > self.largest[k] {
            a
        } else {
            self.largest[k]
        };
        let nonzero = if a == 0.0 { f64::INFINITY } else { a };
        self.smallest[k] = if nonzero < self.smallest[k] {
            nonzero
        } else {
            self.smallest[k]
        };
        // Zero for a finite value, NaN for infinity or NaN: the point of the expression.
        #[allow(clippy::eq_op)]
        let poisoned = v - v;
        self.poison[k] += poisoned;
        self.lo[k] = if v < self.lo[k] { v } else { self.lo[k] };
        self.hi[k] = if v > self.hi[k] { v } else { self.hi[k] };
    }

    /// The scan of both inputs.
    fn merge(&self, other: &Scan) -> Scan {
        let mut out = Scan::new();
        for k in 0..SCAN_LANES {
            out.largest[k] = self.largest[k].max(other.largest[k]);
            out.smallest[k] = self.smallest[k].min(other.smallest[k]);
            out.poison[k] = self.poison[k] + other.poison[k];
            out.lo[k] = self.lo[k].min(other.lo[k]);
            out.hi[k] = self.hi[k].max(other.hi[k]);
        }
        out
    }

    fn finite(&self) -> bool {
        self.poison.iter().all(|p| *p == 0.0)
    }

    fn extent(&self) -> Extent {
        let largest = self.largest.into_iter().fold(0.0f64, f64::max);
        let smallest = self.smallest.into_iter().fold(f64::INFINITY, f64::min);
        Extent {
            max_abs: largest,
            in_fast_range: largest <= SAFE_MAX && smallest >= SAFE_MIN,
            bounds: Aabb {
                lo: [0, 1, 2].map(|k| self.lo[k].min(self.lo[k + 3])),
                hi: [0, 1, 2].map(|k| self.hi[k].max(self.hi[k + 3])),
            },
        }
    }
}

/// The first non-finite coordinate, as an error (there must be one).
fn first_non_finite(count: usize, position: impl Fn(usize) -> Point) -> Error {
    for vertex in 0..count {
        let p = position(vertex);
        if let Some(axis) = p.iter().position(|v| !v.is_finite()) {
            return Error::NonFiniteCoordinate {
                vertex,
                axis,
                value: p[axis],
            };
        }
    }
    unreachable!("a non-finite coordinate was seen")
}

/// Checks every coordinate of a flat `x, y, z` array of `out.len()` vertices (its length checked
/// by the caller) and copies it to `out`, in one pass. On error, `out` holds garbage: the caller
/// writes into a spare buffer.
pub(crate) fn store_positions(input: &[f64], out: &mut [Point], threads: usize) -> Result<Extent> {
    debug_assert_eq!(input.len(), 3 * out.len());
    let scan = scan_store(input, out, threads);
    if !scan.finite() {
        return Err(first_non_finite(out.len(), |v| {
            [input[3 * v], input[3 * v + 1], input[3 * v + 2]]
        }));
    }
    Ok(scan.extent())
}

/// Below this many vertices per thread, storing positions stays on fewer threads.
const STORE_VERTICES_PER_THREAD: usize = 16_384;

/// Copies and scans `input` into `out`, halves on two threads while each has `threads` to spare
/// and enough vertices.
fn scan_store(input: &[f64], out: &mut [Point], threads: usize) -> Scan {
    if threads < 2 || out.len() < 2 * STORE_VERTICES_PER_THREAD {
        return scan_store_here(input, out);
    }
    // An even split point keeps both halves' lanes aligned on vertex pairs.
    let mid = (out.len() / 2) & !1;
    let (in_lo, in_hi) = input.split_at(3 * mid);
    let (out_lo, out_hi) = out.split_at_mut(mid);
    let (left, right) = crate::threads::join(
        crate::threads::Step::Store,
        || scan_store(in_lo, out_lo, threads / 2),
        || scan_store(in_hi, out_hi, threads - threads / 2),
    );
    left.merge(&right)
}

/// [`scan_store`] on the calling thread.
fn scan_store_here(input: &[f64], out: &mut [Point]) -> Scan {
    let mut scan = Scan::new();
    let pairs = input.chunks_exact(SCAN_LANES);
    let tail = pairs.remainder();
    let (two, last) = out.split_at_mut(out.len() & !1);
    for (c, o) in pairs.zip(two.chunks_exact_mut(2)) {
        for (lane, &v) in c.iter().enumerate() {
            scan.fold(lane, v);
        }
        o[0] = [c[0], c[1], c[2]];
        o[1] = [c[3], c[4], c[5]];
    }
    if let ([x, y, z], [o]) = (tail, last) {
        for (lane, v) in [*x, *y, *z].into_iter().enumerate() {
            scan.fold(lane, v);
        }
        *o = [*x, *y, *z];
    }
    scan
}

/// [`store_positions`] for points read one by one (`out.len()` of them).
pub(crate) fn store_points(position: impl Fn(usize) -> Point, out: &mut [Point]) -> Result<Extent> {
    let mut scan = Scan::new();
    for (v, o) in out.iter_mut().enumerate() {
        let p = position(v);
        for (lane, &x) in p.iter().enumerate() {
            scan.fold(lane, x);
        }
        *o = p;
    }
    if !scan.finite() {
        return Err(first_non_finite(out.len(), position));
    }
    Ok(scan.extent())
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
                in_fast_range: true,
                bounds: Aabb {
                    lo: [1.0, -2.0, 0.0],
                    hi: [1.0, -2.0, 0.0]
                }
            }
        );
        assert!(!scan_positions(&[1e-300, 0.0, 0.0]).unwrap().in_fast_range);
        assert!(!scan_positions(&[1e100, 0.0, 0.0]).unwrap().in_fast_range);
    }
}
