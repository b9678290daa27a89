//! Newton's cradle in a headless bevy_rapier app with kimpact (built as
//! `cradle2d` by bevy_kimpact2d and `cradle3d` by bevy_kimpact3d):
//!
//!     cargo +nightly run --ignore-rust-version --example cradle3d
//!
//! Six balls in a row, the first one moving at 1 m/s: kimpact's exact mode
//! passes its velocity down the row to the last ball; rapier's own response
//! spreads it over the row. A system prints kimpact's impact messages; the
//! final velocities are printed for both.

#[cfg(feature = "dim2")]
use bevy_kimpact2d as bk;
#[cfg(feature = "dim3")]
use bevy_kimpact3d as bk;

use std::time::Duration;

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bk::bevy_rapier::prelude::*;
use bk::prelude::*;

type Vect = bk::bevy_rapier::math::Vect;

const DT: f32 = 1.0 / 60.0;

fn main() {
    for with_kimpact in [true, false] {
        let velocities = cradle(with_kimpact);
        let label = if with_kimpact {
            "kimpact (exact)"
        } else {
            "rapier"
        };
        let row: Vec<String> = velocities.iter().map(|v| format!("{v:.4}")).collect();
        println!(
            "{label:>16}: final velocities along the row [{}]",
            row.join(", ")
        );
    }
}

/// Run the cradle for two seconds; the balls' final velocities along x.
fn cradle(with_kimpact: bool) -> Vec<f32> {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin));
    if with_kimpact {
        // In place of RapierPhysicsPlugin (and `KimpactCollider` below).
        app.add_plugins(KimpactPlugin::default())
            .insert_resource(KimpactSettings {
                mode: Mode::Exact,
                law: LawParams::default(),
            })
            .add_systems(PostUpdate, print_impacts.after(KimpactSet::Step));
    } else {
        app.add_plugins(RapierPhysicsPlugin::<NoUserData>::default());
    }
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
        DT,
    )))
    .insert_resource(TimestepMode::Fixed {
        dt: DT,
        substeps: 1,
    })
    .add_systems(Startup, (no_gravity, spawn_row));
    app.finish();
    app.cleanup();
    for _ in 0..120 {
        app.update();
    }
    let world = app.world_mut();
    let mut balls: Vec<(f32, f32)> = world
        .query_filtered::<(&Ball, &Velocity), With<RigidBody>>()
        .iter(world)
        .map(|(b, v)| (b.0, v.linear.x))
        .collect();
    balls.sort_by(|a, b| a.0.total_cmp(&b.0));
    balls.into_iter().map(|(_, v)| v).collect()
}

/// A ball's place in the row (its starting x).
#[derive(Component)]
struct Ball(f32);

fn no_gravity(mut config: Query<&mut RapierConfiguration>) {
    for mut c in &mut config {
        c.gravity = Vect::ZERO;
    }
}

fn spawn_row(mut commands: Commands) {
    let r = 0.5;
    let first = -(2.0 * r + 3.5 * DT);
    for (i, x) in std::iter::once(first)
        .chain((0..5).map(|i| 2.0 * r * i as f32))
        .enumerate()
    {
        let v = if i == 0 { 1.0 } else { 0.0 };
        commands.spawn((
            Ball(x),
            RigidBody::Dynamic,
            Collider::ball(r),
            ColliderMassProperties::Mass(1.0),
            Restitution::coefficient(1.0),
            Friction::coefficient(0.0),
            Sleeping::disabled(),
            Velocity::linear(Vect::X * v),
            Transform::from_xyz(x, 0.0, 0.0),
            // The one component a marked collider needs.
            KimpactCollider::default(),
        ));
    }
}

fn print_impacts(mut impacts: MessageReader<ImpactMessage>, balls: Query<&Ball>) {
    for m in impacts.read() {
        let place = |e| balls.get(e).map_or(f32::NAN, |b| b.0);
        println!(
            "impact: balls at x = {:.2} and {:.2}, {:.4} s into the step, impulse {:.4}, restitution {:.4}",
            place(m.collider1),
            place(m.collider2),
            m.impact.time,
            m.impact.impulse,
            m.impact.restitution
        );
    }
}
