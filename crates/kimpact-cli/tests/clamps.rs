//! A large clamped share explained: `compare`'s summary (the file and the
//! terminal) and `run`'s note say whose clamps they are, the law's (a law
//! for a small restitution asks oblique impacts for more than their normal
//! motion holds) or rounding, from the dissipation the clamps left unmet.

mod common;

use std::path::PathBuf;

use common::{kimpact, run_scene, temp_dir, write};

/// Ten pairs of equal balls under the law for e = 0 (f64): a ball at
/// 1 m/s passes a ball at rest `b = 0.05 + 0.01 k` off its line, an
/// oblique impact at `sin θ = b / 0.2`. Returns the scene and the closed
/// form of what the clamps leave unmet: the law asks `d = d̃ M |w|² =
/// 0.25`, the normal motion holds `½ μ u² = 0.25 cos²θ` of which the clamp
/// takes `1 − 10⁻⁶`, so `Σ 0.25 (sin²θ + 10⁻⁶ cos²θ)`.
fn oblique() -> (PathBuf, f64) {
    let mut bodies = Vec::new();
    let mut unmet = 0.0;
    for k in 0..10 {
        let y = 3.0 * k as f64;
        let b = 0.05 + 0.01 * k as f64;
        bodies.push(format!(r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, {y:?}], velocity: [1.0, 0.0])"#));
        bodies.push(format!(
            r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.5, {:?}])"#,
            y + b
        ));
        let sin2 = (b / 0.2) * (b / 0.2);
        unmet += 0.25 * (sin2 + 1e-6 * (1.0 - sin2));
    }
    let path = write(
        "oblique.ron",
        format!(
            r#"(dim: 2, precision: "f64", steps: 60, law: (restitution: 0.0), bodies: [{}])"#,
            bodies.join(", ")
        ),
    );
    (path, unmet)
}

/// Forty pairs meeting head-on along directions off the axes under the
/// law for e = 0, in f32: each impact asks exactly the normal energy
/// (`q = 1`, plastic), and rounding pushes many of them a few ulps over.
/// Returns the scene and each pair's direction.
fn head_on() -> (PathBuf, Vec<(f64, f64)>) {
    let mut bodies = Vec::new();
    let mut dirs = Vec::new();
    for k in 0..40 {
        let y = 3.0 * k as f64;
        let a = 0.05 + 0.037 * k as f64;
        let (s, c) = a.sin_cos();
        bodies.push(format!(r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, {y:?}], velocity: [{c:?}, {s:?}])"#));
        bodies.push(format!(
            r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [{:?}, {:?}])"#,
            0.5 * c,
            y + 0.5 * s
        ));
        dirs.push((c, s));
    }
    let path = write(
        "head-on.ron",
        format!(
            r#"(dim: 2, precision: "f32", steps: 60, law: (restitution: 0.0), bodies: [{}])"#,
            bodies.join(", ")
        ),
    );
    (path, dirs)
}

/// Every oblique impact is clamped: `compare`'s `summary.md` and its
/// terminal summary give a "Clamped impacts" section naming each law mode
/// and the share, `run` prints it as a note and reports it; the same pairs
/// head-on along the x axis (plastic, q = 1 exactly, never clamped) get
/// none.
#[test]
fn a_large_clamped_share_is_explained_in_the_summary_the_terminal_and_the_report() {
    let (path, _) = oblique();
    let out = temp_dir("compare-oblique");
    let o = kimpact(&[
        "compare",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let terminal = String::from_utf8_lossy(&o.stdout);
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    for text in [summary.as_str(), &terminal] {
        assert!(text.contains("## Clamped impacts"), "{text}");
        for mode in ["restitution", "impulse", "exact"] {
            assert!(
                text.contains(&format!("- {mode}: 10 of 10 impacts clamped (100%)")),
                "{mode}: {text}"
            );
        }
        assert!(!text.contains("- native:"), "{text}");
    }
    let (r, err) = run_scene(&path, "exact");
    let note = r["impacts"]["clamps"].as_str().expect("a note");
    assert!(err.contains(&format!("note: {note}")), "{err}");

    let plastic = write(
        "plastic.ron",
        r#"(dim: 2, precision: "f64", steps: 60, law: (restitution: 0.0), bodies: [
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], velocity: [1.0, 0.0]),
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.5, 0.0])])"#,
    );
    for mode in ["restitution", "impulse", "exact"] {
        let (r, err) = run_scene(&plastic, mode);
        assert_eq!(r["impacts"]["count"], 1, "{mode}");
        assert_eq!(r["impacts"]["clamped"], 0, "{mode}");
        assert!(r["impacts"]["clamps"].is_null(), "{mode}");
        assert!(!err.contains("note:"), "{mode}: {err}");
    }
}

/// The law's clamps and rounding told apart by what the clamps left unmet
/// (the adapters' `Stats::unmet_dissipation`): the oblique pairs leave the
/// closed form's `Σ 0.25 (sin²θ + 10⁻⁶ cos²θ)` (to 1e-9 in f64, exact and
/// impulse mode, which meet the pair at contact), a large share of the
/// 2.5 J asked: the law's clamps. The f32 head-on pairs leave about 10⁻⁶
/// of what they ask: rounding, and each pair ends plastic (both balls at
/// half the striker's velocity, to the clamp's e = 10⁻³).
#[test]
fn the_law_s_clamps_are_told_from_rounding() {
    let (path, unmet) = oblique();
    for mode in ["restitution", "impulse", "exact"] {
        let (r, _) = run_scene(&path, mode);
        let i = &r["impacts"];
        let note = i["clamps"].as_str().expect("a note");
        assert!(
            note.contains("the law's own clamps, not a numerical failure"),
            "{mode}: {note}"
        );
        let got = i["unmet_dissipation"].as_f64().unwrap();
        if mode != "restitution" {
            assert!(
                (got - unmet).abs() <= 1e-9 * unmet,
                "{mode}: unmet {got}, closed form {unmet}"
            );
        }
        let asked = got + i["dissipated"].as_f64().unwrap();
        assert!(got > 0.1 * asked, "{mode}: {got} of {asked}");
    }
    let (path, dirs) = head_on();
    for mode in ["restitution", "impulse", "exact"] {
        let (r, _) = run_scene(&path, mode);
        let i = &r["impacts"];
        let (count, clamped) = (i["count"].as_u64().unwrap(), i["clamped"].as_u64().unwrap());
        assert!(
            clamped * 10 >= count,
            "{mode}: {clamped} of {count} clamped"
        );
        let note = i["clamps"].as_str().expect("a note");
        assert!(note.contains("from rounding"), "{mode}: {note}");
        let unmet = i["unmet_dissipation"].as_f64().unwrap();
        assert!(
            unmet > 0.0 && unmet < 1e-5 * clamped as f64,
            "{mode}: {unmet}"
        );
        for (k, (c, s)) in dirs.iter().enumerate() {
            for b in [2 * k, 2 * k + 1] {
                let v = &r["bodies"][b]["velocity"];
                let (vx, vy) = (v[0].as_f64().unwrap(), v[1].as_f64().unwrap());
                assert!(
                    (vx - 0.5 * c).abs() < 1e-3 && (vy - 0.5 * s).abs() < 1e-3,
                    "{mode}: pair {k} body {b} at ({vx}, {vy})"
                );
            }
        }
    }
}
