//! Everything a run measured, as `raw.json` stores it (from which
//! `--rerender` rebuilds the outputs): each child's answer and the groups
//! of children of one configuration.

use serde::{Deserialize, Serialize};

use kimpact::{Mode, Precision};

use crate::cli::{Cli, Effect, Scene};

/// What the measured steps of one world did: their number, the CPU time
/// of the process per step of each sample (µs), the heap allocations (all
/// threads) and the impacts the law resolved.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Measure {
    pub steps: usize,
    pub cpu_us: Vec<f64>,
    pub allocs: u64,
    pub impacts: u64,
    /// With `--stages`, per measured step: kimpact's `before_step`,
    /// rapier's step and kimpact's `after_step` (µs, on the step clock).
    #[serde(default)]
    pub stages_us: Vec<[f64; 3]>,
}

/// A timing child: native's measure and the mode's, in lockstep in one
/// process.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Pair {
    pub native: Measure,
    pub law: Measure,
}

/// A memory child: the allocations of one mode alone in its measured
/// steps, its `VmHWM` after them (KiB) and, from a second pass classifying
/// every allocation, (classified, kimpact's).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Solo {
    pub allocs: u64,
    pub peak_rss_kib: u64,
    pub attributed: Option<(u64, u64)>,
}

/// The runs of one scene, size, precision and effect (`None`: the
/// matrix's scene), of every mode (native first): timing children, then
/// memory children.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Group {
    pub scene: Scene,
    pub precision: Precision,
    pub balls: usize,
    #[serde(default)]
    pub effect: Option<Effect>,
    pub modes: Vec<Mode>,
    pub pairs: Vec<(Mode, Result<Pair, String>)>,
    pub solos: Vec<(Mode, Result<Solo, String>)>,
}

/// What the table's header says about the run: the command line and its
/// options, the machine, whether rapier's `parallel` feature was on, and
/// the run's wall time (s).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Header {
    pub command: String,
    pub cli: Cli,
    pub machine: String,
    pub parallel: bool,
    pub wall_s: f64,
}

/// Everything a run measured: `raw.json` in the output folder.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Raw {
    pub header: Header,
    pub groups: Vec<Group>,
}
