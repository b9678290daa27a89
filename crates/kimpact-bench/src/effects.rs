//! `--effects`: what each effect a scene can call for (see [`Effect`])
//! costs in every law mode: each configuration is a group of children as
//! the matrix's; each row sets what the mode adds to native's step beside
//! what it adds on the base.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

use kimpact_harness::{BenchRow, EffectRow};

use kimpact::Mode;

use crate::cli::{Effect, name};
use crate::raw::{Group, Raw};
use crate::report::{self, fmt_or_unknown, fmt_us};

/// The table's rows: every law mode of every configuration.
pub fn rows(groups: &[Group]) -> Vec<EffectRow> {
    let all: Vec<(&Group, Vec<BenchRow>)> = groups.iter().map(|g| (g, report::rows(g))).collect();
    let base = |g: &Group, mode| {
        let same = |b: &Group| (b.scene, b.balls, b.precision) == (g.scene, g.balls, g.precision);
        let (_, rows) = all
            .iter()
            .find(|(b, _)| same(b) && b.effect == Some(Effect::Base))?;
        Some(rows.iter().find(|r| r.mode == mode)?.delta_us)
    };
    let mut out = Vec::new();
    for (g, rows) in &all {
        for r in rows.iter().filter(|r| r.mode != Mode::Native) {
            let base_delta_us = base(g, r.mode).unwrap_or(f64::NAN);
            out.push(EffectRow {
                effect: g.effect.map_or_else(String::new, name),
                scene: r.scene.clone(),
                precision: r.precision,
                balls: r.balls,
                mode: r.mode,
                median_us: r.median_us,
                native_median_us: r.native_median_us,
                ratio: r.ratio,
                delta_us: r.delta_us,
                base_delta_us,
                effect_us: r.delta_us - base_delta_us,
                kimpact_allocs_per_step: r.kimpact_allocs_per_step,
                impacts_per_step: r.impacts_per_step,
                error: r.error.clone(),
            });
        }
    }
    out
}

/// One scene's effects table as markdown.
fn markdown(raw: &Raw, rows: &[&EffectRow]) -> String {
    let (h, c) = (&raw.header, &raw.header.cli);
    let scene = rows.first().map_or("", |r| &r.scene);
    let mut s = report::heading(h, &format!("effects: {scene}"));
    let (warmup, steps, block, rounds) = (c.warmup, c.steps, c.block, c.rounds.max(1));
    let (memory_steps, memory_warmup) = (c.memory_steps, c.memory_warmup.unwrap_or(warmup));
    let wall_s = h.wall_s;
    let _ = writeln!(
        s,
        "- base: the gas scene's balls with no effect at all (no gravity, d̃ = 0, no friction, no spin, no walls, nobody reading the impact events, no material); each other configuration switches one effect on. Each timing run is one process stepping native rapier and one mode on two copies of the configuration in lockstep ({warmup} warm-up steps, then {steps} measured steps each, alternated in blocks of {block}); {rounds} timing run(s) per mode and configuration; allocations attributed in a separate process per mode ({memory_steps} steps after {memory_warmup} warm-up steps); wall time {wall_s:.0} s"
    );
    s += "- impact_friction: the spin configuration with every ball marked with a material of μ = 0.5, β = 0 (impact friction on); off, it is the spin row (no material) and the materials row (a material without impact friction)\n";
    s += "- native and mode: median CPU time per step in the configuration's timing runs; ×native: their ratio; added: mode − native, what the mode adds to rapier's step; effect: added − the base's added in the same mode, what the effect costs kimpact; kimpact's allocs/step: attributed from their stacks (? when not)\n\n";
    s += "| prec | balls | effect | mode | native | mode | ×native | added | effect | kimpact's allocs/step | impacts/step | notes |\n";
    s += "|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---|\n";
    for r in rows {
        let (precision, balls, effect, mode) = (r.precision, r.balls, &r.effect, r.mode);
        let (native_us, mode_us) = (fmt_us(r.native_median_us), fmt_us(r.median_us));
        let (ratio, added, effect_us) = (r.ratio, r.delta_us, r.effect_us);
        let allocs = fmt_or_unknown(r.kimpact_allocs_per_step, 2);
        let (impacts, notes) = (r.impacts_per_step, r.error.as_deref().unwrap_or_default());
        let _ = writeln!(
            s,
            "| {precision} | {balls} | {effect} | {mode} | {native_us} | {mode_us} | {ratio:.3} | {added:+.2} µs | {effect_us:+.2} µs | {allocs} | {impacts:.2} | {notes} |"
        );
    }
    s
}

/// Print each scene's effects table and write it into
/// `dir/effects-<scene>/` (`effects.md`, `effects.csv`), whole.
pub fn render(dir: &Path, raw: &Raw) -> ExitCode {
    let rows = rows(&raw.groups);
    let mut files = Vec::new();
    for scene in BTreeSet::from_iter(rows.iter().map(|r| &r.scene)) {
        let mine: Vec<&EffectRow> = rows.iter().filter(|r| &r.scene == scene).collect();
        let md = markdown(raw, &mine);
        println!("{md}");
        let folder = dir.join(format!("effects-{scene}"));
        files.extend([
            (folder.join("effects.md"), md.into()),
            (folder.join("effects.csv"), report::csv(&mine)),
        ]);
    }
    report::write(dir, &files)
}
