//! The constants of one step, fixed when it is prepared.

use crate::math::{Real, Vector};
use crate::rapier::prelude::IntegrationParameters;

/// What a step's stages share: taken from rapier's gravity and integration
/// parameters by [`crate::Kimpact::before_step`].
#[derive(Copy, Clone, Debug)]
pub(crate) struct StepFrame {
    pub gravity: Vector,
    pub dt: Real,
    /// rapier's prediction distance: how far beyond a shape its contacts
    /// reach.
    pub prediction: Real,
    /// Approach speeds at or below this are resting contacts.
    pub rest_speed: Real,
    /// `|g| dt`: the approach speed gravity can add over the step.
    pub gravity_speed: Real,
}

impl StepFrame {
    /// The frame of a step with `gravity` and `params`, the rest speed
    /// `rest_speed` (`None`: `2 |g| dt`).
    pub(crate) fn new(
        gravity: Vector,
        params: &IntegrationParameters,
        rest_speed: Option<Real>,
    ) -> Self {
        let dt = params.dt;
        let g = gravity.length();
        Self {
            gravity,
            dt,
            prediction: params.prediction_distance(),
            rest_speed: rest_speed.unwrap_or(2.0 * g * dt),
            gravity_speed: g * dt,
        }
    }

    /// `g dt`: what rapier adds to a dynamic body's velocity this step.
    pub(crate) fn gravity_dt(&self) -> Vector {
        self.gravity * self.dt
    }
}
