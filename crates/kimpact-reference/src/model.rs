//! What the reference is given and what it counts: the balls, the box,
//! the statistics of a run and the guard against a run that stalls.

use nalgebra::SVector;

/// One hard ball (a disk in 2D, a sphere in 3D): the input of
/// [`Reference::new`](crate::Reference::new) and its view of the current
/// state.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Ball<const D: usize> {
    /// The radius, finite and positive.
    pub radius: f64,
    /// The mass, finite and positive.
    pub mass: f64,
    /// The position of the centre.
    pub position: SVector<f64, D>,
    /// The velocity.
    pub velocity: SVector<f64, D>,
}

impl<const D: usize> Ball<D> {
    /// A ball (checked only by [`Reference::new`](crate::Reference::new)).
    pub fn new(
        radius: f64,
        mass: f64,
        position: SVector<f64, D>,
        velocity: SVector<f64, D>,
    ) -> Self {
        Self {
            radius,
            mass,
            position,
            velocity,
        }
    }

    /// Kinetic energy `½ m |v|²`.
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass * self.velocity.norm_squared()
    }

    /// Momentum `m v`.
    pub fn momentum(&self) -> SVector<f64, D> {
        self.velocity * self.mass
    }
}

/// An axis-aligned box `[lo, hi]`: its walls are the planes `x_k = lo_k`
/// and `x_k = hi_k`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BoxBounds<const D: usize> {
    /// The lower corner.
    pub lo: SVector<f64, D>,
    /// The upper corner.
    pub hi: SVector<f64, D>,
}

impl<const D: usize> BoxBounds<D> {
    /// The box `[lo, hi]` (checked only by
    /// [`Reference::new`](crate::Reference::new)).
    pub fn new(lo: SVector<f64, D>, hi: SVector<f64, D>) -> Self {
        Self { lo, hi }
    }

    /// The edge lengths `hi − lo`.
    pub fn size(&self) -> SVector<f64, D> {
        self.hi - self.lo
    }
}

/// Counters of what happened since [`Reference::new`](crate::Reference::new).
///
/// Walls are indexed `[axis][side]`, side 0 being the lower wall (`x_k =
/// lo_k`) and side 1 the upper one (`x_k = hi_k`): 4 walls in 2D, 6 in 3D.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Stats<const D: usize> {
    /// Impacts between two balls.
    pub ball_impacts: u64,
    /// Impacts of a ball on a wall.
    pub wall_impacts: u64,
    /// Impacts on each wall, `[axis][side]`.
    pub wall_hits: [[u64; 2]; D],
    /// Total normal impulse `Σ J` given to each wall, `[axis][side]`
    /// (non-negative, pointing out of the box). Divided by the elapsed time
    /// and the wall's area it is the pressure on that wall.
    pub wall_impulse: [[f64; 2]; D],
    /// Impacts (ball or wall) in which the law clamped the dissipation.
    pub clamped: u64,
    /// Kinetic energy dissipated by the law, `Σ d`.
    pub dissipated: f64,
    /// Events at which the law found the pair not approaching (grazing
    /// contacts at rounding level, or a ball at rest on a wall under
    /// gravity); nothing changed at them.
    pub missed: u64,
    /// Cell crossings processed (bookkeeping events of the cell list).
    pub cell_crossings: u64,
    /// Pair events found stale when due (the partner had had an impact
    /// since they were predicted), after which the ball's next event was
    /// predicted again.
    pub stale_events: u64,
    /// How many times the [`StallGuard`] tripped.
    pub stalls: u64,
}

impl<const D: usize> Default for Stats<D> {
    fn default() -> Self {
        Self {
            ball_impacts: 0,
            wall_impacts: 0,
            wall_hits: [[0; 2]; D],
            wall_impulse: [[0.0; 2]; D],
            clamped: 0,
            dissipated: 0.0,
            missed: 0,
            cell_crossings: 0,
            stale_events: 0,
            stalls: 0,
        }
    }
}

impl<const D: usize> Stats<D> {
    /// All impacts, ball-ball and ball-wall.
    pub fn impacts(&self) -> u64 {
        self.ball_impacts + self.wall_impacts
    }
}

/// The guard against a simulation that stalls.
///
/// With `d̃ > 0` a group of balls can undergo infinitely many impacts in a
/// finite time (inelastic collapse), and a ball bouncing on a wall under
/// gravity comes to rest after infinitely many ever smaller bounces; in
/// floating point either ends with events piling up at one instant. The
/// guard counts the events (impacts, wall impacts and cell crossings) whose
/// times lie within `window` of the first event of the current window; when
/// more than `max_events` do,
/// [`Reference::advance_to`](crate::Reference::advance_to) stops there with
/// [`ReferenceError::Stalled`](crate::ReferenceError::Stalled), leaving the
/// simulation consistent at that time (calling it again allows another
/// `max_events` events).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StallGuard {
    /// The width of the time window, in the simulation's time unit. The
    /// default, `1e-12`, suits lengths and speeds of order one.
    pub window: f64,
    /// The most events allowed within one window. Default: one million,
    /// far more than a healthy gas of a million balls produces in `1e-12`
    /// time units (and still a fraction of a second of work).
    pub max_events: u64,
}

impl Default for StallGuard {
    fn default() -> Self {
        Self {
            window: 1e-12,
            max_events: 1_000_000,
        }
    }
}
