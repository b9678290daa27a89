//! Restitutions in scene files, end to end: a material's (or `law`'s)
//! `restitution` and `wall_restitution` give those restitutions in the
//! reference impacts (equal masses head-on; head-on on a fixed body), and a
//! body's own `restitution` gives its bounce when the scene sets no law
//! constant, in every law mode.

mod common;

use serde_json::Value;

use common::{report, write};

fn vx(r: &Value, body: usize) -> f64 {
    r["bodies"][body]["velocity"][0].as_f64().expect("a number")
}

/// Row `k` (y = 2k): a ball at 1 m/s onto an equal ball at rest, and a
/// ball at 1 m/s onto a wall, far from the pair. Bodies `3k`, `3k + 1`
/// are the pair, `3k + 2` the wall ball; `{a}`, `{b}`, `{w}` are spliced
/// into them (material or restitution keys).
fn rows(rows: &[[&str; 3]]) -> String {
    let mut bodies = Vec::new();
    for (k, [a, b, w]) in rows.iter().enumerate() {
        let y = 2.0 * k as f64;
        bodies.push(format!(r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, {y:?}], velocity: [1.0, 0.0]{a})"#));
        bodies.push(format!(
            r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.5, {y:?}]{b})"#
        ));
        bodies.push(format!(r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [3.0, {y:?}], velocity: [1.0, 0.0]{w})"#));
    }
    bodies.push(
        r#"(shape: "box", half_extents: [0.1, 20.0], position: [4.0, 10.0], fixed: true)"#
            .to_owned(),
    );
    bodies.join(",\n")
}

/// After one head-on impact of equal masses with restitution `e` (the
/// struck ball at rest, the striker at 1 m/s): `(1 − e)/2` and `(1 + e)/2`;
/// off a wall: `−e`.
fn check(r: &Value, row: usize, e_pair: f64, e_wall: f64, what: &str) {
    let (a, b, w) = (vx(r, 3 * row), vx(r, 3 * row + 1), vx(r, 3 * row + 2));
    let tol = 1e-6;
    assert!(
        (a - (1.0 - e_pair) / 2.0).abs() < tol,
        "{what}: striker {a}, e = {e_pair}"
    );
    assert!(
        (b - (1.0 + e_pair) / 2.0).abs() < tol,
        "{what}: struck {b}, e = {e_pair}"
    );
    assert!(
        (w + e_wall).abs() < tol,
        "{what}: off the wall {w}, e = {e_wall}"
    );
}

#[test]
fn materials_and_law_from_restitutions_give_them_in_the_reference_impacts() {
    let m = |name: &str| format!(r#", material: "{name}""#);
    let bodies = rows(&[
        [&m("steel"), &m("steel"), &m("steel")],
        [&m("clay"), &m("clay"), &m("clay")],
        ["", "", ""],
    ]);
    let path = write(
        "materials.ron",
        format!(
            r#"(dim: 2, precision: "f64", steps: 90,
                law: (restitution: 0.3, wall_restitution: 0.7),
                materials: {{"steel": (restitution: 0.8, wall_restitution: 0.9), "clay": (restitution: 0.2)}},
                bodies: [{bodies}])"#
        ),
    );
    for mode in ["restitution", "impulse", "exact"] {
        let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
        check(&r, 0, 0.8, 0.9, &format!("{mode} steel"));
        check(&r, 1, 0.2, 0.2, &format!("{mode} clay"));
        check(&r, 2, 0.3, 0.7, &format!("{mode} law"));
    }
}

/// No `law` constants: each ball's written restitution is its law's. Two
/// balls of 0.6 and 0.8 meet with `sqrt((0.6² + 0.8²)/2)`; each bounces off
/// the wall (restitution 1 for rapier) with its own. With a `law` constant
/// the restitutions are rapier's only: the elastic law.
#[test]
fn a_body_s_restitution_is_its_law_s_when_the_scene_sets_none() {
    let r = |e: f64| format!(", restitution: {e:?}");
    let bodies = rows(&[[&r(0.6), &r(0.8), &r(0.5)], [&r(0.3), &r(0.3), ""]]);
    let speaks = write(
        "speaks.ron",
        format!(r#"(dim: 2, precision: "f64", steps: 90, bodies: [{bodies}])"#),
    );
    let quiet = write(
        "quiet.ron",
        format!(
            r#"(dim: 2, precision: "f64", steps: 90, law: (dissipation: 0.0), bodies: [{bodies}])"#
        ),
    );
    for mode in ["restitution", "impulse", "exact"] {
        let rep = report(&["run", speaks.to_str().unwrap(), "--mode", mode]);
        assert!(
            rep["effects"]
                .as_array()
                .unwrap()
                .iter()
                .any(|e| e == "dissipation"),
            "{mode}: {}",
            rep["effects"]
        );
        check(
            &rep,
            0,
            (0.5_f64).sqrt(),
            0.5,
            &format!("{mode} restitutions"),
        );
        // A ball without a written restitution meets the wall by the
        // scene's law: elastic.
        check(&rep, 1, 0.3, 1.0, &format!("{mode} 0.3"));
        let rep = report(&["run", quiet.to_str().unwrap(), "--mode", mode]);
        check(&rep, 0, 1.0, 1.0, &format!("{mode} law set"));
    }
}
