//! The bench binary runs end to end on the smallest scene (2 warm-up and 3
//! measured steps, every mode and precision, two rounds) and writes the CSV
//! with its columns; the small scenes run in timed blocks over episodes, and
//! the effects table has every effect in every mode. Nothing here looks at
//! a timing.

mod common;

const COLUMNS: [&str; 13] = [
    "scene",
    "precision",
    "balls",
    "mode",
    "median_us",
    "native_median_us",
    "ratio",
    "ratio_median_rounds",
    "allocs_per_step",
    "kimpact_allocs_per_step",
    "peak_rss_mib",
    "energy_rel_change",
    "error",
];

#[test]
fn the_bench_runs_the_smallest_scene_and_writes_its_csv() {
    let out = std::env::temp_dir().join(format!("kimpact-bench-smoke-{}", std::process::id()));
    let mut args: Vec<std::ffi::OsString> = [
        "--scene",
        "billiards",
        "--warmup",
        "2",
        "--steps",
        "3",
        "--rounds",
        "2",
        "--no-attribute",
        "--out",
    ]
    .map(Into::into)
    .into();
    args.push(out.clone().into());
    let stdout = common::run_bench(args);
    assert!(
        stdout.contains("| billiards | f32 | 16 | exact |"),
        "{stdout}"
    );
    assert!(stdout.contains("### Budgets"), "{stdout}");

    let csv = std::fs::read_to_string(out.join("results.csv")).expect("results.csv written");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    for column in COLUMNS {
        assert!(header.contains(&column), "no column {column} in {header:?}");
    }
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // 2 precisions x 4 modes, each row as wide as the header, none failed.
    assert_eq!(rows.len(), 8, "{csv}");
    let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{row:?}");
        assert_eq!(row[col("error")], "", "a run failed: {row:?}");
        assert_eq!(row[col("scene")], "billiards");
        let median: f64 = row[col("median_us")].parse().expect("a number");
        assert!(median > 0.0, "{row:?}");
        if row[col("mode")] != "native" {
            // (native's row pools its runs beside every mode: 3 x 2.)
            assert_eq!(row[col("rounds")], "2", "{row:?}");
            // The median of the two rounds' ratios lies between them.
            let [lo, mid, hi] = ["ratio_min", "ratio_median_rounds", "ratio_max"]
                .map(|c| row[col(c)].parse::<f64>().expect("a number"));
            assert!(lo > 0.0 && lo <= mid && mid <= hi, "{row:?}");
        }
    }
    for mode in ["native", "restitution", "impulse", "exact"] {
        assert!(rows.iter().any(|r| r[col("mode")] == mode), "no {mode} row");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// The CSV at `path`: its header and rows, each row as wide as the header.
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let csv = std::fs::read_to_string(path).expect("the CSV is written");
    let mut lines = csv.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header")
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{row:?}");
    }
    (header, rows)
}

#[test]
fn the_small_scenes_run_in_timed_blocks_and_are_judged_by_goal_3() {
    let out = std::env::temp_dir().join(format!("kimpact-bench-small-{}", std::process::id()));
    let mut args: Vec<std::ffi::OsString> = [
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
        "--out",
    ]
    .map(Into::into)
    .into();
    args.push(out.clone().into());
    let stdout = common::run_bench(args);
    assert!(
        stdout.contains("| restitution3 | f32 | 22 | exact |"),
        "{stdout}"
    );
    assert!(stdout.contains("| pinball | f32 | 3 | exact |"), "{stdout}");
    assert!(stdout.contains("small scene, exact"), "{stdout}");

    let (header, rows) = read_csv(&out.join("results.csv"));
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    // 3 scenes x 4 modes, none failed.
    assert_eq!(rows.len(), 12, "{rows:?}");
    for row in &rows {
        assert_eq!(row[col("error")], "", "a run failed: {row:?}");
        assert_eq!(row[col("non_finite")], "0", "{row:?}");
        assert_eq!(row[col("escaped")], "0", "{row:?}");
        let num = |c: &str| row[col(c)].parse::<f64>().expect("a number");
        if row[col("mode")] == "native" {
            assert_eq!(row[col("small_goal")], "", "{row:?}");
            continue;
        }
        // One sample per block: 4 steps in blocks of 2, 3 episodes.
        assert_eq!(row[col("samples")], "6", "{row:?}");
        assert!(
            ["pass", "miss"].contains(&row[col("small_goal")].as_str()),
            "{row:?}"
        );
        let goal =
            num("median_us") <= (1.15 * num("native_median_us")).max(num("native_median_us") + 1.0);
        assert_eq!(row[col("small_goal")] == "pass", goal, "{row:?}");
        let delta = num("median_us") - num("native_median_us");
        assert!((num("delta_us") - delta).abs() < 2e-3, "{row:?}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn the_effects_table_has_every_effect_in_every_law_mode() {
    let out = std::env::temp_dir().join(format!("kimpact-bench-effects-{}", std::process::id()));
    let mut args: Vec<std::ffi::OsString> = [
        "--effects",
        "--scene",
        "gas2d",
        "--balls",
        "64",
        "--precision",
        "f32",
        "--warmup",
        "2",
        "--steps",
        "3",
        "--memory-steps",
        "2",
        "--no-attribute",
        "--out",
    ]
    .map(Into::into)
    .into();
    args.push(out.clone().into());
    let stdout = common::run_bench(args);
    assert!(stdout.contains("| materials | exact |"), "{stdout}");
    assert!(out.join("effects.md").exists());

    let (header, rows) = read_csv(&out.join("effects.csv"));
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    let effects = [
        "none",
        "gravity",
        "dissipation",
        "friction",
        "spin",
        "walls",
        "events",
        "materials",
    ];
    assert_eq!(rows.len(), effects.len() * 3, "{rows:?}");
    for effect in effects {
        for mode in ["restitution", "impulse", "exact"] {
            let row = rows
                .iter()
                .find(|r| r[col("effect")] == effect && r[col("mode")] == mode)
                .unwrap_or_else(|| panic!("no row for {effect} in {mode}"));
            assert_eq!(row[col("error")], "", "a run failed: {row:?}");
            assert_eq!(row[col("balls")], "64", "{row:?}");
            let num = |c: &str| row[col(c)].parse::<f64>().expect("a number");
            assert!(num("median_us") > 0.0, "{row:?}");
            if effect == "none" {
                // The base against itself.
                assert_eq!(num("delta_minus_base_us"), 0.0, "{row:?}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}
