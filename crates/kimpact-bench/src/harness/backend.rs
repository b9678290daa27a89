//! The rapier side: the adapter's four builds behind [`Sim`], written once.

use kimpact::{Mode, Precision};

use crate::{HarnessError, Method, RefSim, Setup, Sim};

/// How a backend builds rapier on a scene in one mode.
type Make<const D: usize> = fn(&Setup<D>, Mode) -> Result<Box<dyn Sim<D>>, HarnessError>;

/// One adapter build (dimension and precision) behind [`Sim`].
#[derive(Copy, Clone)]
pub struct Backend<const D: usize> {
    /// `"2D f32"`, `"3D f64"`…: the engine column of the tables.
    pub label: &'static str,
    /// The precision of the rapier build.
    pub precision: Precision,
    make: Make<D>,
}

impl<const D: usize> Backend<D> {
    /// A simulator of `setup`: the reference, or this build of rapier in
    /// the method's mode.
    ///
    /// # Errors
    /// An invalid dissipation, or balls the simulator refuses.
    pub fn sim(&self, setup: &Setup<D>, method: Method) -> Result<Box<dyn Sim<D>>, HarnessError> {
        match method {
            Method::Reference => Ok(Box::new(RefSim::new(setup)?)),
            Method::Rapier(mode) => (self.make)(setup, mode),
        }
    }
}

/// The rapier side, written once for the four adapter builds: the
/// [`Backend`] `$name` of the adapter crate `$krate` (dimension `$dim`).
macro_rules! rapier_backend {
    ($name:ident, $module:ident, $label:literal, $precision:ident, $krate:ident, $dim:literal) => {
        #[doc = concat!("The ", stringify!($krate), " (", $label, ") build of the adapter.")]
        pub const $name: Backend<$dim> = Backend {
            label: $label,
            precision: Precision::$precision,
            make: |setup, mode| Ok(Box::new($module::World::new(setup, mode)?)),
        };

        mod $module {
            use std::collections::{HashMap, HashSet};
            use std::time::Instant;

            use crate::{HarnessError, Setup, Sim, State, V};
            use kimpact_reference::Stats;
            use k::math::{Real, Vector};
            use k::rapier::prelude::*;
            use k::{Kimpact, Law, Mode};
            use $krate as k;

            const D: usize = $dim;

            fn to_rapier(x: &V<D>) -> Vector {
                let mut v = Vector::ZERO;
                (0..D).for_each(|i| v[i] = x[i] as Real);
                v
            }

            fn from_rapier(v: Vector) -> V<D> {
                V::<D>::from_fn(|i, _| f64::from(v[i]))
            }

            pub struct World {
                world: PhysicsWorld,
                kimpact: Kimpact,
                balls: Vec<RigidBodyHandle>,
                /// Each wall collider's `(axis, side)`.
                walls: HashMap<ColliderHandle, (usize, usize)>,
                /// Native: pairs that carried an impulse at the last step.
                pushing: HashSet<(ColliderHandle, ColliderHandle)>,
                totals: Stats<D>,
                steps: u64,
                dt: f64,
                busy: f64,
                residual: f64,
                impulse_sum: f64,
            }

            impl World {
                /// This build of rapier on `setup`, with kimpact in `mode`.
                pub fn new(setup: &Setup<D>, mode: Mode) -> Result<Self, HarnessError> {
                    let mut world = PhysicsWorld::new();
                    world.gravity = Vector::ZERO;
                    world.integration_parameters.dt = setup.dt as Real;
                    let law = Law::with_dissipation(setup.dissipation as Real)?;
                    let mut kimpact = Kimpact::new(law, mode);
                    // Native rapier gets the law's head-on restitution for
                    // equal masses (q = 8 d̃) between balls and its wall
                    // restitution (q = 2 d̃, own-mass policy) against walls;
                    // rapier averages the two colliders' coefficients.
                    let d = setup.dissipation;
                    let e_ball = (1.0 - 8.0 * d).max(0.0).sqrt();
                    let e_wall = ((1.0 - 2.0 * d).max(0.0).sqrt() * 2.0 - e_ball).clamp(0.0, 1.0);
                    let mut walls = HashMap::new();
                    let (lo, hi) = (setup.bounds.lo, setup.bounds.hi);
                    let (centre, half, t) = ((lo + hi) * 0.5, (hi - lo) * 0.5, 1.0);
                    for (axis, side) in (0..D).flat_map(|a| [(a, 0), (a, 1)]).filter(|_| setup.walls) {
                        let mut c = centre;
                        c[axis] = if side == 0 { lo[axis] - t } else { hi[axis] + t };
                        let mut he = half.add_scalar(2.0 * t);
                        he[axis] = t;
                        let body = RigidBodyBuilder::fixed().translation(to_rapier(&c));
                        let he = k::rapier::parry::shape::Cuboid::new(to_rapier(&he));
                        let collider = ColliderBuilder::new(SharedShape::new(he))
                            .friction(0.0)
                            .restitution(e_wall as Real);
                        walls.insert(world.insert(body, collider).1, (axis, side));
                    }
                    let mut balls = Vec::new();
                    for b in &setup.balls {
                        let body = RigidBodyBuilder::dynamic()
                            .translation(to_rapier(&b.position))
                            .linvel(to_rapier(&b.velocity))
                            .can_sleep(false);
                        let collider = ColliderBuilder::ball(b.radius as Real)
                            .mass(b.mass as Real)
                            .friction(0.0)
                            .restitution(e_ball as Real);
                        let (handle, c) = world.insert(body, collider);
                        let marked = kimpact.mark(&world.colliders, c);
                        marked.map_err(|e| HarnessError::Mark(e.to_string()))?;
                        balls.push(handle);
                    }
                    let dt = f64::from(world.integration_parameters.dt);
                    Ok(Self {
                        world,
                        kimpact,
                        balls,
                        walls,
                        pushing: HashSet::new(),
                        totals: Stats::default(),
                        steps: 0,
                        dt,
                        busy: 0.0,
                        residual: 0.0,
                        impulse_sum: 0.0,
                    })
                }

                fn momentum(&self) -> V<D> {
                    let bodies = self.balls.iter().map(|&h| &self.world.bodies[h]);
                    bodies.map(|b| from_rapier(b.linvel()) * f64::from(b.mass())).sum()
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
                    for (&c, &(axis, side)) in &self.walls {
                        for cp in self.world.narrow_phase.contact_pairs_with(c) {
                            if cp.has_any_active_contact() {
                                impulse[axis][side] += f64::from(cp.total_impulse()[axis]).abs();
                            }
                        }
                    }
                    let wall = |c1, c2| self.walls.get(&c1).or(self.walls.get(&c2)).copied();
                    if self.kimpact.mode() == Mode::Native {
                        // An impact: a pair that carries an impulse now and
                        // did not at the previous step.
                        let mut now = HashSet::new();
                        for cp in self.world.narrow_phase.contact_pairs() {
                            let key = (cp.collider1, cp.collider2);
                            if !(cp.has_any_active_contact() && cp.total_impulse_magnitude() > 0.0) {
                                continue;
                            }
                            if !self.pushing.contains(&key) {
                                match wall(cp.collider1, cp.collider2) {
                                    Some(_) => self.totals.wall_impacts += 1,
                                    None => self.totals.ball_impacts += 1,
                                }
                            }
                            now.insert(key);
                        }
                        self.pushing = now;
                    } else {
                        for e in self.kimpact.events() {
                            match wall(e.collider1, e.collider2) {
                                Some((axis, side)) => {
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
                    let dp = self.momentum() - p0;
                    for (axis, [lo, hi]) in impulse.into_iter().enumerate() {
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

                fn advance_to(&mut self, t: f64) -> Result<(), HarnessError> {
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

                fn state(&self) -> State<D> {
                    let bodies = self.balls.iter().map(|&h| &self.world.bodies[h]);
                    bodies.map(|b| (from_rapier(b.translation()), from_rapier(b.linvel()))).collect()
                }

                fn totals(&self) -> Stats<D> {
                    self.totals
                }

                fn ms_per_step(&self) -> f64 {
                    match self.steps {
                        0 => f64::NAN,
                        n => 1e3 * self.busy / n as f64,
                    }
                }

                fn diagnostics(&self) -> Option<String> {
                    let s = self.kimpact.stats();
                    (s.event_cap_hits > 0 || s.skipped_non_finite > 0).then(|| {
                        format!(
                            "{} step(s) hit the exact mode's event cap ({} law impacts in all), {} pair(s) skipped for non-finite data",
                            s.event_cap_hits, s.impacts, s.skipped_non_finite
                        )
                    })
                }

                fn impulse_residual(&self) -> f64 {
                    match self.impulse_sum > 0.0 {
                        true => self.residual / self.impulse_sum,
                        false => 0.0,
                    }
                }
            }
        }
    };
}

rapier_backend!(B2_F32, rapier2d_f32, "2D f32", F32, kimpact2d, 2);
rapier_backend!(B3_F32, rapier3d_f32, "3D f32", F32, kimpact3d, 3);
rapier_backend!(B2_F64, rapier2d_f64, "2D f64", F64, kimpact2d_f64, 2);
rapier_backend!(B3_F64, rapier3d_f64, "3D f64", F64, kimpact3d_f64, 3);
