//! Impact friction in the replay: the spins of the bodies whose pairs carry
//! it (a material's [`crate::Material::with_impact_friction`]), the law's
//! impact with its tangential part ([`kimpact::Law::resolve_rigid_with_friction`])
//! and what the write-back does with the spins.
//!
//! The replay moves balls centred on their bodies (and partners that do not
//! turn under the law: fixed, kinematic, dominant): a ball's shape does not
//! depend on its orientation, so its path stays the replay's line; the
//! impact changes its angular velocity, and the orientation it reaches at
//! the step's end turns by what the change adds over the rest of the step.
//! A run without impact friction makes no [`Spin`] and pays one test per
//! impact.

use kimpact::{Contact, ImpactFriction, Law, Mass, RigidImpact};

use super::{Node, Pair, Replay};
use crate::body_view::LawBody;
use crate::math::{DIM, Real, Vector, to_law};
use crate::rapier::prelude::*;
use crate::rigid_view::{LawRigid, angular, inverse_inertia, zero_angular};

/// The law's angular velocity in this dimension.
type LawAngular = kimpact::Angular<Real, DIM>;

/// A node that has no [`Spin`] (yet).
pub(super) const NO_SPIN: u32 = u32::MAX;

/// The rotation of a node the law may turn.
#[derive(Copy, Clone, Debug)]
pub(super) struct Spin {
    /// The angular velocity the law sees: rapier's at the step's end plus
    /// the changes so far.
    omega: LawAngular,
    /// The body's world inverse inertia as rapier's solver uses it (locked
    /// rotations zero).
    inverse_inertia: kimpact::InverseInertia<Real, DIM>,
    /// What the changes so far add to the orientation by the step's end
    /// (`Σ Δω (dt − t)`, a rotation vector).
    turn: LawAngular,
    /// Whether an impact changed `omega`.
    changed: bool,
}

impl Replay {
    /// The number of node `n`'s spin in `spins`, made from its body at
    /// its first impact with friction.
    fn spin(&mut self, bodies: &RigidBodySet, n: usize) -> usize {
        if self.nodes[n].spin != NO_SPIN {
            return self.nodes[n].spin as usize;
        }
        let rb = match self.nodes[n].key {
            super::Key::Body(h) => bodies.get(h),
            super::Key::Collider(_) => None,
        };
        let spin = Spin {
            omega: rb.map_or_else(zero_angular, angular),
            inverse_inertia: rb.map_or_else(Default::default, inverse_inertia),
            turn: zero_angular(),
            changed: false,
        };
        let i = self.spins.len();
        self.spins.push(spin);
        self.nodes[n].spin = i as u32;
        i
    }

    /// The impact of `pair` at time `t` with impact friction `friction`,
    /// the bodies as the law sees them `la` and `lb` (dominance applied);
    /// `None` where the law gives none (the contact points do not
    /// approach, or the data cannot enter it).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn resolve_with_friction(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        pair: &Pair,
        (la, lb): (&LawBody, &LawBody),
        law: &Law<Real>,
        friction: &ImpactFriction<Real>,
        t: Real,
    ) -> Option<RigidImpact<Real, DIM>> {
        let sa = self.spin(bodies, pair.a);
        let sb = self.spin(bodies, pair.b);
        let body = |law: &LawBody, spin: &Spin| match law.mass {
            Mass::Finite(m) => {
                LawRigid::new(m, to_law(law.velocity), spin.omega, spin.inverse_inertia)
            }
            Mass::Infinite => LawRigid::immovable(to_law(law.velocity), spin.omega),
        };
        let a = body(la, &self.spins[sa]).ok()?;
        let b = body(lb, &self.spins[sb]).ok()?;
        let arm = |node: &Node, collider: ColliderHandle, towards: Real| -> Vector {
            match colliders.get(collider).and_then(|co| co.shape().as_ball()) {
                // A ball centred on its body: exactly along the normal.
                Some(ball) => pair.normal * (towards * ball.radius),
                None => pair.point - node.at(t),
            }
        };
        let arm_a = arm(&self.nodes[pair.a], pair.c1, 1.0);
        let arm_b = arm(&self.nodes[pair.b], pair.c2, -1.0);
        let contact =
            Contact::with_unit_normal(to_law(arm_a), to_law(arm_b), to_law(pair.normal)).ok()?;
        law.resolve_rigid_with_friction(&a, &b, &contact, friction)
    }

    /// Node `n` turns by `delta` at time `t` of a step of `dt`.
    pub(super) fn turn(&mut self, n: usize, delta: &LawAngular, t: Real, dt: Real) {
        let i = self.nodes[n].spin;
        if i == NO_SPIN {
            return;
        }
        let spin = &mut self.spins[i as usize];
        spin.omega += *delta;
        spin.turn += *delta * (dt - t);
        spin.changed = true;
    }

    /// Write node `n`'s spin back into its body `rb`: the angular velocity
    /// and the orientation the changes add by the step's end (rapier turned
    /// the body at its own angular velocity over the whole step).
    pub(super) fn write_spin(&self, n: usize, rb: &mut RigidBody) {
        let i = self.nodes[n].spin;
        if i == NO_SPIN {
            return;
        }
        let spin = &self.spins[i as usize];
        if !spin.changed || !finite(&spin.omega) || !finite(&spin.turn) {
            return;
        }
        set_spin(rb, &spin.omega, &spin.turn);
    }
}

/// Whether every component of `w` is finite.
#[cfg(feature = "dim2")]
fn finite(w: &LawAngular) -> bool {
    w.is_finite()
}

/// Whether every component of `w` is finite.
#[cfg(feature = "dim3")]
fn finite(w: &LawAngular) -> bool {
    w.iter().all(|x| x.is_finite())
}

/// Give `rb` angular velocity `omega` and turn it by `turn`.
#[cfg(feature = "dim2")]
fn set_spin(rb: &mut RigidBody, omega: &LawAngular, turn: &LawAngular) {
    rb.set_angvel(*omega, true);
    let angle = rb.rotation().angle() + *turn;
    rb.set_rotation(crate::rapier::math::Rotation::new(angle), true);
}

/// Give `rb` angular velocity `omega` and turn it by `turn`.
#[cfg(feature = "dim3")]
fn set_spin(rb: &mut RigidBody, omega: &LawAngular, turn: &LawAngular) {
    use crate::math::from_law;
    rb.set_angvel(from_law(omega), true);
    let turn = crate::rapier::math::Rotation::from_scaled_axis(from_law(turn));
    rb.set_rotation((turn * *rb.rotation()).normalize(), true);
}
