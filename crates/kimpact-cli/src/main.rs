//! `kimpact`: run scene files with rapier's native restitution and with
//! kimpact's law, and compare the modes side by side.
//!
//! ```text
//! kimpact run SCENE [--mode M] [--steps N] [--out FILE]
//! kimpact compare SCENE [--steps N] [--out DIR] [--gif]
//! kimpact check SCENE
//! ```
//!
//! Exit codes: 0 success, 2 bad input (unreadable or invalid scene, bad
//! flag), 1 internal failure. See `docs/scenes.md` for the scene format.
#![warn(missing_docs)]
#![forbid(unsafe_code)]
// Comparisons written as `!(a < b)` are meant to be true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod animation;
mod clamps;
mod compare;
mod error;
mod html;
mod output;
mod palette;
mod plot;
mod progress;
mod render;
mod report;
mod shown;
mod sim;

use error::CliError;
// Scene files (`crate::scene::…` in the modules below).
use kimpact_scene as scene;

/// The accuracy ladder: the core's, shared by the four adapter crates.
pub use kimpact::Mode;

/// The command line.
#[derive(Parser, Debug)]
#[command(
    name = "kimpact",
    version,
    about = "Run scene files with rapier's native restitution and with kimpact's collision law."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Simulate a scene and write a JSON report (to standard output without --out).
    Run {
        /// The scene file (.json, .ron or .toml).
        scene: PathBuf,
        /// Override the scene's mode: native, restitution, impulse or exact.
        #[arg(long, value_parser = mode_parser())]
        mode: Option<Mode>,
        /// Override the scene's number of steps.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=scene::MAX_STEPS))]
        steps: Option<u64>,
        /// Write the report to this file (atomically) instead of standard output.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Run native and the three law modes; write reports, a summary, plots, pictures and a page.
    ///
    /// The page, `compare.html`, animates the four modes side by side (play,
    /// pause, scrub, speed), with the energy and momentum curves and the
    /// summary table. It is one self-contained file that loads nothing from
    /// the network; long runs show every N-th step (stated on the page).
    Compare {
        /// The scene file (.json, .ron or .toml).
        scene: PathBuf,
        /// Override the scene's number of steps.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=scene::MAX_STEPS))]
        steps: Option<u64>,
        /// Output directory (default: `out/<scene name>`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write `compare.gif`: native beside exact, animated in real time.
        #[arg(long)]
        gif: bool,
    },
    /// Validate a scene and print a one-line summary.
    Check {
        /// The scene file (.json, .ron or .toml).
        scene: PathBuf,
    },
}

/// `--mode`: one of the mode names (listed in `--help`), parsed by
/// `Mode`'s own `FromStr`.
fn mode_parser() -> impl clap::builder::TypedValueParser<Value = Mode> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(Mode::ALL.map(Mode::name))
        .try_map(|s| s.parse::<Mode>())
}

fn main() -> ExitCode {
    // clap's usage errors exit with 2, help and version with 0.
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let outcome = std::panic::catch_unwind(|| execute(cli));
    match outcome {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("{e}");
            ExitCode::from(e.exit_code() as u8)
        }
        // The panic message has been printed by the default hook.
        Err(_) => {
            eprintln!("internal error: the simulation panicked");
            ExitCode::from(1)
        }
    }
}

fn execute(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Run {
            scene,
            mode,
            steps,
            out,
        } => run(&scene, mode, steps, out.as_deref()),
        Command::Compare {
            scene,
            steps,
            out,
            gif,
        } => {
            let scene = load(&scene)?;
            let dir = out.unwrap_or_else(|| Path::new("out").join(&scene.name));
            compare::compare(&scene, steps, &dir, compare::Extras { gif })
        }
        Command::Check { scene } => {
            let scene = load(&scene)?;
            println!(
                "{}: ok: {}D {}, {} bodies ({} fixed), {} joints, {} steps of {} s, mode {}, effects [{}]",
                scene.file,
                scene.dim,
                scene.precision.name(),
                scene.bodies.len(),
                scene.bodies.iter().filter(|b| b.fixed).count(),
                scene.joints.len(),
                scene.steps,
                scene.dt,
                scene.mode,
                scene.active_effects().join(", ")
            );
            Ok(())
        }
    }
}

/// Load a scene and print its warnings.
fn load(path: &Path) -> Result<scene::Scene, CliError> {
    let scene = scene::load(path)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene)
}

/// Check that the directory of an output file exists (bad input otherwise).
fn check_out_file(out: &Path) -> Result<(), CliError> {
    if out.is_dir() {
        return Err(CliError::Input(format!(
            "--out {}: is a directory, expected a file",
            out.display()
        )));
    }
    match out.parent() {
        Some(d) if !d.as_os_str().is_empty() && !d.is_dir() => Err(CliError::Input(format!(
            "--out {}: the directory {} does not exist",
            out.display(),
            d.display()
        ))),
        _ => Ok(()),
    }
}

fn run(
    path: &Path,
    mode: Option<Mode>,
    steps: Option<u64>,
    out: Option<&Path>,
) -> Result<(), CliError> {
    let scene = load(path)?;
    if let Some(out) = out {
        check_out_file(out)?;
    }
    let mode = mode.unwrap_or(scene.mode);
    let steps = steps.unwrap_or(scene.steps);
    let bar = progress::progress_bar(steps, mode.name());
    let result = sim::run(&scene, mode, steps, &[], bar.as_ref());
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let report = report::build(&scene, &result);
    // The scene's own warnings were printed when it was loaded.
    for w in &report.warnings[scene.warnings.len()..] {
        eprintln!("warning: {w}");
    }
    if let Some(c) = &report.impacts.clamps {
        eprintln!("note: {c}");
    }
    let mut json = serde_json::to_string_pretty(&report)
        .map_err(|e| CliError::Internal(format!("cannot encode the report: {e}")))?;
    json.push('\n');
    match out {
        Some(out) => output::write_atomic(out, json.as_bytes()),
        None => {
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(json.as_bytes())
                .and_then(|()| stdout.flush())
                .map_err(|e| CliError::Internal(format!("cannot write to standard output: {e}")))
        }
    }
}
