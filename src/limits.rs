//! The numeric limits the library checks its inputs against (its error messages name them).

/// Largest magnitude a posed mesh's transformed coordinates may reach. Beyond it, differences of
/// world coordinates could overflow and the sphere tests would no longer be conservative.
pub const MAX_POSED_MAGNITUDE: f64 = 1e300;

/// Largest entry of `|RᵀR - I|` a pose's rotation may have. Rotations that went through `f32`
/// (quaternions, engine transforms) are orthonormal to about `1e-7`; anything far beyond this is a
/// scale or shear, which would break the sphere radii.
pub const RIGIDITY_TOLERANCE: f64 = 1e-5;
