//! `kimpact-ladder`: what each mode's accuracy costs, in one plot.
//!
//! ```text
//! cargo run --release -p kimpact-bench --bin kimpact-ladder
//! cargo run --release -p kimpact-bench --bin kimpact-ladder -- --plot-only
//! ```
//!
//! By default it regenerates its inputs first: `kimpact-bench` with the
//! arguments of the published run ([`BENCH_ARGS`]) into a scratch folder,
//! whose `results.csv` and `results.md` then replace `--bench-csv` and the
//! `.md` beside it, and `kimpact-accuracy` into the folder of
//! `--accuracy-json`; both are the programs beside this one (under
//! `cargo run`, built first). Then it reads the bench's rows and the
//! study's summary with the types that wrote them ([`BenchRow`],
//! [`AccuracySummary`]), joins them (`join.rs` holds every rule) and writes
//! `docs/ladder.svg` and `docs/ladder.md`, whole or not at all.
//! `--plot-only` only reads and draws.

mod join;
mod page;
mod plot;

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use clap::Parser;
use kimpact_harness::{AccuracySummary, BenchRow, WriteError, write_files};

/// Error against ×native per mode and scene: regenerate the bench's and
/// the accuracy study's results, and draw them together.
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
    /// Where kimpact-bench writes its run (default: kimpact-ladder-bench
    /// beside the executables).
    #[arg(long)]
    bench_out: Option<PathBuf>,
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
    /// A program the ladder runs could not start, or failed.
    #[error("{program}: {message}")]
    Run {
        /// The program.
        program: String,
        /// What happened.
        message: String,
    },
    /// plotters refused to draw.
    #[error("plot: {0}")]
    Plot(String),
    /// An output could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
}

/// kimpact-bench's arguments of the published run (`docs/benchmarks.md`,
/// *Regenerate*): the memory runs after 600 steps, in the steady state.
pub const BENCH_ARGS: [&str; 4] = ["--balls", "1000", "--memory-warmup", "600"];

/// The name kimpact-accuracy gives its summary.
const SUMMARY_NAME: &str = "accuracy-summary.json";

/// Run `program` with `args`, its output passed through.
fn run(name: &str, program: &Path, args: &[OsString]) -> Result<(), LadderError> {
    let error = |message| LadderError::Run {
        program: name.to_owned(),
        message,
    };
    let shown: Vec<_> = args.iter().map(|a| a.to_string_lossy()).collect();
    eprintln!(
        "kimpact-ladder: running {} {}",
        program.display(),
        shown.join(" ")
    );
    let status = Command::new(program).args(args).status().map_err(|e| {
        error(format!(
            "cannot start {}: {e} (build it with `cargo build --release -p kimpact-bench`, or draw from the existing files with --plot-only)",
            program.display()
        ))
    })?;
    match status.success() {
        true => Ok(()),
        false => Err(error(format!("failed ({status}); nothing was drawn"))),
    }
}

/// Run the bench and the study, then put the bench's results in place.
fn regenerate(args: &Args) -> Result<(), LadderError> {
    if args.accuracy_json.file_name() != Some(SUMMARY_NAME.as_ref()) {
        return Err(LadderError::Run {
            program: "kimpact-accuracy".to_owned(),
            message: format!(
                "it writes {SUMMARY_NAME} into the folder of --accuracy-json, not {}: name that file, or draw with --plot-only",
                args.accuracy_json.display()
            ),
        });
    }
    // `cargo run` builds this program only: build its siblings too.
    if let Some(cargo) = std::env::var_os("CARGO") {
        let build = ["build", "--release", "-p", "kimpact-bench", "--bins"].map(OsString::from);
        run("cargo build", Path::new(&cargo), &build)?;
    }
    let exe = std::env::current_exe().map_err(|e| LadderError::Run {
        program: "kimpact-ladder".to_owned(),
        message: format!("cannot find its own executable: {e}"),
    })?;
    let dir = exe.parent().unwrap_or(Path::new("."));
    let sibling = |name: &str| dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    // Relative to the working folder when inside it: the bench records its
    // command line in results.md, which the docs quote.
    let scratch = args.bench_out.clone().unwrap_or_else(|| {
        let scratch = dir.join("kimpact-ladder-bench");
        std::env::current_dir()
            .ok()
            .and_then(|cwd| scratch.strip_prefix(cwd).ok().map(Path::to_path_buf))
            .unwrap_or(scratch)
    });
    let mut bench: Vec<OsString> = BENCH_ARGS.map(OsString::from).into();
    bench.extend(["--out".into(), scratch.clone().into()]);
    run("kimpact-bench", &sibling("kimpact-bench"), &bench)?;
    let folder = match args.accuracy_json.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut accuracy: Vec<OsString> = vec!["--out".into(), folder.into()];
    if args.quick {
        accuracy.push("--quick".into());
    }
    run("kimpact-accuracy", &sibling("kimpact-accuracy"), &accuracy)?;
    let csv = read(&scratch.join("results.csv"))?;
    let md = read(&scratch.join("results.md"))?;
    let md_path = args.bench_csv.with_extension("md");
    Ok(write_files(&[(&args.bench_csv, &csv), (&md_path, &md)])?)
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
    if !args.plot_only {
        regenerate(args)?;
    }
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
