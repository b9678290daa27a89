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
//! mode, an [`kimpact_harness::AccuracySummary`]). The simulators, scenes and
//! measurements are the `kimpact_harness` library of this package.

mod experiments;
mod format;
mod plot;
mod report;
mod z;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use clap::Parser;
use kimpact_harness::{
    AccuracySummary, B2_F32, B2_F64, B3_F32, B3_F64, HarnessError, Method, WriteError, write_files,
};
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

/// What can stop a run.
#[derive(Debug, thiserror::Error)]
enum RunError {
    #[error(transparent)]
    Harness(#[from] HarnessError),
    #[error("{0}")]
    Output(String),
    #[error(transparent)]
    Write(#[from] WriteError),
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

/// The accuracy jobs, longest first: the reference's Z runs (once per case:
/// it has no precision to vary), then rapier's in 3D, then in 2D (every mode
/// in both precisions), the gases, the cooling gases and the short scenes.
fn jobs<'a>(sizes: &'a Sizes) -> Result<Vec<Job<'a>>, HarnessError> {
    let mut jobs: Vec<Job<'a>> = Vec::new();
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
        z_job(B3_F64, (0.3, n3_large, ell3_large), r, sizes)
    }));
    jobs.push(Box::new(move || z_job(B3_F64, (0.3, n3, ell3), r, sizes)));
    for (i, eta) in [0.3, 0.5].into_iter().enumerate() {
        let n = n2[i];
        jobs.push(Box::new(move || z_job(B2_F64, (eta, n, ell2), r, sizes)));
    }
    for m in Method::RAPIER {
        for b in [B3_F32, B3_F64] {
            jobs.push(Box::new(move || z_job(b, (0.3, n3, ell3), m, sizes)));
        }
    }
    for (i, eta) in [0.3, 0.5].into_iter().enumerate() {
        let n = n2[i];
        for m in Method::RAPIER {
            for b in [B2_F32, B2_F64] {
                jobs.push(Box::new(move || z_job(b, (eta, n, ell2), m, sizes)));
            }
        }
    }
    // The gases, the cooling gases and the short scenes in every build.
    macro_rules! each_build {
        (|$b:ident| $job:expr) => {{
            jobs.push(Box::new(move || {
                let $b = B2_F32;
                $job
            }));
            jobs.push(Box::new(move || {
                let $b = B2_F64;
                $job
            }));
            jobs.push(Box::new(move || {
                let $b = B3_F32;
                $job
            }));
            jobs.push(Box::new(move || {
                let $b = B3_F64;
                $job
            }));
        }};
    }
    for m in Method::RAPIER {
        each_build!(|b| gas_jobs(b, m, sizes));
    }
    each_build!(|b| cooling_jobs(b, sizes));
    each_build!(|b| short_jobs(b));
    Ok(jobs)
}

fn run(args: &Args) -> Result<(), RunError> {
    let sizes = Sizes::new(args.quick);
    let sizes = &sizes;
    let started = Instant::now();

    // Phase 1: accuracy (jobs on `--threads` threads, longest first; their
    // timings share the cores).
    let jobs = jobs(sizes)?;
    let (total, done) = (jobs.len(), AtomicUsize::new(0));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.max(1))
        .build()
        .map_err(|e| RunError::Output(format!("cannot start the worker threads: {e}")))?;
    let outs: Result<Vec<Out>, HarnessError> = pool.install(|| {
        let run = |job: Job<'_>| {
            let out = job();
            let k = done.fetch_add(1, Ordering::SeqCst) + 1;
            let t = started.elapsed().as_secs_f64();
            eprintln!("[{t:>6.1}s] {k}/{total} jobs");
            out
        };
        // One job per task, taken in order: the longest start first.
        jobs.into_par_iter().with_max_len(1).map(run).collect()
    });
    let mut all = Out::default();
    outs?.into_iter().for_each(|o| all.absorb(o));
    // Phase 2: the cost of accuracy, one job at a time so that the timings
    // do not share the cores with other jobs of this program.
    let t = started.elapsed().as_secs_f64();
    eprintln!("[{t:>6.1}s] cost of accuracy (one thread)");
    all.absorb(cost_jobs(B2_F32, sizes)?);
    all.absorb(cost_jobs(B2_F64, sizes)?);
    all.absorb(cost_jobs(B3_F32, sizes)?);
    all.absorb(cost_jobs(B3_F64, sizes)?);
    let elapsed = started.elapsed().as_secs_f64();

    let mut tables: BTreeMap<String, Vec<Vec<String>>> = BTreeMap::new();
    for (k, r) in all.rows {
        tables.entry(k).or_default().push(r);
    }
    let (z_main, z_checks) = report::z_tables(&all.z);
    tables.insert("z".to_owned(), z_main);
    tables.insert("z_checks".to_owned(), z_checks);
    all.errors.extend(z_summary(&all.z));
    let mut csv = csv::Writer::from_writer(Vec::new());
    let csv_error = |e: csv::Error| RunError::Output(e.to_string());
    csv.write_record(experiments::CSV_HEADER)
        .map_err(csv_error)?;
    for row in &all.csv {
        csv.serialize(row).map_err(csv_error)?;
    }
    let csv = csv
        .into_inner()
        .map_err(|e| RunError::Output(e.to_string()))?;
    let (points, notes) = (all.points, all.notes);
    let errors = all.errors;

    let svg = kimpact_harness::svg(&plot::panels(&points, sizes.gas_n), 3, (460, 320))
        .map_err(|e| RunError::Output(format!("plot: {e}")))?;
    let summary = AccuracySummary {
        command: report::command(args.quick),
        quick: args.quick,
        errors,
    };
    let summary = serde_json::to_string_pretty(&summary).expect("the summary serializes") + "\n";
    let dir = &args.out;
    // The hand-written findings between the markers survive regeneration.
    let md_path = dir.join("accuracy.md");
    let old = std::fs::read_to_string(&md_path).ok();
    let doc = report::document(&report::Document {
        tables: &tables,
        findings: &report::findings(old.as_deref()),
        notes: &notes,
        quick: args.quick,
        threads: args.threads,
        elapsed,
        sizes,
    });
    let (svg_path, csv_path) = (dir.join("accuracy.svg"), dir.join("accuracy.csv"));
    let json_path = dir.join("accuracy-summary.json");
    write_files(&[
        (&svg_path, svg.as_bytes()),
        (&csv_path, &csv),
        (&json_path, summary.as_bytes()),
        (&md_path, doc.as_bytes()),
    ])?;
    eprintln!(
        "wrote {} (accuracy.md, .svg, .csv, accuracy-summary.json) in {elapsed:.0} s",
        dir.display()
    );
    Ok(())
}
