// What differs in 3D, included by `dim3` and `dim3_f64` (see lib.rs).

/// A box of the scene's half extents `[x, y, z]`.
fn cuboid(h: &[f64]) -> k::rapier::prelude::ColliderBuilder {
    use k::math::Real;
    k::rapier::prelude::ColliderBuilder::cuboid(h[0] as Real, h[1] as Real, h[2] as Real)
}

/// The scene's rotation (a rotation vector) and angular velocity (world
/// frame) on a body.
fn turned(
    rb: k::rapier::prelude::RigidBodyBuilder,
    rotation: &[f64],
    angular_velocity: &[f64],
) -> k::rapier::prelude::RigidBodyBuilder {
    rb.rotation(vector(rotation)).angvel(vector(angular_velocity))
}

/// The body's orientation: the quaternion `[x, y, z, w]`.
pub fn rotation(rb: &k::rapier::prelude::RigidBody) -> Vec<f64> {
    let q = rb.rotation();
    vec![q.x as f64, q.y as f64, q.z as f64, q.w as f64]
}

/// The body's angular velocity: `[x, y, z]`.
pub fn angular_velocity(rb: &k::rapier::prelude::RigidBody) -> Vec<f64> {
    to_vec(rb.angvel())
}

/// The joint that turns about `axis` (the z axis when the scene gives none).
fn revolute(axis: Option<&[f64]>) -> k::rapier::prelude::RevoluteJointBuilder {
    k::rapier::prelude::RevoluteJointBuilder::new(axis.map_or(k::math::Vector::Z, vector))
}

/// A ball joint.
fn spherical() -> k::rapier::prelude::GenericJoint {
    k::rapier::prelude::SphericalJointBuilder::new().into()
}
