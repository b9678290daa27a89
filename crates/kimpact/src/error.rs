//! Typed errors for bad input to the law.

use thiserror::Error;

/// Which of the two bodies of an impact an error is about.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Which {
    /// The first body (`a`, the one the normal points away from).
    First,
    /// The second body (`b`, the one the normal points towards).
    Second,
    /// A body outside an impact (for example while it is being built).
    Body,
}

impl core::fmt::Display for Which {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Which::First => "first body",
            Which::Second => "second body",
            Which::Body => "body",
        })
    }
}

/// Bad input to the law. Every variant names the offending quantity and
/// carries its value (converted to `f64` for the message), so the caller can
/// report exactly what was wrong. The law never answers bad input with NaN.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum LawError {
    /// A mass that is NaN or infinite. (Use [`crate::Body::immovable`] for
    /// fixed and kinematic partners.)
    #[error("{which}: mass must be finite, got {value}")]
    NonFiniteMass {
        /// Which body.
        which: Which,
        /// The value given.
        value: f64,
    },
    /// A mass that is zero or negative.
    #[error("{which}: mass must be positive, got {value}")]
    NonPositiveMass {
        /// Which body.
        which: Which,
        /// The value given.
        value: f64,
    },
    /// A velocity with a NaN or infinite component.
    #[error("{which}: velocity component {component} must be finite, got {value}")]
    NonFiniteVelocity {
        /// Which body.
        which: Which,
        /// Index of the first bad component.
        component: usize,
        /// The value given.
        value: f64,
    },
    /// A contact normal with a NaN or infinite component.
    #[error("normal component {component} must be finite, got {value}")]
    NonFiniteNormal {
        /// Index of the first bad component.
        component: usize,
        /// The value given.
        value: f64,
    },
    /// A contact normal that is zero (no direction).
    #[error("normal must be non-zero")]
    ZeroNormal,
    /// A dissipation constant that is negative, NaN or infinite.
    #[error("{parameter} must be finite and >= 0, got {value}")]
    InvalidDissipation {
        /// Which parameter (`dissipation` or `wall_dissipation`).
        parameter: &'static str,
        /// The value given.
        value: f64,
    },
    /// A restitution coefficient given to
    /// [`crate::LawParams::from_restitution`] that is NaN or outside `[0, 1]`
    /// (the law can only take energy away: `e > 1` has no `d̃ ≥ 0`).
    #[error("{parameter} must be in [0, 1], got {value}")]
    InvalidRestitution {
        /// Which coefficient (`ball_restitution` or `wall_restitution`).
        parameter: &'static str,
        /// The value given.
        value: f64,
    },
    /// A speed given to [`crate::Law::restitution`] that is NaN, infinite or
    /// (for the tangential speed) negative.
    #[error("{quantity} must be finite{}, got {value}", if *.nonnegative { " and >= 0" } else { "" })]
    InvalidSpeed {
        /// Which speed.
        quantity: &'static str,
        /// Whether the quantity must also be non-negative.
        nonnegative: bool,
        /// The value given.
        value: f64,
    },
}
