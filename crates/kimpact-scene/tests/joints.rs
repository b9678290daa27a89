//! Joints in scene files: every kind read from every format, and every
//! mistake a typed error naming the joint's index and field.

use kimpact_scene::{JointEnd, JointKind, Scene, SceneError, parse, validate};

fn load(text: &str, format: &str) -> Result<Scene, SceneError> {
    let raw = parse(text, format)?;
    validate(raw, &format!("s.{format}"), "s")
}

/// Two balls 0.3 apart on x, named, one fixed box below; `joints` spliced in.
fn scene(joints: &str) -> String {
    format!(
        r#"(dim: 2, steps: 10, gravity: [0.0, -9.81], bodies: [
            (name: "a", shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0]),
            (name: "b", shape: "ball", radius: 0.1, mass: 1.0, position: [0.3, 0.0]),
            (name: "floor", shape: "box", half_extents: [1.0, 0.1], position: [0.0, -1.0], fixed: true),
        ], joints: [{joints}])"#
    )
}

fn error(joints: &str) -> SceneError {
    load(&scene(joints), "ron").expect_err("an invalid joint")
}

#[test]
fn every_kind_is_read_with_its_keys() {
    let s = load(
        &scene(
            r#"(kind: "fixed", body1: 0, body2: "b", anchor1: [0.15, 0.0], anchor2: [-0.15, 0.0]),
               (kind: "revolute", body1: "world", anchor1: [0.0, 1.0], body2: "a", anchor2: [0.0, 1.0], limits: [-1.0, 1.0]),
               (kind: "prismatic", body1: "floor", anchor1: [0.3, 1.0], body2: 1, axis: [2.0, 0.0], limits: [-0.5, 0.5], contacts_enabled: false),
               (kind: "rope", body1: "world", anchor1: [0.0, 2.0], body2: 0, max_distance: 2.5)"#,
        ),
        "ron",
    )
    .expect("valid joints");
    assert_eq!(s.joints.len(), 4);
    let j = &s.joints;
    assert_eq!(j[0].kind, JointKind::Fixed);
    assert_eq!(
        (j[0].body1, j[0].body2),
        (JointEnd::Body(0), JointEnd::Body(1))
    );
    assert_eq!(j[0].anchor1, vec![0.15, 0.0]);
    assert!(j[0].contacts_enabled, "rapier's default");
    assert_eq!(
        j[1].kind,
        JointKind::Revolute {
            axis: None,
            limits: Some([-1.0, 1.0])
        }
    );
    assert_eq!(j[1].body1, JointEnd::World);
    // The axis is normalised; the fixed floor is a body like any other.
    assert_eq!(
        j[2].kind,
        JointKind::Prismatic {
            axis: vec![1.0, 0.0],
            limits: Some([-0.5, 0.5])
        }
    );
    assert_eq!(j[2].body1, JointEnd::Body(2));
    assert!(!j[2].contacts_enabled);
    assert_eq!(j[3].kind, JointKind::Rope { max_distance: 2.5 });
    // A joint to the world or to a fixed body takes momentum.
    assert!(!s.conserves_momentum());
}

#[test]
fn the_three_formats_read_the_same_joints() {
    let base = r#""dim": 3, "steps": 5, "bodies": [
        {"shape": "ball", "radius": 0.5, "mass": 1, "position": [0, 0, 0]},
        {"shape": "ball", "radius": 0.5, "mass": 1, "position": [2, 0, 0]}]"#;
    let json = format!(
        r#"{{{base}, "joints": [{{"kind": "spherical", "body1": 0, "body2": 1, "anchor1": [1, 0, 0], "anchor2": [-1, 0, 0], "contacts_enabled": false}},
                               {{"kind": "revolute", "body1": "world", "anchor1": [0, 3, 0], "body2": 0, "anchor2": [0, 3, 0], "axis": [0, 0, 3]}}]}}"#
    );
    let toml = r#"dim = 3
steps = 5
[[bodies]]
shape = "ball"
radius = 0.5
mass = 1.0
position = [0.0, 0.0, 0.0]
[[bodies]]
shape = "ball"
radius = 0.5
mass = 1.0
position = [2.0, 0.0, 0.0]
[[joints]]
kind = "spherical"
body1 = 0
body2 = 1
anchor1 = [1.0, 0.0, 0.0]
anchor2 = [-1.0, 0.0, 0.0]
contacts_enabled = false
[[joints]]
kind = "revolute"
body1 = "world"
anchor1 = [0.0, 3.0, 0.0]
body2 = 0
anchor2 = [0.0, 3.0, 0.0]
axis = [0.0, 0.0, 3.0]
"#;
    let ron = r#"(dim: 3, steps: 5, bodies: [
        (shape: "ball", radius: 0.5, mass: 1.0, position: [0.0, 0.0, 0.0]),
        (shape: "ball", radius: 0.5, mass: 1.0, position: [2.0, 0.0, 0.0])],
      joints: [(kind: "spherical", body1: 0, body2: 1, anchor1: [1.0, 0.0, 0.0], anchor2: [-1.0, 0.0, 0.0], contacts_enabled: false),
               (kind: "revolute", body1: "world", anchor1: [0.0, 3.0, 0.0], body2: 0, anchor2: [0.0, 3.0, 0.0], axis: [0.0, 0.0, 3.0])])"#;
    let scenes: Vec<Scene> = [(json.as_str(), "json"), (toml, "toml"), (ron, "ron")]
        .into_iter()
        .map(|(t, f)| load(t, f).unwrap_or_else(|e| panic!("{f}: {e}")))
        .collect();
    for s in &scenes[1..] {
        assert_eq!(s.joints, scenes[0].joints);
    }
    assert_eq!(scenes[0].joints[0].kind, JointKind::Spherical);
    assert_eq!(
        scenes[0].joints[1].kind,
        JointKind::Revolute {
            axis: Some(vec![0.0, 0.0, 1.0]),
            limits: None
        }
    );
    // Two free bodies joined to each other keep their momentum; the second
    // joint holds body 0 to the world.
    assert!(!scenes[0].conserves_momentum());
}

/// Each mistake and the field its error names, with words of the message.
#[test]
fn every_mistake_is_an_error_naming_the_joint_and_field() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            r#"(body1: 0, body2: 1)"#,
            "joints[0].kind",
            &["missing", "\"rope\""],
        ),
        (
            r#"(kind: "hinge", body1: 0, body2: 1)"#,
            "joints[0].kind",
            &["unknown joint kind \"hinge\""],
        ),
        (
            r#"(kind: "spherical", body1: 0, body2: 1, anchor1: [0.15, 0.0], anchor2: [-0.15, 0.0])"#,
            "joints[0].kind",
            &["3D", "\"revolute\""],
        ),
        (
            r#"(kind: "fixed", body2: 1)"#,
            "joints[0].body1",
            &["missing", "\"world\""],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: 7)"#,
            "joints[0].body2",
            &["no body 7", "3 bodies"],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: "c")"#,
            "joints[0].body2",
            &["unknown body \"c\""],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: -1)"#,
            "joints[0].body2",
            &["body index"],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: 0)"#,
            "joints[0].body2",
            &["bodies[0] to itself"],
        ),
        (
            r#"(kind: "fixed", body1: "world", body2: "floor", anchor1: [0.0, -1.0])"#,
            "joints[0].body2",
            &["nothing that moves"],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: 1)"#,
            "joints[0].anchor2",
            &["apart at the start", "same point"],
        ),
        (
            r#"(kind: "revolute", body1: 0, body2: 1, anchor1: [0.15, 0.0], anchor2: [-0.15, 0.0], axis: [0.0, 0.0, 1.0])"#,
            "joints[0].axis",
            &["turns about z"],
        ),
        (
            r#"(kind: "prismatic", body1: 0, body2: 1)"#,
            "joints[0].axis",
            &["missing", "axis"],
        ),
        (
            r#"(kind: "prismatic", body1: 0, body2: 1, axis: [0.0, 0.0])"#,
            "joints[0].axis",
            &["must not be zero"],
        ),
        (
            r#"(kind: "prismatic", body1: 0, body2: 1, axis: [1.0])"#,
            "joints[0].axis",
            &["2 components"],
        ),
        (
            r#"(kind: "prismatic", body1: 0, body2: 1, axis: [0.0, 1.0])"#,
            "joints[0].anchor2",
            &["across the axis"],
        ),
        (
            r#"(kind: "prismatic", body1: 0, body2: 1, axis: [1.0, 0.0], limits: [0.5, -0.5])"#,
            "joints[0].limits",
            &["min <= max"],
        ),
        (
            r#"(kind: "prismatic", body1: 0, body2: 1, axis: [1.0, 0.0], limits: [-0.1, 0.1])"#,
            "joints[0].limits",
            &["outside [-0.1, 0.1]"],
        ),
        (
            r#"(kind: "prismatic", body1: 0, body2: 1, axis: [1.0, 0.0], limits: [0.0, NaN])"#,
            "joints[0].limits[1]",
            &["finite"],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: 1, anchor1: [0.15, 0.0], anchor2: [-0.15, 0.0], limits: [0.0, 1.0])"#,
            "joints[0].limits",
            &["no `limits`"],
        ),
        (
            r#"(kind: "rope", body1: 0, body2: 1)"#,
            "joints[0].max_distance",
            &["missing"],
        ),
        (
            r#"(kind: "rope", body1: 0, body2: 1, max_distance: -1.0)"#,
            "joints[0].max_distance",
            &[">= 0"],
        ),
        (
            r#"(kind: "rope", body1: 0, body2: 1, max_distance: 0.2)"#,
            "joints[0].max_distance",
            &["more than the rope's 0.2"],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: 1, max_distance: 1.0)"#,
            "joints[0].max_distance",
            &["no `max_distance`"],
        ),
        (
            r#"(kind: "fixed", body1: 0, body2: 1, anchor1: [0.15, 0.0, 0.0])"#,
            "joints[0].anchor1",
            &["2 components"],
        ),
        (
            r#"(kind: "rope", body1: 0, body2: 1, max_distance: 1.0, lenght: 1.0)"#,
            "joints[0]",
            &["lenght"],
        ),
    ];
    for (joint, field, words) in cases {
        let e = error(joint);
        let text = e.to_string();
        assert!(
            e.field == *field
                || (e.field.is_empty() && text.contains(field))
                || e.field.starts_with(field),
            "{joint}: field {:?}, wanted {field:?}: {text}",
            e.field
        );
        for w in *words {
            assert!(text.contains(w), "{joint}: {text:?} lacks {w:?}");
        }
    }
    // The second joint is named by its index.
    let e = error(
        r#"(kind: "rope", body1: 0, body2: 1, max_distance: 1.0), (kind: "fixed", body1: 0, body2: "nobody")"#,
    );
    assert_eq!(e.field, "joints[1].body2");
}

#[test]
fn a_name_shared_by_generated_bodies_needs_an_index() {
    let text = r#"(dim: 2, steps: 5,
        generators: [(origin: [0.0, 0.0], count: [3, 1], spacing: [1.0, 1.0], body: (name: "bead", shape: "ball", radius: 0.1, mass: 1.0))],
        joints: [(kind: "rope", body1: "world", body2: "bead", max_distance: 5.0)])"#;
    let e = load(text, "ron").expect_err("ambiguous");
    assert_eq!(e.field, "joints[0].body2");
    assert!(e.message.contains("3 bodies are named \"bead\""), "{e}");
    assert!(e.message.contains("generators[0][0] (bodies[0])"), "{e}");
}

#[test]
fn bodies_joined_with_contacts_disabled_may_overlap() {
    let text = |contacts: bool| {
        format!(
            r#"(dim: 2, steps: 5, bodies: [
                (shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0]),
                (shape: "ball", radius: 0.1, mass: 1.0, position: [0.05, 0.0])],
              joints: [(kind: "fixed", body1: 0, body2: 1, anchor1: [0.05, 0.0], contacts_enabled: {contacts})])"#
        )
    };
    assert!(load(&text(false), "ron").is_ok());
    let e = load(&text(true), "ron").expect_err("overlap");
    assert_eq!(e.field, "bodies[1].position");
    assert!(e.message.contains("overlaps bodies[0]"), "{e}");
}

#[test]
fn joints_switch_spin_on_when_effects_are_derived() {
    use kimpact_scene::Effect;
    let s = load(
        &scene(
            r#"(kind: "rope", body1: "world", anchor1: [0.0, 2.0], body2: 0, max_distance: 2.5)"#,
        ),
        "ron",
    )
    .unwrap();
    assert!(s.active(Effect::Spin));
    let s = load(&scene(""), "ron").unwrap();
    assert!(
        !s.active(Effect::Spin),
        "frictionless balls without joints cannot turn"
    );
}
