//! `kimpact-accuracy`: every kimpact mode and native rapier against the
//! exact event-driven reference (`kimpact-reference`), and what accuracy
//! costs.
//!
//! ```text
//! cargo run --release -p kimpact-bench --bin kimpact-accuracy              # ~10 min on 2 cores, writes docs/
//! cargo run --release -p kimpact-bench --bin kimpact-accuracy -- --quick   # a smoke run on small scenes
//! ```
//!
//! It writes `accuracy.md` (its hand-written Findings kept), `.svg`, `.csv`
//! (every number of the plots and series) and `accuracy-summary.json`.

mod experiments;
mod plot;
mod report;
mod z;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use clap::Parser;
use kimpact_harness::{
    AccuracySummary, B2_F32, B2_F64, B3_F32, B3_F64, HarnessError, Method, write_files,
};
use rayon::ThreadPoolBuilder;
use rayon::prelude::*;

use experiments::{Out, Sizes, cooling_jobs, cost_jobs, gas_jobs, short_jobs, z_job, z_summary};

/// A job of the study: it borrows the run's sizes.
type Job<'a> = Box<dyn FnOnce() -> Result<Out, HarnessError> + Send + 'a>;

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

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kimpact-accuracy: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `$job` (of the build `$b`) for every build, 2D then 3D, f32 then f64.
macro_rules! each_build {
    ($jobs:ident, |$b:ident| $job:expr) => {
        for $b in [B2_F32, B2_F64] {
            $jobs.push(Box::new(move || $job));
        }
        for $b in [B3_F32, B3_F64] {
            $jobs.push(Box::new(move || $job));
        }
    };
}

/// The accuracy jobs, longest first: the reference's Z runs (once per case:
/// it has no precision to vary), then rapier's in 3D, then in 2D (every mode
/// in both precisions), the gases, the cooling gases and the short scenes.
fn jobs(sizes: &Sizes) -> Result<Vec<Job<'_>>, HarnessError> {
    let mut jobs: Vec<Job<'_>> = Vec::new();
    let (ell2, ell3, ell3_large) = (sizes.ell2, sizes.ell3, sizes.ell3_large);
    let [t2, t3, t3_large] = sizes.calibrate_t;
    // The box sizes that give the wanted bulk packing fractions.
    eprintln!("calibrating the Z boxes with the reference");
    let n3 = z::calibrate(&B3_F64, 0.3, ell3, t3, sizes.w_min)?;
    // The 3D box small enough for rapier leaves little room away from the
    // walls: the reference also measures Z in a larger one.
    let n3_large = z::calibrate(&B3_F64, 0.3, ell3_large, t3_large, sizes.w_min)?;
    let mut cases2 = Vec::new();
    for eta in [0.3, 0.5] {
        let n = z::calibrate(&B2_F64, eta, ell2, t2, sizes.w_min)?;
        cases2.push((eta, n, ell2));
    }
    let (case3, case3_large) = ((0.3, n3, ell3), (0.3, n3_large, ell3_large));
    let r = Method::Reference;
    jobs.push(Box::new(move || z_job(B3_F64, case3_large, r, sizes)));
    jobs.push(Box::new(move || z_job(B3_F64, case3, r, sizes)));
    for &case in &cases2 {
        jobs.push(Box::new(move || z_job(B2_F64, case, r, sizes)));
    }
    for m in Method::RAPIER {
        for b in [B3_F32, B3_F64] {
            jobs.push(Box::new(move || z_job(b, case3, m, sizes)));
        }
    }
    for case in cases2 {
        for m in Method::RAPIER {
            for b in [B2_F32, B2_F64] {
                jobs.push(Box::new(move || z_job(b, case, m, sizes)));
            }
        }
    }
    // The gases, the cooling gases and the short scenes in every build.
    for m in Method::RAPIER {
        each_build!(jobs, |b| gas_jobs(b, m, sizes));
    }
    each_build!(jobs, |b| cooling_jobs(b, sizes));
    each_build!(jobs, |b| short_jobs(b));
    Ok(jobs)
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let sizes = &Sizes::new(args.quick);
    let started = Instant::now();
    let progress = |what: &str| eprintln!("[{:>6.1}s] {what}", started.elapsed().as_secs_f64());

    // Phase 1: accuracy (jobs on `--threads` threads, longest first; their
    // timings share the cores).
    let jobs = jobs(sizes)?;
    let (total, done) = (jobs.len(), AtomicUsize::new(0));
    let threads = args.threads.max(1);
    let pool = ThreadPoolBuilder::new().num_threads(threads).build();
    let pool = pool.map_err(|e| format!("cannot start the worker threads: {e}"))?;
    let outs: Result<Vec<Out>, HarnessError> = pool.install(|| {
        let run = |job: Job<'_>| {
            let out = job();
            let n = done.fetch_add(1, Ordering::SeqCst) + 1;
            progress(&format!("{n}/{total} jobs"));
            out
        };
        // One job per task, taken in order: the longest start first.
        jobs.into_par_iter().with_max_len(1).map(run).collect()
    });
    let mut all = Out::default();
    outs?.into_iter().for_each(|o| all.absorb(o));
    // Phase 2: the cost of accuracy, one job at a time so that the timings
    // do not share the cores with other jobs of this program.
    progress("cost of accuracy (one thread)");
    all.absorb(cost_jobs(B2_F32, sizes)?);
    all.absorb(cost_jobs(B2_F64, sizes)?);
    all.absorb(cost_jobs(B3_F32, sizes)?);
    all.absorb(cost_jobs(B3_F64, sizes)?);
    let elapsed = started.elapsed().as_secs_f64();

    all.errors.extend(z_summary(&all.z));
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record(experiments::CSV_HEADER)
        .expect("a Vec takes every byte");
    all.csv
        .iter()
        .for_each(|row| csv.serialize(row).expect("a CSV row serializes"));
    let csv = csv.into_inner().expect("a Vec takes every byte");
    let svg = kimpact_harness::svg(&plot::panels(&all.points, sizes.gas_n), 3, (460, 320));
    let svg = svg.map_err(|e| format!("plot: {e}"))?;
    let summary = AccuracySummary {
        command: report::command(args.quick),
        quick: args.quick,
        errors: all.errors,
    };
    let summary = serde_json::to_string_pretty(&summary).expect("the summary serializes") + "\n";
    let dir = &args.out;
    // The hand-written findings between the markers survive regeneration.
    let md_path = dir.join("accuracy.md");
    let old = std::fs::read_to_string(&md_path).ok();
    let doc = report::document(&report::Document {
        rows: &all.rows,
        z: &all.z,
        findings: &report::findings(old.as_deref()),
        notes: &all.notes,
        quick: args.quick,
        threads: args.threads,
        elapsed,
        sizes,
    });
    write_files(&[
        (dir.join("accuracy.svg"), svg.into_bytes()),
        (dir.join("accuracy.csv"), csv),
        (dir.join("accuracy-summary.json"), summary.into_bytes()),
        (md_path, doc.into_bytes()),
    ])?;
    let dir = dir.display();
    eprintln!("wrote {dir} (accuracy.md, .svg, .csv, accuracy-summary.json) in {elapsed:.0} s");
    Ok(())
}
