// 3D helpers, included by `sim3d` and `sim3d_f64` (see mod.rs).

/// Scene vector → rapier vector.
fn vector(v: &[f64]) -> k::math::Vector {
    use k::math::Real;
    k::math::Vector::new(v[0] as Real, v[1] as Real, v[2] as Real)
}

/// rapier vector → scene vector.
fn to_vec(v: k::math::Vector) -> Vec<f64> {
    vec![v.x as f64, v.y as f64, v.z as f64]
}

/// rapier vector → a point of the crossing check (`z = 0` in 2D).
fn to_point(v: k::math::Vector) -> super::crossing::Point {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// The collider of a scene shape.
fn collider(shape: &crate::scene::Shape) -> k::rapier::prelude::ColliderBuilder {
    use crate::scene::Shape;
    use k::math::Real;
    use k::rapier::prelude::ColliderBuilder;
    match shape {
        Shape::Ball { radius } => ColliderBuilder::ball(*radius as Real),
        Shape::Box { half_extents: h } => {
            ColliderBuilder::cuboid(h[0] as Real, h[1] as Real, h[2] as Real)
        }
        Shape::Capsule {
            half_height,
            radius,
        } => ColliderBuilder::capsule_y(*half_height as Real, *radius as Real),
        Shape::Convex { points } => {
            let points: Vec<k::math::Vector> = points.iter().map(|p| vector(p)).collect();
            ColliderBuilder::convex_hull(&points)
                .expect("the scene's points were checked to span a volume")
        }
    }
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

/// The body's angular velocity: `[x, y, z]`.
fn angular_velocity(rb: &k::rapier::prelude::RigidBody) -> Vec<f64> {
    to_vec(rb.angvel())
}

/// The body's orientation: quaternion `[x, y, z, w]`.
fn rotation(rb: &k::rapier::prelude::RigidBody) -> Vec<f64> {
    let q = rb.rotation();
    vec![q.x as f64, q.y as f64, q.z as f64, q.w as f64]
}

/// rapier's joint for a scene joint, with its local anchors.
fn joint(
    j: &crate::scene::Joint,
    a1: k::math::Vector,
    a2: k::math::Vector,
) -> k::rapier::prelude::GenericJoint {
    use crate::scene::JointKind;
    use k::math::{Real, Vector};
    use k::rapier::prelude::*;
    let contacts = j.contacts_enabled;
    let limits = |l: &[f64; 2]| [l[0] as Real, l[1] as Real];
    match &j.kind {
        JointKind::Fixed => FixedJointBuilder::new()
            .local_anchor1(a1)
            .local_anchor2(a2)
            .contacts_enabled(contacts)
            .into(),
        JointKind::Revolute { axis, limits: l } => {
            let mut b = RevoluteJointBuilder::new(axis.as_deref().map_or(Vector::Z, vector))
                .local_anchor1(a1)
                .local_anchor2(a2)
                .contacts_enabled(contacts);
            if let Some(l) = l {
                b = b.limits(limits(l));
            }
            b.into()
        }
        JointKind::Spherical => SphericalJointBuilder::new()
            .local_anchor1(a1)
            .local_anchor2(a2)
            .contacts_enabled(contacts)
            .into(),
        JointKind::Prismatic { axis, limits: l } => {
            let mut b = PrismaticJointBuilder::new(vector(axis))
                .local_anchor1(a1)
                .local_anchor2(a2)
                .contacts_enabled(contacts);
            if let Some(l) = l {
                b = b.limits(limits(l));
            }
            b.into()
        }
        JointKind::Rope { max_distance } => RopeJointBuilder::new(*max_distance as Real)
            .local_anchor1(a1)
            .local_anchor2(a2)
            .contacts_enabled(contacts)
            .into(),
    }
}
