//! Newton's cradle in a window, with kimpact (built as `cradle2d_windowed`
//! by bevy_kimpact2d and `cradle3d_windowed` by bevy_kimpact3d, behind the
//! `windowed` feature, which turns on bevy's rendering and winit on X11):
//!
//!     cargo +nightly run --ignore-rust-version --features windowed --example cradle3d_windowed
//!
//! Six balls in a row, the first one moving: kimpact's exact mode passes
//! its velocity down the row to the last ball, which leaves alone. Space
//! switches to rapier's own response (`Mode::Native`) and back; R starts
//! the row again. The window's title names the mode.

#[cfg(feature = "dim2")]
use bevy_kimpact2d as bk;
#[cfg(feature = "dim3")]
use bevy_kimpact3d as bk;

use bevy::prelude::*;
use bk::bevy_rapier::prelude::*;
use bk::prelude::*;

type Vect = bk::bevy_rapier::math::Vect;

/// The balls' radius (m) and the first one's speed (m/s).
const R: f32 = 0.5;
const SPEED: f32 = 2.0;

fn main() {
    App::new()
        .add_plugins((
            DefaultPlugins.set(WindowPlugin {
                primary_window: Some(Window {
                    title: title(Mode::Exact),
                    ..default()
                }),
                ..default()
            }),
            // In place of RapierPhysicsPlugin::<NoUserData>::default().
            KimpactPlugin::default(),
        ))
        .add_systems(Startup, (no_gravity, spawn_scene))
        .add_systems(Update, (controls, name_the_mode))
        .run();
}

fn title(mode: Mode) -> String {
    let law = match mode {
        Mode::Native => "rapier's own response",
        _ => "kimpact's law",
    };
    format!("Newton's cradle: {law} ({mode:?}); Space: switch, R: restart")
}

/// A ball's place in the row (its starting x).
#[derive(Component)]
struct Ball(f32);

fn no_gravity(mut config: Query<&mut RapierConfiguration>) {
    for mut c in &mut config {
        c.gravity = Vect::ZERO;
    }
}

/// The first ball's start, then the row of touching balls.
fn row() -> impl Iterator<Item = f32> {
    std::iter::once(-4.0 * R).chain((0..5).map(|i| 2.0 * R * i as f32))
}

fn start_velocity(i: usize) -> Velocity {
    Velocity::linear(Vect::X * if i == 0 { SPEED } else { 0.0 })
}

fn spawn_scene(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    #[cfg(feature = "dim2")] mut materials: ResMut<Assets<ColorMaterial>>,
    #[cfg(feature = "dim3")] mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let center = 2.0 * R * 2.0;
    #[cfg(feature = "dim2")]
    let (mesh, material) = {
        commands.spawn((
            Camera2d,
            Projection::Orthographic(OrthographicProjection {
                scale: 1.0 / 60.0,
                ..OrthographicProjection::default_2d()
            }),
            Transform::from_xyz(center, 0.0, 0.0),
        ));
        (
            Mesh2d(meshes.add(Circle::new(R))),
            MeshMaterial2d(materials.add(Color::srgb(0.8, 0.7, 0.3))),
        )
    };
    #[cfg(feature = "dim3")]
    let (mesh, material) = {
        commands.spawn((
            Camera3d::default(),
            Transform::from_xyz(center, 3.0, 9.0).looking_at(Vec3::new(center, 0.0, 0.0), Vec3::Y),
        ));
        commands.spawn((
            DirectionalLight::default(),
            Transform::from_xyz(2.0, 6.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y),
        ));
        (
            Mesh3d(meshes.add(Sphere::new(R))),
            MeshMaterial3d(materials.add(Color::srgb(0.8, 0.7, 0.3))),
        )
    };
    for (i, x) in row().enumerate() {
        commands.spawn((
            Ball(x),
            RigidBody::Dynamic,
            Collider::ball(R),
            ColliderMassProperties::Mass(1.0),
            Restitution::coefficient(1.0),
            Friction::coefficient(0.0),
            Sleeping::disabled(),
            start_velocity(i),
            Transform::from_xyz(x, 0.0, 0.0),
            mesh.clone(),
            material.clone(),
            // The one component a marked collider needs.
            KimpactCollider::default(),
        ));
    }
}

/// Space: exact mode or rapier's own; R: the row from the start.
fn controls(
    keys: Res<ButtonInput<KeyCode>>,
    mut settings: ResMut<KimpactSettings>,
    mut balls: Query<(&Ball, &mut Transform, &mut Velocity)>,
) {
    if keys.just_pressed(KeyCode::Space) {
        settings.mode = match settings.mode {
            Mode::Native => Mode::Exact,
            _ => Mode::Native,
        };
    }
    if keys.just_pressed(KeyCode::KeyR) {
        let mut balls: Vec<_> = balls.iter_mut().collect();
        balls.sort_by(|a, b| a.0.0.total_cmp(&b.0.0));
        for (i, (ball, transform, velocity)) in balls.iter_mut().enumerate() {
            **transform = Transform::from_xyz(ball.0, 0.0, 0.0);
            **velocity = start_velocity(i);
        }
    }
}

fn name_the_mode(state: Res<KimpactState>, mut windows: Query<&mut Window>) {
    if !state.is_changed() {
        return;
    }
    for mut window in &mut windows {
        let title = title(state.mode());
        if window.title != title {
            window.title = title;
        }
    }
}
