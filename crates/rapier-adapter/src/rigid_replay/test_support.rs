//! What the rigid replay's unit tests share: the rounding of this
//! precision, planar helpers and a root finder for the closed forms.
// One source for f32 and f64: `as Real` is a cast in one build only.
#![allow(clippy::unnecessary_cast)]

use crate::math::{Real, Vector};
use crate::rapier::math::AngVector;

/// Rounding of this precision's positions.
pub(super) fn tol() -> f64 {
    if std::mem::size_of::<Real>() == 8 {
        1e-9
    } else {
        1e-3
    }
}

/// A rotation about z by `w` (2D: the angle).
pub(super) fn about_z(w: Real) -> AngVector {
    #[cfg(feature = "dim2")]
    {
        w
    }
    #[cfg(feature = "dim3")]
    {
        AngVector::new(0.0, 0.0, w)
    }
}

/// The point or vector `(x, y)` (3D: z = 0).
pub(super) fn xy(x: Real, y: Real) -> Vector {
    let mut v = Vector::ZERO;
    v[0] = x;
    v[1] = y;
    v
}

/// The first root of `f` in `(0, end]` (sampled, then bisected), if any.
pub(super) fn first_root(f: impl Fn(f64) -> f64, end: f64) -> Option<f64> {
    let samples = 4000;
    let mut prev = 0.0;
    for i in 1..=samples {
        let t = end * i as f64 / samples as f64;
        if f(t) <= 0.0 {
            let (mut lo, mut hi) = (prev, t);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if f(mid) > 0.0 { lo = mid } else { hi = mid }
            }
            return Some(lo);
        }
        prev = t;
    }
    None
}
