//! `kimpact-bench`: what each accuracy level costs against native rapier.
//!
//! Each law mode of each scene, size and precision gets timing runs (a
//! child process stepping native and the mode in lockstep, in blocks) and a
//! memory run (the mode alone: peak RSS, then its allocations attributed to
//! kimpact or rapier from their stacks). The parent prints a markdown table
//! and writes `results.csv` (rows of [`kimpact_harness::BenchRow`]),
//! `results.md`, `raw.json` and scaling plots. It reports figures and
//! judges none: the targets are in `docs/benchmarks.md`.
// `f64::from(x)` converts in the f32 builds and is the identity in the f64 ones.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

mod alloc;
mod child;
mod effects;
mod memory;
mod raw;
mod report;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use clap::{Parser, ValueEnum};
pub use kimpact::{Mode, Precision};
use serde::{Deserialize, Serialize};

#[global_allocator]
static ALLOCATOR: alloc::Counting = alloc::Counting;

/// The scenes and one measured run, once per adapter crate.
macro_rules! build {
    ($($module:ident: $krate:ident),*) => {$(
        mod $module {
            use $krate as k;
            include!("scene.rs");
            include!("small.rs");
        }
    )*};
}
build!(d2: kimpact2d, d3: kimpact3d, d2_f64: kimpact2d_f64, d3_f64: kimpact3d_f64);

/// The bench scenes.
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, ValueEnum, Serialize, Deserialize,
)]
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
}

impl Scene {
    /// The scene's dimension.
    pub fn dim(self) -> usize {
        match self {
            Scene::Pit3d | Scene::Gas3d | Scene::Restitution3 => 3,
            _ => 2,
        }
    }

    /// The balls of a scene of fixed size (`None`: `--balls` sets it).
    pub fn fixed_balls(self) -> Option<usize> {
        match self {
            Scene::Billiards => Some(16),
            Scene::Restitution3 | Scene::Restitution2 => Some(22),
            Scene::Pinball => Some(3),
            _ => None,
        }
    }

    /// A small scene: a step of microseconds, timed by whole blocks.
    pub fn small(self) -> bool {
        self.fixed_balls().is_some()
    }

    /// The name used on the command line and in the outputs.
    pub fn name(self) -> &'static str {
        match self {
            Scene::Pit3d => "pit3d",
            Scene::Pit2d => "pit2d",
            Scene::Gas3d => "gas3d",
            Scene::Gas2d => "gas2d",
            Scene::Billiards => "billiards",
            Scene::Cue => "cue",
            Scene::Restitution3 => "restitution3",
            Scene::Restitution2 => "restitution2",
            Scene::Pinball => "pinball",
        }
    }
}

/// A configuration of the effects table (`--effects`): its base, the gas
/// scenes' balls with no effect at all (no gravity, `d̃ = 0`, no friction,
/// no spin, no walls, nobody reading the impact events, no material), or
/// the base with one effect on.
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, ValueEnum, Serialize, Deserialize,
)]
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
    /// The gas scenes' closed box of fixed walls (the base with it is the
    /// gas scene).
    Walls,
    /// The user reads every impact event after each step (timed).
    Events,
    /// Every ball marked with its own material (`Kimpact::mark_with`,
    /// `d̃ = d̃_w = 0`, so that only the path through materials differs).
    Materials,
    /// The spin configuration with impact friction switched on: every ball
    /// marked with a material of `d̃ = d̃_w = 0`, `μ = 0.5`, `β = 0`
    /// (`Material::with_impact_friction`). Off, friction is the spin and
    /// materials rows.
    #[serde(rename = "impact_friction")]
    #[value(name = "impact_friction")]
    ImpactFriction,
}

impl Effect {
    /// The name on the command line and in the outputs.
    pub fn name(self) -> String {
        let value = self.to_possible_value().expect("no effect is skipped");
        value.get_name().to_owned()
    }
}

/// An angle or angular velocity about z: a scalar in 2D, a vector in 3D.
pub trait AboutZ<R> {
    /// The angle or angular speed `a` about z.
    fn about_z(a: R) -> Self;
}

macro_rules! about_z {
    ($($t:ty: $r:ty => |$a:ident| $e:expr),*) => {$(
        impl AboutZ<$r> for $t {
            fn about_z($a: $r) -> Self { $e }
        }
    )*};
}
about_z!(f32: f32 => |a| a, f64: f64 => |a| a,
    kimpact3d::math::Vector: f32 => |a| Self::Z * a,
    kimpact3d_f64::math::Vector: f64 => |a| Self::Z * a);

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

/// `--hook-native` of this process (read by the scenes when they build
/// their marked colliders).
static HOOK_NATIVE: AtomicBool = AtomicBool::new(false);

/// Whether `--hook-native` was given.
pub fn hook_native() -> bool {
    HOOK_NATIVE.load(Ordering::Relaxed)
}

/// Sorted, without repeats.
fn set<T: Ord + Copy>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut v: Vec<T> = items.into_iter().collect();
    v.sort_unstable();
    v.dedup();
    v
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    HOOK_NATIVE.store(cli.hook_native, Ordering::Relaxed);
    if cli.threads.is_some() && !cfg!(feature = "parallel") {
        eprintln!("--threads needs a build with the `parallel` feature");
        return ExitCode::FAILURE;
    }
    if cli.pair || cli.solo {
        return child::child_main(&cli);
    }
    if cli.rerender {
        let path = cli.out.join("raw.json");
        let raw = std::fs::read_to_string(&path)
            .map_err(|e| e.to_string())
            .and_then(|s| serde_json::from_str(&s).map_err(|e| e.to_string()));
        return match raw {
            Ok(raw) => render(&cli.out, &raw),
            Err(e) => {
                eprintln!("cannot read {}: {e}", path.display());
                ExitCode::FAILURE
            }
        };
    }
    let modes = set(std::iter::once(Mode::Native).chain(cli.mode.iter().copied()));
    let gas = |s: &Scene| matches!(s, Scene::Gas2d | Scene::Gas3d);
    let scenes = set(cli.scene.iter().copied().filter(|s| !cli.effects || gas(s)));
    let effects: Vec<Option<Effect>> = match cli.effects {
        true => Effect::value_variants().iter().copied().map(Some).collect(),
        false => vec![None],
    };
    if scenes.is_empty() {
        eprintln!("--effects runs on the gas2d and gas3d bases: give one in --scene");
        return ExitCode::FAILURE;
    }
    let started = Instant::now();
    let mut groups = Vec::new();
    for precision in set(cli.precision.iter().copied()) {
        for &scene in &scenes {
            let sizes = scene
                .fixed_balls()
                .map_or_else(|| set(cli.balls.iter().copied()), |n| vec![n]);
            for (balls, &effect) in sizes
                .into_iter()
                .flat_map(|n| effects.iter().map(move |e| (n, e)))
            {
                let progress = |what: &str| {
                    let t = started.elapsed().as_secs_f64();
                    let (p, s) = (precision.name(), scene.name());
                    let e = effect
                        .map(|e| format!(", {}", e.name()))
                        .unwrap_or_default();
                    eprintln!("[{t:>6.1}s] {p} {s} {balls} balls{e}: {what}");
                };
                let (config, cli) = (
                    (scene, balls, precision),
                    Cli {
                        effect,
                        ..cli.clone()
                    },
                );
                groups.push(child::measure_group(&cli, config, &modes, progress));
            }
        }
    }
    let command = std::iter::once("kimpact-bench".to_owned())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let (machine, parallel) = (kimpact_harness::machine(), cfg!(feature = "parallel"));
    let wall_s = started.elapsed().as_secs_f64();
    let header = raw::Header {
        command,
        cli: cli.clone(),
        machine,
        parallel,
        wall_s,
    };
    let raw = raw::Raw { header, groups };
    let json = serde_json::to_string(&raw).expect("the results serialize");
    if let Err(e) = kimpact_harness::write_files(&[(&cli.out.join("raw.json"), json.as_bytes())]) {
        eprintln!("{e}");
    }
    render(&cli.out, &raw)
}

/// The effects tables of `raw` if it holds them, else the matrix's outputs.
fn render(dir: &std::path::Path, raw: &raw::Raw) -> ExitCode {
    match raw.groups.iter().any(|g| g.effect.is_some()) {
        true => effects::render(dir, raw),
        false => report::render(dir, raw),
    }
}
