//! How many pipeline steps bevy_rapier's step system is about to run, and
//! with which integration parameters: the same arithmetic as
//! `RapierContextSimulation::step_simulation`, so that kimpact's stages see
//! the step rapier takes, bit for bit.

use bevy::prelude::Time;

use crate::bevy_rapier::plugin::TimestepMode;
use crate::kimpact_rapier::math::Real;
use crate::kimpact_rapier::rapier::prelude::IntegrationParameters;

/// At most this many steps are counted for `Interpolated` (the count only
/// decides between none, one, and several).
const MAX_COUNTED: usize = 1 << 16;

/// The steps of one run of bevy_rapier's step system.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct PlannedSteps {
    /// Pipeline steps (substeps included).
    pub count: usize,
    /// The integration parameters of each.
    pub parameters: IntegrationParameters,
}

/// The steps bevy_rapier runs for `mode`, from the context's integration
/// parameters, the schedule's `time` and the context's time behind the
/// render (`Interpolated`).
pub(crate) fn planned_steps(
    mode: TimestepMode,
    base: IntegrationParameters,
    time: &Time,
    sim_to_render_diff: f32,
) -> PlannedSteps {
    let mut parameters = base;
    let count = match mode {
        TimestepMode::Fixed { dt, substeps } => {
            parameters.dt = dt / (substeps as Real);
            if parameters.dt > 0.0 { substeps } else { 0 }
        }
        TimestepMode::Variable {
            max_dt,
            time_scale,
            substeps,
        } => {
            parameters.dt = (time.delta_secs() * time_scale).min(max_dt);
            parameters.dt /= substeps as Real;
            if parameters.dt > 0.0 { substeps } else { 0 }
        }
        TimestepMode::Interpolated {
            dt,
            time_scale,
            substeps,
        } => {
            parameters.dt = dt / (substeps as Real) * time_scale;
            let per_round = if parameters.dt > 0.0 { substeps } else { 0 };
            let mut diff = sim_to_render_diff + time.delta_secs();
            let mut rounds = 0usize;
            while diff > 0.0 && rounds < MAX_COUNTED {
                diff -= dt;
                rounds += 1;
            }
            rounds.saturating_mul(per_round)
        }
    };
    PlannedSteps { count, parameters }
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
        let base = IntegrationParameters::default();
        let fixed = planned_steps(
            TimestepMode::Fixed {
                dt: 0.02,
                substeps: 1,
            },
            base,
            &time(0.0),
            0.0,
        );
        assert_eq!((fixed.count, fixed.parameters.dt), (1, 0.02));
        let sub = planned_steps(
            TimestepMode::Fixed {
                dt: 0.02,
                substeps: 4,
            },
            base,
            &time(0.0),
            0.0,
        );
        assert_eq!((sub.count, sub.parameters.dt), (4, 0.02 / 4.0));
        let variable = TimestepMode::Variable {
            max_dt: 1.0 / 60.0,
            time_scale: 1.0,
            substeps: 1,
        };
        assert_eq!(planned_steps(variable, base, &time(0.0), 0.0).count, 0);
        let v = planned_steps(variable, base, &time(0.01), 0.0);
        assert_eq!((v.count, v.parameters.dt), (1, 0.01));
        let capped = planned_steps(variable, base, &time(0.5), 0.0);
        assert_eq!((capped.count, capped.parameters.dt), (1, 1.0 / 60.0));
        let interpolated = TimestepMode::Interpolated {
            dt: 0.01,
            time_scale: 1.0,
            substeps: 1,
        };
        // 0.025 s behind: three rounds of 0.01 (the last one goes ahead).
        assert_eq!(
            planned_steps(interpolated, base, &time(0.025), 0.0).count,
            3
        );
        // Ahead of the render by more than this frame: no step.
        assert_eq!(
            planned_steps(interpolated, base, &time(0.01), -0.02).count,
            0
        );
    }
}
