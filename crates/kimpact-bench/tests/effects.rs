//! `--effects` runs end to end on a tiny configuration: one row per effect
//! and law mode, each timed against native, in the scene's folder, rebuilt
//! by `--rerender`. Nothing
//! here looks at a timing beyond its being one.

mod common;

use kimpact::Mode;
use kimpact_harness::EffectRow;

#[test]
fn the_effects_table_has_a_timed_row_per_effect_and_law_mode() {
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench-effects");
    let _ = std::fs::remove_dir_all(&out);
    let args = "--effects --scene gas2d,pit3d --balls 12 --precision f32 --warmup 2 --steps 4 \
        --memory-warmup 1 --memory-steps 2 --no-attribute --out";
    let stdout = common::run_bench(args.split_whitespace().chain([out.to_str().unwrap()]));
    assert!(stdout.contains("| f32 | 12 | spin | exact |"), "{stdout}");
    let folder = out.join("effects-gas2d");
    assert!(!out.join("effects-pit3d").exists(), "pit3d is no gas");
    let md = std::fs::read_to_string(folder.join("effects.md")).expect("effects.md");
    assert!(md.contains("| f32 | 12 | materials | impulse |"), "{md}");
    assert!(
        md.contains("| f32 | 12 | impact_friction | exact |"),
        "{md}"
    );
    let mut reader = csv::Reader::from_path(folder.join("effects.csv")).expect("effects.csv");
    let rows: Vec<EffectRow> = reader
        .deserialize()
        .map(|r| r.expect("an EffectRow"))
        .collect();
    let effects = [
        "base",
        "gravity",
        "dissipation",
        "friction",
        "spin",
        "walls",
        "events",
        "materials",
        "impact_friction",
    ];
    assert_eq!(rows.len(), effects.len() * 3, "{rows:?}");
    for effect in effects {
        for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
            let mine: Vec<_> = rows
                .iter()
                .filter(|r| r.effect == effect && r.mode == mode)
                .collect();
            assert_eq!(mine.len(), 1, "{effect} {mode}: {rows:?}");
            let r = mine[0];
            assert_eq!(r.error, None, "a run failed: {r:?}");
            assert_eq!((r.scene.as_str(), r.balls), ("gas2d", 12));
            for t in [r.median_us, r.native_median_us, r.ratio] {
                assert!(t.is_finite() && t > 0.0, "{r:?}");
            }
            assert!(
                (r.effect_us - (r.delta_us - r.base_delta_us)).abs() < 1e-9,
                "{r:?}"
            );
            assert!(r.kimpact_allocs_per_step.is_nan(), "not attributed: {r:?}");
            if effect == "base" {
                assert_eq!(r.effect_us, 0.0, "{r:?}");
            }
        }
    }
    let csv = std::fs::read(folder.join("effects.csv")).unwrap();
    std::fs::remove_dir_all(&folder).unwrap();
    common::run_bench(["--rerender", "--out", out.to_str().unwrap()]);
    let again = std::fs::read(folder.join("effects.csv")).expect("rebuilt from raw.json");
    assert_eq!(again, csv);
}
