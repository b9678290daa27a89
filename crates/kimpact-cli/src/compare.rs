//! `kimpact compare`: native and the three law modes on the same scene,
//! side by side: one report per mode, `summary.md`, plots of kinetic energy
//! and momentum over time (SVG and PNG) and pictures (`strip.png`, one row
//! per mode and one column per picture time, and `frames/MODE-K.png`).
//!
//! Everything is computed in memory first; each file is then written
//! atomically, so a failure never leaves a partial file.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::Mode;
use crate::error::CliError;
use crate::plot::{self, Series};
use crate::render;
use crate::report::{self, Report, norm};
use crate::scene::Scene;
use crate::sim::{self, RunOutput};

/// The colour of each mode in plots and pictures.
pub fn mode_color(mode: Mode) -> (u8, u8, u8) {
    match mode {
        Mode::Native => (90, 90, 90),
        Mode::Restitution => (230, 159, 0),
        Mode::Impulse => (0, 158, 115),
        Mode::Exact => (0, 114, 178),
    }
}

/// Run the four modes on `scene` and write everything into `dir`.
///
/// # Errors
/// [`CliError::Internal`] if an output cannot be written.
pub fn compare(scene: &Scene, steps: Option<u64>, dir: &Path) -> Result<(), CliError> {
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

    let mut runs: Vec<RunOutput> = Vec::new();
    for mode in Mode::ALL {
        let bar = crate::progress_bar(steps, mode.name());
        runs.push(sim::run(scene, mode, steps, &frame_steps, bar.as_ref()));
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

    let all_frames: Vec<&sim::Frame> = runs.iter().flat_map(|r| r.frames.iter()).collect();
    let bounds = render::bounds(scene, &all_frames);
    let mut rows = Vec::new();
    for r in &runs {
        let mut panels = Vec::new();
        for (k, f) in r.frames.iter().enumerate() {
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
        .map(|r| r.frames.iter().map(|f| f.time).collect())
        .unwrap_or_default();
    let summary = summary(scene, steps, &reports, &times);
    files.push((dir.join("summary.md"), summary.clone().into_bytes()));

    std::fs::create_dir_all(dir.join("frames"))
        .map_err(|e| CliError::Internal(format!("cannot create {}: {e}", dir.display())))?;
    for (path, bytes) in &files {
        crate::output::write_atomic(path, bytes)?;
    }
    print!("{summary}");
    println!("\nwrote {} files to {}", files.len(), dir.display());
    Ok(())
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

/// The markdown summary.
fn summary(scene: &Scene, steps: u64, reports: &[Report], times: &[f64]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# {}: rapier's native restitution vs kimpact\n",
        scene.name
    );
    if let Some(d) = &scene.description {
        let _ = writeln!(s, "{d}\n");
    }
    let _ = writeln!(
        s,
        "{}D, {}, {} bodies ({} fixed), {} steps of {} s ({} s), effects: [{}]\n",
        scene.dim,
        scene.precision.name(),
        scene.bodies.len(),
        scene.bodies.iter().filter(|b| b.fixed).count(),
        steps,
        scene.dt,
        num(steps as f64 * scene.dt),
        scene.active_effects().join(", ")
    );
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
    let _ = writeln!(
        s,
        "| mode | kinetic initial | kinetic final | total energy change | \\|p\\| law initial | \\|p\\| law final | \\|Δp\\| all | impacts | clamped | dissipated | energy integrator | energy unexplained | s/step | max penetration / size | crossings | escaped |"
    );
    let _ = writeln!(
        s,
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for r in reports {
        let dp: Vec<f64> = r
            .momentum
            .r#final
            .all
            .iter()
            .zip(&r.momentum.initial.all)
            .map(|(a, b)| a - b)
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.mode,
            num(r.energy.kinetic_initial),
            num(r.energy.kinetic_final),
            num(r.energy.total_change),
            num(norm(&r.momentum.initial.law)),
            num(norm(&r.momentum.r#final.law)),
            num(norm(&dp)),
            r.impacts.count,
            r.impacts.clamped,
            num(r.impacts.dissipated),
            num(r.checks.energy_integrator),
            num(r.checks.energy_unexplained),
            num(r.timing.seconds_per_step),
            num(r.checks.max_penetration_ratio),
            r.checks.crossings,
            r.checks.escaped.map_or("-".to_owned(), |e| e.to_string()),
        );
    }
    let _ = writeln!(s);
    let tol = reports.first().map_or(0.0, |r| r.checks.tolerance);
    let _ = writeln!(
        s,
        "Impacts, clamped and dissipated are kimpact's counts (none in native mode). Energy integrator = −(h/2) Σ m g·(v_final − v_initial), h = dt / substeps: the part of the total energy change that rapier's symplectic Euler integration accounts for (zero without gravity). Energy unexplained = total energy change + dissipated − energy integrator: negative is energy lost in rapier's contacts, positive is energy created; a warning above names each mode where it exceeds the tolerance (relative to the energy scale: {tol:.0e}). Momentum changes through fixed bodies and gravity; without either, a change beyond the same tolerance (relative to the momentum scale) is warned about too. Max penetration is the deepest contact seen, over the smaller body's size; crossings counts pairs of balls that passed through each other within a step; escaped counts moving bodies that left the box of the fixed bodies.\n"
    );
    let _ = writeln!(
        s,
        "![kinetic energy](energy.svg)\n\n![momentum](momentum.svg)\n"
    );
    let list: Vec<String> = times.iter().map(|t| format!("{} s", num(*t))).collect();
    let _ = writeln!(
        s,
        "![pictures](strip.png)\n\n`strip.png`: one row per mode (native, restitution, impulse, exact; the colour mark on the left matches the plots), one column per time: {}. Single frames in `frames/MODE-K.png`.",
        list.join(", ")
    );
    s
}
