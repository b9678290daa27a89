//! What the tools hand each other: the bench's CSV rows and the accuracy
//! study's summary, serialized and read back with the same types.

use kimpact::{Mode, Precision};
use serde::{Deserialize, Deserializer, Serialize};

/// One row of the bench's `results.csv`: a mode on one scene, size and
/// precision. Times are medians of the process's CPU time per step (µs),
/// pooled over `rounds` timing runs (native's row: every mode's): the
/// mode's and native's in the same processes; `ratio` (×native) is their
/// quotient, `ratio_min`, `ratio_max`, `ratio_median_rounds` the single
/// rounds', `delta_us` their difference. Per measured step: heap
/// allocations (all threads), native's, kimpact's (NaN: not attributed)
/// and the law's impacts; `peak_rss_mib` of the mode running alone.
#[allow(missing_docs)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchRow {
    pub scene: String,
    pub dim: usize,
    pub precision: Precision,
    pub parallel: bool,
    pub balls: usize,
    pub mode: Mode,
    pub rounds: usize,
    pub samples: usize,
    pub median_us: f64,
    pub native_median_us: f64,
    pub ratio: f64,
    pub ratio_min: f64,
    pub ratio_max: f64,
    pub ratio_median_rounds: f64,
    pub delta_us: f64,
    pub allocs_per_step: f64,
    pub native_allocs_per_step: f64,
    pub kimpact_allocs_per_step: f64,
    pub peak_rss_mib: f64,
    pub impacts_per_step: f64,
    pub error: Option<String>,
}

/// One row of the bench's `effects.csv` (`--effects`): a law mode on the
/// effects base of one gas scene with `effect` alone on (`base`: none).
/// Fields as in [`BenchRow`]; `base_delta_us` is the mode's `delta_us` on
/// the base, `effect_us` = `delta_us` − `base_delta_us`.
#[allow(missing_docs)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EffectRow {
    pub effect: String,
    pub scene: String,
    pub precision: Precision,
    pub balls: usize,
    pub mode: Mode,
    pub median_us: f64,
    pub native_median_us: f64,
    pub ratio: f64,
    pub delta_us: f64,
    pub base_delta_us: f64,
    pub effect_us: f64,
    pub kimpact_allocs_per_step: f64,
    pub impacts_per_step: f64,
    pub error: Option<String>,
}

/// One headline error of rapier in one mode and build on one scene of the
/// accuracy study.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    pub quantity: String,
    /// The error against the exact reference (absolute for velocities,
    /// relative otherwise; 0 is exact). NaN is written `null`.
    #[serde(deserialize_with = "number")]
    pub error: f64,
    /// On chaotic scenes, the same quantity between the reference and the
    /// reference from other initial balls (or, for Z, one standard error):
    /// an error below it is noise.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "some_number"
    )]
    pub noise_floor: Option<f64>,
}

/// Everything `accuracy-summary.json` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AccuracySummary {
    /// The command that wrote it.
    #[serde(default)]
    pub command: String,
    /// Whether it was a `--quick` smoke run (its errors mean nothing).
    #[serde(default)]
    pub quick: bool,
    /// The headline errors.
    pub errors: Vec<ErrorRow>,
}

/// A number, `null` (serde_json's NaN) read as NaN.
fn number<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// A present number, `null` read as NaN (an absent one is `None`).
fn some_number<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    number(d).map(Some)
}
