//! The plain types every kimpact crate shares: the accuracy ladder, the
//! precision of a build, and the resolver's running totals. They are
//! defined once here and re-exported by the rapier adapters (`kimpact3d::Mode`
//! is `kimpact::Mode`), so one value crosses from one adapter crate, or from
//! a scene file, to another without conversion.

use core::fmt;
use core::str::FromStr;

/// How kimpact takes part in a step of a rapier adapter: the accuracy
/// ladder, cheapest first (the order of `Ord`).
///
/// | mode | who finds the impacts | who applies the law | when |
/// | --- | --- | --- | --- |
/// | `Native` | rapier | nobody: rapier unchanged | — |
/// | `Restitution` | rapier (kimpact for bodies fast enough to tunnel) | rapier's solver, with the law's restitution per manifold (kimpact, for those fast bodies) | at detection (at the time of impact) |
/// | `Impulse` | rapier's contacts (kimpact for bodies fast enough to tunnel) | kimpact, in time order | at the analytic time of impact, inside the step |
/// | `Exact` | rapier's contacts and kimpact's sweeps of every body that outruns rapier's prediction distance | kimpact, in time order | at the analytic time of impact, inside the step |
///
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Mode {
    /// rapier unchanged (for comparisons from the same code).
    Native,
    /// The law's effective restitution `e = u'/u` is written into each new
    /// manifold of a marked pair; rapier's solver applies it. Cheapest; exact
    /// for an isolated impact, inherits rapier's errors when contacts are
    /// simultaneous (Newton's cradle). A body that moves more than a
    /// quarter of its size per step (which could sink into a partner by
    /// more than a radius, cross it, or leave its box between two of
    /// rapier's contacts) is the replay's instead: its pairs are resolved
    /// after the step as in `Impulse`.
    Restitution,
    /// The replay of `Exact` on the pairs rapier's contacts hold (and those
    /// of bodies that move more than half their size per step): the law at
    /// each impact's time of impact, in time order, chains through touching
    /// bodies, positions written back. A pair that rapier's contacts did
    /// not reach at the step's start (farther apart than its prediction
    /// distance) is first seen overlapping at the next step and rewound to
    /// its time of impact then; a graze that begins and ends within one
    /// step there is missed. Cheaper than `Exact` where bodies outrun the
    /// prediction distance (a gas), the same where they do not.
    Impulse,
    /// Impacts are resolved in time order inside the step at their analytic
    /// time of impact (with rewinds for pairs first seen overlapping, and
    /// chains through touching bodies), positions written back; every body
    /// that moves more than half rapier's prediction distance per step is
    /// swept, so no impact waits for rapier's contacts.
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

/// The floating-point precision of a build: which rapier crates an adapter
/// links (`kimpact2d`/`kimpact3d`: f32; `kimpact2d-f64`/`kimpact3d-f64`:
/// f64). Each adapter states its own as `math::PRECISION`. Its names are
/// `f32` and `f64` in [`Display`](fmt::Display), [`FromStr`] and serde.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Precision {
    /// `f32`: rapier2d, rapier3d.
    #[default]
    F32,
    /// `f64`: rapier2d-f64, rapier3d-f64.
    F64,
}

impl Precision {
    /// Both precisions, f32 first.
    pub const ALL: [Precision; 2] = [Precision::F32, Precision::F64];

    /// `"f32"` or `"f64"`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}

impl fmt::Display for Precision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown precision name (the name given).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown precision {0:?}: expected \"f32\" or \"f64\"")]
pub struct ParsePrecisionError(pub String);

impl FromStr for Precision {
    type Err = ParsePrecisionError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Precision::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| ParsePrecisionError(s.to_owned()))
    }
}

/// A rapier adapter's running totals since its resolver was built (or
/// reset): the same type in every adapter crate, whatever its dimension
/// and precision.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Impacts resolved by the law.
    pub impacts: u64,
    /// Of which clamped.
    pub clamped: u64,
    /// Total energy dissipated by the law (f64 whatever the precision).
    pub dissipated: f64,
    /// Pairs skipped because a body had a non-finite velocity or mass.
    pub skipped_non_finite: u64,
    /// Exact-mode steps that hit the event cap and handed the rest of the
    /// step to rapier.
    pub event_cap_hits: u64,
    /// Steps taken through kimpact.
    pub steps: u64,
    /// Fast bodies left without the contact hook because every partner
    /// they could touch moved with them (the adapters'
    /// `Config::calm_neighbourhoods`), summed over the steps.
    #[cfg_attr(feature = "serde", serde(default))]
    pub calm_bodies: u64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_errors() {
        for mode in Mode::ALL {
            assert_eq!(mode.to_string().parse::<Mode>(), Ok(mode));
        }
        for p in Precision::ALL {
            assert_eq!(p.to_string().parse::<Precision>(), Ok(p));
        }
        let e = "Exact".parse::<Mode>().unwrap_err();
        assert_eq!(e, ParseModeError("Exact".into()));
        assert!(
            e.to_string()
                .contains("native, restitution, impulse, exact")
        );
        assert!(
            "f16"
                .parse::<Precision>()
                .unwrap_err()
                .to_string()
                .contains("f16")
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
