//! The aliases the adapter speaks, for the rapier it was built against, and
//! the one place where rapier's vectors (glam) meet the law's (nalgebra).

use nalgebra::SVector;

pub use crate::rapier::math::{DIM, Pose, Real, Vector};

/// The precision of this build: `Real` is `f32` in `kimpact2d` and
/// `kimpact3d`, `f64` in `kimpact2d-f64` and `kimpact3d-f64`.
#[cfg(all(feature = "f32", not(feature = "f64")))]
pub const PRECISION: kimpact::Precision = kimpact::Precision::F32;
/// The precision of this build: `Real` is `f32` in `kimpact2d` and
/// `kimpact3d`, `f64` in `kimpact2d-f64` and `kimpact3d-f64`.
#[cfg(feature = "f64")]
pub const PRECISION: kimpact::Precision = kimpact::Precision::F64;

/// The law's vector type for this dimension and precision.
pub type LawVector = SVector<Real, DIM>;

/// rapier (glam) → law (nalgebra).
#[inline]
pub fn to_law(v: Vector) -> LawVector {
    #[cfg(feature = "dim2")]
    {
        LawVector::new(v.x, v.y)
    }
    #[cfg(feature = "dim3")]
    {
        LawVector::new(v.x, v.y, v.z)
    }
}

/// law (nalgebra) → rapier (glam).
#[inline]
pub fn from_law(v: &LawVector) -> Vector {
    #[cfg(feature = "dim2")]
    {
        Vector::new(v[0], v[1])
    }
    #[cfg(feature = "dim3")]
    {
        Vector::new(v[0], v[1], v[2])
    }
}
