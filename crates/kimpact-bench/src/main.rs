//! `kimpact-bench`: what each accuracy level costs against native rapier.
//! Each law mode of each scene, size and precision gets timing runs (a child
//! process stepping native and the mode in lockstep) and a memory run (the
//! mode alone); the parent writes `results.md`, `results.csv`, `raw.json`
//! and scaling plots.
// `f64::from(x)` converts in the f32 builds and is the identity in the f64 ones.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

mod alloc;
mod child;
mod cli;
mod effects;
mod memory;
mod raw;
mod report;
mod stages;
mod worlds;

use std::collections::BTreeSet;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use kimpact::Mode;

use cli::{Cli, Effect, HOOK_NATIVE, NO_CALM, REBOUND_CUTOFF, Scene, name};

#[global_allocator]
static ALLOCATOR: alloc::Counting = alloc::Counting;

fn main() -> ExitCode {
    let cli = Cli::parse();
    HOOK_NATIVE.store(cli.hook_native, Ordering::Relaxed);
    NO_CALM.store(cli.no_calm, Ordering::Relaxed);
    REBOUND_CUTOFF.store(
        cli.rebound_cutoff.unwrap_or(0.0).to_bits(),
        Ordering::Relaxed,
    );
    if cli.threads.is_some() && !cfg!(feature = "parallel") {
        eprintln!("--threads needs a build with the `parallel` feature");
        return ExitCode::FAILURE;
    }
    if cli.pair || cli.solo {
        return worlds::child_main(&cli);
    }
    if cli.rerender {
        let path = cli.out.join("raw.json");
        let raw = std::fs::read_to_string(&path).map_err(|e| e.to_string());
        return match raw.and_then(|s| serde_json::from_str(&s).map_err(|e| e.to_string())) {
            Ok(raw) => render(&cli.out, &raw),
            Err(e) => {
                eprintln!("cannot read {}: {e}", path.display());
                ExitCode::FAILURE
            }
        };
    }
    let modes = BTreeSet::from_iter(cli.mode.iter().copied().chain([Mode::Native]));
    let modes: Vec<Mode> = modes.into_iter().collect();
    let gas = |s: &Scene| matches!(s, Scene::Gas2d | Scene::Gas3d);
    let scenes = BTreeSet::from_iter(cli.scene.iter().copied().filter(|s| !cli.effects || gas(s)));
    if scenes.is_empty() {
        eprintln!("--effects runs on the gas2d and gas3d bases: give one in --scene");
        return ExitCode::FAILURE;
    }
    let effects: Vec<Option<Effect>> = match cli.effects {
        true => Effect::value_variants().iter().copied().map(Some).collect(),
        false => vec![None],
    };
    let started = Instant::now();
    let mut groups = Vec::new();
    for precision in BTreeSet::from_iter(cli.precision.iter().copied()) {
        for &scene in &scenes {
            let sizes = match scene.fixed_balls() {
                Some(n) => BTreeSet::from([n]),
                None => BTreeSet::from_iter(cli.balls.iter().copied()),
            };
            for balls in sizes {
                for &effect in &effects {
                    let progress = |what: &str| {
                        let (t, s) = (started.elapsed().as_secs_f64(), name(scene));
                        let e = effect.map(|e| format!(", {}", name(e))).unwrap_or_default();
                        eprintln!("[{t:>6.1}s] {precision} {s} {balls} balls{e}: {what}");
                    };
                    let config = (scene, balls, precision);
                    let mut cli = cli.clone();
                    cli.effect = effect;
                    groups.push(child::measure_group(&cli, config, &modes, progress));
                }
            }
        }
    }
    let args: Vec<String> = std::env::args().skip(1).collect();
    let command = format!("kimpact-bench {}", args.join(" "));
    let header = raw::Header {
        command: command.trim_end().to_owned(),
        cli: cli.clone(),
        machine: kimpact_harness::machine(),
        parallel: cfg!(feature = "parallel"),
        wall_s: started.elapsed().as_secs_f64(),
    };
    let raw = raw::Raw { header, groups };
    let json = serde_json::to_string(&raw).expect("the results serialize");
    if let Err(e) = kimpact_harness::write_files(&[(cli.out.join("raw.json"), json)]) {
        eprintln!("{e}");
    }
    render(&cli.out, &raw)
}

/// The effects tables of `raw` if it holds them, else the matrix's outputs.
fn render(dir: &std::path::Path, raw: &raw::Raw) -> ExitCode {
    match raw.groups.iter().any(|g| g.effect.is_some()) {
        true => effects::render(dir, raw),
        false => report::render(dir, raw),
    }
}
