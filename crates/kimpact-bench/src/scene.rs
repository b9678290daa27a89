// The bench scenes and the child's runs, once for 2D/3D and f32/f64
// (included by `worlds.rs` where `k` is an adapter crate).

use std::sync::atomic::Ordering;

use k::math::{DIM, Vector};
use k::rapier::prelude::*;
use k::{Kimpact, Law, LawError, LawParams, Mode};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

use crate::cli::{Cli, Effect, HOOK_NATIVE, NO_CALM, REBOUND_CUTOFF, Scene};
use crate::raw::{Measure, Pair, Solo};
use crate::{alloc, memory};

/// A vector with components uniform in `[-speed, speed)`.
fn random_vector(rng: &mut Xoshiro256PlusPlus, speed: Real) -> Vector {
    let mut v = Vector::ZERO;
    for axis in 0..DIM {
        v[axis] = speed * rng.random_range(-1.0..1.0) as Real;
    }
    v
}

/// The smallest `k` with `k^DIM >= n` (balls per side of a grid).
fn per_side(n: usize) -> usize {
    let fits = |side: &usize| side.pow(DIM as u32) >= n;
    (1usize..).find(fits).expect("some side fits")
}

/// Cell `i` of a `side`-per-axis grid of pitch `spacing` about the origin.
fn grid_point(i: usize, side: usize, spacing: Real) -> Vector {
    let half = 0.5 * spacing * side as Real;
    let mut p = Vector::ZERO;
    let mut rest = i;
    for axis in 0..DIM {
        p[axis] = -half + spacing * (0.5 + (rest % side) as Real);
        rest /= side;
    }
    p
}

/// A cuboid collider of half-extents `he`, in either dimension.
fn cuboid(he: Vector) -> ColliderBuilder {
    ColliderBuilder::new(SharedShape::new(k::rapier::parry::shape::Cuboid::new(he)))
}

/// A collider's friction and restitution.
type Material = (Real, Real);

/// A point of the xy plane (z = 0 in 3D).
fn xy(x: Real, y: Real) -> Vector {
    let mut p = Vector::ZERO;
    (p[0], p[1]) = (x, y);
    p
}

/// One scene, ready to step.
pub struct Bench {
    world: PhysicsWorld,
    kimpact: Kimpact,
    /// The flippers (kinematic bodies) and their signs, swung before each
    /// step at `sign · 0.45 · (2π/0.25) · sin(2π t/0.25)` rad/s.
    flippers: Vec<(RigidBodyHandle, Real)>,
    /// Simulated time, for the flippers.
    time: Real,
    /// Whether the user reads the impact events after each step.
    read_events: bool,
    /// The material every ball is marked with (`None`: the law's).
    own_material: Option<k::Material>,
}

impl Bench {
    /// A scene's empty world, its `law` from the scene's own (valid)
    /// constants.
    fn new(mode: Mode, law: Result<Law<Real>, LawError>, gravity: Vector) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = gravity;
        Self {
            world,
            kimpact: Kimpact::new(law.expect("valid law parameters"), mode),
            flippers: Vec::new(),
            time: 0.0,
            read_events: false,
            own_material: None,
        }
    }

    /// A marked collider `shape` of mass `mass` on `body` (marked with the
    /// scene's own material if it has one).
    fn mark(&mut self, body: RigidBodyBuilder, shape: ColliderBuilder, mass: Real, m: Material) {
        let collider = shape.mass(mass).friction(m.0).restitution(m.1);
        let collider = self.hooked_if_asked(collider);
        let (_, c) = self.world.insert(body, collider);
        let marked = match self.own_material {
            Some(m) => self.kimpact.mark_with(&self.world.colliders, c, m),
            None => self.kimpact.mark(&self.world.colliders, c),
        };
        marked.expect("inserted just above");
    }

    /// `collider`, hooked in native mode under `--hook-native`.
    pub(crate) fn hooked_if_asked(&self, collider: ColliderBuilder) -> ColliderBuilder {
        if self.kimpact.mode() == Mode::Native && HOOK_NATIVE.load(Ordering::Relaxed) {
            collider.active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        } else {
            collider
        }
    }

    /// A closed box of fixed walls, inner half-extents `half`.
    fn closed_box(&mut self, half: Vector, thickness: Real, material: Material) {
        let t = thickness;
        for axis in 0..DIM {
            for sign in [-1.0, 1.0] {
                let mut center = Vector::ZERO;
                center[axis] = sign * (half[axis] + t);
                let mut he = half + Vector::splat(2.0 * t);
                he[axis] = t;
                let body = RigidBodyBuilder::fixed().translation(center);
                let collider = cuboid(he).friction(material.0).restitution(material.1);
                self.world.insert(body, collider);
            }
        }
    }

    /// `scene` with (about) `balls` balls in `mode` (of this module's
    /// dimension).
    pub fn setup(scene: Scene, balls: usize, mode: Mode) -> Self {
        let mut b = Self::build(scene, balls, mode);
        b.configure();
        b
    }

    /// The resolver settings this process's options ask for:
    /// `--rebound-cutoff` (in rest speeds, `2 |g| dt`) and `--no-calm`.
    fn configure(&mut self) {
        let mut config = *self.kimpact.config();
        let rests = f64::from_bits(REBOUND_CUTOFF.load(Ordering::Relaxed));
        if rests > 0.0 {
            let g = self.world.gravity.length();
            let rest_speed = 2.0 * g * self.world.integration_parameters.dt;
            config.rebound_cutoff = Some(rests as Real * rest_speed);
        }
        if NO_CALM.load(Ordering::Relaxed) {
            config.calm_neighbourhoods = false;
        }
        self.kimpact
            .set_config(config)
            .expect("a finite cut-off of rest speeds >= 0 (checked by the CLI)");
    }

    /// [`Bench::setup`] before the options of this process.
    fn build(scene: Scene, balls: usize, mode: Mode) -> Self {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(42);
        match scene {
            Scene::Pit2d | Scene::Pit3d => {
                // Mixed masses dropped on a grid filling a closed box.
                let mut b = Self::new(mode, Law::with_dissipation(0.09), -Vector::Y * 9.81);
                let material = (0.3, 0.5);
                let (r, spacing) = (0.25, 0.8);
                let side = per_side(balls);
                b.closed_box(Vector::splat(0.5 * spacing * side as Real), 0.5, material);
                for i in 0..balls {
                    let body = RigidBodyBuilder::dynamic()
                        .translation(grid_point(i, side, spacing))
                        .linvel(random_vector(&mut rng, 1.0));
                    let mass = [1.0, 2.0, 0.5][i % 3];
                    b.mark(body, ColliderBuilder::ball(r), mass, material);
                }
                b
            }
            Scene::Gas2d | Scene::Gas3d => Self::effect(Effect::Walls, balls, mode),
            Scene::Billiards => {
                // 15 racked balls and the cue ball, cloth as damping, CCD.
                let mut b = Self::new(mode, Law::with_dissipation(0.012), Vector::ZERO);
                let ball = (0.0, 0.95);
                let cushion = (0.0, 0.9);
                let (r, m) = (0.028575, 0.17);
                b.closed_box(xy(1.27, 0.635), 0.05, cushion);
                let gap = 2.0 * r * 1.0005;
                let foot = 0.635;
                for row in 0..5 {
                    for j in 0..=row {
                        let x = row as Real * gap * 0.8660254;
                        let y = (j as Real - 0.5 * row as Real) * gap;
                        let body = RigidBodyBuilder::dynamic()
                            .translation(xy(foot + x, y))
                            .linear_damping(0.3)
                            .ccd_enabled(true);
                        b.mark(body, ColliderBuilder::ball(r), m, ball);
                    }
                }
                let body = RigidBodyBuilder::dynamic()
                    .translation(xy(-foot, 0.002))
                    .linvel(Vector::X * 6.0)
                    .linear_damping(0.3)
                    .ccd_enabled(true);
                b.mark(body, ColliderBuilder::ball(r), m, ball);
                b
            }
            Scene::Cue => {
                // A heavy cue ball through a grid of resting, damped, awake
                // balls, clipping one every 2 m.
                let mut b = Self::new(mode, Law::with_dissipation(0.0), Vector::ZERO);
                let material = (0.0, 1.0);
                let (r, spacing) = (0.5, 2.0);
                let side = per_side(balls);
                let grid_half = 0.5 * spacing * side as Real;
                b.closed_box(Vector::splat(grid_half + 4.0), 1.0, material);
                for i in 0..balls {
                    let body = RigidBodyBuilder::dynamic()
                        .translation(grid_point(i, side, spacing))
                        .linear_damping(3.0)
                        .can_sleep(false);
                    b.mark(body, ColliderBuilder::ball(r), 1.0, material);
                }
                let row = grid_point(side / 2 * side, side, spacing)[1];
                let body = RigidBodyBuilder::dynamic()
                    .translation(xy(-grid_half - 2.0, row + 0.8))
                    .linvel(Vector::X * 5.0)
                    .can_sleep(false);
                b.mark(body, ColliderBuilder::ball(r), 10.0, material);
                b
            }
            Scene::Restitution3 | Scene::Restitution2 => Self::restitution(mode),
            Scene::Pinball => Self::pinball(mode, &mut rng),
            Scene::Dice => Self::dice(mode, balls, &mut rng),
            Scene::Dominoes => Self::dominoes(mode, balls),
        }
    }

    /// The effects table's base in this dimension with `effect` on (see
    /// [`Effect`]): `balls` elastic balls (radius 0.5, mass 1, thrown at up
    /// to 3 m/s, never asleep) on a grid of the density of the adapter
    /// tests' 500-ball gas, no gravity. With the walls it is the gas scene.
    pub fn effect(effect: Effect, balls: usize, mode: Mode) -> Self {
        let on = |e: Effect| if effect == e { 1.0 } else { 0.0 };
        let (d, g) = (0.09 * on(Effect::Dissipation), 9.81 * on(Effect::Gravity));
        let mut b = Self::new(mode, Law::with_dissipation(d), -Vector::Y * g);
        let material = (0.5 * on(Effect::Friction), 1.0);
        let r = 0.5;
        let half = if DIM == 2 {
            22.0 * (balls as f64 / 500.0).sqrt()
        } else {
            7.0 * (balls as f64 / 500.0).cbrt()
        } as Real;
        if effect == Effect::Walls {
            b.closed_box(Vector::splat(half), 1.0, material);
        }
        b.read_events = effect == Effect::Events;
        let elastic = k::Material::new(0.0, 0.0).expect("zero is a valid dissipation");
        let rough = elastic.with_impact_friction(0.5, 0.0);
        b.own_material = match effect {
            Effect::Materials => Some(elastic),
            Effect::ImpactFriction => Some(rough.expect("mu = 0.5 and beta = 0 are valid")),
            _ => None,
        };
        let side = per_side(balls);
        let spacing = 2.0 * half / side as Real;
        assert!(spacing > 2.0 * r, "the gas grid must not overlap");
        // The spins from their own generator: the velocities stay the base's.
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(42);
        let mut spins = Xoshiro256PlusPlus::seed_from_u64(7);
        for i in 0..balls {
            let spin = on(Effect::Spin) + on(Effect::ImpactFriction);
            let w = 6.0 * spin * spins.random_range(-1.0..1.0) as Real;
            let body = RigidBodyBuilder::dynamic()
                .translation(grid_point(i, side, spacing))
                .linvel(random_vector(&mut rng, 3.0))
                .angvel(about_z(w))
                .can_sleep(false);
            b.mark(body, ColliderBuilder::ball(r), 1.0, material);
        }
        b
    }

    /// One step through kimpact (`Mode::Native` too: identical code path),
    /// after swinging the flippers.
    pub fn step(&mut self) {
        self.swing_and_step(|kimpact, world| {
            kimpact.step_world(world, &(), &());
        });
    }

    /// [`Bench::step`], each of its three stages timed on the step clock:
    /// kimpact's `before_step`, rapier's step, kimpact's `after_step` (µs).
    pub fn step_in_stages(&mut self) -> [f64; 3] {
        let mut stages = [0.0; 3];
        self.swing_and_step(|kimpact, world| {
            let (gravity, params) = (world.gravity, world.integration_parameters);
            let (pipeline, mut sets) = k::StepSets::of_world(world);
            let t0 = memory::step_clock_us();
            let prepared = kimpact.before_step(gravity, &params, &mut sets);
            let t1 = memory::step_clock_us();
            let hooks = kimpact.hooks(&prepared, &());
            sets.step_pipeline(pipeline, gravity, &params, &hooks, &());
            let t2 = memory::step_clock_us();
            kimpact.after_step(prepared, &mut sets, &());
            let t3 = memory::step_clock_us();
            stages = [t1 - t0, t2 - t1, t3 - t2];
        });
        stages
    }

    /// Swing the flippers, step with `step`, read the events if asked.
    fn swing_and_step(&mut self, step: impl FnOnce(&mut Kimpact, &mut PhysicsWorld)) {
        let (tau, period) = (std::f64::consts::TAU as Real, 0.25);
        for &(body, sign) in &self.flippers {
            let w = 0.45 * tau / period * (tau * self.time / period).sin();
            if let Some(rb) = self.world.bodies.get_mut(body) {
                rb.set_angvel(about_z(sign * w), true);
            }
        }
        step(&mut self.kimpact, &mut self.world);
        if self.read_events {
            let impulses = self.kimpact.events().iter().map(|e| e.impulse);
            std::hint::black_box(impulses.sum::<Real>());
        }
        self.time += self.world.integration_parameters.dt;
    }
}

/// CPU time and allocations of `n` measured steps into `m`: a sample per
/// step, or with `whole` one per block (a step of microseconds is too short
/// to time alone); with `stages` (and not `whole`), each step's stages too.
fn measured_block(bench: &mut Bench, n: usize, (whole, stages): (bool, bool), m: &mut Measure) {
    let per_sample = if whole { n } else { 1 };
    for _ in 0..n / per_sample {
        let (count, cpu) = (alloc::count(), memory::step_clock_us());
        for _ in 0..per_sample {
            match stages && !whole {
                true => m.stages_us.push(bench.step_in_stages()),
                false => bench.step(),
            }
        }
        let cpu = memory::step_clock_us() - cpu;
        m.allocs += alloc::count() - count;
        m.cpu_us.push(cpu / per_sample as f64);
    }
}

/// In a child: the timing pair (`--pair`) or the mode alone (`--solo`)
/// that `cli` asks for, as JSON.
pub fn run(cli: &Cli) -> String {
    let (scene, balls, mode) = (cli.scene[0], cli.balls[0], cli.mode[0]);
    let build = |mode| match cli.effect {
        Some(effect) => Bench::effect(effect, balls, mode),
        None => Bench::setup(scene, balls, mode),
    };
    let json = match cli.pair {
        true => serde_json::to_string(&run_pair(cli, build)),
        false => serde_json::to_string(&run_solo(cli, || build(mode))),
    };
    json.expect("a measure serializes")
}

/// Timing: native and `cli`'s mode on two copies of its scene (`build`),
/// per episode warmed up, then measured in alternating blocks, so that the
/// machine's drift hits both alike.
fn run_pair(cli: &Cli, build: impl Fn(Mode) -> Bench) -> Pair {
    let (mut native, mut law) = (Measure::default(), Measure::default());
    let block = cli.block.max(1);
    for _ in 0..cli.repeats.max(1) {
        let (n, l) = (build(Mode::Native), build(cli.mode[0]));
        let mut worlds = [(n, &mut native), (l, &mut law)];
        for _ in 0..cli.warmup {
            worlds.iter_mut().for_each(|(w, _)| w.step());
        }
        let before = worlds.each_ref().map(|(w, _)| w.kimpact.stats().impacts);
        for done in (0..cli.steps).step_by(block) {
            let n = block.min(cli.steps - done);
            for (w, m) in &mut worlds {
                measured_block(w, n, (cli.time_blocks, cli.stages), m);
            }
        }
        for ((w, m), before) in worlds.iter_mut().zip(before) {
            m.steps += cli.steps;
            m.impacts += w.kimpact.stats().impacts - before;
        }
    }
    Pair { native, law }
}

/// Memory: the mode alone, then the peak RSS; with `--attribute`, the same
/// steps again (serial rapier is deterministic) with every allocation
/// attributed (after the RSS is read: symbolizing takes memory).
fn run_solo(cli: &Cli, build: impl Fn() -> Bench) -> Solo {
    let warmed = || {
        let mut bench = build();
        (0..cli.warmup).for_each(|_| bench.step());
        bench
    };
    let mut bench = warmed();
    let count = alloc::count();
    (0..cli.steps).for_each(|_| bench.step());
    let allocs = alloc::count() - count;
    let peak_rss_kib = memory::peak_rss_kib();
    drop(bench);
    let attributed = cli.attribute.then(|| {
        let mut again = warmed();
        alloc::attribute();
        (0..cli.steps).for_each(|_| again.step());
        alloc::stop_attribute()
    });
    Solo {
        allocs,
        peak_rss_kib,
        attributed,
    }
}
