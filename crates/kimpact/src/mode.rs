//! The accuracy ladder ([`Mode`]) an engine integration and its users
//! share. It is defined once here, with no engine in sight, so that one
//! value crosses from one integration crate, or from a scene file, to
//! another without conversion.

use core::fmt;
use core::str::FromStr;

/// How kimpact takes part in a step of an engine integration: the accuracy
/// ladder, cheapest first (the order of `Ord`).
///
/// | mode | who finds the impacts | who applies the law | when |
/// | --- | --- | --- | --- |
/// | `Native` | the engine | nobody: the engine unchanged | — |
/// | `Restitution` | the engine (kimpact for bodies fast enough to tunnel) | the engine's solver, with the law's restitution per contact manifold (kimpact, for those fast bodies) | at detection (at the time of impact) |
/// | `Impulse` | the engine's contacts (kimpact for bodies fast enough to tunnel) | kimpact, in time order | at the analytic time of impact, inside the step |
/// | `Exact` | the engine's contacts and kimpact's sweeps of every body that outruns the engine's contact prediction distance | kimpact, in time order | at the analytic time of impact, inside the step |
///
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Mode {
    /// The engine unchanged (for comparisons from the same code).
    Native,
    /// The law's effective restitution `e = u'/u` is written into each new
    /// manifold of a marked pair; the engine's solver applies it. Cheapest;
    /// exact for an isolated impact, inherits the solver's errors when contacts are
    /// simultaneous (Newton's cradle). A body that moves more than a
    /// quarter of its size per step (which could sink into a partner by
    /// more than a radius, cross it, or leave its box between two of
    /// the engine's contacts) is the integration's instead: its pairs are
    /// resolved after the step as in `Impulse`.
    Restitution,
    /// `Exact`'s resolution on the pairs the engine's contacts hold (and those
    /// of bodies that move more than half their size per step): the law at
    /// each impact's time of impact, in time order, chains through touching
    /// bodies, positions written back. A pair that the engine's contacts did
    /// not reach at the step's start (farther apart than its prediction
    /// distance) is first seen overlapping at the next step and rewound to
    /// its time of impact then; a graze that begins and ends within one
    /// step there is missed. Cheaper than `Exact` where bodies outrun the
    /// prediction distance (a gas), the same where they do not.
    Impulse,
    /// Impacts are resolved in time order inside the step at their analytic
    /// time of impact (with rewinds for pairs first seen overlapping, and
    /// chains through touching bodies), positions written back; every body
    /// that moves more than half the engine's contact prediction distance
    /// per step is swept, so no impact waits for the engine's contacts.
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

/// An unknown mode name (the name given).
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_errors() {
        for mode in Mode::ALL {
            assert_eq!(mode.to_string().parse::<Mode>(), Ok(mode));
        }
        let e = "Exact".parse::<Mode>().unwrap_err();
        assert_eq!(e, ParseModeError("Exact".into()));
        assert!(
            e.to_string()
                .contains("native, restitution, impulse, exact")
        );
    }

    #[test]
    fn the_ladder_is_ordered_cheapest_first() {
        let mut sorted = Mode::ALL;
        sorted.sort();
        assert_eq!(sorted, Mode::ALL);
        assert!(Mode::Native < Mode::Exact);
    }
}
