//! # kimpact for Bevy
//!
//! A plugin for [bevy_rapier](https://rapier.rs) that replaces rapier's
//! contact impulse response, for the colliders you mark, with kimpact's
//! mass-weighted k-update: a collision law that conserves momentum exactly,
//! never creates energy, and dissipates exactly what you ask for (billiard
//! balls, marbles, Newton's cradle, granular gases).
//!
//! This one source is built as `bevy_kimpact2d` (on bevy_rapier2d and
//! kimpact2d) and `bevy_kimpact3d` (on bevy_rapier3d and kimpact3d), the way
//! rapier, bevy_rapier and kimpact's adapters build theirs; [`bevy_rapier`]
//! and [`kimpact_rapier`] are the crates it was built against.
//!
//! A bevy_rapier app gets kimpact with two changes: [`KimpactPlugin`] in
//! place of `RapierPhysicsPlugin` (it adds bevy_rapier's plugin itself),
//! and [`KimpactCollider`] on the colliders that follow the law:
//!
//! ```text
//!  app.add_plugins((
//!      MinimalPlugins,
//! -    RapierPhysicsPlugin::<NoUserData>::default(),
//! +    KimpactPlugin::default(),
//!  ));
//!  commands.spawn((RigidBody::Dynamic, Collider::ball(0.5), /* … */
//! +    KimpactCollider::default(),
//!  ));
//! ```
//!
//! - [`KimpactPlugin`] adds bevy_rapier's plugin with its systems but its
//!   step, and a step system of its own in [`PhysicsSet::StepSimulation`]:
//!   it steps every rapier context as bevy_rapier would, and runs each
//!   pipeline step of the governed context between kimpact's stages
//!   (every substep, every round of `TimestepMode::Interpolated`). Your own
//!   `BevyPhysicsHooks` go to [`KimpactPlugin::with_hooks`] (named once,
//!   instead of `RapierPhysicsPlugin::<MyHooks>`), bevy_rapier's settings
//!   to [`KimpactPlugin::with_rapier`].
//! - [`KimpactCollider`] on a collider's entity marks it: its contacts with
//!   other marked colliders, and with fixed and kinematic bodies, follow the
//!   law (the settings', or the collider's own [`Material`]). Removing the
//!   component, or despawning the entity, unmarks it.
//! - [`KimpactSettings`] (a resource) chooses the [`Mode`] and the law's
//!   [`LawParams`], and can be changed at any time; the next step uses them.
//! - Every impact the law resolves is sent as an [`ImpactMessage`] naming the
//!   entities of both colliders (and of their bodies); read them with a
//!   `MessageReader<ImpactMessage>`. [`KimpactState`] (a resource) gives the
//!   resolver's totals ([`Stats`]) and the law and mode in force.
//!
//! kimpact governs one rapier context: the one with
//! [`DefaultRapierContext`](bevy_rapier::plugin::DefaultRapierContext) (or
//! the only one); the others step as bevy_rapier steps them. It takes part
//! in every step of `TimestepMode::Fixed`, `Variable` and `Interpolated`,
//! substeps included, in `PostUpdate` or in a fixed schedule
//! ([`KimpactPlugin::in_fixed_schedule`]); a context in
//! `SimulationMode::CollisionOnly` has no contact response to replace.
//!
//! Do not add a `RapierPhysicsPlugin` too: added before [`KimpactPlugin`]
//! (or its step system added by hand), kimpact logs an error and stands
//! aside; added after it with the same hooks type, Bevy refuses it (a
//! panic when the app is built). On frames of several steps, bevy_rapier's
//! `RapierContextSimulation::step_stats` describe the frame's last step (each
//! step is its own `step_simulation` call); the [`ImpactMessage`]s cover
//! every step.
#![warn(missing_docs, missing_debug_implementations)]
#![forbid(unsafe_code)]

#[cfg(not(any(feature = "dim2", feature = "dim3")))]
compile_error!("bevy_kimpact needs the `dim2` or the `dim3` feature");

/// The bevy_rapier crate this plugin was built against (bevy_rapier2d or
/// bevy_rapier3d).
#[cfg(feature = "dim2")]
pub use bevy_rapier2d as bevy_rapier;
/// The bevy_rapier crate this plugin was built against (bevy_rapier2d or
/// bevy_rapier3d).
#[cfg(feature = "dim3")]
pub use bevy_rapier3d as bevy_rapier;

/// kimpact's rapier adapter this plugin was built against (kimpact2d or
/// kimpact3d, f32 as bevy_rapier is).
#[cfg(feature = "dim2")]
pub use kimpact2d as kimpact_rapier;
/// kimpact's rapier adapter this plugin was built against (kimpact2d or
/// kimpact3d, f32 as bevy_rapier is).
#[cfg(feature = "dim3")]
pub use kimpact3d as kimpact_rapier;

pub use kimpact_rapier::{
    FixedPartner, ImpactEvent, LawParams, Material, Mode, ResolverConfig, Stats,
};

mod components;
mod hooks;
mod plugin;
mod state;
mod steps;
mod systems;

pub use components::{ImpactMessage, KimpactCollider, KimpactSettings};
pub use plugin::{KimpactPlugin, KimpactSet};
pub use state::KimpactState;

#[cfg(doc)]
use bevy_rapier::plugin::PhysicsSet;

/// What a kimpact app usually needs: the plugin, the component, the
/// settings, the message, the state and the mode.
pub mod prelude {
    pub use crate::{
        ImpactMessage, KimpactCollider, KimpactPlugin, KimpactSet, KimpactSettings, KimpactState,
        LawParams, Material, Mode,
    };
}
