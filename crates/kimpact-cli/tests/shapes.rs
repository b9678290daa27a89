//! Shapes and orientations end to end: the report gives each body's
//! `rotation` and `angular_velocity` in the scene file's forms and counts
//! rotation in `kinetic`; capsules and convex shapes rest on a floor where
//! their geometry says; the bundled dominoes topple and the dice settle in
//! their box, in every mode.

mod common;

use common::{MODES, f, report, scene, vecf, write};

/// A lone box spinning in free space (f64, no gravity) for 1 s, `N` = 240
/// substeps of `h`: the report's rotation is what rapier's linearised
/// rotation gives, `N atan(ω h)` in 2D (each substep turns the unit complex
/// by `(1, ω h)`, normalised) and `N · 2 atan(|ω| h / 2)` about `ω` in 3D
/// (each substep multiplies the quaternion by `(ω h/2, 1)`, normalised), a
/// cube about z; its angular velocity `ω`; and `kinetic` its rotational
/// energy `½ I ω²`: 2D `I = m (a² + b²)/3` for half extents `a`, `b`; a
/// cube of half edge `e`, `I = 2 m e²/3`. A start rotation is kept.
#[test]
fn the_report_gives_rotation_angular_velocity_and_rotational_energy() {
    let two = write(
        "spin2d.ron",
        r#"(dim: 2, precision: "f64", steps: 60, bodies: [
            (shape: "box", half_extents: [0.3, 0.1], mass: 2.0, position: [0.0, 0.0], angular_velocity: 2.0),
            (shape: "box", half_extents: [0.3, 0.1], mass: 2.0, position: [5.0, 0.0], rotation: 0.5)])"#,
    );
    let three = write(
        "spin3d.ron",
        r#"(dim: 3, precision: "f64", steps: 60, bodies: [
            (shape: "box", half_extents: [0.1, 0.1, 0.1], mass: 1.0, position: [0.0, 0.0, 0.0], angular_velocity: [0.0, 0.0, 3.0])])"#,
    );
    for mode in MODES {
        let r = report(&["run", two.to_str().unwrap(), "--mode", mode]);
        let n = 60.0 * r["setup"]["substeps"].as_u64().unwrap() as f64;
        let h = f(&r["dt"]) * 60.0 / n;
        let b = &r["bodies"][0];
        let turned = n * (2.0 * h).atan();
        assert!((turned - 2.0).abs() > 1e-5, "the linearisation shows");
        assert!(
            (f(&b["rotation"]) - turned).abs() < 1e-9,
            "{mode}: {} vs {turned}",
            b["rotation"]
        );
        assert!((f(&b["angular_velocity"]) - 2.0).abs() < 1e-12, "{mode}");
        assert!(
            (f(&r["bodies"][1]["rotation"]) - 0.5).abs() < 1e-12,
            "{mode}"
        );
        let i = 2.0 * (0.09 + 0.01) / 3.0;
        let kinetic = f(&r["energy"]["kinetic_final"]);
        assert!(
            (kinetic - 0.5 * i * 4.0).abs() < 1e-9,
            "{mode}: kinetic {kinetic}"
        );

        let r = report(&["run", three.to_str().unwrap(), "--mode", mode]);
        let b = &r["bodies"][0];
        let rot = vecf(&b["rotation"]);
        let turned = n * 2.0 * (3.0 * h / 2.0).atan();
        assert!(
            rot[0].abs() < 1e-9 && rot[1].abs() < 1e-9 && (rot[2] - turned).abs() < 1e-9,
            "{mode}: {rot:?} vs {turned}"
        );
        let w = vecf(&b["angular_velocity"]);
        assert!(
            w[0].abs() < 1e-12 && w[1].abs() < 1e-12 && (w[2] - 3.0).abs() < 1e-12,
            "{mode}: {w:?}"
        );
        let i = 2.0 * 0.01 / 3.0;
        let kinetic = f(&r["energy"]["kinetic_final"]);
        assert!(
            (kinetic - 0.5 * i * 9.0).abs() < 1e-9,
            "{mode}: kinetic {kinetic}"
        );
    }
}

/// Dropped 5 cm onto a floor (top at y = 0) under gravity, restitution
/// 0.2 (elastic, the law's impulse and exact mode would bounce them to
/// the same height for ever): a standing capsule comes to rest with its
/// centre at `half_height + radius`, a convex triangle (2D) and a
/// tetrahedron (3D) on their flat base with their origin (the base's
/// height) at 0, to rapier's resting overlap.
#[test]
fn capsules_and_convex_shapes_rest_where_their_geometry_says() {
    let two = write(
        "rest2d.ron",
        r#"(dim: 2, precision: "f64", steps: 180, gravity: [0.0, -9.81], bodies: [
            (shape: "box", half_extents: [3.0, 0.1], position: [0.0, -0.1], fixed: true),
            (shape: "capsule", half_height: 0.2, radius: 0.1, mass: 1.0, restitution: 0.2, position: [-1.0, 0.35]),
            (shape: "convex", points: [[-0.2, 0.0], [0.2, 0.0], [0.0, 0.3]], mass: 1.0, restitution: 0.2, position: [1.0, 0.05])])"#,
    );
    let three = write(
        "rest3d.ron",
        r#"(dim: 3, precision: "f64", steps: 180, gravity: [0.0, -9.81, 0.0], bodies: [
            (shape: "box", half_extents: [3.0, 0.1, 3.0], position: [0.0, -0.1, 0.0], fixed: true),
            (shape: "capsule", half_height: 0.2, radius: 0.1, mass: 1.0, restitution: 0.2, position: [-1.0, 0.35, 0.0]),
            (shape: "convex", points: [[-0.2, 0.0, -0.2], [0.2, 0.0, -0.2], [0.0, 0.0, 0.2], [0.0, 0.3, 0.0]], mass: 1.0, restitution: 0.2, position: [1.0, 0.05, 0.0])])"#,
    );
    for path in [two, three] {
        for mode in MODES {
            let r = report(&["run", path.to_str().unwrap(), "--mode", mode]);
            let what = format!("{} {mode}", path.display());
            assert_eq!(r["bodies"][1]["shape"], "capsule");
            assert_eq!(r["bodies"][2]["shape"], "convex");
            let capsule = vecf(&r["bodies"][1]["position"]);
            assert!(
                (capsule[1] - 0.3).abs() < 5e-3,
                "{what}: capsule at {capsule:?}"
            );
            let convex = vecf(&r["bodies"][2]["position"]);
            assert!(convex[1].abs() < 5e-3, "{what}: convex at {convex:?}");
            for b in 1..3 {
                let v = vecf(&r["bodies"][b]["velocity"]);
                assert!(
                    v.iter().all(|x| x.abs() < 1e-2),
                    "{what}: body {b} moves {v:?}"
                );
            }
        }
    }
}

/// The bundled dominoes: the first is tipped, and every one of the 20 ends
/// lying against the next (turned by more than 1 rad), in every mode. The
/// bundled dice: thrown spinning into a closed box, they end at rest on its
/// floor (centres below 0.2 m), none outside.
#[test]
fn the_dominoes_topple_and_the_dice_settle() {
    for mode in MODES {
        let r = report(&[
            "run",
            scene("dominoes2d.ron").to_str().unwrap(),
            "--mode",
            mode,
        ]);
        for b in 1..21 {
            let turn = f(&r["bodies"][b]["rotation"]);
            assert!(turn < -1.0, "{mode}: domino {} turned {turn}", b - 1);
        }
        let r = report(&["run", scene("dice3d.ron").to_str().unwrap(), "--mode", mode]);
        assert_eq!(r["checks"]["escaped"], 0, "{mode}");
        for b in 6..24 {
            let x = vecf(&r["bodies"][b]["position"]);
            let v = vecf(&r["bodies"][b]["velocity"]);
            assert!(x[1] > 0.0 && x[1] < 0.2, "{mode}: die {} at {x:?}", b - 6);
            assert!(
                v.iter().all(|c| c.abs() < 0.05),
                "{mode}: die {} moves {v:?}",
                b - 6
            );
        }
    }
}
