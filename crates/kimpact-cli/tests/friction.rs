//! Impact friction through scene files, end to end: the cut shot of
//! Alciatore's Technical Proof A-14 (stun, equal balls, elastic normal
//! law, β = 0) run by the command in exact and impulse mode, the object
//! ball's throw against the closed form `tan θ = min(μ, tan φ / 7)` for
//! solid spheres (3D) and `min(μ, tan φ / 6)` for rapier's 2D balls
//! (disks), with momentum, angular momentum and energy per pair; impact
//! friction ignored without the `friction` effect; and a scene with impact
//! friction but no `spin` refused.

mod common;

use serde_json::Value;

use common::{kimpact, report, vecf, write};

/// Billiard ball radius and mass (TP A-14's balls; the law scales out).
const R: f64 = 0.028575;
const M: f64 = 0.17;
/// The cue ball's speed.
const V: f64 = 1.0;
/// Alciatore's ball–ball friction coefficient.
const MU: f64 = 0.06;

/// A body's angular velocity about z (2D: the number; 3D: the vector's z,
/// its x and y checked zero: the cut is in the xy plane).
fn spin_z(body: &Value) -> f64 {
    match &body["angular_velocity"] {
        Value::Array(_) => {
            let w = vecf(&body["angular_velocity"]);
            assert_eq!((w[0], w[1]), (0.0, 0.0), "spin out of the table's plane");
            w[2]
        }
        w => w.as_f64().expect("a number"),
    }
}

/// The cut angles: 0° to 60° in steps of 1°.
fn cut_angles() -> Vec<f64> {
    (0..=60).map(|d| f64::from(d).to_radians()).collect()
}

/// Row `k` of the scene: a cue ball at `V` along x from `(0, y)` onto an
/// object ball at rest at `(0.1, y + b)`, `b = 2R sin φ`, rows 0.5 m apart
/// (no row reaches another in the run). The impact normal from cue to
/// object is `(√(4R² − b²), b) / 2R`: the cut angle is `φ`. Materials
/// `material` on every ball; `effects` as given.
fn cut_shots(dim: usize, effects: &str, material: &str) -> (String, Vec<f64>) {
    let z = if dim == 3 { ", 0.0" } else { "" };
    let mut bodies = Vec::new();
    let mut offsets = Vec::new();
    for (k, phi) in cut_angles().into_iter().enumerate() {
        let y = 0.5 * k as f64;
        let b = 2.0 * R * phi.sin();
        offsets.push(b);
        bodies.push(format!(
            r#"(shape: "ball", radius: {R:?}, mass: {M:?}, position: [0.0, {y:?}{z}], velocity: [{V:?}, 0.0{z}], material: "ball")"#
        ));
        bodies.push(format!(
            r#"(shape: "ball", radius: {R:?}, mass: {M:?}, position: [0.1, {:?}{z}], material: "ball")"#,
            y + b
        ));
    }
    let scene = format!(
        r#"(dim: {dim}, precision: "f64", steps: 6, effects: [{effects}],
            materials: {{"ball": ({material})}},
            bodies: [{}])"#,
        bodies.join(",\n")
    );
    (scene, offsets)
}

/// TP A-14 for equal balls of inverse tangential mass `k_tt` (times `m`):
/// a stun cue ball at `V` meets the object ball at cut angle `φ`; the
/// normal impulse is `m V cos φ` (elastic), stopping the contact points'
/// slip `V sin φ` takes `m V sin φ / k_tt`, Coulomb allows `μ` times the
/// normal impulse. Returns the tangential impulse over `m V` and whether
/// the impact sticks.
fn closed_form(phi: f64, k_tt: f64) -> (f64, bool) {
    let (stick, limit) = (phi.sin() / k_tt, MU * phi.cos());
    if stick <= limit {
        (stick, true)
    } else {
        (limit, false)
    }
}

/// Runs the cut shots in `dim` (3D: solid spheres, `K_tt = 7/m`; 2D:
/// rapier's balls are disks, inertia `m R²/2`, `K_tt = 2/m + 2R²/(m R²/2)
/// = 6/m`) in `mode` and checks every row against the closed form: the
/// throw (the angle between the object ball's velocity and the line of
/// centres) to 1e-9 rad, both balls' spin, the energy the friction takes,
/// momentum and angular momentum per row. Returns the rows that stuck and
/// slid.
fn check_cut_shots(dim: usize, mode: &str) -> (usize, usize) {
    let k_tt = if dim == 3 { 7.0 } else { 6.0 };
    // The ball's moment of inertia.
    let inertia = if dim == 3 { 0.4 } else { 0.5 } * M * R * R;
    let (scene, offsets) = cut_shots(
        dim,
        r#""friction", "spin""#,
        &format!("impact_friction: {MU:?}, tangential_restitution: 0.0"),
    );
    let path = write(&format!("cut{dim}d.ron"), &scene);
    let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
    assert_eq!(r["effects"], serde_json::json!(["friction", "spin"]));
    let bodies = r["bodies"].as_array().unwrap();
    let (mut stuck, mut slid) = (0, 0);
    for (k, (phi, b)) in cut_angles().into_iter().zip(offsets).enumerate() {
        let (cue, object) = (&bodies[2 * k], &bodies[2 * k + 1]);
        let n = [(4.0 * R * R - b * b).sqrt() / (2.0 * R), b / (2.0 * R)];
        let (vc, vo) = (vecf(&cue["velocity"]), vecf(&object["velocity"]));
        let (xc, xo) = (vecf(&cue["position"]), vecf(&object["position"]));
        let (wc, wo) = (spin_z(cue), spin_z(object));
        let (tangential, sticks) = closed_form(phi, k_tt);
        if phi > 0.0 {
            if sticks {
                stuck += 1;
            } else {
                slid += 1;
            }
        }
        let deg = phi.to_degrees();
        // The throw.
        let cross = vo[0] * n[1] - vo[1] * n[0];
        let throw = cross.abs().atan2(vo[0] * n[0] + vo[1] * n[1]);
        let want = (phi.tan() / k_tt).min(MU).atan();
        assert!(
            (throw - want).abs() < 1e-9,
            "{dim}D {mode} φ = {deg}°: throw {throw} rad, TP A-14 {want} rad"
        );
        // Thrown towards the cue ball's direction of motion (the friction
        // drags the object ball along the cue ball's slip).
        if phi > 0.0 {
            assert!(
                cross > 0.0,
                "{dim}D {mode} φ = {deg}°: thrown the wrong way"
            );
        }
        // Spin: both balls turn alike, |ω| = R |P_t| / I.
        let spin = R * tangential * M * V / inertia;
        for (w, which) in [(wc, "cue"), (wo, "object")] {
            assert!(
                (w.abs() - spin).abs() <= 1e-9 * spin.max(1.0),
                "{dim}D {mode} φ = {deg}°: {which} ball spins {w}, closed form {spin}"
            );
        }
        // Energy: what the normal impulse leaves minus the friction's
        // part, ½ P_t²/(m/k_tt) below what stopping the slip would free
        // when sticking (β = 0), and μ J_n (|g| − ½ μ J_n k_tt/m) when
        // sliding; never more than at the start.
        let before = 0.5 * M * V * V;
        let after: f64 = 0.5 * M * (vc.iter().chain(&vo).map(|v| v * v).sum::<f64>())
            + 0.5 * inertia * (wc * wc + wo * wo);
        let p = tangential * M * V;
        let lost = p * V * phi.sin() - 0.5 * p * p * k_tt / M;
        assert!(
            after <= before,
            "{dim}D {mode} φ = {deg}°: energy rose from {before} to {after}"
        );
        assert!(
            (before - after - lost).abs() <= 1e-12 * before,
            "{dim}D {mode} φ = {deg}°: lost {}, closed form {lost}",
            before - after
        );
        // Momentum, and angular momentum about the origin (about z: the
        // motion is in the xy plane), kept to 1e-12 of their scales.
        for axis in 0..dim {
            let p = M * (vc[axis] + vo[axis]);
            let p0 = if axis == 0 { M * V } else { 0.0 };
            assert!(
                (p - p0).abs() <= 1e-12 * M * V,
                "{dim}D {mode} φ = {deg}°: momentum[{axis}] {p}, was {p0}"
            );
        }
        let moment = |x: &[f64], v: &[f64]| M * (x[0] * v[1] - x[1] * v[0]);
        let l = moment(&xc, &vc) + moment(&xo, &vo) + inertia * (wc + wo);
        let y = 0.5 * k as f64;
        let l0 = moment(&[0.0, y], &[V, 0.0]);
        let scale = M * V * (xc[1].abs() + xo[1].abs() + xc[0].abs() + xo[0].abs());
        assert!(
            (l - l0).abs() <= 1e-12 * scale,
            "{dim}D {mode} φ = {deg}°: angular momentum {l}, was {l0}"
        );
    }
    assert!(
        r["energy"]["kinetic_final"].as_f64().unwrap()
            <= r["energy"]["kinetic_initial"].as_f64().unwrap()
    );
    (stuck, slid)
}

#[test]
fn the_cut_shot_throws_the_object_ball_as_tp_a14_says_in_3d() {
    for mode in ["exact", "impulse"] {
        // tan φ / 7 = μ at φ = atan(0.42) = 22.8°.
        assert_eq!(check_cut_shots(3, mode), (22, 38), "{mode}");
    }
}

#[test]
fn the_cut_shot_throws_the_object_ball_as_tp_a14_says_in_2d() {
    for mode in ["exact", "impulse"] {
        // tan φ / 6 = μ at φ = atan(0.36) = 19.8°.
        assert_eq!(check_cut_shots(2, mode), (19, 41), "{mode}");
    }
}

/// The materials' impact friction without the `friction` effect: a
/// warning, a line in the report's `setup.added`, and the frictionless
/// law: the object ball leaves along the line of centres, nothing spins.
#[test]
fn impact_friction_without_the_friction_effect_is_ignored() {
    let (scene, offsets) = cut_shots(
        3,
        r#""spin""#,
        &format!("impact_friction: {MU:?}, tangential_restitution: 0.0"),
    );
    let path = write("unlisted.ron", &scene);
    let o = kimpact(&["run", path.to_str().unwrap(), "--mode", "exact"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains(
            "materials.ball.impact_friction: ignored (frictionless impacts), \"friction\" is not in `effects`"
        ),
        "{stderr}"
    );
    let r: Value = serde_json::from_slice(&o.stdout).unwrap();
    let added = r["setup"]["added"].to_string();
    assert!(added.contains("frictionless impacts"), "{added}");
    let bodies = r["bodies"].as_array().unwrap();
    for (k, b) in offsets.into_iter().enumerate() {
        let object = &bodies[2 * k + 1];
        let vo = vecf(&object["velocity"]);
        let n = [(4.0 * R * R - b * b).sqrt() / (2.0 * R), b / (2.0 * R)];
        let throw = (vo[0] * n[1] - vo[1] * n[0]).atan2(vo[0] * n[0] + vo[1] * n[1]);
        assert!(throw.abs() < 1e-12, "row {k}: thrown {throw} rad");
        assert_eq!(spin_z(object), 0.0, "row {k}");
        assert_eq!(spin_z(&bodies[2 * k]), 0.0, "row {k}");
    }
}

/// `friction` listed with a material's impact friction but `spin` not:
/// refused (exit code 2), the message naming `effects` and saying `spin`
/// must be on too.
#[test]
fn a_scene_with_impact_friction_but_no_spin_is_refused() {
    let (scene, _) = cut_shots(3, r#""friction""#, &format!("impact_friction: {MU:?}"));
    let path = write("nospin.ron", &scene);
    let o = kimpact(&["run", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stdout.is_empty());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("nospin.ron: effects: materials.ball gives impact friction"),
        "{stderr}"
    );
    assert!(stderr.contains("\"spin\" must be on too"), "{stderr}");
}

/// Bad impact-friction keys: exit code 2, the message naming the key.
#[test]
fn bad_impact_friction_is_refused_by_key() {
    for (material, key, message) in [
        (
            "impact_friction: -0.1",
            "impact_friction",
            "must be finite and >= 0, got -0.1",
        ),
        (
            "impact_friction: 0.1, tangential_restitution: 1.5",
            "tangential_restitution",
            "must be in [-1, 1], got 1.5",
        ),
        (
            "tangential_restitution: -2.0",
            "tangential_restitution",
            "must be in [-1, 1], got -2",
        ),
    ] {
        let (scene, _) = cut_shots(3, r#""friction", "spin""#, material);
        let path = write("bad.ron", &scene);
        let o = kimpact(&["run", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{material}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            stderr.contains(&format!("materials.ball.{key}: {message}")),
            "{material}: {stderr}"
        );
    }
}

/// rapier caps a body's angular speed at a quarter turn per step (π/4 per
/// `dt`, 15π rad/s at 60 Hz) unless the body allows fast rotation: a ball
/// spun at 100 rad/s keeps it with `allow_fast_rotation: true` and is
/// capped to 15π rad/s without (what took the break's spin energy).
#[test]
fn allow_fast_rotation_lifts_rapier_s_angular_speed_cap() {
    for (allow, want) in [(true, 100.0), (false, 15.0 * std::f64::consts::PI)] {
        let path = write(
            &format!("fast-{allow}.ron"),
            format!(
                r#"(dim: 3, precision: "f64", steps: 3, effects: ["spin"], bodies: [
                    (shape: "ball", radius: {R:?}, mass: {M:?}, position: [0.0, 0.0, 0.0], angular_velocity: [0.0, 0.0, 100.0], allow_fast_rotation: {allow}),
                ])"#
            ),
        );
        for mode in ["native", "exact"] {
            let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
            let w = spin_z(&r["bodies"][0]);
            assert!(
                (w - want).abs() < 1e-9 * want,
                "allow_fast_rotation {allow}, {mode}: {w} rad/s, want {want}"
            );
        }
    }
}
