//! The join of the bench's costs with the accuracy study's errors; every
//! rule of it lives here:
//!
//! - **Scenes** ([`SCENES`]): the bench's `gas2d` and `gas3d` against the
//!   study's [`GAS`] in 2D and 3D (the same kind of scene, other balls).
//! - **Build**: [`PRECISION`] on both sides; the bench's rows of [`BALLS`]
//!   balls without rapier's `parallel`; the study's errors at `dt_div` 1.
//! - **Quantities** ([`QUANTITIES`]): one point per (scene, quantity, mode).
//! - **Modes**: a mode on one side of a joined scene must be on the other,
//!   in every quantity; the same key twice on one side is an error.
//! - **Values**: one that is not a number (NaN, infinite; `null` in the
//!   JSON) leaves its point out, with a note; ×native ≤ 0, a negative error
//!   or noise floor is an error.
//! - **On a log axis**: see [`Level`].

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use kimpact::{Mode, Precision};
use kimpact_harness::{BenchRow, ErrorRow};

/// A joined scene: the bench's scene, the dimension of the accuracy
/// study's [`GAS`] it is measured against, and its label.
pub type SceneRule = (&'static str, usize, &'static str);

/// The joined scenes, in the order of the plot and the page.
pub const SCENES: [SceneRule; 2] = [("gas2d", 2, "2D gas"), ("gas3d", 3, "3D gas")];

/// The accuracy study's scene the bench's gases are measured against.
pub const GAS: &str = "gas";

/// The quantities drawn, one panel each: (name in the summary, label).
pub const QUANTITIES: [(&str, &str); 2] = [
    ("impact_rate_error", "impact rate error"),
    ("energy_error", "energy error"),
];

/// The build of both sides.
pub const PRECISION: Precision = Precision::F32;
/// The bench's rows of this many balls.
pub const BALLS: usize = 1000;

/// Where an error is drawn on a log axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Level {
    /// Above its noise floor (or without one): at itself.
    Measured(f64),
    /// At or below its (positive) noise floor: at the floor, hollow.
    AtFloor(f64),
    /// 0 without a positive noise floor: at the axis's bottom, hollow.
    Zero,
}

/// One joined (scene, quantity's label, mode): ×native from the bench,
/// the error and its noise floor (when there is one) from the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub scene: &'static SceneRule,
    pub quantity: &'static str,
    pub mode: Mode,
    pub ratio: f64,
    pub error: f64,
    pub noise_floor: Option<f64>,
}

impl Point {
    /// Where the error is drawn (see [`Level`]).
    pub fn level(&self) -> Level {
        match self.noise_floor {
            Some(floor) if floor > 0.0 && self.error <= floor => Level::AtFloor(floor),
            _ if self.error > 0.0 => Level::Measured(self.error),
            _ => Level::Zero,
        }
    }
}

/// What the join gives: the points, by scene, quantity and mode, and those
/// left out for a value that is not a number ("scene, quantity, mode: why").
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Join {
    pub points: Vec<Point>,
    pub skipped: Vec<String>,
}

/// The bench's CSV and the accuracy summary, for the errors and notes.
#[derive(Clone, Copy, Debug)]
pub struct Files<'a> {
    pub bench: &'a Path,
    pub accuracy: &'a Path,
}

/// Why the ladder was not drawn (nothing is written then): the file at
/// fault, input or output, and what is wrong, and where.
#[derive(Debug, thiserror::Error)]
#[error("{}: {message}", path.display())]
pub struct LadderError {
    pub path: PathBuf,
    pub message: String,
}

impl LadderError {
    /// An error in `path`.
    pub fn new(path: &Path, message: impl ToString) -> Self {
        let (path, message) = (path.to_owned(), message.to_string());
        Self { path, message }
    }
}

/// Each item of `items` by its mode, with where it is (a line, an index);
/// the same mode twice is an error naming both places.
fn by_mode<'a, T>(
    items: impl Iterator<Item = (String, &'a T, Mode)>,
    what: &str,
    path: &Path,
) -> Result<BTreeMap<Mode, (String, &'a T)>, LadderError> {
    let mut out = BTreeMap::new();
    for (at, item, mode) in items {
        if let Some((first, _)) = out.insert(mode, (at.clone(), item)) {
            let message = format!("{what} in mode {mode} twice, at {first} and {at}");
            return Err(LadderError::new(path, message));
        }
    }
    Ok(out)
}

/// The point of one mode's cost (its line, its row) and error (its index,
/// its entry); `Ok(Err(why))` when a value is not a number.
fn point(
    (scene, quantity): (&'static SceneRule, &'static str),
    (line, cost): &(String, &BenchRow),
    (index, e): &(String, &ErrorRow),
    files: Files<'_>,
) -> Result<Result<Point, String>, LadderError> {
    let (ratio, error, noise_floor, mode) = (cost.ratio, e.error, e.noise_floor, e.mode);
    let at = |field: &str| format!("{}, {index}.{field}", files.accuracy.display());
    if !ratio.is_finite() {
        let said = cost.error.as_ref();
        let said = said.map_or(String::new(), |e| format!("; the bench's error: {e}"));
        let bench = files.bench.display();
        return Ok(Err(format!("×native is {ratio} in {bench}, {line}{said}")));
    }
    if !error.is_finite() {
        return Ok(Err(format!("the error is {error} in {}", at("error"))));
    }
    if let Some(f) = noise_floor.filter(|f| !f.is_finite()) {
        let at = at("noise_floor");
        return Ok(Err(format!("the noise floor is {f} in {at}")));
    }
    if ratio <= 0.0 {
        let message = format!("{line}: ×native is {ratio}, not above 0");
        return Err(LadderError::new(files.bench, message));
    }
    if error < 0.0 || noise_floor.is_some_and(|f| f < 0.0) {
        let message = format!("{index}: a negative error or noise floor");
        return Err(LadderError::new(files.accuracy, message));
    }
    Ok(Ok(Point {
        scene,
        quantity,
        mode,
        ratio,
        error,
        noise_floor,
    }))
}

/// Join the bench's rows (with their lines) with the summary's errors by
/// the rules above.
///
/// # Errors
/// A mode on one side of a scene and not the other, a key twice on one
/// side, a value out of range, or nothing to draw at all.
pub fn join(
    bench: &[(u64, BenchRow)],
    summary: &[ErrorRow],
    files: Files<'_>,
) -> Result<Join, LadderError> {
    let mut out = Join::default();
    let (accuracy, bench_csv) = (files.accuracy.display(), files.bench.display());
    for scene in &SCENES {
        let (name, dim, scene_label) = *scene;
        let bench_key = format!("{name} ({PRECISION}, {BALLS} balls, parallel false)");
        let rows = bench.iter().filter(|(_, r)| {
            (r.scene.as_str(), r.precision, r.balls, r.parallel) == (name, PRECISION, BALLS, false)
        });
        let rows = rows.map(|(line, r)| (format!("line {line}"), r, r.mode));
        let costs = by_mode(rows, &bench_key, files.bench)?;
        let mut errors = Vec::new();
        for (quantity, label) in QUANTITIES {
            let key = format!("{quantity} of scene {GAS} in {dim}D ({PRECISION}, dt_div 1)");
            let entries = summary.iter().enumerate().filter(|(_, e)| {
                let k = (e.scene.as_str(), e.dimension, e.precision, e.dt_div);
                k == (GAS, dim, PRECISION, 1) && e.quantity == quantity
            });
            let entries = entries.map(|(i, e)| (format!("errors[{i}]"), e, e.mode));
            errors.push((label, key, by_mode(entries, quantity, files.accuracy)?));
        }
        let in_errors = errors.iter().flat_map(|e| e.2.keys());
        for mode in BTreeSet::from_iter(costs.keys().chain(in_errors)) {
            if !costs.contains_key(mode) {
                let message = format!("no {mode} for {bench_key}, which {accuracy} has");
                return Err(LadderError::new(files.bench, message));
            }
            if let Some((_, key, _)) = errors.iter().find(|e| !e.2.contains_key(mode)) {
                let message = format!("no {mode} for {key}, which {bench_csv} has");
                return Err(LadderError::new(files.accuracy, message));
            }
        }
        for (label, _, entries) in &errors {
            for (mode, entry) in entries {
                let what = format!("{scene_label}, {label}, {mode}");
                match point((scene, label), &costs[mode], entry, files)? {
                    Ok(p) => out.points.push(p),
                    Err(why) => out.skipped.push(format!("{what}: {why}")),
                }
            }
        }
    }
    if out.points.is_empty() {
        let skipped = match out.skipped.len() {
            0 => String::new(),
            n => format!(" ({n} points left out for a value that is not a number)"),
        };
        let message = format!(
            "nothing to draw: no scene of the join is in both this file and {accuracy}{skipped}"
        );
        return Err(LadderError::new(files.bench, message));
    }
    Ok(out)
}
