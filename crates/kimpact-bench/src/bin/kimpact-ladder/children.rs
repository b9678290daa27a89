//! Regenerating the ladder's inputs: the two sibling programs found beside
//! this executable (built first when it runs under `cargo run`), `kimpact-bench` with the arguments of the published
//! run (*The run* of `docs/benchmarks.md`) into a scratch folder, then
//! `kimpact-accuracy` into the summary's folder; the bench's `results.csv`
//! and `results.md` are then copied over the ladder's `--bench-csv` and
//! the `.md` beside it.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::atomic;
use crate::error::LadderError;

/// The bench program.
pub const BENCH: &str = "kimpact-bench";
/// The accuracy study's program.
pub const ACCURACY: &str = "kimpact-accuracy";
/// The bench's arguments of *The run* in `docs/benchmarks.md`, the run
/// `docs/bench/results.csv` comes from (its `--out` is the ladder's): the
/// memory runs after 600 steps, in the steady state the allocation budget
/// is about.
pub const BENCH_ARGS: [&str; 4] = ["--balls", "1000", "--memory-warmup", "600"];
/// The file name kimpact-accuracy gives its summary.
pub const SUMMARY_NAME: &str = "accuracy-summary.json";
/// The scratch folder of the bench's run, beside the executables, unless
/// `--bench-out` says otherwise.
pub const BENCH_SCRATCH: &str = "kimpact-ladder-bench";

/// What a regeneration runs and where it writes.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The bench's CSV to replace (its `.md` beside it too).
    pub bench_csv: PathBuf,
    /// The accuracy summary that kimpact-accuracy writes (with the rest of
    /// its files, in the same folder).
    pub accuracy_json: PathBuf,
    /// Where the bench writes its run first (`None`: [`BENCH_SCRATCH`]
    /// beside the executables).
    pub bench_out: Option<PathBuf>,
    /// Pass `--quick` to kimpact-accuracy.
    pub quick: bool,
}

/// The program `name` in `dir`.
///
/// # Errors
/// [`LadderError::SiblingMissing`] when it is not there.
pub fn sibling(dir: &Path, name: &'static str) -> Result<PathBuf, LadderError> {
    let path = dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    if path.is_file() {
        Ok(path)
    } else {
        Err(LadderError::SiblingMissing { name, path })
    }
}

/// Run `path` (the program `name`) with `args`, its output passed through.
///
/// # Errors
/// It cannot start, or it exits unsuccessfully.
fn run(name: &'static str, path: &Path, args: &[OsString]) -> Result<(), LadderError> {
    let shown: Vec<String> = args
        .iter()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    eprintln!(
        "kimpact-ladder: running {} {}",
        path.display(),
        shown.join(" ")
    );
    let status = Command::new(path)
        .args(args)
        .status()
        .map_err(|source| LadderError::Spawn {
            name,
            path: path.to_owned(),
            source,
        })?;
    if status.success() {
        Ok(())
    } else {
        Err(LadderError::ChildFailed { name, status })
    }
}

/// The folder of `path` (`.` for a bare file name).
fn folder(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    }
}

/// Run both programs by `plan`, then put the bench's results in place.
///
/// # Errors
/// A summary path kimpact-accuracy cannot write, this executable's path
/// unknown, a sibling missing or failing, the results not readable or
/// writable.
pub fn regenerate(plan: &Plan) -> Result<(), LadderError> {
    if plan.accuracy_json.file_name() != Some(SUMMARY_NAME.as_ref()) {
        return Err(LadderError::SummaryName {
            path: plan.accuracy_json.clone(),
        });
    }
    // Under `cargo run` (which builds only this program), the siblings are
    // built first, so that they are never missing or stale.
    if let Some(cargo) = std::env::var_os("CARGO") {
        let args: Vec<OsString> = ["build", "--release", "-p", "kimpact-bench", "--bins"]
            .iter()
            .map(OsString::from)
            .collect();
        run("cargo build", Path::new(&cargo), &args)?;
    }
    let exe = std::env::current_exe().map_err(LadderError::CurrentExe)?;
    let dir = folder(&exe);
    let bench = sibling(&dir, BENCH)?;
    let accuracy = sibling(&dir, ACCURACY)?;
    // Relative to the working folder when inside it: the bench records its
    // command line in results.md, which the docs quote.
    let scratch = plan.bench_out.clone().unwrap_or_else(|| {
        let scratch = dir.join(BENCH_SCRATCH);
        std::env::current_dir()
            .ok()
            .and_then(|cwd| scratch.strip_prefix(cwd).ok().map(Path::to_path_buf))
            .unwrap_or(scratch)
    });

    let mut args: Vec<OsString> = BENCH_ARGS.iter().map(OsString::from).collect();
    args.extend(["--out".into(), scratch.clone().into_os_string()]);
    run(BENCH, &bench, &args)?;

    let mut args: Vec<OsString> =
        vec!["--out".into(), folder(&plan.accuracy_json).into_os_string()];
    if plan.quick {
        args.push("--quick".into());
    }
    run(ACCURACY, &accuracy, &args)?;

    let read = |name: &str| {
        let path = scratch.join(name);
        std::fs::read(&path).map_err(|source| LadderError::Read { path, source })
    };
    let (csv, md) = (read("results.csv")?, read("results.md")?);
    let md_path = plan.bench_csv.with_extension("md");
    atomic::write_all(&[(&plan.bench_csv, &csv), (&md_path, &md)])
}
