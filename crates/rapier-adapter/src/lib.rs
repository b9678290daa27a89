//! # kimpact for rapier
//!
//! Replace rapier's contact impulse response, for the colliders you mark,
//! with the mass-weighted k-update of [`kimpact`]:
//!
//! ```text
//! v₁' = v₁ + m₂ k n̄₂,   v₂' = v₂ + m₁ k n̄₁,
//! (m₁m₂(m₁+m₂)/2) k² + k m₁m₂ (v₁·n̄₂ + v₂·n̄₁) + d = 0,   d = d̃ (m₁+m₂) |v₂ − v₁|²
//! ```
//!
//! This one source is built as `kimpact2d`, `kimpact3d` (f32) and
//! `kimpact2d-f64`, `kimpact3d-f64` (f64), the way rapier and parry build
//! theirs; [`rapier`] is the rapier crate it was built against and [`math`]
//! holds the aliases the rest of the code speaks.
//!
//! Adding kimpact to a rapier simulation takes three changes: build a
//! [`Kimpact`] from a [`Law`] and a [`Mode`], [`Kimpact::mark`] the colliders
//! that follow the law, and step through [`Kimpact::step`] (same arguments as
//! `PhysicsPipeline::step`, the pipeline first) or [`Kimpact::step_world`].
//! Everything not marked keeps rapier's behaviour. A program that calls
//! `PhysicsPipeline::step` itself runs kimpact's three stages around it:
//! [`Kimpact::before_step`], [`Kimpact::hooks`], [`Kimpact::after_step`].
//! [`prelude`] holds the names these changes use.
#![warn(missing_docs, missing_debug_implementations)]
#![forbid(unsafe_code)]
// One source for f32 and f64: `f64::from(x)` is a conversion in one build
// and the identity in the other.
#![allow(clippy::useless_conversion)]

#[cfg(not(any(feature = "f32", feature = "f64")))]
compile_error!("kimpact's rapier adapter needs the `f32` or the `f64` feature");
#[cfg(not(any(feature = "dim2", feature = "dim3")))]
compile_error!("kimpact's rapier adapter needs the `dim2` or the `dim3` feature");

/// The rapier crate this adapter was built against (rapier2d, rapier3d, or
/// their -f64 twins).
#[cfg(all(feature = "f32", not(feature = "f64")))]
pub extern crate rapier_f32 as rapier;
/// The rapier crate this adapter was built against (rapier2d, rapier3d, or
/// their -f64 twins).
#[cfg(feature = "f64")]
pub extern crate rapier_f64 as rapier;

pub use kimpact::{FixedPartner, ImpactFriction, Law, LawError, LawParams, Precision};

// The module map, from the bottom up (no module imports one above it):
// math, mode, frame, config     plain types (Mode and Stats from the core) and the step's constants
// handle_map                    per-handle storage with generation checks
// material                      law parameters per collider
// body_view, marks, candidates  how the law sees bodies and pairs
// pair_filter                   whether rapier would let a pair touch
// events                        what the stages report
// cast, sweep_grid, leaves      geometry: times of impact, grids, rapier's tree
// rigid_view                    how the law sees a rotating body at a contact
// policy, shared_frame          what a mode does this step; the frame a falling world shares
// calm, prepare                 stage 1: hook flags and starts
// replay                        stages 1 and 3: impacts in time order
// rigid_replay                  stage 3: rigid bodies' impacts in time order
// hook                          stage 2: the contact hook
// snapshot                      the saved form of a resolver's state
// resolver                      Kimpact: the public resolver and its stages
mod body_view;
mod calm;
mod candidates;
mod cast;
mod config;
mod events;
mod frame;
mod handle_map;
mod hook;
mod leaves;
mod marks;
mod material;
pub mod math;
mod mode;
mod pair_filter;
mod policy;
pub mod prelude;
mod prepare;
mod replay;
mod resolver;
mod rigid_replay;
mod rigid_view;
mod shared_frame;
mod snapshot;
mod step_sets;
mod sweep_grid;
#[cfg(test)]
mod test_rng;
mod touches;

pub use config::{ResolverConfig, ResolverConfigError};
pub use events::{ImpactEvent, Stats};
pub use hook::StepHooks;
pub use material::Material;
pub use mode::{Mode, ParseModeError};
pub use resolver::{HandleError, Kimpact, PreparedStep};
pub use snapshot::{Snapshot, SnapshotError};
pub use step_sets::StepSets;
