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

/// The rapier side, written once for the four adapter builds.
macro_rules! rapier_backend {
    ($module:ident, $krate:ident, $dim:literal) => {
        mod $module {
            use std::collections::{HashMap, HashSet};
            use std::time::Instant;

            use crate::{HarnessError, Setup, Sim, State, Totals, V};
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
                mode: Mode,
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

            /// This build of rapier on `setup`, with kimpact in `mode`.
            pub fn make(setup: &Setup<D>, mode: Mode) -> Result<Box<dyn Sim<D>>, HarnessError> {
                Ok(Box::new(World::new(setup, mode)?))
            }

            impl World {
                fn new(setup: &Setup<D>, mode: Mode) -> Result<Self, HarnessError> {
                    let mut world = PhysicsWorld::new();
                    world.gravity = Vector::ZERO;
                    world.integration_parameters.dt = setup.dt as Real;
                    let law = Law::new(LawParams {
                        dissipation: setup.dissipation as Real,
                        ..Default::default()
                    })?;
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
                                let he = k::rapier::parry::shape::Cuboid::new(to_rapier(&he));
                                let collider = ColliderBuilder::new(SharedShape::new(he))
                                    .friction(0.0)
                                    .restitution(e_wall as Real);
                                let handle = world.insert_collider(collider, Some(body));
                                walls.push((handle, axis, side));
                                wall_of.insert(handle, (axis, side));
                            }
                        }
                    }
                    let balls: Result<Vec<_>, HarnessError> = setup
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
                            kimpact
                                .mark(&world.colliders, c)
                                .map_err(|e| HarnessError::Mark(e.to_string()))?;
                            Ok(handle)
                        })
                        .collect();
                    let balls = balls?;
                    let dt = f64::from(world.integration_parameters.dt);
                    Ok(Self {
                        world,
                        kimpact,
                        mode,
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
                    })
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
                    match self.mode {
                        Mode::Native => {
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
                        Mode::Restitution | Mode::Impulse | Mode::Exact => {
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

/// The kimpact2d (2D, f32) build of the adapter.
pub const B2_F32: Backend<2> = Backend {
    label: "2D f32",
    precision: Precision::F32,
    make: rapier2d_f32::make,
};
/// The kimpact3d (3D, f32) build of the adapter.
pub const B3_F32: Backend<3> = Backend {
    label: "3D f32",
    precision: Precision::F32,
    make: rapier3d_f32::make,
};
/// The kimpact2d-f64 (2D, f64) build of the adapter.
pub const B2_F64: Backend<2> = Backend {
    label: "2D f64",
    precision: Precision::F64,
    make: rapier2d_f64::make,
};
/// The kimpact3d-f64 (3D, f64) build of the adapter.
pub const B3_F64: Backend<3> = Backend {
    label: "3D f64",
    precision: Precision::F64,
    make: rapier3d_f64::make,
};
