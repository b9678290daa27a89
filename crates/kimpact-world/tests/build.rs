//! The builder on bundled scenes: each body, collider, mark, material and
//! joint against what the scene file writes (the values are the files',
//! copied here), and what a mode changes in the world.

use std::path::Path;

use approx::assert_relative_eq;
use kimpact::{ImpactFriction, Mode};
use kimpact_scene::Scene;
use kimpact_world::BuildError;

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    kimpact_scene::load(&path).unwrap()
}

/// billiards2d.ron: 16 balls (r = 28.575 mm, 0.17 kg, restitution 1, the
/// cue at 8 m/s from x = −0.635) and four fixed cushions; `fixed_walls`,
/// no gravity, no spin, `auto_ccd`.
#[test]
fn billiards_bodies_colliders_and_marks() {
    use kimpact_world::dim2_f64::{build, to_vec};
    let scene = scene("billiards2d.ron");
    for mode in Mode::ALL {
        let built = build(&scene, mode).unwrap();
        let (world, kimpact) = (&built.world, &built.kimpact);
        assert_eq!(built.bodies.len(), 20);
        assert_eq!(world.bodies.len(), 20);
        assert_eq!(world.colliders.len(), 20);
        assert_eq!(to_vec(world.gravity), [0.0, 0.0]);
        assert_eq!(world.integration_parameters.dt, 1.0 / 60.0);
        assert!(kimpact.config().fixed_partners);
        assert_eq!(kimpact.mode(), mode);
        for (i, (h, c)) in built.bodies.iter().zip(&built.colliders).enumerate() {
            let (rb, co) = (&world.bodies[*h], &world.colliders[*c]);
            assert_eq!(co.parent(), Some(*h));
            assert_eq!(co.restitution(), 1.0);
            if i < 16 {
                let ball = co.shape().as_ball().expect("a ball");
                assert_eq!(ball.radius, 0.028575);
                assert_relative_eq!(rb.mass(), 0.17, max_relative = 1e-12);
                assert!(rb.is_dynamic());
                // No `spin`: rotations locked.
                assert!(rb.is_rotation_locked());
                // Every mode marks the law's balls, without a material.
                assert!(kimpact.is_marked(*c), "ball {i} in {mode}");
                assert_eq!(kimpact.material(*c), None);
            } else {
                assert!(rb.is_fixed());
                assert!(co.shape().as_cuboid().is_some());
                assert!(!kimpact.is_marked(*c), "cushion {i}");
            }
        }
        let cue = &world.bodies[built.bodies[0]];
        assert_eq!(to_vec(cue.translation()), [-0.635, 0.0]);
        assert_eq!(to_vec(cue.linvel()), [8.0, 0.0]);
        let ball_5 = &world.bodies[built.bodies[5]];
        assert_eq!(to_vec(ball_5.translation()), [0.734036, 0.0]);
    }
}

/// Soft CCD and contact recycling follow the mode, at build and on a
/// switch: the cue ball covers 8/60 m, more than its radius, in a step.
#[test]
fn billiards_soft_ccd_follows_the_mode() {
    use kimpact_world::dim2_f64::build;
    let scene = scene("billiards2d.ron");
    let cue_prediction =
        |w: &kimpact_world::dim2_f64::SceneWorld| w.world.bodies[w.bodies[0]].soft_ccd_prediction();
    let mut native = build(&scene, Mode::Native).unwrap();
    // At least the distance the cue ball covers in a step.
    assert!(cue_prediction(&native) >= 8.0 / 60.0);
    assert!(native.soft_ccd_bodies() >= 1);
    assert!(!native.world.integration_parameters.contact_recycling);
    let exact = build(&scene, Mode::Exact).unwrap();
    assert_eq!(exact.soft_ccd_bodies(), 0);
    assert!(exact.world.integration_parameters.contact_recycling);

    let prediction = cue_prediction(&native);
    let count = native.soft_ccd_bodies();
    native.set_mode(Mode::Exact);
    assert_eq!(native.kimpact.mode(), Mode::Exact);
    assert_eq!(native.soft_ccd_bodies(), 0);
    assert!(native.world.integration_parameters.contact_recycling);
    native.set_mode(Mode::Native);
    assert_eq!(cue_prediction(&native), prediction);
    assert_eq!(native.soft_ccd_bodies(), count);
    assert!(!native.world.integration_parameters.contact_recycling);
}

/// cutshot3d.ron (3D, f64): twelve balls of material "ball" (impact
/// friction 0.06, tangential restitution 0), friction 0.06, spin on.
#[test]
fn cutshot_materials_and_spin() {
    use kimpact_world::dim3_f64::{build, to_vec};
    let scene = scene("cutshot3d.ron");
    let built = build(&scene, Mode::Exact).unwrap();
    let (world, kimpact) = (&built.world, &built.kimpact);
    assert_eq!(built.bodies.len(), 12);
    let friction = ImpactFriction::new(0.06, 0.0).unwrap();
    for (h, c) in built.bodies.iter().zip(&built.colliders) {
        let (rb, co) = (&world.bodies[*h], &world.colliders[*c]);
        assert_eq!(co.friction(), 0.06);
        assert_eq!(rb.is_rotation_locked(), [false; 3]);
        // Spin: a solid ball's inertia 2/5 m r², about every axis.
        let inertia = 0.4 * 0.17 * 0.028575 * 0.028575;
        assert_relative_eq!(
            rb.mass_properties().local_mprops.principal_inertia().x,
            inertia,
            max_relative = 1e-9
        );
        let material = kimpact.material(*c).expect("marked with its material");
        assert_eq!(material.impact_friction(), friction);
        // The scene's law (the default: elastic).
        assert_eq!(material.dissipation(), 0.0);
    }
    let object_30 = &world.bodies[built.bodies[7]];
    assert_eq!(to_vec(object_30.translation()), [0.15, 3.028575, 0.0]);
}

/// newton_cradle3d.ron: five balls, each hung by a spherical joint from a
/// fixed point 5 m above it (a world end: a fixed body without a collider
/// at the anchor, its local anchor the origin); gravity −9.81 along y.
#[test]
fn cradle_joints_hang_from_the_world() {
    use kimpact_world::dim3::{build, to_vec};
    let scene = scene("newton_cradle3d.ron");
    let built = build(&scene, Mode::Exact).unwrap();
    let world = &built.world;
    assert_eq!(to_vec(world.gravity), [0.0, -9.81f32 as f64, 0.0]);
    assert_eq!(world.bodies.len(), 10);
    assert_eq!(world.colliders.len(), 5);
    assert_eq!(world.impulse_joints.len(), 5);
    for (_, joint) in world.impulse_joints.iter() {
        let ball = built
            .bodies
            .iter()
            .position(|h| *h == joint.body2())
            .expect("the second end is a ball");
        let top = &world.bodies[joint.body1()];
        assert!(top.is_fixed());
        assert!(top.colliders().is_empty());
        let x = [0.0, 1.1, 2.2, 3.3, 4.4][ball];
        assert_relative_eq!(top.translation().x, x, max_relative = 1e-6);
        assert_eq!(top.translation().y, 5.0);
        assert_eq!(to_vec(joint.data.local_anchor1()), [0.0, 0.0, 0.0]);
        assert_eq!(to_vec(joint.data.local_anchor2()), [0.0, 5.0, 0.0]);
        assert!(joint.data.contacts_enabled());
    }
}

/// A 3D scene in a 2D build is an error naming both dimensions.
#[test]
fn a_scene_of_another_dimension_is_refused() {
    let scene = scene("cradle3d.json");
    match kimpact_world::dim2::build(&scene, Mode::Exact) {
        Err(BuildError::Dimension { scene, world, .. }) => assert_eq!((scene, world), (3, 2)),
        other => panic!("expected a dimension error, got {other:?}"),
    }
}
