//! The join of the bench's costs with the accuracy study's errors. Every
//! rule of it lives here:
//!
//! - **Scenes** ([`SCENES`]): the bench's `gas2d` is measured against the
//!   accuracy study's `gas` in 2D, `gas3d` against `gas` in 3D. Both are
//!   elastic gases of balls in a closed box, the same kind of scene but not
//!   the same balls: the bench's has [`BALLS`] balls, the study's its own.
//! - **Build**: f32 on both sides ([`PRECISION`]); the bench's rows of
//!   [`BALLS`] balls without rapier's `parallel` feature ([`PARALLEL`]);
//!   the study's errors at rapier's own time step (`dt_div` = [`DT_DIV`]).
//! - **Quantities** ([`QUANTITIES`]): `impact_rate_error` (with a noise
//!   floor) and `energy_error` (without); one point per (scene, quantity,
//!   mode).
//! - **Modes**: every mode that either side has for a joined scene must be
//!   on both sides, and in every quantity; a scene in neither file is left
//!   out (with a note); the same key twice on one side is an error, and so
//!   is a bench row of another dimension than its scene's.
//! - **Values**: a ×native, error or noise floor that is not a number
//!   (NaN, infinite; `null` in the JSON) leaves its point out, with a note
//!   in the page; a ×native at or below 0, a negative error or noise floor
//!   is an error.
//! - **On a log axis** ([`Level`]): an error above its noise floor is drawn
//!   at itself; one at or below a positive noise floor at the floor,
//!   hollow; an error of 0 without a positive floor at the axis's bottom,
//!   hollow.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use kimpact::{Mode, Precision};
use kimpact_harness::{BenchRow, ErrorRow};

use crate::LadderError;

/// A bench scene and the accuracy scene it is measured against.
#[derive(Debug, PartialEq, Eq)]
pub struct SceneRule {
    /// The bench's scene (`scene` of [`BenchRow`]).
    pub bench: &'static str,
    /// The accuracy study's scene (`scene` of [`ErrorRow`]).
    pub accuracy: &'static str,
    /// The dimension of both.
    pub dimension: usize,
    /// How the plot and the page name it.
    pub label: &'static str,
}

/// A quantity of the accuracy summary that the ladder draws.
#[derive(Debug, PartialEq, Eq)]
pub struct QuantityRule {
    /// Its name in the summary (`quantity`).
    pub name: &'static str,
    /// How the plot and the page name it.
    pub label: &'static str,
}

/// The joined scenes, in the order of the plot and the page.
pub const SCENES: [SceneRule; 2] = [
    SceneRule {
        bench: "gas2d",
        accuracy: "gas",
        dimension: 2,
        label: "2D gas",
    },
    SceneRule {
        bench: "gas3d",
        accuracy: "gas",
        dimension: 3,
        label: "3D gas",
    },
];

/// The quantities drawn, one panel each.
pub const QUANTITIES: [QuantityRule; 2] = [
    QuantityRule {
        name: "impact_rate_error",
        label: "impact rate error",
    },
    QuantityRule {
        name: "energy_error",
        label: "energy error",
    },
];

/// The build of both sides.
pub const PRECISION: Precision = Precision::F32;
/// The accuracy errors at rapier's own time step.
pub const DT_DIV: usize = 1;
/// The bench's rows of this many balls.
pub const BALLS: usize = 1000;
/// The bench's rows without rapier's `parallel` feature.
pub const PARALLEL: bool = false;

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

/// One joined (scene, quantity, mode).
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// The scene.
    pub scene: &'static SceneRule,
    /// The quantity.
    pub quantity: &'static QuantityRule,
    /// The mode.
    pub mode: Mode,
    /// ×native from the bench.
    pub ratio: f64,
    /// The error from the accuracy summary.
    pub error: f64,
    /// Its noise floor, when the summary gives one.
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

/// What the join gives.
#[derive(Clone, Debug, PartialEq)]
pub struct Join {
    /// The points, by scene, quantity and mode (in the rules' orders).
    pub points: Vec<Point>,
    /// The points left out for a value that is not a number, each as
    /// "scene, quantity, mode: why".
    pub skipped: Vec<String>,
    /// The scenes that are in neither file.
    pub absent: Vec<&'static SceneRule>,
}

/// The two files, for the errors and notes.
#[derive(Clone, Copy, Debug)]
pub struct Files<'a> {
    /// The bench's CSV.
    pub bench: &'a Path,
    /// The accuracy summary.
    pub accuracy: &'a Path,
}

impl Files<'_> {
    fn bench_error(&self, message: String) -> LadderError {
        LadderError::Join {
            path: self.bench.to_owned(),
            message,
        }
    }

    fn accuracy_error(&self, message: String) -> LadderError {
        LadderError::Join {
            path: self.accuracy.to_owned(),
            message,
        }
    }
}

/// The bench rows of a scene in the join's build, by mode, with their
/// lines.
fn costs<'a>(
    rule: &SceneRule,
    bench: &'a [(u64, BenchRow)],
    files: Files<'_>,
) -> Result<BTreeMap<Mode, (u64, &'a BenchRow)>, LadderError> {
    let mut by_mode = BTreeMap::new();
    let rows = bench.iter().filter(|(_, r)| {
        r.scene == rule.bench
            && r.precision == PRECISION
            && r.balls == BALLS
            && r.parallel == PARALLEL
    });
    for (line, r) in rows {
        if r.dim != rule.dimension {
            return Err(files.bench_error(format!(
                "line {line}: {} has dim {}; it is joined to a {}D accuracy scene",
                r.scene, r.dim, rule.dimension
            )));
        }
        if let Some((first, _)) = by_mode.insert(r.mode, (*line, r)) {
            return Err(files.bench_error(format!(
                "{} in mode {} twice, at line {first} and line {line}",
                bench_key(rule),
                r.mode
            )));
        }
    }
    Ok(by_mode)
}

/// The summary's errors of a scene and quantity in the join's build, by
/// mode, with their places in the list.
fn errors<'a>(
    rule: &SceneRule,
    quantity: &QuantityRule,
    errors: &'a [ErrorRow],
    files: Files<'_>,
) -> Result<BTreeMap<Mode, (usize, &'a ErrorRow)>, LadderError> {
    let mut by_mode = BTreeMap::new();
    let entries = errors.iter().enumerate().filter(|(_, e)| {
        e.scene == rule.accuracy
            && e.dimension == rule.dimension
            && e.precision == PRECISION
            && e.dt_div == DT_DIV
            && e.quantity == quantity.name
    });
    for (index, e) in entries {
        if let Some((first, _)) = by_mode.insert(e.mode, (index, e)) {
            return Err(files.accuracy_error(format!(
                "{} in mode {} twice, at errors[{first}] and errors[{index}]",
                accuracy_key(rule, quantity),
                e.mode
            )));
        }
    }
    Ok(by_mode)
}

/// The bench rows a scene rule selects, in words.
fn bench_key(rule: &SceneRule) -> String {
    format!(
        "{} ({PRECISION}, {BALLS} balls, parallel {PARALLEL})",
        rule.bench
    )
}

/// The summary's errors a scene and quantity select, in words.
fn accuracy_key(rule: &SceneRule, quantity: &QuantityRule) -> String {
    format!(
        "{} of scene {} in {}D ({PRECISION}, dt_div {DT_DIV})",
        quantity.name, rule.accuracy, rule.dimension
    )
}

/// The point of one bench row (at `line`) and one error (at `index`), or
/// why it is left out.
fn point(
    (scene, quantity): (&'static SceneRule, &'static QuantityRule),
    (line, cost): (u64, &BenchRow),
    (index, entry): (usize, &ErrorRow),
    files: Files<'_>,
) -> Result<Result<Point, String>, LadderError> {
    let at = |field: &str| format!("{}, errors[{index}].{field}", files.accuracy.display());
    let not_a_number = if !cost.ratio.is_finite() {
        let said = cost
            .error
            .as_ref()
            .map_or(String::new(), |e| format!("; the bench's error: {e}"));
        let bench = files.bench.display();
        Some(format!(
            "×native is {} in {bench}, line {line}{said}",
            cost.ratio
        ))
    } else if !entry.error.is_finite() {
        Some(format!("the error is {} in {}", entry.error, at("error")))
    } else {
        let floor = entry.noise_floor.filter(|f| !f.is_finite());
        floor.map(|f| format!("the noise floor is {f} in {}", at("noise_floor")))
    };
    if let Some(reason) = not_a_number {
        let what = format!("{}, {}, {}", scene.label, quantity.label, cost.mode);
        return Ok(Err(format!("{what}: {reason}")));
    }
    if cost.ratio <= 0.0 {
        return Err(files.bench_error(format!(
            "line {line}, column `ratio`: ×native is {}, not above 0",
            cost.ratio
        )));
    }
    for (what, value) in [
        ("error", entry.error),
        ("noise_floor", entry.noise_floor.unwrap_or(0.0)),
    ] {
        if value < 0.0 {
            return Err(files.accuracy_error(format!("errors[{index}].{what}: {value}, below 0")));
        }
    }
    Ok(Ok(Point {
        scene,
        quantity,
        mode: cost.mode,
        ratio: cost.ratio,
        error: entry.error,
        noise_floor: entry.noise_floor,
    }))
}

/// Join the bench's rows (with their lines) with the summary's errors by
/// the rules above.
///
/// # Errors
/// A mode on one side of a scene and not the other, a key twice on one
/// side, a bench row of another dimension than its accuracy scene, a value
/// out of range, or nothing to draw at all.
pub fn join(
    bench: &[(u64, BenchRow)],
    summary: &[ErrorRow],
    files: Files<'_>,
) -> Result<Join, LadderError> {
    let mut out = Join {
        points: Vec::new(),
        skipped: Vec::new(),
        absent: Vec::new(),
    };
    for scene in &SCENES {
        let costs = costs(scene, bench, files)?;
        let errors = QUANTITIES
            .iter()
            .map(|q| errors(scene, q, summary, files).map(|e| (q, e)))
            .collect::<Result<Vec<_>, _>>()?;
        if costs.is_empty() && errors.iter().all(|(_, e)| e.is_empty()) {
            out.absent.push(scene);
            continue;
        }
        let modes: BTreeSet<Mode> = costs
            .keys()
            .chain(errors.iter().flat_map(|(_, e)| e.keys()))
            .copied()
            .collect();
        for mode in modes {
            if !costs.contains_key(&mode) {
                return Err(files.bench_error(format!(
                    "no {mode} for {}, which {} has",
                    bench_key(scene),
                    files.accuracy.display()
                )));
            }
            if let Some((q, _)) = errors.iter().find(|(_, e)| !e.contains_key(&mode)) {
                return Err(files.accuracy_error(format!(
                    "no {mode} for {}, which {} has",
                    accuracy_key(scene, q),
                    files.bench.display()
                )));
            }
        }
        for (quantity, by_mode) in &errors {
            for (mode, &entry) in by_mode {
                match point((scene, quantity), costs[mode], entry, files)? {
                    Ok(p) => out.points.push(p),
                    Err(s) => out.skipped.push(s),
                }
            }
        }
    }
    if out.points.is_empty() {
        let skipped = match out.skipped.len() {
            0 => String::new(),
            n => format!(" ({n} points left out for a value that is not a number)"),
        };
        return Err(files.bench_error(format!(
            "nothing to draw: no scene of the join is in both this file and {}{skipped}",
            files.accuracy.display()
        )));
    }
    Ok(out)
}
