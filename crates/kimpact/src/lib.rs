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
//!
//! ## Rigid bodies and impact friction
//!
//! [`Law::resolve_rigid`] applies the same impulse at the contact point of
//! two rotating bodies ([`RigidBody`]: mass, velocity, angular velocity,
//! world inverse inertia; [`Contact`]: the arms from each centre of mass
//! and the normal), with the effective mass `1/m_eff = 1/m₁ + 1/m₂ + a₁ +
//! a₂`, `aᵢ = (rᵢ × n̄)·Iᵢ⁻¹(rᵢ × n̄)`, and `d` measured on the relative
//! velocity of the contact points. [`Law::resolve_rigid_with_friction`]
//! adds Coulomb friction with a tangential restitution
//! ([`ImpactFriction`], Walton's three-parameter model); the kinetic energy
//! never rises. See `docs/rigid.md` and `docs/friction.md`.
//!
//! ```
//! use kimpact::{Contact, ImpactFriction, Law, RigidBody};
//! use kimpact::nalgebra::Vector2;
//!
//! // A rod (m = 2, length 1.5) falls flat-ish onto a fixed floor, its left
//! // end first; the normal points from the rod (a) into the floor (b).
//! let inverse_inertia = 12.0 / (2.0 * 1.5 * 1.5);
//! let rod = RigidBody::new(2.0_f64, Vector2::new(0.5, -3.0), 0.0, inverse_inertia)?;
//! let floor = RigidBody::immovable(Vector2::zeros(), 0.0)?;
//! let contact = Contact::new(Vector2::new(-0.7, -0.2), Vector2::zeros(), -Vector2::y())?;
//! // Without friction the end leaves the floor at its approach speed
//! // (elastic), while the centre may still fall as the rod turns.
//! let law = Law::elastic();
//! let impact = law.resolve_rigid(&rod, &floor, &contact).expect("approaching");
//! let (after, _) = impact.apply(&rod, &floor);
//! assert!((after.point_velocity(contact.arm_a()).y - 3.0).abs() < 1e-12);
//! // With impact friction the end's slip is checked too, and the kinetic
//! // energy (translation and rotation) does not rise.
//! let friction = ImpactFriction::new(0.3, 0.0)?;
//! let impact = law
//!     .resolve_rigid_with_friction(&rod, &floor, &contact, &friction)
//!     .expect("approaching");
//! let (after, _) = impact.apply(&rod, &floor);
//! let energy = |b: &RigidBody<f64, 2>| {
//!     0.5 * 2.0 * b.velocity().norm_squared()
//!         + 0.5 / inverse_inertia * b.angular_velocity().powi(2)
//! };
//! let lost = energy(&rod) - energy(&after);
//! assert!(lost >= 0.0 && (lost - impact.dissipated).abs() < 1e-12);
//! # Ok::<(), kimpact::LawError>(())
//! ```
#![warn(missing_docs, missing_debug_implementations)]
#![forbid(unsafe_code)]

// The README's examples are tests too (it is the crate's page on crates.io).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

mod body;
mod dim;
mod error;
mod friction;
mod impact;
mod law;
mod mode;
mod num;
mod params;
mod precision;
pub mod prelude;
mod rigid;
mod rigid_law;
mod stats;

pub use body::{Body, Mass};
pub use dim::RigidDim;
pub use error::{LawError, Which};
pub use friction::ImpactFriction;
pub use impact::{Energies, Impact, Restitution};
pub use law::{CLAMP_TOLERANCE, Law};
pub use mode::{Mode, ParseModeError};
pub use params::{FixedPartner, LawParams, ParseFixedPartnerError};
pub use precision::{ParsePrecisionError, Precision};
pub use rigid::{Angular, Contact, InverseInertia, RigidBody};
pub use rigid_law::{FrictionRegime, RigidImpact};
pub use stats::Stats;

/// Re-export of the nalgebra this crate speaks.
pub use nalgebra;
