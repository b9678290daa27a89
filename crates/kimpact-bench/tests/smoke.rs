//! The bench binary runs end to end on the smallest scene (2 warm-up and 3
//! measured steps, every mode and precision, two rounds) and writes the CSV
//! with its columns. Nothing here looks at a timing.

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
