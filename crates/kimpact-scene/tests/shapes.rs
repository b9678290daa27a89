//! Shapes and orientations in scene files: capsules and convex shapes,
//! `rotation` and `angular_velocity` in their 2D and 3D forms, `law` on
//! every moving body, and what derives from them (spin, bounding boxes,
//! overlaps, joints on turned bodies).

use kimpact_scene::{Effect, Scene, SceneError, Shape, parse, rotate, validate};

fn load(text: &str) -> Result<Scene, SceneError> {
    validate(parse(text, "ron")?, "s.ron", "s")
}

fn one(dim: usize, body: &str) -> Result<Scene, SceneError> {
    load(&format!("(dim: {dim}, steps: 5, bodies: [{body}])"))
}

#[test]
fn every_shape_is_read_with_its_keys() {
    let s = one(
        3,
        r#"(shape: "capsule", half_height: 0.5, radius: 0.2, mass: 1.0, position: [0.0, 0.0, 0.0]),
           (shape: "convex", points: [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], mass: 1.0, position: [3.0, 0.0, 0.0])"#,
    )
    .unwrap();
    assert_eq!(
        s.bodies[0].shape,
        Shape::Capsule {
            half_height: 0.5,
            radius: 0.2
        }
    );
    assert!(matches!(&s.bodies[1].shape, Shape::Convex { points } if points.len() == 4));
    // Every moving body follows the law unless it says otherwise.
    assert!(s.bodies.iter().all(|b| b.law));
    // Neither is a ball: something could turn them.
    assert!(s.active(Effect::Spin));
}

#[test]
fn shape_keys_are_checked() {
    let cases: &[(usize, &str, &str, &str)] = &[
        (
            2,
            r#"shape: "capsule", radius: 0.2"#,
            "bodies[0].half_height",
            "missing: a capsule needs `half_height`",
        ),
        (
            2,
            r#"shape: "capsule", half_height: 0.5"#,
            "bodies[0].radius",
            "missing",
        ),
        (
            2,
            r#"shape: "capsule", half_height: 0.0, radius: 0.2"#,
            "bodies[0].half_height",
            "must be > 0",
        ),
        (
            2,
            r#"shape: "capsule", half_height: 0.5, radius: 0.2, half_extents: [1.0, 1.0]"#,
            "bodies[0].half_extents",
            "a capsule has `half_height` and `radius`",
        ),
        (
            2,
            r#"shape: "ball", radius: 0.2, points: [[0.0, 0.0]]"#,
            "bodies[0].points",
            "a ball has `radius`, not `points`",
        ),
        (
            2,
            r#"shape: "box", radius: 0.2"#,
            "bodies[0].radius",
            "a box has `half_extents`",
        ),
        (2, r#"shape: "convex""#, "bodies[0].points", "missing"),
        (
            2,
            r#"shape: "convex", points: [[0.0, 0.0], [1.0, 0.0]]"#,
            "bodies[0].points",
            "3 to 1000 points",
        ),
        (
            2,
            r#"shape: "convex", points: [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]"#,
            "bodies[0].points",
            "lie on a line",
        ),
        (
            3,
            r#"shape: "convex", points: [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]"#,
            "bodies[0].points",
            "lie on a plane",
        ),
        (
            2,
            r#"shape: "convex", points: [[0.0, 0.0], [1.0, 0.0], [0.0, NaN]]"#,
            "bodies[0].points[2][1]",
            "finite",
        ),
        (
            2,
            r#"shape: "convex", points: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0, 2.0]]"#,
            "bodies[0].points[2]",
            "2 components",
        ),
        (
            2,
            r#"shape: "cone", radius: 1.0"#,
            "bodies[0].shape",
            "\"capsule\" or \"convex\"",
        ),
    ];
    for (dim, keys, field, words) in cases {
        let pos = if *dim == 2 {
            "[0.0, 0.0]"
        } else {
            "[0.0, 0.0, 0.0]"
        };
        let e = one(*dim, &format!("({keys}, mass: 1.0, position: {pos})")).expect_err(keys);
        assert_eq!(e.field, *field, "{keys}: {e}");
        assert!(e.message.contains(words), "{keys}: {e} lacks {words:?}");
    }
}

#[test]
fn rotations_and_angular_velocities_take_their_dimension_s_form() {
    let s = one(
        2,
        r#"(shape: "box", half_extents: [0.5, 0.1], mass: 1.0, position: [0.0, 0.0], rotation: 0.5, angular_velocity: -2)"#,
    )
    .unwrap();
    assert_eq!(
        (
            s.bodies[0].rotation.clone(),
            s.bodies[0].angular_velocity.clone()
        ),
        (vec![0.5], vec![-2.0])
    );
    let s = one(
        3,
        r#"(shape: "box", half_extents: [0.5, 0.1, 0.1], mass: 1.0, position: [0.0, 0.0, 0.0], rotation: [0.0, 0.0, 0.5], angular_velocity: [1.0, 2.0, 3.0])"#,
    )
    .unwrap();
    assert_eq!(s.bodies[0].rotation, vec![0.0, 0.0, 0.5]);
    assert_eq!(s.bodies[0].angular_velocity, vec![1.0, 2.0, 3.0]);
    // Unwritten: zero.
    let s = one(
        3,
        r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0, 0.0])"#,
    )
    .unwrap();
    assert_eq!(s.bodies[0].rotation, vec![0.0; 3]);
    let cases: &[(usize, &str, &str, &str)] = &[
        (
            2,
            "rotation: [0.0, 0.0, 1.0]",
            "bodies[0].rotation",
            "a 2D rotation is a number",
        ),
        (3, "rotation: 1.0", "bodies[0].rotation", "axis times angle"),
        (
            3,
            "angular_velocity: [1.0, 2.0]",
            "bodies[0].angular_velocity",
            "3 components",
        ),
        (
            2,
            "angular_velocity: inf",
            "bodies[0].angular_velocity",
            "finite",
        ),
        (
            2,
            r#"angular_velocity: "fast""#,
            "bodies[0].angular_velocity",
            "a number (2D) or a list of 3 numbers (3D)",
        ),
    ];
    for (dim, key, field, words) in cases {
        let pos = if *dim == 2 {
            "[0.0, 0.0]"
        } else {
            "[0.0, 0.0, 0.0]"
        };
        let e = one(
            *dim,
            &format!(r#"(shape: "ball", radius: 0.1, mass: 1.0, position: {pos}, {key})"#),
        )
        .expect_err(key);
        assert!(e.field.starts_with(field), "{key}: {e}");
        assert!(e.to_string().contains(words), "{key}: {e} lacks {words:?}");
    }
    let e = load(
        r#"(dim: 2, steps: 5, bodies: [(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0]),
            (shape: "box", half_extents: [1.0, 0.1], position: [0.0, -1.0], fixed: true, angular_velocity: 1.0)])"#,
    )
    .unwrap_err();
    assert_eq!(e.field, "bodies[1].angular_velocity");
}

#[test]
fn a_spinning_ball_switches_spin_on_unless_effects_leave_it_out() {
    let ball =
        r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.0, 0.0], angular_velocity: 3.0)"#;
    let s = one(2, ball).unwrap();
    assert!(s.active(Effect::Spin));
    let s = load(&format!(
        "(dim: 2, steps: 5, effects: [], bodies: [{ball}])"
    ))
    .unwrap();
    assert!(!s.active(Effect::Spin));
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("angular_velocity: ignored")),
        "{:?}",
        s.warnings
    );
}

/// A box of half extents (1, 0.1) turned a quarter turn stands up: its
/// bounding box is (0.1, 1), and bodies are compared by it.
#[test]
fn turned_bodies_are_compared_by_their_bounding_boxes() {
    let turned = r#"(shape: "box", half_extents: [1.0, 0.1], mass: 1.0, position: [0.0, 0.0], rotation: 1.5707963267948966)"#;
    let s = one(2, turned).unwrap();
    let h = s.bodies[0].half_box(2);
    assert!(
        (h[0] - 0.1).abs() < 1e-12 && (h[1] - 1.0).abs() < 1e-12,
        "{h:?}"
    );
    // A ball 0.5 to the side fits beside the standing box, not beside the
    // lying one.
    let ball = r#"(shape: "ball", radius: 0.1, mass: 1.0, position: [0.5, 0.0])"#;
    assert!(one(2, &format!("{turned}, {ball}")).is_ok());
    let e = one(
        2,
        &format!(
            "{}, {ball}",
            turned.replace(", rotation: 1.5707963267948966", "")
        ),
    )
    .unwrap_err();
    assert_eq!(e.field, "bodies[1].position");
    // A capsule lying across: its bounding box.
    let capsule = r#"(shape: "capsule", half_height: 1.0, radius: 0.1, mass: 1.0, position: [0.0, 0.0], rotation: 1.5707963267948966)"#;
    let s = one(2, capsule).unwrap();
    let h = s.bodies[0].half_box(2);
    assert!(
        (h[0] - 1.1).abs() < 1e-12 && (h[1] - 0.1).abs() < 1e-12,
        "{h:?}"
    );
}

/// A joint's anchors turn with their body; a joint that holds frames
/// together needs its bodies to start turned alike.
#[test]
fn joints_on_turned_bodies() {
    // A rod turned a quarter turn: its local (0, 1) end is at world (-1, 0).
    let rod = r#"(shape: "box", half_extents: [0.05, 1.0], mass: 1.0, position: [0.0, 0.0], rotation: 1.5707963267948966)"#;
    let end = rotate(&[std::f64::consts::FRAC_PI_2], &[0.0, 1.0]);
    assert!((end[0] + 1.0).abs() < 1e-12 && end[1].abs() < 1e-12);
    let ok = load(&format!(
        r#"(dim: 2, steps: 5, bodies: [{rod}], joints: [(kind: "revolute", body1: "world", anchor1: [-1.0, 0.0], body2: 0, anchor2: [0.0, 1.0])])"#
    ));
    assert!(ok.is_ok(), "{ok:?}");
    let e = load(&format!(
        r#"(dim: 2, steps: 5, bodies: [{rod}], joints: [(kind: "revolute", body1: "world", anchor1: [0.0, 1.0], body2: 0, anchor2: [0.0, 1.0])])"#
    ))
    .unwrap_err();
    assert_eq!(e.field, "joints[0].anchor2");
    let e = load(&format!(
        r#"(dim: 2, steps: 5, bodies: [{rod}], joints: [(kind: "fixed", body1: "world", anchor1: [-1.0, 0.0], body2: 0, anchor2: [0.0, 1.0])])"#
    ))
    .unwrap_err();
    assert_eq!(e.field, "joints[0].kind");
    assert!(e.message.contains("start turned differently"), "{e}");
}
