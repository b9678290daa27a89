//! Regression tests from fuzzing the scene parser (`fuzz/`, target `scene`;
//! see `docs/reliability-fuzz.md`), and the nastiest inputs it is fed: NUL
//! bytes, invalid UTF-8, deep nesting, huge numbers, NaN and infinities, in
//! every format.
//!
//! The contract: `parse` and `validate` never panic; they return a scene or
//! a typed [`SceneError`] with a non-empty message (and a 1-based location
//! for parse errors); a validated scene holds only finite numbers. The
//! parser is the crate `kimpact-scene`, as in the fuzz target; the command
//! line is checked end to end for the same inputs (exit code 2, no panic).

mod common;

use std::path::Path;
use std::process::Command;

use kimpact_scene as scene;
use scene::{Scene, SceneError};

use common::write;

const FORMATS: [&str; 3] = ["json", "ron", "toml"];

/// Parse and validate `text` as `format`, checking the error contract.
fn load(text: &str, format: &str) -> Result<Scene, SceneError> {
    let file = format!("test.{format}");
    let result = scene::parse(text, format).and_then(|raw| scene::validate(raw, &file, "test"));
    if let Err(e) = &result {
        assert!(!e.message.trim().is_empty(), "empty message: {e:?}");
        assert!(!e.to_string().is_empty());
        if let Some((line, col)) = e.location {
            assert!(line >= 1 && col >= 1, "location not 1-based: {e:?}");
        }
    }
    result
}

fn load_err(text: &str, format: &str) -> SceneError {
    match load(text, format) {
        Ok(s) => panic!("{format}: accepted {text:?} as {s:?}"),
        Err(e) => e,
    }
}

/// `kimpact check FILE`: must fail with exit code 2 and a message, never
/// panic (exit code 101) or crash.
fn check_rejects(path: &Path, expect: &str) {
    let out = Command::new(env!("CARGO_BIN_EXE_kimpact"))
        .arg("check")
        .arg(path)
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{path:?}: {stderr}");
    assert!(stderr.contains(expect), "{path:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

// Found by fuzzing (crash-da39a3ee…, the empty input): serde_json reports
// column 0 at the end of an empty file, and the error said `test.json:1:0`.
// Locations are 1-based.
#[test]
fn json_errors_at_the_start_of_a_line_have_column_1() {
    assert_eq!(load_err("", "json").location, Some((1, 1)));
    assert_eq!(load_err("{\"dim\": 2,\n", "json").location, Some((2, 1)));
    let e = load_err("\n\n", "json");
    assert_eq!(e.location, Some((3, 1)), "{e}");
    // As the command prints it (`load` names the file).
    let path = write("empty.json", b"");
    let e = scene::load(&path).expect_err("empty");
    assert_eq!(
        e.to_string(),
        format!("{}:1:1: EOF while parsing a value", path.display())
    );
}

// Found by running hand-made extreme inputs through the fuzz target: a
// generator's positions (origin + spacing × index) and velocities
// (template + speed × direction) overflowed to infinity from finite keys,
// and the validated scene held them. Now a typed error naming the key.
#[test]
fn generators_that_overflow_are_rejected() {
    let position = r#"{"dim": 2, "steps": 10, "generators": [{"origin": [1e308, 0.0],
        "spacing": [1e308, 1.0], "count": [3, 1],
        "body": {"shape": "ball", "radius": 0.1, "mass": 1.0}}]}"#;
    let e = load_err(position, "json");
    assert_eq!(e.field, "generators[0].spacing", "{e}");
    assert!(
        e.message
            .contains("generators[0][1] (bodies[1]) would be at position[0] = inf"),
        "{e}"
    );
    let velocity = r#"{"dim": 2, "steps": 10, "generators": [{"origin": [0.0, 0.0],
        "spacing": [1.0, 1.0], "count": [2, 1], "speed": 1.7e308,
        "body": {"shape": "ball", "radius": 0.1, "mass": 1.0,
                 "velocity": [1.7e308, 1.7e308]}}]}"#;
    let e = load_err(velocity, "json");
    assert_eq!(e.field, "generators[0].speed", "{e}");
    assert!(e.message.contains("overflows"), "{e}");
    // The same scene one step short of overflowing is valid and finite.
    let fine = position.replace("[3, 1]", "[1, 1]");
    let s = load(&fine, "json").expect("valid");
    assert!(
        s.bodies
            .iter()
            .all(|b| b.position.iter().all(|x| x.is_finite()))
    );
    check_rejects(&write("overflow.json", position.as_bytes()), "overflows");
}

// Found by the fuzzer under AddressSanitizer (timeout-2330769f…, > 10 s):
// the overlap check swept along x and recomputed bounding boxes (with an
// allocation) for every pair, so a valid 8,690-body pit took > 10 s under
// the sanitizer, and a one-line column of N bodies was quadratic (release
// build: N = 20,000 took 11.9 s, the allowed 200,000 about 20 minutes).
#[test]
fn overlap_check_of_large_scenes_is_fast_and_still_exact() {
    // A column of 200,000 touching-free balls along y, one overlap planted
    // at the far end (the last body is moved onto its neighbour).
    let column = |n: u64| {
        format!(
            r#"{{"dim": 2, "steps": 1, "generators": [{{"origin": [0.0, 0.0], "spacing": [1.0, 1.0],
                "count": [1, {n}], "body": {{"shape": "ball", "radius": 0.1, "mass": 1.0}}}}]}}"#
        )
    };
    let start = std::time::Instant::now();
    let s = load(&column(200_000), "json").expect("a valid column");
    assert_eq!(s.bodies.len(), 200_000);
    let with_overlap = column(199_999).replace(
        r#""generators""#,
        r#""bodies": [{"shape": "ball", "radius": 0.1, "mass": 1.0, "position": [0.0, 199998.15]}], "generators""#,
    );
    let e = load_err(&with_overlap, "json");
    assert_eq!(
        e.field, "generators[0][199998] (bodies[199999]).position",
        "{e}"
    );
    assert!(
        e.message.starts_with("overlaps bodies[0] by 5.000e-2"),
        "{e}"
    );
    // The fuzzer's pit: 11 x 79 x 10 balls in a walled box.
    let pit = PIT;
    load(pit, "toml").expect("the pit is valid");
    // About a second here; 20 minutes before. Generous for a loaded debug build.
    let took = start.elapsed().as_secs_f64();
    assert!(took < 60.0, "took {took:.1} s");
}

#[test]
fn nul_bytes_are_parse_errors_in_every_format() {
    for format in FORMATS {
        for text in [
            "\0",
            "{\"dim\": 2\0}",
            "dim = 2\0\n",
            "(dim: 2,\0)",
            "\0\0\0\0",
        ] {
            let e = load_err(text, format);
            assert!(e.location.is_some(), "{format} {text:?}: {e}");
        }
    }
    check_rejects(&write("nul.toml", b"dim = 2\0\nsteps = 1\n"), "nul.toml");
}

#[test]
fn invalid_utf8_is_an_error_not_a_panic() {
    for (name, bytes) in [
        (
            "bad.json",
            &b"{\"dim\": 2, \"description\": \"\xff\xfe\"}"[..],
        ),
        ("bad.ron", &b"(dim: 2, description: \"\xc3\x28\")"[..]),
        (
            "bad.toml",
            &b"dim = 2\ndescription = \"\xed\xa0\x80\"\n"[..],
        ),
    ] {
        let path = write(name, bytes);
        let e = scene::load(&path).expect_err("invalid UTF-8");
        assert!(e.message.contains("cannot read the file"), "{e}");
        check_rejects(&path, "cannot read the file");
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let depth = 100_000;
    let open_close = |o: &str, c: &str| format!("{}{}", o.repeat(depth), c.repeat(depth));
    let cases = [
        ("json", open_close("[", "]")),
        ("json", format!("{{\"gravity\": {}}}", open_close("[", "]"))),
        ("json", open_close("{\"a\":", "}")),
        ("ron", open_close("(", ")")),
        ("ron", format!("(gravity: {})", open_close("[", "]"))),
        ("toml", format!("gravity = {}\n", open_close("[", "]"))),
        (
            "toml",
            format!("law = {}1{}\n", "{a = ".repeat(depth), "}".repeat(depth)),
        ),
    ];
    for (format, text) in &cases {
        let e = load_err(text, format);
        assert!(e.location.is_some(), "{format}: {e}");
    }
    // Also as files, through the binary.
    check_rejects(
        &write("deep.json", open_close("[", "]").as_bytes()),
        "deep.json",
    );
}

#[test]
fn huge_numbers_nan_and_infinities_are_typed_errors() {
    // Integers beyond u64 and u32.
    let huge = format!("1{}", "0".repeat(400));
    for (format, text) in [
        ("json", format!("{{\"dim\": 2, \"steps\": {huge}}}")),
        ("ron", format!("(dim: 2, steps: {huge})")),
        ("toml", format!("dim = 2\nsteps = {huge}\n")),
        ("json", "{\"dim\": 4294967296}".to_owned()),
        ("toml", "dim = -1\n".to_owned()),
    ] {
        let e = load_err(&text, format);
        assert!(e.location.is_some(), "{format}: {e}");
    }
    // Floats that overflow, and the non-finite literals TOML and RON have.
    let body = |x: &str| {
        format!(
            r#"{{"dim": 2, "steps": 1, "bodies": [{{"shape": "ball", "radius": 1.0, "mass": {x}, "position": [0.0, 0.0]}}]}}"#
        )
    };
    let e = load_err(&body("1e400"), "json");
    assert!(e.location.is_some(), "{e}");
    for (format, text, expect) in [
        ("toml", "dim = 2\nsteps = 1\ndt = 1e400\n", "overflowed"),
        (
            "toml",
            "dim = 2\nsteps = 1\ndt = nan\n",
            "must be a finite number, got NaN",
        ),
        (
            "toml",
            "dim = 2\nsteps = 1\ndt = -inf\n",
            "must be a finite number, got -inf",
        ),
        (
            "ron",
            "(dim: 2, steps: 1, dt: NaN)",
            "must be a finite number, got NaN",
        ),
        (
            "ron",
            "(dim: 2, steps: 1, dt: inf)",
            "must be a finite number, got inf",
        ),
        (
            "ron",
            "(dim: 2, steps: 1, dt: 1e400)",
            "must be a finite number, got inf",
        ),
    ] {
        let e = load_err(text, format);
        assert_eq!(e.field, "dt", "{format} {text:?}: {e}");
        assert!(e.message.contains(expect), "{format} {text:?}: {e}");
    }
    let e = load_err(
        "dim = 2\nsteps = 1\n[[bodies]]\nshape = \"ball\"\nradius = 1.0\nmass = 5e-324\nposition = [0.0, nan]\n",
        "toml",
    );
    assert_eq!(e.field, "bodies[0].position[1]", "{e}");
    // A subnormal mass and radius are finite and positive: valid.
    let s = load(&body("5e-324"), "json").expect("a subnormal mass is valid");
    assert_eq!(s.bodies[0].mass, Some(5e-324));
}

#[test]
fn unknown_formats_and_garbage_are_typed_errors() {
    let e = scene::parse("dim = 2", "yaml").expect_err("unknown format");
    assert!(e.message.contains("unknown scene format"), "{e}");
    for format in FORMATS {
        for text in ["", " ", "\u{feff}", "💥", "[[[", "}{", "r#\"", "'''", "#"] {
            let _ = load_err(text, format);
        }
    }
    // Seed scenes stay valid in their own format and fail cleanly in the
    // others.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for entry in std::fs::read_dir(dir).expect("scenes/") {
        let path = entry.expect("entry").path();
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        let text = std::fs::read_to_string(&path).expect("UTF-8");
        for format in FORMATS {
            let r = load(&text, format);
            if format == ext {
                let s = r.unwrap_or_else(|e| panic!("{path:?}: {e}"));
                assert!(
                    s.bodies
                        .iter()
                        .all(|b| { b.position.iter().chain(&b.velocity).all(|x| x.is_finite()) })
                );
            }
        }
    }
}

/// The input of timeout-2330769f… as the fuzzer wrote it (a mutated
/// `ballpit3d.toml`: 11 x 79 x 10 balls in a walled box).
const PIT: &str = r#"# Ball pBit (3D, gravity): 1,100 balls of three masses fall into a walled pit and settle; drawn as an orthograpin a 1 x 1 m pit under gravity, d̃ = 0.05, rapier restitution 0.5."
dim = 3
precision = "f32"
dt = 0.016666666666666666
steps = 180
gravity = [0.0, -9.81, 0.0]
mode = "exact"
effects = ["gravity", "dissipation", "fixed_walls"]

[law]
dissipation = 5.05

[view]
axes = "xy"
times = [0.0, 0.5, 1.0, 3.0]

[[bodies]]
name = "floor"
shape = "box"
half_extents = [0.6, 0.05, 0.6]
position = [0.0, -0.05, 0.0]
fixed = true
restitution = 0.5

[[bodies]]
name = "x- wall"
shape = "box"
half_extents = [0.05, 1.2, 0.6]
position = [-0.55, 1.2, 0.0]
fixed = true
restitution = 0.5

[[bodies]]
name = "x+ wall"
shape = "box"
half_extents = [0.10, 1.2, 0.6]
position = [0.55, 1.2, 0.0]
fixed = true
restitution = 0.5

[[bodies]]
name = "z- wall"
shape = "box"
half_extents = [0.5, 1.2, 0.05]
position = [0.0, 1, -0.55]
fixed = true
restitution = 0.5

[[bodies]]
name = "z+ wall"
shape = "box"
half_extents = [0.5, 1.2, 0.05]
position = [0.0, 1.2, 0.55]
fixed = true
restitution = 0.5

[[generators]]
origin = [-5.45, 0.1, -0.45]
count = [11, 79, 10]
spacing = [0.09, 0.2, 0.1]
speed = 0.2
seed = 4
masses = [0.01, 0.02, 0.04]
body = { shape = "ball", radius = 0.03, restitution = 0.5 }
"#;
