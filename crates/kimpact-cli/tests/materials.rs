//! Materials in scene files end to end: each pair's outcome is the core
//! law's for the pair's combined constants (rapier's combine rules), in
//! every law mode, and the three formats read the same materials.

mod common;

use kimpact::nalgebra::Vector2;
use kimpact::{Body, FixedPartner, Law, LawParams};
use serde_json::Value;

use common::{kimpact, report, write};

/// Five head-on pairs (left ball at 1 m/s onto a ball at rest, masses 1
/// and 2) and three balls thrown at walls, one row each, far apart: every
/// body meets one partner once.
const SCENE: &str = r#"
description = "materials: one impact per pair"
dim = 2
precision = "f64"
steps = 20
mode = "exact"

[law]
dissipation = 0.01
wall_dissipation = 0.05

[materials.rubber]
dissipation = 0.02
wall_dissipation = 0.1

[materials.steel]
dissipation = 0.04
wall_dissipation = 0.02
combine = "max"

[materials.clay]
dissipation = 0.1
combine = "geometric_mean"

[materials.cushion]
wall_dissipation = 0.3

# pair 0: rubber / rubber
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 0.0]
velocity = [1.0, 0.0]
material = "rubber"
[[bodies]]
shape = "ball"
radius = 0.1
mass = 2.0
position = [0.25, 0.0]
material = "rubber"

# pair 1: rubber / steel (max)
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 2.0]
velocity = [1.0, 0.0]
material = "rubber"
[[bodies]]
shape = "ball"
radius = 0.1
mass = 2.0
position = [0.25, 2.0]
material = "steel"

# pair 2: steel (max) / clay (geometric mean wins)
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 4.0]
velocity = [1.0, 0.0]
material = "steel"
[[bodies]]
shape = "ball"
radius = 0.1
mass = 2.0
position = [0.25, 4.0]
material = "clay"

# pair 3: no material on either side: the scene's law
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 6.0]
velocity = [1.0, 0.0]
[[bodies]]
shape = "ball"
radius = 0.1
mass = 2.0
position = [0.25, 6.0]

# pair 4: clay / none: clay's own
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 8.0]
velocity = [1.0, 0.0]
material = "clay"
[[bodies]]
shape = "ball"
radius = 0.1
mass = 2.0
position = [0.25, 8.0]

# wall 0: rubber ball onto a cushion wall: the two wall constants averaged
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 10.0]
velocity = [1.0, 0.0]
material = "rubber"
[[bodies]]
shape = "box"
half_extents = [0.05, 0.3]
position = [0.2, 10.0]
fixed = true
material = "cushion"

# wall 1: rubber ball onto a plain wall: rubber's wall constant
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 12.0]
velocity = [1.0, 0.0]
material = "rubber"
[[bodies]]
shape = "box"
half_extents = [0.05, 0.3]
position = [0.2, 12.0]
fixed = true

# wall 2: a ball without material onto the cushion: the cushion's own
[[bodies]]
shape = "ball"
radius = 0.1
mass = 1.0
position = [0.0, 14.0]
velocity = [1.0, 0.0]
[[bodies]]
shape = "box"
half_extents = [0.05, 0.3]
position = [0.2, 14.0]
fixed = true
material = "cushion"
"#;

/// The core law's velocities after the head-on impact of `m1` at 1 m/s
/// onto `m2` at rest (`m2 = None`: a wall), under constants `d`, `dw`.
fn expected(d: f64, dw: f64, m1: f64, m2: Option<f64>) -> (f64, f64) {
    let law = Law::new(LawParams {
        dissipation: d,
        wall_dissipation: Some(dw),
        fixed_partner: FixedPartner::OwnMass,
    })
    .unwrap();
    let a = Body::new(m1, Vector2::new(1.0, 0.0)).unwrap();
    let b = match m2 {
        Some(m) => Body::new(m, Vector2::zeros()).unwrap(),
        None => Body::immovable(Vector2::zeros()).unwrap(),
    };
    let i = law
        .resolve(&a, &b, &Vector2::x())
        .unwrap()
        .expect("approaching");
    assert!(!i.clamped);
    (1.0 + i.delta_v_a.x, i.delta_v_b.x)
}

fn velocities(r: &Value) -> Vec<f64> {
    r["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["velocity"][0].as_f64().unwrap())
        .collect()
}

#[test]
fn each_pair_follows_the_law_of_its_combined_materials() {
    let path = write("materials.toml", SCENE);
    let p = path.to_str().unwrap();
    // (d̃, d̃_w) of each row, by rapier's rules: average unless either side
    // asks for a rule of higher priority; one side alone gives its own.
    let rows = [
        (0.02, 0.1, Some(2.0)),                   // rubber / rubber
        (0.04, 0.1, Some(2.0)),                   // max(0.02, 0.04)
        ((0.04f64 * 0.1).sqrt(), 0.1, Some(2.0)), // geometric mean
        (0.01, 0.05, Some(2.0)),                  // the scene's law
        (0.1, 0.1, Some(2.0)),                    // clay alone
        (0.02, 0.2, None),                        // (0.1 + 0.3) / 2
        (0.02, 0.1, None),                        // rubber alone
        (0.0, 0.3, None),                         // the cushion alone
    ];
    // The velocities are the law's to rounding in every law mode (rapier's
    // solver applies the law's restitution exactly for an isolated impact).
    let tol = 1e-9;
    for mode in ["exact", "impulse", "restitution"] {
        let r = report(&["run", p, "--mode", mode]);
        let v = velocities(&r);
        assert_eq!(r["impacts"]["count"], 8, "{mode}: one impact per row");
        for (k, &(d, dw, m2)) in rows.iter().enumerate() {
            let (v1, v2) = expected(d, dw, 1.0, m2);
            let (got1, got2) = (v[2 * k], v[2 * k + 1]);
            assert!((got1 - v1).abs() < tol, "{mode} row {k}: {got1} vs {v1}");
            if m2.is_some() {
                assert!((got2 - v2).abs() < tol, "{mode} row {k}: {got2} vs {v2}");
            } else {
                assert_eq!(got2, 0.0, "{mode} row {k}: the wall stays");
            }
        }
        // The rows differ: the materials are not all one law.
        let (rubber, _) = expected(0.02, 0.1, 1.0, Some(2.0));
        let (steel, _) = expected(0.04, 0.1, 1.0, Some(2.0));
        assert!((rubber - steel).abs() > 100.0 * tol);
        // Only moving law bodies count as marked (the cushions carry a
        // material but are fixed).
        assert_eq!(r["setup"]["marked_bodies"], 13, "{mode}");
    }
    // Native mode ignores materials: rapier's restitution (0 by default)
    // makes each pair plastic.
    let r = report(&["run", p, "--mode", "native"]);
    let v = velocities(&r);
    assert!((v[0] - v[1]).abs() < 1e-6, "native: {} {}", v[0], v[1]);
}

#[test]
fn the_three_formats_read_the_same_materials() {
    let body = |x: f64, y: f64, vx: f64, m: &str| {
        format!(
            r#"{{"shape": "ball", "radius": 0.1, "mass": 1.0, "position": [{x}, {y}], "velocity": [{vx}, 0.0], "material": "{m}"}}"#
        )
    };
    let json = format!(
        r#"{{"dim": 2, "precision": "f64", "steps": 20, "materials": {{"rubber": {{"dissipation": 0.02, "combine": "min"}}, "steel": {{"dissipation": 0.05}}}}, "bodies": [{}, {}],
        "generators": [{{"origin": [0.0, 3.0], "count": [2, 1], "spacing": [0.25, 1.0], "speed": 0.5, "seed": 3,
                         "body": {{"shape": "ball", "radius": 0.1, "mass": 1.0}}, "materials": ["steel", "rubber"]}}]}}"#,
        body(0.0, 0.0, 1.0, "rubber"),
        body(0.25, 0.0, 0.0, "steel")
    );
    let ron = r#"(dim: 2, precision: "f64", steps: 20,
        materials: {"rubber": (dissipation: 0.02, combine: "min"), "steel": (dissipation: 0.05)},
        bodies: [
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], velocity: [1.0, 0.0], material: "rubber"),
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.25, 0.0], velocity: [0.0, 0.0], material: "steel"),
        ],
        generators: [(origin: [0.0, 3.0], count: [2, 1], spacing: [0.25, 1.0], speed: 0.5, seed: 3,
                      body: (shape: "ball", radius: 0.1, mass: 1.0), materials: ["steel", "rubber"])])"#;
    let toml = r#"dim = 2
precision = "f64"
steps = 20
materials = { rubber = { dissipation = 0.02, combine = "min" }, steel = { dissipation = 0.05 } }
bodies = [
    { shape = "ball", radius = 0.1, mass = 1.0, position = [0.0, 0.0], velocity = [1.0, 0.0], material = "rubber" },
    { shape = "ball", radius = 0.1, mass = 1.0, position = [0.25, 0.0], velocity = [0.0, 0.0], material = "steel" },
]
[[generators]]
origin = [0.0, 3.0]
count = [2, 1]
spacing = [0.25, 1.0]
speed = 0.5
seed = 3
body = { shape = "ball", radius = 0.1, mass = 1.0 }
materials = ["steel", "rubber"]
"#;
    let mut finals = Vec::new();
    for (name, text) in [("m.json", json.as_str()), ("m.ron", ron), ("m.toml", toml)] {
        let path = write(name, text);
        let r = report(&["run", path.to_str().unwrap()]);
        assert!(r["impacts"]["count"].as_u64().unwrap() >= 1, "{name}");
        finals.push((name, r["bodies"].clone(), r["impacts"].clone()));
    }
    // The first pair: min(0.02, 0.05) = 0.02 (rubber asks for min).
    let (v1, v2) = expected(0.02, 0.02, 1.0, Some(1.0));
    let b = &finals[0].1;
    assert!((b[0]["velocity"][0].as_f64().unwrap() - v1).abs() < 1e-9);
    assert!((b[1]["velocity"][0].as_f64().unwrap() - v2).abs() < 1e-9);
    for (name, bodies, impacts) in &finals[1..] {
        assert_eq!(bodies, &finals[0].1, "{name}: the same bodies as JSON");
        assert_eq!(impacts, &finals[0].2, "{name}: the same impacts as JSON");
    }
}

#[test]
fn an_unused_material_is_a_warning_and_f64_holds_what_f32_cannot() {
    let text = r#"{"dim": 2, "precision": "f64", "steps": 2,
        "law": {"dissipation": 1e300},
        "materials": {"spare": {"dissipation": 0.1}},
        "bodies": [{"shape": "ball", "radius": 0.1, "mass": 1, "position": [0, 0]}]}"#;
    let path = write("spare.json", text);
    let o = kimpact(&["check", path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("materials.spare: no body uses it"), "{err}");
}
