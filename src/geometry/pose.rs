//! Rigid poses: a rotation and a translation, `world = R * p + t`.

use super::predicates::Point;
use crate::error::{Error, Result};
use nalgebra::{Isometry3, Matrix3, Vector3};

/// Largest entry of `|RᵀR - I|` a pose's rotation may have. Rotations that went through `f32`
/// (quaternions, engine transforms) are orthonormal to about `1e-7`; anything far beyond this is a
/// scale or shear, which would break the sphere radii.
pub const RIGIDITY_TOLERANCE: f64 = 1e-5;

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
        let r = Matrix3::from_fn(|i, j| rotation[i][j]);
        let gram = r.transpose() * r - Matrix3::identity();
        let deviation = gram.abs().max();
        let determinant = r.determinant();
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

    /// A pose from an nalgebra isometry.
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

    /// A pose from a rotation matrix and a translation vector (nalgebra types).
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

    #[test]
    fn isometry_round_trip() {
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
