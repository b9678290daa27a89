//! Impact friction in scene files: a material's `impact_friction` (μ) and
//! `tangential_restitution` (β), their defaults and checks (each error
//! naming the key), the `friction` effect that switches them on, `spin`
//! required with them, and what the simulation is given
//! (`Scene::effective_material`).

use kimpact_scene::{Effect, Material, Scene, SceneError, parse, validate};

fn load(text: &str) -> Result<Scene, SceneError> {
    validate(parse(text, "ron")?, "s.ron", "s")
}

/// Two balls with material `m` (written `material`), and `effects` if
/// given; `precision` f32 unless `f64`.
fn scene(material: &str, effects: Option<&str>, precision: &str) -> Result<Scene, SceneError> {
    let effects = effects.map_or(String::new(), |e| format!("effects: [{e}], "));
    load(&format!(
        r#"(dim: 3, steps: 5, precision: "{precision}", {effects}materials: {{"m": {material}}}, bodies: [
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0, 0.0], velocity: [1.0, 0.0, 0.0], material: "m"),
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.5, 0.05, 0.0], material: "m"),
        ])"#
    ))
}

fn error(material: &str, effects: Option<&str>, precision: &str) -> SceneError {
    scene(material, effects, precision).expect_err("refused")
}

#[test]
fn the_keys_and_their_defaults() {
    let s = scene(
        "(impact_friction: 0.2, tangential_restitution: 0.4)",
        None,
        "f32",
    )
    .unwrap();
    let m = &s.materials[0];
    assert_eq!((m.impact_friction, m.tangential_restitution), (0.2, 0.4));
    assert!(m.has_impact_friction());
    // β defaults to 0 (a sticking impact stops the slip) with μ written.
    let m = &scene("(impact_friction: 0.2)", None, "f32")
        .unwrap()
        .materials[0];
    assert_eq!((m.impact_friction, m.tangential_restitution), (0.2, 0.0));
    // Neither written: no impact friction (the adapter's μ = 0, β = −1).
    let m = &scene("(dissipation: 0.01)", None, "f32").unwrap().materials[0];
    assert_eq!(m.impact_friction, 0.0);
    assert_eq!(
        m.tangential_restitution,
        Material::NO_TANGENTIAL_RESTITUTION
    );
    assert!(!m.has_impact_friction());
    // β alone: μ = 0, β as written (it counts when the material's pairs
    // combine it with another material's).
    let m = &scene("(tangential_restitution: 0.5)", None, "f32")
        .unwrap()
        .materials[0];
    assert_eq!((m.impact_friction, m.tangential_restitution), (0.0, 0.5));
    assert!(!m.has_impact_friction());
    // The ends of the range.
    for beta in [-1.0, 1.0] {
        let s = scene(
            &format!("(impact_friction: 0.0, tangential_restitution: {beta:?})"),
            None,
            "f32",
        );
        assert_eq!(s.unwrap().materials[0].tangential_restitution, beta);
    }
}

#[test]
fn bad_values_are_errors_naming_the_key() {
    for (material, precision, field, message) in [
        (
            "(impact_friction: -0.1)",
            "f32",
            "materials.m.impact_friction",
            "must be finite and >= 0, got -0.1",
        ),
        (
            "(impact_friction: inf)",
            "f64",
            "materials.m.impact_friction",
            "must be finite and >= 0, got inf",
        ),
        (
            "(impact_friction: NaN)",
            "f64",
            "materials.m.impact_friction",
            "must be finite and >= 0, got NaN",
        ),
        (
            "(impact_friction: 1e300)",
            "f32",
            "materials.m.impact_friction",
            "1e300 is beyond f32's range",
        ),
        (
            "(impact_friction: 0.1, tangential_restitution: 1.01)",
            "f64",
            "materials.m.tangential_restitution",
            "must be in [-1, 1], got 1.01",
        ),
        (
            "(tangential_restitution: -1.5)",
            "f32",
            "materials.m.tangential_restitution",
            "must be in [-1, 1], got -1.5",
        ),
        (
            "(impact_friction: 0.1, tangential_restitution: NaN)",
            "f32",
            "materials.m.tangential_restitution",
            "must be in [-1, 1], got NaN",
        ),
    ] {
        let e = error(material, None, precision);
        assert_eq!(e.field, field, "{material}: {e}");
        assert!(e.message.contains(message), "{material}: {e}");
    }
    // A huge μ holds in f64.
    let s = scene("(impact_friction: 1e300)", None, "f64").unwrap();
    assert_eq!(s.materials[0].impact_friction, 1e300);
}

#[test]
fn impact_friction_needs_spin() {
    let e = error("(impact_friction: 0.1)", Some(r#""friction""#), "f32");
    assert_eq!(e.field, "effects");
    assert!(
        e.message.contains("materials.m gives impact friction"),
        "{e}"
    );
    assert!(e.message.contains("\"spin\" must be on too"), "{e}");
    // With both, on.
    let s = scene(
        "(impact_friction: 0.1)",
        Some(r#""friction", "spin""#),
        "f32",
    )
    .unwrap();
    assert!(s.active(Effect::Friction) && s.active(Effect::Spin));
    assert!(s.impact_friction_active());
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // μ = 0 is no impact friction: nothing to refuse, nothing to switch on.
    let s = scene(
        "(tangential_restitution: 0.5)",
        Some(r#""friction""#),
        "f32",
    )
    .unwrap();
    assert!(!s.active(Effect::Friction) && !s.impact_friction_active());
}

#[test]
fn without_the_friction_effect_impact_friction_is_ignored_with_a_warning() {
    let s = scene("(impact_friction: 0.1)", Some(r#""spin""#), "f32").unwrap();
    assert!(!s.active(Effect::Friction));
    assert!(!s.impact_friction_active());
    assert_eq!(
        s.warnings,
        [
            "s.ron: materials.m.impact_friction: ignored (frictionless impacts), \"friction\" is not in `effects`"
        ]
    );
    // The simulation gets no material at all (nothing else is active in it).
    assert_eq!(s.effective_material(0), None);
}

#[test]
fn derived_effects_switch_friction_and_spin_on() {
    let s = scene("(impact_friction: 0.1)", None, "f32").unwrap();
    assert!(s.effects.contains(&Effect::Friction));
    assert!(s.effects.contains(&Effect::Spin));
    assert!(s.impact_friction_active());
    assert!(!s.active(Effect::Dissipation));
    assert_eq!(s.active_effects(), ["friction", "spin"]);
}

#[test]
fn the_simulation_gets_each_material_with_its_active_parts() {
    // Friction on, dissipation off: μ and β as written, d̃ zero.
    let rough = "(dissipation: 0.02, impact_friction: 0.3, tangential_restitution: 0.5)";
    let s = scene(rough, Some(r#""friction", "spin""#), "f64").unwrap();
    let m = s.effective_material(1).expect("a material");
    assert_eq!((m.impact_friction, m.tangential_restitution), (0.3, 0.5));
    assert_eq!((m.dissipation, m.wall_dissipation), (0.0, 0.0));
    // Dissipation on, friction off: d̃ as written, no impact friction.
    let s = scene(rough, Some(r#""dissipation", "spin""#), "f64").unwrap();
    let m = s.effective_material(1).expect("a material");
    assert_eq!((m.dissipation, m.wall_dissipation), (0.02, 0.02));
    assert_eq!(m.impact_friction, 0.0);
    assert_eq!(
        m.tangential_restitution,
        Material::NO_TANGENTIAL_RESTITUTION
    );
    // Both on: the material as written.
    let s = scene(rough, Some(r#""dissipation", "friction", "spin""#), "f64").unwrap();
    assert_eq!(s.effective_material(0).as_ref(), Some(&s.materials[0]));
}

/// With impact friction on, a body whose material has none is still given
/// its material, so that a pair combines the two μ (here by `"average"`)
/// whether `dissipation` is on or not.
#[test]
fn a_smooth_material_is_given_too_when_impact_friction_is_on() {
    let s = load(
        r#"(dim: 2, steps: 5, effects: ["friction", "spin"],
            materials: {"rough": (impact_friction: 0.3), "smooth": (combine: "average")},
            bodies: [
                (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], velocity: [1.0, 0.0], material: "rough"),
                (shape: "ball", radius: 0.1, mass: 1.0, position: [0.5, 0.0], material: "smooth"),
                (shape: "ball", radius: 0.1, mass: 1.0, position: [1.0, 0.0]),
            ])"#,
    )
    .unwrap();
    let smooth = s.effective_material(1).expect("the smooth material");
    assert_eq!(smooth.name, "smooth");
    assert!(!smooth.has_impact_friction());
    assert_eq!(s.effective_material(2), None, "no material written");
}

/// `allow_fast_rotation` (rapier's lift of its angular speed cap): false
/// unless written, and refused on a fixed body by its key.
#[test]
fn allow_fast_rotation_is_read_and_refused_on_fixed_bodies() {
    let s = load(
        r#"(dim: 2, steps: 5, bodies: [
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], allow_fast_rotation: true),
            (shape: "ball", radius: 0.1, mass: 1.0, position: [1.0, 0.0]),
        ])"#,
    )
    .unwrap();
    assert!(s.bodies[0].allow_fast_rotation);
    assert!(!s.bodies[1].allow_fast_rotation);
    let e = load(
        r#"(dim: 2, steps: 5, effects: ["fixed_walls"], bodies: [
            (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0]),
            (shape: "box", half_extents: [0.1, 1.0], position: [1.0, 0.0], fixed: true, allow_fast_rotation: true),
        ])"#,
    )
    .expect_err("refused");
    assert_eq!(e.field, "bodies[1].allow_fast_rotation");
    assert!(e.message.contains("a fixed body does not turn"), "{e}");
}
