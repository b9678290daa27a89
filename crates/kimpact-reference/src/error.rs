//! Typed errors for bad input and for a stalled simulation.

use kimpact::LawError;
use thiserror::Error;

/// Which quantity of a ball a [`ReferenceError::NonFinite`] is about.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// The radius.
    Radius,
    /// The mass.
    Mass,
    /// A component of the position.
    Position,
    /// A component of the velocity.
    Velocity,
}

impl core::fmt::Display for Quantity {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Quantity::Radius => "radius",
            Quantity::Mass => "mass",
            Quantity::Position => "position",
            Quantity::Velocity => "velocity",
        })
    }
}

/// Bad input to [`crate::Reference`], or a simulation that cannot go on.
///
/// Every variant names the offending ball (its index in the slice given to
/// [`crate::Reference::new`]), axis or time, and carries the values involved.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ReferenceError {
    /// A radius, mass, position or velocity component that is NaN or
    /// infinite.
    #[error("ball {ball}: {quantity} (component {component}) must be finite, got {value}")]
    NonFinite {
        /// Index of the ball.
        ball: usize,
        /// Which quantity.
        quantity: Quantity,
        /// The component (0 for the radius and the mass).
        component: usize,
        /// The value given.
        value: f64,
    },
    /// A radius that is zero or negative.
    #[error("ball {ball}: radius must be positive, got {value}")]
    NonPositiveRadius {
        /// Index of the ball.
        ball: usize,
        /// The value given.
        value: f64,
    },
    /// A mass that is zero or negative.
    #[error("ball {ball}: mass must be positive, got {value}")]
    NonPositiveMass {
        /// Index of the ball.
        ball: usize,
        /// The value given.
        value: f64,
    },
    /// A box whose bounds are not finite or not ordered (`lo < hi`) on some
    /// axis.
    #[error("box: axis {axis} needs finite lo < hi, got lo = {lo}, hi = {hi}")]
    InvalidBox {
        /// The axis.
        axis: usize,
        /// The lower bound given.
        lo: f64,
        /// The upper bound given.
        hi: f64,
    },
    /// A gravity with a NaN or infinite component.
    #[error("gravity component {component} must be finite, got {value}")]
    NonFiniteGravity {
        /// Index of the component.
        component: usize,
        /// The value given.
        value: f64,
    },
    /// A ball that does not lie inside the box: its centre must satisfy
    /// `lo + radius <= position <= hi - radius` on every axis (touching a
    /// wall is allowed).
    #[error(
        "ball {ball} sticks out of the box on axis {axis}: position {position}, radius {radius}, box [{lo}, {hi}]"
    )]
    OutsideBox {
        /// Index of the ball.
        ball: usize,
        /// The first axis on which it sticks out.
        axis: usize,
        /// Its position on that axis.
        position: f64,
        /// Its radius.
        radius: f64,
        /// The box's lower bound on that axis.
        lo: f64,
        /// The box's upper bound on that axis.
        hi: f64,
    },
    /// Two balls that overlap (centre distance below the sum of the radii;
    /// touching, up to [`crate::OVERLAP_TOLERANCE`], is allowed).
    #[error(
        "balls {first} and {second} overlap: centre distance {distance} < contact distance {contact}"
    )]
    Overlap {
        /// Index of the first ball.
        first: usize,
        /// Index of the second ball.
        second: usize,
        /// Their centre distance.
        distance: f64,
        /// The sum of their radii.
        contact: f64,
    },
    /// More balls than [`crate::MAX_BALLS`].
    #[error("too many balls: {count} > {max}")]
    TooManyBalls {
        /// The number given.
        count: usize,
        /// The largest number allowed.
        max: usize,
    },
    /// A target time that is NaN, infinite or before the current time.
    #[error("cannot advance to time {target} from time {now}")]
    InvalidTime {
        /// The time asked for.
        target: f64,
        /// The simulation's current time.
        now: f64,
    },
    /// The stall guard tripped: more than
    /// [`StallGuard::max_events`](crate::StallGuard::max_events) events
    /// happened within [`StallGuard::window`](crate::StallGuard::window) of
    /// simulated time (inelastic collapse, or a ball resting on a wall under
    /// gravity). The simulation is left consistent at `time`; calling
    /// [`crate::Reference::advance_to`] again goes on for another
    /// `max_events` events.
    #[error("stalled at time {time}: {events} events within a window of {window}")]
    Stalled {
        /// The simulated time reached.
        time: f64,
        /// The number of events that happened in the window.
        events: u64,
        /// The guard's window.
        window: f64,
    },
    /// The law refused a body: only possible if a velocity overflowed.
    #[error("the collision law refused a body: {0}")]
    Law(#[from] LawError),
}
