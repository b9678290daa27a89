//! From the child runs to the table, `results.csv` and the scaling plots.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use kimpact::Mode;
use kimpact_harness::{BenchRow, Method, Panel, write_files};

use crate::cli::name;
use crate::raw::{Group, Header, Measure, Pair, Raw};

/// The median of `v` (the upper middle value of an even count; NaN for
/// none).
pub fn median(mut v: Vec<f64>) -> f64 {
    let mid = v.len() / 2;
    match v.is_empty() {
        true => f64::NAN,
        false => *v.select_nth_unstable_by(mid, f64::total_cmp).1,
    }
}

/// The median of the CPU times per step of `runs`, pooled.
fn median_of<'a>(runs: impl IntoIterator<Item = &'a Measure>) -> f64 {
    median(runs.into_iter().flat_map(|m| &m.cpu_us).copied().collect())
}

/// The sum of `f` over `runs` per measured step.
fn per_step(runs: &[&Measure], f: impl Fn(&Measure) -> u64) -> f64 {
    let steps: usize = runs.iter().map(|m| m.steps).sum();
    runs.iter().map(|m| f(m)).sum::<u64>() as f64 / steps as f64
}

/// The rows of one group (one per mode).
pub fn rows(g: &Group) -> Vec<BenchRow> {
    let all = g.pairs.iter();
    let ok = all.clone().filter_map(|p| Some((p.0, p.1.as_ref().ok()?)));
    let ok: Vec<(Mode, &Pair)> = ok.collect();
    let all_native: Vec<&Measure> = ok.iter().map(|p| &p.1.native).collect();
    let solo = |mode| Some(g.solos.iter().find(|(m, _)| *m == mode)?.1.as_ref());
    let row = |mode| {
        let mine: Vec<&Pair> = ok.iter().filter(|p| p.0 == mode).map(|p| p.1).collect();
        // This mode's measures and native's from the same processes.
        let (law, native): (Vec<&Measure>, Vec<&Measure>) = match mode {
            Mode::Native => (all_native.clone(), all_native.clone()),
            _ => mine.iter().map(|p| (&p.law, &p.native)).unzip(),
        };
        let failed = all.clone().filter(|p| mode == Mode::Native || p.0 == mode);
        let error = failed.filter_map(|(_, p)| p.as_ref().err().cloned()).next();
        let memory_error = || Some(format!("memory run: {}", solo(mode)?.err()?));
        let round = |p: &&Pair| median_of([&p.law]) / median_of([&p.native]);
        let rounds: Vec<f64> = mine.iter().map(round).collect();
        let (median_us, native_median_us) = (median_of(law.clone()), median_of(native.clone()));
        let allocs_per_step = per_step(&law, |m| m.allocs);
        let memory = solo(mode).and_then(Result::ok);
        let share = match memory.and_then(|s| s.attributed) {
            Some((seen, own)) if seen > 0 => own as f64 / seen as f64,
            Some(_) => 0.0,
            None => f64::NAN,
        };
        BenchRow {
            scene: name(g.scene),
            dim: g.scene.dim(),
            precision: g.precision,
            parallel: cfg!(feature = "parallel"),
            balls: g.balls,
            mode,
            rounds: law.len(),
            samples: law.iter().map(|m| m.cpu_us.len()).sum(),
            median_us,
            native_median_us,
            ratio: median_us / native_median_us,
            ratio_min: rounds.iter().copied().fold(f64::NAN, f64::min),
            ratio_max: rounds.iter().copied().fold(f64::NAN, f64::max),
            ratio_median_rounds: median(rounds),
            delta_us: median_us - native_median_us,
            allocs_per_step,
            native_allocs_per_step: per_step(&native, |m| m.allocs),
            kimpact_allocs_per_step: share * allocs_per_step,
            peak_rss_mib: memory.map_or(f64::NAN, |s| s.peak_rss_kib as f64 / 1024.0),
            impacts_per_step: per_step(&law, |m| m.impacts),
            error: error.or_else(memory_error),
        }
    };
    g.modes.iter().map(|&mode| row(mode)).collect()
}

/// A time per step for the tables: three significant digits or so.
pub fn fmt_us(us: f64) -> String {
    match us {
        _ if !us.is_finite() => "—".to_owned(),
        _ if us >= 10_000.0 => format!("{:.1} ms", us / 1000.0),
        _ if us >= 1000.0 => format!("{:.2} ms", us / 1000.0),
        _ if us >= 100.0 => format!("{us:.0} µs"),
        _ if us >= 10.0 => format!("{us:.1} µs"),
        _ => format!("{us:.2} µs"),
    }
}

/// `x` with `digits` decimals, or `?` when it is not a number (allocations
/// not attributed).
pub fn fmt_or_unknown(x: f64, digits: usize) -> String {
    match x.is_finite() {
        true => format!("{x:.digits$}"),
        false => "?".to_owned(),
    }
}

/// The title of a report and the run's command and machine.
pub fn heading(h: &Header, title: &str) -> String {
    let (command, machine) = (&h.command, &h.machine);
    format!("## kimpact-bench {title}\n\n- command: `{command}`\n- machine: {machine}\n")
}

/// The whole report as markdown.
pub fn markdown(h: &Header, rows: &[BenchRow]) -> String {
    let c = &h.cli;
    let (warmup, steps, block, memory_steps) = (c.warmup, c.steps, c.block, c.memory_steps);
    let (small_block, small_repeats) = (c.small_block, c.small_repeats);
    let (rounds, memory_warmup) = (c.rounds.max(1), c.memory_warmup.unwrap_or(warmup));
    let (wall_s, parallel) = (h.wall_s, if h.parallel { "on" } else { "off" });
    let mut s = heading(h, "results");
    s += &format!(
        "- rapier `parallel`: {parallel}; each timing run is one process stepping native rapier and one mode on two copies of the scene in lockstep: {warmup} warm-up steps each, then {steps} measured steps each, alternated in blocks of {block} (native, mode, native, mode…); {rounds} timing run(s) per mode; peak RSS and the attribution of allocations from a separate process per mode running alone ({memory_steps} steps after {memory_warmup} warm-up steps); wall time {wall_s:.0} s\n"
    );
    s += &format!(
        "- small scenes (billiards, restitution3, restitution2, pinball): blocks of {small_block} steps, each timed whole (its time over its steps is one sample), over {small_repeats} episodes per timing run (both worlds built anew, warmed up and measured each time)\n"
    );
    s += "- time/step: median CPU time of one step (process, all threads; native's row: over all its timing runs); native, same runs: native's median in this mode's timing runs; ×native: the ratio of the two (with --rounds > 1, in parentheses: the lowest and highest timing run's ratio; after the semicolon, the median of the runs' ratios); Δ/step: the mode's median minus native's; allocs/step: heap allocations per measured step, all threads (in parentheses: kimpact's own, the share of the memory run's allocations whose stacks lead to kimpact's code, times the total); peak RSS: VmHWM of a process running that mode alone; impacts/step: resolved by the law; notes: a failed run\n\n";
    s += "| scene | prec | balls | mode | time/step | native, same runs | ×native | Δ/step | allocs/step (kimpact's) | peak RSS | impacts/step | notes |\n";
    s += "|---|---|---:|---|---:|---:|---|---:|---:|---:|---:|---|\n";
    for r in rows {
        let native = r.mode == Mode::Native;
        let (lo, hi, mid) = (r.ratio_min, r.ratio_max, r.ratio_median_rounds);
        let ratio = match (native, r.rounds > 1) {
            (true, _) => "1".to_owned(),
            (false, true) => format!("{:.3} ({lo:.2}-{hi:.2}; {mid:.2})", r.ratio),
            (false, false) => format!("{:.3}", r.ratio),
        };
        let (native_us, delta) = match native {
            true => (String::new(), String::new()),
            false => (fmt_us(r.native_median_us), format!("{:+.2} µs", r.delta_us)),
        };
        let own = fmt_or_unknown(r.kimpact_allocs_per_step, 1);
        let (scene, precision, balls, mode) = (&r.scene, r.precision, r.balls, r.mode);
        let (allocs_per_step, peak_rss_mib) = (r.allocs_per_step, r.peak_rss_mib);
        let (time, impacts) = (fmt_us(r.median_us), r.impacts_per_step);
        let notes = r.error.as_deref().unwrap_or_default();
        s += &format!(
            "| {scene} | {precision} | {balls} | {mode} | {time} | {native_us} | {ratio} | {delta} | {allocs_per_step:.1} ({own}) | {peak_rss_mib:.0} MiB | {impacts:.2} | {notes} |\n"
        );
    }
    s
}

/// Time per step against balls, one line per mode (log-log), of the rows
/// of one scene and precision, when they hold several sizes.
fn scaling_svg(rows: &[&BenchRow]) -> Option<Result<String, String>> {
    let sizes = BTreeSet::from_iter(rows.iter().map(|r| r.balls));
    let series = Mode::ALL.map(|m| {
        let mine = rows.iter().filter(|r| r.mode == m);
        let points = mine.map(|r| (r.balls as f64, r.median_us / 1000.0));
        (Method::Rapier(m), points.collect())
    });
    let r = rows.first()?;
    let parallel = if r.parallel { ", parallel" } else { "" };
    let panel = Panel {
        title: format!("{} ({}{parallel}): time per step", r.scene, r.precision),
        x_label: "balls".to_owned(),
        y_label: "median time per step (ms)".to_owned(),
        log_x: true,
        dots: true,
        legend: plotters::chart::SeriesLabelPosition::UpperLeft,
        series: series.into(),
    };
    (sizes.len() > 1).then(|| kimpact_harness::svg(&[panel], 1, (800, 500)))
}

/// `rows` as CSV, through serde.
pub fn csv<T: serde::Serialize>(rows: &[T]) -> Vec<u8> {
    let mut csv = csv::Writer::from_writer(Vec::new());
    rows.iter()
        .for_each(|r| csv.serialize(r).expect("a row serializes"));
    csv.into_inner().expect("a Vec takes every byte")
}

/// Write `files` whole (`write_files`), saying so on stderr.
pub fn write(dir: &Path, files: &[(PathBuf, Vec<u8>)]) -> ExitCode {
    if let Err(e) = write_files(files) {
        eprintln!("{e}");
        return ExitCode::FAILURE;
    }
    eprintln!("wrote {}", dir.display());
    ExitCode::SUCCESS
}

/// Print the table of `raw` and write `results.md`, `results.csv` and the
/// scaling plots into `dir`, whole.
pub fn render(dir: &Path, raw: &Raw) -> ExitCode {
    let rows: Vec<BenchRow> = raw.groups.iter().flat_map(rows).collect();
    let markdown = markdown(&raw.header, &rows);
    println!("{markdown}");
    let mut files = vec![
        (dir.join("results.md"), markdown.into_bytes()),
        (dir.join("results.csv"), csv(&rows)),
    ];
    if let Some(stages) = crate::stages::markdown(raw) {
        println!("{stages}");
        files.push((dir.join("stages.md"), stages.into_bytes()));
    }
    for key in BTreeSet::from_iter(rows.iter().map(|r| (&r.scene, r.precision))) {
        let mine = rows.iter().filter(|r| (&r.scene, r.precision) == key);
        let mine: Vec<&BenchRow> = mine.collect();
        match scaling_svg(&mine) {
            Some(Ok(svg)) => files.push((
                dir.join(format!("scaling-{}-{}.svg", key.0, key.1)),
                svg.into(),
            )),
            Some(Err(e)) => eprintln!("plot of {} {}: {e}", key.0, key.1),
            None => {}
        }
    }
    write(dir, &files)
}
