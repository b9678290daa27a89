//! The scenes: balls in a box, built the same way for every simulator.

use std::f64::consts::PI;

use kimpact_reference::{Ball, BoxBounds};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

use crate::HarnessError;

/// A vector of the reference's dimension `D`, in f64.
pub type V<const D: usize> = kimpact_reference::nalgebra::SVector<f64, D>;

/// Positions and velocities of the balls, in the order of `Setup::balls`.
pub type State<const D: usize> = Vec<(V<D>, V<D>)>;

/// A scene: the balls, in the order every simulator reports them, in a
/// box (the reference's; rapier gets fixed cuboid walls on its faces only
/// when `walls`), the law's dissipation `d̃` and rapier's time step.
#[allow(missing_docs)]
#[derive(Clone, Debug)]
pub struct Setup<const D: usize> {
    pub balls: Vec<Ball<D>>,
    pub bounds: BoxBounds<D>,
    pub walls: bool,
    pub dissipation: f64,
    pub dt: f64,
}

impl<const D: usize> Setup<D> {
    /// The balls' positions and velocities at the start.
    pub fn initial(&self) -> State<D> {
        state_of(&self.balls)
    }
}

/// The positions and velocities of `balls`.
pub(crate) fn state_of<const D: usize>(balls: &[Ball<D>]) -> State<D> {
    balls.iter().map(|b| (b.position, b.velocity)).collect()
}

/// rapier's default time step.
pub const DT: f64 = 1.0 / 60.0;
/// Every ball: diameter σ = 1, mass 1.
pub const R: f64 = 0.5;

/// Uniform in `[-a, a)`, from the lattices' seeded generator.
fn sym(rng: &mut Xoshiro256PlusPlus, a: f64) -> f64 {
    a * (2.0 * rng.random::<f64>() - 1.0)
}

/// A standard normal deviate (Box–Muller).
fn gauss(rng: &mut Xoshiro256PlusPlus) -> f64 {
    let u = 1.0 - rng.random::<f64>();
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
}

/// The unit vector along the first axis.
fn unit_x<const D: usize>() -> V<D> {
    let mut v = V::<D>::zeros();
    v[0] = 1.0;
    v
}

/// Volume of a ball of radius `r` in `d` dimensions (2 or 3).
pub fn ball_volume(d: usize, r: f64) -> f64 {
    if d == 2 {
        PI * r * r
    } else {
        4.0 / 3.0 * PI * r * r * r
    }
}

/// How [`lattice`] draws the velocities.
#[derive(Copy, Clone, Debug)]
enum Velocities {
    /// Components uniform in `[-a, a]` (kT = a²/3): relaxes to Maxwell.
    Uniform(f64),
    /// Maxwell at kT = 1, total momentum removed, energy rescaled to exactly
    /// `D N / 2`.
    Maxwell,
}

/// `n` balls on a jittered lattice filling the box `[0, size]` (a random
/// choice of the sites when the lattice has more); [`HarnessError::Crowded`]
/// when they do not fit apart.
fn lattice<const D: usize>(
    n: usize,
    size: V<D>,
    velocities: Velocities,
    seed: u64,
) -> Result<Vec<Ball<D>>, HarnessError> {
    // `rand`'s portable Xoshiro256++: the same balls on every machine.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut s = (size.product() / n as f64).powf(1.0 / D as f64);
    let counts = loop {
        let c: Vec<usize> = (0..D)
            .map(|k| (size[k] / s).floor().max(1.0) as usize)
            .collect();
        if c.iter().product::<usize>() >= n {
            break c;
        }
        s *= 0.99;
    };
    let sites: usize = counts.iter().product();
    let mut order: Vec<usize> = (0..sites).collect();
    for i in 0..n {
        let j = i + (rng.random::<f64>() * (sites - i) as f64) as usize;
        order.swap(i, j.min(sites - 1));
    }
    let mut chosen = order[..n].to_vec();
    chosen.sort_unstable();
    let spacing = V::<D>::from_fn(|k, _| size[k] / counts[k] as f64);
    if n == 0 || spacing.min() <= 2.0 * R {
        return Err(HarnessError::Crowded { balls: n });
    }
    let mut balls: Vec<Ball<D>> = chosen
        .iter()
        .map(|&site| {
            let mut rest = site;
            let p = V::<D>::from_fn(|k, _| {
                let c = rest % counts[k];
                rest /= counts[k];
                let jitter = 0.49 * (spacing[k] - 2.0 * R);
                (c as f64 + 0.5) * spacing[k] + sym(&mut rng, jitter)
            });
            let v = match velocities {
                Velocities::Uniform(a) => V::<D>::from_fn(|_, _| sym(&mut rng, a)),
                Velocities::Maxwell => V::<D>::from_fn(|_, _| gauss(&mut rng)),
            };
            Ball::new(R, 1.0, p, v)
        })
        .collect();
    if let Velocities::Maxwell = velocities {
        let mean: V<D> = balls.iter().map(|b| b.velocity).sum::<V<D>>() / n as f64;
        balls.iter_mut().for_each(|b| b.velocity -= mean);
        set_energy(&mut balls, 0.5 * (D * n) as f64);
    }
    Ok(balls)
}

/// `balls`' velocities scaled to the kinetic energy `e`.
fn set_energy<const D: usize>(balls: &mut [Ball<D>], e: f64) {
    let scale = (e / balls.iter().map(|b| b.kinetic_energy()).sum::<f64>()).sqrt();
    balls.iter_mut().for_each(|b| b.velocity *= scale);
}

/// A gas of `n` balls at packing fraction 0.3 in a cube, velocity
/// components uniform in `[-3, 3]` on randomly chosen lattice sites, scaled
/// to kT = 3 exactly (so that draws differ only in their balls).
///
/// # Errors
/// [`HarnessError::Crowded`] when the balls do not fit apart.
pub fn gas_setup<const D: usize>(
    n: usize,
    dissipation: f64,
    dt: f64,
    seed: u64,
) -> Result<Setup<D>, HarnessError> {
    let side = (n as f64 * ball_volume(D, R) / 0.3).powf(1.0 / D as f64);
    let size = V::<D>::repeat(side);
    let mut balls = lattice(n, size, Velocities::Uniform(3.0), seed)?;
    set_energy(&mut balls, 1.5 * (D * n) as f64);
    Ok(Setup {
        balls,
        bounds: BoxBounds::new(V::zeros(), size),
        walls: true,
        dissipation,
        dt,
    })
}

/// Two balls (masses 1 and `m2`), the first at speed 1 reaching the second,
/// offset by `offset` across its path, 0.3 base steps into the third base
/// step; no walls in rapier, a far box for the reference.
pub fn two_ball_setup<const D: usize>(m2: f64, dissipation: f64, offset: f64, dt: f64) -> Setup<D> {
    let gap = ((2.0 * R).powi(2) - offset * offset).sqrt();
    let mut p2 = V::<D>::zeros();
    p2[0] = gap + 2.3 * DT;
    p2[1] = offset;
    let centre = V::<D>::repeat(20.0);
    let balls = vec![
        Ball::new(R, 1.0, centre, unit_x::<D>()),
        Ball::new(R, m2, centre + p2, V::<D>::zeros()),
    ];
    far_box(balls, dissipation, dt)
}

/// `balls` about the centre of a far box (40 wide), no walls in rapier.
fn far_box<const D: usize>(balls: Vec<Ball<D>>, dissipation: f64, dt: f64) -> Setup<D> {
    Setup {
        balls,
        bounds: BoxBounds::new(V::zeros(), V::repeat(40.0)),
        walls: false,
        dissipation,
        dt,
    }
}

/// Newton's cradle: five touching balls and a sixth arriving at speed 1
/// half a base step into the fourth base step.
pub fn cradle_setup<const D: usize>(dt: f64) -> Setup<D> {
    let (centre, x) = (V::<D>::repeat(20.0), unit_x::<D>());
    let mut balls = vec![Ball::new(R, 1.0, centre - x * (2.0 * R + 3.5 * DT), x)];
    let at_rest = |i: usize| Ball::new(R, 1.0, centre + x * (2.0 * R * i as f64), V::zeros());
    balls.extend((0..5).map(at_rest));
    far_box(balls, 0.0, dt)
}

/// The box of a Z measurement: `n` balls in a box whose lengths
/// accessible to the centres are `ell` (the box is `ell + σ`), Maxwell
/// velocities at kT = 1, elastic, rapier's default step.
///
/// # Errors
/// [`HarnessError::Crowded`] when the balls do not fit apart.
pub fn z_setup<const D: usize>(n: usize, ell: V<D>, seed: u64) -> Result<Setup<D>, HarnessError> {
    let size = ell.add_scalar(2.0 * R);
    let mut balls = lattice(n, ell, Velocities::Maxwell, seed)?;
    for b in &mut balls {
        b.position = b.position.add_scalar(R);
    }
    Ok(Setup {
        balls,
        bounds: BoxBounds::new(V::zeros(), size),
        walls: true,
        dissipation: 0.0,
        dt: DT,
    })
}
