//! What a run gives back, dimension-free and in `f64`: each body's state,
//! the samples of the energies and momenta, the recorded frames and the
//! run's output with its counters.

use crate::scene::Mode;

/// One body's state.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyState {
    /// Centre position.
    pub position: Vec<f64>,
    /// Linear velocity.
    pub velocity: Vec<f64>,
    /// Orientation: 2D `[angle]`, 3D quaternion `[x, y, z, w]`.
    pub rotation: Vec<f64>,
    /// Angular velocity: 2D `[ω]`, 3D `[x, y, z]` (world frame).
    pub angular_velocity: Vec<f64>,
}

/// Totals over the bodies at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Time in seconds.
    pub time: f64,
    /// Kinetic energy of every body (translation, and rotation when `spin`
    /// is active).
    pub kinetic: f64,
    /// Gravitational potential energy `−Σ m g·x` (zero without gravity).
    pub potential: f64,
    /// Momentum of every body.
    pub momentum_all: Vec<f64>,
    /// Momentum of the law bodies.
    pub momentum_law: Vec<f64>,
    /// `Σ m g·v`, the power of gravity: rapier's integrator lags the
    /// potential energy behind the kinetic by `(h/2) Σ m g·v` (see
    /// the report's `Checks::energy_integrator`).
    pub gravity_power: f64,
    /// `Σ m |v|²/2 + Σ m |g·x|` (rotation included with `spin`): the size of
    /// the energies summed, against which the energy balance is judged.
    pub energy_scale: f64,
    /// `Σ m |v|`: the size of the momenta summed.
    pub momentum_scale: f64,
}

/// Every body at one time, for pictures.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Time in seconds.
    pub time: f64,
    /// The bodies, in scene order.
    pub bodies: Vec<BodyState>,
}

/// The outcome of one run.
#[derive(Clone, Debug)]
pub struct RunOutput {
    /// The mode run.
    pub mode: Mode,
    /// Steps taken.
    pub steps: u64,
    /// Masses as simulated (`None` for fixed bodies).
    pub masses: Vec<Option<f64>>,
    /// The bodies at the end, in scene order.
    pub final_bodies: Vec<BodyState>,
    /// Totals at every step (the first at time 0).
    pub samples: Vec<Sample>,
    /// Pictures at the requested steps.
    pub frames: Vec<Frame>,
    /// kimpact's totals (zero in native mode): the adapters' shared type.
    pub stats: kimpact::Stats,
    /// Wall time spent in the physics steps.
    pub wall_seconds: f64,
    /// Deepest contact penetration seen over the run (0 if none).
    pub max_penetration: f64,
    /// The same, relative to the smaller body's smallest half size.
    pub max_penetration_ratio: f64,
    /// Steps in which a pair of balls passed through each other (see
    /// the report's `Checks::crossings`), counted per pair and step.
    pub crossings: u64,
    /// Bodies that got CCD (written in the scene, or chosen by `auto_ccd`).
    pub ccd_bodies: usize,
    /// Of which chosen by the scene's `auto_ccd` rule.
    pub auto_ccd_bodies: usize,
    /// Bodies given soft CCD (`auto_ccd`, native mode).
    pub soft_ccd_bodies: usize,
    /// rapier's `IntegrationParameters::contact_recycling` as run (turned
    /// off with soft CCD).
    pub contact_recycling: bool,
    /// Moving bodies whose rotations were locked (`spin` not active).
    pub locked_rotations: usize,
    /// Bodies whose written friction was set to zero (`friction` not
    /// active).
    pub zeroed_friction: usize,
    /// Joints built.
    pub joints: usize,
    /// Bodies the law governs (marked in every mode; none in native mode,
    /// where kimpact leaves marked pairs to rapier).
    pub law_bodies: usize,
    /// rapier's substeps per step (`IntegrationParameters::num_solver_iterations`).
    pub substeps: usize,
}
