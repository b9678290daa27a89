//! `kimpact-ladder`: what each mode's accuracy costs, in one plot.
//!
//! ```text
//! cargo run --release -p kimpact-bench --bin kimpact-ladder
//! ```
//!
//! It reads the bench's `results.csv` and the accuracy study's summary with
//! the types that wrote them, joins them (`join.rs` holds every rule) and
//! writes `docs/ladder.svg` and `docs/ladder.md`, whole or not at all.

mod join;
mod page;
mod plot;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use kimpact_harness::{AccuracySummary, BenchRow, write_files};

use join::LadderError;

/// Error against ×native per mode and scene: the bench's and the accuracy
/// study's results drawn together.
#[derive(Parser, Debug)]
#[command(name = "kimpact-ladder", version, about)]
struct Args {
    /// The bench's CSV (the command that wrote it is read from the `.md`
    /// beside it).
    #[arg(long, default_value = "docs/bench/results.csv")]
    bench_csv: PathBuf,
    /// The accuracy study's summary.
    #[arg(long, default_value = "docs/accuracy-summary.json")]
    accuracy_json: PathBuf,
    /// The plot to write.
    #[arg(long, default_value = "docs/ladder.svg")]
    svg: PathBuf,
    /// The page to write.
    #[arg(long, default_value = "docs/ladder.md")]
    md: PathBuf,
}

/// The bench's rows at `path`, each with its line (an error names the
/// column at fault).
fn read_bench(path: &Path) -> Result<Vec<(u64, BenchRow)>, LadderError> {
    let error = |e| LadderError::new(path, format!("cannot read: {e}"));
    let bytes = std::fs::read(path).map_err(error)?;
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
    let headers = reader.headers().map_err(|e| LadderError::new(path, e))?;
    let headers = headers.clone();
    let column = |e: &csv::Error| match e.kind() {
        csv::ErrorKind::Deserialize { err, .. } => {
            err.field().and_then(|i| headers.get(i as usize))
        }
        _ => None,
    };
    let rows = reader.records().map(|record| {
        let record = record.map_err(|e| LadderError::new(path, e))?;
        let line = record.position().map_or(0, csv::Position::line);
        let row = record
            .deserialize(Some(&headers))
            .map_err(|e| match column(&e) {
                Some(c) => LadderError::new(path, format!("column `{c}`: {e}")),
                None => LadderError::new(path, e),
            })?;
        Ok((line, row))
    });
    rows.collect()
}

/// The accuracy summary at `path` (its errors name the entry at fault, as
/// `errors[5]`).
fn read_summary(path: &Path) -> Result<AccuracySummary, LadderError> {
    let error = |e| LadderError::new(path, format!("cannot read: {e}"));
    let bytes = std::fs::read(path).map_err(error)?;
    let mut json = serde_json::Deserializer::from_slice(&bytes);
    serde_path_to_error::deserialize(&mut json).map_err(|e| LadderError::new(path, e))
}

fn run(args: &Args) -> Result<String, LadderError> {
    let rows = read_bench(&args.bench_csv)?;
    let summary = read_summary(&args.accuracy_json)?;
    let files = join::Files {
        bench: &args.bench_csv,
        accuracy: &args.accuracy_json,
    };
    let joined = join::join(&rows, &summary.errors, files)?;
    let svg = plot::svg(&joined).map_err(|e| LadderError::new(&args.svg, e))?;
    let md = page::markdown(&joined, &summary, files, (&args.svg, &args.md));
    let written = write_files(&[(&args.svg, svg), (&args.md, md)]);
    written.map_err(|e| LadderError::new(&e.path, e.source))?;
    for s in &joined.skipped {
        eprintln!("kimpact-ladder: left out {s}");
    }
    let (n, left_out) = (joined.points.len(), joined.skipped.len());
    let (svg, md) = (args.svg.display(), args.md.display());
    Ok(format!(
        "wrote {svg} and {md}: {n} points, {left_out} left out"
    ))
}

fn main() -> ExitCode {
    let (said, code) = match run(&Args::parse()) {
        Ok(done) => (done, ExitCode::SUCCESS),
        Err(e) => (e.to_string(), ExitCode::FAILURE),
    };
    eprintln!("kimpact-ladder: {said}");
    code
}
