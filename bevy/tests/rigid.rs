//! Marked colliders of other shapes than balls (a box, a capsule) in a
//! headless bevy_rapier app: the law governs their impacts in every law
//! mode. Written once for 2D and 3D (compiled by bevy_kimpact2d and
//! bevy_kimpact3d).

#[cfg(feature = "dim2")]
use bevy_kimpact2d as bk;
#[cfg(feature = "dim3")]
use bevy_kimpact3d as bk;

use std::time::Duration;

use bevy::ecs::message::Messages;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
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
/// The size of an angular velocity (2D: a number; 3D: a vector).
#[cfg(feature = "dim2")]
fn spin(v: &Velocity) -> f32 {
    v.angular.abs()
}
#[cfg(feature = "dim3")]
fn spin(v: &Velocity) -> f32 {
    v.angular.length()
}

/// A headless app without gravity: `MinimalPlugins`, kimpact (adding
/// bevy_rapier) in `mode` with the elastic law but for the wall
/// dissipation `wall`, steps of 1/60 s.
fn app(mode: Mode, wall: f32) -> App {
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
    app.add_plugins(
        KimpactPlugin::default().with_rapier(move |r| r.with_custom_initialization(init.clone())),
    )
    .insert_resource(KimpactSettings {
        mode,
        law: LawParams {
            wall_dissipation: Some(wall),
            ..Default::default()
        },
    })
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
        DT,
    )))
    .insert_resource(TimestepMode::Fixed {
        dt: DT,
        substeps: 1,
    });
    app.finish();
    app
}

/// A marked dynamic body of mass 1 with `collider` at `p`, moving down at
/// `speed`, frictionless, with bevy_rapier's restitution 0 (only the law
/// can bounce it).
fn drop_body(app: &mut App, collider: Collider, p: Vect, speed: f32) -> Entity {
    app.world_mut()
        .spawn((
            RigidBody::Dynamic,
            collider,
            ColliderMassProperties::Mass(1.0),
            Restitution::coefficient(0.0),
            Friction::coefficient(0.0),
            Velocity::linear(vect(0.0, -speed, 0.0)),
            Sleeping::disabled(),
            KimpactCollider::default(),
            at(p),
        ))
        .id()
}

/// Issue 39.6: a marked box landing flat and a marked capsule landing
/// upright on its rounded end (their contacts under their centres: the
/// effective mass is the mass) on a fixed floor, without gravity, bounce
/// by the law in every law mode: each sends one `ImpactMessage` naming it
/// and the floor, bounced by rapier's solver (`by_solver`) with the law's
/// restitution `e = √(1 − 2 d̃w)` (`d̃w` the wall dissipation), and leaves
/// at `e U` without turning. bevy_rapier's restitution is 0 for both, so
/// in native mode neither bounces (rapier's push out of the overlap leaves
/// each under a tenth of `U`) and no message is sent.
#[test]
fn a_marked_box_and_capsule_bounce_by_the_law_in_every_mode() {
    let speed = 3.0;
    for mode in [Mode::Native, Mode::Restitution, Mode::Impulse, Mode::Exact] {
        for wall in [0.0, 0.1] {
            let mut app = app(mode, wall);
            // The floor's top at y = 0.
            let floor = app
                .world_mut()
                .spawn((
                    RigidBody::Fixed,
                    cuboid(vect(10.0, 0.5, 10.0)),
                    Friction::coefficient(0.0),
                    at(vect(0.0, -0.5, 0.0)),
                ))
                .id();
            let cube = drop_body(
                &mut app,
                cuboid(Vect::splat(0.5)),
                vect(-2.0, 1.0, 0.0),
                speed,
            );
            let capsule = drop_body(
                &mut app,
                Collider::capsule_y(0.3, 0.25),
                vect(2.0, 1.05, 0.0),
                speed,
            );
            let mut messages = Vec::new();
            for _ in 0..40 {
                app.update();
                let world = app.world_mut();
                if let Some(mut m) = world.get_resource_mut::<Messages<ImpactMessage>>() {
                    messages.extend(m.drain());
                }
            }
            let e = (1.0 - 2.0 * wall).sqrt();
            for (name, body) in [("box", cube), ("capsule", capsule)] {
                let case = format!("{mode}, d̃w = {wall}, {name}");
                let v = *app.world().get::<Velocity>(body).expect("a body");
                let own: Vec<_> = messages
                    .iter()
                    .filter(|m| m.collider1 == body || m.collider2 == body)
                    .collect();
                if mode == Mode::Native {
                    assert!(own.is_empty(), "{case}: {own:?}");
                    assert!(
                        v.linear.y.abs() < 0.1 * speed,
                        "{case}: bounced at {:?}",
                        v.linear
                    );
                    continue;
                }
                assert_eq!(own.len(), 1, "{case}: {own:?}");
                let m = own[0];
                assert!(
                    m.collider1 == floor || m.collider2 == floor,
                    "{case}: {m:?}"
                );
                assert!(m.impact.by_solver, "{case}: {m:?}");
                assert!(
                    (m.impact.restitution - e).abs() < 1e-5,
                    "{case}: e = {} for {e}",
                    m.impact.restitution
                );
                assert!(
                    (m.impact.approach_speed - speed).abs() < 1e-4,
                    "{case}: {m:?}"
                );
                assert!(
                    (v.linear - vect(0.0, e * speed, 0.0)).length() < 1e-4 * speed,
                    "{case}: left at {:?}, expected {}",
                    v.linear,
                    e * speed
                );
                assert!(spin(&v) < 1e-4, "{case}: turns at {:?}", v.angular);
            }
        }
    }
}
