//! Marked colliders of other shapes than balls (a box, a capsule): the law
//! governs their impacts in every law mode.

use bevy::prelude::*;

use crate::bk::bevy_rapier::prelude::*;
use crate::bk::prelude::*;
use crate::harness::{Setup, Test, Vect, at, cuboid, vect};

/// The size of an angular velocity (2D: a number; 3D: a vector).
#[cfg(feature = "dim2")]
fn spin(v: &Velocity) -> f32 {
    v.angular.abs()
}
#[cfg(feature = "dim3")]
fn spin(v: &Velocity) -> f32 {
    v.angular.length()
}

/// A marked dynamic body of mass 1 with `collider` at `p`, moving down at
/// `speed`, frictionless, with bevy_rapier's restitution 0 (only the law
/// can bounce it).
fn drop_body(test: &mut Test, collider: Collider, p: Vect, speed: f32) -> Entity {
    test.app
        .world_mut()
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
/// and the floor, bounced by rapier's solver in restitution mode
/// (`by_solver`) and by the rigid replay at its time of impact in impulse
/// and exact mode, with the law's restitution `e = √(1 − 2 d̃w)` (`d̃w`
/// the wall dissipation), and leaves
/// at `e U` without turning. bevy_rapier's restitution is 0 for both, so
/// in native mode neither bounces (rapier's push out of the overlap leaves
/// each under a tenth of `U`) and no message is sent.
#[test]
fn a_marked_box_and_capsule_bounce_by_the_law_in_every_mode() {
    let speed = 3.0;
    for mode in [Mode::Native, Mode::Restitution, Mode::Impulse, Mode::Exact] {
        for wall in [0.0, 0.1] {
            let law = LawParams {
                wall_dissipation: Some(wall),
                ..Default::default()
            };
            let mut test = Setup::new().mode(mode).law(law).build();
            // The floor's top at y = 0, bevy_rapier's restitution 0.
            let floor = test
                .app
                .world_mut()
                .spawn((
                    RigidBody::Fixed,
                    cuboid(vect(10.0, 0.5, 10.0)),
                    Friction::coefficient(0.0),
                    at(vect(0.0, -0.5, 0.0)),
                ))
                .id();
            let cube = drop_body(
                &mut test,
                cuboid(Vect::splat(0.5)),
                vect(-2.0, 1.0, 0.0),
                speed,
            );
            let capsule = drop_body(
                &mut test,
                Collider::capsule_y(0.3, 0.25),
                vect(2.0, 1.05, 0.0),
                speed,
            );
            let messages = test.run(40);
            let e = (1.0 - 2.0 * wall).sqrt();
            for (name, body) in [("box", cube), ("capsule", capsule)] {
                let case = format!("{mode}, d̃w = {wall}, {name}");
                let v = *test.app.world().get::<Velocity>(body).expect("a body");
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
                assert_eq!(
                    m.impact.by_solver,
                    mode == Mode::Restitution,
                    "{case}: {m:?}"
                );
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
