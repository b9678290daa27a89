//! `compare.html` in a real headless Chromium (Debian's `chromium`; set
//! `KIMPACT_CHROMIUM` to use another binary).
//!
//! The page's self-test (`#selftest=T1,T2`) scrubs to each time through the
//! scrubber, reads back what each panel drew (world position, pixel, the
//! colour on the canvas there) and writes a JSON verdict into the DOM, which
//! `chromium --dump-dom` prints. The tests compare what was drawn with the
//! JSON reports the CLI writes: `compare`'s own at the end, and `run
//! --steps K`'s at step K. Without Chromium the tests say so and pass,
//! unless `CI` is set: in CI a missing browser is a failure.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use common::{MODES, kimpact_ok, scene, temp_dir};

/// The Chromium binary, or `None` (with the reason printed) when there is
/// none and `CI` is not set.
fn chromium() -> Option<PathBuf> {
    let found = std::env::var_os("KIMPACT_CHROMIUM")
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths)
                    .flat_map(|d| [d.join("chromium"), d.join("chromium-browser")])
                    .find(|p| p.is_file())
            })
        });
    let ci = std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "false" && v != "0");
    match found {
        Some(p) => Some(p),
        None if ci => panic!(
            "CI is set but no chromium is on PATH: .ci/run installs Debian's `chromium` (apt-get install chromium)"
        ),
        None => {
            println!(
                "SKIPPED: no chromium on PATH (apt-get install chromium, or set KIMPACT_CHROMIUM); the browser tests did not run"
            );
            None
        }
    }
}

/// What Chromium printed.
struct Browsed {
    success: bool,
    stdout: Vec<u8>,
    stderr: Vec<u8>,
}

/// Run Chromium headless on `page` (with `fragment`) with `extra`
/// arguments and a fresh profile; kill it after two minutes. Its output
/// goes to files (the DOM it dumps is larger than a pipe holds).
fn browse(chromium: &Path, page: &Path, fragment: &str, extra: &[&str], dir: &Path) -> Browsed {
    let run = dir.join(format!("chromium-{}", extra.len()));
    let _ = std::fs::remove_dir_all(&run);
    std::fs::create_dir_all(&run).expect("a directory for chromium");
    let url = format!("file://{}#{fragment}", page.display());
    let file = |name: &str| std::fs::File::create(run.join(name)).expect("an output file");
    let mut child = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            "--v=0",
            "--hide-scrollbars",
            "--window-size=1200,1600",
            "--virtual-time-budget=10000",
        ])
        .arg(format!("--user-data-dir={}", run.join("profile").display()))
        .args(extra)
        .arg(&url)
        .stdin(Stdio::null())
        .stdout(file("stdout"))
        .stderr(file("stderr"))
        .spawn()
        .expect("chromium starts");
    let start = Instant::now();
    let status = loop {
        match child.try_wait().expect("chromium runs") {
            Some(status) => break status,
            None if start.elapsed() > Duration::from_secs(120) => {
                let _ = child.kill();
                let _ = child.wait();
                panic!("chromium did not finish within two minutes on {url}");
            }
            None => std::thread::sleep(Duration::from_millis(50)),
        }
    };
    let out = Browsed {
        success: status.success(),
        stdout: std::fs::read(run.join("stdout")).expect("chromium's output"),
        stderr: std::fs::read(run.join("stderr")).expect("chromium's log"),
    };
    let _ = std::fs::remove_dir_all(&run);
    out
}

/// Lines of Chromium's log that report a message of the page's console.
fn console_lines(stderr: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(stderr)
        .lines()
        .filter(|l| l.contains("CONSOLE"))
        .map(str::to_owned)
        .collect()
}

/// The page's self-test verdict at `times` (seconds).
fn verdict(chromium: &Path, page: &Path, times: &[f64], dir: &Path) -> Value {
    let spec: Vec<String> = times.iter().map(|t| t.to_string()).collect();
    let o = browse(
        chromium,
        page,
        &format!("selftest={}", spec.join(",")),
        &["--dump-dom"],
        dir,
    );
    let dom = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.success, "chromium failed: {stderr}");
    let console = console_lines(&o.stderr);
    assert!(console.is_empty(), "console messages: {console:?}");
    let start = dom
        .find("<pre id=\"verdict\">")
        .unwrap_or_else(|| panic!("no verdict element in the DOM; chromium said: {stderr}"))
        + "<pre id=\"verdict\">".len();
    let end = start + dom[start..].find("</pre>").expect("the verdict ends");
    let text = dom[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    assert!(
        !text.is_empty(),
        "the self-test wrote no verdict; chromium said: {stderr}"
    );
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("verdict {text:?}: {e}"))
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn vecf(v: &Value) -> Vec<f64> {
    v.as_array().expect("an array").iter().map(f).collect()
}

fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).expect("the report")).expect("JSON")
}

/// `#rrggbb` as RGB.
fn rgb(hex: &str) -> [u8; 3] {
    let n = u32::from_str_radix(hex.trim_start_matches('#'), 16).expect("a colour");
    [(n >> 16) as u8, (n >> 8) as u8, n as u8]
}

/// The page's promises that do not depend on the scene: loaded with no
/// error, no request, a frame per shown step, every mode drawn.
fn check_page(v: &Value, steps: u64, stride: u64) {
    assert_eq!(
        v["ok"], true,
        "verdict: errors {} blocked {} resources {}",
        v["errors"], v["blocked"], v["resources"]
    );
    assert_eq!(v["errors"].as_array().map(Vec::len), Some(0));
    assert_eq!(v["blocked"].as_array().map(Vec::len), Some(0));
    assert_eq!(
        v["resources"].as_array().map(Vec::len),
        Some(0),
        "{}",
        v["resources"]
    );
    assert_eq!(v["steps"], steps);
    assert_eq!(v["stride"], stride);
    // Frames at 0, stride, 2 stride, ... and the last step.
    let mut expected: Vec<u64> = (0..=steps).step_by(stride as usize).collect();
    if expected.last() != Some(&steps) {
        expected.push(steps);
    }
    let shown: Vec<u64> = v["shown_steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_u64().unwrap())
        .collect();
    assert_eq!(shown, expected);
    assert_eq!(v["frames"], expected.len());
    let rate = v["rate"].as_str().unwrap();
    if stride == 1 {
        assert!(rate.starts_with("Every step shown"), "{rate}");
    } else {
        assert!(
            rate.contains(&format!("one step in {stride} shown")),
            "{rate}"
        );
    }
    assert!(
        rate.contains(&format!("{} frames", expected.len())),
        "{rate}"
    );
    assert_eq!(v["table_rows"], 4);
}

/// What the page drew for `mode` at scrub `k` matches the report's bodies
/// (`reference`): world positions to f32 rounding (the page carries f32),
/// pixels as the view maps them; with `colours`, the canvas under each
/// ball's centre is the ball's colour.
fn check_drawn(v: &Value, k: usize, mode: &str, reference: &Value, colours: bool) {
    let scrub = &v["scrubs"][k];
    let drawn = &scrub["modes"][mode];
    let bodies = reference["bodies"].as_array().unwrap();
    let moving: Vec<usize> = (0..bodies.len())
        .filter(|&i| bodies[i]["fixed"] == false)
        .collect();
    let list = drawn["bodies"].as_array().unwrap();
    assert_eq!(list.len(), moving.len(), "{mode}: every moving body drawn");
    assert!(f(&drawn["painted"]) > 0.0, "{mode}: the panel is blank");
    let [lo, hi] = [vecf(&v["bounds"][0]), vecf(&v["bounds"][1])];
    let (w, h) = (f(&v["panel"][0]), f(&v["panel"][1]));
    let axes = [
        v["axes"][0].as_u64().unwrap() as usize,
        v["axes"][1].as_u64().unwrap() as usize,
    ];
    let scale = (w / (hi[0] - lo[0])).min(h / (hi[1] - lo[1]));
    let (ox, oy) = (
        (w - scale * (hi[0] - lo[0])) / 2.0,
        (h - scale * (hi[1] - lo[1])) / 2.0,
    );
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let mut coloured = 0;
    for d in list {
        let i = d["body"].as_u64().unwrap() as usize;
        let want = vecf(&bodies[i]["position"]);
        let got = vecf(&d["position"]);
        assert_eq!(got.len(), want.len());
        for (g, w_) in got.iter().zip(&want) {
            // f32 carries 24 bits: within 2^-22 of the view's extent.
            assert!(
                (g - w_).abs() <= extent * 2f64.powi(-22),
                "{mode} step {}: body {i} drawn at {got:?}, the report has {want:?}",
                scrub["step"]
            );
        }
        let px = vecf(&d["pixel"]);
        let expect = [
            ox + (want[axes[0]] - lo[0]) * scale,
            h - oy - (want[axes[1]] - lo[1]) * scale,
        ];
        for c in 0..2 {
            assert!(
                (px[c] - expect[c]).abs() < 0.01,
                "{mode}: body {i} at pixel {px:?}, expected {expect:?}"
            );
        }
        if colours && d["radius_px"].as_f64().is_some_and(|r| r >= 2.0) {
            let seen = d["seen"].as_array().expect("a pixel inside the panel");
            let seen: Vec<u8> = seen.iter().map(|c| c.as_u64().unwrap() as u8).collect();
            assert_eq!(
                seen,
                rgb(d["color"].as_str().unwrap()),
                "{mode}: the canvas under body {i}'s centre"
            );
            coloured += 1;
        }
    }
    if colours {
        assert!(
            coloured > 0,
            "{mode}: no ball large enough to check its colour"
        );
    }
}

/// Pixels of a PNG screenshot that are not the page's white background,
/// and those of the given colours.
fn screenshot_pixels(png: &Path, colours: &[[u8; 3]]) -> (usize, usize) {
    let img = tiny_skia::Pixmap::load_png(png).expect("a PNG screenshot");
    let mut painted = 0;
    let mut matching = 0;
    for p in img.pixels() {
        let c = p.demultiply();
        let px = [c.red(), c.green(), c.blue()];
        if px != [255, 255, 255] {
            painted += 1;
        }
        if colours.contains(&px) {
            matching += 1;
        }
    }
    (painted, matching)
}

/// The bundled break: every step shown, positions at 1 s and at the end
/// as the reports have them, every ball in its colour, a page under 5 MB,
/// and a screenshot with the balls on it.
#[test]
fn the_break_plays_in_chromium_as_the_reports_say() {
    let Some(chromium) = chromium() else { return };
    let dir = temp_dir("break");
    let out = dir.join("out");
    kimpact_ok(&[
        "compare",
        scene("billiards2d.ron").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let page = out.join("compare.html");
    let size = std::fs::metadata(&page).unwrap().len();
    assert!(size < 5_000_000, "compare.html is {size} bytes");
    // 1 s = step 60 of 240.
    for mode in MODES {
        kimpact_ok(&[
            "run",
            scene("billiards2d.ron").to_str().unwrap(),
            "--mode",
            mode,
            "--steps",
            "60",
            "--out",
            dir.join(format!("at60-{mode}.json")).to_str().unwrap(),
        ]);
    }
    let v = verdict(&chromium, &page, &[1.0, 4.0], &dir);
    check_page(&v, 240, 1);
    assert_eq!(v["scrubs"][0]["step"], 60);
    assert_eq!(v["scrubs"][1]["step"], 240);
    for mode in MODES {
        assert_eq!(
            v["colors"][mode].as_str().map(rgb),
            Some(match mode {
                "native" => [90, 90, 90],
                "restitution" => [230, 159, 0],
                "impulse" => [0, 158, 115],
                _ => [0, 114, 178],
            }),
            "{mode}: the plots' colour"
        );
        let early = read_json(&dir.join(format!("at60-{mode}.json")));
        check_drawn(&v, 0, mode, &early, true);
        let end = read_json(&out.join(format!("report-{mode}.json")));
        check_drawn(&v, 1, mode, &end, true);
    }
    // The balls' colours as drawn at 1 s.
    let colours: Vec<[u8; 3]> = v["scrubs"][0]["modes"]["exact"]["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| rgb(d["color"].as_str().unwrap()))
        .collect();
    let shot = dir.join("shot.png");
    let o = browse(
        &chromium,
        &page,
        "paused",
        &[&format!("--screenshot={}", shot.display())],
        &dir,
    );
    assert!(o.success, "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        console_lines(&o.stderr).is_empty(),
        "{:?}",
        console_lines(&o.stderr)
    );
    let (painted, balls) = screenshot_pixels(&shot, &colours);
    // 1200 x 1600: four panels of 560 x 300 and the curves at least.
    assert!(painted > 4 * 560 * 250, "{painted} painted pixels");
    // 16 balls of 6.5 px radius in four panels: over 100 pixels each.
    assert!(balls > 4 * 16 * 60, "{balls} pixels in the balls' colours");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A long run is subsampled, says so, and still draws the report's
/// positions at a shown step and at the end.
#[test]
fn a_long_gas_run_is_subsampled_and_stated() {
    let Some(chromium) = chromium() else { return };
    let dir = temp_dir("gas");
    let out = dir.join("out");
    // 400 disks: 3200 values a step, 156 frames within the budget.
    kimpact_ok(&[
        "compare",
        scene("gas2d.toml").to_str().unwrap(),
        "--steps",
        "200",
        "--out",
        out.to_str().unwrap(),
    ]);
    kimpact_ok(&[
        "run",
        scene("gas2d.toml").to_str().unwrap(),
        "--mode",
        "exact",
        "--steps",
        "100",
        "--out",
        dir.join("at100.json").to_str().unwrap(),
    ]);
    let page = out.join("compare.html");
    let v = verdict(&chromium, &page, &[100.0 / 60.0, 200.0 / 60.0], &dir);
    check_page(&v, 200, 2);
    assert_eq!(v["scrubs"][0]["step"], 100);
    check_drawn(&v, 0, "exact", &read_json(&dir.join("at100.json")), false);
    for mode in MODES {
        let end = read_json(&out.join(format!("report-{mode}.json")));
        check_drawn(&v, 1, mode, &end, false);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A 3D scene through the pictures' projection: the drawn positions are
/// the report's in all three axes, their pixels the view's mapping.
#[test]
fn a_3d_cradle_plays_in_chromium() {
    let Some(chromium) = chromium() else { return };
    let dir = temp_dir("cradle3d");
    let out = dir.join("out");
    kimpact_ok(&[
        "compare",
        scene("cradle3d.json").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let v = verdict(&chromium, &page_of(&out), &[1.5], &dir);
    check_page(&v, 90, 1);
    for mode in MODES {
        let end = read_json(&out.join(format!("report-{mode}.json")));
        check_drawn(&v, 0, mode, &end, false);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn page_of(out: &Path) -> PathBuf {
    out.join("compare.html")
}
