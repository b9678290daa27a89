//! The comparisons: each job runs one scene in one build (and every mode,
//! or one mode) against the reference, and hands back its table rows, CSV
//! lines, plot points and summary rows.

use kimpact::Precision;
use kimpact_harness::{
    Backend, DT, ErrorRow, GasSeries, HarnessError, Method, V, cradle_setup, gas_series, gas_setup,
    ks, ks_maxwell, short_run, two_ball_setup, z_setup,
};

use crate::report::{e, ms, pct};
use crate::z::{ZResult, z_run};

/// A name in `accuracy.csv`.
type Name = &'static str;

/// A line of `accuracy.csv`: one value of a series or of the cost sweep:
/// its section (`gas`, `cooling`, `cost`), build, simulator, time step
/// divisor, x (time, or the time step), quantity and value.
pub type CsvRow = (Name, Name, Name, usize, f64, Name, f64);

/// The header of `accuracy.csv`.
pub const CSV_HEADER: [&str; 7] = [
    "section", "engine", "method", "dt_div", "x", "quantity", "value",
];

/// What a job hands back: table rows (by table key), CSV lines, plot
/// points (by panel title and simulator), notes, Z results and summary
/// rows.
#[derive(Default)]
pub struct Out {
    pub rows: Vec<(String, Vec<String>)>,
    pub csv: Vec<CsvRow>,
    pub points: Vec<(String, Method, f64, f64)>,
    pub notes: Vec<String>,
    pub z: Vec<ZEntry>,
    pub errors: Vec<ErrorRow>,
}

impl Out {
    /// Add everything of `other`.
    pub fn absorb(&mut self, other: Out) {
        self.rows.extend(other.rows);
        self.csv.extend(other.csv);
        self.points.extend(other.points);
        self.notes.extend(other.notes);
        self.z.extend(other.z);
        self.errors.extend(other.errors);
    }
}

/// A job's output in one build: what it adds is labelled with the build.
struct Build<'a, const D: usize> {
    b: &'a Backend<D>,
    out: Out,
}

impl<'a, const D: usize> Build<'a, D> {
    fn new(b: &'a Backend<D>) -> Self {
        Self {
            b,
            out: Out::default(),
        }
    }

    /// A row of `table`, the build first.
    fn row(&mut self, table: &str, cells: Vec<String>) {
        let row = [vec![self.b.label.to_owned()], cells].concat();
        self.out.rows.push((table.to_owned(), row));
    }

    /// A line of the CSV in the section `s`.
    fn csv(&mut self, s: Name, m: Method, div: usize, x: f64, q: Name, v: f64) {
        self.out.csv.push((s, self.b.label, m.name(), div, x, q, v));
    }

    /// A point of the panel `title` (with the build's label) of the plot.
    fn point(&mut self, title: &str, method: Method, x: f64, y: f64) {
        let title = format!("{title} {}", self.b.label);
        self.out.points.push((title, method, x, y));
    }

    /// A note about `who` in this build.
    fn note(&mut self, section: &str, who: &str, text: impl std::fmt::Display) {
        let note = format!("{section} {}{who}: {text}", self.b.label);
        self.out.notes.push(note);
    }

    /// A summary row for rapier in `m` (the reference has none).
    fn error(&mut self, m: Method, scene: &str, div: usize, q: &str, v: f64, floor: Option<f64>) {
        let Some(mode) = m.mode() else { return };
        self.out.errors.push(ErrorRow {
            scene: scene.to_owned(),
            dimension: D,
            precision: self.b.precision,
            mode,
            dt_div: div,
            quantity: q.to_owned(),
            error: v,
            noise_floor: floor,
        });
    }

    /// The energy curve of `series` (of `method`) in the cooling section:
    /// CSV lines and plot points.
    fn cooling_curve(&mut self, method: Method, series: &GasSeries) {
        for (&t, &e) in series.t.iter().zip(&series.energy) {
            self.csv("cooling", method, 1, t, "energy", e);
            self.point("cooling", method, t, e);
        }
    }
}

/// One Z run: the case (dimension, η and box, the same for every
/// simulator), who ran it and the result.
pub struct ZEntry {
    pub case: String,
    pub d: usize,
    pub eta: f64,
    pub method: Method,
    /// The rapier build's precision (the reference computes in f64).
    pub precision: Precision,
    pub t_run: f64,
    pub r: ZResult,
}

/// How large and long every comparison is: the gases; the Z runs' times,
/// least distance from the walls, box lengths (2D, 3D, the reference's
/// larger 3D) and calibration times; the cooling gas; the cost runs.
pub struct Sizes {
    pub gas_n: usize,
    pub gas_t: f64,
    pub gas_checkpoints: usize,
    pub z_ref_t: f64,
    pub z_rapier_t: f64,
    pub z_eq: (f64, f64),
    pub w_min: f64,
    pub ell2: V<2>,
    pub ell3: V<3>,
    pub ell3_large: V<3>,
    pub calibrate_t: [f64; 3],
    pub cooling_t: f64,
    pub cooling_checkpoints: usize,
    pub cost_t: f64,
}

/// `full`, or `quick` in a smoke run.
fn pick<T>(quick: bool, full: T, smoke: T) -> T {
    if quick { smoke } else { full }
}

impl Sizes {
    /// The published run, or with `quick` a smoke run: every comparison on
    /// small scenes for short times (the smallest boxes whose lattices still
    /// hold the calibrated balls more than a diameter apart).
    pub fn new(quick: bool) -> Self {
        Self {
            gas_n: pick(quick, 200, 50),
            gas_t: pick(quick, 100.0, 2.0),
            gas_checkpoints: pick(quick, 100, 20),
            z_ref_t: pick(quick, 2000.0, 20.0),
            z_rapier_t: pick(quick, 100.0, 5.0),
            z_eq: pick(quick, (50.0, 10.0), (2.0, 1.0)),
            w_min: pick(quick, 3.5, 1.5),
            ell2: pick(quick, V::<2>::new(60.0, 30.0), V::<2>::new(20.0, 10.0)),
            ell3: pick(
                quick,
                V::<3>::new(10.0, 10.0, 20.0),
                V::<3>::new(8.0, 8.0, 16.0),
            ),
            ell3_large: pick(
                quick,
                V::<3>::new(14.0, 14.0, 28.0),
                V::<3>::new(9.0, 9.0, 18.0),
            ),
            calibrate_t: pick(quick, [400.0, 100.0, 50.0], [10.0, 10.0, 10.0]),
            cooling_t: pick(quick, 30.0, 2.0),
            cooling_checkpoints: pick(quick, 60, 12),
            cost_t: pick(quick, 10.0, 0.5),
        }
    }
}

/// One oblique impact (1:10 elastic, 1:1 dissipative) and Newton's cradle,
/// every mode of one build.
pub fn short_jobs<const D: usize>(b: Backend<D>) -> Result<Out, HarnessError> {
    let mut j = Build::new(&b);
    for m in Method::RAPIER {
        for (m2, d) in [(10.0, 0.0), (1.0, 0.05)] {
            let s = short_run(&b, &two_ball_setup::<D>(m2, d, 0.6, DT), m, 10.0 * DT)?;
            if d > 0.0 {
                j.error(m, "one_impact_dissipative", 1, "velocity_error", s.dv, None);
            }
            let (kept, masses) = (format!("{:.6}", s.kept), format!("1:{m2}, d̃ = {d}"));
            let (name, dv, dx, dp) = (m.name().into(), e(s.dv), e(s.dx), e(s.dp));
            j.row("impact", vec![name, masses, dv, dx, kept, dp]);
        }
        let s = short_run(&b, &cradle_setup::<D>(DT), m, 30.0 * DT)?;
        let (name, kept) = (m.name().into(), format!("{:.4}", s.kept));
        j.row("cradle", vec![name, e(s.dv), kept, e(s.dp)]);
    }
    Ok(j.out)
}

/// The elastic gas over time in one build and mode against the reference
/// (and, with `native`, the reference's own rows).
pub fn gas_jobs<const D: usize>(
    b: Backend<D>,
    m: Method,
    sizes: &Sizes,
) -> Result<Out, HarnessError> {
    let mut j = Build::new(&b);
    let (n, t, checkpoints) = (sizes.gas_n, sizes.gas_t, sizes.gas_checkpoints);
    let setup = gas_setup::<D>(n, 0.0, DT, 1)?;
    let g = gas_series(&b, &setup, m, t, checkpoints)?;
    let r = gas_series(&b, &setup, Method::Reference, t, checkpoints)?;
    // The noise floor: the reference from other initial balls.
    let other_balls = gas_setup::<D>(n, 0.0, DT, 2)?;
    let other = gas_series(&b, &other_balls, Method::Reference, t, checkpoints)?;
    let rate = |s: &GasSeries| *s.impacts.last().unwrap() as f64 / s.t.last().unwrap();
    let mean_p = |s: &GasSeries| s.momentum.iter().sum::<f64>() / s.momentum.len() as f64;
    let ks_ref = |s: &GasSeries| ks(&mut s.speeds.clone(), &mut r.speeds.clone());
    let rate_error = |s: &GasSeries| (rate(s) / rate(&r) - 1.0).abs();
    let cells = |label: &str, s: &GasSeries| {
        let residual = match s.escaped {
            0 => e(s.residual),
            n => format!("{n} escaped"),
        };
        vec![
            label.to_owned(),
            format!("{:.6}", s.energy.last().unwrap()),
            format!("{:.3}", mean_p(s)),
            format!("{:.0}", rate(s)),
            pct(rate(s) / rate(&r) - 1.0),
            format!("{:.3}", ks_ref(s)),
            format!("{:.3}", ks_maxwell(D, &mut s.speeds.clone())),
            ms(s.ms_per_step, 3),
            residual,
        ]
    };
    let (ks_e, ks_floor) = (ks_ref(&g), ks_ref(&other));
    j.error(m, "gas", 1, "ks_speeds_vs_reference", ks_e, Some(ks_floor));
    let (rate_e, rate_floor) = (rate_error(&g), rate_error(&other));
    j.error(m, "gas", 1, "impact_rate_error", rate_e, Some(rate_floor));
    let mut series = vec![(&g, m)];
    if m == Method::NATIVE {
        j.row("gas", cells("reference", &r));
        j.row("gas", cells("reference, other balls", &other));
        series.push((&r, Method::Reference));
    }
    j.row("gas", cells(m.name(), &g));
    let who = format!(" {}", m.name());
    for text in g.error.iter().chain(&g.diagnostics) {
        j.note("gas", &who, text);
    }
    for (s, m) in series {
        for i in 0..s.t.len() {
            j.csv("gas", m, 1, s.t[i], "energy", s.energy[i]);
            if i > 0 {
                let rate = (s.impacts[i] - s.impacts[i - 1]) as f64 / (s.t[i] - s.t[i - 1]);
                j.csv("gas", m, 1, s.t[i], "impact_rate", rate);
            }
            j.csv("gas", m, 1, s.t[i], "momentum", s.momentum[i]);
        }
    }
    Ok(j.out)
}

/// The cooling granular gas in one build, every mode against the
/// reference.
pub fn cooling_jobs<const D: usize>(b: Backend<D>, sizes: &Sizes) -> Result<Out, HarnessError> {
    let mut j = Build::new(&b);
    let (n, d) = (sizes.gas_n, 0.01);
    let (t, checkpoints) = (sizes.cooling_t, sizes.cooling_checkpoints);
    // With d̃ > 0 the reference can stall (inelastic collapse): take the
    // first two draws it runs through, for the comparison and the noise
    // floor.
    let mut good: Vec<(u64, GasSeries)> = Vec::new();
    for seed in 3..16 {
        let setup = gas_setup::<D>(n, d, DT, seed)?;
        let g = gas_series(&b, &setup, Method::Reference, t, checkpoints)?;
        match &g.error {
            Some(err) => {
                let who = format!(" reference, draw {seed} (skipped)");
                j.note("cooling", &who, format!("{err} (inelastic collapse)"));
            }
            None => good.push((seed, g)),
        }
        if good.len() == 2 {
            break;
        }
    }
    let (Some((other_seed, other)), Some((seed, r))) = (good.pop(), good.pop()) else {
        let none = "no two draws the reference runs through; no comparison";
        j.note("cooling", "", none);
        return Ok(j.out);
    };
    let draws = format!("compared on draw {seed}; noise floor from draw {other_seed}");
    j.note("cooling", "", draws);
    let setup = gas_setup::<D>(n, d, DT, seed)?;
    let mut runs = vec![("reference, other balls", Method::Reference, other)];
    for m in Method::RAPIER {
        runs.push((m.name(), m, gas_series(&b, &setup, m, t, checkpoints)?));
    }
    let deviation = |s: &GasSeries, i: usize| (s.energy[i] / r.energy[i] - 1.0).abs();
    let worst = |s: &GasSeries| {
        let checkpoints = 1..s.t.len().min(r.t.len());
        checkpoints.map(|i| deviation(s, i)).fold(0.0, f64::max)
    };
    let row = |label: &str, s: &GasSeries, vs: bool| {
        let k = s.t.len().min(r.t.len());
        let end = pct(s.energy[k - 1] / r.energy[k - 1] - 1.0);
        let (end, worst) = match vs {
            true => (end, format!("{:.1}%", 100.0 * worst(s))),
            false => ("–".into(), "–".into()),
        };
        let (label, impacts) = (label.to_owned(), s.impacts[k - 1].to_string());
        let energy = |i: usize| format!("{:.4}", s.energy[i]);
        vec![label, energy(k / 2), energy(k - 1), end, worst, impacts]
    };
    j.row("cooling", row("reference", &r, false));
    j.cooling_curve(Method::Reference, &r);
    let floor = worst(&runs[0].2);
    for (label, m, s) in &runs {
        j.row("cooling", row(label, s, true));
        let (q, deviation) = ("worst_energy_deviation", worst(s));
        j.error(*m, "cooling", 1, q, deviation, Some(floor));
        if *m != Method::Reference {
            j.cooling_curve(*m, s);
        }
        for text in s.diagnostics.iter().chain(&s.error) {
            j.note("cooling", &format!(" {label}"), text);
        }
    }
    Ok(j.out)
}

/// One Z run: the case (dimension, η, box of `ell` with `n` balls) with
/// one simulator.
pub fn z_job<const D: usize>(
    b: Backend<D>,
    (eta, n, ell): (f64, usize, V<D>),
    method: Method,
    sizes: &Sizes,
) -> Result<Out, HarnessError> {
    let mut out = Out::default();
    let setup = z_setup::<D>(n, ell, 11)?;
    let (eq_ref, eq_rapier) = sizes.z_eq;
    let (t_eq, t_run, blocks) = match (method, D) {
        (Method::Reference, 2) => (eq_ref, sizes.z_ref_t * 4.0, 20),
        (Method::Reference, _) if n > 2000 => (eq_ref, 0.75 * sizes.z_ref_t, 20),
        (Method::Reference, _) => (eq_ref, sizes.z_ref_t, 20),
        (_, 2) => (eq_rapier, sizes.z_rapier_t, 10),
        _ => (eq_rapier, 0.4 * sizes.z_rapier_t, 10),
    };
    let z = z_run(&b, &setup, method, ell, (t_eq, t_run, blocks), sizes.w_min)?;
    let lengths: Vec<String> = ell.iter().map(|x| format!("{x}")).collect();
    let case = format!("{D}D η = {eta}, ℓ = ({})", lengths.join(", "));
    let precision = method.mode().map_or(Precision::F64, |_| b.precision);
    let who = format!("{case}, {} {precision}", method.name());
    let errors = z.error.iter().map(ToString::to_string);
    let notes = errors.chain(z.diagnostics.clone());
    out.notes.extend(notes.map(|t| format!("Z {who}: {t}")));
    out.z.push(ZEntry {
        case,
        d: D,
        eta,
        method,
        precision,
        t_run,
        r: z,
    });
    Ok(out)
}

/// The reference's run of `x`'s case.
pub fn reference_of<'a>(z: &'a [ZEntry], x: &ZEntry) -> Option<&'a ZEntry> {
    z.iter()
        .find(|y| y.case == x.case && y.method == Method::Reference)
}

/// The single-wall Z of a rapier run relative to the reference's in the
/// same case, with its standard error (both runs' combined).
pub fn z_vs_reference(x: &ZEntry, reference: &ZEntry) -> (f64, f64) {
    let (r, q) = (&x.r, &reference.r);
    let ratio = r.z_single / q.z_single;
    let rel = |z: &ZResult| (z.z_single_err / z.z_single).powi(2);
    (ratio - 1.0, ratio * (rel(r) + rel(q)).sqrt())
}

/// The summary rows of the Z runs: |single-wall Z vs the reference's − 1|
/// per case and rapier run, its standard error as the noise floor.
pub fn z_summary(z: &[ZEntry]) -> Vec<ErrorRow> {
    z.iter()
        .filter_map(|x| {
            let (dev, err) = z_vs_reference(x, reference_of(z, x)?);
            Some(ErrorRow {
                scene: format!("compressibility_{}d_eta{}", x.d, x.eta),
                dimension: x.d,
                precision: x.precision,
                mode: x.method.mode()?,
                dt_div: 1,
                quantity: "single_wall_z_vs_reference".to_owned(),
                error: dev.abs(),
                noise_floor: Some(err),
            })
        })
        .collect()
}

/// The cost of accuracy in one build: every mode at dt, dt/2, dt/4 and
/// dt/8, the gas's CPU time against the errors of the gas, one impact and
/// the cradle.
pub fn cost_jobs<const D: usize>(b: Backend<D>, sizes: &Sizes) -> Result<Out, HarnessError> {
    let mut j = Build::new(&b);
    for m in Method::RAPIER {
        for div in [1usize, 2, 4, 8] {
            let dt = DT / div as f64;
            let gas = gas_setup::<D>(sizes.gas_n, 0.0, dt, 1)?;
            let g = gas_series(&b, &gas, m, sizes.cost_t, 2)?;
            let cost = g.ms_per_step * div as f64 / DT / 1e3; // s per simulated s
            let energy = (g.energy.last().unwrap() - 1.0).abs().max(1e-16);
            let one = short_run(&b, &two_ball_setup::<D>(10.0, 0.0, 0.6, dt), m, 10.0 * DT)?;
            let cradle = short_run(&b, &cradle_setup::<D>(dt), m, 30.0 * DT)?;
            let impacts = format!("{}", g.impacts.last().unwrap());
            let (ms, s) = (format!("{:.3}", g.ms_per_step), format!("{cost:.3}"));
            let errors = [e(energy), e(one.dv), e(cradle.dv)];
            let cells = [m.name().into(), format!("dt/{div}"), impacts, ms, s];
            j.row("cost", cells.into_iter().chain(errors).collect());
            j.point("gas energy error", m, cost, energy);
            j.point("one impact", m, cost, one.dv.max(1e-16));
            j.point("cradle", m, cost, cradle.dv.max(1e-16));
            for (q, v) in [
                ("ms_per_step", g.ms_per_step),
                ("cpu_s_per_sim_s", cost),
                ("gas_energy_error", energy),
                ("impact_velocity_error", one.dv),
                ("cradle_velocity_error", cradle.dv),
            ] {
                j.csv("cost", m, div, dt, q, v);
            }
            j.error(m, "gas", div, "energy_error", energy, None);
            j.error(m, "one_impact", div, "velocity_error", one.dv, None);
            j.error(m, "cradle", div, "velocity_error", cradle.dv, None);
        }
    }
    Ok(j.out)
}
