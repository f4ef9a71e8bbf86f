//! Rigid poses: a rotation and a translation, `world = R * p + t`.

use super::predicates::Point;
use crate::error::{Error, Result};
#[cfg(feature = "nalgebra")]
use nalgebra::{Isometry3, Matrix3, Vector3};

pub use crate::limits::RIGIDITY_TOLERANCE;

/// A rigid motion of a mesh: `world = R * p + t`, with `R` a rotation (orthonormal within
/// [`RIGIDITY_TOLERANCE`], determinant positive).
///
/// With a pose, a query tests the triangles at the world coordinates computed by
/// [`Pose::transform_point`]; the exact triangle test then decides on those doubles. The sphere
/// tests are widened by a bound on the rounding of that transformation and on the rotation's
/// departure from orthonormality, so they never drop a pair the exact test would report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    rotation: [[f64; 3]; 3],
    translation: [f64; 3],
    /// Bound on the largest singular value of the rotation (1 for an exact rotation).
    stretch: f64,
    identity: bool,
}

impl Default for Pose {
    fn default() -> Self {
        Pose::IDENTITY
    }
}

impl Pose {
    /// The pose that changes nothing.
    pub const IDENTITY: Pose = Pose {
        rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        translation: [0.0; 3],
        stretch: 1.0,
        identity: true,
    };

    /// A pose from a row-major rotation and a translation.
    ///
    /// Errors: [`Error::NonFinitePose`] for a NaN or infinite entry, [`Error::NonRigidPose`] when
    /// the rotation is not orthonormal within [`RIGIDITY_TOLERANCE`] or is a reflection.
    pub fn new(rotation: [[f64; 3]; 3], translation: [f64; 3]) -> Result<Pose> {
        for (i, &v) in rotation.iter().flatten().enumerate() {
            if !v.is_finite() {
                return Err(Error::NonFinitePose {
                    part: "rotation",
                    index: i,
                    value: v,
                });
            }
        }
        for (i, &v) in translation.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::NonFinitePose {
                    part: "translation",
                    index: i,
                    value: v,
                });
            }
        }
        let (deviation, determinant) = rigidity(&rotation);
        // Written so that NaN fails too.
        let rigid = deviation <= RIGIDITY_TOLERANCE && determinant > 0.0;
        if !rigid {
            return Err(Error::NonRigidPose {
                deviation,
                determinant,
            });
        }
        // |R x|² = xᵀ(I + E)x ≤ (1 + 3·max|E|)|x|²; the extra term covers rounding of `deviation`.
        let stretch = (1.0 + 3.0 * deviation).sqrt() * (1.0 + 1e-12);
        let identity = rotation == Pose::IDENTITY.rotation && translation == [0.0; 3];
        Ok(Pose {
            rotation,
            translation,
            stretch: if identity { 1.0 } else { stretch },
            identity,
        })
    }

    /// A pose from an nalgebra isometry (cargo feature `nalgebra`).
    #[cfg(feature = "nalgebra")]
    pub fn from_isometry(isometry: &Isometry3<f64>) -> Result<Pose> {
        let m = isometry.rotation.to_rotation_matrix();
        let m = m.matrix();
        let t = isometry.translation.vector;
        Pose::new(
            [
                [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
                [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
                [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
            ],
            [t.x, t.y, t.z],
        )
    }

    /// A pose from a rotation matrix and a translation vector (nalgebra types; cargo feature
    /// `nalgebra`).
    #[cfg(feature = "nalgebra")]
    pub fn from_matrix(rotation: &Matrix3<f64>, translation: &Vector3<f64>) -> Result<Pose> {
        Pose::new(
            [0, 1, 2].map(|i| [rotation[(i, 0)], rotation[(i, 1)], rotation[(i, 2)]]),
            [translation.x, translation.y, translation.z],
        )
    }

    /// The rotation, row-major.
    pub fn rotation(&self) -> [[f64; 3]; 3] {
        self.rotation
    }

    /// The translation.
    pub fn translation(&self) -> [f64; 3] {
        self.translation
    }

    /// Is this exactly the identity (rotation `I`, translation zero)?
    pub fn is_identity(&self) -> bool {
        self.identity
    }

    /// `R * p + t`, evaluated as `((R[i][0] p.x + R[i][1] p.y) + R[i][2] p.z) + t[i]` in `f64`
    /// without fused operations. Queries test triangles at exactly these coordinates, so this is
    /// the function a reference computation must use to agree with them bit for bit.
    #[inline]
    pub fn transform_point(&self, p: &Point) -> Point {
        if self.identity {
            return *p;
        }
        let r = &self.rotation;
        let t = &self.translation;
        [0, 1, 2].map(|i| ((r[i][0] * p[0] + r[i][1] * p[1]) + r[i][2] * p[2]) + t[i])
    }

    /// Bound on the largest singular value of the rotation.
    pub(crate) fn stretch(&self) -> f64 {
        self.stretch
    }

    /// Bound on `|transform_point(p) - (R p + t)|` (Euclidean) over points with coordinates of
    /// magnitude at most `max_abs`, and on the magnitude of transformed coordinates.
    ///
    /// Each component is a sum of four terms evaluated in order, so its rounding error is at most
    /// `γ₄ (Σ|R_ij||p_j| + |t_i|)` with `γ₄ = 4u/(1-4u)` and `Σ|R_ij| ≤ √3·stretch`. The bound
    /// used is about twenty times larger, which costs nothing measurable and leaves room for the
    /// rounding of the bound itself.
    pub(crate) fn rounding_bound(&self, max_abs: f64) -> (f64, f64) {
        if self.identity {
            return (0.0, max_abs);
        }
        let t = self.translation.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let magnitude = 1.75 * self.stretch * max_abs + t;
        let u = f64::EPSILON / 2.0;
        let error = 2.0 * 16.0 * u * magnitude + f64::MIN_POSITIVE;
        (error, magnitude)
    }
}

/// How far `r` is from a rotation: the largest entry of `|RᵀR - I|`, and the determinant. The
/// operations are nalgebra's for `Matrix3` (`(r.transpose() * r - I).abs().max()`,
/// `r.determinant()`), in its order, so that the figures, the poses accepted and the widening of
/// the sphere tests are those of the releases that computed them with nalgebra.
fn rigidity(r: &[[f64; 3]; 3]) -> (f64, f64) {
    // Entry (i, j) of RᵀR: column i of R against column j, summed over rows 0, 1, 2 in order.
    let gram = |i: usize, j: usize| r[0][i] * r[0][j] + r[1][i] * r[1][j] + r[2][i] * r[2][j];
    // Folded column-major from the first entry, each step keeping the running value when it
    // is `>=` the next entry (a NaN entry therefore wins over the entries before it only), as
    // nalgebra's `max` does.
    let mut deviation = (gram(0, 0) - 1.0).abs();
    for j in 0..3 {
        for i in (0..3).filter(|&i| (i, j) != (0, 0)) {
            let e = (gram(i, j) - if i == j { 1.0 } else { 0.0 }).abs();
            deviation = if deviation >= e { deviation } else { e };
        }
    }
    let [[m11, m12, m13], [m21, m22, m23], [m31, m32, m33]] = *r;
    let minor_m12_m23 = m22 * m33 - m32 * m23;
    let minor_m11_m23 = m21 * m33 - m31 * m23;
    let minor_m11_m22 = m21 * m32 - m31 * m22;
    let determinant = m11 * minor_m12_m23 - m12 * minor_m11_m23 + m13 * minor_m11_m22;
    (deviation, determinant)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_is_detected_and_exact() {
        let p = Pose::new(
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [0.0; 3],
        )
        .unwrap();
        assert!(p.is_identity());
        let q = [0.1, -3e200, 7e-300];
        assert_eq!(p.transform_point(&q), q);
        assert_eq!(Pose::default(), Pose::IDENTITY);
    }

    #[test]
    fn rejects_non_rigid_and_non_finite() {
        let s = 1.001;
        let err =
            Pose::new([[s, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], [0.0; 3]).unwrap_err();
        assert!(matches!(err, Error::NonRigidPose { .. }), "{err}");
        assert!(err.to_string().contains("R^T R - I"), "{err}");
        let err = Pose::new(
            [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [0.0; 3],
        )
        .unwrap_err();
        assert!(matches!(err, Error::NonRigidPose { determinant, .. } if determinant < 0.0));
        let err = Pose::new(
            [[1.0, 0.0, 0.0], [0.0, f64::NAN, 0.0], [0.0, 0.0, 1.0]],
            [0.0; 3],
        )
        .unwrap_err();
        assert!(
            matches!(err, Error::NonFinitePose { part: "rotation", index: 4, value } if value.is_nan())
        );
        let err = Pose::new(Pose::IDENTITY.rotation, [0.0, f64::INFINITY, 0.0]).unwrap_err();
        assert!(matches!(
            err,
            Error::NonFinitePose {
                part: "translation",
                index: 1,
                ..
            }
        ));
        // A rotation from f32 data is accepted.
        let a = 0.3f32;
        let (c, s) = (f64::from(a.cos()), f64::from(a.sin()));
        assert!(
            Pose::new(
                [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
                [1.0, 2.0, 3.0]
            )
            .is_ok()
        );
    }

    /// The figures of [`rigidity`] are nalgebra's, bit for bit, on rotations, near-rotations,
    /// shears, reflections and entries whose products overflow.
    #[test]
    fn rigidity_is_nalgebras_arithmetic() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for case in 0..20_000 {
            let mut unit = || (next() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            let (a, b, c) = (unit() * 3.2, unit() * 3.2, unit() * 3.2);
            let rotation = nalgebra::Rotation3::from_euler_angles(a, b, c);
            let mut r: [[f64; 3]; 3] =
                std::array::from_fn(|i| std::array::from_fn(|j| rotation[(i, j)]));
            match case % 5 {
                0 => {}
                1 => r[(case / 5) % 3][case % 3] += unit() * 1e-5,
                2 => r = r.map(|row| row.map(|v| v * (1.0 + unit()))),
                3 => r[0] = r[0].map(|v| -v),
                _ => r[case % 3][(case / 3) % 3] = unit() * 1e300,
            }
            let m = nalgebra::Matrix3::from_fn(|i, j| r[i][j]);
            let expected = (
                (m.transpose() * m - nalgebra::Matrix3::identity())
                    .abs()
                    .max(),
                m.determinant(),
            );
            let got = rigidity(&r);
            assert_eq!(got.0.to_bits(), expected.0.to_bits(), "deviation of {r:?}");
            assert_eq!(
                got.1.to_bits(),
                expected.1.to_bits(),
                "determinant of {r:?}"
            );
        }
    }

    #[test]
    #[cfg(feature = "nalgebra")]
    fn isometry_round_trip() {
        use nalgebra::{Isometry3, Vector3};
        let iso = Isometry3::new(Vector3::new(1.0, -2.0, 0.5), Vector3::new(0.3, 0.2, -0.1));
        let pose = Pose::from_isometry(&iso).unwrap();
        let p = [0.7, -1.1, 2.5];
        let expected = iso.transform_point(&nalgebra::Point3::new(p[0], p[1], p[2]));
        let got = pose.transform_point(&p);
        for i in 0..3 {
            assert!((got[i] - expected[i]).abs() < 1e-12);
        }
        let (err, mag) = pose.rounding_bound(3.0);
        assert!(err > 0.0 && err < 1e-13);
        assert!(mag >= 3.0);
    }
}
