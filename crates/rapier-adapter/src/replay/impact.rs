//! One impact of the replay: the bodies as the law sees them at the
//! meeting (mass, dominance, velocity), and the law's impact, with its
//! tangential part when the pair carries impact friction (a material's
//! [`crate::Material::with_impact_friction`]).
//!
//! The replay moves balls centred on their bodies (and partners that do not
//! turn under the law: fixed, kinematic, dominant): a ball's shape does not
//! depend on its orientation, so its path stays the replay's line; an
//! impact with friction changes its angular velocity, and the orientation
//! it reaches at the step's end turns by what the change adds over the rest
//! of the step.

use kimpact::{Contact, ImpactFriction, Law, Mass, RigidImpact};

use super::context::Run;
use super::node::{LawAngular, Node, Pair};
use super::state::Replay;
use crate::body_view::{LawBody, dominate};
use crate::events::{EventLog, Outcome};
use crate::math::{DIM, LawVector, Real, to_law};
use crate::rapier::prelude::*;
use crate::rigid_view::LawRigid;

/// What the law did at an impact of the replay.
pub(super) struct Applied {
    /// What an event reports of it.
    pub outcome: Outcome,
    /// The change of each body's velocity.
    pub delta_v: [LawVector; 2],
    /// The mass the law took each body with (a dominant body is
    /// immovable to the other).
    pub masses: [Mass<Real>; 2],
}

impl Replay {
    /// The law's impact of `pair` at its queued hit, the angular
    /// velocities it changes already applied; `None` when the law gives
    /// none (the pair is rapier's, the contact points do not approach, or
    /// approach slower than `floor`) or the data cannot enter it (counted
    /// in `log`).
    pub(super) fn impact(
        &mut self,
        run: &Run,
        pair: &Pair,
        floor: Real,
        log: &mut EventLog,
    ) -> Option<Applied> {
        let t = pair.hit.time;
        let (na, nb) = (self.nodes[pair.a], self.nodes[pair.b]);
        // A body with some translations locked: the pair is rapier's.
        let (la, lb) = law_bodies(&na, &nb, t, run.dt)?;
        let (Ok(ba), Ok(bb)) = (la.checked(), lb.checked()) else {
            log.skip(pair.colliders());
            return None;
        };
        // The pair approaches faster than the rest speed: `predict`
        // queued it only then, and neither velocity has changed since.
        let marks = run.input.marks;
        let law = marks.law(run.input.law, pair.c1, pair.c2);
        let friction = marks.friction(pair.c1, pair.c2);
        let masses = [la.mass, lb.mass];
        if friction.is_frictionless() {
            let impact = law.resolve_unit(&ba, &bb, &to_law(pair.hit.normal))?;
            if impact.approach_speed < floor {
                return None;
            }
            return Some(Applied {
                outcome: Outcome::from(&impact),
                delta_v: [impact.delta_v_a, impact.delta_v_b],
                masses,
            });
        }
        let impact = with_friction(pair, [(&na, &la), (&nb, &lb)], &law, &friction)?;
        if impact.approach_speed < floor {
            return None;
        }
        let from = t.max(0.0);
        self.nodes[pair.a].turn_by(&impact.delta_omega_a, from, run.dt);
        self.nodes[pair.b].turn_by(&impact.delta_omega_b, from, run.dt);
        Some(Applied {
            outcome: Outcome::from(&impact),
            delta_v: [impact.delta_v_a, impact.delta_v_b],
            masses,
        })
    }
}

/// Nodes `na` and `nb` as the law meets them at `t` of a step of `dt`:
/// their masses and the velocities of [`Node::law_velocity`]; two dynamic
/// bodies of different dominance groups: the dominant one is immovable to
/// the other, as rapier's solver takes it. `None` for a body with some
/// translations locked.
fn law_bodies(na: &Node, nb: &Node, t: Real, dt: Real) -> Option<(LawBody, LawBody)> {
    let (ma, mb) = (na.law_mass()?, nb.law_mass()?);
    let la = LawBody {
        mass: ma,
        velocity: na.law_velocity(t, dt),
    };
    let lb = LawBody {
        mass: mb,
        velocity: nb.law_velocity(t, dt),
    };
    if na.dominance == nb.dominance || ma.is_infinite() || mb.is_infinite() {
        return Some((la, lb));
    }
    Some((
        dominate(la, na.dominance, nb.dominance),
        dominate(lb, nb.dominance, na.dominance),
    ))
}

/// The impact of `pair` with impact friction `friction`, each body a node
/// with how the law sees it (dominance applied) as a rigid body at the
/// hit's arm; `None` where the law gives none (the contact points do not
/// approach, or the data cannot enter it).
fn with_friction(
    pair: &Pair,
    bodies: [(&Node, &LawBody); 2],
    law: &Law<Real>,
    friction: &ImpactFriction<Real>,
) -> Option<RigidImpact<Real, DIM>> {
    let rigid = |(node, law): (&Node, &LawBody)| {
        let (velocity, omega) = (to_law(law.velocity), node.body.angvel);
        match law.mass {
            Mass::Finite(m) => LawRigid::new(m, velocity, omega, node.body.inv_inertia),
            Mass::Infinite => LawRigid::immovable(velocity, omega),
        }
    };
    let a = rigid(bodies[0]).ok()?;
    let b = rigid(bodies[1]).ok()?;
    let [arm_a, arm_b] = pair.hit.arms;
    let contact =
        Contact::with_unit_normal(to_law(arm_a), to_law(arm_b), to_law(pair.hit.normal)).ok()?;
    law.resolve_rigid_with_friction(&a, &b, &contact, friction)
}

/// Write node `node`'s rotation back into its body `rb`: the angular
/// velocity and the orientation the changes add by the step's end (rapier
/// turned the body at its own angular velocity over the whole step).
pub(super) fn write_spin(node: &Node, rb: &mut RigidBody) {
    if !node.turned || !finite(&node.body.angvel) || !finite(&node.turn) {
        return;
    }
    set_spin(rb, &node.body.angvel, &node.turn);
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
