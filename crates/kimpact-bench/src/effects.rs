//! `--effects`: what each effect a scene can call for costs in every law
//! mode. On one base scene (the gas scenes' balls with no effect at all: no
//! gravity, `d̃ = 0`, no friction, no spin, no walls, no reader of the
//! impact events, no material) each effect is switched on alone; every
//! configuration, the base too, is timed in lockstep with native rapier on
//! the same configuration (child processes, as the matrix), and its heap
//! allocations attributed from their stacks. The table compares each
//! effect's configuration with the base: time per step, ×native, what the
//! mode adds to native's step, and kimpact's own allocations per step.

use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::Instant;

use clap::ValueEnum;
use serde::{Deserialize, Serialize};

use crate::report::{self, Group, Row, fmt_delta_us, fmt_us};
use crate::{Cli, Mode, Precision, Scene, machine, measure_group};

/// A configuration of the effects table: the base, or the base with one
/// effect on (see the effects builder in `effect_scene.rs`).
#[derive(
    Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, ValueEnum, Serialize, Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Effect {
    /// No effect at all: the base.
    None,
    /// Gravity, 9.81 m/s² along −y.
    Gravity,
    /// The law's `d̃ > 0` (0.09).
    Dissipation,
    /// Friction 0.5 on every ball.
    Friction,
    /// Every ball spinning (angular velocity about z).
    Spin,
    /// A closed box of fixed walls.
    Walls,
    /// The user reads kimpact's impact events after each step.
    Events,
    /// Every ball marked with its own material (`Kimpact::mark_with`).
    Materials,
}

impl Effect {
    /// The base first, then every effect.
    pub const ALL: [Effect; 8] = [
        Effect::None,
        Effect::Gravity,
        Effect::Dissipation,
        Effect::Friction,
        Effect::Spin,
        Effect::Walls,
        Effect::Events,
        Effect::Materials,
    ];

    /// The name on the command line and in the outputs.
    pub fn name(self) -> &'static str {
        match self {
            Effect::None => "none",
            Effect::Gravity => "gravity",
            Effect::Dissipation => "dissipation",
            Effect::Friction => "friction",
            Effect::Spin => "spin",
            Effect::Walls => "walls",
            Effect::Events => "events",
            Effect::Materials => "materials",
        }
    }
}

/// Everything an effects run measured (`effects-raw.json`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EffectsRaw {
    pub header: report::Header,
    pub groups: Vec<(Effect, Group)>,
}

/// One line of the effects table: a configuration in one law mode, beside
/// the base in the same mode.
#[derive(Clone, Debug)]
pub struct EffectRow {
    pub effect: Effect,
    pub on: Row,
    pub base: Option<Row>,
}

/// Run the effects table as `cli` asks (see the module docs).
pub fn run(cli: &Cli) -> ExitCode {
    if cli.rerender {
        let raw = std::fs::read_to_string(cli.out.join("effects-raw.json"))
            .map_err(|e| e.to_string())
            .and_then(|s| serde_json::from_str::<EffectsRaw>(&s).map_err(|e| e.to_string()));
        return match raw {
            Ok(raw) => render(cli, &raw),
            Err(e) => {
                eprintln!("cannot read {}/effects-raw.json: {e}", cli.out.display());
                ExitCode::FAILURE
            }
        };
    }
    let scene = cli.scene.first().copied().unwrap_or(Scene::Gas3d);
    if !matches!(scene, Scene::Gas3d | Scene::Gas2d) {
        eprintln!(
            "--effects runs on the gas3d or gas2d base, not {}",
            scene.name()
        );
        return ExitCode::FAILURE;
    }
    let balls = cli.balls.first().copied().unwrap_or(1000);
    let precision = cli.precision.first().copied().unwrap_or(Precision::F32);
    let mut modes = vec![Mode::Native];
    modes.extend(cli.mode.iter().copied().filter(|&m| m != Mode::Native));
    modes.sort_unstable();
    modes.dedup();
    let law_modes: Vec<Mode> = modes
        .iter()
        .copied()
        .filter(|&m| m != Mode::Native)
        .collect();
    let rounds = cli.rounds.max(1);
    let started = Instant::now();
    let mut groups = Vec::new();
    for effect in Effect::ALL {
        let progress = |what: &str, mode: Mode| {
            eprintln!(
                "[{:>6.1}s] effects {} {} {} balls, {}: {what} {}",
                started.elapsed().as_secs_f64(),
                precision.name(),
                scene.name(),
                balls,
                effect.name(),
                mode.name()
            );
        };
        let extra = ["--effect".to_owned(), effect.name().to_owned()];
        let config = (scene, balls, precision);
        let alone = "allocations of";
        let group = measure_group(cli, config, &modes, &law_modes, &extra, alone, progress);
        groups.push((effect, group));
    }
    let command = std::iter::once("kimpact-bench".to_owned())
        .chain(std::env::args().skip(1))
        .collect::<Vec<_>>()
        .join(" ");
    let header = report::Header {
        command,
        machine: machine(),
        parallel: cfg!(feature = "parallel"),
        clock: cli.clock,
        steps: cli.steps,
        warmup: cli.warmup,
        rounds,
        block: cli.block,
        small_block: 0,
        small_repeats: 0,
        memory_steps: cli.memory_steps,
        memory_warmup: cli.memory_warmup,
        wall_s: started.elapsed().as_secs_f64(),
    };
    let raw = EffectsRaw { header, groups };
    if let Err(e) = std::fs::create_dir_all(&cli.out).and_then(|()| {
        let json = serde_json::to_string(&raw).map_err(std::io::Error::other)?;
        std::fs::write(cli.out.join("effects-raw.json"), json)
    }) {
        eprintln!("cannot write {}/effects-raw.json: {e}", cli.out.display());
    }
    render(cli, &raw)
}

/// The table's lines: every configuration's law modes beside the base's.
pub fn rows(raw: &EffectsRaw) -> Vec<EffectRow> {
    let per_group: Vec<(Effect, Vec<Row>)> = raw
        .groups
        .iter()
        .map(|(e, g)| (*e, report::rows(g)))
        .collect();
    let base = per_group
        .iter()
        .find(|(e, _)| *e == Effect::None)
        .map(|(_, rows)| rows.clone())
        .unwrap_or_default();
    per_group
        .into_iter()
        .flat_map(|(effect, rows)| {
            let base = &base;
            rows.into_iter()
                .filter(|r| r.mode != Mode::Native)
                .map(move |on| EffectRow {
                    effect,
                    base: base.iter().find(|b| b.mode == on.mode).cloned(),
                    on,
                })
        })
        .collect()
}

/// kimpact's allocations per step, or `?` when not attributed.
fn own_allocs(r: &Row) -> String {
    if r.kimpact_allocs_per_step.is_finite() {
        format!(
            "{:.2} of {:.1}",
            r.kimpact_allocs_per_step, r.allocs_per_step
        )
    } else {
        format!("? of {:.1}", r.allocs_per_step)
    }
}

/// The effects table as markdown.
pub fn markdown(raw: &EffectsRaw, rows: &[EffectRow]) -> String {
    let h = &raw.header;
    let (scene, balls, precision) = raw.groups.first().map_or(("?", 0, "?"), |(_, g)| {
        (g.scene.name(), g.balls, g.precision.name())
    });
    let mut s = String::new();
    let _ = writeln!(s, "## kimpact-bench effects\n");
    let _ = writeln!(s, "- command: `{}`", h.command);
    let _ = writeln!(s, "- machine: {}", h.machine);
    let _ = writeln!(
        s,
        "- base: {balls} balls of the {scene} scene, {precision}, with no effect at all (no gravity, d̃ = 0, no friction, no spin, no walls, no reader of the impact events, no material); each configuration switches one effect on. Each timing run is one process stepping native rapier and one mode on two copies of the configuration in lockstep ({} warm-up steps, then {} measured steps each, alternated in blocks of {}, each step timed by {} time); {} timing run(s) per mode and configuration; allocations attributed in a separate process per mode ({} steps after {} warm-up steps); wall time {:.0} s",
        h.warmup,
        h.steps,
        h.block,
        h.clock.name(),
        h.rounds,
        h.memory_steps,
        h.memory_warmup.unwrap_or(h.warmup),
        h.wall_s
    );
    let _ = writeln!(
        s,
        "- columns: native and mode: median time per step in the configuration's timing runs; ×native: their ratio (pooled over the runs); added: mode − native, what the mode adds to rapier's step; added − base: the same in the base configuration subtracted (what the effect costs kimpact); allocs/step: kimpact's own (attributed from their stacks) of all, per step\n"
    );
    let _ = writeln!(
        s,
        "| effect | mode | native | mode | ×native | added | ×native, base | added, base | added − base | kimpact's allocs/step | impacts/step |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in rows {
        let on = &r.on;
        let (base_ratio, base_delta, diff) = match &r.base {
            Some(b) => (
                format!("{:.3}", b.ratio),
                fmt_delta_us(b.delta_us),
                fmt_delta_us(on.delta_us - b.delta_us),
            ),
            None => ("—".to_owned(), "—".to_owned(), "—".to_owned()),
        };
        let mut effect = r.effect.name().to_owned();
        if let Some(e) = &on.error {
            effect.push_str(&format!(" (failed: {e})"));
        }
        let _ = writeln!(
            s,
            "| {effect} | {} | {} | {} | {:.3} | {} | {base_ratio} | {base_delta} | {diff} | {} | {:.1} |",
            on.mode.name(),
            fmt_us(on.native_median_us),
            fmt_us(on.median_us),
            on.ratio,
            fmt_delta_us(on.delta_us),
            own_allocs(on),
            on.impacts_per_step,
        );
    }
    s
}

/// The CSV's columns, in order.
pub const COLUMNS: [&str; 20] = [
    "effect",
    "scene",
    "precision",
    "balls",
    "mode",
    "rounds",
    "native_median_us",
    "median_us",
    "ratio",
    "ratio_min",
    "ratio_max",
    "delta_us",
    "base_ratio",
    "base_delta_us",
    "delta_minus_base_us",
    "allocs_per_step",
    "kimpact_allocs_per_step",
    "attr_kimpact",
    "attr_classified",
    "error",
];

/// The effects table as CSV, with [`COLUMNS`] as header.
pub fn csv(rows: &[EffectRow]) -> String {
    let mut s = COLUMNS.join(",");
    s.push('\n');
    for r in rows {
        let on = &r.on;
        let base = |f: fn(&Row) -> f64| r.base.as_ref().map_or(f64::NAN, f);
        let fields = [
            r.effect.name().to_owned(),
            on.scene.name().to_owned(),
            on.precision.name().to_owned(),
            on.balls.to_string(),
            on.mode.name().to_owned(),
            on.rounds.to_string(),
            format!("{:.3}", on.native_median_us),
            format!("{:.3}", on.median_us),
            format!("{:.4}", on.ratio),
            format!("{:.4}", on.ratio_min),
            format!("{:.4}", on.ratio_max),
            format!("{:.3}", on.delta_us),
            format!("{:.4}", base(|b| b.ratio)),
            format!("{:.3}", base(|b| b.delta_us)),
            format!("{:.3}", on.delta_us - base(|b| b.delta_us)),
            format!("{:.3}", on.allocs_per_step),
            format!("{:.3}", on.kimpact_allocs_per_step),
            on.attr_sampled.0.to_string(),
            on.attr_sampled.1.to_string(),
            on.error.as_deref().unwrap_or("").replace([',', '\n'], ";"),
        ];
        s.push_str(&fields.join(","));
        s.push('\n');
    }
    s
}

/// Print the effects table and write effects.md and effects.csv.
fn render(cli: &Cli, raw: &EffectsRaw) -> ExitCode {
    let rows = rows(raw);
    let md = markdown(raw, &rows);
    println!("{md}");
    let written = std::fs::create_dir_all(&cli.out)
        .and_then(|()| std::fs::write(cli.out.join("effects.md"), &md))
        .and_then(|()| std::fs::write(cli.out.join("effects.csv"), csv(&rows)));
    if let Err(e) = written {
        eprintln!("cannot write the effects to {}: {e}", cli.out.display());
        return ExitCode::FAILURE;
    }
    eprintln!(
        "wrote {}/effects.md, effects.csv and effects-raw.json",
        cli.out.display()
    );
    ExitCode::SUCCESS
}
