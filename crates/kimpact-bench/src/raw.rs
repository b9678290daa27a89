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

/// The runs of one scene, size and precision.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Group {
    /// The scene.
    pub scene: Scene,
    /// The precision.
    pub precision: Precision,
    /// Its balls (as asked: a small scene's own count).
    pub balls: usize,
    /// The effects table's configuration (`None`: the matrix's scene).
    #[serde(default)]
    pub effect: Option<Effect>,
    /// Every mode of the table (native first).
    pub modes: Vec<Mode>,
    /// Timing children: native and a mode in lockstep.
    pub pairs: Vec<(Mode, Result<Pair, String>)>,
    /// Memory children: each mode alone.
    pub solos: Vec<(Mode, Result<Solo, String>)>,
}

/// What the table's header says about the run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Header {
    /// The command line, and its options.
    pub command: String,
    /// See `command`.
    pub cli: Cli,
    /// The machine.
    pub machine: String,
    /// Whether rapier's `parallel` feature was on.
    pub parallel: bool,
    /// Wall time of the whole run, s.
    pub wall_s: f64,
}

/// Everything a run measured: `raw.json` in the output folder, from which
/// `--rerender` rebuilds the table, the CSV and the plots.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Raw {
    /// The run.
    pub header: Header,
    /// Its groups.
    pub groups: Vec<Group>,
}
