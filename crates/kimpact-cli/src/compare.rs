//! `kimpact compare`: native and the three law modes on the same scene,
//! side by side: one report per mode, `summary.md`, plots of kinetic energy
//! and momentum over time (SVG and PNG), pictures (`strip.png`, one row
//! per mode and one column per picture time, and `frames/MODE-K.png`), the
//! page `compare.html` (the four modes animated in sync, see [`crate::html`])
//! and, on request, `compare.gif` (native beside exact, see [`crate::animation`]).
//!
//! Everything is computed in memory first; each file is then written
//! atomically, so a failure never leaves a partial file.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use kimpact::Mode;

use crate::error::CliError;
use crate::html;
use crate::palette::mode_color;
use crate::plot::{self, Series};
use crate::render;
use crate::report::{self, Report, norm};
use crate::scene::Scene;
use crate::shown::shown_steps;
use crate::sim::{self, Frame, RunOutput};

/// What `compare` writes besides the reports, summary, plots, pictures and
/// page.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Extras {
    /// Also write `compare.gif`.
    pub gif: bool,
}

/// Run the four modes on `scene` and write everything into `dir`.
///
/// # Errors
/// [`CliError::Internal`] if an output cannot be written.
pub fn compare(
    scene: &Scene,
    steps: Option<u64>,
    dir: &Path,
    extras: Extras,
) -> Result<(), CliError> {
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::Input(format!(
            "--out {}: exists and is not a directory",
            dir.display()
        )));
    }
    let steps = steps.unwrap_or(scene.steps);
    let mut frame_steps: Vec<u64> = scene
        .picture_times(steps)
        .iter()
        .map(|t| ((t / scene.dt).round() as u64).min(steps))
        .collect();
    frame_steps.sort_unstable();
    frame_steps.dedup();
    // The page's steps (every step, or every stride-th in long runs) and
    // the animation's: recorded together with the pictures' in one run.
    let stride = html::stride(steps, html::values_per_step(scene), Mode::ALL.len() as u64);
    let shown = shown_steps(steps, stride);
    let gif_steps = if extras.gif {
        crate::animation::steps(scene.dt, steps)
    } else {
        Vec::new()
    };
    let mut recorded: Vec<u64> = frame_steps
        .iter()
        .chain(&shown)
        .chain(&gif_steps)
        .copied()
        .collect();
    recorded.sort_unstable();
    recorded.dedup();
    let at = |r, wanted: &[u64]| frames_at(&recorded, r, wanted);

    let mut runs: Vec<RunOutput> = Vec::new();
    for mode in Mode::ALL {
        let bar = crate::progress::progress_bar(steps, mode.name());
        runs.push(sim::run(scene, mode, steps, &recorded, bar.as_ref()));
        if let Some(b) = bar {
            b.finish_and_clear();
        }
    }
    let reports: Vec<Report> = runs.iter().map(|r| report::build(scene, r)).collect();
    for r in &reports {
        for w in &r.warnings[scene.warnings.len()..] {
            eprintln!("warning: {w}");
        }
    }

    // Everything in memory first.
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    for r in &reports {
        let mut json = serde_json::to_string_pretty(r)
            .map_err(|e| CliError::Internal(format!("cannot encode a report: {e}")))?;
        json.push('\n');
        files.push((
            dir.join(format!("report-{}.json", r.mode)),
            json.into_bytes(),
        ));
    }
    let energy: Vec<Series> = runs
        .iter()
        .map(|r| Series {
            label: r.mode.name().to_owned(),
            color: mode_color(r.mode),
            points: plot::thin(
                &r.samples
                    .iter()
                    .map(|s| (s.time, s.kinetic))
                    .collect::<Vec<_>>(),
            ),
        })
        .collect();
    let momentum: Vec<Series> = runs
        .iter()
        .map(|r| Series {
            label: r.mode.name().to_owned(),
            color: mode_color(r.mode),
            points: plot::thin(
                &r.samples
                    .iter()
                    .map(|s| (s.time, norm(&s.momentum_all)))
                    .collect::<Vec<_>>(),
            ),
        })
        .collect();
    let internal = |what: &str, e: String| CliError::Internal(format!("cannot draw {what}: {e}"));
    let title = |what: &str| format!("{} — {what}", scene.name);
    files.push((
        dir.join("energy.svg"),
        plot::svg(
            &title("kinetic energy"),
            "time (s)",
            "kinetic energy",
            &energy,
        )
        .map_err(|e| internal("energy.svg", e))?
        .into_bytes(),
    ));
    files.push((
        dir.join("energy.png"),
        plot::png(
            &title("kinetic energy"),
            "time (s)",
            "kinetic energy",
            &energy,
        )
        .map_err(|e| internal("energy.png", e))?,
    ));
    files.push((
        dir.join("momentum.svg"),
        plot::svg(
            &title("|momentum| of all bodies"),
            "time (s)",
            "|momentum|",
            &momentum,
        )
        .map_err(|e| internal("momentum.svg", e))?
        .into_bytes(),
    ));
    files.push((
        dir.join("momentum.png"),
        plot::png(
            &title("|momentum| of all bodies"),
            "time (s)",
            "|momentum|",
            &momentum,
        )
        .map_err(|e| internal("momentum.png", e))?,
    ));

    // One view for the pictures, the page and the animation: fitted to
    // every recorded frame when no fixed bodies enclose the scene.
    let all_frames: Vec<&Frame> = runs.iter().flat_map(|r| r.frames.iter()).collect();
    let bounds = render::bounds(scene, &all_frames);
    let mut rows = Vec::new();
    for r in &runs {
        let mut panels = Vec::new();
        for (k, f) in at(r, &frame_steps).into_iter().enumerate() {
            let p = render::frame(scene, &f.bodies, &bounds)
                .ok_or_else(|| internal("a frame", "cannot allocate".into()))?;
            files.push((
                dir.join("frames").join(format!("{}-{k}.png", r.mode)),
                p.encode_png()
                    .map_err(|e| internal("a frame", e.to_string()))?,
            ));
            panels.push(p);
        }
        rows.push((panels, mode_color(r.mode)));
    }
    let strip = render::strip(&rows).ok_or_else(|| internal("strip.png", "no frames".into()))?;
    files.push((
        dir.join("strip.png"),
        strip
            .encode_png()
            .map_err(|e| internal("strip.png", e.to_string()))?,
    ));
    let times: Vec<f64> = runs
        .first()
        .map(|r| at(r, &frame_steps).iter().map(|f| f.time).collect())
        .unwrap_or_default();
    let table = table(&reports);
    let summary = summary(scene, steps, &reports, &table, &times);
    files.push((dir.join("summary.md"), summary.clone().into_bytes()));
    let shown_frames: Vec<Vec<&Frame>> = runs.iter().map(|r| at(r, &shown)).collect();
    let page = html::page(
        scene,
        setup_line(scene, steps),
        &runs,
        &html::Shown {
            steps: &shown,
            stride,
            frames: &shown_frames,
        },
        &bounds,
        &table,
    )
    .map_err(|e| internal("compare.html", e))?;
    files.push((dir.join("compare.html"), page.into_bytes()));
    if extras.gif {
        let pick = |mode: Mode| {
            runs.iter()
                .find(|r| r.mode == mode)
                .map(|r| (mode, at(r, &gif_steps)))
        };
        let panes: Vec<(Mode, Vec<&Frame>)> = [Mode::Native, Mode::Exact]
            .into_iter()
            .filter_map(pick)
            .collect();
        let bytes = crate::animation::animation(scene, &panes, &bounds)
            .map_err(|e| internal("compare.gif", e))?;
        files.push((dir.join("compare.gif"), bytes));
    }

    std::fs::create_dir_all(dir.join("frames"))
        .map_err(|e| CliError::Internal(format!("cannot create {}: {e}", dir.display())))?;
    for (path, bytes) in &files {
        crate::output::write_atomic(path, bytes)?;
    }
    print!("{summary}");
    println!("\nwrote {} files to {}", files.len(), dir.display());
    Ok(())
}

/// A run's frames at some of the `recorded` steps (the steps its frames
/// were recorded at, sorted).
fn frames_at<'a>(recorded: &[u64], run: &'a RunOutput, wanted: &[u64]) -> Vec<&'a Frame> {
    wanted
        .iter()
        .filter_map(|s| recorded.binary_search(s).ok())
        .filter_map(|k| run.frames.get(k))
        .collect()
}

/// A number for a table: fixed notation in a readable range, scientific
/// otherwise.
fn num(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 {
        "0".to_owned()
    } else if (1e-3..1e5).contains(&a) {
        format!("{x:.6}")
    } else {
        format!("{x:.3e}")
    }
}

/// The setup in one line: dimension, precision, bodies, steps, effects.
fn setup_line(scene: &Scene, steps: u64) -> String {
    format!(
        "{}D, {}, {} bodies ({} fixed), {} steps of {} s ({} s), effects: [{}]",
        scene.dim,
        scene.precision.name(),
        scene.bodies.len(),
        scene.bodies.iter().filter(|b| b.fixed).count(),
        steps,
        scene.dt,
        num(steps as f64 * scene.dt),
        scene.active_effects().join(", ")
    )
}

/// The summary table (for `summary.md` and the page), with what its
/// columns mean.
fn table(reports: &[Report]) -> html::Table {
    let header = [
        "mode",
        "kinetic initial",
        "kinetic final",
        "total energy change",
        "|p| law initial",
        "|p| law final",
        "|Δp| all",
        "impacts",
        "clamped",
        "dissipated",
        "energy integrator",
        "energy unexplained",
        "s/step",
        "max penetration / size",
        "crossings",
        "escaped",
    ]
    .map(str::to_owned)
    .to_vec();
    let rows = reports
        .iter()
        .map(|r| {
            let dp: Vec<f64> = r
                .momentum
                .r#final
                .all
                .iter()
                .zip(&r.momentum.initial.all)
                .map(|(a, b)| a - b)
                .collect();
            vec![
                r.mode.clone(),
                num(r.energy.kinetic_initial),
                num(r.energy.kinetic_final),
                num(r.energy.total_change),
                num(norm(&r.momentum.initial.law)),
                num(norm(&r.momentum.r#final.law)),
                num(norm(&dp)),
                r.impacts.count.to_string(),
                r.impacts.clamped.to_string(),
                num(r.impacts.dissipated),
                num(r.checks.energy_integrator),
                num(r.checks.energy_unexplained),
                num(r.timing.seconds_per_step),
                num(r.checks.max_penetration_ratio),
                r.checks.crossings.to_string(),
                r.checks.escaped.map_or("-".to_owned(), |e| e.to_string()),
            ]
        })
        .collect();
    let tol = reports.first().map_or(0.0, |r| r.checks.tolerance);
    let note = format!(
        "Impacts, clamped and dissipated are kimpact's counts (none in native mode). Energy integrator = −(h/2) Σ m g·(v_final − v_initial), h = dt / substeps: the part of the total energy change that rapier's symplectic Euler integration accounts for (zero without gravity). Energy unexplained = total energy change + dissipated − energy integrator: negative is energy lost (in rapier's contacts or joints, for example), positive is energy created; a warning above names each mode where it exceeds the tolerance (relative to the energy scale: {tol:.1e}, the precision's rounding over the run's substeps). Momentum changes through fixed bodies, gravity and joints to the world; without them, a change beyond the same tolerance (relative to the momentum scale) is warned about too. Max penetration is the deepest contact seen, over the smaller body's size; crossings counts pairs of balls that passed through each other within a step; escaped counts moving bodies that left the box of the fixed bodies."
    );
    html::Table { header, rows, note }
}

/// The summary's "Settings the command adds": the settings of every mode,
/// then each mode's own (see `report::Setup::added`).
fn added(s: &mut String, reports: &[Report]) {
    let _ = writeln!(s, "## Settings the command adds\n");
    let all: Vec<&String> = reports
        .first()
        .map(|r| r.setup.added.iter().collect())
        .unwrap_or_default();
    let common: Vec<&String> = all
        .into_iter()
        .filter(|a| reports.iter().all(|r| r.setup.added.contains(a)))
        .collect();
    let mut any = false;
    for a in &common {
        let _ = writeln!(s, "- every mode: {a}");
        any = true;
    }
    for r in reports {
        for a in r.setup.added.iter().filter(|a| !common.contains(a)) {
            let _ = writeln!(s, "- {}: {a}", r.mode);
            any = true;
        }
    }
    if !any {
        let _ = writeln!(
            s,
            "None: every mode runs the scene's bodies as rapier builds them."
        );
    }
    let _ = writeln!(s);
}

/// The markdown summary.
fn summary(
    scene: &Scene,
    steps: u64,
    reports: &[Report],
    table: &html::Table,
    times: &[f64],
) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# {}: rapier's native restitution vs kimpact\n",
        scene.name
    );
    if let Some(d) = &scene.description {
        let _ = writeln!(s, "{d}\n");
    }
    let _ = writeln!(s, "{}\n", setup_line(scene, steps));
    added(&mut s, reports);
    let run_warnings: Vec<&String> = reports
        .iter()
        .flat_map(|r| &r.warnings[scene.warnings.len()..])
        .collect();
    if !scene.warnings.is_empty() || !run_warnings.is_empty() {
        let _ = writeln!(s, "## Warnings\n");
        for w in scene.warnings.iter().chain(run_warnings) {
            let _ = writeln!(s, "- {w}");
        }
        let _ = writeln!(s);
    }
    let clamps: Vec<&String> = reports
        .iter()
        .filter_map(|r| r.impacts.clamps.as_ref())
        .collect();
    if !clamps.is_empty() {
        let _ = writeln!(s, "## Clamped impacts\n");
        for c in clamps {
            let _ = writeln!(s, "- {c}");
        }
        let _ = writeln!(s);
    }
    let cells = |row: &[String]| {
        let escaped: Vec<String> = row.iter().map(|c| c.replace('|', "\\|")).collect();
        format!("| {} |", escaped.join(" | "))
    };
    let _ = writeln!(s, "{}", cells(&table.header));
    let align: Vec<&str> = (0..table.header.len())
        .map(|k| if k == 0 { "---" } else { "---:" })
        .collect();
    let _ = writeln!(s, "|{}|", align.join("|"));
    for row in &table.rows {
        let _ = writeln!(s, "{}", cells(row));
    }
    let _ = writeln!(s);
    let _ = writeln!(s, "{}\n", table.note);
    let _ = writeln!(
        s,
        "![kinetic energy](energy.svg)\n\n![momentum](momentum.svg)\n"
    );
    let list: Vec<String> = times.iter().map(|t| format!("{} s", num(*t))).collect();
    let _ = writeln!(
        s,
        "![pictures](strip.png)\n\n`strip.png`: one row per mode (native, restitution, impulse, exact; the colour mark on the left matches the plots), one column per time: {}. Single frames in `frames/MODE-K.png`. `compare.html`: the four modes animated side by side (open it in a browser; it loads nothing from the network).",
        list.join(", ")
    );
    s
}
