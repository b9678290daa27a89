//! The resolver's settings, and their checks.

use crate::math::Real;

/// Tuning of the hand-over between kimpact and rapier. Checked when a
/// [`crate::Kimpact`] is built ([`crate::Kimpact::with_config`]) and when it
/// is changed ([`crate::Kimpact::set_config`]): see [`ResolverConfig::validate`].
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct ResolverConfig {
    /// Normal approach speeds at or below this are resting contacts: rapier
    /// keeps them, with zero restitution (no bounce) in a pair kimpact's hook
    /// sees, and with the colliders' own restitution in a pair of two bodies
    /// it leaves unhooked (two bodies that cannot close on each other faster
    /// than this, as rapier itself would treat them). `None` (the default)
    /// means `2 |g| dt`, the speed gravity gives in two steps, so that piles
    /// rest under rapier's solver and only real impacts reach the law.
    /// Must be finite and `≥ 0`.
    pub rest_speed: Option<Real>,
    /// Whether a marked collider meets fixed and kinematic bodies (walls,
    /// cushions, floors, paddles) through the law, with the law's
    /// [`kimpact::FixedPartner`] policy. Default `true`.
    pub fixed_partners: bool,
    /// The most law impacts resolved in one step (a guard against inelastic
    /// collapse); the rest of the step is left to rapier, counted in
    /// [`crate::Stats::event_cap_hits`] and logged. Must be at least 1.
    pub max_events_per_step: usize,
    /// Leave unhooked a fast body whose every possible partner this step
    /// moves with it (velocities at most the rest speed apart): a pile that
    /// creeps or falls as a whole keeps rapier's contact recycling. Tried
    /// when at least 256 bodies, and one in eight awake bodies, are fast,
    /// and less often where it does not pay (few such bodies, or few
    /// contacts among them, as in a gas). Default `true`; `false` hooks
    /// every body faster than half the rest speed.
    pub calm_neighbourhoods: bool,
    /// Keep a marked body awake while it moves faster than the rest speed.
    /// rapier puts a body to sleep once it has been slower than its
    /// activation threshold for a while (`RigidBodyActivation`, 2 s by
    /// default) and zeroes its velocity then: a slow ball of an elastic gas
    /// (where the rest speed is zero) would lose its energy and momentum.
    /// With this on, kimpact restarts the sleep timer of such a body before
    /// each step (`RigidBody::wake_up(true)`, only for bodies whose timer
    /// runs); bodies at rest, a settled pile under gravity among them, and
    /// bodies with linear damping (whose motion dies out anyway: balls
    /// rolling on a cloth) sleep as rapier lets them, and so does any body
    /// in `Native` mode. Default
    /// `true`; `false` leaves sleeping to rapier alone.
    #[cfg_attr(feature = "serde-serialize", serde(default = "yes"))]
    pub keep_moving_awake: bool,
    /// A cut-off against inelastic collapse in landing piles, after the
    /// contact duration of Luding and McNamara's TC model: a pair the law
    /// has struck already in this step and that meets again approaching
    /// slower than this (a ball rattling between its neighbours in a pile)
    /// is not struck again in this step. Its rebound waits for the next
    /// step, which takes it as it takes any pair: the law's impact when
    /// rapier's contact for it is fresh, rapier's solver with no bounce
    /// when rapier's solver pressed it (see the rest speed). `None` (the
    /// default): every impact the replay finds follows the law at its time.
    ///
    /// It changes such a pair's path (it keeps closing, by at most
    /// `cut-off × dt`, until the next step takes it), which is why it is
    /// off by default; it never touches a pair's first impact in a step,
    /// so a scene without repeated meetings within a step is bit for bit
    /// the same (`docs/benchmarks.md`, *Landings*, measures it in a
    /// landing ball pit). The balls' replay only: the rigid replay strikes
    /// at every meeting. Must be finite and `≥ 0`.
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub rebound_cutoff: Option<Real>,
}

#[cfg(feature = "serde-serialize")]
fn yes() -> bool {
    true
}

impl Default for ResolverConfig {
    fn default() -> Self {
        Self {
            rest_speed: None,
            fixed_partners: true,
            max_events_per_step: 100_000,
            calm_neighbourhoods: true,
            keep_moving_awake: true,
            rebound_cutoff: None,
        }
    }
}

/// An invalid [`ResolverConfig`] field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ResolverConfigError {
    /// `rest_speed` is NaN, infinite or negative.
    #[error("ResolverConfig::rest_speed must be finite and >= 0, got {0}")]
    RestSpeed(Real),
    /// `rebound_cutoff` is NaN, infinite or negative.
    #[error("ResolverConfig::rebound_cutoff must be finite and >= 0, got {0}")]
    ReboundCutoff(Real),
    /// `max_events_per_step` is zero.
    #[error("ResolverConfig::max_events_per_step must be at least 1, got 0")]
    MaxEventsPerStep,
}

impl ResolverConfig {
    /// Check every field.
    ///
    /// # Errors
    /// The first invalid field, as a [`ResolverConfigError`] naming it.
    pub fn validate(&self) -> Result<(), ResolverConfigError> {
        if let Some(r) = self.rest_speed
            && !(r.is_finite() && r >= 0.0)
        {
            return Err(ResolverConfigError::RestSpeed(r));
        }
        if let Some(c) = self.rebound_cutoff
            && !(c.is_finite() && c >= 0.0)
        {
            return Err(ResolverConfigError::ReboundCutoff(c));
        }
        if self.max_events_per_step == 0 {
            return Err(ResolverConfigError::MaxEventsPerStep);
        }
        Ok(())
    }
}
