//! Accuracy of every kimpact mode and of native rapier against the exact
//! event-driven reference (`kimpact-reference`), and what accuracy costs.
//!
//! ```text
//! cargo run --release --example accuracy              # a few minutes, writes docs/
//! cargo run --release --example accuracy -- --quick   # a smoke run, ~10x shorter
//! ```
//!
//! It writes `docs/accuracy.md` (tables, the method, the command and the
//! machine), `docs/accuracy.svg` (the cost of accuracy and the cooling
//! curves) and `docs/accuracy.csv` (every number of the plots and the time
//! series, long format: `section,engine,method,dt_div,x,quantity,value`).
//! Options: `--quick`, `--threads N` (default 2), `--out DIR` (default
//! `docs`).
//!
//! The rapier side is the adapter built four times (`kimpact2d`,
//! `kimpact3d`, `kimpact2d-f64`, `kimpact3d-f64`); one macro wraps each into
//! the same [`Sim`] interface as the reference, so that every experiment is
//! written once, generic over the dimension, and run on the same initial
//! balls in every simulator.
// A report generator: long argument lists and tuple-heavy tables are its nature.
#![allow(
    clippy::too_many_arguments,
    clippy::type_complexity,
    clippy::needless_range_loop
)]
// `f64::from(x)` converts in the f32 builds and is the identity in the f64 ones.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use kimpact::{Law, LawParams};
use kimpact_reference::nalgebra::SVector;
use kimpact_reference::{Ball, BoxBounds, Reference};

type V<const D: usize> = SVector<f64, D>;

// ---------------------------------------------------------------------------
// Simulators behind one interface
// ---------------------------------------------------------------------------

/// Who simulates: the reference, or rapier in one of the adapter's modes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Method {
    Reference,
    Native,
    Restitution,
    Impulse,
    Exact,
}

impl Method {
    const RAPIER: [Method; 4] = [
        Method::Native,
        Method::Restitution,
        Method::Impulse,
        Method::Exact,
    ];
    const ALL: [Method; 5] = [
        Method::Reference,
        Method::Native,
        Method::Restitution,
        Method::Impulse,
        Method::Exact,
    ];

    fn name(self) -> &'static str {
        match self {
            Method::Reference => "reference",
            Method::Native => "native",
            Method::Restitution => "restitution",
            Method::Impulse => "impulse",
            Method::Exact => "exact",
        }
    }

    fn color(self) -> &'static str {
        match self {
            Method::Reference => "#000000",
            Method::Native => "#d62728",
            Method::Restitution => "#ff7f0e",
            Method::Impulse => "#2ca02c",
            Method::Exact => "#1f77b4",
        }
    }
}

/// A scene: balls in a box, the law's dissipation and rapier's time step.
#[derive(Clone)]
struct Setup<const D: usize> {
    balls: Vec<Ball<D>>,
    /// The box. The reference always has one; rapier gets fixed cuboid
    /// walls on its faces only when `walls`.
    bounds: BoxBounds<D>,
    walls: bool,
    dissipation: f64,
    dt: f64,
}

/// Running totals since the start.
#[derive(Copy, Clone, Debug)]
struct Totals<const D: usize> {
    ball_impacts: u64,
    wall_impacts: u64,
    /// Normal impulse given to each wall, `[axis][lower, upper]`.
    wall_impulse: [[f64; 2]; D],
}

impl<const D: usize> Totals<D> {
    fn zero() -> Self {
        Self {
            ball_impacts: 0,
            wall_impacts: 0,
            wall_impulse: [[0.0; 2]; D],
        }
    }

    fn impacts(&self) -> u64 {
        self.ball_impacts + self.wall_impacts
    }
}

trait Sim<const D: usize> {
    fn time(&self) -> f64;
    /// Advance to time `t` (rapier: to the last whole step not after `t`,
    /// up to the rounding of the step).
    fn advance_to(&mut self, t: f64) -> Result<(), String>;
    /// Positions and velocities, in the order of `Setup::balls`.
    fn state(&self) -> Vec<(V<D>, V<D>)>;
    fn totals(&self) -> Totals<D>;
    /// Wall-clock seconds spent advancing, and rapier steps taken.
    fn busy(&self) -> (f64, u64);
    /// Largest residual of the wall-impulse bookkeeping so far: per step and
    /// axis, the change of the balls' total momentum minus the net wall
    /// impulse, summed, relative to the summed wall impulses (rapier only;
    /// it checks that the impulses used for the pressure are the ones
    /// applied).
    fn impulse_residual(&self) -> f64 {
        0.0
    }
    /// Anything unusual the simulator counted (rapier: the adapter's event
    /// cap hits and pairs skipped for non-finite data).
    fn diagnostics(&self) -> Option<String> {
        None
    }
}

struct RefSim<const D: usize> {
    sim: Reference<D>,
    busy: f64,
}

impl<const D: usize> RefSim<D> {
    fn new(setup: &Setup<D>) -> Self {
        let law = Law::new(LawParams {
            dissipation: setup.dissipation,
            ..Default::default()
        })
        .expect("valid law");
        let sim = Reference::new(setup.balls.clone(), setup.bounds, V::zeros(), law)
            .expect("valid scene");
        Self { sim, busy: 0.0 }
    }
}

impl<const D: usize> Sim<D> for RefSim<D> {
    fn time(&self) -> f64 {
        self.sim.time()
    }

    fn advance_to(&mut self, t: f64) -> Result<(), String> {
        let start = Instant::now();
        let r = self.sim.advance_to(t).map_err(|e| e.to_string());
        self.busy += start.elapsed().as_secs_f64();
        r
    }

    fn state(&self) -> Vec<(V<D>, V<D>)> {
        self.sim
            .balls()
            .iter()
            .map(|b| (b.position, b.velocity))
            .collect()
    }

    fn totals(&self) -> Totals<D> {
        let s = self.sim.stats();
        Totals {
            ball_impacts: s.ball_impacts,
            wall_impacts: s.wall_impacts,
            wall_impulse: s.wall_impulse,
        }
    }

    fn busy(&self) -> (f64, u64) {
        (self.busy, 0)
    }
}

/// One adapter build (dimension and precision) behind [`Sim`].
#[derive(Copy, Clone)]
struct Backend<const D: usize> {
    label: &'static str,
    /// `"f32"` or `"f64"`: the precision of the rapier build.
    precision: &'static str,
    make: fn(&Setup<D>, Method) -> Box<dyn Sim<D>>,
}

impl<const D: usize> Backend<D> {
    fn sim(&self, setup: &Setup<D>, method: Method) -> Box<dyn Sim<D>> {
        match method {
            Method::Reference => Box::new(RefSim::new(setup)),
            m => (self.make)(setup, m),
        }
    }
}

fn no_rapier<const D: usize>(_: &Setup<D>, _: Method) -> Box<dyn Sim<D>> {
    unreachable!("the reference needs no rapier backend")
}

/// The rapier side, written once for the four adapter builds.
macro_rules! rapier_backend {
    ($module:ident, $krate:ident, $dim:literal) => {
        mod $module {
            use std::collections::{HashMap, HashSet};
            use std::time::Instant;

            use super::{Method, Setup, Sim, Totals, V};
            use k::math::{Real, Vector};
            use k::rapier::prelude::*;
            use k::{Kimpact, Law, LawParams, Mode};
            use $krate as k;

            const D: usize = $dim;

            fn to_rapier(x: &V<D>) -> Vector {
                let mut v = Vector::ZERO;
                for i in 0..D {
                    v[i] = x[i] as Real;
                }
                v
            }

            fn from_rapier(v: Vector) -> V<D> {
                V::<D>::from_fn(|i, _| f64::from(v[i]))
            }

            pub struct World {
                world: PhysicsWorld,
                kimpact: Kimpact,
                method: Method,
                balls: Vec<RigidBodyHandle>,
                /// Wall colliders with their `(axis, side)`.
                walls: Vec<(ColliderHandle, usize, usize)>,
                wall_of: HashMap<ColliderHandle, (usize, usize)>,
                /// Native: pairs that carried an impulse at the last step.
                pushing: HashSet<(ColliderHandle, ColliderHandle)>,
                totals: Totals<D>,
                steps: u64,
                dt: f64,
                busy: f64,
                residual: f64,
                impulse_sum: f64,
            }

            pub fn make(setup: &Setup<D>, method: Method) -> Box<dyn Sim<D>> {
                Box::new(World::new(setup, method))
            }

            impl World {
                fn new(setup: &Setup<D>, method: Method) -> Self {
                    let mut world = PhysicsWorld::new();
                    world.gravity = Vector::ZERO;
                    world.integration_parameters.dt = setup.dt as Real;
                    let law = Law::new(LawParams {
                        dissipation: setup.dissipation as Real,
                        ..Default::default()
                    })
                    .expect("valid law");
                    let mode = match method {
                        Method::Native => Mode::Native,
                        Method::Restitution => Mode::Restitution,
                        Method::Impulse => Mode::Impulse,
                        Method::Exact | Method::Reference => Mode::Exact,
                    };
                    let mut kimpact = Kimpact::new(law, mode);
                    // Native rapier gets the law's head-on restitution for
                    // equal masses (q = 8 d̃) between balls and its wall
                    // restitution (q = 2 d̃, own-mass policy) against walls;
                    // rapier averages the two colliders' coefficients.
                    let d = setup.dissipation;
                    let e_ball = (1.0 - 8.0 * d).max(0.0).sqrt();
                    let e_wall = ((1.0 - 2.0 * d).max(0.0).sqrt() * 2.0 - e_ball).clamp(0.0, 1.0);
                    let mut walls = Vec::new();
                    let mut wall_of = HashMap::new();
                    if setup.walls {
                        let (lo, hi) = (setup.bounds.lo, setup.bounds.hi);
                        let centre = (lo + hi) * 0.5;
                        let half = (hi - lo) * 0.5;
                        let t = 1.0;
                        for axis in 0..D {
                            for side in 0..2 {
                                let mut c = centre;
                                c[axis] = if side == 0 {
                                    lo[axis] - t
                                } else {
                                    hi[axis] + t
                                };
                                let mut he = half.add_scalar(2.0 * t);
                                he[axis] = t;
                                let body = world.insert_body(
                                    RigidBodyBuilder::fixed().translation(to_rapier(&c)),
                                );
                                let collider = k::math::cuboid(to_rapier(&he))
                                    .friction(0.0)
                                    .restitution(e_wall as Real);
                                let handle = world.insert_collider(collider, Some(body));
                                walls.push((handle, axis, side));
                                wall_of.insert(handle, (axis, side));
                            }
                        }
                    }
                    let balls = setup
                        .balls
                        .iter()
                        .map(|b| {
                            let body = RigidBodyBuilder::dynamic()
                                .translation(to_rapier(&b.position))
                                .linvel(to_rapier(&b.velocity))
                                .can_sleep(false);
                            let collider = ColliderBuilder::ball(b.radius as Real)
                                .mass(b.mass as Real)
                                .friction(0.0)
                                .restitution(e_ball as Real);
                            let (handle, c) = world.insert(body, collider);
                            kimpact.mark(&world.colliders, c).expect("inserted just above");
                            handle
                        })
                        .collect();
                    let dt = f64::from(world.integration_parameters.dt);
                    Self {
                        world,
                        kimpact,
                        method,
                        balls,
                        walls,
                        wall_of,
                        pushing: HashSet::new(),
                        totals: Totals::zero(),
                        steps: 0,
                        dt,
                        busy: 0.0,
                        residual: 0.0,
                        impulse_sum: 0.0,
                    }
                }

                fn momentum(&self) -> V<D> {
                    self.balls
                        .iter()
                        .map(|&h| {
                            let b = &self.world.bodies[h];
                            from_rapier(b.linvel()) * f64::from(b.mass())
                        })
                        .sum()
                }

                fn step(&mut self) {
                    let p0 = self.momentum();
                    let start = Instant::now();
                    self.kimpact.step_world(&mut self.world, &(), &());
                    self.busy += start.elapsed().as_secs_f64();
                    self.steps += 1;
                    let mut impulse = [[0.0f64; 2]; D];
                    // The impulses rapier's solver applied to the walls (in
                    // the law modes: the contacts rapier kept).
                    for &(c, axis, side) in &self.walls {
                        for cp in self.world.narrow_phase.contact_pairs_with(c) {
                            if cp.has_any_active_contact() {
                                impulse[axis][side] += f64::from(cp.total_impulse()[axis]).abs();
                            }
                        }
                    }
                    match self.method {
                        Method::Native | Method::Reference => {
                            // An impact: a pair that carries an impulse now
                            // and did not at the previous step.
                            let mut now = HashSet::new();
                            for cp in self.world.narrow_phase.contact_pairs() {
                                if cp.has_any_active_contact() && cp.total_impulse_magnitude() > 0.0
                                {
                                    let key = (cp.collider1, cp.collider2);
                                    if !self.pushing.contains(&key) {
                                        if self.wall_of.contains_key(&cp.collider1)
                                            || self.wall_of.contains_key(&cp.collider2)
                                        {
                                            self.totals.wall_impacts += 1;
                                        } else {
                                            self.totals.ball_impacts += 1;
                                        }
                                    }
                                    now.insert(key);
                                }
                            }
                            self.pushing = now;
                        }
                        Method::Restitution | Method::Impulse | Method::Exact => {
                            for e in self.kimpact.events() {
                                let wall = self
                                    .wall_of
                                    .get(&e.collider1)
                                    .or(self.wall_of.get(&e.collider2));
                                match wall {
                                    Some(&(axis, side)) => {
                                        self.totals.wall_impacts += 1;
                                        // rapier's solver applied it: counted above.
                                        if !e.by_solver {
                                            impulse[axis][side] += f64::from(e.impulse).abs();
                                        }
                                    }
                                    None => self.totals.ball_impacts += 1,
                                }
                            }
                        }
                    }
                    let dp = self.momentum() - p0;
                    for axis in 0..D {
                        let [lo, hi] = impulse[axis];
                        self.residual += (dp[axis] - (lo - hi)).abs();
                        self.impulse_sum += lo + hi;
                        self.totals.wall_impulse[axis][0] += lo;
                        self.totals.wall_impulse[axis][1] += hi;
                    }
                }
            }

            impl Sim<D> for World {
                fn time(&self) -> f64 {
                    self.steps as f64 * self.dt
                }

                fn advance_to(&mut self, t: f64) -> Result<(), String> {
                    // A hundredth of a step of slack: the step is rounded to
                    // the build's precision (f32 makes 1/60 larger by 5e-8 of
                    // itself, a whole step short after 6,000 steps), and `t`
                    // is a whole number of nominal steps.
                    let steps = (t / self.dt + 1e-2).floor() as u64;
                    while self.steps < steps {
                        self.step();
                    }
                    Ok(())
                }

                fn state(&self) -> Vec<(V<D>, V<D>)> {
                    self.balls
                        .iter()
                        .map(|&h| {
                            let b = &self.world.bodies[h];
                            (from_rapier(b.translation()), from_rapier(b.linvel()))
                        })
                        .collect()
                }

                fn totals(&self) -> Totals<D> {
                    self.totals
                }

                fn busy(&self) -> (f64, u64) {
                    (self.busy, self.steps)
                }

                fn diagnostics(&self) -> Option<String> {
                    let s = self.kimpact.stats();
                    if s.event_cap_hits > 0 || s.skipped_non_finite > 0 {
                        Some(format!(
                            "{} step(s) hit the exact mode's event cap ({} law impacts in all), {} pair(s) skipped for non-finite data",
                            s.event_cap_hits, s.impacts, s.skipped_non_finite
                        ))
                    } else {
                        None
                    }
                }

                fn impulse_residual(&self) -> f64 {
                    if self.impulse_sum > 0.0 {
                        self.residual / self.impulse_sum
                    } else {
                        0.0
                    }
                }
            }
        }
    };
}

rapier_backend!(rapier2d_f32, kimpact2d, 2);
rapier_backend!(rapier3d_f32, kimpact3d, 3);
rapier_backend!(rapier2d_f64, kimpact2d_f64, 2);
rapier_backend!(rapier3d_f64, kimpact3d_f64, 3);

const B2_F32: Backend<2> = Backend {
    label: "2D f32",
    precision: "f32",
    make: rapier2d_f32::make,
};
const B3_F32: Backend<3> = Backend {
    label: "3D f32",
    precision: "f32",
    make: rapier3d_f32::make,
};
const B2_F64: Backend<2> = Backend {
    label: "2D f64",
    precision: "f64",
    make: rapier2d_f64::make,
};
const B3_F64: Backend<3> = Backend {
    label: "3D f64",
    precision: "f64",
    make: rapier3d_f64::make,
};

// ---------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------

/// rapier's default time step.
const DT: f64 = 1.0 / 60.0;
/// Every ball: diameter σ = 1, mass 1.
const R: f64 = 0.5;

/// The seeded generator of the lattices: `rand`'s portable Xoshiro256++.
struct Rng(rand::rngs::Xoshiro256PlusPlus);

impl Rng {
    fn new(seed: u64) -> Self {
        use rand::SeedableRng;
        Self(rand::rngs::Xoshiro256PlusPlus::seed_from_u64(seed))
    }

    /// Uniform in `[0, 1)`.
    fn next(&mut self) -> f64 {
        use rand::RngExt;
        self.0.random()
    }

    fn sym(&mut self, a: f64) -> f64 {
        a * (2.0 * self.next() - 1.0)
    }

    fn gauss(&mut self) -> f64 {
        let u = 1.0 - self.next();
        let v = self.next();
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
    }
}

/// The unit vector along the first axis.
fn unit_x<const D: usize>() -> V<D> {
    let mut v = V::<D>::zeros();
    v[0] = 1.0;
    v
}

/// Volume of a ball of radius `r` in `D` dimensions (2 or 3).
fn ball_volume(d: usize, r: f64) -> f64 {
    if d == 2 {
        PI * r * r
    } else {
        4.0 / 3.0 * PI * r * r * r
    }
}

#[derive(Copy, Clone)]
enum Velocities {
    /// Components uniform in `[-a, a]` (kT = a²/3): relaxes to Maxwell.
    Uniform(f64),
    /// Maxwell at kT = 1, total momentum removed, energy rescaled to exactly
    /// `D N / 2`.
    Maxwell,
}

/// `n` balls on a jittered lattice filling the box `[0, size]` (a random
/// choice of the sites when the lattice has more).
fn lattice<const D: usize>(
    n: usize,
    size: V<D>,
    velocities: Velocities,
    seed: u64,
) -> Vec<Ball<D>> {
    let mut rng = Rng::new(seed);
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
        let j = i + (rng.next() * (sites - i) as f64) as usize;
        order.swap(i, j.min(sites - 1));
    }
    let mut chosen = order[..n].to_vec();
    chosen.sort_unstable();
    let spacing = V::<D>::from_fn(|k, _| size[k] / counts[k] as f64);
    assert!(spacing.min() > 2.0 * R, "the lattice is too tight");
    let mut balls: Vec<Ball<D>> = chosen
        .iter()
        .map(|&site| {
            let mut rest = site;
            let p = V::<D>::from_fn(|k, _| {
                let c = rest % counts[k];
                rest /= counts[k];
                let jitter = 0.49 * (spacing[k] - 2.0 * R);
                (c as f64 + 0.5) * spacing[k] + rng.sym(jitter)
            });
            let v = match velocities {
                Velocities::Uniform(a) => V::<D>::from_fn(|_, _| rng.sym(a)),
                Velocities::Maxwell => V::<D>::from_fn(|_, _| rng.gauss()),
            };
            Ball::new(R, 1.0, p, v)
        })
        .collect();
    if let Velocities::Maxwell = velocities {
        let mean: V<D> = balls.iter().map(|b| b.velocity).sum::<V<D>>() / n as f64;
        for b in &mut balls {
            b.velocity -= mean;
        }
        let e: f64 = balls.iter().map(|b| b.kinetic_energy()).sum();
        let scale = (0.5 * (D * n) as f64 / e).sqrt();
        for b in &mut balls {
            b.velocity *= scale;
        }
    }
    balls
}

/// The kind of gas of the CI test (`tests/accuracy.rs`): `n` balls at
/// packing fraction 0.3 in a cube, velocity components uniform in `[-3, 3]`
/// (here on randomly chosen lattice sites and scaled to kT = 3 exactly, so
/// that draws differ only in their balls; the CI test fills its lattice row
/// by row and keeps the drawn energy).
fn gas_setup<const D: usize>(n: usize, dissipation: f64, dt: f64, seed: u64) -> Setup<D> {
    let side = (n as f64 * ball_volume(D, R) / 0.3).powf(1.0 / D as f64);
    let size = V::<D>::repeat(side);
    let mut balls = lattice(n, size, Velocities::Uniform(3.0), seed);
    // Every draw gets the same energy (kT = 3), so that different draws
    // are samples of the same gas.
    let e: f64 = balls.iter().map(|b| b.kinetic_energy()).sum();
    let scale = (1.5 * (D * n) as f64 / e).sqrt();
    for b in &mut balls {
        b.velocity *= scale;
    }
    Setup {
        balls,
        bounds: BoxBounds::new(V::zeros(), size),
        walls: true,
        dissipation,
        dt,
    }
}

/// Two balls (masses 1 and `m2`), the first at speed 1 reaching the second,
/// offset by `offset` across its path, 0.3 base steps into the third base
/// step; no walls in rapier, a far box for the reference.
fn two_ball_setup<const D: usize>(m2: f64, dissipation: f64, offset: f64, dt: f64) -> Setup<D> {
    let gap = ((2.0 * R).powi(2) - offset * offset).sqrt();
    let mut p2 = V::<D>::zeros();
    p2[0] = gap + 2.3 * DT;
    p2[1] = offset;
    let centre = V::<D>::repeat(20.0);
    Setup {
        balls: vec![
            Ball::new(R, 1.0, centre, unit_x::<D>()),
            Ball::new(R, m2, centre + p2, V::<D>::zeros()),
        ],
        bounds: BoxBounds::new(V::zeros(), V::repeat(40.0)),
        walls: false,
        dissipation,
        dt,
    }
}

/// Newton's cradle: five touching balls and a sixth arriving at speed 1
/// half a base step into the fourth base step.
fn cradle_setup<const D: usize>(dt: f64) -> Setup<D> {
    let centre = V::<D>::repeat(20.0);
    let mut balls = vec![Ball::new(
        R,
        1.0,
        centre - unit_x::<D>() * (2.0 * R + 3.5 * DT),
        unit_x::<D>(),
    )];
    for i in 0..5 {
        balls.push(Ball::new(
            R,
            1.0,
            centre + unit_x::<D>() * (2.0 * R * i as f64),
            V::<D>::zeros(),
        ));
    }
    Setup {
        balls,
        bounds: BoxBounds::new(V::zeros(), V::repeat(40.0)),
        walls: false,
        dissipation: 0.0,
        dt,
    }
}

// ---------------------------------------------------------------------------
// Measurements
// ---------------------------------------------------------------------------

fn kinetic<const D: usize>(setup: &Setup<D>, state: &[(V<D>, V<D>)]) -> f64 {
    setup
        .balls
        .iter()
        .zip(state)
        .map(|(b, (_, v))| 0.5 * b.mass * v.norm_squared())
        .sum()
}

fn momentum<const D: usize>(setup: &Setup<D>, state: &[(V<D>, V<D>)]) -> V<D> {
    setup
        .balls
        .iter()
        .zip(state)
        .map(|(b, (_, v))| v * b.mass)
        .sum()
}

/// Errors of a short scene against the reference at the same time.
struct ShortResult {
    /// Largest velocity difference (the incoming speed is 1).
    dv: f64,
    /// Largest position difference, in radii.
    dx: f64,
    /// Kinetic energy kept.
    kept: f64,
    /// |Δ momentum| relative to the initial momentum.
    dp: f64,
}

fn short_run<const D: usize>(
    b: &Backend<D>,
    setup: &Setup<D>,
    method: Method,
    t_end: f64,
) -> ShortResult {
    let mut sim = b.sim(setup, method);
    sim.advance_to(t_end).expect("rapier never fails");
    let mut reference = RefSim::new(setup);
    reference
        .advance_to(sim.time())
        .expect("the reference runs");
    let s = sim.state();
    let r = reference.state();
    let dv = s
        .iter()
        .zip(&r)
        .map(|(a, b)| (a.1 - b.1).norm())
        .fold(0.0, f64::max);
    let dx = s
        .iter()
        .zip(&r)
        .map(|(a, b)| (a.0 - b.0).norm())
        .fold(0.0, f64::max)
        / R;
    let initial: Vec<_> = setup
        .balls
        .iter()
        .map(|b| (b.position, b.velocity))
        .collect();
    let p0 = momentum(setup, &initial);
    ShortResult {
        dv,
        dx,
        kept: kinetic(setup, &s) / kinetic(setup, &initial),
        dp: (momentum(setup, &s) - p0).norm() / p0.norm(),
    }
}

/// Two-sample Kolmogorov–Smirnov distance.
fn ks(a: &mut [f64], b: &mut [f64]) -> f64 {
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] <= x {
            i += 1;
        }
        while j < b.len() && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// erf, Abramowitz & Stegun 7.1.26 (|error| < 1.5e-7).
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.3275911 * x.abs());
    let y = 1.0
        - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t
            + 0.254829592)
            * t
            * (-x * x).exp();
    if x >= 0.0 { y } else { -y }
}

/// KS distance of speeds in units of the rms speed from Maxwell–Boltzmann.
fn ks_maxwell(d: usize, x: &mut [f64]) -> f64 {
    x.sort_by(f64::total_cmp);
    let cdf = |u: f64| {
        if d == 2 {
            1.0 - (-u * u).exp()
        } else {
            // a = v_rms/√3; F = erf(v/(√2 a)) − √(2/π) (v/a) e^{−v²/2a²}.
            let w = u * 3f64.sqrt();
            erf(w / 2f64.sqrt()) - (2.0 / PI).sqrt() * w * (-w * w / 2.0).exp()
        }
    };
    let n = x.len() as f64;
    x.iter()
        .enumerate()
        .map(|(i, &u)| {
            let f = cdf(u);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

/// A gas over time: kinetic energy, momentum and impacts at checkpoints;
/// speeds in units of the rms speed pooled over the second half.
struct GasSeries {
    t: Vec<f64>,
    energy: Vec<f64>,
    momentum: Vec<f64>,
    impacts: Vec<u64>,
    speeds: Vec<f64>,
    ms_per_step: f64,
    error: Option<String>,
    residual: f64,
    escaped: usize,
    diagnostics: Option<String>,
}

fn gas_series<const D: usize>(
    b: &Backend<D>,
    setup: &Setup<D>,
    method: Method,
    t_end: f64,
    checkpoints: usize,
) -> GasSeries {
    let mut sim = b.sim(setup, method);
    let mut out = GasSeries {
        t: vec![0.0],
        energy: vec![1.0],
        momentum: vec![],
        impacts: vec![0],
        speeds: vec![],
        ms_per_step: 0.0,
        error: None,
        residual: 0.0,
        escaped: 0,
        diagnostics: None,
    };
    let initial: Vec<_> = setup
        .balls
        .iter()
        .map(|b| (b.position, b.velocity))
        .collect();
    let e0 = kinetic(setup, &initial);
    let m_total: f64 = setup.balls.iter().map(|b| b.mass).sum();
    // |P| in units of sqrt(2 M E): about 1/sqrt(N) for an equilibrium gas.
    out.momentum
        .push(momentum(setup, &initial).norm() / (2.0 * m_total * e0).sqrt());
    for c in 1..=checkpoints {
        // Whole base steps, so that every simulator stops at the same times.
        let steps = (t_end / DT * c as f64 / checkpoints as f64).round();
        if let Err(e) = sim.advance_to(steps * DT) {
            out.error = Some(e);
            break;
        }
        let state = sim.state();
        let e = kinetic(setup, &state);
        out.t.push(sim.time());
        out.energy.push(e / e0);
        out.momentum
            .push(momentum(setup, &state).norm() / (2.0 * m_total * e).sqrt());
        out.impacts.push(sim.totals().impacts());
        if 2 * c > checkpoints {
            let v_rms = (2.0 * e / m_total).sqrt();
            out.speeds
                .extend(state.iter().map(|(_, v)| v.norm() / v_rms));
        }
    }
    let (busy, steps) = sim.busy();
    out.ms_per_step = if steps > 0 {
        1e3 * busy / steps as f64
    } else {
        f64::NAN
    };
    out.diagnostics = sim.diagnostics();
    out.residual = sim.impulse_residual();
    let (lo, hi) = (setup.bounds.lo, setup.bounds.hi);
    out.escaped = sim
        .state()
        .iter()
        .filter(|(p, _)| (0..D).any(|k| !(p[k] >= lo[k] && p[k] <= hi[k])))
        .count();
    out
}

// ---------------------------------------------------------------------------
// The compressibility factor
// ---------------------------------------------------------------------------

/// Henderson's equation of state for hard disks.
fn henderson(eta: f64) -> f64 {
    (1.0 + eta * eta / 8.0) / (1.0 - eta).powi(2)
}

/// Carnahan–Starling for hard spheres.
fn carnahan_starling(eta: f64) -> f64 {
    (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3)
}

fn eos(d: usize, eta: f64) -> f64 {
    if d == 2 {
        henderson(eta)
    } else {
        carnahan_starling(eta)
    }
}

/// The box of a Z measurement: `n` balls in a box whose lengths
/// accessible to the centres are `ell` (the box is `ell + σ`).
fn z_setup<const D: usize>(n: usize, ell: V<D>, seed: u64) -> Setup<D> {
    let size = ell.add_scalar(2.0 * R);
    let mut balls = lattice(n, ell, Velocities::Maxwell, seed);
    for b in &mut balls {
        b.position = b.position.add_scalar(R);
    }
    Setup {
        balls,
        bounds: BoxBounds::new(V::zeros(), size),
        walls: true,
        dissipation: 0.0,
        dt: DT,
    }
}

/// The distances from the walls beyond which the density is counted: the
/// one used (first), one σ closer and one σ farther, to show how much the
/// result depends on it. A fifth of the shortest accessible length, at
/// least 3.5 σ (the density oscillations near a wall decay over a few σ).
fn ws<const D: usize>(ell: &V<D>) -> [f64; 3] {
    let w = (0.2 * ell.min()).max(3.5);
    [w, w - 1.0, w + 1.0]
}

const NW: usize = 3;

/// The number of balls that gives the bulk packing fraction `eta` in the
/// box `ell`: the nominal count `eta ℓ^D / v`, corrected twice by short
/// reference runs (the walls hold some balls back).
fn calibrate<const D: usize>(eta: f64, ell: V<D>, t: f64) -> usize {
    let mut n = (eta * ell.product() / ball_volume(D, R)).round() as usize;
    for _ in 0..2 {
        let setup = z_setup::<D>(n, ell, 11);
        let b = Backend::<D> {
            label: "reference",
            precision: "f64",
            make: no_rapier::<D>,
        };
        let z = z_run(&b, &setup, Method::Reference, ell, 0.2 * t, t, 4, 0.5);
        n = (n as f64 * eta / z.eta_bulk).round() as usize;
    }
    n
}

#[derive(Clone)]
struct ZResult {
    n: usize,
    eta_bulk: f64,
    z: f64,
    z_err: f64,
    /// Total wall force over the whole box surface, nominal density N/V.
    z_naive: f64,
    /// Force on the walls of axis 0 over their accessible area, bulk
    /// density: no correction for the walls' excess near their ends.
    z_single: f64,
    /// Standard error of `z_single`.
    z_single_err: f64,
    /// (w, bulk η, Z) for every `W`.
    by_w: Vec<(f64, f64, f64)>,
    kt_drift: f64,
    impacts: u64,
    ms_per_step: f64,
    residual: f64,
    error: Option<String>,
    diagnostics: Option<String>,
}

/// Pressure from the mean forces on the walls of each axis, `f[k]`, with
/// the walls' excess near edges and corners eliminated (see the doc):
/// 2D, `F_k = P ℓ_j − 2γ`; 3D, square cross-section `ℓ = (a, a, c)`,
/// `F_k = P A_k − 2γ Per_k` (edge line tension neglected).
fn pressure<const D: usize>(f: &[f64; D], ell: &V<D>) -> f64 {
    if D == 2 {
        (f[1] - f[0]) / (ell[0] - ell[1])
    } else {
        let (a, c) = (ell[0], ell[2]);
        let fx = 0.5 * (f[0] + f[1]);
        (2.0 * fx - (a + c) * f[2] / a) / (a * (c - a))
    }
}

fn mean_and_error(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, (var / n).sqrt())
}

/// Z from a run: equilibrate for `t_eq`, then measure over `t_run` in
/// `blocks` blocks, counting the centres in the regions at least `ws(&ell)[i]`
/// from every wall every `sample` time units.
#[allow(clippy::too_many_arguments)]
fn z_run<const D: usize>(
    b: &Backend<D>,
    setup: &Setup<D>,
    method: Method,
    ell: V<D>,
    t_eq: f64,
    t_run: f64,
    blocks: usize,
    sample: f64,
) -> ZResult {
    let n = setup.balls.len();
    let mut sim = b.sim(setup, method);
    let size = setup.bounds.size();
    let region = |w: f64| size.add_scalar(-2.0 * w).product();
    let mut out = ZResult {
        n,
        eta_bulk: f64::NAN,
        z: f64::NAN,
        z_err: f64::NAN,
        z_naive: f64::NAN,
        z_single: f64::NAN,
        z_single_err: f64::NAN,
        by_w: Vec::new(),
        kt_drift: f64::NAN,
        impacts: 0,
        ms_per_step: f64::NAN,
        residual: 0.0,
        error: None,
        diagnostics: None,
    };
    let steps_of = |t: f64| (t / DT).round() * DT;
    if let Err(e) = sim.advance_to(steps_of(t_eq)) {
        out.error = Some(e);
        return out;
    }
    let kt = |state: &[(V<D>, V<D>)]| 2.0 * kinetic(setup, state) / (D * n) as f64;
    let kt0 = kt(&sim.state());
    let mut last = sim.totals();
    let mut t_last = sim.time();
    let samples_per_block = ((t_run / blocks as f64) / sample).round().max(1.0) as usize;
    let (mut z_blocks, mut single_blocks) = (Vec::new(), Vec::new());
    let (mut sum_f, mut sum_t, mut sum_kt) = ([0.0; D], 0.0, 0.0);
    let mut sum_rho = [0.0; NW];
    let mut impulse_total = 0.0;
    for _ in 0..blocks {
        let (mut rho, mut temp) = ([0.0; NW], 0.0);
        for _ in 0..samples_per_block {
            let target = steps_of(sim.time() + sample);
            if let Err(e) = sim.advance_to(target) {
                out.error = Some(e);
                return out;
            }
            let state = sim.state();
            for (i, &w) in ws(&ell).iter().enumerate() {
                let inside = state
                    .iter()
                    .filter(|(p, _)| (0..D).all(|k| p[k] >= w && p[k] <= size[k] - w))
                    .count();
                rho[i] += inside as f64 / region(w);
            }
            temp += kt(&state);
        }
        for r in &mut rho {
            *r /= samples_per_block as f64;
        }
        temp /= samples_per_block as f64;
        let now = sim.totals();
        let dt_block = sim.time() - t_last;
        let mut f = [0.0; D];
        for k in 0..D {
            let j = now.wall_impulse[k][0] + now.wall_impulse[k][1]
                - last.wall_impulse[k][0]
                - last.wall_impulse[k][1];
            f[k] = 0.5 * j / dt_block;
            impulse_total += j;
            sum_f[k] += f[k] * dt_block;
        }
        z_blocks.push(pressure(&f, &ell) / (rho[0] * temp));
        single_blocks.push(f[0] / (ell.product() / ell[0]) / (rho[0] * temp));
        sum_t += dt_block;
        for i in 0..NW {
            sum_rho[i] += rho[i];
        }
        sum_kt += temp;
        last = now;
        t_last = sim.time();
    }
    let f: [f64; D] = std::array::from_fn(|k| sum_f[k] / sum_t);
    let temp = sum_kt / blocks as f64;
    let p = pressure(&f, &ell);
    let rho: Vec<f64> = sum_rho.iter().map(|r| r / blocks as f64).collect();
    out.z = p / (rho[0] * temp);
    out.z_err = mean_and_error(&z_blocks).1;
    out.eta_bulk = rho[0] * ball_volume(D, R);
    out.by_w = ws(&ell)
        .iter()
        .zip(&rho)
        .map(|(&w, &r)| (w, r * ball_volume(D, R), p / (r * temp)))
        .collect();
    let area: f64 = (0..D).map(|k| 2.0 * size.product() / size[k]).sum();
    let p_naive = impulse_total / sum_t / area;
    out.z_naive = p_naive / (n as f64 / size.product() * temp);
    out.z_single = f[0] / (ell.product() / ell[0]) / (rho[0] * temp);
    out.z_single_err = mean_and_error(&single_blocks).1;
    out.kt_drift = temp / kt0 - 1.0;
    out.impacts = sim.totals().impacts();
    let (busy, steps) = sim.busy();
    out.ms_per_step = if steps > 0 {
        1e3 * busy / steps as f64
    } else {
        f64::NAN
    };
    out.residual = sim.impulse_residual();
    out.diagnostics = sim.diagnostics();
    out
}

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

/// What a job hands back: table rows (by table key), CSV lines and plot
/// points (by panel key and series name).
#[derive(Default)]
struct Out {
    rows: Vec<(String, Vec<String>)>,
    csv: Vec<String>,
    points: Vec<(String, String, &'static str, f64, f64)>,
    notes: Vec<String>,
    z: Vec<ZEntry>,
}

/// One Z run: the case (dimension, η and box, the same for every
/// simulator), who ran it and the result.
struct ZEntry {
    case: String,
    d: usize,
    eta: f64,
    method: Method,
    /// The rapier build's precision (the reference computes in f64).
    precision: &'static str,
    t_run: f64,
    r: ZResult,
}

impl Out {
    fn row(&mut self, table: &str, cells: Vec<String>) {
        self.rows.push((table.to_owned(), cells));
    }

    fn csv(
        &mut self,
        section: &str,
        engine: &str,
        method: Method,
        dt_div: usize,
        x: f64,
        quantity: &str,
        value: f64,
    ) {
        self.csv.push(format!(
            "{section},{engine},{},{dt_div},{x},{quantity},{value:e}",
            method.name()
        ));
    }

    fn point(&mut self, panel: &str, series: &str, color: &'static str, x: f64, y: f64) {
        self.points
            .push((panel.to_owned(), series.to_owned(), color, x, y));
    }
}

fn e(x: f64) -> String {
    if x == 0.0 {
        "0".to_owned()
    } else if !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:.1e}")
    }
}

fn pct(x: f64) -> String {
    format!("{:+.2}%", 100.0 * x)
}

/// Run `jobs` on `threads` threads, results in job order.
fn run_jobs<T: Send>(jobs: Vec<Box<dyn FnOnce() -> T + Send + '_>>, threads: usize) -> Vec<T> {
    let n = jobs.len();
    let queue: Mutex<Vec<Option<Box<dyn FnOnce() -> T + Send + '_>>>> =
        Mutex::new(jobs.into_iter().map(Some).collect());
    let results: Mutex<Vec<Option<T>>> = Mutex::new((0..n).map(|_| None).collect());
    let next = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    if i >= n {
                        break;
                    }
                    let job = queue.lock().unwrap()[i].take().unwrap();
                    let r = job();
                    results.lock().unwrap()[i] = Some(r);
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap()
        .into_iter()
        .map(|r| r.unwrap())
        .collect()
}

// ---------------------------------------------------------------------------
// The experiments
// ---------------------------------------------------------------------------

struct Sizes {
    /// Simulated time of the gas statistics.
    gas_t: f64,
    /// Reference Z runs: measuring time (time units).
    z_ref_t: f64,
    /// rapier Z runs: measuring time.
    z_rapier_t: f64,
    cooling_t: f64,
    cost_t: f64,
}

fn short_jobs<const D: usize>(b: Backend<D>) -> Out {
    let mut out = Out::default();
    for method in Method::RAPIER {
        for (m2, d) in [(10.0, 0.0), (1.0, 0.05)] {
            let s = short_run(&b, &two_ball_setup::<D>(m2, d, 0.6, DT), method, 10.0 * DT);
            out.row(
                "impact",
                vec![
                    b.label.into(),
                    method.name().into(),
                    format!("1:{m2}, d̃ = {d}"),
                    e(s.dv),
                    e(s.dx),
                    format!("{:.6}", s.kept),
                    e(s.dp),
                ],
            );
        }
        let s = short_run(&b, &cradle_setup::<D>(DT), method, 30.0 * DT);
        out.row(
            "cradle",
            vec![
                b.label.into(),
                method.name().into(),
                e(s.dv),
                format!("{:.4}", s.kept),
                e(s.dp),
            ],
        );
    }
    out
}

fn gas_jobs<const D: usize>(b: Backend<D>, method: Method, sizes: &Sizes) -> Out {
    let mut out = Out::default();
    let n = 200;
    let setup = gas_setup::<D>(n, 0.0, DT, 1);
    let checkpoints = 100;
    let g = gas_series(&b, &setup, method, sizes.gas_t, checkpoints);
    let r = gas_series(&b, &setup, Method::Reference, sizes.gas_t, checkpoints);
    // The noise floor: the reference from other initial balls.
    let other = gas_series(
        &b,
        &gas_setup::<D>(n, 0.0, DT, 2),
        Method::Reference,
        sizes.gas_t,
        checkpoints,
    );
    let rate = |s: &GasSeries| *s.impacts.last().unwrap() as f64 / s.t.last().unwrap();
    let mean_p = |s: &GasSeries| s.momentum.iter().sum::<f64>() / s.momentum.len() as f64;
    let cells = |label: String, s: &GasSeries| {
        let mut sp = s.speeds.clone();
        let mut rsp = r.speeds.clone();
        vec![
            b.label.into(),
            label,
            format!("{:.6}", s.energy.last().unwrap()),
            format!("{:.3}", mean_p(s)),
            format!("{:.0}", rate(s)),
            pct(rate(s) / rate(&r) - 1.0),
            format!("{:.3}", ks(&mut sp, &mut rsp)),
            format!("{:.3}", ks_maxwell(D, &mut s.speeds.clone())),
            if s.ms_per_step.is_nan() {
                "–".into()
            } else {
                format!("{:.3}", s.ms_per_step)
            },
            if s.escaped > 0 {
                format!("{} escaped", s.escaped)
            } else {
                e(s.residual)
            },
        ]
    };
    if method == Method::Native {
        let row = cells("reference".into(), &r);
        out.row("gas", row);
        let row = cells("reference, other balls".into(), &other);
        out.row("gas", row);
    }
    let row = cells(method.name().into(), &g);
    out.row("gas", row);
    if let Some(err) = &g.error {
        out.notes
            .push(format!("gas {} {}: {err}", b.label, method.name()));
    }
    if let Some(d) = &g.diagnostics {
        out.notes
            .push(format!("gas {} {}: {d}", b.label, method.name()));
    }
    for (s, m) in [(&g, method), (&r, Method::Reference)] {
        if m == Method::Reference && method != Method::Native {
            continue;
        }
        for i in 0..s.t.len() {
            out.csv("gas", b.label, m, 1, s.t[i], "energy", s.energy[i]);
            if i > 0 {
                let rate = (s.impacts[i] - s.impacts[i - 1]) as f64 / (s.t[i] - s.t[i - 1]);
                out.csv("gas", b.label, m, 1, s.t[i], "impact_rate", rate);
            }
            out.csv("gas", b.label, m, 1, s.t[i], "momentum", s.momentum[i]);
        }
    }
    out
}

fn cooling_jobs<const D: usize>(b: Backend<D>, sizes: &Sizes) -> Out {
    let mut out = Out::default();
    let d = 0.01;
    let checkpoints = 60;
    // With d̃ > 0 the reference can stall: grazing impacts are clamped to a
    // restitution of 1e-3, and three balls in contact then collapse into
    // infinitely many impacts at one instant (inelastic collapse). Take
    // the first two draws of the balls that it runs through for the whole
    // time: the first for the comparison, the second as the noise floor.
    let mut good: Vec<(u64, GasSeries)> = Vec::new();
    for seed in 3..16 {
        let g = gas_series(
            &b,
            &gas_setup::<D>(200, d, DT, seed),
            Method::Reference,
            sizes.cooling_t,
            checkpoints,
        );
        match &g.error {
            Some(err) => out.notes.push(format!(
                "cooling {} reference, draw {seed} (skipped): {err} (inelastic collapse)",
                b.label
            )),
            None => good.push((seed, g)),
        }
        if good.len() == 2 {
            break;
        }
    }
    assert!(good.len() == 2, "no two draws the reference runs through");
    let (other_seed, other) = good.pop().unwrap();
    let (seed, r) = good.pop().unwrap();
    out.notes.push(format!(
        "cooling {}: compared on draw {seed}; noise floor from draw {other_seed}",
        b.label
    ));
    let setup = gas_setup::<D>(200, d, DT, seed);
    let panel = format!("cooling {}", b.label);
    let runs: Vec<(String, Method, GasSeries)> = std::iter::once((
        "reference, other balls".to_owned(),
        Method::Reference,
        other,
    ))
    .chain(Method::RAPIER.into_iter().map(|m| {
        (
            m.name().to_owned(),
            m,
            gas_series(&b, &setup, m, sizes.cooling_t, checkpoints),
        )
    }))
    .collect();
    let row = |label: &str, s: &GasSeries, vs: bool| {
        let m = s.t.len().min(r.t.len());
        let worst = (1..m)
            .map(|i| (s.energy[i] / r.energy[i] - 1.0).abs())
            .fold(0.0, f64::max);
        vec![
            b.label.into(),
            label.to_owned(),
            format!("{:.4}", s.energy[m / 2]),
            format!("{:.4}", s.energy[m - 1]),
            if vs {
                pct(s.energy[m - 1] / r.energy[m - 1] - 1.0)
            } else {
                "–".into()
            },
            if vs {
                format!("{:.1}%", 100.0 * worst)
            } else {
                "–".into()
            },
            format!("{}", s.impacts[m - 1]),
        ]
    };
    out.row("cooling", row("reference", &r, false));
    for i in 0..r.t.len() {
        out.csv(
            "cooling",
            b.label,
            Method::Reference,
            1,
            r.t[i],
            "energy",
            r.energy[i],
        );
        out.point(
            &panel,
            "reference",
            Method::Reference.color(),
            r.t[i],
            r.energy[i],
        );
    }
    if let Some(err) = &r.error {
        out.notes
            .push(format!("cooling {} reference: {err}", b.label));
    }
    for (label, method, s) in &runs {
        out.row("cooling", row(label, s, true));
        if *method != Method::Reference {
            for i in 0..s.t.len() {
                out.csv(
                    "cooling",
                    b.label,
                    *method,
                    1,
                    s.t[i],
                    "energy",
                    s.energy[i],
                );
                out.point(&panel, method.name(), method.color(), s.t[i], s.energy[i]);
            }
        }
        if let Some(d) = &s.diagnostics {
            out.notes.push(format!("cooling {} {label}: {d}", b.label));
        }
        if let Some(err) = &s.error {
            out.notes
                .push(format!("cooling {} {label}: {err}", b.label));
        }
    }
    out
}

fn z_job<const D: usize>(
    b: Backend<D>,
    eta: f64,
    n: usize,
    ell: V<D>,
    method: Method,
    sizes: &Sizes,
) -> Out {
    let mut out = Out::default();
    let setup = z_setup::<D>(n, ell, 11);
    let (t_eq, t_run, blocks) = match (method, D) {
        (Method::Reference, 2) => (50.0, sizes.z_ref_t * 4.0, 20),
        (Method::Reference, _) if n > 2000 => (50.0, 0.75 * sizes.z_ref_t, 20),
        (Method::Reference, _) => (50.0, sizes.z_ref_t, 20),
        (_, 2) => (10.0, sizes.z_rapier_t, 10),
        _ => (10.0, 0.4 * sizes.z_rapier_t, 10),
    };
    let z = z_run(&b, &setup, method, ell, t_eq, t_run, blocks, 0.5);
    let lengths: Vec<String> = ell.iter().map(|x| format!("{x}")).collect();
    let case = format!("{D}D η = {eta}, ℓ = ({})", lengths.join(", "));
    let precision = if method == Method::Reference {
        "f64"
    } else {
        b.precision
    };
    let who = format!("{case}, {} {precision}", method.name());
    if let Some(err) = &z.error {
        out.notes.push(format!("Z {who}: {err}"));
    }
    if let Some(d) = &z.diagnostics {
        out.notes.push(format!("Z {who}: {d}"));
    }
    out.z.push(ZEntry {
        case,
        d: D,
        eta,
        method,
        precision,
        t_run,
        r: z,
    });
    out
}

/// The Z tables, from every job's results: the cases in the order of their
/// first run, each with the reference first, then every mode in f32 and
/// f64.
fn z_tables(z: &[ZEntry]) -> (Vec<Vec<String>>, Vec<Vec<String>>) {
    let case_rank = |case: &str| z.iter().position(|x| x.case == case).unwrap_or(0);
    let mut sorted: Vec<&ZEntry> = z.iter().collect();
    sorted.sort_by_key(|x| (case_rank(&x.case), x.method, x.precision));
    let mut main = Vec::new();
    let mut checks = Vec::new();
    for x in sorted {
        let (case, eta, d, method, t_run, r) = (&x.case, &x.eta, &x.d, &x.method, &x.t_run, &x.r);
        let reference = z
            .iter()
            .find(|y| &y.case == case && y.method == Method::Reference)
            .map(|y| &y.r);
        let fit = eos(*d, r.eta_bulk);
        let name = if *d == 2 {
            "Henderson"
        } else {
            "Carnahan–Starling"
        };
        let vs_ref = match reference {
            Some(q) if *method != Method::Reference => {
                let ratio = r.z_single / q.z_single;
                let err = ratio
                    * ((r.z_single_err / r.z_single).powi(2)
                        + (q.z_single_err / q.z_single).powi(2))
                    .sqrt();
                format!("{} ± {:.2}%", pct(ratio - 1.0), 100.0 * err)
            }
            _ => "–".into(),
        };
        main.push(vec![
            case.clone(),
            method.name().into(),
            x.precision.into(),
            format!("{}", r.n),
            format!("{t_run}"),
            format!("{:.4}", r.eta_bulk),
            format!("{:.4} ± {:.4}", r.z, r.z_err),
            format!("{fit:.4} ({name})"),
            format!("{} ± {:.2}%", pct(r.z / fit - 1.0), 100.0 * r.z_err / fit),
            vs_ref,
            pct(r.kt_drift),
            format!("{}", r.impacts),
            if r.ms_per_step.is_nan() {
                "–".into()
            } else {
                format!("{:.2}", r.ms_per_step)
            },
            e(r.residual),
        ]);
        if *method == Method::Reference {
            let mut row = vec![
                case.clone(),
                pct(r.z_naive / eos(*d, *eta) - 1.0),
                pct(r.z_single / fit - 1.0),
            ];
            for (w, eta_w, z_w) in &r.by_w {
                row.push(format!(
                    "{w}: η {eta_w:.4}, Z/EOS {}",
                    pct(z_w / eos(*d, *eta_w) - 1.0)
                ));
            }
            checks.push(row);
        }
    }
    (main, checks)
}

fn cost_jobs<const D: usize>(b: Backend<D>, sizes: &Sizes) -> Out {
    let mut out = Out::default();
    for method in Method::RAPIER {
        for div in [1usize, 2, 4, 8] {
            let dt = DT / div as f64;
            let setup = gas_setup::<D>(200, 0.0, dt, 1);
            let g = gas_series(&b, &setup, method, sizes.cost_t, 2);
            let cost = g.ms_per_step * div as f64 / DT / 1e3; // s per simulated s
            let energy = (g.energy.last().unwrap() - 1.0).abs().max(1e-16);
            let one = short_run(
                &b,
                &two_ball_setup::<D>(10.0, 0.0, 0.6, dt),
                method,
                10.0 * DT,
            );
            let cradle = short_run(&b, &cradle_setup::<D>(dt), method, 30.0 * DT);
            out.row(
                "cost",
                vec![
                    b.label.into(),
                    method.name().into(),
                    format!("dt/{div}"),
                    format!("{}", g.impacts.last().unwrap()),
                    format!("{:.3}", g.ms_per_step),
                    format!("{:.3}", cost),
                    e(energy),
                    e(one.dv),
                    e(cradle.dv),
                ],
            );
            let x = cost;
            let color = method.color();
            out.point(
                &format!("gas energy error {}", b.label),
                method.name(),
                color,
                x,
                energy,
            );
            out.point(
                &format!("one impact {}", b.label),
                method.name(),
                color,
                x,
                one.dv.max(1e-16),
            );
            out.point(
                &format!("cradle {}", b.label),
                method.name(),
                color,
                x,
                cradle.dv.max(1e-16),
            );
            for (q, v) in [
                ("ms_per_step", g.ms_per_step),
                ("cpu_s_per_sim_s", cost),
                ("gas_energy_error", energy),
                ("impact_velocity_error", one.dv),
                ("cradle_velocity_error", cradle.dv),
            ] {
                out.csv("cost", b.label, method, div, dt, q, v);
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------
// SVG
// ---------------------------------------------------------------------------

struct Panel {
    title: String,
    xlabel: &'static str,
    ylabel: &'static str,
    logx: bool,
    series: Vec<(String, &'static str, Vec<(f64, f64)>)>,
}

fn svg(panels: &[Panel], cols: usize) -> String {
    let (pw, ph) = (460.0, 320.0);
    let rows = panels.len().div_ceil(cols);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" font-family="sans-serif" font-size="11">"#,
        pw * cols as f64,
        ph * rows as f64
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for (i, p) in panels.iter().enumerate() {
        let (ox, oy) = ((i % cols) as f64 * pw, (i / cols) as f64 * ph);
        let (l, r, t, b) = (ox + 60.0, ox + pw - 110.0, oy + 28.0, oy + ph - 42.0);
        let pts: Vec<(f64, f64)> = p
            .series
            .iter()
            .flat_map(|s| s.2.iter().copied())
            .filter(|(x, y)| x.is_finite() && y.is_finite() && *y > 0.0)
            .collect();
        if pts.is_empty() {
            continue;
        }
        let fx = |x: f64| if p.logx { x.log10() } else { x };
        let (mut x0, mut x1) = pts.iter().fold((f64::MAX, f64::MIN), |a, q| {
            (a.0.min(fx(q.0)), a.1.max(fx(q.0)))
        });
        let (mut y0, mut y1) = pts.iter().fold((f64::MAX, f64::MIN), |a, q| {
            (a.0.min(q.1.log10()), a.1.max(q.1.log10()))
        });
        if p.logx {
            x0 = x0.floor();
            x1 = x1.ceil();
        } else {
            x0 = 0.0;
            // f32 times end a hair past the whole second (30.0000016).
            x1 = (x1 - 1e-6 * x1.abs()).ceil();
        }
        y0 = y0.floor();
        y1 = y1.ceil().max(y0 + 1.0);
        if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        let px = |x: f64| l + (fx(x) - x0) / (x1 - x0) * (r - l);
        let py = |y: f64| b - (y.log10() - y0) / (y1 - y0) * (b - t);
        let _ = writeln!(
            s,
            r##"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="#888"/>"##,
            r - l,
            b - t
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle" font-size="13">{}</text>"#,
            (l + r) / 2.0,
            oy + 18.0,
            p.title
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
            (l + r) / 2.0,
            b + 32.0,
            p.xlabel
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle" transform="rotate(-90 {} {})">{}</text>"#,
            ox + 14.0,
            (t + b) / 2.0,
            ox + 14.0,
            (t + b) / 2.0,
            p.ylabel
        );
        let ystep = ((y1 - y0) / 8.0).ceil().max(1.0);
        let mut y = y0;
        while y <= y1 + 1e-9 {
            let yy = b - (y - y0) / (y1 - y0) * (b - t);
            let _ = writeln!(
                s,
                r##"<line x1="{l}" x2="{r}" y1="{yy}" y2="{yy}" stroke="#eee"/><text x="{}" y="{}" text-anchor="end">1e{}</text>"##,
                l - 4.0,
                yy + 4.0,
                y as i32
            );
            y += ystep;
        }
        if p.logx {
            let mut x = x0;
            while x <= x1 + 1e-9 {
                let xx = l + (x - x0) / (x1 - x0) * (r - l);
                let _ = writeln!(
                    s,
                    r##"<line x1="{xx}" x2="{xx}" y1="{t}" y2="{b}" stroke="#eee"/><text x="{xx}" y="{}" text-anchor="middle">1e{}</text>"##,
                    b + 14.0,
                    x as i32
                );
                x += 1.0;
            }
        } else {
            for i in 0..=5 {
                let x = x0 + (x1 - x0) * i as f64 / 5.0;
                let xx = l + (r - l) * i as f64 / 5.0;
                let _ = writeln!(
                    s,
                    r##"<line x1="{xx}" x2="{xx}" y1="{t}" y2="{b}" stroke="#eee"/><text x="{xx}" y="{}" text-anchor="middle">{}</text>"##,
                    b + 14.0,
                    (x * 100.0).round() / 100.0
                );
            }
        }
        for (k, (name, color, pts)) in p.series.iter().enumerate() {
            let path: Vec<String> = pts
                .iter()
                .filter(|(x, y)| x.is_finite() && y.is_finite() && *y > 0.0)
                .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{color}" stroke-width="1.5"/>"#,
                path.join(" ")
            );
            if p.logx {
                for q in &path {
                    let (a, c) = q.split_once(',').unwrap();
                    let _ = writeln!(s, r#"<circle cx="{a}" cy="{c}" r="3" fill="{color}"/>"#);
                }
            }
            let ly = t + 14.0 + 16.0 * k as f64;
            let _ = writeln!(
                s,
                r#"<line x1="{}" x2="{}" y1="{}" y2="{}" stroke="{color}" stroke-width="2"/><text x="{}" y="{}">{name}</text>"#,
                r + 8.0,
                r + 26.0,
                ly - 4.0,
                ly - 4.0,
                r + 30.0,
                ly
            );
        }
    }
    s.push_str("</svg>\n");
    s
}

// ---------------------------------------------------------------------------
// main
// ---------------------------------------------------------------------------

fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        " --- |".repeat(header.len())
    );
    for r in rows {
        let _ = writeln!(s, "| {} |", r.join(" | "));
    }
    s
}

fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let cmd = |c: &str, a: &[&str]| {
        std::process::Command::new(c)
            .args(a)
            .output()
            .ok()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
            .unwrap_or_default()
    };
    format!(
        "{cpu}, {cores} cores available to the process, {}; {}; {}",
        cmd("uname", &["-sr"]),
        cmd("rustc", &["-V"]),
        cmd("date", &["-u", "+%Y-%m-%d %H:%M UTC"])
    )
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let threads: usize = arg("--threads").and_then(|t| t.parse().ok()).unwrap_or(2);
    let dir = arg("--out").unwrap_or_else(|| "docs".into());
    let f = if quick { 0.1 } else { 1.0 };
    let sizes = Sizes {
        gas_t: 100.0 * f,
        z_ref_t: 2000.0 * f,
        z_rapier_t: 100.0 * f,
        cooling_t: 30.0 * f,
        cost_t: 10.0 * f,
    };
    let started = Instant::now();
    let sizes = &sizes;

    // Phase 1: accuracy (parallel jobs; their timings share the cores).
    let mut jobs: Vec<Box<dyn FnOnce() -> Out + Send + '_>> = Vec::new();
    let ell2 = V::<2>::new(60.0, 30.0);
    let ell3 = V::<3>::new(10.0, 10.0, 20.0);
    // The box sizes that give the wanted bulk packing fractions.
    eprintln!("calibrating the Z boxes with the reference");
    let n3 = calibrate::<3>(0.3, ell3, if quick { 30.0 } else { 100.0 });
    // The 3D box small enough for rapier leaves little room away from the
    // walls: the reference also measures Z in a larger one.
    let ell3_large = V::<3>::new(14.0, 14.0, 28.0);
    let n3_large = calibrate::<3>(0.3, ell3_large, if quick { 20.0 } else { 50.0 });
    let n2: Vec<usize> = [0.3, 0.5]
        .iter()
        .map(|&eta| calibrate::<2>(eta, ell2, if quick { 100.0 } else { 400.0 }))
        .collect();
    // The longest first: the reference runs (once per case: it has no
    // precision to vary), then rapier's in 3D, then in 2D; every mode in
    // both precisions.
    let r = Method::Reference;
    jobs.push(Box::new(move || {
        z_job(B3_F64, 0.3, n3_large, ell3_large, r, sizes)
    }));
    jobs.push(Box::new(move || z_job(B3_F64, 0.3, n3, ell3, r, sizes)));
    for (i, eta) in [0.3, 0.5].into_iter().enumerate() {
        let n = n2[i];
        jobs.push(Box::new(move || z_job(B2_F64, eta, n, ell2, r, sizes)));
    }
    for m in Method::RAPIER {
        for b in [B3_F32, B3_F64] {
            jobs.push(Box::new(move || z_job(b, 0.3, n3, ell3, m, sizes)));
        }
    }
    for (i, eta) in [0.3, 0.5].into_iter().enumerate() {
        let n = n2[i];
        for m in Method::RAPIER {
            for b in [B2_F32, B2_F64] {
                jobs.push(Box::new(move || z_job(b, eta, n, ell2, m, sizes)));
            }
        }
    }
    for m in Method::RAPIER {
        jobs.push(Box::new(move || gas_jobs(B2_F32, m, sizes)));
        jobs.push(Box::new(move || gas_jobs(B2_F64, m, sizes)));
        jobs.push(Box::new(move || gas_jobs(B3_F32, m, sizes)));
        jobs.push(Box::new(move || gas_jobs(B3_F64, m, sizes)));
    }
    jobs.push(Box::new(move || cooling_jobs(B2_F32, sizes)));
    jobs.push(Box::new(move || cooling_jobs(B2_F64, sizes)));
    jobs.push(Box::new(move || cooling_jobs(B3_F32, sizes)));
    jobs.push(Box::new(move || cooling_jobs(B3_F64, sizes)));
    jobs.push(Box::new(|| short_jobs(B2_F32)));
    jobs.push(Box::new(|| short_jobs(B2_F64)));
    jobs.push(Box::new(|| short_jobs(B3_F32)));
    jobs.push(Box::new(|| short_jobs(B3_F64)));
    let total = jobs.len();
    let done = AtomicUsize::new(0);
    let done = &done;
    let jobs = jobs
        .into_iter()
        .map(|j| -> Box<dyn FnOnce() -> Out + Send + '_> {
            Box::new(move || {
                let o = j();
                let k = done.fetch_add(1, Ordering::SeqCst) + 1;
                eprintln!(
                    "[{:>6.1}s] {k}/{total} jobs",
                    started.elapsed().as_secs_f64()
                );
                o
            })
        })
        .collect();
    let mut outs = run_jobs(jobs, threads);
    // Phase 2: the cost of accuracy, one job at a time so that the timings
    // do not share the cores with other jobs of this program.
    eprintln!(
        "[{:>6.1}s] cost of accuracy (one thread)",
        started.elapsed().as_secs_f64()
    );
    outs.push(cost_jobs(B2_F32, sizes));
    outs.push(cost_jobs(B2_F64, sizes));
    outs.push(cost_jobs(B3_F32, sizes));
    outs.push(cost_jobs(B3_F64, sizes));
    let elapsed = started.elapsed().as_secs_f64();

    let mut tables: BTreeMap<String, Vec<Vec<String>>> = BTreeMap::new();
    let mut csv = vec!["section,engine,method,dt_div,x,quantity,value".to_owned()];
    let mut panels: BTreeMap<String, BTreeMap<String, (&'static str, Vec<(f64, f64)>)>> =
        BTreeMap::new();
    let mut notes = Vec::new();
    let mut z_results = Vec::new();
    for o in outs {
        for (k, r) in o.rows {
            tables.entry(k).or_default().push(r);
        }
        csv.extend(o.csv);
        for (panel, series, color, x, y) in o.points {
            panels
                .entry(panel)
                .or_default()
                .entry(series)
                .or_insert((color, Vec::new()))
                .1
                .push((x, y));
        }
        notes.extend(o.notes);
        z_results.extend(o.z);
    }
    let (z_main, z_checks) = z_tables(&z_results);
    let order = |name: &str| {
        Method::ALL
            .iter()
            .position(|m| m.name() == name)
            .unwrap_or(9)
    };
    let mut panel_list = Vec::new();
    for (title, series) in &panels {
        let cooling = title.starts_with("cooling");
        let mut series: Vec<_> = series
            .iter()
            .map(|(n, (c, p))| (n.clone(), *c, p.clone()))
            .collect();
        series.sort_by_key(|s| order(&s.0));
        panel_list.push(Panel {
            title: title.clone(),
            xlabel: if cooling {
                "time (s)"
            } else {
                "CPU seconds per simulated second (200-ball gas)"
            },
            ylabel: if cooling {
                "kinetic energy / initial"
            } else {
                "error"
            },
            logx: !cooling,
            series,
        });
    }
    let rank = |t: &str| {
        ["gas energy", "one impact", "cradle", "cooling"]
            .iter()
            .position(|k| t.starts_with(k))
            .unwrap_or(9)
    };
    // One row of three cost panels per build (2D f32, 2D f64, 3D f32, 3D
    // f64), then the cooling curves.
    panel_list.sort_by_key(|p| {
        let cooling = p.title.starts_with("cooling");
        let build = if cooling {
            (false, false)
        } else {
            (p.title.contains("3D"), p.title.contains("f64"))
        };
        (cooling, build, rank(&p.title), p.title.clone())
    });
    std::fs::create_dir_all(&dir).expect("output directory");
    std::fs::write(format!("{dir}/accuracy.svg"), svg(&panel_list, 3)).expect("write svg");
    std::fs::write(format!("{dir}/accuracy.csv"), csv.join("\n") + "\n").expect("write csv");
    let get = |k: &str| tables.get(k).cloned().unwrap_or_default();
    // The hand-written findings between the markers survive regeneration.
    let findings = std::fs::read_to_string(format!("{dir}/accuracy.md"))
        .ok()
        .and_then(|old| {
            let a = old.find(FINDINGS_BEGIN)? + FINDINGS_BEGIN.len();
            let b = old.find(FINDINGS_END)?;
            (a <= b).then(|| old[a..b].to_owned())
        })
        .unwrap_or_else(|| {
            "\n(Write the findings here: this block is kept when the file is regenerated.)\n\n"
                .into()
        });
    let doc = document(
        &findings,
        &get("impact"),
        &get("cradle"),
        &get("gas"),
        &z_main,
        &z_checks,
        &get("cooling"),
        &get("cost"),
        &notes,
        &machine(),
        quick,
        threads,
        elapsed,
        sizes,
    );
    std::fs::write(format!("{dir}/accuracy.md"), doc).expect("write markdown");
    eprintln!("wrote {dir}/accuracy.md, accuracy.svg, accuracy.csv in {elapsed:.0} s");
}

#[allow(clippy::too_many_arguments)]
fn document(
    findings: &str,
    impact: &[Vec<String>],
    cradle: &[Vec<String>],
    gas: &[Vec<String>],
    z: &[Vec<String>],
    z_checks: &[Vec<String>],
    cooling: &[Vec<String>],
    cost: &[Vec<String>],
    notes: &[String],
    machine: &str,
    quick: bool,
    threads: usize,
    elapsed: f64,
    sizes: &Sizes,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Accuracy against the exact reference\n");
    let _ = writeln!(
        s,
        "Generated by `cargo run --release --example accuracy{}` ({threads} worker threads, {elapsed:.0} s) on {machine}. \
         Every table below, the plot `accuracy.svg` and the data `accuracy.csv` come from that one command \
         (the Findings are written by hand from them, and kept when the file is regenerated); the CI versions of the first three comparisons are `cargo test --test accuracy`.\n",
        if quick { " -- --quick" } else { "" }
    );
    let _ = writeln!(s, "{INTRO}");
    let _ = writeln!(
        s,
        "## Findings\n\n{FINDINGS_BEGIN}{findings}{FINDINGS_END}\n"
    );
    let _ = writeln!(s, "## One oblique impact\n");
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "mode",
                "masses, dissipation",
                "velocity error",
                "position error / r",
                "energy kept",
                "momentum error"
            ],
            impact
        )
    );
    let _ = writeln!(s, "## Newton's cradle\n");
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "mode",
                "velocity error",
                "energy kept",
                "momentum error"
            ],
            cradle
        )
    );
    let _ = writeln!(s, "## Elastic gas: statistics over time\n");
    let _ = writeln!(
        s,
        "{}",
        GAS_TEXT.replace("{T}", &format!("{}", sizes.gas_t))
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "simulator",
                "E(T)/E(0)",
                "mean abs(P)/sqrt(2ME)",
                "impacts per s",
                "vs reference",
                "KS speeds vs reference",
                "KS speeds vs Maxwell",
                "ms/step",
                "wall-impulse residual"
            ],
            gas
        )
    );
    let _ = writeln!(s, "## Compressibility factor of hard disks and spheres\n");
    let _ = writeln!(
        s,
        "{}",
        Z_TEXT
            .replace("{TREF}", &format!("{}", sizes.z_ref_t))
            .replace("{TRAP}", &format!("{}", sizes.z_rapier_t))
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "case",
                "simulator",
                "precision",
                "N",
                "measured over",
                "bulk η",
                "Z (± 1 s.e.)",
                "equation of state at bulk η",
                "Z vs EOS",
                "single-wall Z vs reference's",
                "kT drift",
                "impacts",
                "ms/step",
                "wall-impulse residual"
            ],
            z
        )
    );
    let _ = writeln!(s, "{}", Z_CHECKS_TEXT);
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "case (reference)",
                "naive Z vs EOS(nominal η)",
                "no end correction vs EOS",
                "w used",
                "w − 1",
                "w + 1"
            ],
            z_checks
        )
    );
    let _ = writeln!(s, "## Cooling granular gas\n");
    let _ = writeln!(
        s,
        "{}",
        COOLING_TEXT.replace("{T}", &format!("{}", sizes.cooling_t))
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "simulator",
                "E(T/2)/E(0)",
                "E(T)/E(0)",
                "E(T) vs reference",
                "worst deviation",
                "impacts"
            ],
            cooling
        )
    );
    let _ = writeln!(s, "## What accuracy costs\n");
    let _ = writeln!(
        s,
        "{}",
        COST_TEXT.replace("{T}", &format!("{}", sizes.cost_t))
    );
    let _ = writeln!(
        s,
        "![accuracy against cost, and the cooling curves](accuracy.svg)\n"
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "mode",
                "dt",
                "impacts",
                "ms/step",
                "CPU s per simulated s",
                "gas energy error",
                "one-impact velocity error",
                "cradle velocity error"
            ],
            cost
        )
    );
    if !notes.is_empty() {
        let _ = writeln!(s, "## Notes from the run\n");
        for n in notes {
            let _ = writeln!(s, "- {n}");
        }
        s.push('\n');
    }
    s
}

const FINDINGS_BEGIN: &str = "<!-- findings: hand-written, kept by the generator -->";
const FINDINGS_END: &str = "<!-- end of findings -->";

const INTRO: &str = "\
All scenes use balls of diameter σ = 1 and mass 1 (except where a mass ratio is given), no \
friction, no gravity, rapier's default time step dt = 1/60 s and its default integration \
parameters. Each comparison builds the rapier world from the reference's own balls, so both \
start from the same state. The reference (`kimpact-reference`) is exact: every impact at its \
time of impact, up to rounding. Errors are absolute, with the incoming speed 1 and the radius \
as units. `native` is rapier unchanged with restitution 1 (or, for the cooling gas, the law's \
head-on restitution), the other rows are the adapter's modes.
";

const GAS_TEXT: &str = "\
200 balls at packing fraction 0.3 in a closed cubic box (the kind of gas of the CI test; 3D: 200 \
spheres), velocity components drawn uniform in [−3, 3] and scaled to kT = 3, run for \
T = {T} s (6,000 steps). The reference runs the same balls. `reference, other balls` is the \
reference from another draw of the initial balls at the same energy: it shows how far two exact \
runs of the same gas differ (hard-ball dynamics is chaotic, so beyond a few hundred impacts only \
statistics can agree), i.e. the noise floor of every column. Momentum: |P| in units of \
sqrt(2ME), averaged over the checkpoints (about 1/sqrt(N) = 0.07 for an equilibrium gas; the \
walls exchange momentum with the balls). Speeds are divided by the rms speed at their checkpoint \
and pooled over the second half of the run (100 checkpoints in all); KS is the \
Kolmogorov–Smirnov distance. ms/step is measured while another job of the program shares the \
two cores. The wall-impulse residual checks the impulse bookkeeping used for the pressure: per \
step and axis, the change of the balls' total momentum minus the net impulse counted on the \
walls, summed, over the summed wall impulses (0 is perfect; f32 rounds).
";

const Z_TEXT: &str = "\
Elastic hard disks (2D, bulk η = 0.3 and 0.5) and spheres (3D, bulk η = 0.3), Maxwell \
velocities at kT = 1, in boxes whose lengths accessible to the centres are ℓ = (60, 30) (2D) \
and (10, 10, 20) (3D) diameters (the box is ℓ + σ); the reference also runs a larger 3D box, \
ℓ = (14, 14, 28), too large for rapier in a few minutes. N is chosen by two short reference runs so \
that the bulk packing fraction comes out at the wanted η. The reference is equilibrated for 50 \
time units and measured over the time in the table (20 blocks); the rapier modes, each in the \
f32 and the f64 build of the adapter (`precision`; the reference always computes in f64), for 10 \
and then over the time in the table (10 blocks), one run each, from the same balls.

**The estimator.** Near a hard wall the density is not the bulk density, and near the edges \
and corners of the box the force on a wall is not the bulk pressure times its area. So:

- *Density* is counted away from the walls: the centres in the region at least w = max(ℓ_min/5, 3.5 σ) from every wall (6 σ in 2D, 3.5 \
and 5.6 σ in the two 3D boxes), sampled every 0.5 time units, divided by the region's volume; η_bulk = ρ v_ball, and \
the equation of state is evaluated at η_bulk.
- *Pressure* comes from the wall impulses, with each wall's excess near its ends eliminated by \
comparing walls of different lengths. A wall of accessible length ℓ_j feels F = P ℓ_j − 2γ in \
2D (γ the excess per end, the same at every 90° corner by symmetry), so \
P = (F_y − F_x)/(ℓ_x − ℓ_y): the force on the extra length of the long walls, which lies away \
from the corners. In 3D, with a square cross-section ℓ = (a, a, c), F_k = P A_k − 2γ Per_k \
(A_k and Per_k the accessible area and perimeter of face k; the edges' line tension adds a \
constant, of relative size ~1e-3 here, which is neglected), so \
P = (2 F_x − (a + c) F_z / a) / (a (c − a)). F_k is the mean of the two walls of axis k.
- *Temperature* kT = 2 E_kin/(D N), averaged over the samples (constant in the exact \
simulators; `kT drift` shows how much a rapier mode lost or gained during the measurement).
- Z = P/(ρ_bulk kT); the error is the standard error over the blocks. rapier's wall impulses \
are those its solver applied plus, in the `impulse` and `exact` modes, the law's impulses \
(`Kimpact::events`); the wall-impulse residual checks them against the balls' momentum.

The difference of two wall forces is noisy (about 4x the relative noise of one force), so the \
rapier runs, much shorter than the reference's, also get a low-noise comparison: \
`single-wall Z vs reference's` is the force on the walls of axis 0 over their accessible \
length or area, with the bulk density (an estimator with a bias of its own, the same in every \
simulator), relative to the reference's value of the same estimator.
";

const Z_CHECKS_TEXT: &str = "\
Checks of the estimator, on the reference: `naive Z` (total wall impulse over the whole box \
surface, mean density N/V, compared with the equation of state at the nominal η = N v/V), \
`no end correction` (force on one pair of walls over its accessible length or area, bulk \
density), and the result with the density counted beyond other distances w from the walls \
(cells: w, bulk η there, Z against the equation of state at that η).
";

const COOLING_TEXT: &str = "\
The gas above (another draw of the balls) with d̃ = 0.01 (walls too, own-mass policy), for \
T = {T} s: kinetic energy over time in the reference and in each mode (the curves are in \
`accuracy.svg` and `accuracy.csv`). The law's effective restitution depends on the masses and \
on the impact angle (grazing impacts are clamped), so the curves are compared with the \
reference, not with a constant-restitution formula. `native` has the law's head-on restitution \
sqrt(1 − 8 d̃) between balls and sqrt(1 − 2 d̃) against walls (rapier averages the two \
colliders' coefficients, which the walls' coefficient accounts for). `worst deviation` is the \
largest |E/E_ref − 1| over the 60 checkpoints; `reference, other balls` (another draw at the \
same energy) is the noise floor: beyond a few collision times every run is an independent \
sample of the same cooling.
";

const COST_TEXT: &str = "\
Each mode at dt, dt/2, dt/4 and dt/8 (rapier's own way to buy accuracy), in each of the four \
builds (2D and 3D, f32 and f64; one row of the plot each): the CPU time of the 200-ball gas \
per simulated second (one thread, no other job of this program running), against the relative \
energy error of that gas after T = {T} s (elastic: every loss is error), the velocity error \
after one oblique impact (masses 1:10) and in Newton's cradle. Errors are clamped at 1e-16 in \
the plot.
";
