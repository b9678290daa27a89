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
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bk::bevy_rapier::pipeline::ContactModificationContextView;
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

/// When bevy_rapier steps.
#[derive(Copy, Clone, Debug)]
enum Timing {
    /// `TimestepMode::Fixed` (dt = 1/60) in `PostUpdate`.
    Fixed,
    /// `TimestepMode::Variable` in `PostUpdate`, frames of 1/60 s.
    Variable,
    /// bevy_rapier and kimpact in `FixedUpdate` at 60 Hz.
    FixedUpdate,
    /// `TimestepMode::Fixed` with this many substeps.
    Substeps(usize),
    /// bevy_rapier in `FixedUpdate`, kimpact (wrongly) in `PostUpdate`.
    Mismatched,
}

/// A user's own hooks: count the calls for colliders they flagged.
#[derive(Resource, Default, Clone)]
struct UserCalls(Arc<AtomicUsize>);

#[derive(SystemParam)]
struct CountingHooks<'w> {
    calls: Res<'w, UserCalls>,
}

impl BevyPhysicsHooks for CountingHooks<'_> {
    fn modify_solver_contacts(&self, _context: ContactModificationContextView) {
        self.calls.0.fetch_add(1, Ordering::Relaxed);
    }
}

/// A headless app without gravity: `MinimalPlugins`, bevy_rapier, and
/// kimpact in `settings` (none: the same app without kimpact).
fn app(settings: Option<KimpactSettings>, timing: Timing) -> App {
    app_with(settings, timing, false)
}

fn app_with(settings: Option<KimpactSettings>, timing: Timing, user_hooks: bool) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin));
    let init = RapierContextInitialization::InitializeDefaultRapierContext {
        integration_parameters: Default::default(),
        rapier_configuration: RapierConfiguration {
            gravity: Vect::ZERO,
            ..RapierConfiguration::new(1.0)
        },
        broad_phase_optimization_strategy: Default::default(),
    };
    let fixed = matches!(timing, Timing::FixedUpdate | Timing::Mismatched);
    match (settings.is_some(), user_hooks) {
        (true, false) => {
            let rapier =
                RapierPhysicsPlugin::<KimpactHooks>::default().with_custom_initialization(init);
            if matches!(timing, Timing::Mismatched) {
                app.add_plugins((rapier.in_fixed_schedule(), KimpactPlugin::default()));
            } else if fixed {
                app.add_plugins((
                    rapier.in_fixed_schedule(),
                    KimpactPlugin::default().in_fixed_schedule(),
                ));
            } else {
                app.add_plugins((rapier, KimpactPlugin::default()));
            }
        }
        (true, true) => {
            assert!(!fixed);
            app.init_resource::<UserCalls>().add_plugins((
                RapierPhysicsPlugin::<KimpactHooks<CountingHooks>>::default()
                    .with_custom_initialization(init),
                KimpactPlugin::default().with_hooks::<CountingHooks>(),
            ));
        }
        (false, _) => {
            let rapier =
                RapierPhysicsPlugin::<NoUserData>::default().with_custom_initialization(init);
            if fixed {
                app.add_plugins(rapier.in_fixed_schedule());
            } else {
                app.add_plugins(rapier);
            }
        }
    }
    if let Some(settings) = settings {
        app.insert_resource(settings);
    }
    let frame = match timing {
        Timing::FixedUpdate | Timing::Mismatched => {
            app.insert_resource(Time::<Fixed>::from_hz(60.0));
            Duration::from_secs_f64(1.0 / 60.0)
        }
        _ => Duration::from_secs_f32(DT),
    };
    app.insert_resource(TimeUpdateStrategy::ManualDuration(frame));
    app.insert_resource(match timing {
        Timing::Fixed | Timing::FixedUpdate | Timing::Mismatched => TimestepMode::Fixed {
            dt: DT,
            substeps: 1,
        },
        Timing::Variable => TimestepMode::Variable {
            max_dt: DT,
            time_scale: 1.0,
            substeps: 1,
        },
        Timing::Substeps(n) => TimestepMode::Fixed {
            dt: DT,
            substeps: n,
        },
    });
    app.finish();
    app
}

fn exact() -> Option<KimpactSettings> {
    Some(KimpactSettings::default())
}

fn with_mode(mode: Mode) -> Option<KimpactSettings> {
    Some(KimpactSettings {
        mode,
        ..Default::default()
    })
}

/// A frictionless elastic (for rapier) ball that never sleeps, marked for
/// kimpact if `marked`.
fn ball(app: &mut App, p: Vect, v: Vect, r: f32, mass: f32, marked: bool) -> Entity {
    let mut e = app.world_mut().spawn((
        RigidBody::Dynamic,
        Collider::ball(r),
        ColliderMassProperties::Mass(mass),
        Restitution::coefficient(1.0),
        Friction::coefficient(0.0),
        Velocity::linear(v),
        Sleeping::disabled(),
        at(p),
    ));
    if marked {
        e.insert(KimpactCollider::default());
    }
    e.id()
}

/// A fixed frictionless wall (unmarked: walls meet the law as fixed partners).
fn wall(app: &mut App, center: Vect, half: Vect) -> Entity {
    app.world_mut()
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
fn closed_box(app: &mut App, half: f32) {
    let t = 1.0;
    for axis in 0..DIM {
        for sign in [-1.0, 1.0] {
            let mut center = Vect::ZERO;
            center[axis] = sign * (half + t);
            let mut h = Vect::splat(half + 2.0 * t);
            h[axis] = t;
            wall(app, center, h);
        }
    }
}

fn vel(app: &App, e: Entity) -> Vect {
    app.world().get::<Velocity>(e).expect("a body").linear
}

fn pos(app: &App, e: Entity) -> Vect {
    let t = app.world().get::<Transform>(e).expect("a body").translation;
    #[cfg(feature = "dim2")]
    return t.truncate();
    #[cfg(feature = "dim3")]
    return t;
}

fn kinetic(app: &App, balls: &[(Entity, f32)]) -> f64 {
    balls
        .iter()
        .map(|&(e, m)| 0.5 * f64::from(m) * f64::from(vel(app, e).length_squared()))
        .sum()
}

/// Run `frames` updates, collecting the impact messages.
fn run(app: &mut App, frames: usize) -> Vec<ImpactMessage> {
    let mut out = Vec::new();
    for _ in 0..frames {
        app.update();
        if let Some(mut messages) = app
            .world_mut()
            .get_resource_mut::<Messages<ImpactMessage>>()
        {
            out.extend(messages.drain());
        }
    }
    out
}

/// Newton's cradle: five touching balls and one incoming at 1 m/s, elastic.
/// The balls, the energy before and after, the messages.
fn cradle(timing: Timing) -> (App, Vec<Entity>, f64, f64, Vec<ImpactMessage>) {
    let mut app = app(exact(), timing);
    let r = 0.5;
    let mut balls = vec![ball(
        &mut app,
        vect(-(2.0 * r + 3.5 * DT), 0.0, 0.0),
        vect(1.0, 0.0, 0.0),
        r,
        1.0,
        true,
    )];
    for i in 0..5 {
        balls.push(ball(
            &mut app,
            vect(2.0 * r * i as f32, 0.0, 0.0),
            Vect::ZERO,
            r,
            1.0,
            true,
        ));
    }
    let masses: Vec<_> = balls.iter().map(|&e| (e, 1.0)).collect();
    app.update();
    let e0 = kinetic(&app, &masses);
    let messages = run(&mut app, 40);
    let e1 = kinetic(&app, &masses);
    (app, balls, e0, e1, messages)
}

#[test]
fn exact_newtons_cradle_passes_the_velocity_down_the_row() {
    for timing in [Timing::Fixed, Timing::Variable, Timing::FixedUpdate] {
        let (app, balls, e0, e1, messages) = cradle(timing);
        for (i, &b) in balls.iter().enumerate() {
            let expect = if i == 5 { 1.0 } else { 0.0 };
            let v = vel(&app, b);
            assert!(
                (v - vect(expect, 0.0, 0.0)).length() < 1e-5,
                "{timing:?}: ball {i} has {v:?}"
            );
        }
        assert!(
            ((e1 - e0) / e0).abs() < 1e-5,
            "{timing:?}: energy {e0} -> {e1}"
        );
        // One impact per touching pair, in order down the row.
        let pairs: Vec<_> = messages
            .iter()
            .map(|m| {
                let i = balls.iter().position(|&b| b == m.collider1).unwrap();
                let j = balls.iter().position(|&b| b == m.collider2).unwrap();
                (i.min(j), i.max(j))
            })
            .collect();
        assert_eq!(
            pairs,
            [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)],
            "{timing:?}"
        );
        let stats = app.world().resource::<KimpactState>().stats();
        assert_eq!(stats.impacts, 5, "{timing:?}");
    }
}

#[test]
fn several_steps_per_frame_run_rapier_natively_without_losing_the_mode() {
    let (app, balls, _, _, messages) = cradle(Timing::Substeps(2));
    assert!(messages.is_empty(), "kimpact took part: {messages:?}");
    let state = app.world().resource::<KimpactState>();
    assert_eq!(state.mode(), Mode::Exact);
    assert_eq!(state.stats().impacts, 0);
    // rapier's own cradle does not pass the velocity down the row.
    assert!(vel(&app, balls[5]).x < 0.9, "{:?}", vel(&app, balls[5]));
}

#[test]
fn kimpact_outside_bevy_rapiers_schedule_leaves_rapier_alone() {
    // The stages run with no step between them: kimpact warns and stands
    // aside (its hook passes every pair to rapier), nothing breaks.
    let (app, balls, e0, e1, messages) = cradle(Timing::Mismatched);
    assert!(messages.is_empty(), "{messages:?}");
    assert!(vel(&app, balls[5]).x < 0.9, "{:?}", vel(&app, balls[5]));
    assert!(e1 <= e0 * (1.0 + 1e-6), "energy {e0} -> {e1}");
}

/// A gas of `n` balls (restitution 1, no friction) in a closed box; the
/// balls and their masses.
fn gas(app: &mut App, n: usize) -> Vec<(Entity, f32)> {
    let half = 5.0;
    closed_box(app, half);
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
        let m = 1.0 + (i % 3) as f32;
        balls.push((ball(app, p, v, 0.3, m, true), m));
    }
    balls
}

#[test]
fn an_elastic_gas_keeps_its_energy_in_exact_mode() {
    let mut app = app(exact(), Timing::Fixed);
    let balls = gas(&mut app, 100);
    app.update();
    let e0 = kinetic(&app, &balls);
    let messages = run(&mut app, 600);
    let e1 = kinetic(&app, &balls);
    let impacts = app.world().resource::<KimpactState>().stats().impacts;
    eprintln!(
        "gas {DIM}D: {impacts} impacts, energy {e0} -> {e1} ({:.2e})",
        (e1 - e0) / e0
    );
    assert!(impacts > 500, "only {impacts} impacts");
    assert_eq!(messages.len() as u64, impacts, "one message per impact");
    assert!(((e1 - e0) / e0).abs() < 1e-5, "energy {e0} -> {e1}");
    for &(b, _) in &balls {
        let p = pos(&app, b);
        assert!(p.abs().max_element() < 5.0, "{b} escaped to {p:?}");
    }
}

/// Bits of every ball's position, rotation and velocity after `frames`.
fn gas_bits(settings: Option<KimpactSettings>, frames: usize) -> Vec<u32> {
    let mut app = app(settings, Timing::Fixed);
    let balls = gas(&mut app, 100);
    run(&mut app, frames);
    let mut bits = Vec::new();
    for &(b, _) in &balls {
        let t = app.world().get::<Transform>(b).unwrap();
        let v = app.world().get::<Velocity>(b).unwrap();
        bits.extend(t.translation.to_array().map(f32::to_bits));
        bits.extend(t.rotation.to_array().map(f32::to_bits));
        bits.extend(v.linear.to_array().map(f32::to_bits));
        #[cfg(feature = "dim2")]
        bits.push(v.angular.to_bits());
        #[cfg(feature = "dim3")]
        bits.extend(v.angular.to_array().map(f32::to_bits));
    }
    bits
}

#[test]
fn native_mode_leaves_bevy_rapier_unchanged_bit_for_bit() {
    let without = gas_bits(None, 200);
    assert_eq!(gas_bits(with_mode(Mode::Native), 200), without);
    // The comparison can tell: kimpact's law changes this scene.
    assert_ne!(gas_bits(exact(), 200), without);
}

#[test]
fn impact_messages_name_the_colliders_and_bodies() {
    let mut app = app(exact(), Timing::Fixed);
    let a = ball(
        &mut app,
        vect(0.0, 0.0, 0.0),
        vect(2.0, 0.0, 0.0),
        0.5,
        1.0,
        true,
    );
    let b = ball(&mut app, vect(1.5, 0.0, 0.0), Vect::ZERO, 0.5, 1.0, true);
    let w = wall(&mut app, vect(3.5, 0.0, 0.0), vect(0.5, 2.0, 2.0));
    // An unmarked pair meets too: rapier's, no message.
    let c = ball(
        &mut app,
        vect(0.0, 5.0, 0.0),
        vect(2.0, 0.0, 0.0),
        0.5,
        1.0,
        false,
    );
    let d = ball(&mut app, vect(1.5, 5.0, 0.0), Vect::ZERO, 0.5, 1.0, false);
    let messages = run(&mut app, 120);
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
    assert!(vel(&app, d).x > 1.0, "{:?}", vel(&app, d));
}

#[test]
fn despawning_marked_balls_mid_run_keeps_the_others_impacts() {
    let mut app = app(exact(), Timing::Fixed);
    let balls = gas(&mut app, 100);
    run(&mut app, 100);
    let gone: Vec<_> = balls.iter().step_by(10).map(|&(e, _)| e).collect();
    for &e in &gone {
        app.world_mut().despawn(e);
    }
    let rest: Vec<_> = balls
        .iter()
        .copied()
        .filter(|(e, _)| !gone.contains(e))
        .collect();
    let e0 = kinetic(&app, &rest);
    let messages = run(&mut app, 300);
    let e1 = kinetic(&app, &rest);
    let state = app.world().resource::<KimpactState>();
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
    let lossy = KimpactSettings {
        law: LawParams {
            dissipation: 0.2,
            ..Default::default()
        },
        ..Default::default()
    };
    let speed_after = |unmark: bool| {
        let mut app = app(Some(lossy.clone()), Timing::Fixed);
        let a = ball(
            &mut app,
            vect(0.0, 0.0, 0.0),
            vect(1.0, 0.0, 0.0),
            0.5,
            1.0,
            true,
        );
        let b = ball(&mut app, vect(1.3, 0.0, 0.0), Vect::ZERO, 0.5, 1.0, true);
        run(&mut app, 3);
        assert!(app.world().resource::<KimpactState>().is_marked(b));
        if unmark {
            app.world_mut().entity_mut(b).remove::<KimpactCollider>();
        }
        let messages = run(&mut app, 30);
        let state = app.world().resource::<KimpactState>();
        assert_eq!(state.is_marked(b), !unmark);
        (
            messages.len(),
            vel(&app, a).x + vel(&app, b).x,
            vel(&app, b).x,
        )
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
    let mut app = app(exact(), Timing::Fixed);
    let a = ball(
        &mut app,
        vect(0.0, 0.0, 0.0),
        vect(1.0, 0.0, 0.0),
        0.5,
        1.0,
        true,
    );
    let b = ball(&mut app, vect(1.3, 0.0, 0.0), Vect::ZERO, 0.5, 1.0, true);
    // A second pair, meeting after the switch to native mode.
    ball(
        &mut app,
        vect(0.0, 4.0, 0.0),
        vect(1.0, 0.0, 0.0),
        0.5,
        1.0,
        true,
    );
    let d = ball(&mut app, vect(3.0, 4.0, 0.0), Vect::ZERO, 0.5, 1.0, true);
    run(&mut app, 2);
    app.world_mut()
        .resource_mut::<KimpactSettings>()
        .law
        .dissipation = -1.0;
    let messages = run(&mut app, 30);
    let state = app.world().resource::<KimpactState>();
    assert_eq!(state.law().dissipation(), 0.0, "the valid law stays");
    assert_eq!(messages.len(), 1, "a and b meet under the elastic law");
    assert!((vel(&app, b).x - 1.0).abs() < 1e-5 && vel(&app, a).x.abs() < 1e-5);
    app.world_mut().resource_mut::<KimpactSettings>().mode = Mode::Native;
    let messages = run(&mut app, 150);
    assert_eq!(app.world().resource::<KimpactState>().mode(), Mode::Native);
    assert!(messages.is_empty(), "native mode sends none: {messages:?}");
    assert!(
        vel(&app, d).x > 0.5,
        "the second pair met (rapier's): {:?}",
        vel(&app, d)
    );
}

#[test]
fn the_users_hooks_are_chained() {
    let mut app = app_with(exact(), Timing::Fixed, true);
    // The user's flag on an unmarked ball hitting a wall, and on a marked
    // one: the user's hook runs for both, and the law still takes the
    // marked pair.
    let u = ball(
        &mut app,
        vect(0.0, 4.0, 0.0),
        vect(2.0, 0.0, 0.0),
        0.5,
        1.0,
        false,
    );
    app.world_mut()
        .entity_mut(u)
        .insert(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    wall(&mut app, vect(2.5, 4.0, 0.0), vect(0.5, 1.0, 1.0));
    let a = ball(
        &mut app,
        vect(0.0, 0.0, 0.0),
        vect(1.0, 0.0, 0.0),
        0.5,
        1.0,
        true,
    );
    app.world_mut()
        .entity_mut(a)
        .insert(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    let b = ball(&mut app, vect(1.3, 0.0, 0.0), Vect::ZERO, 0.5, 1.0, true);
    let messages = run(&mut app, 80);
    let calls = app
        .world()
        .resource::<UserCalls>()
        .0
        .load(Ordering::Relaxed);
    assert!(calls > 0, "the user's hook never ran");
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!((vel(&app, b).x - 1.0).abs() < 1e-5 && vel(&app, a).x.abs() < 1e-5);
    assert!(vel(&app, u).x < 0.0, "u bounced off the wall");
}

#[test]
fn another_rapier_context_keeps_rapiers_response_and_the_users_hooks() {
    let mut app = app_with(exact(), Timing::Fixed, true);
    app.update();
    let other = app
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
    let a = ball(
        &mut app,
        vect(0.0, 0.0, 0.0),
        vect(1.0, 0.0, 0.0),
        0.5,
        1.0,
        true,
    );
    let b = ball(&mut app, vect(1.3, 0.0, 0.0), Vect::ZERO, 0.5, 1.0, true);
    let c = ball(
        &mut app,
        vect(0.0, 0.0, 0.0),
        vect(1.0, 0.0, 0.0),
        0.5,
        1.0,
        true,
    );
    let d = ball(&mut app, vect(1.3, 0.0, 0.0), Vect::ZERO, 0.5, 1.0, true);
    for e in [c, d] {
        app.world_mut().entity_mut(e).insert((
            RapierContextEntityLink(other),
            ActiveHooks::MODIFY_SOLVER_CONTACTS,
        ));
    }
    let messages = run(&mut app, 40);
    let named: Vec<_> = messages
        .iter()
        .map(|m| (m.collider1, m.collider2))
        .collect();
    assert!(named == [(a, b)] || named == [(b, a)], "{named:?}");
    let state = app.world().resource::<KimpactState>();
    assert!(state.is_marked(a) && !state.is_marked(c) && !state.is_marked(d));
    assert!((vel(&app, b).x - 1.0).abs() < 1e-5 && vel(&app, a).x.abs() < 1e-5);
    // rapier's response (and the user's hook) in the other context.
    assert!(
        app.world()
            .resource::<UserCalls>()
            .0
            .load(Ordering::Relaxed)
            > 0
    );
    assert!(vel(&app, d).x > 0.5, "c and d met: {:?}", vel(&app, d));
    assert!(pos(&app, d).x > pos(&app, c).x + 0.9, "c went through d");
}

#[test]
fn a_colliders_material_gives_its_pairs_their_own_law() {
    let mut app = app(exact(), Timing::Fixed);
    let lossy = Material::new(0.2, 0.2).unwrap();
    // Three head-on pairs at rows y = 0, 3, 6: both balls lossy; none yet
    // (one gets the material at run time); none (the settings' elastic law).
    let mut pairs = Vec::new();
    for row in 0..3 {
        let y = 3.0 * row as f32;
        let a = ball(
            &mut app,
            vect(0.0, y, 0.0),
            vect(1.0, 0.0, 0.0),
            0.5,
            1.0,
            true,
        );
        let b = ball(&mut app, vect(1.3, y, 0.0), Vect::ZERO, 0.5, 1.0, true);
        pairs.push((a, b));
    }
    for e in [pairs[0].0, pairs[0].1] {
        app.world_mut()
            .entity_mut(e)
            .insert(KimpactCollider::with_material(lossy));
    }
    run(&mut app, 3);
    app.world_mut()
        .get_mut::<KimpactCollider>(pairs[1].0)
        .unwrap()
        .material = Some(lossy);
    let messages = run(&mut app, 30);
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
    let state = app.world().resource::<KimpactState>();
    let handle = app
        .world()
        .get::<RapierColliderHandle>(pairs[1].0)
        .unwrap()
        .0;
    assert_eq!(state.kimpact().material(handle), Some(lossy));
}
