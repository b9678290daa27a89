//! The accuracy ladder.

use core::fmt;
use core::str::FromStr;

/// How kimpact takes part in a step: the accuracy ladder, cheapest first.
///
/// | mode | who applies the law | when |
/// | --- | --- | --- |
/// | `Native` | nobody: rapier unchanged | — |
/// | `Restitution` | rapier's solver, with the law's restitution per manifold | at detection |
/// | `Impulse` | kimpact, before rapier's step, in time order, velocities only | the step of the impact |
/// | `Exact` | kimpact, in time order, at the analytic time of impact | inside the step |
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
#[cfg_attr(feature = "serde-serialize", serde(rename_all = "snake_case"))]
pub enum Mode {
    /// rapier unchanged (for comparisons from the same code).
    Native,
    /// The law's effective restitution `e = u'/u` is written into each new
    /// manifold of a marked pair; rapier's solver applies it. Cheapest; exact
    /// for an isolated impact, inherits rapier's errors when contacts are
    /// simultaneous (Newton's cradle).
    Restitution,
    /// Before rapier's step, kimpact finds the impacts the marked bodies are
    /// about to have this step (exact linear times of impact, chains through
    /// touching bodies, in time order) and applies the law's velocity
    /// changes; rapier's solver then integrates the new velocities with
    /// every contact in place (the law's pairs separate, so rapier never
    /// bounces them, and still keeps them from overlapping). Velocities are
    /// the law's to rounding; positions are as if each impact happened at the
    /// start of its step (off by at most `|Δv| dt`).
    Impulse,
    /// Impacts are resolved in time order inside the step at their analytic
    /// time of impact (with rewinds for pairs first seen overlapping, and
    /// chains through touching bodies), positions written back.
    #[default]
    Exact,
}

impl Mode {
    /// Every mode, cheapest first.
    pub const ALL: [Mode; 4] = [Mode::Native, Mode::Restitution, Mode::Impulse, Mode::Exact];

    /// The mode's name as in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Native => "native",
            Mode::Restitution => "restitution",
            Mode::Impulse => "impulse",
            Mode::Exact => "exact",
        }
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown mode name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown mode {0:?}: expected one of native, restitution, impulse, exact")]
pub struct ParseModeError(pub String);

impl FromStr for Mode {
    type Err = ParseModeError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Mode::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| ParseModeError(s.to_owned()))
    }
}
