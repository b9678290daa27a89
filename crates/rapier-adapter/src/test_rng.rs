//! The tests' deterministic generator.

use crate::math::{DIM, Real, Vector};
use crate::rapier::prelude::Aabb;

/// A small deterministic generator (an LCG).
#[allow(clippy::unnecessary_cast)]
pub(crate) struct Lcg(pub(crate) u64);
#[allow(clippy::unnecessary_cast)]
impl Lcg {
    pub(crate) fn next(&mut self) -> Real {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) as Real
    }
    pub(crate) fn aabb(&mut self, spread: Real, size: Real) -> Aabb {
        let mut lo = Vector::ZERO;
        let mut ext = Vector::ZERO;
        for k in 0..DIM {
            lo[k] = spread * self.next();
            ext[k] = size * self.next();
        }
        Aabb::new(lo, lo + ext)
    }
}
