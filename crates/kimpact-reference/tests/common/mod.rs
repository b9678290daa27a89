//! Helpers shared by the integration tests: random non-overlapping
//! configurations (from a seeded `rand` generator) and invariant checks.
#![allow(dead_code)]

use kimpact_reference::nalgebra::SVector;
use kimpact_reference::{Ball, BoxBounds, Reference};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

/// The tests' deterministic generator: `rand`'s portable Xoshiro256++,
/// seeded.
pub struct Rng(Xoshiro256PlusPlus);

impl Rng {
    /// The generator of `seed`.
    pub fn new(seed: u64) -> Self {
        Self(Xoshiro256PlusPlus::seed_from_u64(seed))
    }

    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0.random()
    }

    /// Uniform in [lo, hi) (`lo` when the range is empty).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The unit box (or a box of side `side`) from the origin.
pub fn cube<const D: usize>(side: f64) -> BoxBounds<D> {
    BoxBounds::new(SVector::zeros(), SVector::repeat(side))
}

/// `n` balls on a jittered cubic lattice filling `bounds`, radii in
/// `[r_min, r_max]`, masses in `[m_min, m_max]`, velocity components
/// uniform in `[-v, v]`. Panics if the lattice is too tight.
pub fn lattice_gas<const D: usize>(
    seed: u64,
    n: usize,
    bounds: &BoxBounds<D>,
    (r_min, r_max): (f64, f64),
    (m_min, m_max): (f64, f64),
    v: f64,
) -> Vec<Ball<D>> {
    let mut rng = Rng::new(seed);
    let per_axis = (n as f64).powf(1.0 / D as f64).ceil() as usize;
    let size = bounds.size();
    let spacing = size.min() / per_axis as f64;
    assert!(spacing > 2.0 * r_max, "lattice too tight");
    let jitter = 0.5 * (spacing - 2.0 * r_max);
    (0..n)
        .map(|i| {
            let mut rest = i;
            let position = SVector::<f64, D>::from_fn(|k, _| {
                let c = rest % per_axis;
                rest /= per_axis;
                bounds.lo[k] + (c as f64 + 0.5) * spacing + rng.range(-jitter, jitter)
            });
            let velocity = SVector::<f64, D>::from_fn(|_, _| rng.range(-v, v));
            Ball::new(
                rng.range(r_min, r_max),
                rng.range(m_min, m_max),
                position,
                velocity,
            )
        })
        .collect()
}

/// The largest relative overlap `1 − d/σ` over all pairs (≤ 0 if none) and
/// the largest distance by which a ball sticks out of the box.
pub fn violations<const D: usize>(sim: &Reference<D>) -> (f64, f64) {
    let balls = sim.balls();
    let mut overlap = f64::NEG_INFINITY;
    for (i, a) in balls.iter().enumerate() {
        for b in &balls[i + 1..] {
            let sigma = a.radius + b.radius;
            overlap = overlap.max(1.0 - (b.position - a.position).norm() / sigma);
        }
    }
    let bounds = sim.bounds();
    let mut outside = f64::NEG_INFINITY;
    for b in balls {
        for k in 0..D {
            outside = outside
                .max(bounds.lo[k] + b.radius - b.position[k])
                .max(b.position[k] + b.radius - bounds.hi[k]);
        }
    }
    (overlap, outside)
}
