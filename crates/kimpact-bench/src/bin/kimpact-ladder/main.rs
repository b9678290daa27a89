//! `kimpact-ladder`: what each mode's accuracy costs, in one plot.
//!
//! ```text
//! cargo build --release -p kimpact-bench && cargo run --release -p kimpact-bench --bin kimpact-ladder
//! cargo run --release -p kimpact-bench --bin kimpact-ladder -- --plot-only
//! ```
//!
//! By default it regenerates everything: it runs `kimpact-bench` with the
//! arguments of the published run (`docs/benchmarks.md`, *The run*) and
//! copies its `results.csv` and `results.md` into `docs/bench/`, runs
//! `kimpact-accuracy` (which writes `docs/accuracy.*` and
//! `docs/accuracy-summary.json`), both found beside this executable; then
//! it joins the bench's ×native with the accuracy study's errors
//! (`join.rs` holds every rule) and writes `docs/ladder.svg` (error
//! against ×native, log scales, per mode and scene) and `docs/ladder.md`
//! (the joined table). `--plot-only` only reads the existing files and
//! draws. The outputs are written whole or not at all.

mod atomic;
mod bench;
mod children;
mod csv;
mod error;
mod join;
mod page;
mod plot;
mod summary;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

use error::LadderError;

/// Error against ×native per mode and scene: regenerate the bench's and
/// the accuracy study's tables, and draw them together.
#[derive(Parser, Debug)]
#[command(name = "kimpact-ladder", version, about)]
struct Args {
    /// Only read the existing files and draw: run neither kimpact-bench
    /// nor kimpact-accuracy.
    #[arg(long)]
    plot_only: bool,
    /// Pass `--quick` to kimpact-accuracy (a smoke run whose errors mean
    /// nothing; it still writes into the summary's folder).
    #[arg(long, conflicts_with = "plot_only")]
    quick: bool,
    /// The bench's CSV (×native per scene and mode); a run replaces it and
    /// the `.md` beside it.
    #[arg(long, default_value = "docs/bench/results.csv")]
    bench_csv: PathBuf,
    /// The accuracy summary (errors per scene and mode); a run writes it,
    /// with the rest of kimpact-accuracy's files, into its folder.
    #[arg(long, default_value = "docs/accuracy-summary.json")]
    accuracy_json: PathBuf,
    /// The plot to write.
    #[arg(long, default_value = "docs/ladder.svg")]
    svg: PathBuf,
    /// The page to write.
    #[arg(long, default_value = "docs/ladder.md")]
    md: PathBuf,
    /// Where kimpact-bench writes its run before its results.csv and
    /// results.md are copied over --bench-csv (default:
    /// kimpact-ladder-bench beside the executables).
    #[arg(long)]
    bench_out: Option<PathBuf>,
}

/// The command that made the page, as a reader would type it.
fn command() -> String {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut c = "cargo run --release -p kimpact-bench --bin kimpact-ladder".to_owned();
    if !args.is_empty() {
        c.push_str(" -- ");
        c.push_str(&args.join(" "));
    }
    c
}

fn run(args: &Args) -> Result<String, LadderError> {
    if !args.plot_only {
        children::regenerate(&children::Plan {
            bench_csv: args.bench_csv.clone(),
            accuracy_json: args.accuracy_json.clone(),
            bench_out: args.bench_out.clone(),
            quick: args.quick,
        })?;
    }
    let rows = bench::read(&args.bench_csv)?;
    let summary = summary::read(&args.accuracy_json)?;
    let files = join::Files {
        bench: &args.bench_csv,
        accuracy: &args.accuracy_json,
    };
    let joined = join::join(&rows, &summary.errors, files)?;
    let svg = plot::svg(&joined)?;
    let command = command();
    let bench_command = bench::command(&args.bench_csv);
    let md = page::markdown(
        &joined,
        &page::Sources {
            command: &command,
            bench: &args.bench_csv,
            bench_command: bench_command.as_deref(),
            accuracy: &args.accuracy_json,
            summary: &summary,
            svg: &args.svg,
            md: &args.md,
        },
    );
    atomic::write_all(&[(&args.svg, svg.as_bytes()), (&args.md, md.as_bytes())])?;
    for s in &joined.skipped {
        eprintln!(
            "kimpact-ladder: left out {} {} {}: {}",
            s.scene.label, s.quantity.label, s.mode, s.reason
        );
    }
    Ok(format!(
        "wrote {} and {}: {} points, {} left out",
        args.svg.display(),
        args.md.display(),
        joined.points.len(),
        joined.skipped.len()
    ))
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(done) => {
            eprintln!("kimpact-ladder: {done}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("kimpact-ladder: {e}");
            ExitCode::FAILURE
        }
    }
}
