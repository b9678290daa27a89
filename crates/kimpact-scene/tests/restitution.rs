//! The law from a restitution in scene files: `restitution` and
//! `wall_restitution` in `law` and in materials, converted by
//! `LawParams::from_restitution`, and a body's own `restitution` standing
//! for its law when nothing else sets one.

use kimpact::LawParams;
use kimpact_scene::{Effect, Scene, SceneError, parse, validate};

fn load(text: &str) -> Result<Scene, SceneError> {
    validate(parse(text, "ron")?, "s.ron", "s")
}

const BALL: &str =
    r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], material: "m")"#;

fn with_material(material: &str) -> Result<Scene, SceneError> {
    load(&format!(
        "(dim: 2, steps: 5, materials: {{\"m\": {material}}}, bodies: [{BALL}])"
    ))
}

#[test]
fn a_material_s_restitution_is_from_restitution_s_d() {
    let s = with_material("(restitution: 0.8, wall_restitution: 0.9)").unwrap();
    let want = LawParams::from_restitution(0.8, 0.9).unwrap();
    let m = &s.materials[0];
    assert_eq!(m.dissipation, want.dissipation);
    assert_eq!(Some(m.wall_dissipation), want.wall_dissipation);
    assert_eq!(m.restitution, Some([0.8, 0.9]));
    assert!(s.active(Effect::Dissipation));
    // The wall's restitution defaults to the restitution.
    let s = with_material("(restitution: 0.6)").unwrap();
    let want = LawParams::from_restitution(0.6, 0.6).unwrap();
    assert_eq!(Some(s.materials[0].wall_dissipation), want.wall_dissipation);
    // ... unless the wall's d̃ is written; and a wall restitution goes with
    // a written d̃.
    let s = with_material("(restitution: 0.6, wall_dissipation: 0.0)").unwrap();
    assert_eq!(s.materials[0].wall_dissipation, 0.0);
    assert_eq!(s.materials[0].restitution, None);
    let s = with_material("(dissipation: 0.01, wall_restitution: 0.5)").unwrap();
    assert_eq!(s.materials[0].dissipation, 0.01);
    assert_eq!(s.materials[0].wall_dissipation, (1.0 - 0.25) / 2.0);
    // Elastic.
    let s = with_material("(restitution: 1.0)").unwrap();
    assert!(!s.materials[0].dissipates());
}

#[test]
fn the_law_table_takes_a_restitution_too() {
    let s = load(&format!(
        "(dim: 2, steps: 5, law: (restitution: 0.5), bodies: [{}])",
        BALL.replace(r#", material: "m""#, "")
    ))
    .unwrap();
    let want = LawParams::from_restitution(0.5, 0.5).unwrap();
    assert_eq!(s.law, want);
}

#[test]
fn a_reference_impact_given_twice_or_out_of_range_is_an_error() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "(restitution: 0.8, dissipation: 0.01)",
            "materials.m.restitution",
            &["`materials.m.restitution` or `materials.m.dissipation`, not both"],
        ),
        (
            "(wall_restitution: 0.8, wall_dissipation: 0.01)",
            "materials.m.wall_restitution",
            &["`materials.m.wall_dissipation`"],
        ),
        (
            "(restitution: 1.5)",
            "materials.m.restitution",
            &["[0, 1]", "1.5"],
        ),
        (
            "(restitution: -0.1)",
            "materials.m.restitution",
            &["[0, 1]"],
        ),
        ("(restitution: NaN)", "materials.m.restitution", &["[0, 1]"]),
        (
            "(restitution: 0.5, wall_restitution: 2.0)",
            "materials.m.wall_restitution",
            &["[0, 1]"],
        ),
    ];
    for (material, field, words) in cases {
        let e = with_material(material).expect_err(material);
        assert_eq!(e.field, *field, "{material}: {e}");
        for w in *words {
            assert!(e.message.contains(w), "{material}: {e} lacks {w:?}");
        }
    }
    let e = load(&format!(
        "(dim: 2, steps: 5, law: (restitution: 0.5, dissipation: 0.1), bodies: [{}])",
        BALL.replace(r#", material: "m""#, "")
    ))
    .unwrap_err();
    assert_eq!(e.field, "law.restitution");
    assert!(e.message.contains("`law.dissipation`"), "{e}");
    // A wall restitution below 1 holds under "own_mass" only.
    let e = load(&format!(
        "(dim: 2, steps: 5, law: (fixed_partner: \"literal\"), materials: {{\"m\": (restitution: 0.5)}}, bodies: [{BALL}])"
    ))
    .unwrap_err();
    assert_eq!(e.field, "materials.m.restitution");
    assert!(e.message.contains("\"own_mass\""), "{e}");
}

/// Two law balls and a wall with written restitutions and no `law`
/// constants: each ball's restitution is its law's; the wall's is rapier's
/// only. With `law` constants, a body's restitution is rapier's only.
#[test]
fn a_body_s_restitution_speaks_to_the_law_when_nothing_else_does() {
    let bodies = r#"bodies: [
        (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], restitution: 0.6),
        (shape: "ball", radius: 0.1, mass: 1.0, position: [1.0, 0.0], restitution: 0.8),
        (shape: "ball", radius: 0.1, mass: 1.0, position: [2.0, 0.0], restitution: 0.6),
        (shape: "ball", radius: 0.1, mass: 1.0, position: [3.0, 0.0]),
        (shape: "box", half_extents: [0.1, 1.0], position: [-1.0, 0.0], fixed: true, restitution: 0.2),
    ]"#;
    let s = load(&format!("(dim: 2, steps: 5, {bodies})")).unwrap();
    assert_eq!(
        s.materials.len(),
        2,
        "one per restitution: {:?}",
        s.materials
    );
    let m = |i: usize| s.bodies[i].material.map(|k| &s.materials[k]);
    let e06 = m(0).expect("a material");
    assert_eq!(e06.name, "restitution 0.6");
    assert!(!e06.named);
    let want = LawParams::from_restitution(0.6, 0.6).unwrap();
    assert_eq!(e06.dissipation, want.dissipation);
    assert_eq!(Some(e06.wall_dissipation), want.wall_dissipation);
    assert_eq!(s.bodies[2].material, s.bodies[0].material, "shared");
    assert_eq!(m(1).unwrap().name, "restitution 0.8");
    assert_eq!(
        s.bodies[3].material, None,
        "nothing written: the scene's law"
    );
    assert_eq!(
        s.bodies[4].material, None,
        "a fixed body's restitution is rapier's"
    );
    assert!(
        s.active(Effect::Dissipation),
        "derived from the restitutions"
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);

    for law in ["law: (dissipation: 0.0)", "law: (wall_restitution: 1.0)"] {
        let s = load(&format!("(dim: 2, steps: 5, {law}, {bodies})")).unwrap();
        assert!(s.materials.is_empty(), "{law}");
        assert!(s.bodies.iter().all(|b| b.material.is_none()), "{law}");
    }
    // `fixed_partner` alone sets no constant.
    let s = load(&format!(
        "(dim: 2, steps: 5, law: (fixed_partner: \"own_mass\"), {bodies})"
    ))
    .unwrap();
    assert_eq!(s.materials.len(), 2);
    // A body that does not follow the law keeps its restitution to rapier.
    let s = load(
        r#"(dim: 2, steps: 5, bodies: [(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], restitution: 0.5, law: false)])"#,
    )
    .unwrap();
    assert!(s.materials.is_empty());
}

#[test]
fn a_body_restitution_above_1_is_an_error_only_where_it_is_the_law_s() {
    let ball = r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], restitution: 1.5)"#;
    let e = load(&format!("(dim: 2, steps: 5, bodies: [{ball}])")).unwrap_err();
    assert_eq!(e.field, "bodies[0].restitution");
    assert!(e.message.contains("the law only takes energy away"), "{e}");
    assert!(e.message.contains("`law`"), "{e}");
    assert!(
        load(&format!(
            "(dim: 2, steps: 5, law: (dissipation: 0.0), bodies: [{ball}])"
        ))
        .is_ok()
    );
    // A generated body is named by its generator.
    let e = load(
        r#"(dim: 2, steps: 5, generators: [(origin: [0.0, 0.0], count: [2, 1], spacing: [1.0, 1.0],
            body: (shape: "ball", radius: 0.1, mass: 1.0, restitution: 1.2))])"#,
    )
    .unwrap_err();
    assert_eq!(e.field, "generators[0][0] (bodies[0]).restitution");
}

#[test]
fn restitution_combine_is_read_by_name() {
    use kimpact_scene::CombineRule;
    let s = load(
        r#"(dim: 2, steps: 5, law: (dissipation: 0.0), bodies: [(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], restitution: 0.5, restitution_combine: "geometric_mean")])"#,
    )
    .unwrap();
    assert_eq!(s.bodies[0].restitution_combine, CombineRule::GeometricMean);
    let e = load(
        r#"(dim: 2, steps: 5, bodies: [(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], restitution_combine: "mean")])"#,
    )
    .unwrap_err();
    assert!(e.field.starts_with("bodies[0].restitution_combine"), "{e}");
}
