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
    /// runs); bodies at rest, a settled pile under gravity among them, sleep
    /// as rapier lets them, and so does any body in `Native` mode. Default
    /// `true`; `false` leaves sleeping to rapier alone.
    #[cfg_attr(feature = "serde-serialize", serde(default = "yes"))]
    pub keep_moving_awake: bool,
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
        }
    }
}

/// An invalid [`ResolverConfig`] field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ResolverConfigError {
    /// `rest_speed` is NaN, infinite or negative.
    #[error("ResolverConfig::rest_speed must be finite and >= 0, got {0}")]
    RestSpeed(Real),
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
        if self.max_events_per_step == 0 {
            return Err(ResolverConfigError::MaxEventsPerStep);
        }
        Ok(())
    }
}
