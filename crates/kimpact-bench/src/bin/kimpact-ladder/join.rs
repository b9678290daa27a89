//! The join of the bench's costs with the accuracy study's errors. Every
//! rule of it lives here:
//!
//! - **Scenes** ([`SCENES`]): the bench's `gas2d` is measured against the
//!   accuracy study's `gas` in 2D, `gas3d` against `gas` in 3D: elastic
//!   gases of balls in a closed box, the same kind of scene but not the same
//!   balls (the bench's has [`BALLS`], the study's its own).
//! - **Build**: f32 on both sides ([`PRECISION`]); the bench's rows of
//!   [`BALLS`] balls without rapier's `parallel` feature; the study's errors
//!   at rapier's own time step (`dt_div` 1).
//! - **Quantities** ([`QUANTITIES`]): `impact_rate_error` (with a noise
//!   floor) and `energy_error` (without); one point per (scene, quantity,
//!   mode).
//! - **Modes**: every mode either side has for a joined scene must be on
//!   both sides, in every quantity; the same key twice on one side is an
//!   error.
//! - **Values**: a ×native, error or noise floor that is not a number (NaN,
//!   infinite; `null` in the JSON) leaves its point out, with a note; a
//!   ×native at or below 0, a negative error or noise floor is an error.
//! - **On a log axis** ([`Level`]): an error above its noise floor is drawn
//!   at itself; one at or below a positive noise floor at the floor,
//!   hollow; an error of 0 without a positive floor at the axis's bottom,
//!   hollow.

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
#[derive(Clone, Debug, PartialEq)]
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
/// fault (an input that cannot be read or breaks a rule of the join, an
/// output that cannot be drawn or written) and what is wrong, and where.
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
    let (points, skipped) = (vec![], vec![]);
    let mut out = Join { points, skipped };
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
        let modes: BTreeSet<Mode> = costs
            .keys()
            .chain(errors.iter().flat_map(|e| e.2.keys()))
            .copied()
            .collect();
        for mode in modes {
            if !costs.contains_key(&mode) {
                let message = format!(
                    "no {mode} for {bench_key}, which {} has",
                    files.accuracy.display()
                );
                return Err(LadderError::new(files.bench, message));
            }
            if let Some((_, key, _)) = errors.iter().find(|e| !e.2.contains_key(&mode)) {
                let message = format!("no {mode} for {key}, which {} has", files.bench.display());
                return Err(LadderError::new(files.accuracy, message));
            }
        }
        for (label, _, entries) in &errors {
            for (mode, (index, e)) in entries {
                let (line, cost) = &costs[mode];
                let what = format!("{scene_label}, {label}, {mode}");
                let at = |field: &str| format!("{}, {index}.{field}", files.accuracy.display());
                let nan = if !cost.ratio.is_finite() {
                    let said = cost.error.as_ref();
                    let said = said.map(|e| format!("; the bench's error: {e}"));
                    let (bench, said) = (files.bench.display(), said.unwrap_or_default());
                    Some(format!(
                        "×native is {} in {bench}, {line}{said}",
                        cost.ratio
                    ))
                } else if !e.error.is_finite() {
                    Some(format!("the error is {} in {}", e.error, at("error")))
                } else {
                    let floor = e.noise_floor.filter(|f| !f.is_finite());
                    floor.map(|f| format!("the noise floor is {f} in {}", at("noise_floor")))
                };
                if let Some(reason) = nan {
                    out.skipped.push(format!("{what}: {reason}"));
                    continue;
                }
                if cost.ratio <= 0.0 {
                    let message = format!("{line}: ×native is {}, not above 0", cost.ratio);
                    return Err(LadderError::new(files.bench, message));
                }
                if e.error < 0.0 || e.noise_floor.is_some_and(|f| f < 0.0) {
                    let message = format!("{index}: a negative error or noise floor");
                    return Err(LadderError::new(files.accuracy, message));
                }
                let (ratio, error, noise_floor, mode) = (cost.ratio, e.error, e.noise_floor, *mode);
                let quantity = label;
                out.points.push(Point {
                    scene,
                    quantity,
                    mode,
                    ratio,
                    error,
                    noise_floor,
                });
            }
        }
    }
    if out.points.is_empty() {
        let skipped = match out.skipped.len() {
            0 => String::new(),
            n => format!(" ({n} points left out for a value that is not a number)"),
        };
        let message = format!(
            "nothing to draw: no scene of the join is in both this file and {}{skipped}",
            files.accuracy.display()
        );
        return Err(LadderError::new(files.bench, message));
    }
    Ok(out)
}
