//! Bad input end to end: every invalid scene and bad flag exits with code
//! 2, naming the file and the field, and writes nothing.

mod common;

use common::{kimpact, scene, stderr, temp_dir};

const BALL: &str = r#"{"shape": "ball", "radius": 0.1, "mass": 1, "position": [0, 0]}"#;

fn bad_scenes() -> Vec<(String, String, Vec<&'static str>)> {
    let json = |body: &str| format!(r#"{{"dim": 2, "steps": 10, "bodies": [{body}]}}"#);
    let mut cases: Vec<(String, String, Vec<&'static str>)> = vec![
        ("missing_dim.json".into(), format!(r#"{{"steps": 10, "bodies": [{BALL}]}}"#), vec!["dim", "missing"]),
        ("dim4.json".into(), format!(r#"{{"dim": 4, "steps": 10, "bodies": [{BALL}]}}"#), vec!["dim", "must be 2 or 3, got 4"]),
        ("missing_steps.json".into(), format!(r#"{{"dim": 2, "bodies": [{BALL}]}}"#), vec!["steps", "missing"]),
        ("wrong_type_dim.json".into(), format!("{{\n  \"dim\": \"two\", \"steps\": 10, \"bodies\": [{BALL}]}}"), vec!["dim", ":2:"]),
        ("negative_steps.json".into(), format!(r#"{{"dim": 2, "steps": -5, "bodies": [{BALL}]}}"#), vec!["steps"]),
        ("negative_mass.json".into(), json(r#"{"shape": "ball", "radius": 0.1, "mass": -1, "position": [0, 0]}"#), vec!["bodies[0].mass", "must be > 0"]),
        ("wrong_type_mass.json".into(), json(r#"{"shape": "ball", "radius": 0.1, "mass": "heavy", "position": [0, 0]}"#), vec!["bodies[0].mass", "invalid type"]),
        ("zero_radius.json".into(), json(r#"{"shape": "ball", "radius": 0, "mass": 1, "position": [0, 0]}"#), vec!["bodies[0].radius", "must be > 0, got 0"]),
        ("nan_radius.toml".into(), "dim = 2\nsteps = 10\n[[bodies]]\nshape = \"ball\"\nradius = nan\nmass = 1.0\nposition = [0.0, 0.0]\n".into(), vec!["bodies[0].radius", "finite"]),
        ("nan_velocity.ron".into(), "(dim: 2, steps: 10, bodies: [(shape: \"ball\", radius: 0.1, mass: 1.0, position: [0.0, 0.0], velocity: [NaN, 0.0])])".into(), vec!["bodies[0].velocity[0]", "finite"]),
        ("inf_gravity.toml".into(), "dim = 2\nsteps = 10\ngravity = [0.0, -inf]\n[[bodies]]\nshape = \"ball\"\nradius = 0.1\nmass = 1.0\nposition = [0.0, 0.0]\n".into(), vec!["gravity[1]", "finite"]),
        ("negative_dissipation.json".into(), format!(r#"{{"dim": 2, "steps": 10, "law": {{"dissipation": -0.1}}, "bodies": [{BALL}]}}"#), vec!["law.dissipation", ">= 0"]),
        ("negative_wall_dissipation.json".into(), format!(r#"{{"dim": 2, "steps": 10, "law": {{"wall_dissipation": -1}}, "bodies": [{BALL}]}}"#), vec!["law.wall_dissipation"]),
        ("bad_fixed_partner.json".into(), format!(r#"{{"dim": 2, "steps": 10, "law": {{"fixed_partner": "infinite"}}, "bodies": [{BALL}]}}"#), vec!["law.fixed_partner"]),
        ("unknown_mode.json".into(), format!(r#"{{"dim": 2, "steps": 10, "mode": "fast", "bodies": [{BALL}]}}"#), vec!["mode", "unknown mode \"fast\""]),
        ("bad_precision.json".into(), format!(r#"{{"dim": 2, "steps": 10, "precision": "f16", "bodies": [{BALL}]}}"#), vec!["precision"]),
        ("zero_dt.json".into(), format!(r#"{{"dim": 2, "steps": 10, "dt": 0, "bodies": [{BALL}]}}"#), vec!["dt", "must be > 0"]),
        ("negative_rebound_cutoff.json".into(), format!(r#"{{"dim": 2, "steps": 10, "rebound_cutoff": -0.5, "bodies": [{BALL}]}}"#), vec!["rebound_cutoff", "must be >= 0"]),
        ("position_3_in_2d.json".into(), json(r#"{"shape": "ball", "radius": 0.1, "mass": 1, "position": [0, 0, 0]}"#), vec!["bodies[0].position", "must have 2 components"]),
        ("gravity_3_in_2d.json".into(), format!(r#"{{"dim": 2, "steps": 10, "gravity": [0, -9.81, 0], "bodies": [{BALL}]}}"#), vec!["gravity", "must have 2 components"]),
        ("half_extents_2_in_3d.json".into(), r#"{"dim": 3, "steps": 10, "bodies": [{"shape": "box", "half_extents": [1, 1], "mass": 1, "position": [0, 0, 0]}]}"#.into(), vec!["bodies[0].half_extents", "3 components"]),
        ("unknown_top_key.json".into(), format!(r#"{{"dim": 2, "steps": 10, "gravty": [0, 1], "bodies": [{BALL}]}}"#), vec!["gravty", "unknown field"]),
        ("unknown_body_key.ron".into(), "(dim: 2, steps: 10, bodies: [(shape: \"ball\", radus: 0.1, mass: 1.0, position: [0.0, 0.0])])".into(), vec!["bodies[0]", "radus"]),
        ("unknown_shape.json".into(), json(r#"{"shape": "cube", "radius": 0.1, "mass": 1, "position": [0, 0]}"#), vec!["bodies[0].shape", "cube"]),
        ("box_without_half_extents.json".into(), json(r#"{"shape": "box", "mass": 1, "position": [0, 0]}"#), vec!["bodies[0].half_extents", "missing"]),
        ("ball_without_mass.json".into(), json(r#"{"shape": "ball", "radius": 0.1, "position": [0, 0]}"#), vec!["bodies[0].mass", "missing"]),
        ("missing_position.json".into(), json(r#"{"shape": "ball", "radius": 0.1, "mass": 1}"#), vec!["bodies[0].position", "missing"]),
        ("overlap.json".into(), json(&format!(r#"{BALL}, {{"shape": "ball", "radius": 0.1, "mass": 1, "position": [0.15, 0]}}"#)), vec!["bodies[1].position", "overlaps bodies[0]"]),
        ("unknown_effect.json".into(), format!(r#"{{"dim": 2, "steps": 10, "effects": ["wind"], "bodies": [{BALL}]}}"#), vec!["effects[0]", "wind"]),
        (
            "fixed_without_fixed_walls.json".into(),
            json(&format!(r#"{BALL}, {{"shape": "box", "half_extents": [1, 0.1], "position": [0, -1], "fixed": true}}"#)).replace(r#""steps": 10,"#, r#""steps": 10, "effects": [],"#),
            vec!["effects", "fixed_walls"],
        ),
        ("law_on_fixed.json".into(), json(&format!(r#"{BALL}, {{"shape": "ball", "radius": 0.1, "position": [1, 0], "fixed": true, "law": true}}"#)), vec!["bodies[1].law"]),
        ("mass_on_fixed.json".into(), json(&format!(r#"{BALL}, {{"shape": "ball", "radius": 0.1, "mass": 2, "position": [1, 0], "fixed": true}}"#)), vec!["bodies[1].mass"]),
        ("no_bodies.json".into(), r#"{"dim": 2, "steps": 10, "bodies": []}"#.into(), vec!["bodies"]),
        ("generator_count.json".into(), r#"{"dim": 2, "steps": 10, "generators": [{"origin": [0, 0], "count": [2], "spacing": [1, 1], "body": {"shape": "ball", "radius": 0.1, "mass": 1}}]}"#.into(), vec!["generators[0].count"]),
        ("generator_position.json".into(), r#"{"dim": 2, "steps": 10, "generators": [{"origin": [0, 0], "count": [2, 2], "spacing": [1, 1], "body": {"shape": "ball", "radius": 0.1, "mass": 1, "position": [0, 0]}}]}"#.into(), vec!["generators[0].body.position"]),
        ("syntax.json".into(), "{\"dim\": 2,\n \"steps\": 10,,\n}".into(), vec![":2:"]),
        ("syntax.ron".into(), "(dim: 2, steps: 10, bodies: [\n(shape: \"ball\" radius: 0.1)])".into(), vec![":2:"]),
        ("syntax.toml".into(), "dim = 2\nsteps = = 10\n".into(), vec![":2:"]),
        ("scene.yaml".into(), "dim: 2".into(), vec!["scene format"]),
        ("bad_view_axes.json".into(), format!(r#"{{"dim": 2, "steps": 10, "view": {{"axes": "xz"}}, "bodies": [{BALL}]}}"#), vec!["view.axes"]),
        // Materials: names, constants and combine rules, in every format.
        ("unknown_material.json".into(), format!(r#"{{"dim": 2, "steps": 10, "materials": {{"rubber": {{"dissipation": 0.1}}, "steel": {{}}}}, "bodies": [{}]}}"#, BALL.replace('}', r#", "material": "rubbr"}"#)), vec!["bodies[0].material", r#"unknown material "rubbr""#, r#""rubber", "steel""#]),
        ("material_without_materials.ron".into(), "(dim: 2, steps: 10, bodies: [(shape: \"ball\", radius: 0.1, mass: 1.0, position: [0.0, 0.0], material: \"rubber\")])".into(), vec!["bodies[0].material", "defines no `materials`"]),
        ("negative_material_dissipation.toml".into(), "dim = 2\nsteps = 10\n[materials.rubber]\ndissipation = -0.1\n[[bodies]]\nshape = \"ball\"\nradius = 0.1\nmass = 1.0\nposition = [0.0, 0.0]\nmaterial = \"rubber\"\n".into(), vec!["materials.rubber.dissipation", "must be finite and >= 0, got -0.1"]),
        ("nan_material_wall_dissipation.ron".into(), "(dim: 2, steps: 10, materials: {\"rubber\": (wall_dissipation: NaN)}, bodies: [(shape: \"ball\", radius: 0.1, mass: 1.0, position: [0.0, 0.0], material: \"rubber\")])".into(), vec!["materials.rubber.wall_dissipation", "finite"]),
        ("bad_combine_rule.json".into(), format!(r#"{{"dim": 2, "steps": 10, "materials": {{"rubber": {{"combine": "sum"}}}}, "bodies": [{BALL}]}}"#), vec!["materials.rubber.combine", "sum", "geometric_mean"]),
        ("bad_combine_rule.toml".into(), "dim = 2\nsteps = 10\n[materials.rubber]\ncombine = 3\n[[bodies]]\nshape = \"ball\"\nradius = 0.1\nmass = 1.0\nposition = [0.0, 0.0]\n".into(), vec!["materials.rubber.combine", ":4:"]),
        ("unknown_material_key.json".into(), format!(r#"{{"dim": 2, "steps": 10, "materials": {{"rubber": {{"dissipaton": 0.1}}}}, "bodies": [{BALL}]}}"#), vec!["materials.rubber", "dissipaton"]),
        ("material_on_a_non_law_body.json".into(), json(r#"{"shape": "ball", "radius": 0.1, "mass": 1, "position": [0, 0], "law": false, "material": "rubber"}"#).replace(r#""steps": 10,"#, r#""steps": 10, "materials": {"rubber": {}},"#), vec!["bodies[0].material", "does not follow the law"]),
        ("generator_unknown_material.json".into(), r#"{"dim": 2, "steps": 10, "materials": {"rubber": {}}, "generators": [{"origin": [0, 0], "count": [2, 2], "spacing": [1, 1], "body": {"shape": "ball", "radius": 0.1, "mass": 1}, "materials": ["rubber", "wood"]}]}"#.into(), vec!["generators[0].materials[1]", r#"unknown material "wood""#]),
        // Constants f32 cannot hold are errors in an f32 scene (they would
        // reach the adapter as infinity), not a panic.
        ("f32_law_overflow.json".into(), format!(r#"{{"dim": 2, "steps": 10, "law": {{"dissipation": 1e300}}, "bodies": [{BALL}]}}"#), vec!["law.dissipation", "beyond f32's range", "\"f64\""]),
        ("f32_material_overflow.json".into(), format!(r#"{{"dim": 2, "steps": 10, "materials": {{"rubber": {{"dissipation": 0.1, "wall_dissipation": 1e39}}}}, "bodies": [{BALL}]}}"#), vec!["materials.rubber.wall_dissipation", "beyond f32's range"]),
    ];
    cases.sort_by(|a, b| a.0.cmp(&b.0));
    cases
}

#[test]
fn bad_scenes_exit_2_naming_the_file_and_field_and_write_nothing() {
    let dir = temp_dir("bad");
    let cases = bad_scenes();
    assert!(cases.len() >= 20);
    for (file, text, expect) in cases {
        let path = dir.join(&file);
        std::fs::write(&path, &text).unwrap();
        let out = dir.join(format!("{file}.report.json"));
        let o = kimpact(&[
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{file}: exit code, stderr: {err}");
        assert!(
            err.contains(&file),
            "{file}: the message must name the file: {err}"
        );
        for e in expect {
            assert!(
                err.contains(e),
                "{file}: the message must contain {e:?}: {err}"
            );
        }
        assert!(!out.exists(), "{file}: no report may be written");
        // compare writes nothing either.
        let cdir = dir.join(format!("{file}.compare"));
        let o = kimpact(&[
            "compare",
            path.to_str().unwrap(),
            "--out",
            cdir.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{file}: compare exit code");
        assert!(
            !cdir.exists(),
            "{file}: compare must not create its directory"
        );
    }
    let missing = dir.join("missing.json");
    let o = kimpact(&["run", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing.json") && stderr(&o).contains("cannot read"));
}

#[test]
fn an_existing_output_survives_a_bad_scene() {
    let dir = temp_dir("keep");
    let out = dir.join("report.json");
    std::fs::write(&out, "old report").unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(&bad, r#"{"dim": 5}"#).unwrap();
    let o = kimpact(&["run", bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old report");
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn bad_flags_exit_2() {
    let cradle = scene("cradle2d.ron");
    let c = cradle.to_str().unwrap();
    for args in [
        vec!["run", c, "--mode", "fast"],
        vec!["run", c, "--steps", "0"],
        vec!["run", c, "--steps", "many"],
        vec!["run", c, "--bogus"],
        vec!["run"],
        vec!["frobnicate"],
        vec![],
        vec!["run", c, "--out", "/nonexistent-kimpact-dir/report.json"],
    ] {
        let o = kimpact(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    }
    assert_eq!(kimpact(&["--help"]).status.code(), Some(0));
    assert_eq!(kimpact(&["run", "--help"]).status.code(), Some(0));
}
