//! Whether rapier would let two colliders touch: the test every pair the
//! replay's sweeps find must pass before the law may act on it (the pairs
//! rapier's narrow phase lists have passed it already).

use crate::rapier::prelude::*;

/// What decides whether a pair may touch besides the colliders themselves:
/// the joints (a joint with contacts disabled keeps its two bodies from
/// touching) and the user's hooks (`filter_contact_pair`, for colliders
/// with `ActiveHooks::FILTER_CONTACT_PAIR`).
#[derive(Copy, Clone)]
pub(crate) struct PairFilter<'a> {
    impulse_joints: &'a ImpulseJointSet,
    multibody_joints: &'a MultibodyJointSet,
    /// Whether either joint set holds anything (a world without joints
    /// pays nothing for them).
    any_joints: bool,
    user: &'a dyn PhysicsHooks,
}

impl<'a> PairFilter<'a> {
    /// The filter of a step with these joints and user hooks.
    pub(crate) fn new(
        impulse_joints: &'a ImpulseJointSet,
        multibody_joints: &'a MultibodyJointSet,
        user: &'a dyn PhysicsHooks,
    ) -> Self {
        let any_joints =
            !impulse_joints.is_empty() || multibody_joints.multibodies().next().is_some();
        Self {
            impulse_joints,
            multibody_joints,
            any_joints,
            user,
        }
    }

    /// Whether rapier's solver would let colliders `c1` (`co1`) and `c2`
    /// (`co2`) of `pair` push each other, as its narrow phase decides it: both
    /// enabled, neither a sensor, their collision and solver groups
    /// admitting each other, their active collision types (either
    /// collider's) admitting their bodies' types (`dynamic` says whether
    /// either body is dynamic, which is all the default types ask), no
    /// joint between their bodies with contacts disabled (nor a multibody
    /// without self-contacts holding both), and the user's
    /// `filter_contact_pair` computing impulses for them when either
    /// collider asks for that hook.
    pub(crate) fn admits(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        pair: [(ColliderHandle, &Collider); 2],
        dynamic: bool,
    ) -> bool {
        let [(c1, co1), (c2, co2)] = pair;
        if !(co1.is_enabled()
            && co2.is_enabled()
            && !co1.is_sensor()
            && !co2.is_sensor()
            && co1.collision_groups().test(co2.collision_groups())
            && co1.solver_groups().test(co2.solver_groups()))
        {
            return false;
        }
        let (p1, p2) = (co1.parent(), co2.parent());
        if self.any_joints
            && let (Some(b1), Some(b2)) = (p1, p2)
            && !self.joints_admit(b1, b2)
        {
            return false;
        }
        let (a1, a2) = (co1.active_collision_types(), co2.active_collision_types());
        let types =
            if a1 == ActiveCollisionTypes::default() && a2 == ActiveCollisionTypes::default() {
                dynamic
            } else {
                let body_type = |p: Option<RigidBodyHandle>| {
                    p.and_then(|h| bodies.get(h))
                        .map_or(RigidBodyType::Fixed, |rb| rb.body_type())
                };
                let (t1, t2) = (body_type(p1), body_type(p2));
                a1.test(t1, t2) || a2.test(t1, t2)
            };
        if !types {
            return false;
        }
        if (co1.active_hooks() | co2.active_hooks()).contains(ActiveHooks::FILTER_CONTACT_PAIRS) {
            let context = PairFilterContext {
                bodies,
                colliders,
                rigid_body1: p1,
                rigid_body2: p2,
                collider1: c1,
                collider2: c2,
            };
            return self
                .user
                .filter_contact_pair(&context)
                .is_some_and(|flags| flags.contains(SolverFlags::COMPUTE_RIGID_IMPULSES));
        }
        true
    }

    /// Whether the joints let bodies `b1` and `b2` touch (rapier's narrow
    /// phase rules).
    fn joints_admit(&self, b1: RigidBodyHandle, b2: RigidBodyHandle) -> bool {
        if self
            .impulse_joints
            .joints_between(b1, b2)
            .any(|(_, joint)| !joint.data.contacts_enabled)
        {
            return false;
        }
        let mb = self.multibody_joints;
        if let (Some(l1), Some(l2)) = (mb.rigid_body_link(b1), mb.rigid_body_link(b2))
            && l1.multibody == l2.multibody
        {
            if mb
                .get_multibody(l1.multibody)
                .is_some_and(|m| !m.self_contacts_enabled())
            {
                return false;
            }
            if mb
                .joint_between(b1, b2)
                .is_some_and(|(_, _, link)| !link.joint.data.contacts_enabled)
            {
                return false;
            }
        }
        true
    }
}
