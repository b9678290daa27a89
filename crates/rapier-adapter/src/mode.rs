//! The accuracy ladder: [`kimpact::Mode`], defined once in the core crate
//! and shared by the four adapter crates, the CLI and the bench.

pub use kimpact::{Mode, ParseModeError};

/// Whether `mode` may resolve impacts after rapier's step, by the replay
/// (every law mode: `Impulse` and `Exact` every governed impact,
/// `Restitution` those of bodies too fast for rapier's contacts), so that
/// the bodies' starts are stored.
pub(crate) fn replays(mode: Mode) -> bool {
    mode != Mode::Native
}
