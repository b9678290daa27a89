//! The child processes of a run: what they measure, their arguments, and
//! running one (its JSON answer on its last line of output).

use std::process::{Command, ExitCode, Stdio};

use crate::raw::Group;
use crate::{Cli, Mode, Precision, Scene, d2, d2_f64, d3, d3_f64};

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
    if let Some(threads) = cli.threads {
        args.extend(["--threads".to_owned(), threads.to_string()]);
    }
    if let Some(effect) = cli.effect {
        args.extend(["--effect".to_owned(), effect.name().to_owned()]);
    }
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
/// mode (native against itself when there is none), then each mode alone;
/// a child that fails is reported and kept as its error.
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
        effect: cli.effect,
        modes: modes.to_vec(),
        pairs,
        solos,
    }
}

/// In a child: run what `--pair` or `--solo` asks and print it as JSON.
pub fn child_main(cli: &Cli) -> ExitCode {
    let (scene, precision) = (cli.scene[0], cli.precision[0]);
    let run = || match (scene.dim(), precision) {
        (2, Precision::F32) => d2::run(cli),
        (2, Precision::F64) => d2_f64::run(cli),
        (_, Precision::F32) => d3::run(cli),
        (_, Precision::F64) => d3_f64::run(cli),
    };
    // `--threads`: the steps run inside a pool of that many threads (rapier
    // and kimpact's passes use the pool they run in).
    let pool = cli.threads.map(|n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n.into())
            .build()
    });
    let json = match pool {
        None => run(),
        Some(Ok(pool)) => {
            crate::memory::time_by_wall_clock();
            pool.install(run)
        }
        Some(Err(e)) => {
            eprintln!("cannot start {} threads: {e}", cli.threads.unwrap_or(0));
            return ExitCode::FAILURE;
        }
    };
    println!("{json}");
    ExitCode::SUCCESS
}
