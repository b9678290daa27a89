//! The bench binary runs end to end on small configurations and writes
//! what it says: the billiards scene in every mode and precision over two
//! rounds, the small scenes in timed blocks over episodes, the rigid-body
//! scenes (dice, dominoes) with law impacts in every law mode, and a scene
//! at two sizes (its scaling plot), whose outputs `--rerender` rebuilds
//! from `raw.json`. The CSV is read back with the type that wrote it. Nothing
//! here looks at a timing.

mod common;

use std::path::{Path, PathBuf};

use kimpact::Mode;
use kimpact_harness::BenchRow;

/// A fresh output folder for one test.
fn out_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("bench")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Run the bench with `args` into `out`; its standard output.
fn bench(args: &[&str], out: &Path) -> String {
    let mut all: Vec<std::ffi::OsString> = args.iter().map(Into::into).collect();
    all.extend(["--out".into(), out.as_os_str().to_owned()]);
    common::run_bench(all)
}

/// The rows of `<out>/results.csv`.
fn rows(out: &Path) -> Vec<BenchRow> {
    let mut reader = csv::Reader::from_path(out.join("results.csv")).expect("results.csv");
    reader
        .deserialize()
        .map(|r| r.expect("a BenchRow"))
        .collect()
}

#[test]
fn the_bench_runs_the_billiards_in_every_mode_and_precision() {
    let out = out_dir("billiards");
    let args = [
        "--scene",
        "billiards",
        "--warmup",
        "2",
        "--steps",
        "3",
        "--rounds",
        "2",
    ];
    let stdout = bench(&[&args[..], &["--no-attribute"]].concat(), &out);
    assert!(
        stdout.contains("| billiards | f32 | 16 | exact |"),
        "{stdout}"
    );
    let rows = rows(&out);
    // 2 precisions x 4 modes, none failed.
    assert_eq!(rows.len(), 8, "{rows:?}");
    for r in &rows {
        assert_eq!(r.error, None, "a run failed: {r:?}");
        assert_eq!((r.scene.as_str(), r.balls, r.dim), ("billiards", 16, 2));
        assert!(r.median_us > 0.0 && r.native_median_us > 0.0, "{r:?}");
        assert!(r.kimpact_allocs_per_step.is_nan(), "not attributed: {r:?}");
        if r.mode != Mode::Native {
            // (native's row pools its runs beside every mode: 3 x 2.)
            assert_eq!(r.rounds, 2, "{r:?}");
            assert!((r.ratio - r.median_us / r.native_median_us).abs() < 1e-12);
            let (lo, mid, hi) = (r.ratio_min, r.ratio_median_rounds, r.ratio_max);
            assert!(lo > 0.0 && lo <= mid && mid <= hi, "{r:?}");
        }
    }
    for mode in Mode::ALL {
        assert!(rows.iter().any(|r| r.mode == mode), "no {mode} row");
    }
}

#[test]
fn the_small_scenes_run_in_timed_blocks_over_episodes() {
    let out = out_dir("small");
    let args = [
        "--scene",
        "restitution3,restitution2,pinball",
        "--precision",
        "f32",
        "--warmup",
        "2",
        "--steps",
        "4",
        "--small-block",
        "2",
        "--small-repeats",
        "3",
        "--no-attribute",
    ];
    let stdout = bench(&args, &out);
    assert!(
        stdout.contains("| restitution3 | f32 | 22 | exact |"),
        "{stdout}"
    );
    assert!(stdout.contains("| pinball | f32 | 3 | exact |"), "{stdout}");
    let rows = rows(&out);
    // 3 scenes x 4 modes, none failed.
    assert_eq!(rows.len(), 12, "{rows:?}");
    for r in rows.iter().filter(|r| r.mode != Mode::Native) {
        assert_eq!(r.error, None, "a run failed: {r:?}");
        // One sample per block: 4 steps in blocks of 2, 3 episodes.
        assert_eq!(r.samples, 6, "{r:?}");
        assert!((r.delta_us - (r.median_us - r.native_median_us)).abs() < 1e-9);
    }
}

/// The rigid-body scenes, 1,000 dice (3D) and 1,000 dominoes (2D), run in
/// every mode against native, timed step by step (not small scenes), and
/// every law mode reports law impacts of their boxes while measured (steps
/// 20-29: the dice land on the floor and on each other, the first domino of
/// each row hits the second at step 26).
#[test]
fn the_rigid_scenes_run_in_every_mode_with_law_impacts() {
    let out = out_dir("rigid");
    let args = [
        "--scene",
        "dice,dominoes",
        "--precision",
        "f32",
        "--warmup",
        "20",
        "--steps",
        "10",
        "--memory-warmup",
        "1",
        "--memory-steps",
        "1",
        "--no-attribute",
    ];
    let stdout = bench(&args, &out);
    assert!(stdout.contains("| dice | f32 | 1000 | exact |"), "{stdout}");
    assert!(
        stdout.contains("| dominoes | f32 | 1000 | exact |"),
        "{stdout}"
    );
    let rows = rows(&out);
    // 2 scenes x 4 modes, none failed.
    assert_eq!(rows.len(), 8, "{rows:?}");
    for r in &rows {
        assert_eq!(r.error, None, "a run failed: {r:?}");
        let dim = if r.scene == "dice" { 3 } else { 2 };
        assert_eq!((r.balls, r.dim), (1000, dim), "{r:?}");
        // One sample per step (native's row pools its runs beside every
        // mode: 3 x 10).
        if r.mode == Mode::Native {
            assert_eq!(r.samples, 30, "{r:?}");
            assert_eq!(r.impacts_per_step, 0.0, "{r:?}");
        } else {
            assert_eq!(r.samples, 10, "{r:?}");
            assert!(r.impacts_per_step > 0.0, "no law impact: {r:?}");
        }
    }
}

#[test]
fn two_sizes_give_a_scaling_plot_and_rerender_rebuilds_the_outputs() {
    let out = out_dir("scaling");
    let args = [
        "--scene",
        "gas2d",
        "--balls",
        "50,20",
        "--precision",
        "f32",
        "--mode",
        "exact",
        "--warmup",
        "1",
        "--steps",
        "3",
        "--memory-warmup",
        "2",
        "--memory-steps",
        "2",
        "--hook-native",
    ];
    let stdout = bench(&args, &out);
    let first = rows(&out);
    // 2 sizes x (native, exact), attributed.
    assert_eq!(first.len(), 4, "{first:?}");
    assert_eq!(
        first.iter().map(|r| r.balls).collect::<Vec<_>>(),
        [20, 20, 50, 50]
    );
    for r in &first {
        assert_eq!(r.error, None, "a run failed: {r:?}");
        assert!(r.kimpact_allocs_per_step >= 0.0, "attributed: {r:?}");
        assert!(r.peak_rss_mib > 0.0, "{r:?}");
    }
    let svg = out.join("scaling-gas2d-f32.svg");
    let plot = std::fs::read_to_string(&svg).expect("the scaling plot");
    assert!(plot.starts_with("<svg") && plot.contains("exact"));

    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    for name in ["results.csv", "results.md", "scaling-gas2d-f32.svg"] {
        std::fs::remove_file(out.join(name)).unwrap();
    }
    let again = bench(&["--rerender"], &out);
    assert_eq!(again, stdout, "the table rebuilt from raw.json");
    assert_eq!(
        std::fs::read_to_string(out.join("results.csv")).unwrap(),
        csv
    );
    assert!(svg.exists());
}

/// `--stages` times each measured step's three stages and writes their
/// medians per law mode into `stages.md`, every one a time (no `—`, which
/// would be a run without stages); a run without it writes no such file.
#[test]
fn the_stage_table_has_a_timed_row_per_law_mode() {
    let out = out_dir("stages");
    let args = [
        "--scene",
        "gas2d",
        "--balls",
        "50",
        "--precision",
        "f32",
        "--warmup",
        "2",
        "--steps",
        "4",
        "--no-attribute",
        "--stages",
    ];
    bench(&args, &out);
    let md = std::fs::read_to_string(out.join("stages.md")).expect("stages.md");
    for mode in ["restitution", "impulse", "exact"] {
        let row = md
            .lines()
            .find(|l| l.starts_with(&format!("| gas2d | f32 | 50 | {mode} |")))
            .unwrap_or_else(|| panic!("no {mode} row in\n{md}"));
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        // native's step, before, rapier, after, kimpact's share.
        for cell in &cells[5..10] {
            assert!(!cell.contains('—') && !cell.is_empty(), "{row}");
        }
        let share: f64 = cells[9].parse().expect("a share");
        assert!(share.is_finite() && share >= 0.0, "{row}");
    }
    let plain = out_dir("no-stages");
    bench(&args[..args.len() - 1], &plain);
    assert!(plain.join("results.md").exists());
    assert!(!plain.join("stages.md").exists());
}

/// `--rebound-cutoff` reaches the children's law worlds: the same landing
/// 2D pit resolves fewer law impacts with it (its rebounds within a step
/// wait), and a cut-off that is not a number of rest speeds is refused,
/// naming it.
#[test]
fn the_rebound_cutoff_reaches_the_law_worlds() {
    let args = [
        "--scene",
        "pit2d",
        "--balls",
        "300",
        "--mode",
        "exact",
        "--precision",
        "f32",
        "--warmup",
        "40",
        "--steps",
        "40",
        "--no-attribute",
    ];
    let impacts = |out: &Path| {
        let row = rows(out)
            .into_iter()
            .find(|r| r.mode == Mode::Exact)
            .expect("an exact row");
        row.impacts_per_step
    };
    let plain = out_dir("no-cutoff");
    bench(&args, &plain);
    let cut = out_dir("cutoff");
    bench(&[&args[..], &["--rebound-cutoff", "2"]].concat(), &cut);
    let (without, with) = (impacts(&plain), impacts(&cut));
    assert!(
        without > 0.0 && with < 0.9 * without,
        "impacts per step: {without} without, {with} with the cut-off"
    );
    let refused = std::process::Command::new(env!("CARGO_BIN_EXE_kimpact-bench"))
        .arg("--rebound-cutoff=-1")
        .output()
        .expect("the bench binary starts");
    assert!(!refused.status.success());
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        stderr.contains("rebound-cutoff") && stderr.contains(">= 0"),
        "{stderr}"
    );
}
