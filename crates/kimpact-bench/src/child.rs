//! The child processes of a run: their arguments, and running one (its
//! JSON answer on its last line of output).

use std::process::{Command, Stdio};

use kimpact::{Mode, Precision};

use crate::cli::{Cli, Scene, name};
use crate::raw::Group;

/// A scene, its balls and the precision of a run.
pub type Config = (Scene, usize, Precision);

/// A child process of this binary with `args`, its JSON answer parsed;
/// `Err` with the reason when it failed (also reported on stderr).
fn spawn<T: serde::de::DeserializeOwned>(args: &[String]) -> Result<T, String> {
    let answer = || {
        let exe = std::env::current_exe().map_err(|e| format!("no executable path: {e}"))?;
        let out = Command::new(exe).args(args).stdin(Stdio::null()).output();
        let out = out.map_err(|e| format!("cannot start a child: {e}"))?;
        if !out.status.success() {
            let err = String::from_utf8_lossy(&out.stderr);
            let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
            let (status, lines) = (out.status, lines.join(" | "));
            return Err(format!("child failed ({status}): {lines}"));
        }
        let stdout = String::from_utf8_lossy(&out.stdout);
        let line = stdout.lines().rev().find(|l| l.starts_with('{'));
        let line = line.ok_or("the child printed no result")?;
        serde_json::from_str(line).map_err(|e| format!("unreadable child output: {e}"))
    };
    let answer = answer();
    if let Err(e) = &answer {
        eprintln!("    failed: {e}");
    }
    answer
}

/// The arguments of a child (`--pair`, or `--solo` with `solo`) for one
/// configuration.
fn child_args(cli: &Cli, solo: bool, (scene, balls, precision): Config, mode: Mode) -> Vec<String> {
    let (steps, warmup) = match solo {
        true => (cli.memory_steps, cli.memory_warmup.unwrap_or(cli.warmup)),
        false => (cli.steps, cli.warmup),
    };
    let small = scene.small();
    let block = if small { cli.small_block } else { cli.block };
    let repeats = if small && !solo { cli.small_repeats } else { 1 };
    let kind = if solo { "--solo" } else { "--pair" };
    let scene = name(scene);
    let threads = cli.threads.map(|n| format!(" --threads {n}"));
    let effect = cli.effect.map(|e| format!(" --effect {}", name(e)));
    let cutoff = cli.rebound_cutoff.map(|n| format!(" --rebound-cutoff {n}"));
    let (threads, effect) = (threads.unwrap_or_default(), effect.unwrap_or_default());
    let cutoff = cutoff.unwrap_or_default();
    let args = format!(
        "{kind} --scene {scene} --mode {mode} --precision {precision} --balls {balls} \
         --steps {steps} --warmup {warmup} --block {block} --repeats {repeats}{threads}{effect}{cutoff}"
    );
    let mut args: Vec<String> = args.split(' ').map(str::to_owned).collect();
    let flags = [
        (small, "--time-blocks"),
        (cli.hook_native, "--hook-native"),
        (cli.no_calm, "--no-calm"),
        (solo && !cli.no_attribute, "--attribute"),
        (!solo && cli.stages, "--stages"),
    ];
    args.extend(flags.iter().filter(|f| f.0).map(|f| f.1.to_owned()));
    args
}

/// The children of one configuration: `--rounds` timing pairs of each law
/// mode (native against itself when there is none), then each mode alone;
/// a child that fails is reported and kept as its error.
pub fn measure_group(cli: &Cli, config: Config, modes: &[Mode], progress: impl Fn(&str)) -> Group {
    let mut timed = Vec::from_iter(modes.iter().copied().filter(|&m| m != Mode::Native));
    if timed.is_empty() {
        timed.push(Mode::Native);
    }
    let mut pairs = Vec::new();
    for _ in 0..cli.rounds.max(1) {
        for &mode in &timed {
            progress(&format!("timing native + {mode}"));
            pairs.push((mode, spawn(&child_args(cli, false, config, mode))));
        }
    }
    let mut solos = Vec::new();
    for &mode in modes {
        progress(&format!("memory of {mode}"));
        solos.push((mode, spawn(&child_args(cli, true, config, mode))));
    }
    let (scene, balls, precision) = config;
    let (effect, modes) = (cli.effect, modes.to_vec());
    Group {
        scene,
        precision,
        balls,
        effect,
        modes,
        pairs,
        solos,
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    /// The law worlds' settings reach every child: `--rebound-cutoff` with
    /// its value and `--no-calm`, in the timing and the memory runs, and
    /// neither when not asked.
    #[test]
    fn the_law_world_settings_reach_the_children() {
        let config = (Scene::Pit2d, 300, Precision::F32);
        let asked = Cli::parse_from(["kimpact-bench", "--no-calm", "--rebound-cutoff", "2.5"]);
        for solo in [false, true] {
            let args = child_args(&asked, solo, config, Mode::Exact);
            let at = args.iter().position(|a| a == "--rebound-cutoff");
            assert_eq!(at.map(|i| args[i + 1].as_str()), Some("2.5"), "{args:?}");
            assert!(args.iter().any(|a| a == "--no-calm"), "{args:?}");
            let child = Cli::parse_from(std::iter::once("kimpact-bench".to_owned()).chain(args));
            assert_eq!((child.rebound_cutoff, child.no_calm), (Some(2.5), true));
        }
        let plain = Cli::parse_from(["kimpact-bench"]);
        let args = child_args(&plain, false, config, Mode::Exact);
        assert!(
            !args
                .iter()
                .any(|a| a == "--rebound-cutoff" || a == "--no-calm"),
            "{args:?}"
        );
    }
}
