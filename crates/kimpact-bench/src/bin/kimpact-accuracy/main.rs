//! `kimpact-accuracy`: every kimpact mode and native rapier against the
//! exact event-driven reference (`kimpact-reference`), and what accuracy
//! costs.
//!
//! ```text
//! cargo run --release -p kimpact-bench --bin kimpact-accuracy              # ~10 min on 2 cores, writes docs/
//! cargo run --release -p kimpact-bench --bin kimpact-accuracy -- --quick   # a smoke run on small scenes
//! ```
//!
//! It writes `docs/accuracy.md` (tables, the method, the command and the
//! machine; the hand-written Findings of the previous file are kept),
//! `docs/accuracy.svg` (the cost of accuracy and the cooling curves),
//! `docs/accuracy.csv` (every number of the plots and the time series, long
//! format: `section,engine,method,dt_div,x,quantity,value`) and
//! `docs/accuracy-summary.json` (the headline errors per scene, build and
//! mode, and the cost of each mode). The simulators, scenes and
//! measurements are the `kimpact_harness` library of this package.

mod experiments;
mod format;
mod plot;
mod pool;
mod report;
mod stats;
mod summary;
mod texts;
mod z;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use clap::Parser;
use kimpact_harness::{B2_F32, B2_F64, B3_F32, B3_F64, HarnessError, Method};

use experiments::{Out, Sizes, cooling_jobs, cost_jobs, gas_jobs, short_jobs, z_job, z_summary};
use pool::{Job, run_jobs};

/// Every kimpact mode and native rapier against the exact reference.
#[derive(Parser, Debug)]
#[command(name = "kimpact-accuracy", version, about)]
struct Args {
    /// A smoke run: every comparison on small scenes for short times (its
    /// figures mean nothing).
    #[arg(long)]
    quick: bool,
    /// Worker threads of the accuracy jobs (the cost runs use one).
    #[arg(long, default_value_t = 2)]
    threads: usize,
    /// Where to write accuracy.md, .svg, .csv and accuracy-summary.json.
    #[arg(long, default_value = "docs")]
    out: PathBuf,
}

/// What can stop a run.
#[derive(Debug, thiserror::Error)]
enum RunError {
    #[error(transparent)]
    Harness(#[from] HarnessError),
    #[error("plot: {0}")]
    Plot(String),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kimpact-accuracy: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Write `text` to `path`.
fn write(path: &Path, text: &str) -> Result<(), RunError> {
    std::fs::write(path, text).map_err(|source| RunError::Io {
        path: path.to_owned(),
        source,
    })
}

/// The accuracy jobs, longest first: the reference's Z runs (once per case:
/// it has no precision to vary), then rapier's in 3D, then in 2D (every mode
/// in both precisions), the gases, the cooling gases and the short scenes.
fn jobs<'a>(sizes: &'a Sizes) -> Result<Vec<Job<'a, Result<Out, HarnessError>>>, HarnessError> {
    let mut jobs: Vec<Job<'a, Result<Out, HarnessError>>> = Vec::new();
    let (ell2, ell3, ell3_large) = (sizes.ell2, sizes.ell3, sizes.ell3_large);
    let [t2, t3, t3_large] = sizes.calibrate_t;
    // The box sizes that give the wanted bulk packing fractions.
    eprintln!("calibrating the Z boxes with the reference");
    let n3 = z::calibrate(&B3_F64, 0.3, ell3, t3, sizes.w_min)?;
    // The 3D box small enough for rapier leaves little room away from the
    // walls: the reference also measures Z in a larger one.
    let n3_large = z::calibrate(&B3_F64, 0.3, ell3_large, t3_large, sizes.w_min)?;
    let n2 = [
        z::calibrate(&B2_F64, 0.3, ell2, t2, sizes.w_min)?,
        z::calibrate(&B2_F64, 0.5, ell2, t2, sizes.w_min)?,
    ];
    let r = Method::Reference;
    jobs.push(Box::new(move || {
        z_job(B3_F64, 0.3, n3_large, ell3_large, r, sizes)
    }));
    jobs.push(Box::new(move || z_job(B3_F64, 0.3, n3, ell3, r, sizes)));
    for (i, eta) in [0.3, 0.5].into_iter().enumerate() {
        let n = n2[i];
        jobs.push(Box::new(move || z_job(B2_F64, eta, n, ell2, r, sizes)));
    }
    for m in Method::RAPIER {
        for b in [B3_F32, B3_F64] {
            jobs.push(Box::new(move || z_job(b, 0.3, n3, ell3, m, sizes)));
        }
    }
    for (i, eta) in [0.3, 0.5].into_iter().enumerate() {
        let n = n2[i];
        for m in Method::RAPIER {
            for b in [B2_F32, B2_F64] {
                jobs.push(Box::new(move || z_job(b, eta, n, ell2, m, sizes)));
            }
        }
    }
    for m in Method::RAPIER {
        jobs.push(Box::new(move || gas_jobs(B2_F32, m, sizes)));
        jobs.push(Box::new(move || gas_jobs(B2_F64, m, sizes)));
        jobs.push(Box::new(move || gas_jobs(B3_F32, m, sizes)));
        jobs.push(Box::new(move || gas_jobs(B3_F64, m, sizes)));
    }
    jobs.push(Box::new(move || cooling_jobs(B2_F32, sizes)));
    jobs.push(Box::new(move || cooling_jobs(B2_F64, sizes)));
    jobs.push(Box::new(move || cooling_jobs(B3_F32, sizes)));
    jobs.push(Box::new(move || cooling_jobs(B3_F64, sizes)));
    jobs.push(Box::new(|| short_jobs(B2_F32)));
    jobs.push(Box::new(|| short_jobs(B2_F64)));
    jobs.push(Box::new(|| short_jobs(B3_F32)));
    jobs.push(Box::new(|| short_jobs(B3_F64)));
    Ok(jobs)
}

fn run(args: &Args) -> Result<(), RunError> {
    let sizes = if args.quick {
        Sizes::quick()
    } else {
        Sizes::full()
    };
    let sizes = &sizes;
    let started = Instant::now();

    // Phase 1: accuracy (parallel jobs; their timings share the cores).
    let jobs = jobs(sizes)?;
    let total = jobs.len();
    let done = AtomicUsize::new(0);
    let done = &done;
    let jobs = jobs
        .into_iter()
        .map(|j| -> Job<'_, Result<Out, HarnessError>> {
            Box::new(move || {
                let o = j();
                let k = done.fetch_add(1, Ordering::SeqCst) + 1;
                eprintln!(
                    "[{:>6.1}s] {k}/{total} jobs",
                    started.elapsed().as_secs_f64()
                );
                o
            })
        })
        .collect();
    let mut outs = run_jobs(jobs, args.threads)
        .into_iter()
        .collect::<Result<Vec<Out>, HarnessError>>()?;
    // Phase 2: the cost of accuracy, one job at a time so that the timings
    // do not share the cores with other jobs of this program.
    eprintln!(
        "[{:>6.1}s] cost of accuracy (one thread)",
        started.elapsed().as_secs_f64()
    );
    outs.push(cost_jobs(B2_F32, sizes)?);
    outs.push(cost_jobs(B2_F64, sizes)?);
    outs.push(cost_jobs(B3_F32, sizes)?);
    outs.push(cost_jobs(B3_F64, sizes)?);
    let elapsed = started.elapsed().as_secs_f64();

    let mut tables: BTreeMap<String, Vec<Vec<String>>> = BTreeMap::new();
    let mut csv = vec!["section,engine,method,dt_div,x,quantity,value".to_owned()];
    let (mut points, mut notes, mut z_results) = (Vec::new(), Vec::new(), Vec::new());
    let (mut errors, mut costs) = (Vec::new(), Vec::new());
    for o in outs {
        for (k, r) in o.rows {
            tables.entry(k).or_default().push(r);
        }
        csv.extend(o.csv);
        points.extend(o.points);
        notes.extend(o.notes);
        z_results.extend(o.z);
        errors.extend(o.errors);
        costs.extend(o.costs);
    }
    let (z_main, z_checks) = report::z_tables(&z_results);
    errors.extend(z_summary(&z_results));

    let dir = &args.out;
    std::fs::create_dir_all(dir).map_err(|source| RunError::Io {
        path: dir.clone(),
        source,
    })?;
    let svg = plot::svg(&plot::panels(&points, sizes.gas_n), 3).map_err(RunError::Plot)?;
    write(&dir.join("accuracy.svg"), &svg)?;
    write(&dir.join("accuracy.csv"), &(csv.join("\n") + "\n"))?;
    let summary = summary::Summary {
        command: report::command(args.quick),
        quick: args.quick,
        errors,
        costs,
    };
    let path = dir.join("accuracy-summary.json");
    summary::write(&path, &summary).map_err(|source| RunError::Io { path, source })?;
    let get = |k: &str| tables.get(k).cloned().unwrap_or_default();
    // The hand-written findings between the markers survive regeneration.
    let md = dir.join("accuracy.md");
    let old = std::fs::read_to_string(&md).ok();
    let doc = report::document(
        &report::findings(old.as_deref()),
        &get("impact"),
        &get("cradle"),
        &get("gas"),
        &z_main,
        &z_checks,
        &get("cooling"),
        &get("cost"),
        &notes,
        &report::machine(),
        args.quick,
        args.threads,
        elapsed,
        sizes,
    );
    write(&md, &doc)?;
    eprintln!(
        "wrote {} (accuracy.md, .svg, .csv, accuracy-summary.json) in {elapsed:.0} s",
        dir.display()
    );
    Ok(())
}
