//! The stage table (`--stages`): where the law world's step goes, kimpact's
//! two stages against rapier's step, beside native's step, per scene and
//! mode, into `stages.md`.

use std::fmt::Write;

use kimpact::Mode;

use crate::cli::name;
use crate::raw::{Group, Measure, Raw};
use crate::report::{fmt_us, median};

/// The median of stage `k` over `runs`' steps (NaN without stages).
fn stage(runs: &[&Measure], k: usize) -> f64 {
    median(
        runs.iter()
            .flat_map(|m| &m.stages_us)
            .map(|s| s[k])
            .collect(),
    )
}

/// One line per law mode of `g` that has stages.
fn lines(g: &Group, out: &mut String) {
    for &mode in g.modes.iter().filter(|&&m| m != Mode::Native) {
        let pairs = g.pairs.iter().filter(|p| p.0 == mode);
        let pairs: Vec<_> = pairs.filter_map(|p| p.1.as_ref().ok()).collect();
        let law: Vec<&Measure> = pairs.iter().map(|p| &p.law).collect();
        let native: Vec<&Measure> = pairs.iter().map(|p| &p.native).collect();
        if law.iter().all(|m| m.stages_us.is_empty()) {
            continue;
        }
        let [before, rapier, after] = [0, 1, 2].map(|k| stage(&law, k));
        let native_rapier = stage(&native, 1);
        let share = (before + after) / native_rapier;
        let (scene, precision, balls) = (name(g.scene), g.precision, g.balls);
        let _ = writeln!(
            out,
            "| {scene} | {precision} | {balls} | {mode} | {} | {} | {} | {} | {share:.2} |",
            fmt_us(native_rapier),
            fmt_us(before),
            fmt_us(rapier),
            fmt_us(after),
        );
    }
}

/// `stages.md` of `raw`, if any run timed its stages.
pub fn markdown(raw: &Raw) -> Option<String> {
    let mut rows = String::new();
    raw.groups.iter().for_each(|g| lines(g, &mut rows));
    if rows.is_empty() {
        return None;
    }
    let h = &raw.header;
    let threads = h
        .cli
        .threads
        .map_or("rayon's default".to_owned(), |n| n.to_string());
    let mut s = crate::report::heading(h, "stages");
    let _ = writeln!(
        s,
        "- rayon threads: {threads}; each stage of each measured step timed on the step clock (CPU time of the process, or the wall clock with --threads); medians over the steps of every timing run\n- native's step: rapier's step in the native world; before, rapier and after: kimpact's `before_step`, rapier's step and kimpact's `after_step` in the mode's world; kimpact's share: (before + after) / native's step\n"
    );
    s += "| scene | prec | balls | mode | native's step | before | rapier | after | kimpact's share |\n";
    s += "|---|---|---:|---|---:|---:|---:|---:|---:|\n";
    Some(s + &rows)
}
