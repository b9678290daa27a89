//! The report's energy and momentum bookkeeping: rapier's integrator's share
//! (`checks.energy_integrator`) explains a free fall exactly in every mode,
//! dimension and precision, and `run` and `compare` warn (the report's
//! `warnings`, standard error, `summary.md`) when energy is unexplained or
//! momentum changes in a scene that conserves it, beyond the tolerance the
//! report states; never for a clean scene.

mod common;

use std::path::{Path, PathBuf};

use serde_json::Value;

use common::{MODES, f, kimpact, run_scene, scene, temp_dir};

fn warnings(r: &Value) -> Vec<String> {
    r["warnings"]
        .as_array()
        .expect("warnings")
        .iter()
        .map(|w| w.as_str().unwrap().to_owned())
        .collect()
}

/// Two balls falling freely (one from rest, one thrown sideways and up),
/// far apart, no fixed body: no contact ever.
fn free_fall(dir: &Path, dim: usize, precision: &str) -> PathBuf {
    let path = dir.join(format!("fall{dim}d-{precision}.ron"));
    let (g, x0, x1, v1) = if dim == 2 {
        ("[0.0, -9.81]", "[0.0, 10.0]", "[5.0, 3.0]", "[1.5, 4.0]")
    } else {
        (
            "[0.0, 0.0, -9.81]",
            "[0.0, 0.0, 10.0]",
            "[5.0, 1.0, 3.0]",
            "[1.5, -0.5, 4.0]",
        )
    };
    std::fs::write(
        &path,
        format!(
            r#"(dim: {dim}, precision: "{precision}", steps: 120, gravity: {g}, bodies: [
                (shape: "ball", radius: 0.1, mass: 2.0, position: {x0}),
                (shape: "ball", radius: 0.05, mass: 0.3, position: {x1}, velocity: {v1}),
            ])"#
        ),
    )
    .unwrap();
    path
}

/// The tiny tolerance of a free fall's unexplained energy, relative to the
/// energy scale: rounding of the step-end states (f64), and of rapier's f32
/// integration over 480 substeps (f32). Far below the report's own
/// tolerance, which must not warn either.
fn tiny(precision: &str) -> f64 {
    if precision == "f64" { 1e-13 } else { 2e-6 }
}

#[test]
fn a_free_fall_is_explained_by_the_integrator_in_every_mode() {
    let dir = temp_dir("fall");
    for dim in [2, 3] {
        for precision in ["f32", "f64"] {
            let path = free_fall(&dir, dim, precision);
            for mode in MODES {
                let (r, err) = run_scene(&path, mode);
                let what = format!("{dim}D {precision} {mode}");
                let c = &r["checks"];
                let scale = f(&c["energy_scale"]);
                let unexplained = f(&c["energy_unexplained"]);
                let integrator = f(&c["energy_integrator"]);
                assert!(
                    unexplained.abs() <= tiny(precision) * scale,
                    "{what}: unexplained {unexplained:e} of scale {scale}"
                );
                // The integrator's share is the whole total change, and
                // without it the report would warn.
                let total = f(&r["energy"]["total_change"]);
                assert!(
                    integrator.abs() > 10.0 * f(&c["tolerance"]) * scale,
                    "{what}: integrator {integrator:e}"
                );
                assert!(total < 0.0 && (total - integrator).abs() <= tiny(precision) * scale);
                // The closed form: each ball falls for τ = 2 s with the same
                // gravity, so −(h/2) Σ m |g|² τ, h = dt / substeps.
                let substeps = r["setup"]["substeps"].as_u64().unwrap() as f64;
                let h = f(&r["dt"]) / substeps;
                let expected = -0.5 * h * (2.0 + 0.3) * 9.81 * 9.81 * 2.0;
                let rel = if precision == "f64" { 1e-12 } else { 1e-5 };
                assert!(
                    (integrator - expected).abs() <= rel * expected.abs(),
                    "{what}: integrator {integrator} vs {expected}"
                );
                assert_eq!(r["impacts"]["count"], 0, "{what}: no contact");
                assert!(warnings(&r).is_empty(), "{what}: {:?}", r["warnings"]);
                assert!(!err.contains("warning"), "{what}: {err}");
                assert_eq!(c["momentum_conserved"], false, "{what}: gravity");
            }
        }
    }
}

/// docs/report.md's tolerance: `max(base, u · steps · substeps)`, base 1e-9
/// (f64) or 1e-5 (f32), `u` the unit roundoff 2⁻⁵³ or 2⁻²⁴.
fn documented_tolerance(precision: &str, r: &Value) -> f64 {
    let n = r["steps"].as_u64().unwrap() as f64 * r["setup"]["substeps"].as_u64().unwrap() as f64;
    if precision == "f64" {
        1e-9_f64.max(n * 2f64.powi(-53))
    } else {
        1e-5_f64.max(n * 2f64.powi(-24))
    }
}

/// Five balls (masses 1 to 5) falling from rest for 10 s, 490 m, no
/// contact: in f32 rapier's integrator rounds the energy by 2.1e-5 of its
/// scale (each of the 2,400 substeps rounds positions near 490 m), beyond
/// a fixed 1e-5, within the tolerance that follows the substeps
/// (1.4e-4): no warning in any mode, dimension or precision.
#[test]
fn five_balls_falling_490_m_warn_in_no_mode() {
    let dir = temp_dir("long-fall");
    for dim in [2, 3] {
        for precision in ["f32", "f64"] {
            let v = |x: f64, y: f64| {
                if dim == 2 {
                    format!("[{x:?}, {y:?}]")
                } else {
                    format!("[{x:?}, {y:?}, 0.0]")
                }
            };
            let bodies: Vec<String> = (0..5)
                .map(|i| {
                    format!(
                        r#"(shape: "ball", radius: 0.1, mass: {:?}, position: {})"#,
                        1.0 + i as f64,
                        v(i as f64, 0.0)
                    )
                })
                .collect();
            let path = dir.join(format!("fall-{dim}d-{precision}.ron"));
            std::fs::write(
                &path,
                format!(
                    r#"(dim: {dim}, precision: "{precision}", steps: 600, gravity: {}, bodies: [{}])"#,
                    v(0.0, -9.81),
                    bodies.join(", ")
                ),
            )
            .unwrap();
            for mode in MODES {
                let (r, err) = run_scene(&path, mode);
                let what = format!("{dim}D {precision} {mode}");
                let y = r["bodies"][0]["position"][1].as_f64().unwrap();
                assert!((y + 490.5).abs() < 1.0, "{what}: fell to {y}");
                let c = &r["checks"];
                let tol = f(&c["tolerance"]);
                assert_eq!(tol, documented_tolerance(precision, &r), "{what}");
                let share = f(&c["energy_unexplained"]).abs() / f(&c["energy_scale"]);
                assert!(
                    share <= tol,
                    "{what}: {share:e} of the scale, tolerance {tol:e}"
                );
                if precision == "f32" {
                    // What a tolerance blind to the steps would warn about.
                    assert!(share > 1e-5, "{what}: {share:e}");
                }
                assert!(warnings(&r).is_empty(), "{what}: {:?}", r["warnings"]);
                assert!(!err.contains("warning"), "{what}: {err}");
            }
        }
    }
}

/// Each warning says what the user can do. Energy lost (rapier's
/// restitution 0.5 on a ball bouncing under gravity, native mode): the
/// causes are examples, gravity's share at an impact among them, and the
/// warning points to `compare` and `effects`. Energy created (rapier's
/// restitution 1.5, native mode): in f32 the remedy is precision "f64", in
/// f64 a report; a restitution above 1 is named as a cause.
#[test]
fn warnings_say_what_to_do() {
    let dir = temp_dir("advice");
    for (precision, restitution) in [("f64", 0.5), ("f32", 1.5), ("f64", 1.5)] {
        let path = dir.join(format!("bounce-{precision}-{restitution}.ron"));
        std::fs::write(
            &path,
            format!(
                r#"(dim: 2, precision: "{precision}", steps: 120, gravity: [0.0, -9.81], law: (dissipation: 0.0), bodies: [
                    (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 1.0], restitution: {restitution:?}),
                    (shape: "box", half_extents: [1.0, 0.1], position: [0.0, -0.1], fixed: true, restitution: {restitution:?}),
                ])"#
            ),
        )
        .unwrap();
        let (r, err) = run_scene(&path, "native");
        let w = warnings(&r);
        assert_eq!(w.len(), 1, "{w:?}");
        let w = &w[0];
        assert!(err.contains(w.as_str()), "{err}");
        if restitution < 1.0 {
            for words in [
                "energy lost, for example in rapier's contacts",
                "in rapier's joints",
                "at impacts under gravity",
                "(h/2) m g·Δv",
                "`kimpact compare`",
                "`effects`",
            ] {
                assert!(w.contains(words), "{w} lacks {words:?}");
            }
        } else {
            assert!(w.contains("energy created"), "{w}");
            assert!(w.contains("restitution above 1"), "{w}");
            if precision == "f32" {
                assert!(w.contains("precision \"f64\""), "{w}");
            } else {
                assert!(w.contains("report the scene"), "{w}");
            }
        }
    }
}

/// Five balls of two masses meeting in open space: no fixed body, no
/// gravity, several impacts (the first ones at once), all apart again at
/// the end.
fn cluster(dir: &Path, precision: &str, restitution: f64) -> PathBuf {
    let path = dir.join(format!("cluster-{precision}-{restitution}.ron"));
    std::fs::write(
        &path,
        format!(
            r#"(dim: 2, precision: "{precision}", steps: 120, bodies: [
                (shape: "ball", radius: 0.1, mass: 1.0, position: [-1.0, 0.02], velocity: [2.0, 0.0], restitution: {restitution}),
                (shape: "ball", radius: 0.1, mass: 2.0, position: [0.0, 0.0], restitution: {restitution}),
                (shape: "ball", radius: 0.1, mass: 1.0, position: [0.3, 0.13], restitution: {restitution}),
                (shape: "ball", radius: 0.1, mass: 2.0, position: [1.0, -0.05], velocity: [-1.5, 0.3], restitution: {restitution}),
                (shape: "ball", radius: 0.1, mass: 1.0, position: [0.2, -1.0], velocity: [0.1, 1.8], restitution: {restitution}),
            ])"#
        ),
    )
    .unwrap();
    path
}

/// The elastic law in exact mode conserves the energy and momentum of a
/// free cluster (f64 and f32) and of Newton's cradle (`scenes/cradle2d.ron`,
/// f32, no fixed body, no gravity) to rounding: no warning. rapier's own
/// restitution 1 keeps the cluster's pairwise impacts too (no warning in
/// native mode), not the cradle's simultaneous contacts, where it loses
/// about 30% of the energy: the warning names the mode and the energy, in
/// the report and on standard error.
#[test]
fn the_cradle_warns_in_native_mode_and_clean_scenes_do_not() {
    let dir = temp_dir("cluster");
    for precision in ["f64", "f32"] {
        let path = cluster(&dir, precision, 1.0);
        for mode in ["exact", "native"] {
            let (r, err) = run_scene(&path, mode);
            let c = &r["checks"];
            if mode == "exact" {
                assert!(
                    r["impacts"]["count"].as_u64().unwrap() >= 3,
                    "the cluster has impacts: {}",
                    r["impacts"]
                );
            }
            assert_eq!(c["momentum_conserved"], true);
            let tol = f(&c["tolerance"]);
            assert_eq!(tol, documented_tolerance(precision, &r));
            let what = format!("cluster {precision} {mode}");
            assert!(
                f(&c["energy_unexplained"]).abs() <= tol * f(&c["energy_scale"]),
                "{what}: {c}"
            );
            assert!(
                f(&c["momentum_change"]) <= tol * f(&c["momentum_scale"]),
                "{what}: {c}"
            );
            assert_eq!(f(&c["energy_integrator"]), 0.0, "no gravity");
            assert!(warnings(&r).is_empty(), "{what}: {:?}", r["warnings"]);
            assert!(!err.contains("warning"), "{what}: {err}");
        }
    }

    let cradle = scene("cradle2d.ron");
    let (exact, _) = run_scene(&cradle, "exact");
    assert!(warnings(&exact).is_empty(), "{:?}", exact["warnings"]);
    let (native, err) = run_scene(&cradle, "native");
    let c = &native["checks"];
    let ratio = f(&c["energy_unexplained"]).abs() / f(&c["energy_scale"]);
    println!("cradle, native: energy unexplained {ratio:.3e} of the scale");
    assert!(
        ratio > f(&c["tolerance"]),
        "rapier kept the energy: {ratio:e}"
    );
    let w = warnings(&native);
    assert!(
        w.iter()
            .any(|w| w.contains("native: energy unexplained") && w.contains("energy lost")),
        "{w:?}"
    );
    assert!(
        err.contains("warning:") && err.contains("energy unexplained"),
        "{err}"
    );
}

/// A slow ball in open space falls asleep under rapier's default
/// activation settings, which zeroes its velocity: momentum and energy
/// vanish with no fixed body and no gravity to take them. Both warnings,
/// in `run` and in `compare`'s summary; a free fall's `compare` has none.
#[test]
fn momentum_lost_to_sleep_is_warned_about_in_run_and_compare() {
    let dir = temp_dir("sleep");
    let path = dir.join("drift.ron");
    std::fs::write(
        &path,
        r#"(dim: 3, precision: "f64", steps: 300, bodies: [
            (shape: "ball", radius: 0.1, mass: 1000.0, position: [0.0, 0.0, 0.0], velocity: [0.001, 0.0, 0.0]),
        ])"#,
    )
    .unwrap();
    let (r, err) = run_scene(&path, "native");
    let c = &r["checks"];
    assert_eq!(c["momentum_conserved"], true);
    assert!(
        f(&c["momentum_change"]) > 0.5,
        "the ball fell asleep: {}",
        r["bodies"][0]["velocity"]
    );
    let w = warnings(&r);
    assert!(w.iter().any(|w| w.contains("momentum changed")), "{w:?}");
    assert!(w.iter().any(|w| w.contains("energy unexplained")), "{w:?}");
    assert!(err.contains("momentum changed"), "{err}");

    let out = dir.join("compare");
    let o = kimpact(&[
        "compare",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(summary.contains("## Warnings"), "{summary}");
    assert!(
        summary
            .lines()
            .any(|l| l.starts_with("- ") && l.contains("native: momentum changed")),
        "{summary}"
    );
    let native: Value =
        serde_json::from_slice(&std::fs::read(out.join("report-native.json")).unwrap()).unwrap();
    assert!(
        warnings(&native)
            .iter()
            .any(|w| w.contains("momentum changed"))
    );

    let fall = free_fall(&dir, 2, "f64");
    let out = dir.join("compare-fall");
    let o = kimpact(&[
        "compare",
        fall.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(!summary.contains("Warnings"), "{summary}");
    assert!(summary.contains("energy integrator"), "{summary}");
}
