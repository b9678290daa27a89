//! The accuracy ladder: [`kimpact::Mode`], defined once in the core crate
//! and shared by the four adapter crates, the CLI and the bench.

pub use kimpact::{Mode, ParseModeError};

/// Whether `mode` resolves a step's impacts after rapier's step, by the
/// replay (`Impulse`, `Exact`): the hook then takes the law's pairs from
/// rapier's solver and the bodies' starts are stored.
pub(crate) fn replays(mode: Mode) -> bool {
    matches!(mode, Mode::Impulse | Mode::Exact)
}
