//! `kimpact-bench`: what each accuracy level costs against native rapier.
//!
//! For every chosen scene, ball count and precision, each law mode gets a
//! timing run: a child process of this binary that builds the scene twice,
//! native and with the mode, and steps the two in lockstep, alternating
//! blocks of steps (native, mode, native, mode…) so that whatever else the
//! machine does hits both alike; the ratio to native comes from that same
//! process. Each mode (native too) then runs alone in another child for its
//! peak resident memory and, in an untimed second pass, the attribution of
//! its heap allocations to kimpact's code or rapier's (from their stacks).
//! The parent prints a markdown table (median time per step, ratio,
//! allocations per step, peak RSS, the budgets of issue 6 as PASS/MISS,
//! scaling slopes) and writes `results.csv`, `results.md` and one
//! `scaling-<scene>-<precision>.svg` per scene with several ball counts.
//! The small scenes (a step of microseconds) are timed by whole blocks of
//! steps over repeated episodes. `--effects` measures instead what each
//! effect costs on a base scene without any (see `effects.rs`).
//!
//! Benchmarks are not tests: nothing here fails on a timing.
// `f64::from(x)` converts in the f32 builds and is the identity in the f64 ones.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

mod alloc;
mod effects;
mod memory;
mod report;

use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use clap::{Parser, ValueEnum};
use serde::{Deserialize, Serialize};

#[global_allocator]
static ALLOCATOR: alloc::Counting = alloc::Counting;

mod d2 {
    use kimpact2d as k;
    include!("scene.rs");
    include!("small.rs");
    include!("effect_scene.rs");
}

mod d3 {
    use kimpact3d as k;
    include!("scene.rs");
    include!("small.rs");
    include!("effect_scene.rs");
}

mod d2_f64 {
    use kimpact2d_f64 as k;
    include!("scene.rs");
    include!("small.rs");
    include!("effect_scene.rs");
}

mod d3_f64 {
    use kimpact3d_f64 as k;
    include!("scene.rs");
    include!("small.rs");
    include!("effect_scene.rs");
}

/// The bench scenes.
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, ValueEnum, Serialize, Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Scene {
    /// 3D ball pit under gravity: mixed masses dropped into a closed box.
    #[value(name = "pit3d")]
    Pit3d,
    /// 2D ball pit under gravity.
    #[value(name = "pit2d")]
    Pit2d,
    /// 3D elastic gas in a closed box (no gravity, no sleeping).
    #[value(name = "gas3d")]
    Gas3d,
    /// 2D elastic gas in a closed box.
    #[value(name = "gas2d")]
    Gas2d,
    /// 2D billiards break: 15 racked balls and the cue ball (16 balls).
    #[value(name = "billiards")]
    Billiards,
    /// 2D, no gravity: one cue ball moving through resting balls (awake).
    #[value(name = "cue")]
    Cue,
    /// 3D, rapier's examples3d/restitution3.rs: 22 balls of restitution
    /// 0..1 dropped on a floor (22 balls).
    #[value(name = "restitution3")]
    Restitution3,
    /// Its 2D twin, rapier's examples2d/restitution2.rs (22 balls).
    #[value(name = "restitution2")]
    Restitution2,
    /// 2D pinball: 3 balls on a tilted table (a polyline outline, fixed
    /// bumpers) and two kinematic flippers swinging periodically.
    #[value(name = "pinball")]
    Pinball,
}

impl Scene {
    /// Every scene, in table order.
    pub const ALL: [Scene; 9] = [
        Scene::Pit3d,
        Scene::Pit2d,
        Scene::Gas3d,
        Scene::Gas2d,
        Scene::Billiards,
        Scene::Cue,
        Scene::Restitution3,
        Scene::Restitution2,
        Scene::Pinball,
    ];

    /// The scene's dimension.
    pub fn dim(self) -> usize {
        match self {
            Scene::Pit3d | Scene::Gas3d | Scene::Restitution3 => 3,
            _ => 2,
        }
    }

    /// The balls of a scene whose size is fixed (`--balls` does not set
    /// it), `None` for the scenes that scale.
    pub fn fixed_balls(self) -> Option<usize> {
        match self {
            Scene::Billiards => Some(16),
            Scene::Restitution3 | Scene::Restitution2 => Some(22),
            Scene::Pinball => Some(3),
            _ => None,
        }
    }

    /// Whether `--balls` sets its size.
    pub fn scales(self) -> bool {
        self.fixed_balls().is_none()
    }

    /// A small scene (the fixed-size ones): a step of a few microseconds,
    /// timed by whole blocks of steps over repeated episodes (see
    /// `--small-block`).
    pub fn small(self) -> bool {
        !self.scales()
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

/// An angular velocity (or rotation) about the z axis, for the scenes'
/// one source: a scalar in 2D, a vector in 3D.
pub trait AboutZ<R> {
    /// The angle or angular speed `a` about z.
    fn about_z(a: R) -> Self;
}

impl AboutZ<f32> for f32 {
    fn about_z(a: f32) -> Self {
        a
    }
}

impl AboutZ<f64> for f64 {
    fn about_z(a: f64) -> Self {
        a
    }
}

impl AboutZ<f32> for kimpact3d::math::Vector {
    fn about_z(a: f32) -> Self {
        Self::Z * a
    }
}

impl AboutZ<f64> for kimpact3d_f64::math::Vector {
    fn about_z(a: f64) -> Self {
        Self::Z * a
    }
}

/// What a measured run builds: a scene of the matrix, or (with `effect`)
/// a configuration of the effects table on the scene's base.
#[derive(Copy, Clone, Debug)]
pub struct Setup {
    pub scene: Scene,
    pub balls: usize,
    pub mode: Mode,
    pub effect: Option<effects::Effect>,
}

/// How a timing run steps its two worlds.
#[derive(Copy, Clone, Debug)]
pub struct Timing {
    /// Steps before measuring, in every episode.
    pub warmup: usize,
    /// Measured steps per episode, per world.
    pub steps: usize,
    /// Steps per block (native's block, then the mode's).
    pub block: usize,
    /// Time each block as a whole (one clock reading per block, the time
    /// per step its time over its steps) instead of each step.
    pub time_blocks: bool,
    /// Episodes: the two worlds are built anew, warmed up and measured this
    /// many times (the scenes are deterministic: each episode repeats the
    /// same steps).
    pub repeats: usize,
}

/// The accuracy ladder and the precision of a run: the core's types, the
/// same in the four adapter crates (serialized as `"exact"`, `"f32"`).
pub use kimpact::{Mode, Precision};

/// A comma-separated list flag of `T`'s names (listed in `--help`), parsed
/// by `T`'s own `FromStr`.
fn names_parser<T, E>(
    names: impl IntoIterator<Item = &'static str>,
) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: std::str::FromStr<Err = E> + Clone + Send + Sync + 'static,
    E: std::error::Error + Send + Sync + 'static,
{
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(names).try_map(|s| s.parse::<T>())
}

/// Which time per step the medians and ratios use (both are recorded).
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Clock {
    /// CPU time of the process during the step (all threads): robust to
    /// other work on a shared machine.
    Cpu,
    /// Wall-clock time of the step.
    Wall,
}

impl Clock {
    /// "cpu" or "wall".
    pub fn name(self) -> &'static str {
        match self {
            Clock::Cpu => "cpu",
            Clock::Wall => "wall",
        }
    }
}

/// What the measured steps of one world did.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Measure {
    pub steps: usize,
    /// Wall time of each measured step, in microseconds.
    pub times_us: Vec<f64>,
    /// CPU time of the process (all threads) during each measured step, in
    /// microseconds.
    pub cpu_us: Vec<f64>,
    /// Heap allocations during the measured steps (all threads).
    pub allocs: u64,
    /// Bytes requested by those allocations.
    pub alloc_bytes: u64,
    /// Impacts the law resolved during the measured steps.
    pub impacts: u64,
    pub cap_hits: u64,
    pub skipped: u64,
    /// Kinetic + potential energy (from the floor) at the start and the end
    /// of the measured steps.
    pub energy_start: f64,
    pub energy_end: f64,
    pub non_finite: usize,
    pub escaped: usize,
    pub awake_end: usize,
}

/// A timing child: native and one mode, in lockstep in one process.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Pair {
    pub scene: Scene,
    /// Dynamic balls in the scene.
    pub balls: usize,
    pub mode: Mode,
    pub precision: Precision,
    /// Whether rapier's `parallel` feature was on.
    pub parallel: bool,
    pub warmup: usize,
    pub block: usize,
    /// Whether each block was timed whole (a sample per block).
    #[serde(default)]
    pub time_blocks: bool,
    /// Episodes measured (each built anew).
    #[serde(default)]
    pub repeats: usize,
    /// The configuration of the effects table, if this is one.
    #[serde(default)]
    pub effect: Option<effects::Effect>,
    pub native: Measure,
    pub law: Measure,
}

/// A memory child: one mode alone, its peak RSS and the attribution of its
/// allocations.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Solo {
    pub scene: Scene,
    pub balls: usize,
    pub mode: Mode,
    pub precision: Precision,
    pub steps: usize,
    /// The configuration of the effects table, if this is one.
    #[serde(default)]
    pub effect: Option<effects::Effect>,
    /// Allocations during the measured steps (untimed run).
    pub allocs: u64,
    /// `VmHWM` after warm-up and the measured steps, KiB.
    pub peak_rss_kib: u64,
    /// Whether a second pass attributed the allocations from their stacks.
    pub attributed: bool,
    /// Allocations during that pass's measured steps, how many were
    /// classified (all of them since d70b4d1; earlier runs' raw.json
    /// sampled about 1,000), and how many of these were kimpact's own.
    pub attr_seen: u64,
    pub attr_sampled: u64,
    pub attr_own: u64,
    /// Distinct stacks among the classified allocations.
    #[serde(default)]
    pub attr_stacks: u64,
}

/// The kimpact benchmark matrix: time per step against native rapier,
/// memory and allocations, scaling, and the budgets of the issue.
#[derive(Parser, Debug)]
#[command(name = "kimpact-bench", version)]
pub(crate) struct Cli {
    /// Scenes to run (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = Scene::ALL)]
    pub(crate) scene: Vec<Scene>,
    /// Ball counts for the scenes that scale (all but billiards).
    #[arg(long, value_delimiter = ',', default_values_t = [1000usize, 10000])]
    pub(crate) balls: Vec<usize>,
    /// Add the 100,000-ball size (slow: minutes per scene).
    #[arg(long)]
    pub(crate) big: bool,
    /// Law modes to run; native always runs too (it is the reference).
    #[arg(long, value_parser = names_parser::<Mode, _>(Mode::ALL.map(Mode::name)), value_delimiter = ',', default_values_t = Mode::ALL)]
    pub(crate) mode: Vec<Mode>,
    /// Precisions to run.
    #[arg(long, value_parser = names_parser::<Precision, _>(Precision::ALL.map(Precision::name)), value_delimiter = ',', default_values_t = Precision::ALL)]
    pub(crate) precision: Vec<Precision>,
    /// Measured steps per run (the budgets need at least 200).
    #[arg(long, default_value_t = 200)]
    pub(crate) steps: usize,
    /// Steps of the memory runs (each mode alone: peak RSS, and the
    /// attribution of allocations), after the warm-up (`--memory-warmup`).
    #[arg(long, default_value_t = 50)]
    pub(crate) memory_steps: usize,
    /// Steps before measuring, in every run.
    #[arg(long, default_value_t = 50)]
    pub(crate) warmup: usize,
    /// Steps before measuring in the memory runs (peak RSS and the
    /// attribution of allocations), when not `--warmup`: a long one
    /// (600) reaches the steady state in which kimpact allocates nothing.
    #[arg(long)]
    pub(crate) memory_warmup: Option<usize>,
    /// Timing runs per mode (each a child process running native and the
    /// mode in lockstep); the medians pool them.
    #[arg(long, default_value_t = 1)]
    pub(crate) rounds: usize,
    /// Steps per block when alternating native and the mode in a timing run
    /// of a scene that scales (each step timed).
    #[arg(long, default_value_t = 10)]
    pub(crate) block: usize,
    /// Steps per block in the small scenes (billiards, restitution3,
    /// restitution2, pinball), each block timed whole: a step of a few
    /// microseconds is too short to time alone.
    #[arg(long, default_value_t = 100)]
    pub(crate) small_block: usize,
    /// Episodes per timing run of a small scene: both worlds are built anew,
    /// warmed up and measured this many times, for enough blocks.
    #[arg(long, default_value_t = 100)]
    pub(crate) small_repeats: usize,
    /// Measure the effects table instead of the matrix: on the base scene
    /// (the first of `--scene`, gas3d or gas2d; the first of `--balls`,
    /// `--precision`), each effect on and off, in every law mode; writes
    /// effects.md, effects.csv and effects-raw.json into `--out`.
    #[arg(long)]
    pub(crate) effects: bool,
    /// Internal (with --pair/--solo): time each block whole.
    #[arg(long, hide = true)]
    pub(crate) time_blocks: bool,
    /// Internal (with --pair): episodes.
    #[arg(long, hide = true, default_value_t = 1)]
    pub(crate) repeats: usize,
    /// Internal (with --pair/--solo): a configuration of the effects table.
    #[arg(long, hide = true, value_enum)]
    pub(crate) effect: Option<effects::Effect>,
    /// Which time the medians and ratios use: process CPU time (default;
    /// the machine may be shared) or wall time. Both go in the CSV.
    #[arg(long, value_enum, default_value_t = Clock::Cpu)]
    pub(crate) clock: Clock,
    /// Where results.csv, results.md and the plots go.
    #[arg(long, default_value = "target/kimpact-bench")]
    pub(crate) out: PathBuf,
    /// Seconds before a child run is killed and reported as timed out.
    #[arg(long, default_value_t = 600)]
    pub(crate) timeout: u64,
    /// Skip the untimed pass that attributes the heap allocations of the
    /// measured steps to kimpact or rapier from their stacks (every one
    /// classified; each distinct stack symbolized once).
    #[arg(long)]
    pub(crate) no_attribute: bool,
    /// Switch off kimpact's calm-neighbourhood test
    /// (`Config::calm_neighbourhoods`): every body faster than half the rest
    /// speed carries the contact hook, as before the test existed. To
    /// measure what the test buys.
    #[arg(long)]
    pub(crate) no_calm: bool,
    /// Give native mode's marked colliders rapier's
    /// `ActiveHooks::MODIFY_SOLVER_CONTACTS` with a hook that does nothing:
    /// what rapier itself pays for a hooked pair (no contact recycling, the
    /// hook's call), the floor of a law mode that hooks every marked
    /// collider. It changes the native world of every timing run too, so
    /// compare its `--solo --mode native` runs (under callgrind, say) with
    /// those without it.
    #[arg(long)]
    pub(crate) hook_native: bool,
    /// Internal (with --solo): run the attribution pass.
    #[arg(long, hide = true)]
    pub(crate) attribute: bool,
    /// Rebuild the table, CSV and plots from `<out>/raw.json` of an earlier
    /// run, without running anything.
    #[arg(long)]
    pub(crate) rerender: bool,
    /// Internal: run one timing pair (native and the first mode) in this
    /// process and print it as JSON.
    #[arg(long, hide = true)]
    pub(crate) pair: bool,
    /// Internal: run one mode alone for memory (and attribution with
    /// --attribute) and print it as JSON.
    #[arg(long, hide = true)]
    pub(crate) solo: bool,
}

/// The children of one scene, size and precision: `--rounds` timing pairs
/// of each of `timed` (native and the mode in lockstep), then one run of
/// each of `modes` alone (with the attribution of allocations unless
/// `--no-attribute`), every child given `extra` after its usual arguments.
/// `progress` hears of each child before it runs, with what it is
/// ("timing native +", or `alone` for a mode alone). A child that fails is
/// reported on stderr and kept as its error.
pub(crate) fn measure_group(
    cli: &Cli,
    (scene, balls, precision): (Scene, usize, Precision),
    modes: &[Mode],
    timed: &[Mode],
    extra: &[String],
    alone: &str,
    progress: impl Fn(&str, Mode),
) -> report::Group {
    let with_extra = |mut args: Vec<String>| {
        args.extend(extra.iter().cloned());
        args
    };
    let mut pairs = Vec::new();
    for _ in 0..cli.rounds.max(1) {
        for &mode in timed {
            progress("timing native +", mode);
            let args = child_args(cli, "--pair", scene, balls, mode, precision);
            let pair = spawn_child::<Pair>(cli, &with_extra(args));
            if let Err(e) = &pair {
                eprintln!("    failed: {e}");
            }
            pairs.push((mode, pair));
        }
    }
    let mut solos = Vec::new();
    for &mode in modes {
        progress(alone, mode);
        let mut args = child_args(cli, "--solo", scene, balls, mode, precision);
        if !cli.no_attribute {
            args.push("--attribute".to_owned());
        }
        let solo = spawn_child::<Solo>(cli, &with_extra(args));
        if let Err(e) = &solo {
            eprintln!("    failed: {e}");
        }
        solos.push((mode, solo));
    }
    report::Group {
        clock: cli.clock,
        parallel: cfg!(feature = "parallel"),
        scene,
        precision,
        balls,
        modes: modes.to_vec(),
        pairs,
        solos,
    }
}

/// A child process of this binary, its JSON answer parsed; `Err` with the
/// reason when it failed (a panic, a timeout, no answer).
pub(crate) fn spawn_child<T: serde::de::DeserializeOwned>(
    cli: &Cli,
    args: &[String],
) -> Result<T, String> {
    let exe = std::env::current_exe().map_err(|e| format!("no executable path: {e}"))?;
    let mut child = Command::new(exe)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start a child: {e}"))?;
    let mut stdout = child.stdout.take().expect("piped");
    let mut stderr = child.stderr.take().expect("piped");
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stdout.read_to_string(&mut s);
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if start.elapsed() > Duration::from_secs(cli.timeout) => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(format!("waiting for the child: {e}")),
        }
    };
    let out = out.join().unwrap_or_default();
    let err = err.join().unwrap_or_default();
    match status {
        None => Err(format!("timed out after {} s", cli.timeout)),
        Some(s) if !s.success() => {
            let lines = err
                .lines()
                .filter(|l| !l.trim().is_empty())
                .take(3)
                .collect::<Vec<_>>()
                .join(" | ");
            Err(format!("child failed ({s}): {lines}"))
        }
        Some(_) => match out.lines().rev().find(|l| l.starts_with('{')) {
            Some(line) => {
                serde_json::from_str(line).map_err(|e| format!("unreadable child output: {e}"))
            }
            None => Err("the child printed no result".to_owned()),
        },
    }
}

/// The arguments of a child for one configuration.
pub(crate) fn child_args(
    cli: &Cli,
    kind: &str,
    scene: Scene,
    balls: usize,
    mode: Mode,
    precision: Precision,
) -> Vec<String> {
    let steps = if kind == "--solo" {
        cli.memory_steps
    } else {
        cli.steps
    };
    let mut args: Vec<String> = [
        kind,
        "--scene",
        scene.name(),
        "--mode",
        mode.name(),
        "--precision",
        precision.name(),
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    let small = scene.small();
    let warmup = match kind {
        "--solo" => cli.memory_warmup.unwrap_or(cli.warmup),
        _ => cli.warmup,
    };
    let (block, repeats) = match (small, kind) {
        (true, "--pair") => (cli.small_block, cli.small_repeats),
        (true, _) => (cli.small_block, 1),
        (false, _) => (cli.block, 1),
    };
    for (flag, value) in [
        ("--balls", balls),
        ("--steps", steps),
        ("--warmup", warmup),
        ("--block", block),
        ("--repeats", repeats),
    ] {
        args.push(flag.to_owned());
        args.push(value.to_string());
    }
    if small {
        args.push("--time-blocks".to_owned());
    }
    if cli.no_calm {
        args.push("--no-calm".to_owned());
    }
    if cli.hook_native {
        args.push("--hook-native".to_owned());
    }
    args
}

/// `--no-calm` of this process (read by the scenes when they build their
/// resolver).
static NO_CALM: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether `--no-calm` was given.
pub fn no_calm() -> bool {
    NO_CALM.load(std::sync::atomic::Ordering::Relaxed)
}

/// `--hook-native` of this process (read by the scenes when they build
/// their marked colliders).
static HOOK_NATIVE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether `--hook-native` was given.
pub fn hook_native() -> bool {
    HOOK_NATIVE.load(std::sync::atomic::Ordering::Relaxed)
}

/// In a child: run what `--pair` or `--solo` asks and print it as JSON.
fn child_main(cli: &Cli) -> ExitCode {
    let (Some(&scene), Some(&balls), Some(&mode), Some(&precision)) = (
        cli.scene.first(),
        cli.balls.first(),
        cli.mode.first(),
        cli.precision.first(),
    ) else {
        eprintln!("--pair/--solo need a scene, a ball count, a mode and a precision");
        return ExitCode::FAILURE;
    };
    let setup = Setup {
        scene,
        balls,
        mode,
        effect: cli.effect,
    };
    let timing = Timing {
        warmup: cli.warmup,
        steps: cli.steps,
        block: cli.block,
        time_blocks: cli.time_blocks,
        repeats: cli.repeats,
    };
    let run = (scene.dim(), precision);
    let json = if cli.pair {
        let pair = match run {
            (2, Precision::F32) => d2::run_pair(setup, timing),
            (2, Precision::F64) => d2_f64::run_pair(setup, timing),
            (_, Precision::F32) => d3::run_pair(setup, timing),
            (_, Precision::F64) => d3_f64::run_pair(setup, timing),
        };
        pair.map(|p| serde_json::to_string(&p))
    } else {
        let a = cli.attribute;
        let (w, st) = (timing.warmup, timing.steps);
        let solo = match run {
            (2, Precision::F32) => d2::run_solo(setup, w, st, a),
            (2, Precision::F64) => d2_f64::run_solo(setup, w, st, a),
            (_, Precision::F32) => d3::run_solo(setup, w, st, a),
            (_, Precision::F64) => d3_f64::run_solo(setup, w, st, a),
        };
        solo.map(|s| serde_json::to_string(&s))
    };
    match json {
        Some(Ok(json)) => {
            println!("{json}");
            ExitCode::SUCCESS
        }
        Some(Err(e)) => {
            eprintln!("cannot write the result: {e}");
            ExitCode::FAILURE
        }
        None => {
            eprintln!("scene {} has no {precision:?} build", scene.name());
            ExitCode::FAILURE
        }
    }
}

pub(crate) fn machine() -> String {
    let cpus = std::thread::available_parallelism().map_or(0, |n| n.get());
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("model name"))
                .map(|v| v.trim_start_matches([' ', '\t', ':']).trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".to_owned());
    format!("{cpus} CPUs available (nproc), {model}")
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    NO_CALM.store(cli.no_calm, std::sync::atomic::Ordering::Relaxed);
    HOOK_NATIVE.store(cli.hook_native, std::sync::atomic::Ordering::Relaxed);
    if cli.pair || cli.solo {
        return child_main(&cli);
    }
    if cli.effects {
        return effects::run(&cli);
    }
    if cli.rerender {
        let raw = std::fs::read_to_string(cli.out.join("raw.json"))
            .map_err(|e| e.to_string())
            .and_then(|s| serde_json::from_str::<report::Raw>(&s).map_err(|e| e.to_string()));
        return match raw {
            Ok(raw) => render(&cli, &raw),
            Err(e) => {
                eprintln!("cannot read {}/raw.json: {e}", cli.out.display());
                ExitCode::FAILURE
            }
        };
    }

    let mut counts = cli.balls.clone();
    if cli.big {
        counts.push(100_000);
    }
    counts.sort_unstable();
    counts.dedup();
    let mut modes = vec![Mode::Native];
    modes.extend(cli.mode.iter().copied().filter(|&m| m != Mode::Native));
    modes.sort_unstable();
    modes.dedup();
    let mut scenes = cli.scene.clone();
    scenes.sort_unstable();
    scenes.dedup();
    let mut precisions = cli.precision.clone();
    precisions.sort_unstable();
    precisions.dedup();
    let rounds = cli.rounds.max(1);
    if cli.steps < 200 {
        eprintln!(
            "note: {} measured steps per run; the budgets are defined on at least 200",
            cli.steps
        );
    }

    let command = std::iter::once("kimpact-bench".to_owned())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let started = Instant::now();
    let mut groups = Vec::new();
    for &precision in &precisions {
        for &scene in &scenes {
            let sizes: Vec<usize> = match scene.fixed_balls() {
                None => counts.clone(),
                Some(n) => vec![n],
            };
            for &balls in &sizes {
                let law_modes: Vec<Mode> = modes
                    .iter()
                    .copied()
                    .filter(|&m| m != Mode::Native)
                    .collect();
                // native against itself when no law mode was asked for
                let timed = if law_modes.is_empty() {
                    vec![Mode::Native]
                } else {
                    law_modes
                };
                let progress = |what: &str, mode: Mode| {
                    eprintln!(
                        "[{:>6.1}s] {} {} {} balls: {what} {}",
                        started.elapsed().as_secs_f64(),
                        precision.name(),
                        scene.name(),
                        balls,
                        mode.name(),
                    );
                };
                let config = (scene, balls, precision);
                groups.push(measure_group(
                    &cli,
                    config,
                    &modes,
                    &timed,
                    &[],
                    "memory of",
                    progress,
                ));
            }
        }
    }
    let header = report::Header {
        command,
        machine: machine(),
        parallel: cfg!(feature = "parallel"),
        clock: cli.clock,
        steps: cli.steps,
        warmup: cli.warmup,
        rounds,
        block: cli.block,
        small_block: cli.small_block,
        small_repeats: cli.small_repeats,
        memory_steps: cli.memory_steps,
        memory_warmup: cli.memory_warmup,
        wall_s: started.elapsed().as_secs_f64(),
    };
    let raw = report::Raw { header, groups };
    if let Err(e) = std::fs::create_dir_all(&cli.out).and_then(|()| {
        let json = serde_json::to_string(&raw).map_err(std::io::Error::other)?;
        std::fs::write(cli.out.join("raw.json"), json)
    }) {
        eprintln!("cannot write {}/raw.json: {e}", cli.out.display());
    }
    render(&cli, &raw)
}

/// Print the table and write the outputs of a run.
fn render(cli: &Cli, raw: &report::Raw) -> ExitCode {
    let rows: Vec<report::Row> = raw.groups.iter().flat_map(report::rows).collect();
    let header = &raw.header;
    let markdown = report::markdown(header, &rows);
    println!("{markdown}");
    if let Err(e) = report::write_all(&cli.out, &markdown, &rows) {
        eprintln!("cannot write the results to {}: {e}", cli.out.display());
        return ExitCode::FAILURE;
    }
    eprintln!(
        "wrote {}/results.csv, results.md, raw.json and the scaling plots",
        cli.out.display()
    );
    ExitCode::SUCCESS
}
