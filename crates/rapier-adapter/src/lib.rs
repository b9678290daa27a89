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
//! This one source is built as `kimpact2d`, `kimpact3d` (f32, or f64 with the
//! `f64` feature) and `kimpact2d-f64`, `kimpact3d-f64`, the way rapier and
//! parry build theirs; [`rapier`] is the rapier crate it was built against and
//! [`math`] holds the aliases the rest of the code speaks.
//!
//! Adding kimpact to a rapier simulation takes three changes: build a
//! [`Kimpact`] from a [`Law`] and a [`Mode`], [`Kimpact::mark`] the colliders
//! that follow the law, and step through [`Kimpact::step`] (same arguments as
//! `PhysicsPipeline::step`, the pipeline first) or [`Kimpact::step_world`].
//! Everything not marked keeps rapier's behaviour.
#![warn(missing_docs)]
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

pub use kimpact::{FixedPartner, Law, LawError, LawParams};

mod calm;
mod cast;
mod events;
pub mod math;
mod mode;
mod replay;
mod resolver;

pub use events::{ImpactEvent, Stats};
pub use mode::{Mode, ParseModeError};
pub use resolver::{Config, Kimpact};
