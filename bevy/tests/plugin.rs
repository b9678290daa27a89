//! The plugin in headless bevy_rapier apps, written once for 2D and 3D
//! (compiled by bevy_kimpact2d and bevy_kimpact3d).

#[cfg(feature = "dim2")]
use bevy_kimpact2d as bk;
#[cfg(feature = "dim3")]
use bevy_kimpact3d as bk;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use bevy::ecs::message::Messages;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bk::bevy_rapier::pipeline::{ContactModificationContextView, PairFilterContextView};
use bk::bevy_rapier::prelude::*;
use bk::prelude::*;

type Vect = bk::bevy_rapier::math::Vect;

const DT: f32 = 1.0 / 60.0;

#[cfg(feature = "dim2")]
fn vect(x: f32, y: f32, _z: f32) -> Vect {
    Vect::new(x, y)
}
#[cfg(feature = "dim3")]
fn vect(x: f32, y: f32, z: f32) -> Vect {
    Vect::new(x, y, z)
}
#[cfg(feature = "dim2")]
fn cuboid(h: Vect) -> Collider {
    Collider::cuboid(h.x, h.y)
}
#[cfg(feature = "dim3")]
fn cuboid(h: Vect) -> Collider {
    Collider::cuboid(h.x, h.y, h.z)
}
#[cfg(feature = "dim2")]
fn at(p: Vect) -> Transform {
    Transform::from_translation(p.extend(0.0))
}
#[cfg(feature = "dim3")]
fn at(p: Vect) -> Transform {
    Transform::from_translation(p)
}
#[cfg(feature = "dim2")]
const DIM: usize = 2;
#[cfg(feature = "dim3")]
const DIM: usize = 3;

/// When bevy_rapier steps (frames of 1/60 s).
#[derive(Copy, Clone, Debug, PartialEq)]
enum Timing {
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
struct Ghost;

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
enum Rapier {
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
struct Setup {
    settings: KimpactSettings,
    timing: Timing,
    rapier: Rapier,
    user_hooks: bool,
}

impl Setup {
    fn new() -> Self {
        Self {
            settings: KimpactSettings::default(),
            timing: Timing::Fixed(1),
            rapier: Rapier::ByKimpact,
            user_hooks: false,
        }
    }

    /// The same app without kimpact.
    fn without_kimpact() -> Self {
        Self::new().rapier(Rapier::Alone)
    }

    fn mode(mut self, mode: Mode) -> Self {
        self.settings.mode = mode;
        self
    }

    fn law(mut self, law: LawParams<f32>) -> Self {
        self.settings.law = law;
        self
    }

    fn timing(mut self, timing: Timing) -> Self {
        self.timing = timing;
        self
    }

    fn rapier(mut self, rapier: Rapier) -> Self {
        self.rapier = rapier;
        self
    }

    /// With the user's hooks ([`UserHooks`]).
    fn user_hooks(mut self) -> Self {
        self.user_hooks = true;
        self
    }

    fn build(&self) -> Test {
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
struct Test {
    app: App,
    timing: Timing,
}

/// A frictionless elastic (for rapier) ball that never sleeps.
#[derive(Copy, Clone, Debug)]
struct Ball {
    p: Vect,
    v: Vect,
    r: f32,
    mass: f32,
    marked: bool,
}

impl Ball {
    /// A marked ball of radius 0.5 and mass 1 at `p`, moving at `v`.
    fn at(p: Vect, v: Vect) -> Self {
        Self {
            p,
            v,
            r: 0.5,
            mass: 1.0,
            marked: true,
        }
    }

    fn unmarked(self) -> Self {
        Self {
            marked: false,
            ..self
        }
    }
}

impl Test {
    fn spawn(&mut self, b: Ball) -> Entity {
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
    fn ball(&mut self, p: Vect, v: Vect) -> Entity {
        self.spawn(Ball::at(p, v))
    }

    /// A fixed frictionless wall (unmarked: walls meet the law as fixed
    /// partners).
    fn wall(&mut self, center: Vect, half: Vect) -> Entity {
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
    fn closed_box(&mut self, half: f32) {
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

    fn vel(&self, e: Entity) -> Vect {
        self.app.world().get::<Velocity>(e).expect("a body").linear
    }

    fn pos(&self, e: Entity) -> Vect {
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

    fn kinetic(&self, balls: &[(Entity, f32)]) -> f64 {
        balls
            .iter()
            .map(|&(e, m)| 0.5 * f64::from(m) * f64::from(self.vel(e).length_squared()))
            .sum()
    }

    fn state(&self) -> &KimpactState {
        self.app.world().resource::<KimpactState>()
    }

    fn user_calls(&self) -> usize {
        self.app
            .world()
            .resource::<UserCalls>()
            .0
            .load(Ordering::Relaxed)
    }

    /// Run `frames` updates, collecting the impact messages.
    fn run(&mut self, frames: usize) -> Vec<ImpactMessage> {
        self.run_with_collisions(frames).0
    }

    /// Run `frames` updates, collecting the impact messages and bevy_rapier's
    /// collision events.
    fn run_with_collisions(&mut self, frames: usize) -> (Vec<ImpactMessage>, Vec<CollisionEvent>) {
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
struct Cradle {
    test: Test,
    balls: Vec<Entity>,
    e0: f64,
    e1: f64,
    messages: Vec<ImpactMessage>,
}

const CRADLE_FRAMES: usize = 40;

fn cradle(setup: Setup) -> Cradle {
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

/// The cradle's law result: (0, 0, 0, 0, 0, 1) to 1e-5, its energy kept
/// to 1e-5, one impact message per touching pair, in order down the row.
fn assert_law_cradle(c: &Cradle, timing: Timing) {
    for (i, &b) in c.balls.iter().enumerate() {
        let expect = if i == 5 { 1.0 } else { 0.0 };
        let v = c.test.vel(b);
        assert!(
            (v - vect(expect, 0.0, 0.0)).length() < 1e-5,
            "{timing:?}: ball {i} has {v:?}"
        );
    }
    assert!(
        ((c.e1 - c.e0) / c.e0).abs() < 1e-5,
        "{timing:?}: energy {} -> {}",
        c.e0,
        c.e1
    );
    let pairs: Vec<_> = c
        .messages
        .iter()
        .map(|m| {
            let i = c.balls.iter().position(|&b| b == m.collider1).unwrap();
            let j = c.balls.iter().position(|&b| b == m.collider2).unwrap();
            (i.min(j), i.max(j))
        })
        .collect();
    assert_eq!(
        pairs,
        [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)],
        "{timing:?}"
    );
    assert_eq!(c.test.state().stats().impacts, 5, "{timing:?}");
}

#[test]
fn exact_newtons_cradle_passes_the_velocity_down_the_row() {
    for timing in [
        Timing::Fixed(1),
        Timing::Variable(1),
        Timing::FixedUpdate(1),
        Timing::Interpolated {
            rounds: 1.0,
            substeps: 1,
        },
    ] {
        let c = cradle(Setup::new().timing(timing));
        assert_law_cradle(&c, timing);
    }
}

#[test]
fn every_step_of_a_frame_of_several_follows_the_law() {
    // Substeps, and rounds of `Interpolated` (two or three a frame).
    let timings = [
        Timing::Fixed(3),
        Timing::Variable(3),
        Timing::FixedUpdate(2),
        Timing::Interpolated {
            rounds: 2.5,
            substeps: 1,
        },
        Timing::Interpolated {
            rounds: 3.0,
            substeps: 2,
        },
    ];
    for timing in timings {
        let c = cradle(Setup::new().timing(timing));
        assert_law_cradle(&c, timing);
        // kimpact's stages ran around every pipeline step: the frames of the
        // run (the first update and the cradle's) at the steps per frame.
        let steps = c.test.state().stats().steps;
        let frames = CRADLE_FRAMES as u64 + 1;
        let expect = match timing {
            Timing::Fixed(n) => frames * n as u64,
            // Variable's first frame has no time (no step).
            Timing::Variable(n) => (frames - 1) * n as u64,
            // One fixed tick a frame but the first.
            Timing::FixedUpdate(n) => (frames - 1) * n as u64,
            Timing::Interpolated { rounds, substeps } => {
                ((frames - 1) as f32 * rounds).round() as u64 * substeps as u64
            }
        };
        // Interpolated's rounds follow the render by float sums: one round
        // more or less.
        let slack = match timing {
            Timing::Interpolated { substeps, .. } => substeps as u64,
            _ => 0,
        };
        assert!(
            steps.abs_diff(expect) <= slack,
            "{timing:?}: {steps} steps through kimpact, {expect} expected"
        );
    }
}

/// A gas of `n` balls (restitution 1, no friction) in a closed box; the
/// balls and their masses.
fn gas(test: &mut Test, n: usize) -> Vec<(Entity, f32)> {
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

/// The gas in exact mode for `frames`: its energy kept to 1e-5, one message
/// per impact, no ball out of the box.
fn assert_gas_keeps_its_energy(timing: Timing, frames: usize) {
    let mut test = Setup::new().timing(timing).build();
    let balls = gas(&mut test, 100);
    test.app.update();
    let e0 = test.kinetic(&balls);
    let messages = test.run(frames);
    let e1 = test.kinetic(&balls);
    let stats = test.state().stats();
    eprintln!(
        "gas {DIM}D {timing:?}: {} steps, {} impacts, energy {e0} -> {e1} ({:.2e})",
        stats.steps,
        stats.impacts,
        (e1 - e0) / e0
    );
    assert!(
        stats.impacts > 500,
        "{timing:?}: only {} impacts",
        stats.impacts
    );
    assert_eq!(
        messages.len() as u64,
        stats.impacts,
        "one message per impact"
    );
    assert!(
        ((e1 - e0) / e0).abs() < 1e-5,
        "{timing:?}: energy {e0} -> {e1}"
    );
    for &(b, _) in &balls {
        let p = test.pos(b);
        assert!(p.abs().max_element() < 5.0, "{b} escaped to {p:?}");
    }
}

#[test]
fn an_elastic_gas_keeps_its_energy_in_exact_mode() {
    assert_gas_keeps_its_energy(Timing::Fixed(1), 600);
}

#[test]
fn an_elastic_gas_keeps_its_energy_over_substeps() {
    // The same 10 s, in steps of half the frame.
    assert_gas_keeps_its_energy(Timing::Fixed(2), 600);
    assert_gas_keeps_its_energy(Timing::Variable(2), 600);
}

/// Bits of every ball's position, rotation and velocity after `frames` (and
/// of the context's dt and time behind the render), and bevy_rapier's
/// collision events.
fn gas_bits(setup: Setup, frames: usize) -> (Vec<u32>, Vec<CollisionEvent>) {
    let mut test = setup.build();
    let balls = gas(&mut test, 100);
    let (_, collisions) = test.run_with_collisions(frames);
    let world = test.app.world_mut();
    let (simulation, to_render) = world
        .query::<(&RapierContextSimulation, &SimulationToRenderTime)>()
        .single(world)
        .expect("one context");
    let mut bits = vec![
        simulation.integration_parameters.dt.to_bits(),
        to_render.diff.to_bits(),
    ];
    for &(b, _) in &balls {
        let world = test.app.world();
        let t = world.get::<Transform>(b).unwrap();
        let v = world.get::<Velocity>(b).unwrap();
        bits.extend(t.translation.to_array().map(f32::to_bits));
        bits.extend(t.rotation.to_array().map(f32::to_bits));
        bits.extend(v.linear.to_array().map(f32::to_bits));
        #[cfg(feature = "dim2")]
        bits.push(v.angular.to_bits());
        #[cfg(feature = "dim3")]
        bits.extend(v.angular.to_array().map(f32::to_bits));
    }
    (bits, collisions)
}

#[test]
fn native_mode_leaves_bevy_rapier_unchanged_bit_for_bit() {
    // kimpact's step system runs bevy_rapier's steps one by one: the same
    // bodies (interpolated ones too) and collision events as bevy_rapier's
    // own step system, in every timestep mode. The reference is the same
    // app with bevy_rapier's own step (kimpact standing aside): bevy_rapier's
    // results change by rounding with the app's archetypes (one more
    // resource is enough), so the two apps have the same plugins.
    let timings = [
        Timing::Fixed(1),
        Timing::Fixed(3),
        Timing::Variable(2),
        Timing::Interpolated {
            rounds: 2.5,
            substeps: 2,
        },
        Timing::FixedUpdate(2),
    ];
    for timing in timings {
        let rapiers = gas_bits(Setup::new().rapier(Rapier::AlsoBefore).timing(timing), 200);
        assert!(!rapiers.1.is_empty(), "{timing:?}: no collision event");
        let native = gas_bits(Setup::new().mode(Mode::Native).timing(timing), 200);
        assert!(native.0 == rapiers.0, "{timing:?}: the bodies differ");
        assert_eq!(
            native.1, rapiers.1,
            "{timing:?}: the collision events differ"
        );
        // The comparison can tell: kimpact's law changes this scene.
        if timing == Timing::Fixed(1) {
            assert_ne!(gas_bits(Setup::new().timing(timing), 200).0, rapiers.0);
        }
    }
}

#[test]
fn a_rapier_plugin_beside_kimpacts_makes_kimpact_stand_aside() {
    // A user's RapierPhysicsPlugin added before KimpactPlugin (which adds
    // its own), or bevy_rapier's step system added by hand: kimpact logs an
    // error and steps nothing, bevy_rapier runs as without it (not twice:
    // the same bodies to rounding, see the native test).
    let without = cradle(Setup::without_kimpact());
    for rapier in [Rapier::AlsoBefore, Rapier::OwnStepByHand] {
        let c = cradle(Setup::new().rapier(rapier));
        assert!(c.messages.is_empty(), "{rapier:?}: {:?}", c.messages);
        let state = c.test.state();
        assert_eq!(state.stats().steps, 0, "{rapier:?}");
        assert!(!state.is_marked(c.balls[0]), "{rapier:?}");
        for (&b, &w) in c.balls.iter().zip(&without.balls) {
            let (p, pw) = (c.test.pos(b), without.test.pos(w));
            let (v, vw) = (c.test.vel(b), without.test.vel(w));
            assert!((p - pw).length() < 1e-5, "{rapier:?}: {p:?} vs {pw:?}");
            assert!((v - vw).length() < 1e-5, "{rapier:?}: {v:?} vs {vw:?}");
        }
        // rapier's own cradle does not pass the velocity down the row.
        assert!(c.test.vel(c.balls[5]).x < 0.9, "{rapier:?}");
    }
}

#[test]
fn impact_messages_name_the_colliders_and_bodies() {
    let mut test = Setup::new().build();
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(2.0, 0.0, 0.0));
    let b = test.ball(vect(1.5, 0.0, 0.0), Vect::ZERO);
    let w = test.wall(vect(3.5, 0.0, 0.0), vect(0.5, 2.0, 2.0));
    // An unmarked pair meets too: rapier's, no message.
    let c = test.spawn(Ball::at(vect(0.0, 5.0, 0.0), vect(2.0, 0.0, 0.0)).unmarked());
    let d = test.spawn(Ball::at(vect(1.5, 5.0, 0.0), Vect::ZERO).unmarked());
    let messages = test.run(120);
    let named: Vec<_> = messages
        .iter()
        .map(|m| {
            assert_eq!(m.body1, Some(m.collider1), "the collider is on its body");
            assert_eq!(m.body2, Some(m.collider2));
            (m.collider1, m.collider2)
        })
        .collect();
    // a hits b, b the wall, b comes back to hit a.
    assert!(named.len() >= 3, "{named:?}");
    let same = |x: (Entity, Entity), y: (Entity, Entity)| x == y || x == (y.1, y.0);
    assert!(same(named[0], (a, b)), "{named:?}");
    assert!(same(named[1], (b, w)), "{named:?}");
    assert!(same(named[2], (a, b)), "{named:?}");
    for m in &messages {
        assert!(![c, d].contains(&m.collider1) && ![c, d].contains(&m.collider2));
    }
    // The normal points from collider 1 towards collider 2.
    let first = &messages[0];
    let towards = if first.collider1 == a { 1.0 } else { -1.0 };
    assert!((first.impact.normal.x - towards).abs() < 1e-5, "{first:?}");
    assert!(
        (first.impact.approach_speed - 2.0).abs() < 1e-5,
        "{first:?}"
    );
    // The unmarked pair did collide (rapier's response).
    assert!(test.vel(d).x > 1.0, "{:?}", test.vel(d));
}

#[test]
fn despawning_marked_balls_mid_run_keeps_the_others_impacts() {
    let mut test = Setup::new().build();
    let balls = gas(&mut test, 100);
    test.run(100);
    let gone: Vec<_> = balls.iter().step_by(10).map(|&(e, _)| e).collect();
    for &e in &gone {
        test.app.world_mut().despawn(e);
    }
    let rest: Vec<_> = balls
        .iter()
        .copied()
        .filter(|(e, _)| !gone.contains(e))
        .collect();
    let e0 = test.kinetic(&rest);
    let messages = test.run(300);
    let e1 = test.kinetic(&rest);
    let state = test.state();
    assert_eq!(state.marked_count(), 90);
    assert!(gone.iter().all(|&e| !state.is_marked(e)));
    assert!(messages.len() > 100, "only {} impacts", messages.len());
    for m in &messages {
        assert!(
            !gone.contains(&m.collider1) && !gone.contains(&m.collider2),
            "{m:?}"
        );
    }
    assert!(((e1 - e0) / e0).abs() < 1e-5, "energy {e0} -> {e1}");
}

#[test]
fn removing_the_component_hands_the_collider_back_to_rapier() {
    // A lossy law (rapier's restitution is 1): kimpact's impacts are told
    // apart by the speed they leave.
    let lossy = LawParams {
        dissipation: 0.2,
        ..Default::default()
    };
    let speed_after = |unmark: bool| {
        let mut test = Setup::new().law(lossy).build();
        let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
        let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
        test.run(3);
        assert!(test.state().is_marked(b));
        if unmark {
            test.app
                .world_mut()
                .entity_mut(b)
                .remove::<KimpactCollider>();
        }
        let messages = test.run(30);
        assert_eq!(test.state().is_marked(b), !unmark);
        (messages.len(), test.vel(a).x + test.vel(b).x, test.vel(b).x)
    };
    let (n_law, momentum_law, b_law) = speed_after(false);
    let (n_rapier, momentum_rapier, b_rapier) = speed_after(true);
    assert_eq!(n_law, 1);
    assert_eq!(n_rapier, 0, "an unmarked pair sends no message");
    assert!((momentum_law - 1.0).abs() < 1e-5 && (momentum_rapier - 1.0).abs() < 1e-3);
    assert!(
        b_rapier > b_law + 0.02,
        "rapier's {b_rapier} vs the law's {b_law}"
    );
}

#[test]
fn settings_change_at_run_time_and_an_invalid_law_is_refused() {
    let mut test = Setup::new().build();
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    // A second pair, meeting after the switch to native mode.
    test.ball(vect(0.0, 4.0, 0.0), vect(1.0, 0.0, 0.0));
    let d = test.ball(vect(3.0, 4.0, 0.0), Vect::ZERO);
    test.run(2);
    test.app
        .world_mut()
        .resource_mut::<KimpactSettings>()
        .law
        .dissipation = -1.0;
    let messages = test.run(30);
    assert_eq!(test.state().law().dissipation(), 0.0, "the valid law stays");
    assert_eq!(messages.len(), 1, "a and b meet under the elastic law");
    assert!((test.vel(b).x - 1.0).abs() < 1e-5 && test.vel(a).x.abs() < 1e-5);
    test.app.world_mut().resource_mut::<KimpactSettings>().mode = Mode::Native;
    let messages = test.run(150);
    assert_eq!(test.state().mode(), Mode::Native);
    assert!(messages.is_empty(), "native mode sends none: {messages:?}");
    assert!(
        test.vel(d).x > 0.5,
        "the second pair met (rapier's): {:?}",
        test.vel(d)
    );
}

#[test]
fn the_users_hooks_are_chained() {
    let mut test = Setup::new().user_hooks().build();
    // The user's flag on an unmarked ball hitting a wall, and on a marked
    // one: the user's hook runs for both, and the law still takes the
    // marked pair.
    let u = test.spawn(Ball::at(vect(0.0, 4.0, 0.0), vect(2.0, 0.0, 0.0)).unmarked());
    test.app
        .world_mut()
        .entity_mut(u)
        .insert(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    test.wall(vect(2.5, 4.0, 0.0), vect(0.5, 1.0, 1.0));
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    test.app
        .world_mut()
        .entity_mut(a)
        .insert(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    let messages = test.run(80);
    assert!(test.user_calls() > 0, "the user's hook never ran");
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!((test.vel(b).x - 1.0).abs() < 1e-5 && test.vel(a).x.abs() < 1e-5);
    assert!(test.vel(u).x < 0.0, "u bounced off the wall");
}

#[test]
fn the_users_contact_filter_decides_marked_and_unmarked_pairs() {
    // Ghosts (the user's filter_contact_pair) pass through a marked ball
    // and an unmarked one; the same pairs without the ghost meet (by the law
    // and by rapier), in every timestep mode.
    for timing in [
        Timing::Fixed(1),
        Timing::Variable(2),
        Timing::Interpolated {
            rounds: 2.0,
            substeps: 1,
        },
    ] {
        let mut test = Setup::new().user_hooks().timing(timing).build();
        let mut pairs = Vec::new();
        for (row, (marked, ghost)) in [(true, true), (false, true), (true, false), (false, false)]
            .into_iter()
            .enumerate()
        {
            let y = 3.0 * row as f32;
            let mut first = Ball::at(vect(0.0, y, 0.0), vect(1.0, 0.0, 0.0));
            let mut second = Ball::at(vect(1.3, y, 0.0), Vect::ZERO);
            if !marked {
                (first, second) = (first.unmarked(), second.unmarked());
            }
            let (a, b) = (test.spawn(first), test.spawn(second));
            if ghost {
                test.app
                    .world_mut()
                    .entity_mut(a)
                    .insert((Ghost, ActiveHooks::FILTER_CONTACT_PAIRS));
            }
            pairs.push((a, b));
        }
        let messages = test.run(180);
        let [marked_ghost, ghost, marked, rapier] = pairs[..] else {
            unreachable!()
        };
        for (a, b) in [marked_ghost, ghost] {
            assert_eq!(test.vel(a).x, 1.0, "{timing:?}: the ghost was touched");
            assert_eq!(test.vel(b).x, 0.0, "{timing:?}: the ghost touched");
            assert!(test.pos(a).x > test.pos(b).x + 1.0, "{timing:?}: no pass");
        }
        for (a, b) in [marked, rapier] {
            assert!(test.vel(a).x.abs() < 1e-3, "{timing:?}: {:?}", test.vel(a));
            assert!((test.vel(b).x - 1.0).abs() < 1e-3, "{timing:?}");
        }
        // One impact, the marked pair's without a ghost.
        let named: Vec<_> = messages
            .iter()
            .map(|m| (m.collider1, m.collider2))
            .collect();
        assert!(
            named == [marked] || named == [(marked.1, marked.0)],
            "{timing:?}: {named:?}"
        );
    }
}

#[test]
fn another_rapier_context_keeps_rapiers_response_and_the_users_hooks() {
    let mut test = Setup::new().user_hooks().build();
    test.app.update();
    let other = test
        .app
        .world_mut()
        .spawn((
            RapierContextSimulation::default(),
            RapierConfiguration {
                gravity: Vect::ZERO,
                ..RapierConfiguration::new(1.0)
            },
        ))
        .id();
    // The same pair in both contexts: their collider handles coincide.
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    let c = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    let d = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    for e in [c, d] {
        test.app.world_mut().entity_mut(e).insert((
            RapierContextEntityLink(other),
            ActiveHooks::MODIFY_SOLVER_CONTACTS,
        ));
    }
    let messages = test.run(40);
    let named: Vec<_> = messages
        .iter()
        .map(|m| (m.collider1, m.collider2))
        .collect();
    assert!(named == [(a, b)] || named == [(b, a)], "{named:?}");
    let state = test.state();
    assert!(state.is_marked(a) && !state.is_marked(c) && !state.is_marked(d));
    assert!((test.vel(b).x - 1.0).abs() < 1e-5 && test.vel(a).x.abs() < 1e-5);
    // rapier's response (and the user's hook) in the other context.
    assert!(test.user_calls() > 0);
    assert!(test.vel(d).x > 0.5, "c and d met: {:?}", test.vel(d));
    assert!(test.pos(d).x > test.pos(c).x + 0.9, "c went through d");
}

#[test]
fn a_colliders_material_gives_its_pairs_their_own_law() {
    let mut test = Setup::new().build();
    let lossy = Material::new(0.2, 0.2).unwrap();
    // Three head-on pairs at rows y = 0, 3, 6: both balls lossy; none yet
    // (one gets the material at run time); none (the settings' elastic law).
    let pairs: Vec<_> = (0..3)
        .map(|row| {
            let y = 3.0 * row as f32;
            let a = test.ball(vect(0.0, y, 0.0), vect(1.0, 0.0, 0.0));
            (a, test.ball(vect(1.3, y, 0.0), Vect::ZERO))
        })
        .collect();
    for e in [pairs[0].0, pairs[0].1] {
        test.app
            .world_mut()
            .entity_mut(e)
            .insert(KimpactCollider::with_material(lossy));
    }
    test.run(3);
    test.app
        .world_mut()
        .get_mut::<KimpactCollider>(pairs[1].0)
        .unwrap()
        .material = Some(lossy);
    let messages = test.run(30);
    let restitution = |(a, b): (Entity, Entity)| {
        let m: Vec<_> = messages
            .iter()
            .filter(|m| [a, b].contains(&m.collider1) && [a, b].contains(&m.collider2))
            .collect();
        assert_eq!(m.len(), 1, "{m:?}");
        m[0].impact.restitution
    };
    let (lossy_both, lossy_one, elastic) = (
        restitution(pairs[0]),
        restitution(pairs[1]),
        restitution(pairs[2]),
    );
    assert!(lossy_both < 0.95, "{lossy_both}");
    // One side's material is the pair's law.
    assert!(
        (lossy_one - lossy_both).abs() < 1e-5,
        "{lossy_one} vs {lossy_both}"
    );
    assert!((elastic - 1.0).abs() < 1e-5, "{elastic}");
    let handle = test
        .app
        .world()
        .get::<RapierColliderHandle>(pairs[1].0)
        .unwrap()
        .0;
    assert_eq!(test.state().kimpact().material(handle), Some(lossy));
}

#[test]
fn a_non_finite_body_is_quarantined_as_bevy_rapier_does() {
    // A marked ball whose velocity becomes NaN on a collision course: no
    // panic, rapier's quarantine disables it (RigidBodyDisabled, as
    // bevy_rapier's own step system marks it), the others keep going.
    for setup in [Setup::without_kimpact(), Setup::new()] {
        let mut test = setup.build();
        let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
        let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
        let c = test.ball(vect(0.0, 4.0, 0.0), vect(1.0, 0.0, 0.0));
        test.run(2);
        test.app
            .world_mut()
            .get_mut::<Velocity>(a)
            .unwrap()
            .linear
            .x = f32::NAN;
        test.run(30);
        let world = test.app.world();
        assert!(
            world.get::<RigidBodyDisabled>(a).is_some(),
            "a is not quarantined"
        );
        assert!(world.get::<RigidBodyDisabled>(c).is_none());
        assert!(test.vel(c).x == 1.0 && test.pos(c).x > 0.4);
        let _ = b;
    }
}

#[test]
fn the_plugin_and_the_state_are_debug() {
    let plugin = KimpactPlugin::default().with_rapier(|rapier| rapier.with_length_unit(2.0));
    let shown = format!("{plugin:?}");
    assert!(shown.starts_with("KimpactPlugin"), "{shown}");
    assert!(shown.contains("configures_rapier: true"), "{shown}");
    let c = cradle(Setup::new());
    let shown = format!("{:?}", c.test.state());
    assert!(shown.contains("mode: Exact"), "{shown}");
    assert!(
        shown.contains(&format!("impacts: {}", c.test.state().stats().impacts)),
        "{shown}"
    );
}
