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
    /// An angular velocity with a NaN or infinite component (always
    /// component 0 in 2D).
    #[error("{which}: angular velocity component {component} must be finite, got {value}")]
    NonFiniteAngularVelocity {
        /// Which body.
        which: Which,
        /// Index of the first bad component.
        component: usize,
        /// The value given.
        value: f64,
    },
    /// An inverse inertia with a NaN or infinite entry (row and column 0 in
    /// 2D). Use a zero inverse inertia for a body that must not turn.
    #[error("{which}: inverse inertia entry ({row}, {column}) must be finite, got {value}")]
    NonFiniteInertia {
        /// Which body.
        which: Which,
        /// Row of the first bad entry.
        row: usize,
        /// Column of the first bad entry.
        column: usize,
        /// The value given.
        value: f64,
    },
    /// An inverse inertia that is negative (2D) or not positive
    /// semidefinite beyond rounding (3D): `value` is the negative inverse
    /// inertia, or the smallest eigenvalue of the 3D matrix.
    #[error("{which}: inverse inertia must be positive semidefinite, has eigenvalue {value}")]
    NegativeInertia {
        /// Which body.
        which: Which,
        /// The negative value or eigenvalue.
        value: f64,
    },
    /// A 3D inverse inertia that is not symmetric beyond rounding (64 ulps
    /// of its largest entry).
    #[error(
        "{which}: inverse inertia must be symmetric, entries ({row}, {column}) and ({column}, {row}) differ by {difference}"
    )]
    AsymmetricInertia {
        /// Which body.
        which: Which,
        /// Row of the upper entry.
        row: usize,
        /// Column of the upper entry.
        column: usize,
        /// The upper entry less the lower one.
        difference: f64,
    },
    /// A contact arm (contact point less a body's centre of mass) with a
    /// NaN or infinite component.
    #[error("{which}: contact arm component {component} must be finite, got {value}")]
    NonFiniteArm {
        /// Which body's arm.
        which: Which,
        /// Index of the first bad component.
        component: usize,
        /// The value given.
        value: f64,
    },
    /// An impact friction parameter out of its range: `impact_friction`
    /// (Coulomb's μ) must be finite and `>= 0`, `tangential_restitution`
    /// (β) in `[−1, 1]`; NaN is neither.
    #[error("{parameter} must be {expected}, got {value}")]
    InvalidFriction {
        /// Which parameter (`impact_friction` or `tangential_restitution`).
        parameter: &'static str,
        /// Its range, in words.
        expected: &'static str,
        /// The value given.
        value: f64,
    },
}
