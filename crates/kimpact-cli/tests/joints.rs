//! Joints end to end: each kind holds its bodies as the closed form of its
//! motion says (pendulum period, momentum shared by a weld, a slider's
//! axis and limit, a rope's length), the jointed Newton's cradle as rapier's
//! newton_cradle3 builds it runs through `run`, `compare` and `check`, and a
//! bad joint exits 2 naming its index and field.

mod common;

use std::f64::consts::PI;

use serde_json::Value;

use common::{MODES, kimpact, report, scene, temp_dir, vecf, write};

/// A ball of radius 0.05 on a massless arm of length L = 1 from a pivot at
/// the origin, released at rest 0.05 rad from the vertical (f64, 600 Hz):
/// half a period later it is on the other side. The ball turns with the
/// arm, so the period is the physical pendulum's,
/// `T = 2π sqrt((L² + 2r²/5) / (g L))`, times `1 + θ₀²/16`.
#[test]
fn a_pendulum_swings_over_in_half_its_period_in_2d_and_3d() {
    let (l, r, g, theta0) = (1.0_f64, 0.05_f64, 9.81_f64, 0.05_f64);
    let period =
        2.0 * PI * ((l * l + 0.4 * r * r) / (g * l)).sqrt() * (1.0 + theta0 * theta0 / 16.0);
    let dt = 1.0 / 600.0;
    let steps = (0.5 * period / dt).round() as u64;
    let (x0, y0) = (l * theta0.sin(), -l * theta0.cos());
    for (dim, joint) in [(2, "revolute"), (3, "spherical"), (3, "revolute")] {
        let v = |x: f64, y: f64| {
            if dim == 2 {
                format!("[{x:?}, {y:?}]")
            } else {
                format!("[{x:?}, {y:?}, 0.0]")
            }
        };
        let axis = if dim == 3 && joint == "revolute" {
            ", axis: [0.0, 0.0, 1.0]"
        } else {
            ""
        };
        let path = write(
            &format!("pendulum-{dim}d-{joint}.ron"),
            format!(
                r#"(dim: {dim}, precision: "f64", dt: {dt:?}, steps: {steps}, gravity: {g},
                    bodies: [(shape: "ball", radius: {r:?}, mass: 1.0, position: {pos})],
                    joints: [(kind: "{joint}", body1: "world", anchor1: {origin}, body2: 0, anchor2: {arm}{axis})])"#,
                g = v(0.0, -g),
                pos = v(x0, y0),
                origin = v(0.0, 0.0),
                arm = v(-x0, -y0),
            ),
        );
        for mode in MODES {
            let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
            let what = format!("{dim}D {joint} {mode}");
            assert_eq!(r["setup"]["joints"], 1, "{what}");
            assert_eq!(
                r["checks"]["momentum_conserved"], false,
                "{what}: held by the world"
            );
            let p = vecf(&r["bodies"][0]["position"]);
            // On the arm's circle, and mirrored.
            let radius = (p[0] * p[0] + p[1] * p[1]).sqrt();
            assert!((radius - l).abs() < 1e-3, "{what}: arm {radius}");
            assert!(
                (p[0] + x0).abs() < 0.02 * x0,
                "{what}: x = {} after half a period, expected {}",
                p[0],
                -x0
            );
        }
    }
}

/// Two equal balls welded by a fixed joint at their touching point, one
/// moving at 1 m/s towards the other's far side along the line of centres:
/// the joint makes them one body moving at the shared momentum's velocity,
/// 0.5 m/s, without turning; nothing outside acts, so momentum is kept.
#[test]
fn a_weld_shares_momentum() {
    let path = write(
        "weld.ron",
        r#"(dim: 2, precision: "f64", steps: 60, bodies: [
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], velocity: [1.0, 0.0]),
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.2, 0.0])],
          joints: [(kind: "fixed", body1: 0, anchor1: [0.1, 0.0], body2: 1, anchor2: [-0.1, 0.0])])"#,
    );
    for mode in MODES {
        let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
        assert_eq!(r["checks"]["momentum_conserved"], true, "{mode}");
        for b in 0..2 {
            let v = vecf(&r["bodies"][b]["velocity"]);
            assert!(
                (v[0] - 0.5).abs() < 1e-6 && v[1].abs() < 1e-9,
                "{mode}: body {b} at {v:?}"
            );
        }
        let a = vecf(&r["bodies"][0]["position"]);
        let b = vecf(&r["bodies"][1]["position"]);
        assert!((b[0] - a[0] - 0.2).abs() < 1e-6, "{mode}: {a:?} {b:?}");
    }
}

/// A ball on a slider along x (a prismatic joint to the world, limits
/// ±0.2), thrown at (1, 1) m/s: the joint takes the y velocity, the ball
/// slides along x and stops at the limit.
#[test]
fn a_slider_keeps_its_axis_and_limits() {
    let path = write(
        "slider.ron",
        r#"(dim: 2, precision: "f64", steps: 60, bodies: [
            (shape: "ball", radius: 0.05, mass: 1.0, position: [0.0, 0.0], velocity: [1.0, 1.0])],
          joints: [(kind: "prismatic", body1: "world", body2: 0, axis: [1.0, 0.0], limits: [-0.2, 0.2])])"#,
    );
    for mode in MODES {
        let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
        let p = vecf(&r["bodies"][0]["position"]);
        let v = vecf(&r["bodies"][0]["velocity"]);
        assert!(p[1].abs() < 1e-3, "{mode}: off the axis at {p:?}");
        assert!(
            p[0] > 0.19 && p[0] < 0.201,
            "{mode}: at {p:?}, the limit is 0.2"
        );
        assert!(
            v[0].abs() < 1e-2 && v[1].abs() < 1e-2,
            "{mode}: still moving {v:?}"
        );
    }
}

/// A ball on a slack rope of length 1 from the origin, 0.5 below it: it
/// falls freely for sqrt(2 · 0.5 / g) = 0.32 s (after 0.25 s it is where
/// rapier's integrator puts a free fall), then hangs 1 below the anchor.
#[test]
fn a_rope_is_slack_then_holds_its_length() {
    let g = 9.81_f64;
    let path = write(
        "rope.ron",
        r#"(dim: 3, precision: "f64", steps: 240, gravity: [0.0, -9.81, 0.0], bodies: [
            (shape: "ball", radius: 0.05, mass: 1.0, position: [0.0, -0.5, 0.0])],
          joints: [(kind: "rope", body1: "world", body2: 0, max_distance: 1.0)])"#,
    );
    for mode in MODES {
        let early = report(&[
            "run",
            path.to_str().unwrap(),
            "--mode",
            mode,
            "--steps",
            "15",
        ]);
        let substeps = early["setup"]["substeps"].as_u64().unwrap() as f64;
        // Symplectic Euler over n substeps of h: y = y0 − g h² n(n+1)/2.
        let h = (1.0 / 60.0) / substeps;
        let n = 15.0 * substeps;
        let y = vecf(&early["bodies"][0]["position"])[1];
        let expected = -0.5 - g * h * h * n * (n + 1.0) / 2.0;
        assert!(
            (y - expected).abs() < 1e-9,
            "{mode}: free fall at {y}, expected {expected}"
        );
        let late = report(&["run", path.to_str().unwrap(), "--mode", mode]);
        let p = vecf(&late["bodies"][0]["position"]);
        assert!(
            (p[1] + 1.0).abs() < 5e-3 && p[0].abs() < 1e-9 && p[2].abs() < 1e-9,
            "{mode}: hangs at {p:?}"
        );
    }
}

/// Two overlapping balls welded with contacts disabled stay put (rapier
/// would push them apart if they collided).
#[test]
fn welded_bodies_with_contacts_disabled_do_not_push_each_other() {
    let path = write(
        "overlap.json",
        r#"{"dim": 2, "precision": "f64", "steps": 30, "bodies": [
            {"shape": "ball", "radius": 0.1, "mass": 1, "position": [0, 0]},
            {"shape": "ball", "radius": 0.1, "mass": 1, "position": [0.05, 0]}],
          "joints": [{"kind": "fixed", "body1": 0, "anchor1": [0.05, 0], "body2": 1, "contacts_enabled": false}]}"#,
    );
    for mode in MODES {
        let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
        assert_eq!(vecf(&r["bodies"][0]["position"]), vec![0.0, 0.0], "{mode}");
        assert_eq!(vecf(&r["bodies"][1]["position"]), vec![0.05, 0.0], "{mode}");
        assert_eq!(r["energy"]["kinetic_final"], 0.0, "{mode}");
    }
}

/// rapier's newton_cradle3, bundled: `check` names its joints, every mode
/// runs it, and `compare` writes its outputs. Before the first impact the
/// swung ball keeps to its 5 m circle and its energy (to the 2% rapier's
/// joint loses in the swing); at the first strike (the impacts at 2.4 s)
/// the law's modes hand the swing to the ball at the other end, as an
/// elastic row of equal balls does: it leaves with the striker's energy
/// `½|v|² + g y` per unit mass (less what rapier's joints take as the row
/// moves: 4-5%), and the three balls between stay.
#[test]
fn the_jointed_cradle_runs_in_run_compare_and_check() {
    let path = scene("newton_cradle3d.ron");
    let p = path.to_str().unwrap();
    let o = kimpact(&["check", p]);
    assert!(o.status.success());
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(line.contains("5 joints"), "{line}");
    assert!(line.contains("effects [gravity, friction, spin]"), "{line}");

    let g = 9.81;
    let energy = |b: &Value| {
        let v = vecf(&b["velocity"]);
        let y = vecf(&b["position"])[1];
        0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + g * y
    };
    let start = 0.5 * 49.0;
    for mode in MODES {
        let r = report(&["run", p, "--mode", mode, "--steps", "120"]);
        assert_eq!(r["setup"]["joints"], 5);
        assert_eq!(
            r["impacts"]["count"], 0,
            "{mode}: no impact in the first swing"
        );
        let ball = &r["bodies"][4];
        let x = vecf(&ball["position"]);
        let arm = ((x[0] - 4.4).powi(2) + (x[1] - 5.0).powi(2) + x[2].powi(2)).sqrt();
        assert!((arm - 5.0).abs() < 1e-3, "{mode}: arm {arm}");
        let e = energy(ball);
        assert!(e <= start && e > 0.98 * start, "{mode}: swing energy {e}");
        for b in 0..4 {
            assert_eq!(
                vecf(&r["bodies"][b]["velocity"]),
                vec![0.0; 3],
                "{mode}: {b}"
            );
        }
    }
    for mode in ["impulse", "exact"] {
        let before = report(&["run", p, "--mode", mode, "--steps", "140"]);
        assert_eq!(before["impacts"]["count"], 0, "{mode}");
        let striker = energy(&before["bodies"][4]);
        let r = report(&["run", p, "--mode", mode, "--steps", "150"]);
        assert_eq!(
            r["impacts"]["count"], 4,
            "{mode}: one strike through the row"
        );
        let e = energy(&r["bodies"][0]);
        assert!(
            e > 0.9 * striker && e < striker,
            "{mode}: the far ball leaves with {e} of the striker's {striker}"
        );
        for b in 1..5 {
            let v = vecf(&r["bodies"][b]["velocity"]);
            let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            assert!(speed < 0.5, "{mode}: ball {b} moves at {speed}");
        }
    }

    let out = temp_dir("compare");
    let o = kimpact(&[
        "compare",
        p,
        "--out",
        out.to_str().unwrap(),
        "--steps",
        "200",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "summary.md",
        "strip.png",
        "compare.html",
        "report-exact.json",
        "report-native.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
}

#[test]
fn a_bad_joint_exits_2_naming_its_index_and_field() {
    let path = write(
        "bad-joint.ron",
        r#"(dim: 3, steps: 10, bodies: [(shape: "ball", radius: 0.5, mass: 1.0, position: [0.0, 0.0, 0.0])],
           joints: [(kind: "spherical", body1: "world", body2: 0, anchor1: [0.0, 5.0, 0.0], anchor2: [0.0, 5.0, 0.0]),
                    (kind: "spherical", body1: "world", body2: "ball")])"#,
    );
    for cmd in ["run", "check", "compare"] {
        let out = temp_dir("bad").join("out");
        let mut args = vec![cmd, path.to_str().unwrap()];
        if cmd != "check" {
            args.extend(["--out", out.to_str().unwrap()]);
        }
        let o = kimpact(&args);
        assert_eq!(o.status.code(), Some(2), "{cmd}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("bad-joint.ron: joints[1].body2: unknown body \"ball\""),
            "{cmd}: {err}"
        );
        assert!(!out.exists(), "{cmd} wrote {}", out.display());
    }
}
