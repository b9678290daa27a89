//! The soak command: long runs of the 1,000-ball elastic gas and the
//! 1,000-ball pit (f64), checking after every step that no position or
//! velocity is NaN, no ball has left its box, and the energy stays within
//! its bound (gas, `exact`: |E − E₀|/E₀ ≤ 1e-9; pit, every mode: (E − E₀)/E₀
//! ≤ 1e-3, energies from the floor). Not part of CI; `tests/soak.rs` runs a
//! short version of the same code (`tests/cases/soak.rs`).
//!
//! ```text
//! cargo run --release --example soak -- [--steps N] [--scene gas|pit|all]
//!     [--dim 2|3|all] [--mode native|restitution|impulse|exact|all]
//!     [--balls N] [--progress N] [--cpu-minutes M]
//! ```
//!
//! Defaults: 1,000,000 steps, both scenes, 2D, 1,000 balls, a progress line
//! every 10,000 steps, no time limit; the gas runs in `exact` mode and the
//! pit in every mode unless `--mode` says otherwise. `--cpu-minutes` stops
//! each run once it has used that much CPU time (checked every 100 steps;
//! the summary then says `steps=done/asked`): a budget that does not depend
//! on the machine's load, unlike wall time.
//! The pit's balls may fall asleep once the pile settles (rapier's default;
//! `tests/cases/long.rs`'s 400-step pit keeps them awake).
//! Prints one `SOAK ...` summary line per run (steps, wall and CPU time,
//! energy start/end/max/min, escaped and NaN counts, how many balls sank past
//! a wall's inner face and how deep, the law's counters, PASS/FAIL) and exits
//! with status 1 if any run failed.
// `f64::from(x)` in the shared test world is the identity in f64.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

use std::process::ExitCode;

mod d2 {
    use kimpact2d_f64 as k;
    mod world {
        use kimpact2d_f64 as k;
        include!("../tests/cases/world.rs");
    }
    use self::world::TestWorld;
    use k::Mode;
    use k::math::{DIM, Real, Vector};
    use k::rapier::prelude::*;
    include!("../tests/cases/soak.rs");

    pub fn run(
        scene: &'static str,
        mode: &str,
        balls: usize,
        steps: u64,
        progress: u64,
        limit: Option<f64>,
    ) -> bool {
        let mode: Mode = mode.parse().expect("checked by main");
        let s = soak(scene, mode, balls, steps, progress, limit);
        println!("{}", s.summary());
        s.passed()
    }
}

mod d3 {
    use kimpact3d_f64 as k;
    mod world {
        use kimpact3d_f64 as k;
        include!("../tests/cases/world.rs");
    }
    use self::world::TestWorld;
    use k::Mode;
    use k::math::{DIM, Real, Vector};
    use k::rapier::prelude::*;
    include!("../tests/cases/soak.rs");

    pub fn run(
        scene: &'static str,
        mode: &str,
        balls: usize,
        steps: u64,
        progress: u64,
        limit: Option<f64>,
    ) -> bool {
        let mode: Mode = mode.parse().expect("checked by main");
        let s = soak(scene, mode, balls, steps, progress, limit);
        println!("{}", s.summary());
        s.passed()
    }
}

const MODES: [&str; 4] = ["native", "restitution", "impulse", "exact"];

struct Args {
    steps: u64,
    scenes: Vec<&'static str>,
    dims: Vec<u32>,
    mode: Option<Vec<&'static str>>,
    balls: usize,
    progress: u64,
    /// CPU seconds per run.
    limit: Option<f64>,
}

fn usage() -> String {
    "usage: soak [--steps N] [--scene gas|pit|all] [--dim 2|3|all] \
     [--mode native|restitution|impulse|exact|all] [--balls N] [--progress N] \
     [--cpu-minutes M]"
        .to_owned()
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        steps: 1_000_000,
        scenes: vec!["gas", "pit"],
        dims: vec![2],
        mode: None,
        balls: 1000,
        progress: 10_000,
        limit: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        if flag == "--help" || flag == "-h" {
            return Err(usage());
        }
        let value = it
            .next()
            .ok_or_else(|| format!("{flag} needs a value\n{}", usage()))?;
        let number = |v: &str| -> Result<u64, String> {
            v.replace('_', "")
                .parse()
                .map_err(|_| format!("{flag}: not a number: {v:?}"))
        };
        match flag.as_str() {
            "--steps" => a.steps = number(&value)?,
            "--balls" => a.balls = number(&value)? as usize,
            "--progress" => a.progress = number(&value)?,
            "--cpu-minutes" => a.limit = Some(60.0 * number(&value)? as f64),
            "--scene" => {
                a.scenes = match value.as_str() {
                    "gas" => vec!["gas"],
                    "pit" => vec!["pit"],
                    "all" => vec!["gas", "pit"],
                    _ => return Err(format!("--scene: gas, pit or all, not {value:?}")),
                }
            }
            "--dim" => {
                a.dims = match value.as_str() {
                    "2" => vec![2],
                    "3" => vec![3],
                    "all" => vec![2, 3],
                    _ => return Err(format!("--dim: 2, 3 or all, not {value:?}")),
                }
            }
            "--mode" => {
                a.mode = Some(match value.as_str() {
                    "all" => MODES.to_vec(),
                    m => vec![
                        *MODES
                            .iter()
                            .find(|&&x| x == m)
                            .ok_or_else(|| format!("--mode: unknown mode {m:?}"))?,
                    ],
                })
            }
            _ => return Err(format!("unknown argument {flag:?}\n{}", usage())),
        }
    }
    Ok(a)
}

fn main() -> ExitCode {
    let args = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let start = std::time::Instant::now();
    let mut failed = 0;
    for &dim in &args.dims {
        for &scene in &args.scenes {
            let modes = args.mode.clone().unwrap_or_else(|| match scene {
                "gas" => vec!["exact"],
                _ => MODES.to_vec(),
            });
            for mode in modes {
                println!(
                    "soak: {scene} {dim}D {mode}, {} balls, {} steps",
                    args.balls, args.steps
                );
                let a = &args;
                let run = if dim == 2 { d2::run } else { d3::run };
                let ok = run(scene, mode, a.balls, a.steps, a.progress, a.limit);
                failed += usize::from(!ok);
            }
        }
    }
    println!(
        "soak: done in {:.1}s, {failed} run(s) failed",
        start.elapsed().as_secs_f64()
    );
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
