//! Every simulator behind one interface: who simulates, the exact
//! reference, and what can go wrong.

use kimpact::{Law, LawError, Mode};
use kimpact_reference::{Reference, ReferenceError, Stats};

use crate::scenes::state_of;
use crate::{Setup, State, V};

/// A scene a simulator refused, or a run that could not go on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HarnessError {
    /// The scene's dissipation gives no valid law.
    #[error("invalid law: {0}")]
    Law(#[from] LawError),
    /// The reference refused the scene or stopped (for instance an
    /// inelastic collapse).
    #[error("{0}")]
    Reference(#[from] ReferenceError),
    /// A lattice with no room for its balls (or with none).
    #[error("{balls} balls do not fit apart on a lattice in the box")]
    Crowded {
        /// How many balls were asked for.
        balls: usize,
    },
    /// The adapter refused to mark a ball's collider (the message of its
    /// error; the four adapter crates have four handle types).
    #[error("could not mark a ball: {0}")]
    Mark(String),
}

/// Who simulates: the reference, or rapier in one of the adapter's modes
/// (`kimpact::Mode`, the one type every kimpact crate shares). Ordered
/// reference first, then the modes cheapest first.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Method {
    /// The exact event-driven reference (`kimpact-reference`).
    Reference,
    /// rapier, with kimpact in this mode (`Native`: rapier unchanged).
    Rapier(Mode),
}

impl Method {
    /// rapier in every mode, cheapest first.
    pub const RAPIER: [Method; 4] = [
        Method::Rapier(Mode::Native),
        Method::Rapier(Mode::Restitution),
        Method::Rapier(Mode::Impulse),
        Method::Rapier(Mode::Exact),
    ];
    /// Native rapier.
    pub const NATIVE: Method = Method::Rapier(Mode::Native);

    /// `reference`, or the mode's name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Reference => "reference",
            Method::Rapier(m) => m.name(),
        }
    }

    /// The mode, for rapier.
    pub fn mode(self) -> Option<Mode> {
        match self {
            Method::Reference => None,
            Method::Rapier(m) => Some(m),
        }
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
    /// The running counters: the reference's own, of which rapier fills
    /// the impacts and the wall impulses (the others stay 0).
    fn totals(&self) -> Stats<D>;
    /// Wall-clock milliseconds per rapier step so far (NaN for the
    /// reference, which takes no steps).
    fn ms_per_step(&self) -> f64 {
        f64::NAN
    }
    /// The wall-impulse bookkeeping's residual so far (rapier only): per
    /// step and axis, |Δ momentum − net wall impulse|, summed, over the
    /// summed wall impulses.
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
        let law = Law::with_dissipation(setup.dissipation)?;
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
        state_of(self.0.balls())
    }

    fn totals(&self) -> Stats<D> {
        *self.0.stats()
    }
}
