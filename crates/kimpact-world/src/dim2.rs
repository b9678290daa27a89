// What differs in 2D, included by `dim2` and `dim2_f64` (see lib.rs).

/// A box of the scene's half extents `[x, y]`.
fn cuboid(h: &[f64]) -> k::rapier::prelude::ColliderBuilder {
    use k::math::Real;
    k::rapier::prelude::ColliderBuilder::cuboid(h[0] as Real, h[1] as Real)
}

/// The scene's rotation (`[angle]`) and angular velocity (`[ω]`) on a body.
fn turned(
    rb: k::rapier::prelude::RigidBodyBuilder,
    rotation: &[f64],
    angular_velocity: &[f64],
) -> k::rapier::prelude::RigidBodyBuilder {
    use k::math::Real;
    rb.rotation(rotation[0] as Real)
        .angvel(angular_velocity[0] as Real)
}

/// The body's orientation as a scene writes it: `[angle]`.
pub fn rotation(rb: &k::rapier::prelude::RigidBody) -> Vec<f64> {
    vec![rb.rotation().angle() as f64]
}

/// The body's angular velocity as a scene writes it: `[ω]`.
pub fn angular_velocity(rb: &k::rapier::prelude::RigidBody) -> Vec<f64> {
    vec![rb.angvel() as f64]
}

/// The joint that turns about its anchor (a 2D revolute has no axis).
fn revolute(_axis: Option<&[f64]>) -> k::rapier::prelude::RevoluteJointBuilder {
    k::rapier::prelude::RevoluteJointBuilder::new()
}

/// A ball joint: a 2D scene has none (the validator says so); the joint that
/// turns freely about its anchor in 2D is the revolute.
fn spherical() -> k::rapier::prelude::GenericJoint {
    revolute(None).into()
}
