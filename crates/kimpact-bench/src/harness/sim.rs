//! Every simulator behind one interface, and the reference behind it.

use kimpact::{Law, LawParams};
use kimpact_reference::{Reference, Stats};

use crate::{HarnessError, Setup, State, V};

/// One simulator of a [`Setup`]: the reference or rapier in one mode.
pub trait Sim<const D: usize> {
    /// The simulated time.
    fn time(&self) -> f64;
    /// Advance to time `t` (rapier: to the last whole step not after `t`,
    /// up to the rounding of the step).
    ///
    /// # Errors
    /// The reference's, when it cannot go on (rapier never fails).
    fn advance_to(&mut self, t: f64) -> Result<(), HarnessError>;
    /// Positions and velocities, in the order of `Setup::balls`.
    fn state(&self) -> State<D>;
    /// The running counters: the reference's own, of which rapier fills
    /// the impacts and the wall impulses (the others stay 0).
    fn totals(&self) -> Stats<D>;
    /// Wall-clock milliseconds per rapier step so far (NaN for the
    /// reference, which takes no steps).
    fn ms_per_step(&self) -> f64 {
        f64::NAN
    }
    /// Largest residual of the wall-impulse bookkeeping so far: per step and
    /// axis, the change of the balls' total momentum minus the net wall
    /// impulse, summed, relative to the summed wall impulses (rapier only;
    /// it checks that the impulses used for the pressure are the ones
    /// applied).
    fn impulse_residual(&self) -> f64 {
        0.0
    }
    /// Anything unusual the simulator counted (rapier: the adapter's event
    /// cap hits and pairs skipped for non-finite data).
    fn diagnostics(&self) -> Option<String> {
        None
    }
}

/// The exact reference behind [`Sim`].
pub struct RefSim<const D: usize>(Reference<D>);

impl<const D: usize> RefSim<D> {
    /// The reference on the balls and box of `setup`, with its law.
    ///
    /// # Errors
    /// An invalid dissipation, or balls the reference refuses.
    pub fn new(setup: &Setup<D>) -> Result<Self, HarnessError> {
        let dissipation = setup.dissipation;
        let law = Law::new(LawParams {
            dissipation,
            ..Default::default()
        })?;
        let balls = setup.balls.clone();
        Ok(Self(Reference::new(balls, setup.bounds, V::zeros(), law)?))
    }
}

impl<const D: usize> Sim<D> for RefSim<D> {
    fn time(&self) -> f64 {
        self.0.time()
    }

    fn advance_to(&mut self, t: f64) -> Result<(), HarnessError> {
        Ok(self.0.advance_to(t)?)
    }

    fn state(&self) -> State<D> {
        self.0
            .balls()
            .iter()
            .map(|b| (b.position, b.velocity))
            .collect()
    }

    fn totals(&self) -> Stats<D> {
        *self.0.stats()
    }
}
