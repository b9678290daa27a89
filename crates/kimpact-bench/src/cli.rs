//! The command line, the hidden options of a child process included.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64};

use clap::{Parser, ValueEnum};
use kimpact::{Mode, Precision};
use serde::{Deserialize, Serialize};

/// The name of a value on the command line and in the outputs (`gas2d`,
/// `spin`).
pub fn name(value: impl ValueEnum) -> String {
    let value = value.to_possible_value().expect("no value is skipped");
    value.get_name().to_owned()
}

/// The bench scenes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[value(rename_all = "lower")]
pub enum Scene {
    /// 3D ball pit under gravity: mixed masses dropped into a closed box.
    Pit3d,
    /// 2D ball pit under gravity.
    Pit2d,
    /// 3D elastic gas in a closed box (no gravity, no sleeping).
    Gas3d,
    /// 2D elastic gas in a closed box.
    Gas2d,
    /// 2D billiards break: 15 racked balls and the cue ball (16 balls).
    Billiards,
    /// 2D, no gravity: one cue ball moving through resting balls (awake).
    Cue,
    /// 3D, rapier's examples3d/restitution3.rs (22 balls).
    Restitution3,
    /// Its 2D twin, rapier's examples2d/restitution2.rs (22 balls).
    Restitution2,
    /// 2D pinball: 3 balls, a polyline table, bumpers and two flippers.
    Pinball,
    /// 3D dice: 1,000 cubes of two sizes thrown spinning into a closed box.
    Dice,
    /// 2D dominoes: 50 rows of 20 on a floor, each row's first tipped.
    Dominoes,
}

impl Scene {
    /// The scene's dimension.
    pub fn dim(self) -> usize {
        match self {
            Scene::Pit3d | Scene::Gas3d | Scene::Restitution3 | Scene::Dice => 3,
            _ => 2,
        }
    }

    /// The balls of a scene of fixed size (`None`: `--balls` sets it).
    pub fn fixed_balls(self) -> Option<usize> {
        match self {
            Scene::Billiards => Some(16),
            Scene::Restitution3 | Scene::Restitution2 => Some(22),
            Scene::Pinball => Some(3),
            Scene::Dice | Scene::Dominoes => Some(1000),
            _ => None,
        }
    }

    /// A small scene: a step of microseconds, timed by whole blocks.
    pub fn small(self) -> bool {
        matches!(
            self,
            Scene::Billiards | Scene::Restitution3 | Scene::Restitution2 | Scene::Pinball
        )
    }
}

/// A configuration of the effects table (`--effects`): the base (the gas
/// scenes' balls with no effect at all), or the base with one effect on.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[value(rename_all = "lower")]
pub enum Effect {
    /// No effect at all.
    Base,
    /// Gravity, 9.81 m/s² along −y.
    Gravity,
    /// The law's `d̃ = 0.09` (the pits').
    Dissipation,
    /// Friction 0.5 on every ball.
    Friction,
    /// Every ball spinning about z at up to 6 rad/s.
    Spin,
    /// The gas scenes' closed box of fixed walls (with it, the gas scene).
    Walls,
    /// The user reads every impact event after each step (timed).
    Events,
    /// Every ball marked with a material of `d̃ = d̃_w = 0` (only the path
    /// through materials differs).
    Materials,
    /// Spin, every ball marked with a material of `d̃ = d̃_w = 0` and impact
    /// friction `μ = 0.5`, `β = 0`.
    #[serde(rename = "impact_friction")]
    #[value(name = "impact_friction")]
    ImpactFriction,
}

/// `--hook-native` of this process, for the scenes' marked colliders.
pub static HOOK_NATIVE: AtomicBool = AtomicBool::new(false);

/// `--rebound-cutoff` of this process (the bits of an `f64`; 0: off), for
/// the scenes' law worlds.
pub static REBOUND_CUTOFF: AtomicU64 = AtomicU64::new(0);

/// `--no-calm` of this process, for the scenes' law worlds.
pub static NO_CALM: AtomicBool = AtomicBool::new(false);

/// `--rebound-cutoff`'s value: a finite number of rest speeds, `≥ 0`.
fn parse_cutoff(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .parse()
        .map_err(|e| format!("{s:?} is not a number: {e}"))?;
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(format!(
            "the rebound cut-off must be finite and >= 0 rest speeds, got {x}"
        ))
    }
}

/// The kimpact benchmark matrix: time per step against native rapier,
/// memory and allocations, and scaling.
#[derive(Parser, Debug, Clone, Serialize, Deserialize)]
#[command(name = "kimpact-bench", version)]
pub struct Cli {
    /// Scenes to run (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = Scene::value_variants().to_vec())]
    pub scene: Vec<Scene>,
    /// Ball counts for the scenes that scale (all but the small scenes).
    #[arg(long, value_delimiter = ',', default_values_t = [1000usize, 10000])]
    pub balls: Vec<usize>,
    /// Law modes to run; native always runs too (it is the reference).
    #[arg(long, value_delimiter = ',', default_values_t = Mode::ALL)]
    pub mode: Vec<Mode>,
    /// Precisions to run.
    #[arg(long, value_delimiter = ',', default_values_t = Precision::ALL)]
    pub precision: Vec<Precision>,
    /// Measured steps per run.
    #[arg(long, default_value_t = 200)]
    pub steps: usize,
    /// Steps before measuring, in every run.
    #[arg(long, default_value_t = 50)]
    pub warmup: usize,
    /// Steps of the memory runs (each mode alone: peak RSS, attribution).
    #[arg(long, default_value_t = 50)]
    pub memory_steps: usize,
    /// Steps before measuring in the memory runs, when not `--warmup`.
    #[arg(long)]
    pub memory_warmup: Option<usize>,
    /// Timing runs per mode (child processes); the medians pool them.
    #[arg(long, default_value_t = 1)]
    pub rounds: usize,
    /// Steps per block when alternating native and the mode.
    #[arg(long, default_value_t = 10)]
    pub block: usize,
    /// Steps per block in the small scenes, each block timed whole.
    #[arg(long, default_value_t = 100)]
    pub small_block: usize,
    /// Episodes per timing run of a small scene (worlds built anew).
    #[arg(long, default_value_t = 100)]
    pub small_repeats: usize,
    /// Where results.csv, results.md, raw.json and the plots go.
    #[arg(long, default_value = "target/kimpact-bench")]
    pub out: PathBuf,
    /// Skip attributing the memory runs' allocations to kimpact or rapier.
    #[arg(long)]
    pub no_attribute: bool,
    /// Native mode's marked colliders get `MODIFY_SOLVER_CONTACTS` and a
    /// hook that does nothing: what rapier pays for a hooked pair.
    #[arg(long)]
    pub hook_native: bool,
    /// The effects table instead of the matrix: each gas scene of `--scene`
    /// with each effect alone on (see `Effect`), into
    /// `<out>/effects-<scene>/`.
    #[arg(long)]
    pub effects: bool,
    /// Internal: the effects table's configuration to run.
    #[arg(long, hide = true)]
    pub effect: Option<Effect>,
    /// Rebuild the table, CSV and plots from `<out>/raw.json`.
    #[arg(long)]
    pub rerender: bool,
    /// Run each child's steps (native's and the modes') on a rayon pool of
    /// this many threads, timed by the wall clock (builds with the
    /// `parallel` feature).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    pub threads: Option<u16>,
    /// Time kimpact's two stages and rapier's step apart, each on the step
    /// clock: their medians into `stages.md` in `--out`.
    #[arg(long)]
    pub stages: bool,
    /// `ResolverConfig::rebound_cutoff` in every law world, in rest speeds
    /// (`N × 2 |g| dt`; nothing in a scene without gravity).
    #[arg(long, value_parser = parse_cutoff)]
    pub rebound_cutoff: Option<f64>,
    /// `ResolverConfig::calm_neighbourhoods` off in every law world (what
    /// the calm test saves or costs).
    #[arg(long)]
    pub no_calm: bool,
    /// Internal: one timing pair (native and the mode), printed as JSON.
    #[arg(long, hide = true)]
    pub pair: bool,
    /// Internal: one mode alone for memory, printed as JSON.
    #[arg(long, hide = true)]
    pub solo: bool,
    /// Internal (with --solo): run the attribution pass.
    #[arg(long, hide = true)]
    pub attribute: bool,
    /// Internal (with --pair): time each block whole.
    #[arg(long, hide = true)]
    pub time_blocks: bool,
    /// Internal (with --pair): episodes.
    #[arg(long, hide = true, default_value_t = 1)]
    pub repeats: usize,
}
