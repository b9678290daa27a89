//! The constants of one step, fixed when it is prepared.

use crate::math::{Real, Vector};
use crate::rapier::prelude::{IntegrationParameters, RigidBody};

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
    /// rapier's substeps per step (`num_solver_iterations`, at least 1).
    pub substeps: usize,
    /// The velocity every body of a world falling as a whole shares this
    /// step, if it does (see the `shared_frame` module): the sweeps judge a
    /// body's motion against it. `None`: each body's own motion.
    pub shared: Option<Vector>,
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
            substeps: params.num_solver_iterations.max(1),
            shared: None,
        }
    }

    /// Half of body `rb`'s substep, `dt / (2 N)`: rapier integrates a body
    /// in `N` substeps (`num_solver_iterations` plus the body's
    /// `additional_solver_iterations`), each `v += g h; x += v h` with
    /// `h = dt / N`. Its positions then lie on the parabola of gravity
    /// whose velocity is `v + g h / 2` at the same instants: the velocity
    /// whose kinetic energy, with `−m g·x`, rapier's integrator conserves
    /// in free flight.
    pub(crate) fn half_substep(&self, rb: &RigidBody) -> Real {
        let substeps = self.substeps + rb.additional_solver_iterations();
        self.dt / (2.0 * substeps as Real)
    }

    /// `g dt`: what rapier adds to a dynamic body's velocity this step.
    pub(crate) fn gravity_dt(&self) -> Vector {
        self.gravity * self.dt
    }

    /// Path velocity `v` as the sweeps judge it: relative to the shared
    /// frame's velocity if the step has one ([`StepFrame::shared`]).
    #[inline]
    pub(crate) fn relative(&self, v: Vector) -> Vector {
        match self.shared {
            Some(w) => v - w,
            None => v,
        }
    }

    /// How far the shared frame ([`StepFrame::shared`]) moves in `time`
    /// (zero without one). A swept box is built in the frame where it is at
    /// the step's end, as rapier's broad phase holds every other box: a
    /// point at `x` at time `t` is at `x + lag(dt − t)` there, so a body
    /// moving with the frame sweeps a box no longer than its own motion
    /// against it, however fast the world falls.
    #[inline]
    pub(crate) fn lag(&self, time: Real) -> Vector {
        match self.shared {
            Some(w) => w * time,
            None => Vector::ZERO,
        }
    }
}
