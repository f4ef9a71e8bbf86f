//! What the fuzz targets run, shared with `tests/fuzz_replay.rs`, which replays the kept inputs
//! under `cargo test` (stable): each driver turns arbitrary bytes into calls and panics when a
//! promise breaks.
//!
//! - [`triangle_oracle`]: the exact triangle test against an independent exact oracle (a
//!   feasibility test of the two triangles' convex combinations meeting, in rationals).
//! - [`c_abi`]: the C ABI driven in the order the bytes say, with the counts, indices,
//!   positions, options, poses and distances they say; no call may report an internal panic,
//!   and a failed call must leave the mesh and the result buffer as they were.

#![allow(dead_code)] // each fuzz target uses one driver

use dvh::ffi::*;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

/// Reads the input as a little stream of values; past its end, zeros.
pub struct Bytes<'a>(&'a [u8]);

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Bytes(data)
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn u8(&mut self) -> u8 {
        let (&b, rest) = self.0.split_first().unwrap_or((&0, &[]));
        self.0 = rest;
        b
    }

    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }

    /// A double, mostly from a few interesting families, sometimes any bit pattern.
    pub fn f64(&mut self) -> f64 {
        match self.u8() % 8 {
            0 => f64::from_bits(u64::from(self.u32()) | u64::from(self.u32()) << 32),
            1 => f64::from(self.u8() as i8) * 2f64.powi(i32::from(self.u8() as i8) * 8),
            2 => f64::from(self.u8() % 5) - 2.0,
            _ => f64::from(self.u8() as i8) / 16.0,
        }
    }
}

/// The exact value of a finite double.
fn exact(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// Do the closed triangles share a point? Exact, by other means than dvh's: a point of both is
/// `sum u_i a_i = sum v_j b_j` with `u, v >= 0` summing to 1 each, a linear feasibility
/// problem; it is feasible exactly when some basic solution is (columns linearly independent,
/// solved exactly, non-negative), so every subset of the six columns is tried.
pub fn oracle(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> bool {
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

/// Differential target: dvh's exact triangle test (Rust and C) against [`oracle`].
pub fn triangle_oracle(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let corner = |bytes: &mut Bytes| [bytes.f64(), bytes.f64(), bytes.f64()];
    let tri = |bytes: &mut Bytes| [corner(bytes), corner(bytes), corner(bytes)];
    let (a, b) = (tri(&mut bytes), tri(&mut bytes));
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
    let got = dvh::triangles_intersect(&a, &b);
    assert_eq!(got, result, "Rust and C disagree on {a:?} {b:?}");
    assert_eq!(
        got,
        oracle(&a, &b),
        "dvh and the oracle disagree on {a:?} {b:?}"
    );
}

/// Everything a mesh handle reports, to check that a failed call changed nothing.
fn snapshot(mesh: *const DvhMesh, pairs: *const DvhPairs) -> (usize, usize, u64, Vec<(u32, u32)>) {
    let mut stats = DvhRefitStats::default();
    // SAFETY: live handles, one thread.
    unsafe {
        assert_eq!(dvh_mesh_last_refit_stats(mesh, &mut stats), DVH_STATUS_OK);
        assert_eq!(dvh_mesh_validate(mesh), DVH_STATUS_OK);
        let n = dvh_pairs_len(pairs);
        let data = dvh_pairs_data(pairs);
        let list = (0..n)
            .map(|i| ((*data.add(i)).a, (*data.add(i)).b))
            .collect();
        (
            dvh_mesh_vertex_count(mesh),
            dvh_mesh_node_count(mesh),
            stats.nodes_refit,
            list,
        )
    }
}

/// Structural target: the C ABI in the order the bytes say.
pub fn c_abi(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    // A mesh from the bytes: small counts, indices sometimes out of range, any doubles.
    let vertex_count = 1 + usize::from(bytes.u8() % 24);
    let triangle_count = usize::from(bytes.u8() % 24);
    let positions: Vec<f64> = (0..3 * vertex_count).map(|_| bytes.f64()).collect();
    let indices: Vec<u32> = (0..3 * triangle_count)
        .map(|_| {
            let i = bytes.u8();
            if i == 255 {
                bytes.u32()
            } else {
                u32::from(i) % vertex_count as u32
            }
        })
        .collect();
    let mut options = dvh_build_options_default();
    options.tree = u32::from(bytes.u8() % 3);
    options.volume = u32::from(bytes.u8() % 4);
    options.radius = u32::from(bytes.u8() % 3);
    options.leftovers = u32::from(bytes.u8() % 3);
    options.refit_threads = u32::from(bytes.u8() % 3);
    let mut mesh = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given.
    let status = unsafe {
        dvh_mesh_create(
            positions.as_ptr(),
            vertex_count,
            indices.as_ptr(),
            triangle_count,
            &options,
            &mut mesh,
        )
    };
    assert_ne!(status, DVH_STATUS_INTERNAL_PANIC);
    if status != DVH_STATUS_OK {
        assert!(mesh.is_null(), "a failed create wrote its out-parameter");
        return;
    }
    let pairs = dvh_pairs_new();
    while !bytes.is_empty() {
        let before = snapshot(mesh, pairs);
        let mut query = dvh_query_options_default();
        query.mode = u32::from(bytes.u8() % 8);
        query.max_depth = u32::from(bytes.u8() % 8);
        query.max_pairs = u64::from(bytes.u8() % 4) * 3;
        query.budget = u64::from(bytes.u8() % 4) * 5;
        query.threads = u32::from(bytes.u8() % 3);
        let pose = DvhPose {
            rotation: std::array::from_fn(|_| {
                if bytes.u8().is_multiple_of(4) {
                    bytes.f64()
                } else {
                    0.0
                }
            }),
            translation: [bytes.f64(), bytes.f64(), bytes.f64()],
        };
        let pose = {
            let mut p = pose;
            // Mostly rotations, sometimes whatever the bytes said.
            if !bytes.u8().is_multiple_of(3) {
                p.rotation = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
            }
            p
        };
        let distance = bytes.f64();
        let moved: Vec<f64> = positions.iter().map(|&x| x + bytes.f64()).collect();
        let mut stats = DvhQueryStats::default();
        // SAFETY: live handles and readable arguments, one thread.
        let (status, changes_mesh) = unsafe {
            match bytes.u8() % 6 {
                0 => (dvh_mesh_refit(mesh, moved.as_ptr(), vertex_count), true),
                1 => (
                    dvh_collide(
                        mesh,
                        std::ptr::null(),
                        mesh,
                        &pose,
                        &query,
                        pairs,
                        &mut stats,
                    ),
                    false,
                ),
                2 => (dvh_self_collide(mesh, &query, pairs, &mut stats), false),
                3 => (
                    dvh_proximity(
                        mesh,
                        &pose,
                        mesh,
                        std::ptr::null(),
                        distance,
                        &query,
                        pairs,
                        &mut stats,
                    ),
                    false,
                ),
                4 => (
                    dvh_self_proximity(mesh, distance, &query, pairs, &mut stats),
                    false,
                ),
                _ => (
                    dvh_mesh_refit(
                        mesh,
                        positions.as_ptr(),
                        vertex_count + usize::from(bytes.u8() % 2),
                    ),
                    true,
                ),
            }
        };
        assert_ne!(status, DVH_STATUS_INTERNAL_PANIC);
        if status != DVH_STATUS_OK {
            assert_eq!(
                snapshot(mesh, pairs),
                before,
                "a failed call changed something"
            );
        } else if !changes_mesh {
            let after = snapshot(mesh, pairs);
            assert_eq!(
                (after.0, after.1, after.2),
                (before.0, before.1, before.2),
                "a query changed the mesh"
            );
        }
    }
    // SAFETY: live handles, released once.
    unsafe {
        dvh_pairs_free(pairs);
        dvh_mesh_free(mesh);
    }
}
