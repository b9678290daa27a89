//! What can go wrong when a scene is built or run.

use kimpact::LawError;
use kimpact_reference::ReferenceError;

/// A scene a simulator refused, or a run that could not go on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HarnessError {
    /// The scene's dissipation gives no valid law.
    #[error("invalid law: {0}")]
    Law(#[from] LawError),
    /// The reference refused the scene or stopped (for instance an
    /// inelastic collapse).
    #[error("{0}")]
    Reference(#[from] ReferenceError),
    /// A lattice with no room for its balls (or with none).
    #[error("{balls} balls do not fit apart on a lattice in the box")]
    Crowded {
        /// How many balls were asked for.
        balls: usize,
    },
    /// The adapter refused to mark a ball's collider (the message of its
    /// error; the four adapter crates have four handle types).
    #[error("could not mark a ball: {0}")]
    Mark(String),
}
