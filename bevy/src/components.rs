//! What a kimpact app puts in its world: the component that marks a
//! collider, the settings resource, and the message each impact sends.

use bevy::prelude::*;

#[cfg(doc)]
use crate::kimpact_rapier::ResolverConfig;
use crate::kimpact_rapier::math::Real;
use crate::kimpact_rapier::{ImpactEvent, LawParams, Material, Mode};
#[cfg(doc)]
use crate::state::KimpactState;

/// Marks the collider of its entity for kimpact: the collider's contacts with
/// other marked colliders (and with fixed and kinematic bodies, see
/// [`ResolverConfig::fixed_partners`]) follow the law. Put it beside bevy_rapier's
/// `Collider`; removing it, or despawning the entity, unmarks the collider.
///
/// `KimpactCollider::default()` follows the law of [`KimpactSettings`];
/// [`KimpactCollider::with_material`] gives the collider a [`Material`] of
/// its own (combined with a partner's as [`Material`] says). Changing the
/// component changes the collider's material from the next step.
#[derive(Component, Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct KimpactCollider {
    /// The collider's own law parameters (`None`: the settings' law).
    pub material: Option<Material>,
}

impl KimpactCollider {
    /// A marker following the law of [`KimpactSettings`] (the same as
    /// `default()`).
    pub const fn new() -> Self {
        Self { material: None }
    }

    /// A marker with the collider's own `material`.
    pub const fn with_material(material: Material) -> Self {
        Self {
            material: Some(material),
        }
    }
}

/// The mode and the law, a resource read before every step: change it at any
/// time, the next step uses it. An invalid law (a negative or non-finite
/// dissipation) is logged and not applied: the last valid one stays in force
/// (see [`KimpactState::law`]).
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct KimpactSettings {
    /// How kimpact takes part in the step (default [`Mode::Exact`]).
    pub mode: Mode,
    /// The law's parameters (default elastic: no dissipation).
    pub law: LawParams<Real>,
}

impl Default for KimpactSettings {
    fn default() -> Self {
        Self {
            mode: Mode::Exact,
            law: LawParams::default(),
        }
    }
}

/// One impact the law resolved, with the entities involved: sent after the
/// step it happened in (read it with `MessageReader<ImpactMessage>`).
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct ImpactMessage {
    /// The entity of the first collider (the normal points away from it).
    pub collider1: Entity,
    /// The entity of the second collider (the normal points towards it).
    pub collider2: Entity,
    /// The entity of the first collider's rigid body (`None` for a collider
    /// without one).
    pub body1: Option<Entity>,
    /// The entity of the second collider's rigid body.
    pub body2: Option<Entity>,
    /// The impact: time within the step, point, normal, impulse, approach
    /// speed, restitution, energy dissipated (its collider handles are
    /// rapier's).
    pub impact: ImpactEvent,
}
