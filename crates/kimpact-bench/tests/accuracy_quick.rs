//! `kimpact-accuracy --quick` runs end to end into a temporary folder and
//! writes the four files with their sections and columns; every error of
//! the summary is finite, for every scene, build and mode; the hand-written
//! Findings of an existing `accuracy.md` survive. Nothing here looks at how
//! large an error is (the scenes are too small to mean anything).

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::Command;

const FINDINGS: &str = "\nA finding written by hand, kept across runs.\n\n";

#[test]
fn quick_run_writes_every_file_with_finite_errors_and_keeps_the_findings() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("accuracy-quick");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let old = format!(
        "# old\n\n<!-- findings: hand-written, kept by the generator -->{FINDINGS}<!-- end of findings -->\n"
    );
    std::fs::write(dir.join("accuracy.md"), old).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_kimpact-accuracy"))
        .args(["--quick", "--threads", "2", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "kimpact-accuracy failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );

    let md = std::fs::read_to_string(dir.join("accuracy.md")).unwrap();
    assert!(md.contains(FINDINGS), "the findings were not kept:\n{md}");
    assert!(md.contains("--bin kimpact-accuracy -- --quick"));
    for section in [
        "## One oblique impact",
        "## Newton's cradle",
        "## Elastic gas: statistics over time",
        "## Compressibility factor of hard disks and spheres",
        "## Cooling granular gas",
        "## What accuracy costs",
    ] {
        assert!(md.contains(section), "no section {section:?}");
    }
    // Every table row of the one-impact table: 4 builds × 4 modes × 2 cases.
    let impact_rows = md
        .lines()
        .filter(|l| l.contains("| 1:10, d̃ = 0 |") || l.contains("| 1:1, d̃ = 0.05 |"))
        .count();
    assert_eq!(impact_rows, 32);

    let csv = std::fs::read_to_string(dir.join("accuracy.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("section,engine,method,dt_div,x,quantity,value")
    );
    let sections: BTreeSet<&str> = lines
        .map(|l| {
            assert_eq!(l.split(',').count(), 7, "bad CSV line {l:?}");
            l.split(',').next().unwrap()
        })
        .collect();
    assert_eq!(
        sections,
        BTreeSet::from(["cooling", "cost", "gas"]),
        "CSV sections"
    );

    let svg = std::fs::read_to_string(dir.join("accuracy.svg")).unwrap();
    assert!(svg.starts_with("<svg"));
    for title in [
        "gas energy error 3D f64",
        "one impact 2D f32",
        "cradle 3D f32",
        "cooling 2D f64",
    ] {
        assert!(svg.contains(title), "no panel {title:?} in the plot");
    }

    let json = std::fs::read_to_string(dir.join("accuracy-summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(summary["quick"], true);
    let errors = summary["errors"].as_array().unwrap();
    let mut seen = BTreeSet::new();
    for row in errors {
        let error = row["error"].as_f64();
        assert!(
            error.is_some_and(|e| e.is_finite() && e >= 0.0),
            "not a finite error: {row}"
        );
        seen.insert((
            row["scene"].as_str().unwrap().to_owned(),
            row["dimension"].as_u64().unwrap(),
            row["precision"].as_str().unwrap().to_owned(),
            row["mode"].as_str().unwrap().to_owned(),
        ));
    }
    for scene in [
        "one_impact",
        "one_impact_dissipative",
        "cradle",
        "gas",
        "cooling",
    ] {
        for (d, p) in [(2, "f32"), (2, "f64"), (3, "f32"), (3, "f64")] {
            for mode in ["native", "restitution", "impulse", "exact"] {
                let key = (scene.to_owned(), d, p.to_owned(), mode.to_owned());
                assert!(seen.contains(&key), "no error for {key:?}");
            }
        }
    }
    for scene in [
        "compressibility_2d_eta0.3",
        "compressibility_2d_eta0.5",
        "compressibility_3d_eta0.3",
    ] {
        assert!(
            seen.iter().filter(|k| k.0 == scene).count() == 8,
            "{scene}: not every mode in both precisions"
        );
    }
}
