//! How the law sees a rapier body as a rigid body (mass, velocity, angular
//! velocity, world inverse inertia, centre of mass), for the pairs of a
//! marked collider of any shape on a dynamic body that every law mode
//! governs at the manifold's contact ([`kimpact::Law::resolve_rigid`]).

use kimpact::{Contact, ImpactFriction, Law, Mass, RigidImpact};

use crate::body_view::LawBody;
use crate::math::{DIM, Real, Vector, to_law};
use crate::rapier::prelude::*;

/// The law's rigid body of this dimension and precision.
pub(crate) type LawRigid = kimpact::RigidBody<Real, DIM>;

/// The law's angular velocity of rapier body `rb` (world frame).
#[cfg(feature = "dim2")]
pub(crate) fn angular(rb: &RigidBody) -> kimpact::Angular<Real, DIM> {
    rb.angvel()
}

/// The law's angular velocity of rapier body `rb` (world frame).
#[cfg(feature = "dim3")]
pub(crate) fn angular(rb: &RigidBody) -> kimpact::Angular<Real, DIM> {
    let w = rb.angvel();
    nalgebra::Vector3::new(w.x, w.y, w.z)
}

/// The world inverse inertia of rapier body `rb` as its solver uses it
/// (rows and columns of locked rotations zero).
#[cfg(feature = "dim2")]
pub(crate) fn inverse_inertia(rb: &RigidBody) -> kimpact::InverseInertia<Real, DIM> {
    rb.mass_properties().effective_world_inv_inertia
}

/// The world inverse inertia of rapier body `rb` as its solver uses it
/// (rows and columns of locked rotations zero).
#[cfg(feature = "dim3")]
pub(crate) fn inverse_inertia(rb: &RigidBody) -> kimpact::InverseInertia<Real, DIM> {
    let m = rb.mass_properties().effective_world_inv_inertia;
    nalgebra::Matrix3::new(
        m.m11, m.m12, m.m13, m.m12, m.m22, m.m23, m.m13, m.m23, m.m33,
    )
}

/// No rotation, in this dimension.
pub(crate) fn zero_angular() -> kimpact::Angular<Real, DIM> {
    Default::default()
}

/// The body `parent` as the law sees it at a contact (`law`: its mass
/// after locked translations and dominance, see
/// [`crate::body_view::law_body`] and [`crate::body_view::dominated`]),
/// and its centre of mass in the world (`None` without a body). `None`
/// when the data cannot enter the law (non-finite, or an inverse inertia
/// that is not positive semidefinite).
fn rigid(
    bodies: &RigidBodySet,
    parent: Option<RigidBodyHandle>,
    law: &LawBody,
) -> Option<(LawRigid, Option<Vector>)> {
    let rb = parent.and_then(|h| bodies.get(h));
    let omega = rb.map_or_else(zero_angular, angular);
    let velocity = to_law(law.velocity);
    let body = match (law.mass, rb) {
        (Mass::Finite(m), Some(rb)) => LawRigid::new(m, velocity, omega, inverse_inertia(rb)),
        (Mass::Finite(m), None) => LawRigid::new(m, velocity, omega, Default::default()),
        (Mass::Infinite, _) => LawRigid::immovable(velocity, omega),
    };
    Some((body.ok()?, rb.map(|rb| rb.center_of_mass())))
}

/// The velocity of the material point at `point` of the body `parent`
/// (`v + ω × (point − c)`); zero without a body.
pub(crate) fn point_velocity(
    bodies: &RigidBodySet,
    parent: Option<RigidBodyHandle>,
    point: Vector,
) -> Vector {
    parent
        .and_then(|h| bodies.get(h))
        .map_or(Vector::ZERO, |rb| rb.velocity_at_point(point))
}

/// The law's impact of the pair of bodies `p1`, `p2` (as the law sees
/// them: `b1`, `b2`) touching at `point` with unit normal `normal` from
/// the first towards the second, at the velocities they have now, with
/// impact friction `friction`; and the tangential velocity of the second
/// contact point relative to the first after it (what rapier's solver
/// contact takes as its `tangent_velocity`). `None` when the contact points
/// do not approach or the data cannot enter the law.
pub(crate) fn resolve(
    law: &Law<Real>,
    friction: &ImpactFriction<Real>,
    bodies: &RigidBodySet,
    (p1, b1): (Option<RigidBodyHandle>, &LawBody),
    (p2, b2): (Option<RigidBodyHandle>, &LawBody),
    point: Vector,
    normal: Vector,
) -> Option<(RigidImpact<Real, DIM>, Vector)> {
    let (a, centre_a) = rigid(bodies, p1, b1)?;
    let (b, centre_b) = rigid(bodies, p2, b2)?;
    // A body without a centre of mass (a collider without a body) is
    // immovable and still: its arm changes nothing.
    let arm = |centre: Option<Vector>| to_law(point - centre.unwrap_or(point));
    let (arm_a, arm_b) = (arm(centre_a), arm(centre_b));
    let contact = Contact::with_unit_normal(arm_a, arm_b, to_law(normal)).ok()?;
    let impact = law.resolve_rigid_with_friction(&a, &b, &contact, friction)?;
    if friction.is_frictionless() {
        return Some((impact, Vector::ZERO));
    }
    let after = |body: &LawRigid, dv, dw| {
        let (v, w) = (body.velocity() + dv, *body.angular_velocity() + dw);
        match body.mass() {
            Mass::Finite(m) => LawRigid::new(m, v, w, *body.inverse_inertia()).ok(),
            Mass::Infinite => LawRigid::immovable(v, w).ok(),
        }
    };
    let a1 = after(&a, impact.delta_v_a, impact.delta_omega_a)?;
    let b1 = after(&b, impact.delta_v_b, impact.delta_omega_b)?;
    let slip = b1.point_velocity(&arm_b) - a1.point_velocity(&arm_a);
    let n = to_law(normal);
    let tangential = slip - n * slip.dot(&n);
    Some((impact, crate::math::from_law(&tangential)))
}
