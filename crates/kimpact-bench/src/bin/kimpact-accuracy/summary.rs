//! The machine-readable summary, `accuracy-summary.json`: the headline
//! errors per scene, build and mode, and the cost of each mode, for a
//! later join with the bench's cost per mode (error against ×native).

use std::path::Path;

use kimpact::{Mode, Precision};
use serde::Serialize;

/// One headline error of rapier in one mode and build on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct ErrorRow {
    /// `one_impact` (masses 1:10, elastic), `one_impact_dissipative` (1:1,
    /// d̃ = 0.05), `cradle`, `gas`, `cooling` or
    /// `compressibility_<D>d_eta<η>`.
    pub scene: String,
    /// 2 or 3.
    pub dimension: usize,
    /// The rapier build's precision.
    pub precision: Precision,
    /// kimpact's mode (`native`: rapier unchanged).
    pub mode: Mode,
    /// The time step is rapier's default divided by this.
    pub dt_div: usize,
    /// What `error` measures (see `docs/accuracy.md`): `velocity_error`,
    /// `energy_error`, `ks_speeds_vs_reference`, `impact_rate_error`,
    /// `worst_energy_deviation` or `single_wall_z_vs_reference`.
    pub quantity: &'static str,
    /// The error against the exact reference (absolute for velocities,
    /// relative otherwise; 0 is exact).
    pub error: f64,
    /// On chaotic scenes, the same quantity between the reference and the
    /// reference from other initial balls (or, for Z, one standard error):
    /// an error below it is noise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise_floor: Option<f64>,
}

/// The cost of one mode in one build: the elastic gas of the cost runs.
#[derive(Clone, Debug, Serialize)]
pub struct CostRow {
    /// 2 or 3.
    pub dimension: usize,
    /// The rapier build's precision.
    pub precision: Precision,
    /// kimpact's mode.
    pub mode: Mode,
    /// The time step is rapier's default divided by this.
    pub dt_div: usize,
    /// Balls of the gas.
    pub balls: usize,
    /// Milliseconds per step (wall clock, one thread).
    pub ms_per_step: f64,
    /// CPU seconds per simulated second.
    pub cpu_s_per_sim_s: f64,
}

/// Everything `accuracy-summary.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The command that wrote it.
    pub command: String,
    /// Whether it was a `--quick` smoke run (reduced scenes).
    pub quick: bool,
    /// The headline errors.
    pub errors: Vec<ErrorRow>,
    /// The cost of each mode.
    pub costs: Vec<CostRow>,
}

/// Write `summary` as pretty JSON to `path`.
///
/// # Errors
/// The file system's.
pub fn write(path: &Path, summary: &Summary) -> std::io::Result<()> {
    let json = serde_json::to_string_pretty(summary).map_err(std::io::Error::other)?;
    std::fs::write(path, json + "\n")
}
