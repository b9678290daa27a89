//! `kimpact-ladder`: what each mode's accuracy costs, in one plot.
//!
//! ```text
//! cargo run --release -p kimpact-bench --bin kimpact-ladder
//! ```
//!
//! It reads what the bench wrote (`docs/bench/results.csv`, rows of
//! [`BenchRow`]) and what the accuracy study wrote
//! (`docs/accuracy-summary.json`, an [`AccuracySummary`]) with the types
//! that wrote them, joins them (`join.rs` holds every rule) and writes
//! `docs/ladder.svg` and `docs/ladder.md`, whole or not at all.

mod join;
mod page;
mod plot;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use kimpact_harness::{AccuracySummary, BenchRow, WriteError, write_files};

/// Error against ×native per mode and scene: the bench's and the accuracy
/// study's results drawn together.
#[derive(Parser, Debug)]
#[command(name = "kimpact-ladder", version, about)]
struct Args {
    /// The bench's CSV (×native per scene and mode; the command that wrote
    /// it is read from the `.md` beside it).
    #[arg(long, default_value = "docs/bench/results.csv")]
    bench_csv: PathBuf,
    /// The accuracy summary (errors per scene and mode).
    #[arg(long, default_value = "docs/accuracy-summary.json")]
    accuracy_json: PathBuf,
    /// The plot to write.
    #[arg(long, default_value = "docs/ladder.svg")]
    svg: PathBuf,
    /// The page to write.
    #[arg(long, default_value = "docs/ladder.md")]
    md: PathBuf,
}

/// Why the ladder was not drawn. Nothing is written when one of these is
/// returned.
#[derive(Debug, thiserror::Error)]
pub enum LadderError {
    /// A file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The file system's reason.
        source: std::io::Error,
    },
    /// The bench's CSV does not read as [`BenchRow`]s.
    #[error("{}{}: {source}", path.display(), column.as_ref().map_or(String::new(), |c| format!(", column `{c}`")))]
    Csv {
        /// The file.
        path: PathBuf,
        /// The column of the field at fault, when one is.
        column: Option<String>,
        /// csv's reason, with the line.
        source: csv::Error,
    },
    /// The summary does not read as an [`AccuracySummary`].
    #[error("{}, {source}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// serde_json's reason and the entry at fault (`errors[5]`).
        source: serde_path_to_error::Error<serde_json::Error>,
    },
    /// The two files break a rule of the join.
    #[error("{}: {message}", path.display())]
    Join {
        /// The file at fault.
        path: PathBuf,
        /// What is wrong, and where.
        message: String,
    },
    /// plotters refused to draw.
    #[error("plot: {0}")]
    Plot(String),
    /// An output could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
}

/// The bytes of `path`.
fn read(path: &Path) -> Result<Vec<u8>, LadderError> {
    std::fs::read(path).map_err(|source| LadderError::Read {
        path: path.to_owned(),
        source,
    })
}

/// The bench's rows at `path`, each with the line it is on.
fn read_bench(path: &Path) -> Result<Vec<(u64, BenchRow)>, LadderError> {
    let bytes = read(path)?;
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
    let error = |column: Option<String>, source| LadderError::Csv {
        path: path.to_owned(),
        column,
        source,
    };
    let headers = reader.headers().map_err(|e| error(None, e))?.clone();
    reader
        .records()
        .map(|record| {
            let record = record.map_err(|e| error(None, e))?;
            let line = record.position().map_or(0, csv::Position::line);
            let row = record.deserialize(Some(&headers)).map_err(|e| {
                let column = match e.kind() {
                    csv::ErrorKind::Deserialize { err, .. } => err
                        .field()
                        .and_then(|i| headers.get(i as usize))
                        .map(str::to_owned),
                    _ => None,
                };
                error(column, e)
            })?;
            Ok((line, row))
        })
        .collect()
}

/// The accuracy summary at `path`.
fn read_summary(path: &Path) -> Result<AccuracySummary, LadderError> {
    let bytes = read(path)?;
    let mut json = serde_json::Deserializer::from_slice(&bytes);
    serde_path_to_error::deserialize(&mut json).map_err(|source| LadderError::Json {
        path: path.to_owned(),
        source,
    })
}

/// The command that made the page, as a reader would type it.
fn command() -> String {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut c = "cargo run --release -p kimpact-bench --bin kimpact-ladder".to_owned();
    if !args.is_empty() {
        c = format!("{c} -- {}", args.join(" "));
    }
    c
}

fn run_ladder(args: &Args) -> Result<String, LadderError> {
    let rows = read_bench(&args.bench_csv)?;
    let summary = read_summary(&args.accuracy_json)?;
    let files = join::Files {
        bench: &args.bench_csv,
        accuracy: &args.accuracy_json,
    };
    let joined = join::join(&rows, &summary.errors, files)?;
    let svg = plot::svg(&joined)?;
    let bench_command = std::fs::read_to_string(args.bench_csv.with_extension("md"))
        .ok()
        .and_then(|md| {
            md.lines()
                .find_map(|l| l.trim().strip_prefix("- command: `")?.strip_suffix('`'))
                .map(str::to_owned)
        });
    let md = page::markdown(
        &joined,
        &page::Sources {
            command: &command(),
            bench_command: bench_command.as_deref(),
            summary: &summary,
            files,
            svg: &args.svg,
            md: &args.md,
        },
    );
    write_files(&[(&args.svg, svg.as_bytes()), (&args.md, md.as_bytes())])?;
    for s in &joined.skipped {
        eprintln!("kimpact-ladder: left out {s}");
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
    match run_ladder(&Args::parse()) {
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
