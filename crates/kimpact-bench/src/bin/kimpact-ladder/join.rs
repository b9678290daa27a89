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
//!   out (with a note); the same key twice on one side is an error.
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

use crate::bench::BenchRow;
use crate::error::LadderError;
use crate::summary::ErrorEntry;

/// A bench scene and the accuracy scene it is measured against.
#[derive(Debug, PartialEq, Eq)]
pub struct SceneRule {
    /// The bench's scene (`scene` column of `results.csv`).
    pub bench: &'static str,
    /// The accuracy study's scene (`scene` of the summary's errors).
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

/// A (scene, quantity, mode) left out, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Skipped {
    /// The scene.
    pub scene: &'static SceneRule,
    /// The quantity.
    pub quantity: &'static QuantityRule,
    /// The mode.
    pub mode: Mode,
    /// Which value is not a number, and where.
    pub reason: String,
}

/// What the join gives.
#[derive(Clone, Debug, PartialEq)]
pub struct Join {
    /// The points, by scene, quantity and mode (in the rules' orders).
    pub points: Vec<Point>,
    /// The points left out for a value that is not a number.
    pub skipped: Vec<Skipped>,
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

/// The bench rows of a scene in the join's build, by mode.
fn costs<'a>(
    rule: &SceneRule,
    bench: &'a [BenchRow],
    files: Files<'_>,
) -> Result<BTreeMap<Mode, &'a BenchRow>, LadderError> {
    let mut by_mode: BTreeMap<Mode, &BenchRow> = BTreeMap::new();
    let rows = bench.iter().filter(|r| {
        r.scene == rule.bench
            && r.precision == PRECISION
            && r.balls == BALLS
            && r.parallel == PARALLEL
    });
    for r in rows {
        if r.dim != rule.dimension {
            return Err(LadderError::Dimension {
                path: files.bench.to_owned(),
                line: r.line,
                scene: r.scene.clone(),
                found: r.dim,
                expected: rule.dimension,
            });
        }
        if let Some(first) = by_mode.insert(r.mode, r) {
            return Err(LadderError::Duplicate {
                path: files.bench.to_owned(),
                what: format!("{} in mode {}", bench_key(rule), r.mode),
                first: format!("line {}", first.line),
                second: format!("line {}", r.line),
            });
        }
    }
    Ok(by_mode)
}

/// The summary's errors of a scene and quantity in the join's build, by
/// mode.
fn errors<'a>(
    rule: &SceneRule,
    quantity: &QuantityRule,
    errors: &'a [ErrorEntry],
    files: Files<'_>,
) -> Result<BTreeMap<Mode, &'a ErrorEntry>, LadderError> {
    let mut by_mode: BTreeMap<Mode, &ErrorEntry> = BTreeMap::new();
    let entries = errors.iter().filter(|e| {
        e.scene == rule.accuracy
            && e.dimension == rule.dimension
            && e.precision == PRECISION
            && e.dt_div == DT_DIV
            && e.quantity == quantity.name
    });
    for e in entries {
        if let Some(first) = by_mode.insert(e.mode, e) {
            return Err(LadderError::Duplicate {
                path: files.accuracy.to_owned(),
                what: format!("{} in mode {}", accuracy_key(rule, quantity), e.mode),
                first: format!("errors[{}]", first.index),
                second: format!("errors[{}]", e.index),
            });
        }
    }
    Ok(by_mode)
}

/// The bench rows a scene rule selects, in words.
fn bench_key(rule: &SceneRule) -> String {
    format!(
        "{} ({}, {BALLS} balls, parallel {PARALLEL})",
        rule.bench, PRECISION
    )
}

/// The summary's errors a scene and quantity select, in words.
fn accuracy_key(rule: &SceneRule, quantity: &QuantityRule) -> String {
    format!(
        "{} of scene {} in {}D ({}, dt_div {DT_DIV})",
        quantity.name, rule.accuracy, rule.dimension, PRECISION
    )
}

/// The point of one bench row and one error, `Ok(Err(_))` when a value is
/// not a number.
fn point(
    scene: &'static SceneRule,
    quantity: &'static QuantityRule,
    cost: &BenchRow,
    entry: &ErrorEntry,
    files: Files<'_>,
) -> Result<Result<Point, Skipped>, LadderError> {
    let skip = |reason: String| {
        Ok(Err(Skipped {
            scene,
            quantity,
            mode: cost.mode,
            reason,
        }))
    };
    if !cost.ratio.is_finite() {
        let said = if cost.error.is_empty() {
            String::new()
        } else {
            format!("; the bench's error: {}", cost.error)
        };
        return skip(format!(
            "×native is {} in {}, line {}{said}",
            cost.ratio,
            files.bench.display(),
            cost.line
        ));
    }
    let at = |field: &str| format!("errors[{}].{field}", entry.index);
    if !entry.error.is_finite() {
        return skip(format!(
            "the error is {} in {}, {}",
            entry.error,
            files.accuracy.display(),
            at("error")
        ));
    }
    if let Some(floor) = entry.noise_floor.filter(|f| !f.is_finite()) {
        return skip(format!(
            "the noise floor is {floor} in {}, {}",
            files.accuracy.display(),
            at("noise_floor")
        ));
    }
    if cost.ratio <= 0.0 {
        return Err(LadderError::OutOfRange {
            path: files.bench.to_owned(),
            at: format!("line {}, column `ratio`", cost.line),
            what: "×native",
            value: cost.ratio,
            expected: "not above 0",
        });
    }
    let negative = |what, value: f64, field| LadderError::OutOfRange {
        path: files.accuracy.to_owned(),
        at: at(field),
        what,
        value,
        expected: "below 0",
    };
    if entry.error < 0.0 {
        return Err(negative("the error", entry.error, "error"));
    }
    if let Some(floor) = entry.noise_floor.filter(|f| *f < 0.0) {
        return Err(negative("the noise floor", floor, "noise_floor"));
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

/// Join the bench's rows with the summary's errors by the rules above.
///
/// # Errors
/// A mode on one side of a scene and not the other, a key twice on one
/// side, a bench row of another dimension than its accuracy scene, a value
/// out of range, or nothing to draw at all.
pub fn join(
    bench: &[BenchRow],
    summary: &[ErrorEntry],
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
        for &mode in &modes {
            if !costs.contains_key(&mode) {
                return Err(LadderError::ModeMissing {
                    path: files.bench.to_owned(),
                    what: bench_key(scene),
                    mode,
                    other: files.accuracy.to_owned(),
                });
            }
            if let Some((q, _)) = errors.iter().find(|(_, e)| !e.contains_key(&mode)) {
                return Err(LadderError::ModeMissing {
                    path: files.accuracy.to_owned(),
                    what: accuracy_key(scene, q),
                    mode,
                    other: files.bench.to_owned(),
                });
            }
        }
        for (quantity, by_mode) in &errors {
            for (mode, entry) in by_mode {
                match point(scene, quantity, costs[mode], entry, files)? {
                    Ok(p) => out.points.push(p),
                    Err(s) => out.skipped.push(s),
                }
            }
        }
    }
    if out.points.is_empty() {
        return Err(LadderError::EmptyJoin {
            bench: files.bench.to_owned(),
            accuracy: files.accuracy.to_owned(),
            skipped: out.skipped.len(),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files() -> Files<'static> {
        Files {
            bench: Path::new("results.csv"),
            accuracy: Path::new("summary.json"),
        }
    }

    fn row(line: usize, scene: &str, dim: usize, mode: Mode, ratio: f64) -> BenchRow {
        BenchRow {
            line,
            scene: scene.into(),
            dim,
            precision: Precision::F32,
            parallel: false,
            balls: 1000,
            mode,
            ratio,
            error: String::new(),
        }
    }

    fn entry(index: usize, dimension: usize, mode: Mode, quantity: &str, error: f64) -> ErrorEntry {
        ErrorEntry {
            index,
            scene: "gas".into(),
            dimension,
            precision: Precision::F32,
            mode,
            dt_div: 1,
            quantity: quantity.into(),
            error,
            noise_floor: (quantity == "impact_rate_error").then_some(0.002),
        }
    }

    /// Both gases in every mode, and rows and errors the join must ignore.
    fn inputs() -> (Vec<BenchRow>, Vec<ErrorEntry>) {
        let mut bench = Vec::new();
        let mut summary = Vec::new();
        for (d, scene) in [(2, "gas2d"), (3, "gas3d")] {
            for (i, mode) in Mode::ALL.into_iter().enumerate() {
                let ratio = 1.0 + 0.1 * i as f64 + 0.01 * d as f64;
                bench.push(row(bench.len() + 2, scene, d, mode, ratio));
                let mut other = row(bench.len() + 2, scene, d, mode, 9.0);
                other.balls = 10_000;
                bench.push(other);
                let mut other = row(bench.len() + 2, scene, d, mode, 9.0);
                other.precision = Precision::F64;
                bench.push(other);
                for q in [
                    "impact_rate_error",
                    "energy_error",
                    "ks_speeds_vs_reference",
                ] {
                    let error = 0.1 / (1 + i) as f64 / d as f64;
                    summary.push(entry(summary.len(), d, mode, q, error));
                    let mut other = entry(summary.len(), d, mode, q, 7.0);
                    other.dt_div = 2;
                    summary.push(other);
                }
            }
        }
        bench.push(row(bench.len() + 2, "pit3d", 3, Mode::Exact, 1.1));
        (bench, summary)
    }

    #[test]
    fn joins_each_gas_with_its_dimension_in_the_chosen_build() {
        let (bench, summary) = inputs();
        let j = join(&bench, &summary, files()).unwrap();
        assert_eq!(j.points.len(), 2 * 2 * 4);
        assert!(j.skipped.is_empty() && j.absent.is_empty());
        let p = &j.points[0];
        assert_eq!(
            (p.scene.bench, p.quantity.name, p.mode),
            ("gas2d", "impact_rate_error", Mode::Native)
        );
        assert_eq!((p.ratio, p.error, p.noise_floor), (1.02, 0.05, Some(0.002)));
        let p = &j.points[15];
        assert_eq!(
            (p.scene.bench, p.quantity.name, p.mode),
            ("gas3d", "energy_error", Mode::Exact)
        );
        assert!((p.ratio - 1.33).abs() < 1e-12);
        assert!((p.error - 0.1 / 12.0).abs() < 1e-15);
        assert_eq!(p.noise_floor, None);
    }

    #[test]
    fn a_mode_on_one_side_only_is_an_error_naming_the_file_without_it() {
        let (mut bench, summary) = inputs();
        bench.retain(|r| !(r.scene == "gas3d" && r.mode == Mode::Impulse));
        let e = join(&bench, &summary, files()).unwrap_err();
        assert!(
            matches!(
                e,
                LadderError::ModeMissing {
                    mode: Mode::Impulse,
                    ..
                }
            ),
            "{e}"
        );
        assert_eq!(
            e.to_string(),
            "results.csv: no impulse for gas3d (f32, 1000 balls, parallel false), which summary.json has"
        );
        let (bench, mut summary) = inputs();
        summary.retain(|s| {
            !(s.dimension == 2 && s.mode == Mode::Native && s.quantity == "energy_error")
        });
        let e = join(&bench, &summary, files()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "summary.json: no native for energy_error of scene gas in 2D (f32, dt_div 1), which results.csv has"
        );
    }

    #[test]
    fn a_nan_leaves_its_point_out_with_the_reason() {
        let (mut bench, mut summary) = inputs();
        let r = bench
            .iter_mut()
            .find(|r| r.scene == "gas2d" && r.mode == Mode::Exact)
            .unwrap();
        r.ratio = f64::NAN;
        r.error = "timed out".into();
        let line = r.line;
        let s = summary
            .iter_mut()
            .find(|s| {
                s.dimension == 3
                    && s.mode == Mode::Native
                    && s.quantity == "impact_rate_error"
                    && s.dt_div == 1
            })
            .unwrap();
        s.noise_floor = Some(f64::NAN);
        let j = join(&bench, &summary, files()).unwrap();
        assert_eq!(j.points.len(), 16 - 3);
        assert!(
            j.points
                .iter()
                .all(|p| p.ratio.is_finite() && p.error.is_finite())
        );
        assert_eq!(j.skipped.len(), 3);
        assert_eq!(
            j.skipped[0].reason,
            format!("×native is NaN in results.csv, line {line}; the bench's error: timed out")
        );
        assert!(
            j.skipped[2]
                .reason
                .starts_with("the noise floor is NaN in summary.json, errors[")
        );
    }

    #[test]
    fn nothing_to_draw_is_an_error() {
        let (mut bench, summary) = inputs();
        for r in &mut bench {
            r.ratio = f64::NAN;
        }
        let e = join(&bench, &summary, files()).unwrap_err();
        assert!(
            matches!(e, LadderError::EmptyJoin { skipped: 16, .. }),
            "{e}"
        );
        let bench = vec![row(2, "pit3d", 3, Mode::Native, 1.0)];
        let e = join(&bench, &[], files()).unwrap_err();
        assert!(
            matches!(e, LadderError::EmptyJoin { skipped: 0, .. }),
            "{e}"
        );
    }

    #[test]
    fn a_scene_in_neither_file_is_left_out() {
        let (mut bench, mut summary) = inputs();
        bench.retain(|r| r.scene != "gas3d");
        summary.retain(|s| s.dimension != 3);
        let j = join(&bench, &summary, files()).unwrap();
        assert_eq!(j.points.len(), 8);
        assert_eq!(j.absent, vec![&SCENES[1]]);
    }

    #[test]
    fn twice_the_same_key_or_another_dimension_is_an_error() {
        let (mut bench, summary) = inputs();
        bench.push(row(99, "gas2d", 2, Mode::Exact, 1.5));
        let e = join(&bench, &summary, files()).unwrap_err();
        assert!(e.to_string().contains("at line 11 and line 99"), "{e}");
        let (mut bench, summary) = inputs();
        bench[0].dim = 3;
        let e = join(&bench, &summary, files()).unwrap_err();
        assert!(
            matches!(
                e,
                LadderError::Dimension {
                    line: 2,
                    found: 3,
                    expected: 2,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn a_negative_error_or_a_ratio_at_zero_is_an_error() {
        let (mut bench, summary) = inputs();
        bench[0].ratio = 0.0;
        let e = join(&bench, &summary, files()).unwrap_err();
        assert!(
            matches!(
                e,
                LadderError::OutOfRange {
                    what: "×native",
                    ..
                }
            ),
            "{e}"
        );
        let (bench, mut summary) = inputs();
        summary[0].error = -1.0;
        let e = join(&bench, &summary, files()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "summary.json, errors[0].error: the error is -1, below 0"
        );
    }

    #[test]
    fn errors_at_or_below_the_floor_or_zero_are_drawn_hollow() {
        let p = |error, noise_floor| Point {
            scene: &SCENES[0],
            quantity: &QUANTITIES[0],
            mode: Mode::Exact,
            ratio: 1.0,
            error,
            noise_floor,
        };
        assert_eq!(p(0.01, Some(0.002)).level(), Level::Measured(0.01));
        assert_eq!(p(0.002, Some(0.002)).level(), Level::AtFloor(0.002));
        assert_eq!(p(0.0, Some(0.002)).level(), Level::AtFloor(0.002));
        assert_eq!(p(1e-6, None).level(), Level::Measured(1e-6));
        assert_eq!(p(0.0, None).level(), Level::Zero);
        assert_eq!(p(0.0, Some(0.0)).level(), Level::Zero);
    }
}
