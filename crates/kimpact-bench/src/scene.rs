// The bench scenes and one measured run, written once for 2D/3D and f32/f64:
// included into modules that alias the adapter crate as `k` (see main.rs).
// Native and the law modes run through exactly this code; only the `Mode`
// given to `Kimpact::new` differs.

use std::time::Instant;

use k::math::{DIM, Real, Vector};
use k::rapier::prelude::*;
use k::{Kimpact, Law, LawParams, Mode};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

use crate::{Measure, Pair, Scene, Solo, alloc, memory};

/// A vector with components uniform in `[-speed, speed)`, from the scene's
/// seeded generator (the same sequence in every mode).
fn random_vector(rng: &mut Xoshiro256PlusPlus, speed: Real) -> Vector {
    let mut v = Vector::ZERO;
    for axis in 0..DIM {
        v[axis] = speed * rng.random_range(-1.0..1.0) as Real;
    }
    v
}

/// The smallest `k` with `k^DIM >= n` (balls per side of a grid).
fn per_side(n: usize) -> usize {
    let mut side = 1usize;
    while side.pow(DIM as u32) < n {
        side += 1;
    }
    side
}

/// Grid cell `i` of a `side`-per-axis grid of pitch `spacing` centred at the
/// origin.
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

#[derive(Copy, Clone)]
struct Material {
    friction: Real,
    restitution: Real,
}

/// One scene, ready to step.
pub struct Bench {
    world: PhysicsWorld,
    kimpact: Kimpact,
    balls: Vec<RigidBodyHandle>,
    /// Inner half-extents of the enclosing box.
    half: Vector,
}

impl Bench {
    fn new(mode: Mode, dissipation: Real, gravity: Vector) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = gravity;
        let law = Law::new(LawParams {
            dissipation,
            ..Default::default()
        })
        .expect("valid law parameters");
        Self {
            world,
            kimpact: Kimpact::with_config(
                law,
                mode,
                k::Config {
                    calm_neighbourhoods: !crate::no_calm(),
                    ..Default::default()
                },
            )
            .expect("the default configuration with calm_neighbourhoods set is valid"),
            balls: Vec::new(),
            half: Vector::ZERO,
        }
    }

    /// A marked ball.
    fn ball(
        &mut self,
        body: RigidBodyBuilder,
        radius: Real,
        mass: Real,
        material: Material,
    ) -> RigidBodyHandle {
        let collider = ColliderBuilder::ball(radius)
            .mass(mass)
            .friction(material.friction)
            .restitution(material.restitution);
        let (b, c) = self.world.insert(body, collider);
        self.kimpact
            .mark(&self.world.colliders, c)
            .expect("inserted just above");
        self.balls.push(b);
        b
    }

    /// A closed box of inner half-extents `half` centred at the origin, made
    /// of fixed, unmarked walls (they meet the law as fixed partners).
    fn closed_box(&mut self, half: Vector, thickness: Real, material: Material) {
        self.half = half;
        let t = thickness;
        for axis in 0..DIM {
            for sign in [-1.0, 1.0] {
                let mut center = Vector::ZERO;
                center[axis] = sign * (half[axis] + t);
                let mut he = half + Vector::splat(2.0 * t);
                he[axis] = t;
                let b = self
                    .world
                    .insert_body(RigidBodyBuilder::fixed().translation(center));
                let collider = k::math::cuboid(he)
                    .friction(material.friction)
                    .restitution(material.restitution);
                self.world.insert_collider(collider, Some(b));
            }
        }
    }

    /// Build `scene` with (about) `balls` balls, or `None` when the scene is
    /// not of this module's dimension.
    pub fn build(scene: Scene, balls: usize, mode: Mode) -> Option<Self> {
        if scene.dim() != DIM {
            return None;
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(42);
        let bench = match scene {
            Scene::Pit2d | Scene::Pit3d => {
                // Mixed masses dropped on a grid filling a closed box.
                let mut b = Self::new(mode, 0.09, -Vector::Y * 9.81);
                let material = Material {
                    friction: 0.3,
                    restitution: 0.5,
                };
                let (r, spacing) = (0.25, 0.8);
                let side = per_side(balls);
                b.closed_box(Vector::splat(0.5 * spacing * side as Real), 0.5, material);
                for i in 0..balls {
                    let body = RigidBodyBuilder::dynamic()
                        .translation(grid_point(i, side, spacing))
                        .linvel(random_vector(&mut rng, 1.0));
                    b.ball(body, r, [1.0, 2.0, 0.5][i % 3], material);
                }
                b
            }
            Scene::Gas2d | Scene::Gas3d => {
                // Elastic balls in a closed box, no gravity, no sleeping; the
                // density of the 500-ball gas of the adapter tests.
                let mut b = Self::new(mode, 0.0, Vector::ZERO);
                let material = Material {
                    friction: 0.0,
                    restitution: 1.0,
                };
                let r = 0.5;
                let half = if DIM == 2 {
                    22.0 * (balls as f64 / 500.0).sqrt()
                } else {
                    7.0 * (balls as f64 / 500.0).cbrt()
                } as Real;
                b.closed_box(Vector::splat(half), 1.0, material);
                let side = per_side(balls);
                let spacing = 2.0 * half / side as Real;
                assert!(spacing > 2.0 * r, "the gas grid must not overlap");
                for i in 0..balls {
                    let body = RigidBodyBuilder::dynamic()
                        .translation(grid_point(i, side, spacing))
                        .linvel(random_vector(&mut rng, 3.0))
                        .can_sleep(false);
                    b.ball(body, r, 1.0, material);
                }
                b
            }
            Scene::Billiards => {
                // A pool table seen from above: 15 racked balls and the cue
                // ball, cloth as linear damping, CCD on (a ball moves more
                // than its diameter per step at break speed).
                let mut b = Self::new(mode, 0.012, Vector::ZERO);
                let ball = Material {
                    friction: 0.0,
                    restitution: 0.95,
                };
                let cushion = Material {
                    friction: 0.0,
                    restitution: 0.9,
                };
                let (r, m) = (0.028575, 0.17);
                let mut half = Vector::ZERO;
                half[0] = 1.27;
                half[1] = 0.635;
                b.closed_box(half, 0.05, cushion);
                let gap = 2.0 * r * 1.0005;
                let foot = 0.635;
                for row in 0..5 {
                    for j in 0..=row {
                        let mut p = Vector::ZERO;
                        p[0] = foot + row as Real * gap * 0.8660254;
                        p[1] = (j as Real - 0.5 * row as Real) * gap;
                        let body = RigidBodyBuilder::dynamic()
                            .translation(p)
                            .linear_damping(0.3)
                            .ccd_enabled(true);
                        b.ball(body, r, m, ball);
                    }
                }
                let mut p = Vector::ZERO;
                p[0] = -foot;
                p[1] = 0.002;
                let body = RigidBodyBuilder::dynamic()
                    .translation(p)
                    .linvel(Vector::X * 6.0)
                    .linear_damping(0.3)
                    .ccd_enabled(true);
                b.ball(body, r, m, ball);
                b
            }
            Scene::Cue => {
                // One heavy cue ball crossing a grid of `balls` resting
                // balls, no gravity; it clips the row below its lane every
                // 2 m, and the balls it knocks are damped back to rest. The
                // resting balls never sleep: rapier steps all of them, and
                // kimpact must not add more than a few percent for the one
                // body that needs the law (asleep, a step costs microseconds
                // in every mode).
                let mut b = Self::new(mode, 0.0, Vector::ZERO);
                let material = Material {
                    friction: 0.0,
                    restitution: 1.0,
                };
                let (r, spacing) = (0.5, 2.0);
                let side = per_side(balls);
                let grid_half = 0.5 * spacing * side as Real;
                b.closed_box(Vector::splat(grid_half + 4.0), 1.0, material);
                for i in 0..balls {
                    let body = RigidBodyBuilder::dynamic()
                        .translation(grid_point(i, side, spacing))
                        .linear_damping(3.0)
                        .can_sleep(false);
                    b.ball(body, r, 1.0, material);
                }
                let row = grid_point(side / 2 * side, side, spacing)[1];
                let mut p = Vector::ZERO;
                p[0] = -grid_half - 2.0;
                p[1] = row + 0.8;
                let body = RigidBodyBuilder::dynamic()
                    .translation(p)
                    .linvel(Vector::X * 5.0)
                    .can_sleep(false);
                b.ball(body, r, 10.0, material);
                b
            }
        };
        Some(bench)
    }

    /// One step through kimpact (`Mode::Native` too: identical code path).
    pub fn step(&mut self) {
        self.kimpact.step_world(&mut self.world, &(), &());
    }

    /// Kinetic plus potential energy (from the floor of the box), f64.
    pub fn energy(&self) -> f64 {
        let g = f64::from(self.world.gravity.length());
        let floor = f64::from(self.half[1]);
        self.world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(_, b)| {
                let m = f64::from(b.mass());
                let v2 = f64::from(b.linvel().length_squared());
                0.5 * m * v2 + m * g * (f64::from(b.translation()[1]) + floor)
            })
            .sum()
    }

    /// Balls with a non-finite position or velocity.
    pub fn non_finite(&self) -> usize {
        self.balls
            .iter()
            .filter(|&&h| {
                let b = &self.world.bodies[h];
                !(b.translation().is_finite() && b.linvel().is_finite())
            })
            .count()
    }

    /// Balls outside the box (by more than a ball radius of slack).
    pub fn escaped(&self) -> usize {
        let slack = 1.0;
        self.balls
            .iter()
            .filter(|&&h| {
                let p = self.world.bodies[h].translation();
                (0..DIM).any(|a| p[a].is_nan() || p[a].abs() > self.half[a] + slack)
            })
            .count()
    }

    /// Awake dynamic bodies.
    pub fn awake(&self) -> usize {
        self.world
            .islands
            .active_bodies()
            .filter(|&h| self.world.bodies.get(h).is_some_and(|b| b.is_dynamic()))
            .count()
    }
}

/// Time, CPU time and allocations of one measured step, appended to `m`.
fn measured_step(bench: &mut Bench, m: &mut Measure) {
    let (count0, bytes0) = alloc::snapshot();
    let t = Instant::now();
    let c = memory::process_cpu_us();
    bench.step();
    let cpu = memory::process_cpu_us() - c;
    let wall = t.elapsed().as_secs_f64() * 1e6;
    let (count1, bytes1) = alloc::snapshot();
    m.times_us.push(wall);
    m.cpu_us.push(cpu);
    m.allocs += count1 - count0;
    m.alloc_bytes += bytes1 - bytes0;
}

/// An empty measure for `steps` steps, with the state before them.
fn start_measure(bench: &Bench, steps: usize) -> (Measure, k::Stats) {
    let m = Measure {
        steps,
        times_us: Vec::with_capacity(steps),
        cpu_us: Vec::with_capacity(steps),
        energy_start: bench.energy(),
        ..Measure::default()
    };
    (m, bench.kimpact.stats())
}

/// Fill in what the measured steps did to the scene.
fn finish_measure(bench: &Bench, m: &mut Measure, stats0: k::Stats) {
    let stats1 = bench.kimpact.stats();
    m.impacts = stats1.impacts - stats0.impacts;
    m.cap_hits = stats1.event_cap_hits - stats0.event_cap_hits;
    m.skipped = stats1.skipped_non_finite - stats0.skipped_non_finite;
    m.energy_end = bench.energy();
    m.non_finite = bench.non_finite();
    m.escaped = bench.escaped();
    m.awake_end = bench.awake();
}

/// Timing: native rapier and `mode` on two copies of the scene in this
/// process, in lockstep: warm-up, then `steps` measured steps each,
/// alternated in blocks of `block` (native's block, then the mode's), so
/// that whatever else the machine does hits both alike.
pub fn run_pair(
    scene: Scene,
    balls: usize,
    mode: Mode,
    warmup: usize,
    steps: usize,
    block: usize,
) -> Option<Pair> {
    let mut native = Bench::build(scene, balls, Mode::Native)?;
    let mut law = Bench::build(scene, balls, mode)?;
    for _ in 0..warmup {
        native.step();
        law.step();
    }
    let (mut mn, sn) = start_measure(&native, steps);
    let (mut ml, sl) = start_measure(&law, steps);
    let block = block.max(1);
    let mut done = 0;
    while done < steps {
        let n = block.min(steps - done);
        for _ in 0..n {
            measured_step(&mut native, &mut mn);
        }
        for _ in 0..n {
            measured_step(&mut law, &mut ml);
        }
        done += n;
    }
    finish_measure(&native, &mut mn, sn);
    finish_measure(&law, &mut ml, sl);
    Some(Pair {
        scene,
        balls: law.balls.len(),
        mode,
        precision: k::math::PRECISION,
        parallel: cfg!(feature = "parallel"),
        warmup,
        block,
        native: mn,
        law: ml,
    })
}

/// Memory and attribution: `mode` alone in this process (untimed): warm-up
/// and `steps` steps, then the peak RSS. With `attribute`, the same again
/// (serial rapier is deterministic), classifying every allocation of the
/// measured steps as kimpact's or rapier's from its stack (after the RSS is
/// read: symbolizing takes memory).
pub fn run_solo(
    scene: Scene,
    balls: usize,
    mode: Mode,
    warmup: usize,
    steps: usize,
    attribute: bool,
) -> Option<Solo> {
    let mut bench = Bench::build(scene, balls, mode)?;
    for _ in 0..warmup {
        bench.step();
    }
    let (count0, _) = alloc::snapshot();
    for _ in 0..steps {
        bench.step();
    }
    let (count1, _) = alloc::snapshot();
    let peak_rss_kib = memory::peak_rss_kib();
    let mut solo = Solo {
        scene,
        balls: bench.balls.len(),
        mode,
        precision: k::math::PRECISION,
        steps,
        allocs: count1 - count0,
        peak_rss_kib,
        attributed: false,
        attr_seen: 0,
        attr_sampled: 0,
        attr_own: 0,
        attr_stacks: 0,
    };
    if attribute {
        drop(bench);
        let mut again = Bench::build(scene, balls, mode)?;
        for _ in 0..warmup {
            again.step();
        }
        alloc::attribute();
        for _ in 0..steps {
            again.step();
        }
        (solo.attr_seen, solo.attr_own, solo.attr_stacks) = alloc::stop_attribute();
        // Every allocation is classified (the field is kept for earlier
        // runs' raw.json, which sampled about 1,000).
        solo.attr_sampled = solo.attr_seen;
        solo.attributed = true;
    }
    Some(solo)
}
