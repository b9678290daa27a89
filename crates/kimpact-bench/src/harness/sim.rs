//! Every simulator behind one interface, and the reference behind it.

use std::time::Instant;

use kimpact::{Law, LawParams};
use kimpact_reference::Reference;

use crate::{HarnessError, Setup, V};

/// Positions and velocities of the balls, in the order of `Setup::balls`.
pub type State<const D: usize> = Vec<(V<D>, V<D>)>;

/// Running totals since the start.
#[derive(Copy, Clone, Debug)]
pub struct Totals<const D: usize> {
    /// Impacts between two balls.
    pub ball_impacts: u64,
    /// Impacts of a ball on a wall.
    pub wall_impacts: u64,
    /// Normal impulse given to each wall, `[axis][lower, upper]`.
    pub wall_impulse: [[f64; 2]; D],
}

impl<const D: usize> Totals<D> {
    /// No impact yet.
    pub fn zero() -> Self {
        Self {
            ball_impacts: 0,
            wall_impacts: 0,
            wall_impulse: [[0.0; 2]; D],
        }
    }

    /// Impacts of every kind.
    pub fn impacts(&self) -> u64 {
        self.ball_impacts + self.wall_impacts
    }
}

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
    /// The running totals.
    fn totals(&self) -> Totals<D>;
    /// Wall-clock seconds spent advancing, and rapier steps taken.
    fn busy(&self) -> (f64, u64);
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
pub struct RefSim<const D: usize> {
    sim: Reference<D>,
    busy: f64,
}

impl<const D: usize> RefSim<D> {
    /// The reference on the balls and box of `setup`, with its law.
    ///
    /// # Errors
    /// An invalid dissipation, or balls the reference refuses.
    pub fn new(setup: &Setup<D>) -> Result<Self, HarnessError> {
        let law = Law::new(LawParams {
            dissipation: setup.dissipation,
            ..Default::default()
        })?;
        let sim = Reference::new(setup.balls.clone(), setup.bounds, V::zeros(), law)?;
        Ok(Self { sim, busy: 0.0 })
    }
}

impl<const D: usize> Sim<D> for RefSim<D> {
    fn time(&self) -> f64 {
        self.sim.time()
    }

    fn advance_to(&mut self, t: f64) -> Result<(), HarnessError> {
        let start = Instant::now();
        let r = self.sim.advance_to(t);
        self.busy += start.elapsed().as_secs_f64();
        Ok(r?)
    }

    fn state(&self) -> State<D> {
        self.sim
            .balls()
            .iter()
            .map(|b| (b.position, b.velocity))
            .collect()
    }

    fn totals(&self) -> Totals<D> {
        let s = self.sim.stats();
        Totals {
            ball_impacts: s.ball_impacts,
            wall_impacts: s.wall_impacts,
            wall_impulse: s.wall_impulse,
        }
    }

    fn busy(&self) -> (f64, u64) {
        (self.busy, 0)
    }
}
