//! The floats of the law target: the scalar types under test, how a float
//! is decoded from the input, and the checks' arithmetic in f64 (norms
//! without overflow, exact scaling by powers of two).

use std::fmt::Debug;

use arbitrary::{Result, Unstructured};
use kimpact::nalgebra::{RealField, SVector};

/// The scalar types under test, with their constants as f64.
pub trait Float: RealField + Copy + Debug {
    const EPS: f64;
    const MIN_POSITIVE: f64;
    const DENORM_MIN: f64;
    const MAX: f64;
    fn from_raw(u: &mut Unstructured<'_>) -> Result<Self>;
    fn from64(x: f64) -> Self;
    fn to64(self) -> f64;
    fn bits(self) -> u64;

    /// One float: raw bits half of the time, else a special value, a
    /// moderate value or a small integer.
    fn decode(u: &mut Unstructured<'_>) -> Result<Self> {
        let tag: u8 = u.arbitrary()?;
        Ok(match tag % 8 {
            0..=3 => Self::from_raw(u)?,
            4 => {
                let specials = [
                    0.0,
                    -0.0,
                    1.0,
                    -1.0,
                    f64::NAN,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    Self::MIN_POSITIVE,
                    -Self::MIN_POSITIVE,
                    Self::DENORM_MIN,
                    -Self::DENORM_MIN,
                    Self::MAX,
                    -Self::MAX,
                    Self::EPS,
                    0.5,
                    2.0,
                    1e-6,
                    1.0 - 1e-6,
                    1e-3,
                    Self::MAX.sqrt(),
                    Self::MIN_POSITIVE.sqrt(),
                    0.25,
                    1e6,
                    1e12,
                    1e-12,
                ];
                Self::from64(specials[usize::from(u.arbitrary::<u8>()?) % specials.len()])
            }
            5 | 6 => {
                let mantissa = 1.0 + f64::from(u.arbitrary::<u16>()?) / 65536.0;
                let exponent = i32::from(u.arbitrary::<i8>()?) / 4;
                let sign = if u.arbitrary::<bool>()? { -1.0 } else { 1.0 };
                Self::from64(sign * mantissa * 2f64.powi(exponent))
            }
            _ => Self::from64(f64::from(u.arbitrary::<i8>()?)),
        })
    }
}

impl Float for f32 {
    const EPS: f64 = f32::EPSILON as f64;
    const MIN_POSITIVE: f64 = f32::MIN_POSITIVE as f64;
    const DENORM_MIN: f64 = f32::from_bits(1) as f64;
    const MAX: f64 = f32::MAX as f64;
    fn from_raw(u: &mut Unstructured<'_>) -> Result<Self> {
        Ok(f32::from_bits(u.arbitrary()?))
    }
    fn from64(x: f64) -> Self {
        x as f32
    }
    fn to64(self) -> f64 {
        f64::from(self)
    }
    fn bits(self) -> u64 {
        u64::from(self.to_bits())
    }
}

impl Float for f64 {
    const EPS: f64 = f64::EPSILON;
    const MIN_POSITIVE: f64 = f64::MIN_POSITIVE;
    const DENORM_MIN: f64 = f64::from_bits(1);
    const MAX: f64 = f64::MAX;
    fn from_raw(u: &mut Unstructured<'_>) -> Result<Self> {
        Ok(f64::from_bits(u.arbitrary()?))
    }
    fn from64(x: f64) -> Self {
        x
    }
    fn to64(self) -> f64 {
        self
    }
    fn bits(self) -> u64 {
        self.to_bits()
    }
}

/// A vector of floats decoded by [`Float::decode`].
pub fn vector<T: Float, const D: usize>(u: &mut Unstructured<'_>) -> Result<SVector<T, D>> {
    let mut v = SVector::<T, D>::zeros();
    for c in v.iter_mut() {
        *c = T::decode(u)?;
    }
    Ok(v)
}

/// `v` in f64.
pub fn to64<T: Float, const D: usize>(v: &SVector<T, D>) -> SVector<f64, D> {
    v.map(T::to64)
}

/// The unit normal as the law documents it: `normal / |normal|`, scaled
/// first by the largest component.
pub fn unit<T: Float, const D: usize>(n: &SVector<T, D>) -> SVector<T, D> {
    let scaled = n / n.amax();
    scaled / scaled.norm()
}

/// `|v|` without under- or overflow of the squares (scaled by the largest
/// component), for the checks.
pub fn norm<const D: usize>(v: &SVector<f64, D>) -> f64 {
    let scale = v.amax();
    if scale == 0.0 || !scale.is_finite() {
        return scale;
    }
    scale * (v / scale).norm()
}

/// `|v|²`, as [`norm`].
pub fn norm_squared<const D: usize>(v: &SVector<f64, D>) -> f64 {
    let n = norm(v);
    n * n
}

/// `k` such that `x · 2^k` is in `[1, 2)` (0 for 0 or non-finite `x`).
pub fn exponent_to_unit(x: f64) -> i32 {
    if x > 0.0 && x.is_finite() {
        -(x.log2().floor() as i32)
    } else {
        0
    }
}

/// `x · 2^k`, exact unless the result leaves the range of f64 (in steps
/// of at most 2^±1000, as `2^k` alone may not be representable).
pub fn times_pow2(mut x: f64, mut k: i32) -> f64 {
    while k != 0 {
        let step = k.clamp(-1000, 1000);
        x *= 2f64.powi(step);
        k -= step;
    }
    x
}
