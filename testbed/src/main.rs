//! `kimpact-testbed`: kimpact's bundled 2D scenes in rapier's own testbed
//! (rapier_testbed2d), with the mode switchable while a scene runs.
//!
//! ```text
//! kimpact-testbed [SCENE ...] [--mode M]
//!                 [--switch MODE@FRAME ...] [--frames N]
//!                 [--screenshot FILE.png] [--report FILE.json]
//! ```
//!
//! Without a scene it lists every bundled 2D scene (`scenes/*2d*`) in the
//! testbed's example menu. The "kimpact mode" menu of the settings panel
//! switches between native rapier, restitution, impulse and exact at the
//! next step, without restarting the scene; the panel also shows kimpact's
//! impacts so far. `--switch`, `--frames`, `--screenshot` and `--report`
//! script a run (the tests use them under Xvfb): switch mode at the given
//! simulated frames, stop after `N` frames, save the last frame as a PNG and
//! write what each mode did as JSON.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod run;
mod script;
mod view;

use std::path::{Path, PathBuf};

use clap::Parser;
use rapier_testbed2d::{ExampleEntry, TestbedViewer};

use crate::script::{Script, Switch};

/// The command line.
#[derive(Parser, Debug)]
#[command(name = "kimpact-testbed", version, about)]
struct Args {
    /// Scene files (2D); none: every bundled 2D scene.
    scenes: Vec<PathBuf>,
    /// The starting mode (native, restitution, impulse, exact); default:
    /// the scene's own.
    #[arg(long)]
    mode: Option<kimpact2d::Mode>,
    /// Switch to MODE at simulated frame FRAME (`exact@60`); repeatable.
    #[arg(long = "switch", value_name = "MODE@FRAME")]
    switches: Vec<Switch>,
    /// Quit after this many simulated frames (default: run until closed).
    #[arg(long)]
    frames: Option<u64>,
    /// Save the last frame as a PNG (needs `--frames`).
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Write what each mode did (frames, impacts, energy) as JSON (needs
    /// `--frames`).
    #[arg(long, requires = "frames")]
    report: Option<PathBuf>,
}

/// The bundled 2D scenes, by name.
fn bundled_scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut found: Vec<PathBuf> = std::fs::read_dir(&dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_stem()
                .and_then(|s| s.to_str())
                .is_some_and(|s| s.contains("2d"))
        })
        .collect();
    found.sort();
    found
}

/// Exit with `message` and code 2 (bad input), as the CLI does.
fn fail(message: impl std::fmt::Display) -> ! {
    eprintln!("kimpact-testbed: {message}");
    std::process::exit(2)
}

#[kiss3d::main]
async fn main() {
    let args = Args::parse();
    let paths = if args.scenes.is_empty() {
        bundled_scenes()
    } else {
        args.scenes.clone()
    };
    if paths.is_empty() {
        fail("no scene given and no bundled 2D scene found");
    }
    let mut scenes = Vec::with_capacity(paths.len());
    for path in &paths {
        let scene = kimpact_scene::load(path).unwrap_or_else(|e| fail(e));
        // Checked here, before a window opens.
        if let Err(e) = kimpact_world::dim2::build(&scene, scene.mode) {
            fail(e);
        }
        scenes.push(scene);
    }
    let script = Script::new(args.switches.clone(), args.frames);
    let entries = scenes
        .iter()
        .map(|s| ExampleEntry::new("kimpact", Box::leak(s.name.clone().into_boxed_str())))
        .collect();
    let mut viewer = TestbedViewer::new(entries).await;
    loop {
        viewer.clear_scene();
        let scene = &scenes[viewer.selected()];
        let start = args.mode.unwrap_or(scene.mode);
        let outcome = run::run_scene(&mut viewer, scene, start, &script).await;
        match outcome {
            Ok(run::Ended::Scripted(record)) => {
                if let Some(path) = &args.screenshot {
                    let image = viewer.window().snap_image();
                    script::save_png(&image, path).unwrap_or_else(|e| fail(e));
                }
                if let Some(path) = &args.report {
                    script::save_report(&record, path).unwrap_or_else(|e| fail(e));
                }
                break;
            }
            Ok(run::Ended::Closed) => {}
            Err(e) => fail(e),
        }
        if viewer.quitting() {
            break;
        }
    }
}
