//! # kimpact: the mass-weighted k-update collision law
//!
//! The core of kimpact, with no physics-engine dependency: one impact between
//! two bodies, generic over the scalar (`f32`, `f64`) and the dimension (2,
//! 3, any `D`) through nalgebra. An engine integration calls it for the
//! contacts it takes over.
//!
//! For bodies 1 and 2 with masses `m₁, m₂`, velocities `v₁, v₂` and the
//! unit normal `n̄₁` from 1 towards the contact (`n̄₂ = −n̄₁`):
//!
//! ```text
//! v₁' = v₁ + m₂ k n̄₂,      v₂' = v₂ + m₁ k n̄₁,
//! (m₁m₂(m₁+m₂)/2) k² + k m₁m₂ (v₁·n̄₂ + v₂·n̄₁) + d = 0,
//! d = d̃ (m₁+m₂) |v₂ − v₁|²,
//! ```
//!
//! taking the root of larger magnitude, and reducing `d` to `(1 − 1e-6)` of
//! its largest admissible value when the roots would be complex. Momentum is
//! conserved, kinetic energy falls by exactly `d`, `d̃ = 0` is elastic. See
//! [`Law`] for the form in which it is computed (exact to a few ulps across
//! extreme mass ratios) and [`FixedPartner`] for walls.
//!
//! `d̃` is not a restitution coefficient. [`LawParams::from_restitution`]
//! (and [`Law::from_restitution`]) chooses `d̃` and the wall's `d̃_w` from
//! the restitution of two reference impacts (equal masses head-on; head-on
//! against a wall); how the restitution of every other impact follows from
//! the mass ratio and the impact angle is tabulated, and explained, in
//! [`docs/restitution.md`](https://github.com/kimpact/kimpact/blob/main/docs/restitution.md).
//!
//! ```
//! use kimpact::{Body, Law, LawParams};
//! use nalgebra::Vector3;
//!
//! let law = Law::new(LawParams { dissipation: 0.01_f64, ..Default::default() })?;
//! let cue = Body::new(0.17, Vector3::new(2.0, 0.0, 0.0))?;
//! let object = Body::new(0.17, Vector3::zeros())?;
//! // The normal points from the first body towards the second.
//! let impact = law.resolve(&cue, &object, &Vector3::x())?.expect("approaching");
//! let energies = impact.energies(&cue, &object);
//! let lost = energies.before - energies.after;
//! assert!((lost - impact.dissipated).abs() < 1e-12);
//! assert!(impact.restitution < 1.0);
//! # Ok::<(), kimpact::LawError>(())
//! ```
#![warn(missing_docs)]
#![forbid(unsafe_code)]

// The README's examples are tests too (it is the crate's page on crates.io).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

mod body;
mod dim;
mod error;
mod impact;
mod law;
mod mode;
mod num;
mod params;
pub mod prelude;
mod rigid;
mod rigid_law;
mod stats;

pub use body::{Body, Mass};
pub use dim::RigidDim;
pub use error::{LawError, Which};
pub use impact::{Energies, Impact, Restitution};
pub use law::{CLAMP_TOLERANCE, Law};
pub use mode::{Mode, ParseModeError, ParsePrecisionError, Precision};
pub use params::{FixedPartner, LawParams, ParseFixedPartnerError};
pub use rigid::{Angular, Contact, InverseInertia, RigidBody};
pub use rigid_law::RigidImpact;
pub use stats::Stats;

/// Re-export of the nalgebra this crate speaks.
pub use nalgebra;
