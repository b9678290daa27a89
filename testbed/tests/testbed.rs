//! The testbed app as a user runs it: a bundled scene in a real window
//! (under Xvfb when there is no display), the mode switched while it runs,
//! the last frame saved and what each mode did recorded.
//!
//! Needs a display or `xvfb-run` (Debian's xvfb) and a Vulkan or GL driver
//! (Debian's mesa-vulkan-drivers); `testbed/run-tests.sh` installs them
//! under CI. Without them the window tests fail under CI (CI=true) and are
//! skipped with a message otherwise.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

/// A fresh folder for one run (the testbed autosaves its UI state in the
/// working directory).
fn run_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kimpact-testbed-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The app with `args` in `dir`, in a window: on the display if there is
/// one, else under `xvfb-run`. `None` when neither exists (outside CI).
fn windowed(dir: &Path, args: &[&str]) -> Option<Output> {
    let exe = env!("CARGO_BIN_EXE_kimpact-testbed");
    let mut cmd = if std::env::var_os("DISPLAY").is_some() {
        Command::new(exe)
    } else if Command::new("xvfb-run").arg("--help").output().is_ok() {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 1280x720x24", exe]);
        c
    } else {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "no display and no xvfb-run (apt-get install xvfb)"
        );
        eprintln!("skipped: no display and no xvfb-run");
        return None;
    };
    let out = cmd
        .args(args)
        .current_dir(dir)
        .env("XDG_RUNTIME_DIR", dir)
        .output()
        .expect("the app starts");
    assert!(
        out.status.success(),
        "{args:?}: {}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    Some(out)
}

struct Segment {
    mode: String,
    frames: u64,
    impacts: u64,
    kinetic_start: f64,
    kinetic_end: f64,
}

fn segments(report: &Path) -> (u64, Vec<Segment>) {
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
    let segments = r["segments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| Segment {
            mode: s["mode"].as_str().unwrap().to_string(),
            frames: s["frames"].as_u64().unwrap(),
            impacts: s["impacts"].as_u64().unwrap(),
            kinetic_start: s["kinetic_start"].as_f64().unwrap(),
            kinetic_end: s["kinetic_end"].as_f64().unwrap(),
        })
        .collect();
    (r["frames"].as_u64().unwrap(), segments)
}

#[test]
fn the_cradle_switched_from_exact_to_native_keeps_its_energy_then_hands_over() {
    let dir = run_dir("cradle");
    let cradle = scene("cradle2d.ron");
    let args = [
        cradle.to_str().unwrap(),
        "--mode",
        "exact",
        "--switch",
        "native@45",
        "--frames",
        "90",
        "--screenshot",
        "shot.png",
        "--report",
        "report.json",
    ];
    if windowed(&dir, &args).is_none() {
        return;
    }
    let (frames, s) = segments(&dir.join("report.json"));
    assert_eq!(frames, 90);
    assert_eq!(s.len(), 2);
    assert_eq!((s[0].mode.as_str(), s[0].frames), ("exact", 45));
    assert_eq!((s[1].mode.as_str(), s[1].frames), ("native", 45));
    // The strike and its chain through the row, by the law: elastic.
    assert!(s[0].impacts >= 4, "exact: {} impacts", s[0].impacts);
    let drift = (s[0].kinetic_end - s[0].kinetic_start).abs() / s[0].kinetic_start;
    assert!(drift < 1e-5, "exact: kinetic energy drifted by {drift:e}");
    // Native: kimpact resolves nothing.
    assert_eq!(s[1].impacts, 0);

    // The frame: the window's size, the scene drawn (not one colour, and
    // pixels of the bodies below the UI panels).
    let shot = image::open(dir.join("shot.png")).unwrap().to_rgb8();
    assert_eq!(shot.dimensions(), (1280, 720));
    let background = *shot.get_pixel(1279, 719);
    let drawn = shot
        .enumerate_pixels()
        .filter(|(_, y, p)| *y > 320 && **p != background)
        .count();
    assert!(drawn > 1000, "only {drawn} pixels of the scene drawn");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn pachinko_switched_from_native_to_exact_is_taken_by_the_law() {
    let dir = run_dir("pachinko");
    let pachinko = scene("pachinko2d.toml");
    let args = [
        pachinko.to_str().unwrap(),
        "--mode",
        "native",
        "--switch",
        "exact@60",
        "--frames",
        "150",
        "--report",
        "report.json",
    ];
    if windowed(&dir, &args).is_none() {
        return;
    }
    let (frames, s) = segments(&dir.join("report.json"));
    assert_eq!(frames, 150);
    assert_eq!(s.len(), 2);
    assert_eq!((s[0].mode.as_str(), s[0].impacts), ("native", 0));
    assert_eq!(s[1].mode, "exact");
    assert!(s[1].impacts > 0, "exact: no impacts after the switch");
    // Falling marbles gain energy; nothing blows up.
    assert!(s[1].kinetic_end.is_finite() && s[1].kinetic_end > s[1].kinetic_start);
    assert!(!dir.join("shot.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_input_is_refused_before_a_window_opens() {
    let exe = env!("CARGO_BIN_EXE_kimpact-testbed");
    let run = |args: &[&str]| {
        let out = Command::new(exe)
            .args(args)
            .env_remove("DISPLAY")
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let gas3d = scene("gas3d.json");
    let (code, err) = run(&[gas3d.to_str().unwrap()]);
    assert_eq!(code, Some(2));
    assert!(err.contains("gas3d.json") && err.contains("3D"), "{err}");

    let (code, err) = run(&["no-such-scene.ron"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("no-such-scene.ron"), "{err}");

    let cradle = scene("cradle2d.ron");
    let (code, err) = run(&[cradle.to_str().unwrap(), "--switch", "fast@3"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("fast@3"), "{err}");

    let (code, err) = run(&[cradle.to_str().unwrap(), "--screenshot", "x.png"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("--frames"), "{err}");
}
