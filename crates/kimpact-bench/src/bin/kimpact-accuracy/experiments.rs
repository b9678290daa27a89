//! The comparisons: each job runs one scene in one build (and every mode,
//! or one mode) against the reference, and hands back its table rows, CSV
//! lines, plot points and summary rows.

use kimpact::Precision;
use kimpact_harness::{
    Backend, CostRow, DT, ErrorRow, GasSeries, HarnessError, Method, V, cradle_setup, gas_series,
    gas_setup, short_run, two_ball_setup, z_setup,
};
use serde::Serialize;

use crate::format::{e, pct};
use crate::stats::{ks, ks_maxwell};
use crate::z::{ZResult, z_run};

/// A line of `accuracy.csv`: one value of a series or of the cost sweep.
#[derive(Serialize)]
pub struct CsvRow {
    /// `gas`, `cooling` or `cost`.
    section: &'static str,
    /// The build (`2D f32`…).
    engine: &'static str,
    /// The simulator (`reference` or a mode).
    method: &'static str,
    /// The time step is rapier's default divided by this.
    dt_div: usize,
    /// The time (series) or the time step (cost).
    x: f64,
    /// What `value` is.
    quantity: &'static str,
    /// The value.
    value: f64,
}

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
    pub costs: Vec<CostRow>,
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

impl Out {
    fn row(&mut self, table: &str, cells: Vec<String>) {
        self.rows.push((table.to_owned(), cells));
    }

    /// A line of the CSV: `(section, engine, method, dt_div)`, then the
    /// point.
    fn csv(
        &mut self,
        (section, engine, method, dt_div): (&'static str, &'static str, Method, usize),
        x: f64,
        quantity: &'static str,
        value: f64,
    ) {
        let method = method.name();
        self.csv.push(CsvRow {
            section,
            engine,
            method,
            dt_div,
            x,
            quantity,
            value,
        });
    }

    fn point(&mut self, panel: &str, method: Method, x: f64, y: f64) {
        self.points.push((panel.to_owned(), method, x, y));
    }

    /// A summary row for rapier in `method` (the reference has none).
    #[allow(clippy::too_many_arguments)]
    fn error<const D: usize>(
        &mut self,
        scene: &str,
        b: &Backend<D>,
        method: Method,
        dt_div: usize,
        quantity: &'static str,
        error: f64,
        noise_floor: Option<f64>,
    ) {
        if let Some(mode) = method.mode() {
            self.errors.push(ErrorRow {
                scene: scene.to_owned(),
                dimension: D,
                precision: b.precision,
                mode,
                dt_div,
                quantity: quantity.to_owned(),
                error,
                noise_floor,
            });
        }
    }
}

/// How large and long every comparison is.
pub struct Sizes {
    /// Balls of the gases (statistics, cooling, cost).
    pub gas_n: usize,
    /// Simulated time of the gas statistics.
    pub gas_t: f64,
    /// Checkpoints of the gas statistics.
    pub gas_checkpoints: usize,
    /// Reference Z runs: measuring time (time units).
    pub z_ref_t: f64,
    /// rapier Z runs: measuring time.
    pub z_rapier_t: f64,
    /// Z runs: equilibration of the reference and of rapier.
    pub z_eq: (f64, f64),
    /// Z: the least distance from the walls beyond which density counts.
    pub w_min: f64,
    /// Z: the accessible box lengths, 2D, 3D and the reference's larger 3D.
    pub ell2: V<2>,
    /// See `ell2`.
    pub ell3: V<3>,
    /// See `ell2`.
    pub ell3_large: V<3>,
    /// Z: the reference's calibration time in each of those boxes.
    pub calibrate_t: [f64; 3],
    /// Simulated time of the cooling gas.
    pub cooling_t: f64,
    /// Checkpoints of the cooling gas.
    pub cooling_checkpoints: usize,
    /// Simulated time of the cost runs.
    pub cost_t: f64,
}

impl Sizes {
    /// The published run.
    pub fn full() -> Self {
        Self {
            gas_n: 200,
            gas_t: 100.0,
            gas_checkpoints: 100,
            z_ref_t: 2000.0,
            z_rapier_t: 100.0,
            z_eq: (50.0, 10.0),
            w_min: 3.5,
            ell2: V::<2>::new(60.0, 30.0),
            ell3: V::<3>::new(10.0, 10.0, 20.0),
            ell3_large: V::<3>::new(14.0, 14.0, 28.0),
            calibrate_t: [400.0, 100.0, 50.0],
            cooling_t: 30.0,
            cooling_checkpoints: 60,
            cost_t: 10.0,
        }
    }

    /// A smoke run: every comparison, on small scenes for short times.
    pub fn quick() -> Self {
        Self {
            gas_n: 50,
            gas_t: 2.0,
            gas_checkpoints: 20,
            z_ref_t: 20.0,
            z_rapier_t: 5.0,
            z_eq: (2.0, 1.0),
            w_min: 1.5,
            // The smallest boxes whose lattices still hold the calibrated
            // number of balls more than a diameter apart.
            ell2: V::<2>::new(20.0, 10.0),
            ell3: V::<3>::new(8.0, 8.0, 16.0),
            ell3_large: V::<3>::new(9.0, 9.0, 18.0),
            calibrate_t: [10.0, 10.0, 10.0],
            cooling_t: 2.0,
            cooling_checkpoints: 12,
            cost_t: 0.5,
        }
    }
}

/// One oblique impact (1:10 elastic, 1:1 dissipative) and Newton's cradle,
/// every mode of one build.
pub fn short_jobs<const D: usize>(b: Backend<D>) -> Result<Out, HarnessError> {
    let mut out = Out::default();
    for method in Method::RAPIER {
        for (m2, d) in [(10.0, 0.0), (1.0, 0.05)] {
            let s = short_run(&b, &two_ball_setup::<D>(m2, d, 0.6, DT), method, 10.0 * DT)?;
            if d > 0.0 {
                out.error(
                    "one_impact_dissipative",
                    &b,
                    method,
                    1,
                    "velocity_error",
                    s.dv,
                    None,
                );
            }
            out.row(
                "impact",
                vec![
                    b.label.into(),
                    method.name().into(),
                    format!("1:{m2}, d̃ = {d}"),
                    e(s.dv),
                    e(s.dx),
                    format!("{:.6}", s.kept),
                    e(s.dp),
                ],
            );
        }
        let s = short_run(&b, &cradle_setup::<D>(DT), method, 30.0 * DT)?;
        out.row(
            "cradle",
            vec![
                b.label.into(),
                method.name().into(),
                e(s.dv),
                format!("{:.4}", s.kept),
                e(s.dp),
            ],
        );
    }
    Ok(out)
}

/// The elastic gas over time in one build and mode against the reference
/// (and, with `native`, the reference's own rows).
pub fn gas_jobs<const D: usize>(
    b: Backend<D>,
    method: Method,
    sizes: &Sizes,
) -> Result<Out, HarnessError> {
    let mut out = Out::default();
    let n = sizes.gas_n;
    let setup = gas_setup::<D>(n, 0.0, DT, 1)?;
    let checkpoints = sizes.gas_checkpoints;
    let g = gas_series(&b, &setup, method, sizes.gas_t, checkpoints)?;
    let r = gas_series(&b, &setup, Method::Reference, sizes.gas_t, checkpoints)?;
    // The noise floor: the reference from other initial balls.
    let other = gas_series(
        &b,
        &gas_setup::<D>(n, 0.0, DT, 2)?,
        Method::Reference,
        sizes.gas_t,
        checkpoints,
    )?;
    let rate = |s: &GasSeries| *s.impacts.last().unwrap() as f64 / s.t.last().unwrap();
    let mean_p = |s: &GasSeries| s.momentum.iter().sum::<f64>() / s.momentum.len() as f64;
    let cells = |label: String, s: &GasSeries| {
        let mut sp = s.speeds.clone();
        let mut rsp = r.speeds.clone();
        vec![
            b.label.into(),
            label,
            format!("{:.6}", s.energy.last().unwrap()),
            format!("{:.3}", mean_p(s)),
            format!("{:.0}", rate(s)),
            pct(rate(s) / rate(&r) - 1.0),
            format!("{:.3}", ks(&mut sp, &mut rsp)),
            format!("{:.3}", ks_maxwell(D, &mut s.speeds.clone())),
            if s.ms_per_step.is_nan() {
                "–".into()
            } else {
                format!("{:.3}", s.ms_per_step)
            },
            if s.escaped > 0 {
                format!("{} escaped", s.escaped)
            } else {
                e(s.residual)
            },
        ]
    };
    let ks_ref = |s: &GasSeries| ks(&mut s.speeds.clone(), &mut r.speeds.clone());
    let rate_error = |s: &GasSeries| (rate(s) / rate(&r) - 1.0).abs();
    out.error(
        "gas",
        &b,
        method,
        1,
        "ks_speeds_vs_reference",
        ks_ref(&g),
        Some(ks_ref(&other)),
    );
    out.error(
        "gas",
        &b,
        method,
        1,
        "impact_rate_error",
        rate_error(&g),
        Some(rate_error(&other)),
    );
    if method == Method::NATIVE {
        let row = cells("reference".into(), &r);
        out.row("gas", row);
        let row = cells("reference, other balls".into(), &other);
        out.row("gas", row);
    }
    let row = cells(method.name().into(), &g);
    out.row("gas", row);
    if let Some(err) = &g.error {
        out.notes
            .push(format!("gas {} {}: {err}", b.label, method.name()));
    }
    if let Some(d) = &g.diagnostics {
        out.notes
            .push(format!("gas {} {}: {d}", b.label, method.name()));
    }
    for (s, m) in [(&g, method), (&r, Method::Reference)] {
        if m == Method::Reference && method != Method::NATIVE {
            continue;
        }
        for i in 0..s.t.len() {
            let key = ("gas", b.label, m, 1);
            out.csv(key, s.t[i], "energy", s.energy[i]);
            if i > 0 {
                let rate = (s.impacts[i] - s.impacts[i - 1]) as f64 / (s.t[i] - s.t[i - 1]);
                out.csv(key, s.t[i], "impact_rate", rate);
            }
            out.csv(key, s.t[i], "momentum", s.momentum[i]);
        }
    }
    Ok(out)
}

/// The cooling granular gas in one build, every mode against the
/// reference.
pub fn cooling_jobs<const D: usize>(b: Backend<D>, sizes: &Sizes) -> Result<Out, HarnessError> {
    let mut out = Out::default();
    let d = 0.01;
    let n = sizes.gas_n;
    let checkpoints = sizes.cooling_checkpoints;
    // With d̃ > 0 the reference can stall: grazing impacts are clamped to a
    // restitution of 1e-3, and three balls in contact then collapse into
    // infinitely many impacts at one instant (inelastic collapse). Take
    // the first two draws of the balls that it runs through for the whole
    // time: the first for the comparison, the second as the noise floor.
    let mut good: Vec<(u64, GasSeries)> = Vec::new();
    for seed in 3..16 {
        let g = gas_series(
            &b,
            &gas_setup::<D>(n, d, DT, seed)?,
            Method::Reference,
            sizes.cooling_t,
            checkpoints,
        )?;
        match &g.error {
            Some(err) => out.notes.push(format!(
                "cooling {} reference, draw {seed} (skipped): {err} (inelastic collapse)",
                b.label
            )),
            None => good.push((seed, g)),
        }
        if good.len() == 2 {
            break;
        }
    }
    let (Some((other_seed, other)), Some((seed, r))) = (good.pop(), good.pop()) else {
        out.notes.push(format!(
            "cooling {}: no two draws the reference runs through; no comparison",
            b.label
        ));
        return Ok(out);
    };
    out.notes.push(format!(
        "cooling {}: compared on draw {seed}; noise floor from draw {other_seed}",
        b.label
    ));
    let setup = gas_setup::<D>(n, d, DT, seed)?;
    let panel = format!("cooling {}", b.label);
    let mut runs = vec![(
        "reference, other balls".to_owned(),
        Method::Reference,
        other,
    )];
    for m in Method::RAPIER {
        let s = gas_series(&b, &setup, m, sizes.cooling_t, checkpoints)?;
        runs.push((m.name().to_owned(), m, s));
    }
    let worst = |s: &GasSeries| {
        let m = s.t.len().min(r.t.len());
        (1..m)
            .map(|i| (s.energy[i] / r.energy[i] - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let row = |label: &str, s: &GasSeries, vs: bool| {
        let m = s.t.len().min(r.t.len());
        let worst = worst(s);
        vec![
            b.label.into(),
            label.to_owned(),
            format!("{:.4}", s.energy[m / 2]),
            format!("{:.4}", s.energy[m - 1]),
            if vs {
                pct(s.energy[m - 1] / r.energy[m - 1] - 1.0)
            } else {
                "–".into()
            },
            if vs {
                format!("{:.1}%", 100.0 * worst)
            } else {
                "–".into()
            },
            format!("{}", s.impacts[m - 1]),
        ]
    };
    out.row("cooling", row("reference", &r, false));
    for i in 0..r.t.len() {
        out.csv(
            ("cooling", b.label, Method::Reference, 1),
            r.t[i],
            "energy",
            r.energy[i],
        );
        out.point(&panel, Method::Reference, r.t[i], r.energy[i]);
    }
    if let Some(err) = &r.error {
        out.notes
            .push(format!("cooling {} reference: {err}", b.label));
    }
    let floor = worst(&runs[0].2);
    for (label, method, s) in &runs {
        out.row("cooling", row(label, s, true));
        let dev = worst(s);
        out.error(
            "cooling",
            &b,
            *method,
            1,
            "worst_energy_deviation",
            dev,
            Some(floor),
        );
        if *method != Method::Reference {
            for i in 0..s.t.len() {
                out.csv(
                    ("cooling", b.label, *method, 1),
                    s.t[i],
                    "energy",
                    s.energy[i],
                );
                out.point(&panel, *method, s.t[i], s.energy[i]);
            }
        }
        if let Some(d) = &s.diagnostics {
            out.notes.push(format!("cooling {} {label}: {d}", b.label));
        }
        if let Some(err) = &s.error {
            out.notes
                .push(format!("cooling {} {label}: {err}", b.label));
        }
    }
    Ok(out)
}

/// One Z run: the case (dimension, η, box of `ell` with `n` balls) with
/// one simulator.
pub fn z_job<const D: usize>(
    b: Backend<D>,
    eta: f64,
    n: usize,
    ell: V<D>,
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
    let z = z_run(
        &b,
        &setup,
        method,
        ell,
        t_eq,
        t_run,
        blocks,
        0.5,
        sizes.w_min,
    )?;
    let lengths: Vec<String> = ell.iter().map(|x| format!("{x}")).collect();
    let case = format!("{D}D η = {eta}, ℓ = ({})", lengths.join(", "));
    let precision = if method == Method::Reference {
        Precision::F64
    } else {
        b.precision
    };
    let who = format!("{case}, {} {precision}", method.name());
    if let Some(err) = &z.error {
        out.notes.push(format!("Z {who}: {err}"));
    }
    if let Some(d) = &z.diagnostics {
        out.notes.push(format!("Z {who}: {d}"));
    }
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

/// The single-wall Z of a rapier run relative to the reference's in the
/// same case, with its standard error (both runs' combined).
pub fn z_vs_reference(x: &ZEntry, reference: &ZEntry) -> (f64, f64) {
    let (r, q) = (&x.r, &reference.r);
    let ratio = r.z_single / q.z_single;
    let err = ratio
        * ((r.z_single_err / r.z_single).powi(2) + (q.z_single_err / q.z_single).powi(2)).sqrt();
    (ratio - 1.0, err)
}

/// The summary rows of the Z runs: |single-wall Z vs the reference's − 1|
/// per case and rapier run, its standard error as the noise floor.
pub fn z_summary(z: &[ZEntry]) -> Vec<ErrorRow> {
    let mut rows = Vec::new();
    for x in z {
        let Some(mode) = x.method.mode() else {
            continue;
        };
        let reference = z
            .iter()
            .find(|y| y.case == x.case && y.method == Method::Reference);
        if let Some(q) = reference {
            let (dev, err) = z_vs_reference(x, q);
            rows.push(ErrorRow {
                scene: format!("compressibility_{}d_eta{}", x.d, x.eta),
                dimension: x.d,
                precision: x.precision,
                mode,
                dt_div: 1,
                quantity: "single_wall_z_vs_reference".to_owned(),
                error: dev.abs(),
                noise_floor: Some(err),
            });
        }
    }
    rows
}

/// The cost of accuracy in one build: every mode at dt, dt/2, dt/4 and
/// dt/8, the gas's CPU time against the errors of the gas, one impact and
/// the cradle.
pub fn cost_jobs<const D: usize>(b: Backend<D>, sizes: &Sizes) -> Result<Out, HarnessError> {
    let mut out = Out::default();
    for method in Method::RAPIER {
        for div in [1usize, 2, 4, 8] {
            let dt = DT / div as f64;
            let setup = gas_setup::<D>(sizes.gas_n, 0.0, dt, 1)?;
            let g = gas_series(&b, &setup, method, sizes.cost_t, 2)?;
            let cost = g.ms_per_step * div as f64 / DT / 1e3; // s per simulated s
            let energy = (g.energy.last().unwrap() - 1.0).abs().max(1e-16);
            let one = short_run(
                &b,
                &two_ball_setup::<D>(10.0, 0.0, 0.6, dt),
                method,
                10.0 * DT,
            )?;
            let cradle = short_run(&b, &cradle_setup::<D>(dt), method, 30.0 * DT)?;
            out.row(
                "cost",
                vec![
                    b.label.into(),
                    method.name().into(),
                    format!("dt/{div}"),
                    format!("{}", g.impacts.last().unwrap()),
                    format!("{:.3}", g.ms_per_step),
                    format!("{:.3}", cost),
                    e(energy),
                    e(one.dv),
                    e(cradle.dv),
                ],
            );
            let x = cost;
            out.point(&format!("gas energy error {}", b.label), method, x, energy);
            out.point(
                &format!("one impact {}", b.label),
                method,
                x,
                one.dv.max(1e-16),
            );
            out.point(
                &format!("cradle {}", b.label),
                method,
                x,
                cradle.dv.max(1e-16),
            );
            for (q, v) in [
                ("ms_per_step", g.ms_per_step),
                ("cpu_s_per_sim_s", cost),
                ("gas_energy_error", energy),
                ("impact_velocity_error", one.dv),
                ("cradle_velocity_error", cradle.dv),
            ] {
                out.csv(("cost", b.label, method, div), dt, q, v);
            }
            out.error("gas", &b, method, div, "energy_error", energy, None);
            out.error(
                "one_impact",
                &b,
                method,
                div,
                "velocity_error",
                one.dv,
                None,
            );
            out.error("cradle", &b, method, div, "velocity_error", cradle.dv, None);
            if let Some(mode) = method.mode() {
                out.costs.push(CostRow {
                    dimension: D,
                    precision: b.precision,
                    mode,
                    dt_div: div,
                    balls: sizes.gas_n,
                    ms_per_step: g.ms_per_step,
                    cpu_s_per_sim_s: cost,
                });
            }
        }
    }
    Ok(out)
}
