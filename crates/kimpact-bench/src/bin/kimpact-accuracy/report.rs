//! `accuracy.md`: the template `accuracy.md.in` (the method's prose and
//! the tables' headers) filled with the tables, the command and the
//! machine, with the hand-written Findings kept from the previous file;
//! and how numbers are written in it.

use kimpact_harness::Method;

use crate::experiments::{Sizes, ZEntry, reference_of, z_vs_reference};
use crate::z::eos;

/// A number in one-digit scientific notation (`0` for zero).
pub fn e(x: f64) -> String {
    match x {
        _ if x == 0.0 => "0".to_owned(),
        _ if !x.is_finite() => format!("{x}"),
        _ => format!("{x:.1e}"),
    }
}

/// A relative deviation as a signed percentage.
pub fn pct(x: f64) -> String {
    format!("{:+.2}%", 100.0 * x)
}

/// Milliseconds with `digits` decimals, `–` for NaN (the reference's).
pub fn ms(x: f64, digits: usize) -> String {
    if x.is_nan() {
        "–".into()
    } else {
        format!("{x:.digits$}")
    }
}

/// The markers of the hand-written findings in `accuracy.md`.
const FINDINGS_BEGIN: &str = "<!-- findings: hand-written, kept by the generator -->";
const FINDINGS_END: &str = "<!-- end of findings -->";

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
        let (case, eta, d, method, t_run, r) = (&x.case, x.eta, x.d, x.method, x.t_run, &x.r);
        let reference = reference_of(z, x);
        let fit = eos(d, r.eta_bulk);
        let name = ["Henderson", "Carnahan–Starling"][d - 2];
        let vs_ref = match reference {
            Some(q) if method != Method::Reference => {
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
            ms(r.ms_per_step, 2),
            e(r.residual),
        ]);
        if method == Method::Reference {
            let naive = pct(r.z_naive / eos(d, eta) - 1.0);
            let single = pct(r.z_single / fit - 1.0);
            let by_w = r.by_w.iter().map(|&(w, eta_w, z_w)| {
                let vs_eos = pct(z_w / eos(d, eta_w) - 1.0);
                format!("{w}: η {eta_w:.4}, Z/EOS {vs_eos}")
            });
            let row = [case.clone(), naive, single].into_iter().chain(by_w);
            checks.push(row.collect());
        }
    }
    (main, checks)
}

/// What `accuracy.md` is filled with: the jobs' rows by the template's
/// table (`impact`, `cradle`…), the Z runs, the findings to keep, and the
/// run's notes, `--quick`, worker threads, wall time (s) and sizes.
pub struct Document<'a> {
    pub rows: &'a [(String, Vec<String>)],
    pub z: &'a [ZEntry],
    pub findings: &'a str,
    pub notes: &'a [String],
    pub quick: bool,
    pub threads: usize,
    pub elapsed: f64,
    pub sizes: &'a Sizes,
}

/// The whole of `accuracy.md`: the template `accuracy.md.in` (the prose
/// and the tables' headers) filled in.
pub fn document(d: &Document<'_>) -> String {
    let (z, z_checks) = z_tables(d.z);
    let mut rows: Vec<(&str, &Vec<String>)> = d.rows.iter().map(|(k, r)| (k.as_str(), r)).collect();
    rows.extend(z.iter().map(|r| ("z", r)));
    rows.extend(z_checks.iter().map(|r| ("z_checks", r)));
    let table = |key| {
        let mine = rows.iter().filter(|r| r.0 == key);
        mine.map(|r| format!("| {} |\n", r.1.join(" | ")))
            .collect::<String>()
    };
    let quick = if d.quick {
        "**A smoke run (`--quick`)**: smaller scenes and much shorter runs than the text below describes; its figures mean nothing.\n\n"
    } else {
        ""
    };
    let notes = match d.notes.is_empty() {
        true => String::new(),
        false => {
            let notes: String = d.notes.iter().map(|n| format!("- {n}\n")).collect();
            format!("## Notes from the run\n\n{notes}\n")
        }
    };
    let tables = [
        "impact", "cradle", "gas", "z", "z_checks", "cooling", "cost",
    ];
    let mut fills: Vec<(&str, String)> = tables.iter().map(|&k| (k, table(k))).collect();
    // The texts from outside the program last: nothing in them is filled.
    fills.extend([
        ("gas_t", d.sizes.gas_t.to_string()),
        ("cooling_t", d.sizes.cooling_t.to_string()),
        ("cost_t", d.sizes.cost_t.to_string()),
        ("command", command(d.quick)),
        ("threads", d.threads.to_string()),
        ("elapsed", format!("{:.0}", d.elapsed)),
        ("quick", quick.to_owned()),
        ("notes", notes),
        ("machine", kimpact_harness::machine()),
        ("findings", d.findings.to_owned()),
    ]);
    let template = include_str!("accuracy.md.in");
    fills.iter().fold(template.to_owned(), |doc, (key, value)| {
        doc.replace(&format!("{{{key}}}"), value)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn findings_between_the_markers_are_kept_and_a_placeholder_otherwise() {
        let old = format!("# x\n{FINDINGS_BEGIN}\nmine\n{FINDINGS_END}\n");
        assert_eq!(findings(Some(&old)), "\nmine\n");
        assert!(findings(None).contains("Write the findings here"));
        assert!(findings(Some("no markers")).contains("Write the findings here"));
    }
}
