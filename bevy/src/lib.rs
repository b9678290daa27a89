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
//! A bevy_rapier app gets kimpact with three changes:
//!
//! ```text
//!  app.add_plugins((
//! -    RapierPhysicsPlugin::<NoUserData>::default(),
//! +    RapierPhysicsPlugin::<KimpactHooks>::default(),
//! +    KimpactPlugin::default(),
//!  ));
//!  commands.spawn((RigidBody::Dynamic, Collider::ball(0.5), /* … */
//! +    KimpactCollider::default(),
//!  ));
//! ```
//!
//! - [`KimpactPlugin`] runs kimpact's three stages around bevy_rapier's step:
//!   before it (after [`PhysicsSet::SyncBackend`]), inside it (kimpact's
//!   contact hook, through bevy_rapier's hooks parameter [`KimpactHooks`],
//!   which chains your own `BevyPhysicsHooks`: `KimpactHooks<MyHooks>`), and
//!   after it (after [`PhysicsSet::StepSimulation`], before
//!   [`PhysicsSet::Writeback`], so that bevy_rapier writes kimpact's
//!   positions and velocities back to your components).
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
//! the only one). Run [`KimpactPlugin`] in the schedule bevy_rapier runs in
//! ([`KimpactPlugin::in_fixed_schedule`] beside
//! `RapierPhysicsPlugin::in_fixed_schedule`). kimpact takes part in frames
//! where bevy_rapier runs one physics step (`TimestepMode::Fixed` and
//! `Variable` with one substep, the defaults; `Interpolated` on frames with
//! one step); frames of several steps (`substeps > 1`, or `Interpolated`
//! catching up) run rapier's own response, with a warning.
#![warn(missing_docs)]
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

pub use kimpact_rapier::{Config, FixedPartner, ImpactEvent, LawParams, Material, Mode, Stats};

mod hooks;
mod plugin;
mod state;
mod steps;

pub use hooks::KimpactHooks;
pub use plugin::{ImpactMessage, KimpactCollider, KimpactPlugin, KimpactSet, KimpactSettings};
pub use state::KimpactState;

#[cfg(doc)]
use bevy_rapier::plugin::PhysicsSet;

/// What a kimpact app usually needs: the plugin, the hooks parameter, the
/// component, the settings, the message and the mode.
pub mod prelude {
    pub use crate::{
        ImpactMessage, KimpactCollider, KimpactHooks, KimpactPlugin, KimpactSet, KimpactSettings,
        KimpactState, LawParams, Material, Mode,
    };
}
