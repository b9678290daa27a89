//! `accuracy.md`: the tables in their sections, the method, the command and
//! the machine, with the hand-written Findings kept from the previous file.

use std::fmt::Write as _;

use kimpact_harness::Method;

use crate::experiments::{Sizes, ZEntry, z_vs_reference};
use crate::format::{e, pct, table};
use crate::texts::{
    COOLING_TEXT, COST_TEXT, FINDINGS_BEGIN, FINDINGS_END, GAS_TEXT, INTRO, Z_CHECKS_TEXT, Z_TEXT,
};
use crate::z::eos;

/// The command that regenerates the docs.
pub fn command(quick: bool) -> String {
    format!(
        "cargo run --release -p kimpact-bench --bin kimpact-accuracy{}",
        if quick { " -- --quick" } else { "" }
    )
}

/// The hand-written findings between the markers of the previous
/// `accuracy.md` (`old`), or a placeholder.
pub fn findings(old: Option<&str>) -> String {
    old.and_then(|old| {
        let a = old.find(FINDINGS_BEGIN)? + FINDINGS_BEGIN.len();
        let b = old.find(FINDINGS_END)?;
        (a <= b).then(|| old[a..b].to_owned())
    })
    .unwrap_or_else(|| {
        "\n(Write the findings here: this block is kept when the file is regenerated.)\n\n".into()
    })
}

/// The Z tables, from every job's results: the cases in the order of their
/// first run, each with the reference first, then every mode in f32 and
/// f64.
pub fn z_tables(z: &[ZEntry]) -> (Vec<Vec<String>>, Vec<Vec<String>>) {
    let case_rank = |case: &str| z.iter().position(|x| x.case == case).unwrap_or(0);
    let mut sorted: Vec<&ZEntry> = z.iter().collect();
    sorted.sort_by_key(|x| (case_rank(&x.case), x.method, x.precision));
    let mut main = Vec::new();
    let mut checks = Vec::new();
    for x in sorted {
        let (case, eta, d, method, t_run, r) = (&x.case, &x.eta, &x.d, &x.method, &x.t_run, &x.r);
        let reference = z
            .iter()
            .find(|y| &y.case == case && y.method == Method::Reference);
        let fit = eos(*d, r.eta_bulk);
        let name = if *d == 2 {
            "Henderson"
        } else {
            "Carnahan–Starling"
        };
        let vs_ref = match reference {
            Some(q) if *method != Method::Reference => {
                let (dev, err) = z_vs_reference(x, q);
                format!("{} ± {:.2}%", pct(dev), 100.0 * err)
            }
            _ => "–".into(),
        };
        main.push(vec![
            case.clone(),
            method.name().into(),
            x.precision.name().into(),
            format!("{}", r.n),
            format!("{t_run}"),
            format!("{:.4}", r.eta_bulk),
            format!("{:.4} ± {:.4}", r.z, r.z_err),
            format!("{fit:.4} ({name})"),
            format!("{} ± {:.2}%", pct(r.z / fit - 1.0), 100.0 * r.z_err / fit),
            vs_ref,
            pct(r.kt_drift),
            format!("{}", r.impacts),
            if r.ms_per_step.is_nan() {
                "–".into()
            } else {
                format!("{:.2}", r.ms_per_step)
            },
            e(r.residual),
        ]);
        if *method == Method::Reference {
            let mut row = vec![
                case.clone(),
                pct(r.z_naive / eos(*d, *eta) - 1.0),
                pct(r.z_single / fit - 1.0),
            ];
            for (w, eta_w, z_w) in &r.by_w {
                row.push(format!(
                    "{w}: η {eta_w:.4}, Z/EOS {}",
                    pct(z_w / eos(*d, *eta_w) - 1.0)
                ));
            }
            checks.push(row);
        }
    }
    (main, checks)
}

/// `rustc 1.95.0 (59807616e 2026-04-14)` without the commit hash (the docs
/// name no commits): `rustc 1.95.0 (2026-04-14)`.
fn without_hash(version: &str) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut open = false;
    for w in version.split(' ') {
        let bare = w.trim_start_matches('(');
        if bare.len() >= 7 && bare.chars().all(|c| c.is_ascii_hexdigit()) {
            open = w.starts_with('(');
            continue;
        }
        out.push(if open { format!("({w}") } else { w.to_owned() });
        open = false;
    }
    out.join(" ")
}

/// The machine, the toolchain and the date, for the header.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let cmd = |c: &str, a: &[&str]| {
        std::process::Command::new(c)
            .args(a)
            .output()
            .ok()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
            .unwrap_or_default()
    };
    format!(
        "{cpu}, {cores} cores available to the process, {}; {}; {}",
        cmd("uname", &["-sr"]),
        without_hash(&cmd("rustc", &["-V"])),
        cmd("date", &["-u", "+%Y-%m-%d %H:%M UTC"])
    )
}

/// The whole of `accuracy.md`.
#[allow(clippy::too_many_arguments)]
pub fn document(
    findings: &str,
    impact: &[Vec<String>],
    cradle: &[Vec<String>],
    gas: &[Vec<String>],
    z: &[Vec<String>],
    z_checks: &[Vec<String>],
    cooling: &[Vec<String>],
    cost: &[Vec<String>],
    notes: &[String],
    machine: &str,
    quick: bool,
    threads: usize,
    elapsed: f64,
    sizes: &Sizes,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Accuracy against the exact reference\n");
    let _ = writeln!(
        s,
        "Generated by `{}` ({threads} worker threads, {elapsed:.0} s) on {machine}. \
         Every table below, the plot `accuracy.svg`, the data `accuracy.csv` and the headline errors per scene, build and mode \
         `accuracy-summary.json` come from that one command \
         (the Findings are written by hand from them, and kept when the file is regenerated); the CI versions of the first three comparisons are `cargo test --test accuracy`.\n",
        command(quick)
    );
    if quick {
        let _ = writeln!(
            s,
            "**A smoke run (`--quick`)**: smaller scenes and much shorter runs than the text below describes; its figures mean nothing.\n"
        );
    }
    let _ = writeln!(s, "{INTRO}");
    let _ = writeln!(
        s,
        "## Findings\n\n{FINDINGS_BEGIN}{findings}{FINDINGS_END}\n"
    );
    let _ = writeln!(s, "## One oblique impact\n");
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "mode",
                "masses, dissipation",
                "velocity error",
                "position error / r",
                "energy kept",
                "momentum error"
            ],
            impact
        )
    );
    let _ = writeln!(s, "## Newton's cradle\n");
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "mode",
                "velocity error",
                "energy kept",
                "momentum error"
            ],
            cradle
        )
    );
    let _ = writeln!(s, "## Elastic gas: statistics over time\n");
    let _ = writeln!(
        s,
        "{}",
        GAS_TEXT.replace("{T}", &format!("{}", sizes.gas_t))
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "simulator",
                "E(T)/E(0)",
                "mean abs(P)/sqrt(2ME)",
                "impacts per s",
                "vs reference",
                "KS speeds vs reference",
                "KS speeds vs Maxwell",
                "ms/step",
                "wall-impulse residual"
            ],
            gas
        )
    );
    let _ = writeln!(s, "## Compressibility factor of hard disks and spheres\n");
    let _ = writeln!(
        s,
        "{}",
        Z_TEXT
            .replace("{TREF}", &format!("{}", sizes.z_ref_t))
            .replace("{TRAP}", &format!("{}", sizes.z_rapier_t))
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "case",
                "simulator",
                "precision",
                "N",
                "measured over",
                "bulk η",
                "Z (± 1 s.e.)",
                "equation of state at bulk η",
                "Z vs EOS",
                "single-wall Z vs reference's",
                "kT drift",
                "impacts",
                "ms/step",
                "wall-impulse residual"
            ],
            z
        )
    );
    let _ = writeln!(s, "{}", Z_CHECKS_TEXT);
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "case (reference)",
                "naive Z vs EOS(nominal η)",
                "no end correction vs EOS",
                "w used",
                "w − 1",
                "w + 1"
            ],
            z_checks
        )
    );
    let _ = writeln!(s, "## Cooling granular gas\n");
    let _ = writeln!(
        s,
        "{}",
        COOLING_TEXT.replace("{T}", &format!("{}", sizes.cooling_t))
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "simulator",
                "E(T/2)/E(0)",
                "E(T)/E(0)",
                "E(T) vs reference",
                "worst deviation",
                "impacts"
            ],
            cooling
        )
    );
    let _ = writeln!(s, "## What accuracy costs\n");
    let _ = writeln!(
        s,
        "{}",
        COST_TEXT.replace("{T}", &format!("{}", sizes.cost_t))
    );
    let _ = writeln!(
        s,
        "![accuracy against cost, and the cooling curves](accuracy.svg)\n"
    );
    let _ = writeln!(
        s,
        "{}",
        table(
            &[
                "engine",
                "mode",
                "dt",
                "impacts",
                "ms/step",
                "CPU s per simulated s",
                "gas energy error",
                "one-impact velocity error",
                "cradle velocity error"
            ],
            cost
        )
    );
    if !notes.is_empty() {
        let _ = writeln!(s, "## Notes from the run\n");
        for n in notes {
            let _ = writeln!(s, "- {n}");
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rustc_version_loses_its_commit_hash_only() {
        assert_eq!(
            without_hash("rustc 1.95.0 (59807616e 2026-04-14)"),
            "rustc 1.95.0 (2026-04-14)"
        );
        assert_eq!(without_hash("rustc 1.95.0"), "rustc 1.95.0");
    }

    #[test]
    fn findings_between_the_markers_are_kept_and_a_placeholder_otherwise() {
        let old = format!("# x\n{FINDINGS_BEGIN}\nmine\n{FINDINGS_END}\n");
        assert_eq!(findings(Some(&old)), "\nmine\n");
        assert!(findings(None).contains("Write the findings here"));
        assert!(findings(Some("no markers")).contains("Write the findings here"));
    }
}
