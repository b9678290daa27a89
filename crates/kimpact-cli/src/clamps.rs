//! Why impacts were clamped: the law's own clamps (a law for a small
//! restitution asks oblique impacts for more than their normal motion
//! holds) told from rounding, by the share of the asked dissipation the
//! clamps could not take (`kimpact::Stats::unmet_dissipation`).

use kimpact::Mode;

/// The share of impacts clamped from which a run explains its clamps.
pub const LARGE_SHARE: f64 = 0.1;

/// The share of the asked dissipation left unmet above which the clamps
/// are the law's: a clamp from rounding leaves about `1e-6` of its
/// impact's normal energy unmet, a clamp of the law a share of the order
/// of the impact's energy.
pub const LAW_SHARE: f64 = 1e-4;

/// What the law's statistics say about the clamps of one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clamps {
    /// Impacts resolved by the law.
    pub impacts: u64,
    /// Of which clamped.
    pub clamped: u64,
    /// Energy the law dissipated.
    pub dissipated: f64,
    /// Dissipation the clamps asked for and could not take.
    pub unmet: f64,
    /// Clamps whose ask was unbounded (literal walls).
    pub unbounded: u64,
}

/// Whose clamps they are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    /// The law's formula asked for more than the normal motion held.
    Law,
    /// Walls under `fixed_partner: "literal"` with d̃ > 0: an unbounded ask.
    LiteralWalls,
    /// Impacts on the edge of plastic, pushed over by rounding.
    Rounding,
    /// Clamps with nothing unmet reported: a clamp always leaves at least
    /// `1e-6` of its impact's normal energy unmet, so the integration did
    /// not record it, and whose clamps they are is not known.
    Unreported,
}

impl Clamps {
    /// The statistics of a run.
    pub fn of(stats: &kimpact::Stats) -> Self {
        Self {
            impacts: stats.impacts,
            clamped: stats.clamped,
            dissipated: stats.dissipated,
            unmet: stats.unmet_dissipation,
            unbounded: stats.unbounded_clamps,
        }
    }

    /// The clamped share of the impacts (0 without impacts).
    pub fn share(&self) -> f64 {
        if self.impacts == 0 {
            0.0
        } else {
            self.clamped as f64 / self.impacts as f64
        }
    }

    /// The share of the asked dissipation (`dissipated + unmet`) left
    /// unmet (0 when nothing was asked).
    pub fn unmet_share(&self) -> f64 {
        let asked = self.dissipated + self.unmet;
        if asked > 0.0 { self.unmet / asked } else { 0.0 }
    }

    /// Whose clamps they are, when there are any.
    pub fn cause(&self) -> Option<Cause> {
        if self.clamped == 0 {
            None
        } else if self.unbounded > 0 {
            Some(Cause::LiteralWalls)
        } else if !(self.unmet > 0.0) {
            Some(Cause::Unreported)
        } else if self.unmet_share() > LAW_SHARE {
            Some(Cause::Law)
        } else {
            Some(Cause::Rounding)
        }
    }

    /// A sentence explaining a large clamped share (at least
    /// [`LARGE_SHARE`] of the impacts), naming the mode; `None` otherwise.
    pub fn explain(&self, mode: Mode) -> Option<String> {
        if self.share() < LARGE_SHARE {
            return None;
        }
        let head = format!(
            "{mode}: {} of {} impacts clamped ({:.0}%)",
            self.clamped,
            self.impacts,
            100.0 * self.share()
        );
        let asked = format!(
            "{:.3e} of the {:.3e} asked ({:.2e})",
            self.unmet,
            self.dissipated + self.unmet,
            self.unmet_share()
        );
        Some(match self.cause()? {
            Cause::Law => format!(
                "{head}, the law's own clamps, not a numerical failure: they left {asked} unmet. \
                 The law's d includes the tangential speed, so a law for a small restitution asks an \
                 oblique impact for more than its normal motion holds (equal masses clamp beyond \
                 arcsin(e): every oblique impact for e = 0, beyond 30° for e = 0.5, beyond 64° for \
                 e = 0.9; LawParams::from_restitution, docs/restitution.md); the clamp takes what the \
                 normal motion holds (e = 1e-3). To clamp less, give a larger restitution (a \
                 smaller d̃)."
            ),
            Cause::LiteralWalls => format!(
                "{head}: {} against fixed bodies under `law.fixed_partner: \"literal\"`, whose d \
                 grows without bound with the wall's mass: every such impact with d̃_w > 0 is \
                 plastic. `\"own_mass\"` (the default) gives walls a finite law.",
                self.unbounded
            ),
            Cause::Unreported => format!(
                "{head}: the integration reported no unmet dissipation, so whether the clamps are \
                 the law's (oblique impacts under a law for a small restitution, \
                 LawParams::from_restitution) or rounding is not known."
            ),
            Cause::Rounding => format!(
                "{head}, from rounding: they left only {asked} unmet (a rounding clamp leaves about \
                 1e-6 of its impact's normal energy), impacts on the edge of plastic (e = 0 head-on, \
                 say) that rounding pushed over it. Nothing to do."
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clamps(impacts: u64, clamped: u64, dissipated: f64, unmet: f64, unbounded: u64) -> Clamps {
        Clamps {
            impacts,
            clamped,
            dissipated,
            unmet,
            unbounded,
        }
    }

    #[test]
    fn the_unmet_share_tells_the_law_s_clamps_from_rounding() {
        // e = 0 at 10° for equal masses asks q = 1.03 of the normal energy:
        // 3% of the ask is unmet (the table of LawParams::from_restitution).
        let law = clamps(555, 555, 1.0, 0.03 / 1.03, 0);
        assert_eq!(law.cause(), Some(Cause::Law));
        // A rounding clamp leaves about 1e-6 of the impact's normal energy.
        let rounding = clamps(100, 40, 1.0, 40.0 * 1e-6 * 0.025, 0);
        assert_eq!(rounding.cause(), Some(Cause::Rounding));
        assert_eq!(clamps(10, 3, 1.0, 0.0, 0).cause(), Some(Cause::Unreported));
        assert_eq!(
            clamps(10, 3, 1.0, 0.0, 2).cause(),
            Some(Cause::LiteralWalls)
        );
        assert_eq!(clamps(10, 0, 1.0, 0.0, 0).cause(), None);
    }

    #[test]
    fn only_a_large_share_is_explained_and_the_text_says_what_to_do() {
        let small = clamps(100, 9, 1.0, 0.5, 0);
        assert_eq!(small.explain(Mode::Exact), None);
        let none = clamps(0, 0, 0.0, 0.0, 0);
        assert_eq!(none.explain(Mode::Exact), None);
        let law = clamps(100, 10, 1.0, 0.5, 0).explain(Mode::Impulse).unwrap();
        assert!(
            law.starts_with("impulse: 10 of 100 impacts clamped (10%)"),
            "{law}"
        );
        assert!(
            law.contains("the law's own clamps, not a numerical failure"),
            "{law}"
        );
        assert!(
            law.contains("5.000e-1 of the 1.500e0 asked (3.33e-1)"),
            "{law}"
        );
        assert!(
            law.contains("To clamp less, give a larger restitution"),
            "{law}"
        );
        let rounding = clamps(100, 50, 1.0, 1e-7, 0).explain(Mode::Exact).unwrap();
        assert!(rounding.contains("from rounding"), "{rounding}");
        assert!(rounding.contains("Nothing to do"), "{rounding}");
        let walls = clamps(4, 4, 1.0, 0.0, 4).explain(Mode::Exact).unwrap();
        assert!(walls.contains("\"literal\""), "{walls}");
        assert!(walls.contains("\"own_mass\""), "{walls}");
    }
}
