//! The running totals an engine integration keeps of what the law did.

/// An engine integration's running totals since its resolver was built (or
/// reset): one type whatever the integration's dimension and precision.
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
    /// step to the engine.
    pub event_cap_hits: u64,
    /// Steps taken through kimpact.
    pub steps: u64,
    /// Fast bodies left to the engine's own contact response because every
    /// partner they could touch moved with them (where the integration
    /// offers that), summed over the steps.
    #[cfg_attr(feature = "serde", serde(default))]
    pub calm_bodies: u64,
    /// `Σ (asked d − used d)` over the clamped impacts whose ask is finite,
    /// in joules (f64 whatever the precision; never infinite or NaN): the
    /// dissipation the law's formula asked for beyond what the normal
    /// motion held (see [`Impact::unmet_dissipation`]). A clamp from
    /// rounding (`q` a few ulps over 1) adds about `1e-6` of the impact's
    /// normal energy `½ μ u²`; a clamp of the law itself (an oblique impact
    /// under a law for small `e`, an extreme mass ratio) adds a share of
    /// the order of the impact's energy or more. Comparing it with
    /// [`dissipated`](Self::dissipated) tells the two apart.
    ///
    /// [`Impact::unmet_dissipation`]: crate::Impact::unmet_dissipation
    #[cfg_attr(feature = "serde", serde(default))]
    pub unmet_dissipation: f64,
    /// Clamped impacts whose ask was unbounded (a literal wall,
    /// [`FixedPartner::Literal`](crate::FixedPartner::Literal), with
    /// `d̃ > 0`, or `q` beyond the type's range): counted here, not in
    /// [`unmet_dissipation`](Self::unmet_dissipation).
    #[cfg_attr(feature = "serde", serde(default))]
    pub unbounded_clamps: u64,
}

impl Stats {
    /// Account one impact's unmet dissipation (an
    /// [`Impact::unmet_dissipation`](crate::Impact::unmet_dissipation) or a
    /// [`Restitution::unmet_dissipation`](crate::Restitution::unmet_dissipation),
    /// converted to f64): a finite positive value is added to
    /// [`unmet_dissipation`](Self::unmet_dissipation), an infinite one
    /// counts one [`unbounded_clamp`](Self::unbounded_clamps), zero (an
    /// impact that was not clamped) and NaN change nothing.
    ///
    /// ```
    /// let mut stats = kimpact::Stats::default();
    /// stats.record_unmet(0.25);
    /// stats.record_unmet(f64::INFINITY);
    /// stats.record_unmet(0.0);
    /// assert_eq!((stats.unmet_dissipation, stats.unbounded_clamps), (0.25, 1));
    /// ```
    pub fn record_unmet(&mut self, unmet: f64) {
        if unmet.is_finite() {
            if unmet > 0.0 {
                // Saturate rather than overflow: the total stays finite.
                self.unmet_dissipation = (self.unmet_dissipation + unmet).min(f64::MAX);
            }
        } else if unmet > 0.0 {
            self.unbounded_clamps += 1;
        }
    }
}
