//! The exact triangle test against an independent exact oracle.

use super::input::Bytes;
use dvh::ffi::*;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

/// The exact value of a finite double.
fn exact(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// Do the closed triangles share a point? Exact, by other means than dvh's: a point of both is
/// `sum u_i a_i = sum v_j b_j` with `u, v >= 0` summing to 1 each, a linear feasibility
/// problem; it is feasible exactly when some basic solution is (columns linearly independent,
/// solved exactly, non-negative), so every subset of the six columns is tried.
pub fn oracle(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> bool {
    // Boxes apart along an axis share no point (comparing doubles is exact): most random pairs
    // end here, without rationals.
    let span = |t: &[[f64; 3]; 3], k: usize| {
        let v = t.map(|p| p[k]);
        (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]))
    };
    if (0..3).any(|k| span(a, k).1 < span(b, k).0 || span(b, k).1 < span(a, k).0) {
        return false;
    }
    // Rows: x, y, z of a_i (positive) and b_j (negative), then the two sums.
    let mut cols: Vec<[BigRational; 5]> = Vec::with_capacity(6);
    for (tri, sign, which) in [(a, 1, 0), (b, -1, 1)] {
        for p in tri {
            let s = BigRational::from_integer(BigInt::from(sign));
            cols.push([
                exact(p[0]) * &s,
                exact(p[1]) * &s,
                exact(p[2]) * &s,
                BigRational::from_integer(BigInt::from(u8::from(which == 0))),
                BigRational::from_integer(BigInt::from(u8::from(which == 1))),
            ]);
        }
    }
    let rhs: [BigRational; 5] = [
        BigRational::zero(),
        BigRational::zero(),
        BigRational::zero(),
        BigRational::from_integer(1.into()),
        BigRational::from_integer(1.into()),
    ];
    (1u32..64).any(|subset| {
        let chosen: Vec<usize> = (0..6).filter(|k| subset & 1 << k != 0).collect();
        if chosen.len() > 5 {
            return false;
        }
        solve(&chosen.iter().map(|&k| &cols[k]).collect::<Vec<_>>(), &rhs)
            .is_some_and(|x| x.iter().all(|v| !v.is_negative()))
    })
}

/// The unique solution of `sum x_k c_k = rhs` when the columns `c` are independent and the
/// system consistent; `None` otherwise. Gaussian elimination in rationals.
fn solve(c: &[&[BigRational; 5]], rhs: &[BigRational; 5]) -> Option<Vec<BigRational>> {
    let n = c.len();
    // Augmented 5 x (n + 1) matrix.
    let mut m: Vec<Vec<BigRational>> = (0..5)
        .map(|r| {
            let mut row: Vec<BigRational> = c.iter().map(|col| col[r].clone()).collect();
            row.push(rhs[r].clone());
            row
        })
        .collect();
    let mut row = 0;
    for col in 0..n {
        let pivot = (row..5).find(|&r| !m[r][col].is_zero())?; // dependent columns
        m.swap(row, pivot);
        let p = m[row][col].clone();
        for v in &mut m[row][col..] {
            *v = &*v / &p;
        }
        let pivot_row = m[row].clone();
        for (r, line) in m.iter_mut().enumerate() {
            if r != row && !line[col].is_zero() {
                let f = line[col].clone();
                for (v, pv) in line[col..].iter_mut().zip(&pivot_row[col..]) {
                    *v -= &f * pv;
                }
            }
        }
        row += 1;
    }
    // Consistent: the rows below are all zero, right-hand side included.
    if (row..5).any(|r| !m[r][n].is_zero()) {
        return None;
    }
    Some((0..n).map(|k| m[k][n].clone()).collect())
}

/// Gives the triangles a shape that free doubles almost never have, as a trailing byte says
/// (none when the input ends before it, so shorter inputs keep their meaning): both in one plane,
/// sharing vertices, degenerate. Those are where the exact test takes its rare branches
/// (coplanar projections, touching at a vertex or an edge, segments and points).
fn shape(bytes: &mut Bytes, a: &mut [[f64; 3]; 3], b: &mut [[f64; 3]; 3]) {
    let how = bytes.u8();
    match how % 4 {
        // All six in the plane where axis `k` is `c`.
        1 => {
            let (k, c) = (usize::from(bytes.u8() % 3), bytes.f64());
            for p in a.iter_mut().chain(b.iter_mut()) {
                p[k] = c;
            }
        }
        // All six at `o + x u + y v`, (x, y) their first two coordinates: one plane in general
        // position (exactly, when the arithmetic is; the oracle judges the doubles given).
        2 | 3 => {
            let small = |bytes: &mut Bytes| f64::from(bytes.u8() as i8 % 8);
            let mut vector = || [small(bytes), small(bytes), small(bytes)];
            let (o, u, v) = (vector(), vector(), vector());
            for p in a.iter_mut().chain(b.iter_mut()) {
                let (x, y) = (p[0], p[1]);
                *p = [0, 1, 2].map(|k| o[k] + x * u[k] + y * v[k]);
            }
        }
        _ => {}
    }
    // Vertices of `b` taken from `a` (a shared vertex, a shared edge, the same triangle).
    if how & 4 != 0 {
        let share = bytes.u8();
        for (j, q) in b.iter_mut().enumerate() {
            let i = usize::from(share >> (2 * j) & 3);
            if i < 3 {
                *q = a[i];
            }
        }
    }
    // Degenerate: a vertex on the line of the other two (midpoint) or on one of them.
    for (t, bit) in [(&mut *a, 8), (&mut *b, 16)] {
        if how & bit != 0 {
            t[2] = if how & 32 != 0 {
                t[0]
            } else {
                [0, 1, 2].map(|k| t[0][k] / 2.0 + t[1][k] / 2.0)
            };
        }
    }
}

/// Differential target: dvh's exact triangle test (Rust and C) against [`oracle`].
pub fn triangle_oracle(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let corner = |bytes: &mut Bytes| [bytes.f64(), bytes.f64(), bytes.f64()];
    let tri = |bytes: &mut Bytes| [corner(bytes), corner(bytes), corner(bytes)];
    let (mut a, mut b) = (tri(&mut bytes), tri(&mut bytes));
    shape(&mut bytes, &mut a, &mut b);
    let finite = a.iter().chain(&b).flatten().all(|x| x.is_finite());
    let mut result = false;
    // SAFETY: nine readable doubles each, a writable result.
    let status =
        unsafe { dvh_triangles_intersect(a.as_ptr().cast(), b.as_ptr().cast(), &mut result) };
    if !finite {
        assert_eq!(status, DVH_STATUS_NON_FINITE_COORDINATE);
        return;
    }
    assert_eq!(status, DVH_STATUS_OK);
    let got = dvh::exact::triangles_intersect(&a, &b);
    assert_eq!(got, result, "Rust and C disagree on {a:?} {b:?}");
    assert_eq!(
        got,
        oracle(&a, &b),
        "dvh and the oracle disagree on {a:?} {b:?}"
    );
}
