//! From the child runs to the table, the CSV, the plots and the budgets.

use std::fmt::Write as _;
use std::path::Path;

use plotters::prelude::*;
use serde::{Deserialize, Serialize};

use crate::{Clock, Measure, Mode, Pair, Precision, Scene, Solo};

/// The runs of one scene, size and precision.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Group {
    pub clock: Clock,
    pub parallel: bool,
    pub scene: Scene,
    pub precision: Precision,
    pub balls: usize,
    /// Every mode of the table (native first).
    pub modes: Vec<Mode>,
    /// Timing children: native and a mode in lockstep.
    pub pairs: Vec<(Mode, Result<Pair, String>)>,
    /// Memory children: each mode alone.
    pub solos: Vec<(Mode, Result<Solo, String>)>,
}

/// One line of the table and of the CSV.
#[derive(Clone, Debug)]
pub struct Row {
    pub scene: Scene,
    pub precision: Precision,
    pub parallel: bool,
    pub balls: usize,
    pub mode: Mode,
    pub rounds: usize,
    pub samples: usize,
    pub clock: Clock,
    /// Median time per step by the chosen clock (the p10/p90 too).
    pub median_us: f64,
    pub wall_median_us: f64,
    pub cpu_median_us: f64,
    pub p10_us: f64,
    pub p90_us: f64,
    pub native_median_us: f64,
    /// Median of this mode over median of native, all rounds pooled.
    pub ratio: f64,
    /// `median_us − native_median_us`: what the mode adds to a step.
    pub delta_us: f64,
    /// Goal 3 of issue 26, for a small scene's law mode: within 1.15x
    /// native or within 1 µs per step of it, whichever is larger.
    pub small_goal: Option<bool>,
    /// The same ratio per round: its smallest and largest value, and the
    /// median of the rounds' ratios (on a host whose load changes between
    /// rounds, the pooled ratio can fall outside every round's).
    pub ratio_min: f64,
    pub ratio_max: f64,
    pub ratio_median_rounds: f64,
    pub allocs_per_step: f64,
    pub alloc_bytes_per_step: f64,
    pub native_allocs_per_step: f64,
    /// `allocs_per_step − native_allocs_per_step`: kimpact's share (rapier's
    /// own allocations also differ when the trajectories differ).
    pub extra_allocs_per_step: f64,
    /// The share of the allocations whose stacks lead to kimpact's own code
    /// (every allocation of the memory run's measured steps classified;
    /// NaN: not attributed), that share of `allocs_per_step`, and
    /// (kimpact's, classified) allocations.
    pub kimpact_alloc_share: f64,
    pub kimpact_allocs_per_step: f64,
    pub attr_sampled: (u64, u64),
    pub peak_rss_mib: f64,
    pub native_peak_rss_mib: f64,
    pub impacts_per_step: f64,
    /// Relative energy change over the measured steps (kinetic + potential
    /// from the floor), the largest in magnitude over the rounds.
    pub energy_rel_change: f64,
    pub non_finite: usize,
    pub escaped: usize,
    pub cap_hits: u64,
    pub skipped: u64,
    pub awake_end: usize,
    pub error: Option<String>,
}

/// The CSV's columns, in order.
pub const COLUMNS: [&str; 39] = [
    "scene",
    "dim",
    "precision",
    "parallel",
    "balls",
    "mode",
    "rounds",
    "samples",
    "clock",
    "median_us",
    "wall_median_us",
    "cpu_median_us",
    "p10_us",
    "p90_us",
    "native_median_us",
    "ratio",
    "ratio_min",
    "ratio_max",
    "ratio_median_rounds",
    "delta_us",
    "small_goal",
    "allocs_per_step",
    "alloc_bytes_per_step",
    "native_allocs_per_step",
    "extra_allocs_per_step",
    "kimpact_alloc_share",
    "kimpact_allocs_per_step",
    "attr_kimpact_backtraces",
    "attr_classified_backtraces",
    "peak_rss_mib",
    "native_peak_rss_mib",
    "impacts_per_step",
    "energy_rel_change",
    "non_finite",
    "escaped",
    "cap_hits",
    "skipped",
    "awake_end",
    "error",
];

fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let pos = q * (sorted.len() - 1) as f64;
    let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
    sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64)
}

fn sorted_times<'a>(runs: impl IntoIterator<Item = &'a Measure>, clock: Clock) -> Vec<f64> {
    let mut t: Vec<f64> = runs
        .into_iter()
        .flat_map(|m| match clock {
            Clock::Wall => m.times_us.iter().copied(),
            Clock::Cpu => m.cpu_us.iter().copied(),
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t
}

fn median_of(m: &Measure, clock: Clock) -> f64 {
    quantile(&sorted_times([m], clock), 0.5)
}

fn per_step(measures: &[&Measure], f: impl Fn(&Measure) -> u64) -> f64 {
    let steps: usize = measures.iter().map(|m| m.steps).sum();
    if steps == 0 {
        f64::NAN
    } else {
        measures.iter().map(|m| f(m)).sum::<u64>() as f64 / steps as f64
    }
}

/// The rows of one group (one per mode).
pub fn rows(group: &Group) -> Vec<Row> {
    let clock = group.clock;
    let solo = |mode: Mode| {
        group
            .solos
            .iter()
            .find(|(m, _)| *m == mode)
            .and_then(|(_, s)| s.as_ref().ok())
    };
    let all_native: Vec<&Measure> = group
        .pairs
        .iter()
        .filter_map(|(_, p)| p.as_ref().ok())
        .map(|p| &p.native)
        .collect();
    group
        .modes
        .iter()
        .map(|&mode| {
            // This mode's runs (native: all of them).
            let runs = || {
                group
                    .pairs
                    .iter()
                    .filter(move |(m, _)| mode == Mode::Native || *m == mode)
            };
            let mine: Vec<&Pair> = runs().filter_map(|(_, p)| p.as_ref().ok()).collect();
            // This mode's measures and native's from the same processes.
            let (law, reference): (Vec<&Measure>, Vec<&Measure>) = if mode == Mode::Native {
                (all_native.clone(), all_native.clone())
            } else {
                mine.iter().map(|p| (&p.law, &p.native)).unzip()
            };
            let error = runs()
                .find_map(|(_, p)| p.as_ref().err().cloned())
                .or_else(|| {
                    group
                        .solos
                        .iter()
                        .filter(|(m, _)| *m == mode)
                        .find_map(|(_, s)| s.as_ref().err().map(|e| format!("memory run: {e}")))
                });
            let times = sorted_times(law.iter().copied(), clock);
            let median = quantile(&times, 0.5);
            let native_median = quantile(&sorted_times(reference.iter().copied(), clock), 0.5);
            // Each round's ratio, sorted (for the median of rounds).
            let mut per_round: Vec<f64> = if mode == Mode::Native {
                Vec::new()
            } else {
                mine.iter()
                    .map(|p| median_of(&p.law, clock) / median_of(&p.native, clock))
                    .collect()
            };
            per_round.sort_by(f64::total_cmp);
            let allocs = per_step(&law, |m| m.allocs);
            let native_allocs = per_step(&reference, |m| m.allocs);
            // kimpact's share of the allocations (the memory run's, each
            // classified from its stack), applied to the allocations of the
            // timed steps.
            let (share, sampled) = match solo(mode) {
                Some(s) if s.attributed && s.attr_sampled > 0 => (
                    s.attr_own as f64 / s.attr_sampled as f64,
                    (s.attr_own, s.attr_sampled),
                ),
                Some(s) if s.attributed => (0.0, (0, 0)),
                _ => (f64::NAN, (0, 0)),
            };
            let energy = law
                .iter()
                .map(|m| (m.energy_end - m.energy_start) / m.energy_start.abs())
                .fold(0.0_f64, |acc, x| {
                    if x.is_nan() || x.abs() > acc.abs() {
                        x
                    } else {
                        acc
                    }
                });
            let mib = |s: Option<&Solo>| s.map_or(f64::NAN, |s| s.peak_rss_kib as f64 / 1024.0);
            Row {
                scene: group.scene,
                precision: group.precision,
                parallel: group.parallel,
                balls: group.balls,
                mode,
                rounds: law.len(),
                samples: times.len(),
                clock,
                median_us: median,
                wall_median_us: quantile(&sorted_times(law.iter().copied(), Clock::Wall), 0.5),
                cpu_median_us: quantile(&sorted_times(law.iter().copied(), Clock::Cpu), 0.5),
                p10_us: quantile(&times, 0.1),
                p90_us: quantile(&times, 0.9),
                native_median_us: native_median,
                ratio: median / native_median,
                delta_us: median - native_median,
                small_goal: (group.scene.small() && mode != Mode::Native && median.is_finite())
                    .then(|| within_small_goal(median, native_median)),
                ratio_min: per_round.iter().copied().fold(f64::NAN, f64::min),
                ratio_max: per_round.iter().copied().fold(f64::NAN, f64::max),
                ratio_median_rounds: quantile(&per_round, 0.5),
                allocs_per_step: allocs,
                alloc_bytes_per_step: per_step(&law, |m| m.alloc_bytes),
                native_allocs_per_step: native_allocs,
                extra_allocs_per_step: allocs - native_allocs,
                kimpact_alloc_share: share,
                kimpact_allocs_per_step: share * allocs,
                attr_sampled: sampled,
                peak_rss_mib: mib(solo(mode)),
                native_peak_rss_mib: mib(solo(Mode::Native)),
                impacts_per_step: per_step(&law, |m| m.impacts),
                energy_rel_change: energy,
                non_finite: law.iter().map(|m| m.non_finite).max().unwrap_or(0),
                escaped: law.iter().map(|m| m.escaped).max().unwrap_or(0),
                cap_hits: law.iter().map(|m| m.cap_hits).sum(),
                skipped: law.iter().map(|m| m.skipped).sum(),
                awake_end: law.first().map_or(0, |m| m.awake_end),
                error,
            }
        })
        .collect()
}

/// Goal 3 of issue 26: a small scene's step within 1.15x native's or within
/// 1 µs of it, whichever is larger.
pub fn within_small_goal(median_us: f64, native_us: f64) -> bool {
    median_us <= (1.15 * native_us).max(native_us + 1.0)
}

/// What the table's header says about the run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Header {
    pub command: String,
    pub machine: String,
    pub parallel: bool,
    pub clock: Clock,
    pub steps: usize,
    pub warmup: usize,
    pub rounds: usize,
    pub block: usize,
    /// Steps per block in the small scenes (each block timed whole).
    #[serde(default)]
    pub small_block: usize,
    /// Episodes per timing run of a small scene.
    #[serde(default)]
    pub small_repeats: usize,
    pub memory_steps: usize,
    /// Warm-up steps of the memory runs (`None`: the timing runs').
    #[serde(default)]
    pub memory_warmup: Option<usize>,
    pub wall_s: f64,
}

/// A budget of the issue, judged on the rows of this run.
pub struct Verdict {
    pub budget: String,
    pub config: String,
    pub measured: String,
    pub pass: Option<bool>,
}

fn find(rows: &[Row], scene: Scene, balls: usize, mode: Mode, p: Precision) -> Option<&Row> {
    rows.iter()
        .find(|r| r.scene == scene && r.balls == balls && r.mode == mode && r.precision == p)
}

/// The budgets of issue 6 that this run measured.
pub fn budgets(rows: &[Row]) -> Vec<Verdict> {
    let mut out = Vec::new();
    let mut precisions: Vec<Precision> = rows.iter().map(|r| r.precision).collect();
    precisions.sort_unstable();
    precisions.dedup();
    let ratio_budget = |out: &mut Vec<Verdict>, name: &str, limit: f64, r: &Row| {
        let ok = r.error.is_none() && r.ratio.is_finite();
        out.push(Verdict {
            budget: format!("{name} ≤ {limit:.2}x"),
            config: format!("{} {} {}", r.scene.name(), r.balls, r.precision.name()),
            measured: if ok && r.rounds > 1 {
                format!(
                    "{:.3}x (runs {:.3}-{:.3}, median of runs {:.3})",
                    r.ratio, r.ratio_min, r.ratio_max, r.ratio_median_rounds
                )
            } else if ok {
                format!("{:.3}x", r.ratio)
            } else {
                format!("failed: {}", r.error.clone().unwrap_or_default())
            },
            pass: Some(ok && r.ratio <= limit),
        });
    };
    for &p in &precisions {
        if let Some(r) = find(rows, Scene::Pit3d, 10_000, Mode::Restitution, p) {
            ratio_budget(&mut out, "restitution", 1.10, r);
        }
        for scene in [Scene::Pit3d, Scene::Pit2d, Scene::Gas3d, Scene::Gas2d] {
            if let Some(r) = find(rows, scene, 10_000, Mode::Exact, p) {
                ratio_budget(&mut out, "exact", 1.5, r);
            }
        }
        for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
            if let Some(r) = find(rows, Scene::Cue, 10_000, mode, p) {
                ratio_budget(&mut out, &format!("cue ball, {}", mode.name()), 1.05, r);
            }
        }
    }
    // Goal 3 of issue 26: every law mode of a small scene within 1.15x
    // native or 1 µs per step of it, whichever is larger.
    for r in rows.iter().filter(|r| r.small_goal.is_some()) {
        let ok = r.error.is_none() && r.small_goal == Some(true);
        out.push(Verdict {
            budget: format!("small scene, {}: ≤ max(1.15x, +1 µs)", r.mode.name()),
            config: format!("{} {} {}", r.scene.name(), r.balls, r.precision.name()),
            measured: format!(
                "{:.3}x, {:+.2} µs/step ({:.2} against {:.2} µs)",
                r.ratio, r.delta_us, r.median_us, r.native_median_us
            ),
            pass: Some(ok),
        });
    }
    // The gas's energy in exact mode, f64.
    for r in rows.iter().filter(|r| {
        matches!(r.scene, Scene::Gas2d | Scene::Gas3d)
            && r.mode == Mode::Exact
            && r.precision == Precision::F64
    }) {
        out.push(Verdict {
            budget: "exact gas energy |ΔE/E| ≤ 1e-9 (f64)".to_owned(),
            config: format!("{} {} f64", r.scene.name(), r.balls),
            measured: format!(
                "{:.2e} over {} steps",
                r.energy_rel_change,
                r.samples / r.rounds.max(1)
            ),
            pass: Some(r.error.is_none() && r.energy_rel_change.abs() <= 1e-9),
        });
    }
    // No allocation per step in kimpact's own code: attributed from
    // stacks where available (see alloc.rs), else the total per step of
    // each law mode against native's (which also counts rapier's reaction to
    // different trajectories). Worst scene per mode.
    for mode in Mode::ALL {
        let mine: Vec<&Row> = rows
            .iter()
            .filter(|r| r.mode == mode && r.error.is_none())
            .collect();
        let attributed = mine
            .iter()
            .filter(|r| r.kimpact_allocs_per_step.is_finite())
            .max_by(|a, b| {
                a.kimpact_allocs_per_step
                    .total_cmp(&b.kimpact_allocs_per_step)
            });
        if let Some(r) = attributed {
            out.push(Verdict {
                budget: format!("no allocation per step in kimpact's code ({})", mode.name()),
                config: format!(
                    "worst: {} {} {}",
                    r.scene.name(),
                    r.balls,
                    r.precision.name()
                ),
                measured: format!(
                    "{:.2} of {:.1} allocs/step ({} of {} allocations of the memory run in kimpact's code; native {:.1}/step)",
                    r.kimpact_allocs_per_step,
                    r.allocs_per_step,
                    r.attr_sampled.0,
                    r.attr_sampled.1,
                    r.native_allocs_per_step
                ),
                pass: Some(r.kimpact_allocs_per_step == 0.0),
            });
            continue;
        }
        if mode == Mode::Native {
            continue;
        }
        let worst = mine
            .iter()
            .filter(|r| r.extra_allocs_per_step.is_finite())
            .max_by(|a, b| a.extra_allocs_per_step.total_cmp(&b.extra_allocs_per_step));
        if let Some(r) = worst {
            out.push(Verdict {
                budget: format!(
                    "no allocation per step in kimpact ({}, vs native)",
                    mode.name()
                ),
                config: format!(
                    "worst: {} {} {}",
                    r.scene.name(),
                    r.balls,
                    r.precision.name()
                ),
                measured: format!(
                    "{:+.2} allocs/step vs native ({:.2} vs {:.2}); not attributed",
                    r.extra_allocs_per_step, r.allocs_per_step, r.native_allocs_per_step
                ),
                pass: Some(r.extra_allocs_per_step <= 0.0),
            });
        }
    }
    out.push(Verdict {
        budget: "core law ≥ 50 M impacts/s (f64, 3D)".to_owned(),
        config: "cargo bench -p kimpact --bench law".to_owned(),
        measured: "not measured here".to_owned(),
        pass: None,
    });
    out
}

/// A time per step for the tables: three significant digits or so.
pub fn fmt_us(us: f64) -> String {
    if !us.is_finite() {
        "—".to_owned()
    } else if us >= 10_000.0 {
        format!("{:.1} ms", us / 1000.0)
    } else if us >= 1000.0 {
        format!("{:.2} ms", us / 1000.0)
    } else if us >= 100.0 {
        format!("{us:.0} µs")
    } else if us >= 10.0 {
        format!("{us:.1} µs")
    } else {
        format!("{us:.2} µs")
    }
}

/// A difference of times per step, signed, in µs.
pub fn fmt_delta_us(us: f64) -> String {
    if !us.is_finite() {
        "—".to_owned()
    } else if us.abs() >= 100.0 {
        format!("{us:+.0} µs")
    } else {
        format!("{us:+.2} µs")
    }
}

/// The log-log slope of time per step against balls, per scene, precision
/// and mode, between the smallest and the largest size measured.
fn slopes(rows: &[Row]) -> Vec<(Scene, Precision, Mode, f64, f64)> {
    let mut out = Vec::new();
    let mut keys: Vec<(Scene, Precision, Mode)> = rows
        .iter()
        .map(|r| (r.scene, r.precision, r.mode))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    let slope = |scene, p, mode| -> Option<f64> {
        let mut pts: Vec<&Row> = rows
            .iter()
            .filter(|r| {
                r.scene == scene && r.precision == p && r.mode == mode && r.median_us.is_finite()
            })
            .collect();
        pts.sort_by_key(|r| r.balls);
        let (a, b) = (pts.first()?, pts.last()?);
        (b.balls > a.balls)
            .then(|| (b.median_us / a.median_us).ln() / (b.balls as f64 / a.balls as f64).ln())
    };
    for (scene, p, mode) in keys {
        if let (Some(s), Some(n)) = (slope(scene, p, mode), slope(scene, p, Mode::Native)) {
            out.push((scene, p, mode, s, n));
        }
    }
    out
}

/// The whole report as markdown.
pub fn markdown(h: &Header, rows: &[Row]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "## kimpact-bench results\n");
    let _ = writeln!(s, "- command: `{}`", h.command);
    let _ = writeln!(s, "- machine: {}", h.machine);
    let _ = writeln!(
        s,
        "- rapier `parallel`: {}; each timing run is one process stepping native rapier and one mode on two copies of the scene in lockstep: {} warm-up steps each, then {} measured steps each, alternated in blocks of {} (native, mode, native, mode…); {} timing run(s) per mode; peak RSS and the attribution of allocations from a separate process per mode running alone ({} steps after {} warm-up steps); wall time {:.0} s",
        if h.parallel { "on" } else { "off" },
        h.warmup,
        h.steps,
        h.block,
        h.rounds,
        h.memory_steps,
        h.memory_warmup.unwrap_or(h.warmup),
        h.wall_s
    );
    if h.small_block > 0 {
        let _ = writeln!(
            s,
            "- small scenes (billiards, restitution3, restitution2, pinball): blocks of {} steps, each timed whole (its time over its steps is one sample), over {} episodes per timing run (both worlds built anew, warmed up and measured each time); Δ/step: the mode's median minus native's; goal 3 of issue 26 (✓/✗ in the notes): within 1.15x native or within 1 µs per step of it, whichever is larger",
            h.small_block, h.small_repeats
        );
    }
    let _ = writeln!(
        s,
        "- time/step: median {} time of one step (native's row: over all its timing runs, which differ from each other on a loaded machine); native, same runs: native's median in this mode's timing runs; ×native: the ratio of the two (with --rounds > 1, in parentheses: the lowest and highest timing run's ratio; after the semicolon, the median of the runs' ratios); allocs/step: heap allocations per measured step, all threads (in parentheses: kimpact's own, that is the share of the memory run's allocations whose stacks lead to kimpact's code, every one classified, times the total); peak RSS: VmHWM of a process running that mode alone; impacts/step: resolved by the law; ΔE/E: energy change (kinetic + potential from the floor) over the measured steps\n",
        if h.clock == Clock::Cpu {
            "CPU (process, all threads; the CSV also has wall time)"
        } else {
            "wall (the CSV also has CPU time)"
        }
    );
    let _ = writeln!(
        s,
        "| scene | prec | balls | mode | time/step | native, same runs | ×native | Δ/step | allocs/step (kimpact's) | peak RSS | impacts/step | ΔE/E | notes |"
    );
    let _ = writeln!(
        s,
        "|---|---|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---|"
    );
    for r in rows {
        let mut notes = Vec::new();
        if let Some(e) = &r.error {
            notes.push(e.clone());
        }
        if r.non_finite > 0 {
            notes.push(format!("{} non-finite", r.non_finite));
        }
        if r.escaped > 0 {
            notes.push(format!("{} escaped", r.escaped));
        }
        if r.cap_hits > 0 {
            notes.push(format!("{} event-cap hits", r.cap_hits));
        }
        if r.skipped > 0 {
            notes.push(format!("{} skipped pairs", r.skipped));
        }
        match r.small_goal {
            Some(true) => notes.push("goal 3 ✓".to_owned()),
            Some(false) => notes.push("goal 3 ✗".to_owned()),
            None => {}
        }
        let ratio = if r.mode == Mode::Native {
            "1".to_owned()
        } else {
            if r.rounds > 1 {
                format!(
                    "{:.3} ({:.2}-{:.2}; {:.2})",
                    r.ratio, r.ratio_min, r.ratio_max, r.ratio_median_rounds
                )
            } else {
                format!("{:.3}", r.ratio)
            }
        };
        let allocs = if r.kimpact_allocs_per_step.is_finite() {
            format!(
                "{:.1} ({:.1})",
                r.allocs_per_step, r.kimpact_allocs_per_step
            )
        } else {
            format!("{:.1} (?)", r.allocs_per_step)
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.0} MiB | {:.2} | {:.1e} | {} |",
            r.scene.name(),
            r.precision.name(),
            r.balls,
            r.mode.name(),
            fmt_us(r.median_us),
            if r.mode == Mode::Native {
                String::new()
            } else {
                fmt_us(r.native_median_us)
            },
            ratio,
            if r.mode == Mode::Native {
                String::new()
            } else {
                fmt_delta_us(r.delta_us)
            },
            allocs,
            r.peak_rss_mib,
            r.impacts_per_step,
            r.energy_rel_change,
            notes.join("; ")
        );
    }
    let verdicts = budgets(rows);
    let _ = writeln!(s, "\n### Budgets (issue 6)\n");
    let _ = writeln!(s, "| budget | configuration | measured | result |");
    let _ = writeln!(s, "|---|---|---|---|");
    for v in &verdicts {
        let result = match v.pass {
            Some(true) => "PASS",
            Some(false) => "MISS",
            None => "n/a",
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {result} |",
            v.budget, v.config, v.measured
        );
    }
    let slopes = slopes(rows);
    if !slopes.is_empty() {
        let _ = writeln!(
            s,
            "\n### Scaling (log-log slope of time per step against balls)\n"
        );
        let _ = writeln!(s, "| scene | prec | mode | slope | native's slope |");
        let _ = writeln!(s, "|---|---|---|---:|---:|");
        for (scene, p, mode, slope, native) in slopes {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {slope:.2} | {native:.2} |",
                scene.name(),
                p.name(),
                mode.name()
            );
        }
    }
    s
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// The rows as CSV, with [`COLUMNS`] as header.
pub fn csv(rows: &[Row]) -> String {
    let mut s = COLUMNS.join(",");
    s.push('\n');
    for r in rows {
        let fields = [
            r.scene.name().to_owned(),
            r.scene.dim().to_string(),
            r.precision.name().to_owned(),
            r.parallel.to_string(),
            r.balls.to_string(),
            r.mode.name().to_owned(),
            r.rounds.to_string(),
            r.samples.to_string(),
            r.clock.name().to_owned(),
            format!("{:.3}", r.median_us),
            format!("{:.3}", r.wall_median_us),
            format!("{:.3}", r.cpu_median_us),
            format!("{:.3}", r.p10_us),
            format!("{:.3}", r.p90_us),
            format!("{:.3}", r.native_median_us),
            format!("{:.4}", r.ratio),
            format!("{:.4}", r.ratio_min),
            format!("{:.4}", r.ratio_max),
            format!("{:.4}", r.ratio_median_rounds),
            format!("{:.4}", r.delta_us),
            r.small_goal.map_or(String::new(), |ok| {
                if ok { "pass" } else { "miss" }.to_owned()
            }),
            format!("{:.3}", r.allocs_per_step),
            format!("{:.1}", r.alloc_bytes_per_step),
            format!("{:.3}", r.native_allocs_per_step),
            format!("{:.3}", r.extra_allocs_per_step),
            format!("{:.5}", r.kimpact_alloc_share),
            format!("{:.3}", r.kimpact_allocs_per_step),
            r.attr_sampled.0.to_string(),
            r.attr_sampled.1.to_string(),
            format!("{:.2}", r.peak_rss_mib),
            format!("{:.2}", r.native_peak_rss_mib),
            format!("{:.4}", r.impacts_per_step),
            format!("{:.3e}", r.energy_rel_change),
            r.non_finite.to_string(),
            r.escaped.to_string(),
            r.cap_hits.to_string(),
            r.skipped.to_string(),
            r.awake_end.to_string(),
            csv_field(r.error.as_deref().unwrap_or("")),
        ];
        s.push_str(&fields.join(","));
        s.push('\n');
    }
    s
}

fn color(mode: Mode) -> RGBColor {
    match mode {
        Mode::Native => RGBColor(0, 0, 0),
        Mode::Restitution => RGBColor(31, 119, 180),
        Mode::Impulse => RGBColor(255, 127, 14),
        Mode::Exact => RGBColor(214, 39, 40),
    }
}

/// Time per step against balls, one line per mode (log-log), for one scene
/// and precision; `None` when fewer than two sizes were measured.
pub fn scaling_svg(rows: &[Row], scene: Scene, p: Precision) -> Result<Option<String>, String> {
    let mine: Vec<&Row> = rows
        .iter()
        .filter(|r| {
            r.scene == scene && r.precision == p && r.median_us.is_finite() && r.median_us > 0.0
        })
        .collect();
    let mut sizes: Vec<usize> = mine.iter().map(|r| r.balls).collect();
    sizes.sort_unstable();
    sizes.dedup();
    if sizes.len() < 2 {
        return Ok(None);
    }
    let ms = |r: &Row| r.median_us / 1000.0;
    let (x0, x1) = (sizes[0] as f64 / 1.3, sizes[sizes.len() - 1] as f64 * 1.3);
    let y0 = mine.iter().map(|r| ms(r)).fold(f64::INFINITY, f64::min) / 1.5;
    let y1 = mine.iter().map(|r| ms(r)).fold(0.0, f64::max) * 1.5;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (800, 500)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let parallel = if cfg!(feature = "parallel") {
            ", parallel"
        } else {
            ""
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("{} ({}{parallel}): time per step", scene.name(), p.name()),
                ("sans-serif", 22),
            )
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .light_line_style(WHITE.mix(0.0))
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| {
                if *y >= 10.0 {
                    format!("{y:.0}")
                } else if *y >= 1.0 {
                    format!("{y:.1}")
                } else {
                    format!("{y:.3}")
                }
            })
            .x_desc("balls")
            .y_desc("median time per step (ms)")
            .draw()
            .map_err(|e| e.to_string())?;
        for mode in Mode::ALL {
            let mut pts: Vec<(f64, f64)> = mine
                .iter()
                .filter(|r| r.mode == mode)
                .map(|r| (r.balls as f64, ms(r)))
                .collect();
            if pts.is_empty() {
                continue;
            }
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let c = color(mode);
            chart
                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                .map_err(|e| e.to_string())?
                .label(mode.name())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                });
            chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, c.filled())))
                .map_err(|e| e.to_string())?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(Some(out))
}

/// Everything a run measured: `raw.json` in the output folder, from which
/// `--rerender` rebuilds the table, the CSV and the plots.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Raw {
    pub header: Header,
    pub groups: Vec<Group>,
}

/// Write results.md, results.csv and the scaling plots into `dir`.
pub fn write_all(dir: &Path, markdown: &str, rows: &[Row]) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("results.md"), markdown)?;
    std::fs::write(dir.join("results.csv"), csv(rows))?;
    let mut keys: Vec<(Scene, Precision)> = rows.iter().map(|r| (r.scene, r.precision)).collect();
    keys.sort_unstable();
    keys.dedup();
    for (scene, p) in keys {
        match scaling_svg(rows, scene, p) {
            Ok(Some(svg)) => {
                let name = format!("scaling-{}-{}.svg", scene.name(), p.name());
                std::fs::write(dir.join(name), svg)?;
            }
            Ok(None) => {}
            Err(e) => eprintln!("plot of {} {}: {e}", scene.name(), p.name()),
        }
    }
    Ok(())
}
