//! `kimpact-ladder` on small fixtures written to a temporary folder with
//! the types the bench and the accuracy study write ([`BenchRow`],
//! [`AccuracySummary`]): the plot holds one point (one `<circle>`) per
//! joined (scene, quantity, mode), the page the joined table; a NaN leaves
//! its points out with a note; a missing column, file, field or mode, or an
//! unreadable number, fails with a message naming it and leaves existing
//! outputs as they were.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use kimpact::{Mode, Precision};
use kimpact_harness::{AccuracySummary, BenchRow, ErrorRow};
use serde_json::Value;

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("ladder")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The fixtures' ×native: (scene, dim, ratios by mode).
const RATIOS: [(&str, usize, [f64; 4]); 2] = [
    ("gas2d", 2, [1.0, 1.19, 1.3, 1.6]),
    ("gas3d", 3, [1.0, 1.14, 1.11, 1.33]),
];

/// A bench row as the bench writes it.
fn row(
    scene: &str,
    dim: usize,
    precision: Precision,
    balls: usize,
    mode: Mode,
    ratio: f64,
) -> BenchRow {
    BenchRow {
        scene: scene.to_owned(),
        dim,
        precision,
        parallel: false,
        balls,
        mode,
        rounds: 1,
        samples: 200,
        median_us: 300.5 * ratio,
        native_median_us: 300.5,
        ratio,
        ratio_min: ratio,
        ratio_max: ratio,
        ratio_median_rounds: ratio,
        delta_us: 300.5 * (ratio - 1.0),
        allocs_per_step: 20.0,
        native_allocs_per_step: 20.0,
        kimpact_allocs_per_step: 0.0,
        peak_rss_mib: 12.0,
        impacts_per_step: 5.0,
        error: None,
    }
}

/// The bench's CSV, written with its own type: the joined rows, each
/// passed through `edit`, and rows the join must ignore (other balls,
/// precisions, scenes).
fn bench_csv(edit: impl Fn(&mut BenchRow)) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    for (scene, dim, ratios) in RATIOS {
        for (mode, ratio) in Mode::ALL.into_iter().zip(ratios) {
            let mut r = row(scene, dim, Precision::F32, 1000, mode, ratio);
            edit(&mut r);
            w.serialize(r).unwrap();
            w.serialize(row(scene, dim, Precision::F32, 10_000, mode, 9.0))
                .unwrap();
            w.serialize(row(scene, dim, Precision::F64, 1000, mode, 8.0))
                .unwrap();
        }
    }
    let mut failed = row("pit3d", 3, Precision::F32, 1000, Mode::Exact, 1.1);
    failed.error = Some("failed: a, b".into());
    w.serialize(failed).unwrap();
    String::from_utf8(w.into_inner().unwrap()).unwrap()
}

/// The line of the joined row of `scene` in `mode` in [`bench_csv`]'s file
/// (the header is line 1).
fn line_of(scene: &str, mode: Mode) -> usize {
    let s = RATIOS.iter().position(|r| r.0 == scene).unwrap();
    let m = Mode::ALL.iter().position(|&x| x == mode).unwrap();
    2 + 3 * (4 * s + m)
}

/// The fixtures' errors: (dim, quantity, noise floor, errors by mode).
/// The 2D exact impact rate is below its floor (drawn hollow at it), the
/// 2D exact energy error 0 without a floor (hollow at the bottom).
const ERRORS: [(usize, &str, Option<f64>, [f64; 4]); 4] = [
    (
        2,
        "impact_rate_error",
        Some(0.0025),
        [0.3, 0.5, 0.008, 0.001],
    ),
    (2, "energy_error", None, [0.2, 0.3, 3e-6, 0.0]),
    (
        3,
        "impact_rate_error",
        Some(0.002),
        [0.7, 0.9, 0.005, 0.004],
    ),
    (3, "energy_error", None, [0.8, 0.9, 1e-5, 1.1e-5]),
];

/// An accuracy summary, written with its own type, with the joined errors
/// and entries the join must ignore (another time step, quantity,
/// precision, scene); as JSON, for the tests to edit.
fn summary() -> Value {
    let mut errors = Vec::new();
    for (dim, quantity, floor, values) in ERRORS {
        for (mode, error) in Mode::ALL.into_iter().zip(values) {
            let e = ErrorRow {
                scene: "gas".into(),
                dimension: dim,
                precision: Precision::F32,
                mode,
                dt_div: 1,
                quantity: quantity.into(),
                error,
                noise_floor: floor,
            };
            let ignored = [
                ErrorRow {
                    dt_div: 2,
                    ..e.clone()
                },
                ErrorRow {
                    precision: Precision::F64,
                    ..e.clone()
                },
                ErrorRow {
                    quantity: "ks_speeds_vs_reference".into(),
                    ..e.clone()
                },
                ErrorRow {
                    scene: "cradle".into(),
                    ..e.clone()
                },
            ];
            errors.push(e);
            errors.extend(ignored);
        }
    }
    let command = "kimpact-accuracy (fixture)".into();
    let s = AccuracySummary {
        command,
        quick: false,
        errors,
    };
    serde_json::to_value(s).unwrap()
}

/// The paths of one test's inputs and outputs.
struct Files {
    csv: PathBuf,
    json: PathBuf,
    svg: PathBuf,
    md: PathBuf,
}

impl Files {
    /// The fixtures written into a fresh folder `name`.
    fn new(name: &str, csv: &str, summary: &Value) -> Files {
        let dir = folder(name);
        let f = Files {
            csv: dir.join("bench/results.csv"),
            json: dir.join("accuracy-summary.json"),
            svg: dir.join("out/ladder.svg"),
            md: dir.join("out/ladder.md"),
        };
        std::fs::create_dir_all(f.csv.parent().unwrap()).unwrap();
        std::fs::write(&f.csv, csv).unwrap();
        std::fs::write(&f.json, serde_json::to_string_pretty(summary).unwrap()).unwrap();
        f
    }

    /// The arguments naming these files.
    fn args(&self) -> Vec<std::ffi::OsString> {
        let mut a = Vec::new();
        for (flag, path) in [
            ("--bench-csv", &self.csv),
            ("--accuracy-json", &self.json),
            ("--svg", &self.svg),
            ("--md", &self.md),
        ] {
            a.push(flag.into());
            a.push(path.clone().into_os_string());
        }
        a
    }

    /// Outputs already there, to be left alone on an error.
    fn old_outputs(&self) {
        std::fs::create_dir_all(self.svg.parent().unwrap()).unwrap();
        std::fs::write(&self.svg, "old svg").unwrap();
        std::fs::write(&self.md, "old md").unwrap();
    }

    fn assert_old_outputs(&self) {
        assert_eq!(std::fs::read_to_string(&self.svg).unwrap(), "old svg");
        assert_eq!(std::fs::read_to_string(&self.md).unwrap(), "old md");
        assert_eq!(
            entries(self.svg.parent().unwrap()),
            ["ladder.md", "ladder.svg"]
        );
    }
}

/// The names in a folder, sorted.
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Run the ladder on `files`.
fn ladder(files: &Files) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kimpact-ladder"))
        .args(files.args())
        .output()
        .expect("kimpact-ladder starts")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The table rows of the page.
fn table(md: &str) -> Vec<&str> {
    md.lines()
        .filter(|l| l.starts_with("| ") && l.contains(" gas |"))
        .collect()
}

#[test]
fn draws_one_point_per_joined_scene_quantity_and_mode() {
    let f = Files::new("ok", &bench_csv(|_| ()), &summary());
    let out = ladder(&f);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = std::fs::read_to_string(&f.svg).unwrap();
    assert!(svg.starts_with("<svg"), "not an SVG");
    assert_eq!(svg.matches("<circle").count(), 2 * 2 * 4);
    assert!(!svg.contains("NaN"));
    for text in [
        "× native rapier (time per step)",
        "error",
        "impact rate error",
        "energy error",
        "2D gas",
        "3D gas",
        "exact",
        "noise floor",
        "Hollow: at or below the noise floor",
    ] {
        assert!(svg.contains(text), "no {text:?} in the SVG");
    }

    let md = std::fs::read_to_string(&f.md).unwrap();
    let rows = table(&md);
    assert_eq!(rows.len(), 16, "{md}");
    for row in [
        "| 2D gas | impact rate error | native | 1.000 | 3.00e-1 | 2.50e-3 | the error |",
        "| 2D gas | impact rate error | exact | 1.600 | 1.00e-3 | 2.50e-3 | the noise floor (hollow) |",
        "| 2D gas | energy error | exact | 1.600 | 0.00e0 | — | the bottom (hollow) |",
        "| 3D gas | impact rate error | impulse | 1.110 | 5.00e-3 | 2.00e-3 | the error |",
        "| 3D gas | energy error | exact | 1.330 | 1.10e-5 | — | the error |",
    ] {
        assert!(rows.contains(&row), "no row {row:?} in\n{md}");
    }
    // scene, then quantity, then mode
    assert!(rows[0].starts_with("| 2D gas | impact rate error | native"));
    assert!(rows[15].starts_with("| 3D gas | energy error | exact"));
    assert!(md.contains("![error against × native rapier, per mode and scene](ladder.svg)"));
    assert!(md.contains("--bin kimpact-ladder -- --bench-csv"));
    assert!(md.contains("written by `kimpact-accuracy (fixture)`"));
    assert!(!md.contains("## Left out"));
    assert_eq!(
        entries(f.svg.parent().unwrap()),
        ["ladder.md", "ladder.svg"]
    );
}

#[test]
fn a_nan_leaves_its_points_out_with_a_note() {
    let csv = bench_csv(|r| {
        if r.scene == "gas3d" && r.mode == Mode::Impulse {
            r.ratio = f64::NAN;
            r.error = Some("timed out, after 600 s".into());
        }
    });
    let mut s = summary();
    // serde_json writes a NaN as null
    let entry = s["errors"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|e| {
            e["dimension"] == 2
                && e["mode"] == "native"
                && e["quantity"] == "energy_error"
                && e["dt_div"] == 1
                && e["precision"] == "f32"
        })
        .unwrap();
    entry["error"] = Value::Null;
    let f = Files::new("nan", &csv, &s);
    let out = ladder(&f);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = std::fs::read_to_string(&f.svg).unwrap();
    assert_eq!(svg.matches("<circle").count(), 16 - 3);
    assert!(!svg.contains("NaN"));
    let md = std::fs::read_to_string(&f.md).unwrap();
    assert_eq!(table(&md).len(), 13);
    assert!(md.contains("## Left out"), "{md}");
    let note = format!(
        "- 3D gas, impact rate error, impulse: ×native is NaN in {}, line {}; the bench's error: timed out, after 600 s.",
        f.csv.display(),
        line_of("gas3d", Mode::Impulse)
    );
    assert!(md.contains(&note), "no {note:?} in\n{md}");
    assert!(
        md.contains("- 2D gas, energy error, native: the error is NaN in "),
        "{md}"
    );
}

#[test]
fn a_missing_column_fails_naming_it_and_leaves_the_outputs_alone() {
    let csv = bench_csv(|_| ()).replacen(",ratio,", ",speedup,", 1);
    assert!(csv.lines().next().unwrap().contains(",speedup,"));
    let f = Files::new("column", &csv, &summary());
    f.old_outputs();
    let out = ladder(&f);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains(&f.csv.display().to_string()) && e.contains("missing field `ratio`"),
        "{e}"
    );
    f.assert_old_outputs();
}

#[test]
fn a_missing_file_fails_naming_it() {
    let f = Files::new("file", &bench_csv(|_| ()), &summary());
    f.old_outputs();
    std::fs::remove_file(&f.json).unwrap();
    let out = ladder(&f);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains(&format!("{}: cannot read", f.json.display())),
        "{e}"
    );
    f.assert_old_outputs();
}

#[test]
fn an_unreadable_number_or_a_missing_mode_fails_naming_it() {
    // The ratio 1.6 of the 2D gas in exact mode written as "1.6x".
    let line = line_of("gas2d", Mode::Exact);
    let csv: String = bench_csv(|_| ())
        .lines()
        .enumerate()
        .map(|(i, l)| match i + 1 == line {
            true => l.replacen(",1.6,", ",1.6x,", 1) + "\n",
            false => format!("{l}\n"),
        })
        .collect();
    assert!(csv.contains(",1.6x,"));
    let f = Files::new("number", &csv, &summary());
    let out = ladder(&f);
    assert!(!out.status.success());
    let e = stderr(&out);
    let at = format!("{}: column `ratio`: ", f.csv.display());
    assert!(
        e.contains(&at) && e.contains(&format!("line: {line}")),
        "{e}"
    );

    let line = line_of("gas2d", Mode::Restitution);
    let csv: String = bench_csv(|_| ())
        .lines()
        .enumerate()
        .filter(|(i, _)| i + 1 != line)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let f = Files::new("mode", &csv, &summary());
    f.old_outputs();
    let out = ladder(&f);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains(&format!("{}: no restitution for gas2d", f.csv.display())),
        "{e}"
    );
    assert!(
        e.contains(&format!("which {} has", f.json.display())),
        "{e}"
    );
    f.assert_old_outputs();
}

#[test]
fn an_entry_without_a_field_fails_naming_it() {
    let mut s = summary();
    s["errors"][5].as_object_mut().unwrap().remove("error");
    let f = Files::new("entry", &bench_csv(|_| ()), &s);
    let out = ladder(&f);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains(&format!("{}: errors[5]", f.json.display()))
            && e.contains("missing field `error`"),
        "{e}"
    );
}
