//! # kimpact-reference: an exact event-driven simulator of hard balls
//!
//! Hard disks (`D = 2`) and spheres (`D = 3`, or any `D` up to 16) in an
//! axis-aligned box, optionally under uniform gravity, colliding under the
//! kimpact law ([`kimpact::Law`]). Between impacts every ball moves on its
//! exact ballistic path, and impacts happen at their exact times: this is the
//! ground truth the rapier adapters are compared with, and a fast simulator
//! in its own right (O(log N) work per event; `cargo bench -p
//! kimpact-reference` measures it).
//!
//! ## How it works
//! * **Times of impact** are roots of quadratics, computed in a
//!   cancellation-free form. Two balls falling under the same gravity move
//!   linearly relative to each other, so a ball-ball impact solves
//!   `|r + w t| = R₁ + R₂`; a ball-wall impact (and a cell crossing) solves
//!   `h + s t + ½ g t² = 0` per axis.
//! * **The law** is applied at every impact, with the unit normal from the
//!   first ball to the second; walls are immovable partners
//!   ([`kimpact::Body::immovable`] at rest), so [`kimpact::FixedPartner`]
//!   and the wall dissipation of the law apply.
//! * **One predicted event per ball**: the earliest of its next wall
//!   impact, its next cell crossing and its impacts with its neighbours.
//!   The queue is an indexed 4-ary min-heap with one entry per ball, updated
//!   in place (`O(log N)`) whenever the ball's next event is predicted
//!   again, so it never fills with superseded entries. Invalidation is lazy,
//!   by per-ball impact counters: a pair event records its partner's
//!   counter, and if the partner has had an impact since, the event is found
//!   stale when it comes due and the ball's next event is predicted again.
//! * **A cell list** (a uniform grid whose cells are no smaller than the
//!   largest diameter) limits the search for partners to the `3^D` cells
//!   around a ball; a ball crossing into a new cell is an event of its own,
//!   after which its next event is predicted again. Each event costs
//!   `O(log N)` and a look at the few balls around.
//! * **Balls are advanced lazily**: each stores its position and velocity at
//!   its own last impact, and [`Reference::balls`] presents them at the
//!   current time. The trajectory therefore does not depend on how the
//!   calls to [`Reference::advance_to`] split the time.
//! * **A stall guard** ([`StallGuard`]) turns an inelastic collapse (with
//!   `d̃ > 0`, infinitely many impacts in a finite time) or a ball resting on
//!   a wall under gravity into a [`ReferenceError::Stalled`] instead of a
//!   simulation that never ends.
//!
//! ## Limits
//! * Resting contact is not modelled: a ball that comes to rest on a wall
//!   that gravity pushes it against (or on another ball) is a Zeno point,
//!   reported by the stall guard. Dissipative walls get there quickly under
//!   gravity, since grazing wall impacts are clamped by the law.
//! * Hard-ball dynamics is chaotic: two exact simulations that round
//!   differently part by a factor of order (mean free path / diameter) per
//!   impact. "Exact" means every impact at its time up to rounding, not a
//!   trajectory reproducible by other code over thousands of impacts.
//! * Events at exactly the same time are processed in an unspecified (but
//!   deterministic) order.
//!
//! ```
//! use kimpact::Law;
//! use kimpact_reference::{Ball, BoxBounds, Reference};
//! use nalgebra::Vector2;
//!
//! let balls = vec![
//!     Ball::new(0.1, 1.0, Vector2::new(0.25, 0.5), Vector2::new(1.0, 0.0)),
//!     Ball::new(0.1, 1.0, Vector2::new(0.75, 0.5), Vector2::new(-1.0, 0.0)),
//! ];
//! let bounds = BoxBounds::new(Vector2::zeros(), Vector2::new(1.0, 1.0));
//! let mut sim = Reference::new(balls, bounds, Vector2::zeros(), Law::elastic())?;
//! sim.advance_to(0.2)?;
//! // They met at t = 0.15 (gap 0.3 closed at speed 2) and swapped velocities.
//! assert_eq!(sim.stats().ball_impacts, 1);
//! assert!((sim.balls()[0].position.x - 0.35).abs() < 1e-12);
//! assert!((sim.balls()[0].velocity.x + 1.0).abs() < 1e-12);
//! # Ok::<(), kimpact_reference::ReferenceError>(())
//! ```
#![warn(missing_docs, missing_debug_implementations)]
#![forbid(unsafe_code)]

// The README's examples are tests too (it is the crate's page on crates.io).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

mod error;
mod grid;
mod kinematics;
mod model;
mod queue;
mod sim;

pub use error::{Quantity, ReferenceError};
pub use model::{Ball, BoxBounds, StallGuard, Stats};
pub use sim::{MAX_BALLS, OVERLAP_TOLERANCE, Reference};

/// Re-export of the kimpact law this crate applies.
pub use kimpact;
/// Re-export of the nalgebra this crate speaks.
pub use nalgebra;
