//! The pipeline steps of one frame of bevy_rapier's `TimestepMode`: the
//! same arithmetic as `RapierContextSimulation::step_simulation`, so that
//! the steps the plugin runs one by one are rapier's, bit for bit.

use bevy::prelude::Time;

use crate::bevy_rapier::plugin::TimestepMode;
use crate::kimpact_rapier::math::Real;

/// At most this many rounds are counted for `Interpolated` in one frame.
pub(crate) const MAX_ROUNDS: usize = 1 << 16;

/// The steps of one frame.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct PlannedSteps {
    /// Pipeline steps in all (substeps included).
    pub count: usize,
    /// Steps per round, each of `step_dt`.
    pub substeps: usize,
    /// The `dt` of each step.
    pub step_dt: Real,
    /// The `dt` bevy_rapier leaves in the context's integration parameters.
    pub frame_dt: Real,
    /// `Interpolated`: the mode's `dt`, by which each round brings the
    /// simulation closer to the render (rounds run while it is behind).
    /// Otherwise one round.
    pub round_dt: Option<Real>,
}

/// The steps bevy_rapier runs for `mode`, from the schedule's `time` and
/// the context's time behind the render (`Interpolated`).
pub(crate) fn planned_steps(
    mode: TimestepMode,
    time: &Time,
    sim_to_render_diff: f32,
) -> PlannedSteps {
    let steps = |substeps: usize, step_dt: Real| if step_dt > 0.0 { substeps } else { 0 };
    match mode {
        TimestepMode::Fixed { dt, substeps } => {
            let step_dt = dt / (substeps as Real);
            PlannedSteps {
                count: steps(substeps, step_dt),
                substeps: steps(substeps, step_dt),
                step_dt,
                frame_dt: dt,
                round_dt: None,
            }
        }
        TimestepMode::Variable {
            max_dt,
            time_scale,
            substeps,
        } => {
            let frame_dt = (time.delta_secs() * time_scale).min(max_dt);
            let step_dt = frame_dt / (substeps as Real);
            PlannedSteps {
                count: steps(substeps, step_dt),
                substeps: steps(substeps, step_dt),
                step_dt,
                frame_dt,
                round_dt: None,
            }
        }
        TimestepMode::Interpolated {
            dt,
            time_scale,
            substeps,
        } => {
            let step_dt = dt / (substeps as Real) * time_scale;
            let per_round = steps(substeps, step_dt);
            let mut diff = sim_to_render_diff + time.delta_secs();
            let mut rounds = 0usize;
            // A `dt` that does not bring the simulation closer to the
            // render never ends bevy_rapier's loop: none counted here.
            while dt > 0.0 && diff > 0.0 && rounds < MAX_ROUNDS {
                diff -= dt;
                rounds += 1;
            }
            PlannedSteps {
                count: rounds.saturating_mul(per_round),
                substeps: per_round,
                step_dt,
                frame_dt: dt,
                round_dt: Some(dt),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn time(delta: f32) -> Time {
        let mut t = Time::<()>::default();
        t.advance_by(Duration::from_secs_f32(delta));
        t
    }

    #[test]
    fn fixed_variable_and_interpolated_steps() {
        let fixed = |substeps| TimestepMode::Fixed { dt: 0.02, substeps };
        let one = planned_steps(fixed(1), &time(0.0), 0.0);
        assert_eq!((one.count, one.step_dt, one.frame_dt), (1, 0.02, 0.02));
        let sub = planned_steps(fixed(4), &time(0.0), 0.0);
        assert_eq!((sub.count, sub.substeps), (4, 4));
        assert_eq!((sub.step_dt, sub.frame_dt), (0.02 / 4.0, 0.02));
        assert_eq!(planned_steps(fixed(0), &time(0.0), 0.0).count, 0);
        let variable = |substeps| TimestepMode::Variable {
            max_dt: 1.0 / 60.0,
            time_scale: 1.0,
            substeps,
        };
        assert_eq!(planned_steps(variable(1), &time(0.0), 0.0).count, 0);
        let v = planned_steps(variable(1), &time(0.01), 0.0);
        assert_eq!((v.count, v.step_dt, v.frame_dt), (1, 0.01, 0.01));
        let capped = planned_steps(variable(3), &time(0.5), 0.0);
        assert_eq!((capped.count, capped.frame_dt), (3, 1.0 / 60.0));
        assert_eq!(capped.step_dt, 1.0 / 60.0 / 3.0);
        let interpolated = |dt, substeps| TimestepMode::Interpolated {
            dt,
            time_scale: 1.0,
            substeps,
        };
        // 0.025 s behind: three rounds of 0.01 (the last one goes ahead).
        let i = planned_steps(interpolated(0.01, 2), &time(0.025), 0.0);
        assert_eq!((i.count, i.substeps, i.round_dt), (6, 2, Some(0.01)));
        assert_eq!((i.step_dt, i.frame_dt), (0.005, 0.01));
        // Ahead of the render by more than this frame: no step.
        assert_eq!(
            planned_steps(interpolated(0.01, 1), &time(0.01), -0.02).count,
            0
        );
        // A dt that never catches up: none (bevy_rapier would loop forever).
        assert_eq!(
            planned_steps(interpolated(-0.01, 1), &time(0.01), 0.0).count,
            0
        );
    }
}
