//! The test app: a headless bevy_rapier app with kimpact (or without),
//! its timestep modes, the user's hooks, and the bodies and scenes the
//! tests spawn (a ball, a wall, a closed box, Newton's cradle, a gas).
//! Every test of the plugins builds its app here.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use bevy::ecs::message::Messages;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;

use crate::bk;
use crate::bk::bevy_rapier::pipeline::{ContactModificationContextView, PairFilterContextView};
use crate::bk::bevy_rapier::prelude::*;
use crate::bk::prelude::*;

pub type Vect = bk::bevy_rapier::math::Vect;

pub const DT: f32 = 1.0 / 60.0;

#[cfg(feature = "dim2")]
pub fn vect(x: f32, y: f32, _z: f32) -> Vect {
    Vect::new(x, y)
}
#[cfg(feature = "dim3")]
pub fn vect(x: f32, y: f32, z: f32) -> Vect {
    Vect::new(x, y, z)
}
#[cfg(feature = "dim2")]
pub fn cuboid(h: Vect) -> Collider {
    Collider::cuboid(h.x, h.y)
}
#[cfg(feature = "dim3")]
pub fn cuboid(h: Vect) -> Collider {
    Collider::cuboid(h.x, h.y, h.z)
}
#[cfg(feature = "dim2")]
pub fn at(p: Vect) -> Transform {
    Transform::from_translation(p.extend(0.0))
}
#[cfg(feature = "dim3")]
pub fn at(p: Vect) -> Transform {
    Transform::from_translation(p)
}
#[cfg(feature = "dim2")]
pub const DIM: usize = 2;
#[cfg(feature = "dim3")]
pub const DIM: usize = 3;

/// When bevy_rapier steps (frames of 1/60 s).
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Timing {
    /// `TimestepMode::Fixed` (dt = 1/60, this many substeps) in `PostUpdate`.
    Fixed(usize),
    /// `TimestepMode::Variable` (max_dt = 1/60, this many substeps) in
    /// `PostUpdate`.
    Variable(usize),
    /// `TimestepMode::Interpolated` in `PostUpdate`: rounds of dt =
    /// 1/60 / `rounds` (so `rounds` of them a frame on average), of `substeps`
    /// steps each; the bodies carry `TransformInterpolation`.
    Interpolated { rounds: f32, substeps: usize },
    /// bevy_rapier and kimpact in `FixedUpdate` at 60 Hz, `TimestepMode::Fixed`
    /// with this many substeps.
    FixedUpdate(usize),
}

impl Timing {
    fn timestep_mode(self) -> TimestepMode {
        match self {
            Timing::Fixed(substeps) | Timing::FixedUpdate(substeps) => {
                TimestepMode::Fixed { dt: DT, substeps }
            }
            Timing::Variable(substeps) => TimestepMode::Variable {
                max_dt: DT,
                time_scale: 1.0,
                substeps,
            },
            Timing::Interpolated { rounds, substeps } => TimestepMode::Interpolated {
                dt: DT / rounds,
                time_scale: 1.0,
                substeps,
            },
        }
    }
}

/// A user's hooks: count the `modify_solver_contacts` calls for colliders
/// they flagged, and let ghosts (flagged `FILTER_CONTACT_PAIRS`) touch
/// nothing.
#[derive(Resource, Default, Clone)]
struct UserCalls(Arc<AtomicUsize>);

#[derive(Component)]
pub struct Ghost;

#[derive(SystemParam)]
struct UserHooks<'w, 's> {
    calls: Res<'w, UserCalls>,
    ghosts: Query<'w, 's, (), With<Ghost>>,
}

impl BevyPhysicsHooks for UserHooks<'_, '_> {
    fn filter_contact_pair(&self, context: PairFilterContextView) -> Option<SolverFlags> {
        let ghost = |e| self.ghosts.contains(e);
        if ghost(context.collider1()) || ghost(context.collider2()) {
            None
        } else {
            Some(SolverFlags::COMPUTE_RIGID_IMPULSES)
        }
    }

    fn modify_solver_contacts(&self, _context: ContactModificationContextView) {
        self.calls.0.fetch_add(1, Ordering::Relaxed);
    }
}

/// How bevy_rapier is added beside (or instead of) kimpact.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Rapier {
    /// `KimpactPlugin` adds it (the drop-in).
    ByKimpact,
    /// No kimpact: `RapierPhysicsPlugin::<NoUserData>` alone.
    Alone,
    /// The user's `RapierPhysicsPlugin::<NoUserData>` added before
    /// `KimpactPlugin` (a mistake kimpact tells and stands aside from).
    AlsoBefore,
    /// bevy_rapier's own step system added by hand beside kimpact's (the
    /// same mistake, found when the app is finished).
    OwnStepByHand,
}

/// A headless test app without gravity: `MinimalPlugins`, bevy_rapier and
/// kimpact, in exact mode with `TimestepMode::Fixed` of 1/60 in
/// `PostUpdate` unless a test says otherwise.
#[derive(Clone)]
pub struct Setup {
    settings: KimpactSettings,
    timing: Timing,
    rapier: Rapier,
    user_hooks: bool,
}

impl Setup {
    pub fn new() -> Self {
        Self {
            settings: KimpactSettings::default(),
            timing: Timing::Fixed(1),
            rapier: Rapier::ByKimpact,
            user_hooks: false,
        }
    }

    /// The same app without kimpact.
    pub fn without_kimpact() -> Self {
        Self::new().rapier(Rapier::Alone)
    }

    pub fn mode(mut self, mode: Mode) -> Self {
        self.settings.mode = mode;
        self
    }

    pub fn law(mut self, law: LawParams<f32>) -> Self {
        self.settings.law = law;
        self
    }

    pub fn timing(mut self, timing: Timing) -> Self {
        self.timing = timing;
        self
    }

    pub fn rapier(mut self, rapier: Rapier) -> Self {
        self.rapier = rapier;
        self
    }

    /// With the user's hooks ([`UserHooks`]).
    pub fn user_hooks(mut self) -> Self {
        self.user_hooks = true;
        self
    }

    pub fn build(&self) -> Test {
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, TransformPlugin))
            .init_resource::<UserCalls>();
        let init = RapierContextInitialization::InitializeDefaultRapierContext {
            integration_parameters: Default::default(),
            rapier_configuration: RapierConfiguration {
                gravity: Vect::ZERO,
                ..RapierConfiguration::new(1.0)
            },
            broad_phase_optimization_strategy: Default::default(),
        };
        let fixed = matches!(self.timing, Timing::FixedUpdate(_));
        let kimpact = KimpactPlugin::default();
        let kimpact = if fixed {
            kimpact.in_fixed_schedule()
        } else {
            kimpact
        };
        let plain = || {
            let rapier = RapierPhysicsPlugin::<NoUserData>::default()
                .with_custom_initialization(init.clone());
            if fixed {
                rapier.in_fixed_schedule()
            } else {
                rapier
            }
        };
        match (self.rapier, self.user_hooks) {
            (Rapier::ByKimpact, false) => {
                let init = init.clone();
                app.add_plugins(
                    kimpact.with_rapier(move |r| r.with_custom_initialization(init.clone())),
                );
            }
            (Rapier::ByKimpact, true) => {
                let init = init.clone();
                app.add_plugins(
                    kimpact
                        .with_hooks::<UserHooks>()
                        .with_rapier(move |r| r.with_custom_initialization(init.clone())),
                );
            }
            (Rapier::Alone, _) => {
                app.add_plugins(plain());
            }
            (Rapier::AlsoBefore, _) => {
                app.add_plugins((plain(), kimpact));
            }
            (Rapier::OwnStepByHand, _) => {
                let schedule = if fixed {
                    FixedUpdate.intern()
                } else {
                    PostUpdate.intern()
                };
                let init = init.clone();
                app.add_plugins(
                    kimpact.with_rapier(move |r| r.with_custom_initialization(init.clone())),
                )
                .add_systems(
                    schedule,
                    RapierPhysicsPlugin::<NoUserData>::get_systems(PhysicsSet::StepSimulation),
                );
            }
        }
        if self.rapier != Rapier::Alone {
            app.insert_resource(self.settings.clone());
        }
        if fixed {
            app.insert_resource(Time::<Fixed>::from_hz(60.0));
        }
        let frame = if fixed {
            Duration::from_secs_f64(1.0 / 60.0)
        } else {
            Duration::from_secs_f32(DT)
        };
        app.insert_resource(TimeUpdateStrategy::ManualDuration(frame))
            .insert_resource(self.timing.timestep_mode());
        app.finish();
        Test {
            app,
            timing: self.timing,
        }
    }
}

/// A test app, with the bodies' helpers.
pub struct Test {
    pub app: App,
    timing: Timing,
}

/// A frictionless elastic (for rapier) ball that never sleeps.
#[derive(Copy, Clone, Debug)]
pub struct Ball {
    p: Vect,
    v: Vect,
    r: f32,
    mass: f32,
    marked: bool,
}

impl Ball {
    /// A marked ball of radius 0.5 and mass 1 at `p`, moving at `v`.
    pub fn at(p: Vect, v: Vect) -> Self {
        Self {
            p,
            v,
            r: 0.5,
            mass: 1.0,
            marked: true,
        }
    }

    pub fn unmarked(self) -> Self {
        Self {
            marked: false,
            ..self
        }
    }
}

impl Test {
    pub fn spawn(&mut self, b: Ball) -> Entity {
        let interpolated = matches!(self.timing, Timing::Interpolated { .. });
        let mut e = self.app.world_mut().spawn((
            RigidBody::Dynamic,
            Collider::ball(b.r),
            ColliderMassProperties::Mass(b.mass),
            Restitution::coefficient(1.0),
            Friction::coefficient(0.0),
            Velocity::linear(b.v),
            Sleeping::disabled(),
            ActiveEvents::COLLISION_EVENTS,
            at(b.p),
        ));
        if b.marked {
            e.insert(KimpactCollider::default());
        }
        if interpolated {
            e.insert(TransformInterpolation::default());
        }
        e.id()
    }

    /// A marked ball of radius 0.5 and mass 1.
    pub fn ball(&mut self, p: Vect, v: Vect) -> Entity {
        self.spawn(Ball::at(p, v))
    }

    /// A fixed frictionless wall (unmarked: walls meet the law as fixed
    /// partners).
    pub fn wall(&mut self, center: Vect, half: Vect) -> Entity {
        self.app
            .world_mut()
            .spawn((
                RigidBody::Fixed,
                cuboid(half),
                Restitution::coefficient(1.0),
                Friction::coefficient(0.0),
                at(center),
            ))
            .id()
    }

    /// A closed box of inner half-size `half` around the origin.
    pub fn closed_box(&mut self, half: f32) {
        let t = 1.0;
        for axis in 0..DIM {
            for sign in [-1.0, 1.0] {
                let mut center = Vect::ZERO;
                center[axis] = sign * (half + t);
                let mut h = Vect::splat(half + 2.0 * t);
                h[axis] = t;
                self.wall(center, h);
            }
        }
    }

    pub fn vel(&self, e: Entity) -> Vect {
        self.app.world().get::<Velocity>(e).expect("a body").linear
    }

    pub fn pos(&self, e: Entity) -> Vect {
        let t = self
            .app
            .world()
            .get::<Transform>(e)
            .expect("a body")
            .translation;
        #[cfg(feature = "dim2")]
        return t.truncate();
        #[cfg(feature = "dim3")]
        return t;
    }

    pub fn kinetic(&self, balls: &[(Entity, f32)]) -> f64 {
        balls
            .iter()
            .map(|&(e, m)| 0.5 * f64::from(m) * f64::from(self.vel(e).length_squared()))
            .sum()
    }

    pub fn state(&self) -> &KimpactState {
        self.app.world().resource::<KimpactState>()
    }

    pub fn user_calls(&self) -> usize {
        self.app
            .world()
            .resource::<UserCalls>()
            .0
            .load(Ordering::Relaxed)
    }

    /// Run `frames` updates, collecting the impact messages.
    pub fn run(&mut self, frames: usize) -> Vec<ImpactMessage> {
        self.run_with_collisions(frames).0
    }

    /// Run `frames` updates, collecting the impact messages and bevy_rapier's
    /// collision events.
    pub fn run_with_collisions(
        &mut self,
        frames: usize,
    ) -> (Vec<ImpactMessage>, Vec<CollisionEvent>) {
        let mut impacts = Vec::new();
        let mut collisions = Vec::new();
        for _ in 0..frames {
            self.app.update();
            let world = self.app.world_mut();
            if let Some(mut messages) = world.get_resource_mut::<Messages<ImpactMessage>>() {
                impacts.extend(messages.drain());
            }
            if let Some(mut messages) = world.get_resource_mut::<Messages<CollisionEvent>>() {
                collisions.extend(messages.drain());
            }
        }
        (impacts, collisions)
    }
}

/// Newton's cradle: five touching balls and one incoming at 1 m/s, elastic.
pub struct Cradle {
    pub test: Test,
    pub balls: Vec<Entity>,
    pub e0: f64,
    pub e1: f64,
    pub messages: Vec<ImpactMessage>,
}

pub const CRADLE_FRAMES: usize = 40;

pub fn cradle(setup: Setup) -> Cradle {
    let mut test = setup.build();
    let r = 0.5;
    let mut balls = vec![test.ball(vect(-(2.0 * r + 3.5 * DT), 0.0, 0.0), vect(1.0, 0.0, 0.0))];
    for i in 0..5 {
        balls.push(test.ball(vect(2.0 * r * i as f32, 0.0, 0.0), Vect::ZERO));
    }
    let masses: Vec<_> = balls.iter().map(|&e| (e, 1.0)).collect();
    test.app.update();
    let e0 = test.kinetic(&masses);
    let messages = test.run(CRADLE_FRAMES);
    let e1 = test.kinetic(&masses);
    Cradle {
        test,
        balls,
        e0,
        e1,
        messages,
    }
}

/// A gas of `n` balls (restitution 1, no friction) in a closed box; the
/// balls and their masses.
pub fn gas(test: &mut Test, n: usize) -> Vec<(Entity, f32)> {
    let half = 5.0;
    test.closed_box(half);
    let per_row = if DIM == 2 { 10 } else { 5 };
    let spacing = if DIM == 2 { 0.9 } else { 1.5 };
    let mut balls = Vec::new();
    for i in 0..n {
        let (a, b, c) = (
            i % per_row,
            (i / per_row) % per_row,
            i / (per_row * per_row),
        );
        let offset = -spacing * (per_row as f32 - 1.0) / 2.0;
        let p = vect(
            offset + spacing * a as f32,
            offset + spacing * b as f32,
            offset + spacing * c as f32,
        );
        let v = vect(
            ((i * 7 % 11) as f32 - 5.0) * 0.6,
            ((i * 5 % 13) as f32 - 6.0) * 0.5,
            ((i * 3 % 7) as f32 - 3.0) * 0.6,
        );
        let mass = 1.0 + (i % 3) as f32;
        let ball = Ball {
            r: 0.3,
            mass,
            ..Ball::at(p, v)
        };
        balls.push((test.spawn(ball), mass));
    }
    balls
}
