//! Everything that stops `kimpact-ladder`, each error naming the file and
//! the row, entry or field at fault, or the child program and its status.

use std::path::PathBuf;
use std::process::ExitStatus;

/// Why the ladder was not drawn. Nothing is written when one of these is
/// returned (the outputs are replaced only once everything is ready).
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
    /// A file could not be written (or renamed into place).
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The file system's reason.
        source: std::io::Error,
    },
    /// A CSV file without even a header line.
    #[error("{}: empty, no header line", path.display())]
    NoHeader {
        /// The file.
        path: PathBuf,
    },
    /// A column the join needs is not in the CSV's header.
    #[error("{}: no column `{column}` in the header (line 1)", path.display())]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The column.
        column: &'static str,
    },
    /// A quoted CSV field that never closes.
    #[error("{}, line {line}: a quoted field does not close", path.display())]
    Unterminated {
        /// The file.
        path: PathBuf,
        /// The line of its opening quote.
        line: usize,
    },
    /// A CSV row with another number of fields than the header.
    #[error("{}, line {line}: {found} fields, the header has {expected}", path.display())]
    FieldCount {
        /// The file.
        path: PathBuf,
        /// The row's line.
        line: usize,
        /// Its fields.
        found: usize,
        /// The header's.
        expected: usize,
    },
    /// A CSV field that does not read as what its column holds.
    #[error("{}, line {line}, column `{column}`: cannot read {value:?} as {expected}", path.display())]
    BadField {
        /// The file.
        path: PathBuf,
        /// The row's line.
        line: usize,
        /// The column.
        column: &'static str,
        /// The field as written.
        value: String,
        /// What the column holds.
        expected: &'static str,
    },
    /// A file that is not JSON at all.
    #[error("{}: not JSON: {source}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// serde_json's reason (with the line and column).
        source: serde_json::Error,
    },
    /// An entry of the JSON summary that is missing a field or holds the
    /// wrong kind of value.
    #[error("{}, {entry}: {problem}", path.display())]
    BadEntry {
        /// The file.
        path: PathBuf,
        /// Where in it, as `errors[3].quantity`.
        entry: String,
        /// What is wrong.
        problem: String,
    },
    /// The same (scene, build, mode) twice on one side of the join.
    #[error("{}: {what} twice, at {first} and {second}", path.display())]
    Duplicate {
        /// The file.
        path: PathBuf,
        /// The key that repeats.
        what: String,
        /// Where it is first.
        first: String,
        /// Where it is again.
        second: String,
    },
    /// A bench row of a joined scene with another dimension than the
    /// accuracy scene it is joined to.
    #[error("{}, line {line}: {scene} has dim {found}; it is joined to a {expected}D accuracy scene", path.display())]
    Dimension {
        /// The file.
        path: PathBuf,
        /// The row's line.
        line: usize,
        /// The bench scene.
        scene: String,
        /// The dimension in the row.
        found: usize,
        /// The dimension the join expects.
        expected: usize,
    },
    /// A mode that one side of the join has for a scene and the other does
    /// not.
    #[error("{}: no {mode} for {what}, which {} has", path.display(), other.display())]
    ModeMissing {
        /// The file without it.
        path: PathBuf,
        /// What is looked for in it (scene, build, quantity).
        what: String,
        /// The mode.
        mode: kimpact::Mode,
        /// The file with it.
        other: PathBuf,
    },
    /// A value that cannot be drawn on a log axis and is not NaN: a
    /// negative error or noise floor, a ×native at or below 0.
    #[error("{}, {at}: {what} is {value}, {expected}", path.display())]
    OutOfRange {
        /// The file.
        path: PathBuf,
        /// Where in it.
        at: String,
        /// The quantity.
        what: &'static str,
        /// Its value.
        value: f64,
        /// What it should be.
        expected: &'static str,
    },
    /// Not one point to draw.
    #[error("nothing to draw: no scene of the join is in both {} and {}{}", bench.display(), accuracy.display(), if *skipped > 0 { format!(" ({skipped} points skipped for a value that is not a number)") } else { String::new() })]
    EmptyJoin {
        /// The bench's CSV.
        bench: PathBuf,
        /// The accuracy summary.
        accuracy: PathBuf,
        /// Points left out for a NaN.
        skipped: usize,
    },
    /// This program's own path is unknown (to find its siblings).
    #[error("cannot find kimpact-ladder's own executable (to run its siblings): {0}")]
    CurrentExe(std::io::Error),
    /// A sibling program is not next to this one.
    #[error("{name} is not at {}: build it with `cargo build --release -p kimpact-bench` (kimpact-ladder runs the binaries beside it), or draw from the existing files with --plot-only", path.display())]
    SiblingMissing {
        /// The program.
        name: &'static str,
        /// Where it was looked for.
        path: PathBuf,
    },
    /// A sibling program that could not be started.
    #[error("cannot start {name} ({}): {source}", path.display())]
    Spawn {
        /// The program.
        name: &'static str,
        /// Its path.
        path: PathBuf,
        /// The system's reason.
        source: std::io::Error,
    },
    /// A sibling program that failed.
    #[error("{name} failed ({status}); nothing was drawn")]
    ChildFailed {
        /// The program.
        name: &'static str,
        /// How it ended.
        status: ExitStatus,
    },
    /// A run writes the summary as `accuracy-summary.json` into the folder
    /// of `--accuracy-json`; another file name cannot be regenerated.
    #[error("--accuracy-json {}: kimpact-accuracy writes accuracy-summary.json into its folder; name that file, or draw with --plot-only", path.display())]
    SummaryName {
        /// The path given.
        path: PathBuf,
    },
    /// plotters refused to draw.
    #[error("plot: {0}")]
    Plot(String),
}
