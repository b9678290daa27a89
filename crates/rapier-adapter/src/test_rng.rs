//! The tests' deterministic generator: `rand`'s portable Xoshiro256++,
//! seeded (the one generator of the workspace's tests, benches and scene
//! generators).

use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

use crate::math::{DIM, Real, Vector};
use crate::rapier::prelude::Aabb;

/// A seeded generator of numbers and boxes for the unit tests.
pub(crate) struct TestRng(Xoshiro256PlusPlus);

impl TestRng {
    /// The generator of `seed`.
    pub(crate) fn new(seed: u64) -> Self {
        Self(Xoshiro256PlusPlus::seed_from_u64(seed))
    }

    /// Uniform in `[0, 1)`.
    pub(crate) fn next(&mut self) -> Real {
        self.0.random::<Real>()
    }

    /// A box with its lower corner uniform in `[0, spread)` and its extent
    /// uniform in `[0, size)` on each axis.
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
