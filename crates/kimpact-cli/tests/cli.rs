//! The `kimpact` binary end to end: bundled scenes, the report's keys and
//! meaning, determinism, `compare`'s outputs (bad input: `bad_input.rs`).

mod common;

use std::path::{Path, PathBuf};

use serde_json::Value;

use common::{f, kimpact, report, scene, scenes_dir, stderr, temp_dir, vecf};

fn bundled() -> Vec<PathBuf> {
    let mut all: Vec<PathBuf> = std::fs::read_dir(scenes_dir())
        .expect("scenes/")
        .map(|e| e.expect("entry").path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("json" | "ron" | "toml")
            )
        })
        .collect();
    all.sort();
    all
}

#[test]
fn the_bundled_scenes_are_all_there() {
    let names: Vec<String> = bundled()
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    for want in [
        "cradle2d",
        "cradle3d",
        "billiards2d",
        "masses1000_2d",
        "pachinko2d",
        "ballpit2d",
        "ballpit3d",
        "gas2d",
        "gas3d",
        "cooling2d",
    ] {
        assert!(
            names.iter().any(|n| n == want),
            "scenes/{want}.* is missing (have {names:?})"
        );
    }
}

#[test]
fn every_bundled_scene_runs_in_every_mode() {
    for path in bundled() {
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains("description"),
            "{} has no description",
            path.display()
        );
        let p = path.to_str().unwrap();
        for mode in ["native", "restitution", "impulse", "exact"] {
            let r = report(&["run", p, "--mode", mode, "--steps", "3"]);
            assert_eq!(r["mode"], mode);
            assert_eq!(r["steps"], 3);
            let bodies = r["bodies"].as_array().unwrap();
            assert_eq!(
                bodies.len() as u64,
                r["setup"]["body_count"].as_u64().unwrap()
            );
            assert_eq!(
                r["checks"]["non_finite"], 0,
                "{p} {mode}: non-finite bodies"
            );
            if mode == "native" {
                assert_eq!(r["setup"]["marked_bodies"], 0);
                assert_eq!(r["impacts"]["count"], 0);
            }
        }
        let check = kimpact(&["check", p]);
        assert!(check.status.success(), "check {p}: {}", stderr(&check));
    }
}

#[test]
fn ball_pits_have_more_than_a_thousand_balls() {
    for name in ["ballpit2d.ron", "ballpit3d.toml"] {
        let r = report(&[
            "run",
            scene(name).to_str().unwrap(),
            "--mode",
            "native",
            "--steps",
            "1",
        ]);
        let balls = r["bodies"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|b| b["shape"] == "ball" && b["fixed"] == false)
            .count();
        assert!(balls >= 1000, "{name}: {balls} balls");
        let masses: std::collections::BTreeSet<u64> = r["bodies"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|b| b["mass"].as_f64())
            .map(|m| (m * 1e6).round() as u64)
            .collect();
        assert!(
            masses.len() >= 3,
            "{name}: mixed masses expected, got {masses:?}"
        );
    }
}

#[test]
fn report_keys_and_their_meaning() {
    let r = report(&[
        "run",
        scene("cradle2d.ron").to_str().unwrap(),
        "--steps",
        "60",
    ]);
    for key in [
        "scene",
        "dim",
        "precision",
        "mode",
        "steps",
        "dt",
        "bodies",
        "energy",
        "momentum",
        "impacts",
        "timing",
        "effects",
    ] {
        assert!(r.get(key).is_some(), "missing key {key}");
    }
    for key in [
        "kinetic_initial",
        "kinetic_final",
        "potential_initial",
        "potential_final",
    ] {
        assert!(r["energy"][key].is_f64(), "energy.{key}");
    }
    for key in ["count", "clamped", "dissipated"] {
        assert!(r["impacts"].get(key).is_some(), "impacts.{key}");
    }
    for key in ["wall_seconds", "seconds_per_step"] {
        assert!(r["timing"][key].is_f64(), "timing.{key}");
    }
    assert_eq!(r["dim"], 2);
    assert_eq!(r["precision"], "f32");
    assert_eq!(r["mode"], "exact");
    assert!((f(&r["dt"]) - 1.0 / 60.0).abs() < 1e-15);
    let spp = f(&r["timing"]["seconds_per_step"]);
    assert!((spp * 60.0 - f(&r["timing"]["wall_seconds"])).abs() < 1e-9);

    // Energy and momentum agree with the bodies.
    let bodies = r["bodies"].as_array().unwrap();
    let mut kinetic = 0.0;
    let mut p_all = [0.0; 2];
    let mut p_law = [0.0; 2];
    for b in bodies {
        let m = f(&b["mass"]);
        let v = vecf(&b["velocity"]);
        assert_eq!(vecf(&b["position"]).len(), 2);
        kinetic += 0.5 * m * (v[0] * v[0] + v[1] * v[1]);
        for k in 0..2 {
            p_all[k] += m * v[k];
            if b["law"] == true {
                p_law[k] += m * v[k];
            }
        }
    }
    assert!(
        (kinetic - f(&r["energy"]["kinetic_final"])).abs() < 1e-9,
        "kinetic energy {kinetic} vs {}",
        r["energy"]["kinetic_final"]
    );
    let fin = &r["momentum"]["final"];
    for k in 0..2 {
        assert!((p_all[k] - vecf(&fin["all"])[k]).abs() < 1e-9);
        assert!((p_law[k] - vecf(&fin["law"])[k]).abs() < 1e-9);
    }
    // The initial values: ball 0 at 1 m/s, mass 1.
    assert!((f(&r["energy"]["kinetic_initial"]) - 0.5).abs() < 1e-6);
    assert_eq!(vecf(&r["momentum"]["initial"]["all"]), vec![1.0, 0.0]);
    assert_eq!(f(&r["energy"]["potential_initial"]), 0.0);
    // The elastic law conserves energy and momentum in the cradle, and the
    // last ball leaves alone.
    assert!((f(&r["energy"]["kinetic_final"]) - 0.5).abs() < 1e-5);
    assert!((vecf(&fin["all"])[0] - 1.0).abs() < 1e-5);
    assert!(r["impacts"]["count"].as_u64().unwrap() >= 4);
    assert_eq!(r["impacts"]["clamped"], 0);
    let last = vecf(&bodies[4]["velocity"]);
    assert!((last[0] - 1.0).abs() < 1e-4, "last ball {last:?}");
    for b in &bodies[..4] {
        assert!(vecf(&b["velocity"])[0].abs() < 1e-4);
    }
}

#[test]
fn potential_energy_follows_the_bodies() {
    let r = report(&[
        "run",
        scene("pachinko2d.toml").to_str().unwrap(),
        "--steps",
        "20",
        "--mode",
        "native",
    ]);
    let mut potential = 0.0;
    for b in r["bodies"].as_array().unwrap() {
        if let Some(m) = b["mass"].as_f64() {
            potential += m * 9.81 * vecf(&b["position"])[1];
        }
    }
    let reported = f(&r["energy"]["potential_final"]);
    assert!(
        (potential - reported).abs() < 1e-5 * potential.abs().max(1.0),
        "{potential} vs {reported}"
    );
    assert!(
        reported < f(&r["energy"]["potential_initial"]),
        "the marbles fall"
    );
    let effects: Vec<&str> = r["effects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_str().unwrap())
        .collect();
    assert_eq!(effects, ["gravity", "dissipation", "fixed_walls"]);
}

fn without_timing(mut v: Value) -> Value {
    v.as_object_mut().unwrap().remove("timing");
    v
}

#[test]
fn reports_are_deterministic_apart_from_timing() {
    for (name, mode) in [
        ("billiards2d.ron", "exact"),
        ("gas3d.json", "impulse"),
        ("pachinko2d.toml", "restitution"),
        ("cradle2d.ron", "native"),
    ] {
        let p = scene(name);
        let a = report(&["run", p.to_str().unwrap(), "--mode", mode, "--steps", "40"]);
        let b = report(&["run", p.to_str().unwrap(), "--mode", mode, "--steps", "40"]);
        assert_eq!(without_timing(a), without_timing(b), "{name} {mode}");
    }
}

#[test]
fn run_writes_the_report_atomically() {
    let dir = temp_dir("run-out");
    let out = dir.join("report.json");
    let o = kimpact(&[
        "run",
        scene("cradle3d.json").to_str().unwrap(),
        "--steps",
        "5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.is_empty(), "nothing on stdout with --out");
    let r: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(r["dim"], 3);
    assert_eq!(vecf(&r["bodies"][0]["position"]).len(), 3);
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["report.json"], "no temporary file left");
}

#[test]
fn compare_writes_reports_summary_plots_and_pictures() {
    let dir = temp_dir("compare").join("cradle");
    let o = kimpact(&[
        "compare",
        scene("cradle2d.ron").to_str().unwrap(),
        "--steps",
        "30",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for mode in ["native", "restitution", "impulse", "exact"] {
        let r: Value = serde_json::from_slice(
            &std::fs::read(dir.join(format!("report-{mode}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(r["mode"], mode);
        assert_eq!(r["steps"], 30);
        assert!(dir.join("frames").join(format!("{mode}-0.png")).is_file());
    }
    for png in ["energy.png", "momentum.png", "strip.png"] {
        let bytes = std::fs::read(dir.join(png)).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{png}");
    }
    for svg in ["energy.svg", "momentum.svg"] {
        let text = std::fs::read_to_string(dir.join(svg)).unwrap();
        assert!(
            text.starts_with("<svg") && text.contains("exact") && text.contains("native"),
            "{svg}"
        );
    }
    let summary = std::fs::read_to_string(dir.join("summary.md")).unwrap();
    for mode in [
        "| native |",
        "| restitution |",
        "| impulse |",
        "| exact |",
        "s/step",
        "kinetic",
    ] {
        assert!(summary.contains(mode), "summary lacks {mode}");
    }
}

/// Black pixels (every channel below 60: text and frame, not the plotted
/// lines, whose darkest colour is native's grey 90) of a decoded PNG within
/// the rectangle `x0..x1` × `y0..y1`.
fn black_pixels(png: &tiny_skia::Pixmap, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> usize {
    let mut n = 0;
    for y in y0..y1.min(png.height()) {
        for x in x0..x1.min(png.width()) {
            let p = png.pixel(x, y).expect("inside the image");
            if p.red() < 60 && p.green() < 60 && p.blue() < 60 {
                n += 1;
            }
        }
    }
    n
}

/// Black pixels where a plot's title, x axis label and y axis label (with
/// the tick labels next to them) go. PNG plots without text have none
/// there: their frame ran at 60..880 × 20..460 px, and only the frame is
/// black.
fn text_pixels(png: &[u8]) -> [(&'static str, usize); 3] {
    let png = tiny_skia::Pixmap::decode_png(png).expect("a PNG");
    let (w, h) = (png.width(), png.height());
    assert_eq!((w, h), (900, 500));
    [
        ("title", black_pixels(&png, (w / 4, 3 * w / 4), (24, 45))),
        ("x label", black_pixels(&png, (w / 4, 3 * w / 4), (465, h))),
        ("y label", black_pixels(&png, (0, 55), (h / 4, 3 * h / 4))),
    ]
}

/// The PNG plots carry their text (title, axis labels, tick labels,
/// legend), drawn from the bundled font.
#[test]
fn compare_png_plots_carry_their_text() {
    let dir = temp_dir("compare-text");
    let o = kimpact(&[
        "compare",
        scene("cradle2d.ron").to_str().unwrap(),
        "--steps",
        "30",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["energy.png", "momentum.png"] {
        for (what, n) in text_pixels(&std::fs::read(dir.join(name)).unwrap()) {
            // Without text: 0 in each place (at least 47 with it).
            assert!(n >= 20, "{name}: {n} black pixels where the {what} goes");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn compare_draws_3d_scenes() {
    let dir = temp_dir("compare3d");
    let o = kimpact(&[
        "compare",
        scene("gas3d.json").to_str().unwrap(),
        "--steps",
        "4",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("strip.png").is_file());
    assert!(dir.join("frames/exact-0.png").is_file());
}

#[test]
fn effects_decide_what_is_built() {
    let dir = temp_dir("effects");
    let path = dir.join("s.json");
    // Gravity and friction given but not called for; a box that does not
    // follow the law, and one that does (every moving body does unless it
    // says `law: false`).
    std::fs::write(
        &path,
        r#"{"dim": 2, "steps": 10, "gravity": [0, -9.81], "effects": [],
            "bodies": [
              {"shape": "ball", "radius": 0.1, "mass": 1, "position": [0, 0], "velocity": [1, 0], "friction": 0.5},
              {"shape": "box", "half_extents": [0.1, 0.1], "mass": 2, "position": [1, 0], "law": false},
              {"shape": "box", "half_extents": [0.1, 0.1], "mass": 2, "position": [2, 0]}
            ]}"#,
    )
    .unwrap();
    let o = kimpact(&["run", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("gravity: ignored"), "{}", stderr(&o));
    let r: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(r["effects"].as_array().unwrap().len(), 0);
    assert_eq!(vecf(&r["setup"]["gravity"]), vec![0.0, 0.0]);
    assert_eq!(
        r["setup"]["marked_bodies"], 2,
        "the ball and the second box follow the law"
    );
    assert_eq!(r["setup"]["ccd_bodies"], 0, "slow bodies get no CCD");
    assert_eq!(r["bodies"][1]["law"], false);
    assert_eq!(r["bodies"][2]["law"], true);
    assert_eq!(
        vecf(&r["bodies"][0]["velocity"])[1],
        0.0,
        "no gravity acted"
    );
    // The billiards break gets CCD on its balls.
    let r = report(&[
        "run",
        scene("billiards2d.ron").to_str().unwrap(),
        "--steps",
        "1",
    ]);
    assert_eq!(r["setup"]["ccd_bodies"], 16);
}

#[test]
fn no_progress_bar_without_a_terminal() {
    let o = kimpact(&[
        "run",
        scene("cradle2d.ron").to_str().unwrap(),
        "--steps",
        "10",
    ]);
    assert!(o.status.success());
    assert!(stderr(&o).is_empty(), "stderr: {}", stderr(&o));
}

/// A regression test for an adapter problem seen while building the CLI
/// (since fixed in the adapter): in `exact` mode a ball meeting a fixed
/// wall at a few m/s did not reflect.
#[test]
fn exact_mode_reflects_a_fast_ball_off_a_wall() {
    let dir = temp_dir("wall");
    let path = dir.join("wall.ron");
    std::fs::write(
        &path,
        r#"(dim: 2, steps: 30, precision: "f64", effects: ["fixed_walls"], bodies: [
            (shape: "ball", radius: 0.028575, mass: 0.17, position: [1.0, 0.0], velocity: [6.0, 0.0], restitution: 1.0, ccd: false),
            (shape: "box", half_extents: [0.05, 0.7], position: [1.32, 0.0], fixed: true, restitution: 1.0),
        ])"#,
    )
    .unwrap();
    let r = report(&["run", path.to_str().unwrap(), "--mode", "exact"]);
    let v = vecf(&r["bodies"][0]["velocity"]);
    assert!((v[0] + 6.0).abs() < 1e-6, "velocity after the wall: {v:?}");
}

#[test]
fn the_documented_example_is_a_valid_scene() {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scenes.md"))
            .unwrap();
    let start = doc.find("```ron\n").expect("a RON example") + "```ron\n".len();
    let end = start + doc[start..].find("```").unwrap();
    let dir = temp_dir("doc");
    let path = dir.join("example.ron");
    std::fs::write(&path, &doc[start..end]).unwrap();
    let r = report(&["run", path.to_str().unwrap(), "--steps", "5"]);
    let effects: Vec<&str> = r["effects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_str().unwrap())
        .collect();
    assert_eq!(
        effects,
        ["gravity", "dissipation", "friction", "spin", "fixed_walls"]
    );
    assert_eq!(r["bodies"].as_array().unwrap().len(), 32);
}

/// The bundled scenes with balls faster than a diameter per step (the
/// billiards break's cue ball at 8 m/s, the 1:1000 scene's light ball at
/// 16 m/s, pachinko's falling marbles), over their whole run: in every
/// mode, including native rapier (CCD against the cushions, soft CCD
/// between moving balls), no contact sinks a ball by its radius (the
/// report's `max_penetration_ratio`, relative to the smaller body's
/// smallest half size; native billiards reached 1.17 without soft CCD) and
/// no ball leaves the walls.
#[test]
fn fast_balls_never_sink_a_radius_into_another_body_in_any_mode() {
    for name in ["billiards2d.ron", "masses1000_2d.json", "pachinko2d.toml"] {
        in_every_mode(&scene(name), None, |mode, r| {
            assert!(
                r["setup"]["ccd_bodies"].as_u64().unwrap() > 0,
                "{name}: fast balls get CCD"
            );
            let ratio = f(&r["checks"]["max_penetration_ratio"]);
            assert!(
                ratio < 1.0,
                "{name} {mode}: a contact sank {ratio} radii deep"
            );
        });
    }
}

/// Run `path` (`steps` of it, or all) in each of the four modes, check that
/// no body left the walls and nothing became non-finite, then `check` the
/// report.
fn in_every_mode(path: &Path, steps: Option<&str>, mut check: impl FnMut(&str, &Value)) {
    let name = path.file_name().unwrap().to_string_lossy();
    for mode in ["native", "restitution", "impulse", "exact"] {
        let mut args = vec!["run", path.to_str().unwrap(), "--mode", mode];
        if let Some(n) = steps {
            args.extend(["--steps", n]);
        }
        let r = report(&args);
        let escaped = &r["checks"]["escaped"];
        assert!(
            escaped.is_null() || escaped == 0,
            "{name} {mode}: {escaped} bodies escaped"
        );
        assert_eq!(r["checks"]["non_finite"], 0, "{name} {mode}");
        check(mode, &r);
    }
}

/// Native rapier in the gas scenes: 1 cm disks closing at up to 1 m/s, more
/// than a radius per step. With rapier's contact recycling such a pair met
/// unseen (1.89 radii deep in `gas2d`, 1.23 in `cooling2d` within 120
/// steps); the CLI turns recycling off where soft CCD needs it.
#[test]
fn native_gas_disks_never_sink_a_radius_into_each_other() {
    for name in ["gas2d.toml", "cooling2d.ron", "gas3d.json"] {
        let path = scene(name);
        let r = report(&[
            "run",
            path.to_str().unwrap(),
            "--mode",
            "native",
            "--steps",
            "120",
        ]);
        let ratio = f(&r["checks"]["max_penetration_ratio"]);
        assert!(ratio < 1.0, "{name}: a contact sank {ratio} radii deep");
        assert_eq!(r["checks"]["escaped"], 0, "{name}");
    }
}

#[test]
fn exact_mode_counts_the_99_impacts_of_the_1_to_1000_scene() {
    // floor(π √1000) = 99 impacts for an elastic heavy ball pushing a light
    // one against a wall; the light ball reaches 16 m/s and needs CCD.
    let r = report(&[
        "run",
        scene("masses1000_2d.json").to_str().unwrap(),
        "--mode",
        "exact",
    ]);
    assert_eq!(
        r["setup"]["ccd_bodies"], 1,
        "only the light ball can get fast"
    );
    assert_eq!(r["impacts"]["count"], 99);
    assert!((f(&r["energy"]["kinetic_final"]) - 0.125).abs() < 1e-9);
    let light = vecf(&r["bodies"][1]["position"]);
    assert!(
        light[0] > 0.0,
        "the light ball stays on its side of the wall: {light:?}"
    );
}

/// No ball passes through another (`checks.crossings`, every pair of balls
/// checked on the straight paths of each step) and none leaves the walls, in
/// any bundled scene and any mode. The pits run through the landing of every
/// row (1.25 s of the 2D pit at 120 Hz, where at 60 Hz rapier's solver drove
/// 23 balls through others in native mode and one in impulse mode; 1.5 s of
/// the 3D pit); the other scenes run their full length.
#[test]
fn no_ball_passes_through_another_in_any_mode() {
    for path in bundled() {
        let name = path.file_name().unwrap().to_str().unwrap().to_owned();
        let steps = match name.as_str() {
            "ballpit2d.ron" => Some("150"),
            "ballpit3d.toml" => Some("90"),
            _ => None,
        };
        in_every_mode(&path, steps, |mode, r| {
            assert_eq!(r["checks"]["crossings"], 0, "{name} {mode}");
        });
    }
}

/// The crossing check sees a ball that jumps clean through another between
/// two steps (rapier never sees the pair: no CCD, 1 m per step), and not a
/// ball that passes beside a peg.
#[test]
fn a_ball_jumping_through_another_is_a_crossing() {
    let dir = temp_dir("crossing");
    for (offset, expected) in [(0.0, 1), (0.15, 0)] {
        let path = dir.join(format!("through-{offset}.ron"));
        std::fs::write(
            &path,
            format!(
                r#"(dim: 2, steps: 2, dt: 0.02, bodies: [
                    (shape: "ball", radius: 0.05, mass: 1.0, position: [-0.5, {offset}], velocity: [50.0, 0.0], ccd: false),
                    (shape: "ball", radius: 0.05, mass: 1.0, position: [0.0, 0.0], ccd: false),
                ])"#
            ),
        )
        .unwrap();
        let r = report(&["run", path.to_str().unwrap(), "--mode", "native"]);
        let x = vecf(&r["bodies"][0]["position"]);
        assert!(x[0] > 0.4, "the ball flew on: {x:?}");
        assert_eq!(r["checks"]["crossings"], expected, "offset {offset}");
    }
}
