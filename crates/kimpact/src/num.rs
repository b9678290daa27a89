//! Small numeric helpers shared by the law's modules.

use nalgebra::{RealField, SVector};

use crate::error::LawError;

/// The unit vector along `normal`, scaled first by its largest component so
/// that neither tiny nor huge normals under- or overflow.
pub(crate) fn unit_normal<T: RealField + Copy, const D: usize>(
    normal: &SVector<T, D>,
) -> Result<SVector<T, D>, LawError> {
    if let Some(component) = normal.iter().position(|c| !c.is_finite()) {
        return Err(LawError::NonFiniteNormal {
            component,
            value: to_f64(normal[component]),
        });
    }
    let scale = normal.amax();
    if scale == T::zero() {
        return Err(LawError::ZeroNormal);
    }
    let scaled = normal / scale;
    Ok(scaled / scaled.norm())
}

pub(crate) fn half<T: RealField + Copy>() -> T {
    T::from_subset(&0.5)
}

pub(crate) fn to_f64<T: RealField + Copy>(x: T) -> f64 {
    x.to_subset().unwrap_or(f64::NAN)
}

/// `+∞` of the type.
pub(crate) fn infinity<T: RealField + Copy>() -> T {
    T::one() / T::zero()
}
