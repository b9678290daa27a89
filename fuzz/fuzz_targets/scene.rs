//! Fuzz target `scene`: arbitrary bytes through the scene parser of the
//! `kimpact` command line, in every format (`json`, `ron`, `toml`), then
//! through the validator.
//!
//! The parser is the crate `kimpact-scene` (the CLI's and the testbed's;
//! its only dependency inside the workspace is the core crate `kimpact`,
//! for `Mode`, `Precision` and `LawParams`), so the target builds without
//! rapier.
//!
//! The input is decoded as the CLI decodes a file (`read_to_string`, which
//! rejects invalid UTF-8 with an error); invalid UTF-8 is also fed lossily
//! so that the parsers still see the rest of the bytes.
//!
//! Asserted, beyond "no panic, no stack overflow, no timeout":
//!
//! - `parse(text, format)` returns `Ok` or a `SceneError` with a non-empty
//!   message and an empty `file`; a location, when given, is 1-based.
//! - `validate(raw, file, name)` returns `Ok` or a `SceneError` naming
//!   `file` with a non-empty message.
//! - A validated scene holds what `docs/scenes.md` promises: `dim` 2 or 3,
//!   `dt` finite and > 0, `steps` in 1..=MAX_STEPS, finite `dim`-vectors
//!   (gravity, every position and velocity), finite positive masses and
//!   sizes, finite non-negative coefficients, at least one moving body, at
//!   most MAX_BODIES bodies, fixed bodies without mass or velocity.
#![no_main]

use libfuzzer_sys::fuzz_target;

use kimpact_scene as scene;
use scene::{MAX_BODIES, MAX_STEPS, Scene, SceneError, Shape};

const FORMATS: [&str; 3] = ["json", "ron", "toml"];

fuzz_target!(|data: &[u8]| {
    let lossy;
    let text = match std::str::from_utf8(data) {
        Ok(t) => t,
        Err(_) => {
            lossy = String::from_utf8_lossy(data);
            &lossy
        }
    };
    for format in FORMATS {
        check(text, format);
    }
});

fn check(text: &str, format: &str) {
    let raw = match scene::parse(text, format) {
        Ok(raw) => raw,
        Err(e) => {
            parse_error(&e, format);
            return;
        }
    };
    let file = format!("fuzz.{format}");
    match scene::validate(raw, &file, "fuzz") {
        Ok(s) => valid_scene(&s, &file),
        Err(e) => {
            assert_eq!(e.file, file, "validate: wrong file in {e:?}");
            assert!(
                !e.message.trim().is_empty(),
                "validate: empty message {e:?}"
            );
            assert!(e.location.is_none(), "validate: location in {e:?}");
            assert!(!e.to_string().is_empty());
        }
    }
}

fn parse_error(e: &SceneError, format: &str) {
    assert!(
        !e.message.trim().is_empty(),
        "parse ({format}): empty message {e:?}"
    );
    assert!(e.file.is_empty(), "parse ({format}): file set in {e:?}");
    if let Some((line, col)) = e.location {
        assert!(line >= 1 && col >= 1, "parse ({format}): location {e:?}");
    }
    assert!(!e.to_string().is_empty());
}

fn finite_vec(v: &[f64], dim: usize, what: &str, s: &Scene) {
    assert_eq!(v.len(), dim, "{what}: wrong length in {s:?}");
    assert!(
        v.iter().all(|x| x.is_finite()),
        "{what}: non-finite {v:?} in a validated scene"
    );
}

fn valid_scene(s: &Scene, file: &str) {
    assert_eq!(s.file, file);
    assert_eq!(s.name, "fuzz");
    assert!(s.dim == 2 || s.dim == 3, "dim {}", s.dim);
    assert!(s.dt.is_finite() && s.dt > 0.0, "dt {}", s.dt);
    assert!((1..=MAX_STEPS).contains(&s.steps), "steps {}", s.steps);
    finite_vec(&s.gravity, s.dim, "gravity", s);
    let law = s.law;
    assert!(law.dissipation.is_finite() && law.dissipation >= 0.0);
    if let Some(w) = law.wall_dissipation {
        assert!(w.is_finite() && w >= 0.0);
    }
    assert!(!s.bodies.is_empty() && s.bodies.len() <= MAX_BODIES);
    assert!(s.bodies.iter().any(|b| !b.fixed), "nothing moves");
    for b in &s.bodies {
        let at = &b.origin;
        finite_vec(&b.position, s.dim, &format!("{at}.position"), s);
        finite_vec(&b.velocity, s.dim, &format!("{at}.velocity"), s);
        match &b.shape {
            Shape::Ball { radius } => {
                assert!(radius.is_finite() && *radius > 0.0, "{at}: radius {radius}")
            }
            Shape::Box { half_extents } => {
                finite_vec(half_extents, s.dim, &format!("{at}.half_extents"), s);
                assert!(
                    half_extents.iter().all(|h| *h > 0.0),
                    "{at}: {half_extents:?}"
                );
            }
            Shape::Capsule {
                half_height,
                radius,
            } => assert!(
                *half_height > 0.0 && *radius > 0.0,
                "{at}: capsule {half_height} {radius}"
            ),
            Shape::Convex { points } => {
                assert!(points.len() > s.dim, "{at}: {} points", points.len())
            }
        }
        if b.fixed {
            assert!(b.mass.is_none(), "{at}: fixed body with a mass");
            assert!(
                b.velocity.iter().all(|v| *v == 0.0),
                "{at}: fixed body moves"
            );
            assert!(!b.law, "{at}: fixed body follows the law");
        } else {
            let m = b
                .mass
                .unwrap_or_else(|| panic!("{at}: moving body without a mass"));
            assert!(m.is_finite() && m > 0.0, "{at}: mass {m}");
        }
        assert!(b.restitution.is_finite() && b.restitution >= 0.0);
        assert!(b.friction.is_finite() && b.friction >= 0.0);
    }
    // The derived quantities the simulation uses must not panic.
    let _ = s.ccd_flags();
    let _ = s.extent();
    let _ = s.active_effects();
    let _ = s.effective_law();
    let _ = s.picture_times(s.steps);
}
