//! The child processes of a run: what they measure, the arguments they
//! get, and running one (its JSON answer on its last line of output).

use std::process::{Command, ExitCode, Stdio};

use serde::{Deserialize, Serialize};

use crate::report::Group;
use crate::{Cli, Mode, Precision, Scene, d2, d2_f64, d3, d3_f64};

/// What a measured run builds.
#[derive(Copy, Clone, Debug)]
pub struct Setup {
    /// The scene.
    pub scene: Scene,
    /// Its balls, for the scenes that scale.
    pub balls: usize,
    /// The mode.
    pub mode: Mode,
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
    /// Time each block as a whole (one sample per block) instead of each
    /// step.
    pub time_blocks: bool,
    /// Episodes: both worlds built anew, warmed up and measured this many
    /// times (the scenes are deterministic: each repeats the same steps).
    pub repeats: usize,
}

/// What the measured steps of one world did.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Measure {
    /// Measured steps.
    pub steps: usize,
    /// CPU time of the process (all threads) per step of each sample, µs.
    pub cpu_us: Vec<f64>,
    /// Heap allocations during the measured steps (all threads).
    pub allocs: u64,
    /// Impacts the law resolved.
    pub impacts: u64,
}

/// A timing child: native and one mode, in lockstep in one process.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Pair {
    /// The scene.
    pub scene: Scene,
    /// Dynamic balls in it.
    pub balls: usize,
    /// The mode.
    pub mode: Mode,
    /// Native's measure.
    pub native: Measure,
    /// The mode's.
    pub law: Measure,
}

/// A memory child: one mode alone, its peak RSS and the attribution of its
/// allocations.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Solo {
    /// The mode.
    pub mode: Mode,
    /// Measured steps.
    pub steps: usize,
    /// Allocations during them.
    pub allocs: u64,
    /// `VmHWM` after warm-up and the measured steps, KiB.
    pub peak_rss_kib: u64,
    /// From a second pass classifying every allocation of the measured
    /// steps: (classified, kimpact's).
    pub attributed: Option<(u64, u64)>,
}

/// A child process of this binary with `args`, its JSON answer parsed;
/// `Err` with the reason when it failed.
fn spawn<T: serde::de::DeserializeOwned>(args: &[String]) -> Result<T, String> {
    let exe = std::env::current_exe().map_err(|e| format!("no executable path: {e}"))?;
    let out = Command::new(exe)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("cannot start a child: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
        return Err(format!(
            "child failed ({}): {}",
            out.status,
            lines.join(" | ")
        ));
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout.lines().rev().find(|l| l.starts_with('{'));
    let line = line.ok_or("the child printed no result")?;
    serde_json::from_str(line).map_err(|e| format!("unreadable child output: {e}"))
}

/// The arguments of a child (`--pair` or `--solo`) for one configuration.
fn child_args(cli: &Cli, solo: bool, (scene, balls, precision): Config, mode: Mode) -> Vec<String> {
    let (steps, warmup) = match solo {
        true => (cli.memory_steps, cli.memory_warmup.unwrap_or(cli.warmup)),
        false => (cli.steps, cli.warmup),
    };
    let (block, repeats) = match (scene.small(), solo) {
        (true, false) => (cli.small_block, cli.small_repeats),
        (true, true) => (cli.small_block, 1),
        (false, _) => (cli.block, 1),
    };
    let kind = if solo { "--solo" } else { "--pair" };
    let mut args: Vec<String> = [kind, "--scene", scene.name(), "--mode", mode.name()]
        .map(str::to_owned)
        .into();
    args.extend(["--precision".to_owned(), precision.name().to_owned()]);
    for (flag, value) in [
        ("--balls", balls),
        ("--steps", steps),
        ("--warmup", warmup),
        ("--block", block),
        ("--repeats", repeats),
    ] {
        args.extend([flag.to_owned(), value.to_string()]);
    }
    let flags = [
        (scene.small(), "--time-blocks"),
        (cli.hook_native, "--hook-native"),
        (solo && !cli.no_attribute, "--attribute"),
    ];
    args.extend(flags.iter().filter(|f| f.0).map(|f| f.1.to_owned()));
    args
}

/// `r`, its error reported on stderr.
fn logged<T>(r: Result<T, String>) -> Result<T, String> {
    if let Err(e) = &r {
        eprintln!("    failed: {e}");
    }
    r
}

/// A scene, its balls and the precision of a run.
pub type Config = (Scene, usize, Precision);

/// The children of one configuration: `--rounds` timing pairs of each law
/// mode of `modes` (native against itself when there is none), then one
/// run of each of `modes` alone. `progress` hears of each child before it
/// runs. A child that fails is reported on stderr and kept as its error.
pub fn measure_group(cli: &Cli, config: Config, modes: &[Mode], progress: impl Fn(&str)) -> Group {
    let law: Vec<Mode> = modes
        .iter()
        .copied()
        .filter(|&m| m != Mode::Native)
        .collect();
    let timed = if law.is_empty() {
        vec![Mode::Native]
    } else {
        law
    };
    let mut pairs = Vec::new();
    for _ in 0..cli.rounds.max(1) {
        for &mode in &timed {
            progress(&format!("timing native + {}", mode.name()));
            pairs.push((mode, logged(spawn(&child_args(cli, false, config, mode)))));
        }
    }
    let mut solos = Vec::new();
    for &mode in modes {
        progress(&format!("memory of {}", mode.name()));
        solos.push((mode, logged(spawn(&child_args(cli, true, config, mode)))));
    }
    let (scene, balls, precision) = config;
    Group {
        scene,
        precision,
        balls,
        modes: modes.to_vec(),
        pairs,
        solos,
    }
}

/// In a child: run what `--pair` or `--solo` asks and print it as JSON.
pub fn child_main(cli: &Cli) -> ExitCode {
    let (Some(&scene), Some(&balls), Some(&mode), Some(&precision)) = (
        cli.scene.first(),
        cli.balls.first(),
        cli.mode.first(),
        cli.precision.first(),
    ) else {
        eprintln!("--pair/--solo need a scene, a ball count, a mode and a precision");
        return ExitCode::FAILURE;
    };
    let setup = Setup { scene, balls, mode };
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
        let (w, s, a) = (cli.warmup, cli.steps, cli.attribute);
        let solo = match run {
            (2, Precision::F32) => d2::run_solo(setup, w, s, a),
            (2, Precision::F64) => d2_f64::run_solo(setup, w, s, a),
            (_, Precision::F32) => d3::run_solo(setup, w, s, a),
            (_, Precision::F64) => d3_f64::run_solo(setup, w, s, a),
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
