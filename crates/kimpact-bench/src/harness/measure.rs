//! What a run measures: energies and momenta, the errors of a short scene
//! against the reference, and a gas over time.

use crate::{Backend, DT, HarnessError, Method, R, RefSim, Setup, Sim, V};

/// The kinetic energy of `state` (masses from `setup`).
pub fn kinetic<const D: usize>(setup: &Setup<D>, state: &[(V<D>, V<D>)]) -> f64 {
    let each = setup.balls.iter().zip(state);
    each.map(|(b, (_, v))| 0.5 * b.mass * v.norm_squared())
        .sum()
}

/// The total momentum of `state` (masses from `setup`).
pub fn momentum<const D: usize>(setup: &Setup<D>, state: &[(V<D>, V<D>)]) -> V<D> {
    let each = setup.balls.iter().zip(state);
    each.map(|(b, (_, v))| v * b.mass).sum()
}

/// Errors of a short scene against the reference at the same time: the
/// largest velocity difference (the incoming speed is 1), the largest
/// position difference in radii, the kinetic energy kept, and the relative
/// |Δ momentum|.
#[allow(missing_docs)]
#[derive(Copy, Clone, Debug)]
pub struct ShortResult {
    pub dv: f64,
    pub dx: f64,
    pub kept: f64,
    pub dp: f64,
}

/// Run `setup` to `t_end` with `method` and the reference to the same
/// time, and compare.
///
/// # Errors
/// A scene a simulator refuses, or a reference that cannot go on.
pub fn short_run<const D: usize>(
    b: &Backend<D>,
    setup: &Setup<D>,
    method: Method,
    t_end: f64,
) -> Result<ShortResult, HarnessError> {
    let mut sim = b.sim(setup, method)?;
    sim.advance_to(t_end)?;
    let mut reference = RefSim::new(setup)?;
    reference.advance_to(sim.time())?;
    let (s, r, initial) = (sim.state(), reference.state(), setup.initial());
    let largest = |f: fn(&(V<D>, V<D>)) -> V<D>| {
        let each = s.iter().zip(&r).map(|(a, b)| (f(a) - f(b)).norm());
        each.fold(0.0, f64::max)
    };
    let p0 = momentum(setup, &initial);
    Ok(ShortResult {
        dv: largest(|x| x.1),
        dx: largest(|x| x.0) / R,
        kept: kinetic(setup, &s) / kinetic(setup, &initial),
        dp: (momentum(setup, &s) - p0).norm() / p0.norm(),
    })
}

/// A gas at checkpoints from time 0 (`t`): kinetic energy over the
/// initial one, |P| in units of sqrt(2 M E), impacts so far; speeds over
/// the rms speed pooled over the second half; then [`Sim::ms_per_step`],
/// why the run stopped early, [`Sim::impulse_residual`], the balls outside
/// the box at the end and [`Sim::diagnostics`].
#[allow(missing_docs)]
#[derive(Clone, Debug, Default)]
pub struct GasSeries {
    pub t: Vec<f64>,
    pub energy: Vec<f64>,
    pub momentum: Vec<f64>,
    pub impacts: Vec<u64>,
    pub speeds: Vec<f64>,
    pub ms_per_step: f64,
    pub error: Option<String>,
    pub residual: f64,
    pub escaped: usize,
    pub diagnostics: Option<String>,
}

/// Run `setup` with `method` to `t_end`, measuring at `checkpoints`
/// evenly spaced whole base steps. A reference that stops early ends the
/// series there (`error` says why).
///
/// # Errors
/// A scene the simulator refuses.
pub fn gas_series<const D: usize>(
    b: &Backend<D>,
    setup: &Setup<D>,
    method: Method,
    t_end: f64,
    checkpoints: usize,
) -> Result<GasSeries, HarnessError> {
    let mut sim = b.sim(setup, method)?;
    let initial = setup.initial();
    let e0 = kinetic(setup, &initial);
    let m_total: f64 = setup.balls.iter().map(|b| b.mass).sum();
    // |P| in units of sqrt(2 M E): about 1/sqrt(N) for an equilibrium gas.
    let p =
        |state: &[(V<D>, V<D>)], e: f64| momentum(setup, state).norm() / (2.0 * m_total * e).sqrt();
    let mut out = GasSeries {
        t: vec![0.0],
        energy: vec![1.0],
        momentum: vec![p(&initial, e0)],
        impacts: vec![0],
        ..GasSeries::default()
    };
    for c in 1..=checkpoints {
        // Whole base steps, so that every simulator stops at the same times.
        let steps = (t_end / DT * c as f64 / checkpoints as f64).round();
        if let Err(e) = sim.advance_to(steps * DT) {
            out.error = Some(e.to_string());
            break;
        }
        let state = sim.state();
        let e = kinetic(setup, &state);
        out.t.push(sim.time());
        out.energy.push(e / e0);
        out.momentum.push(p(&state, e));
        out.impacts.push(sim.totals().impacts());
        if 2 * c > checkpoints {
            let v_rms = (2.0 * e / m_total).sqrt();
            out.speeds
                .extend(state.iter().map(|(_, v)| v.norm() / v_rms));
        }
    }
    let (lo, hi) = (setup.bounds.lo, setup.bounds.hi);
    let outside = |p: &V<D>| (0..D).any(|k| !(p[k] >= lo[k] && p[k] <= hi[k]));
    out.escaped = sim.state().iter().filter(|(p, _)| outside(p)).count();
    out.ms_per_step = sim.ms_per_step();
    out.diagnostics = sim.diagnostics();
    out.residual = sim.impulse_residual();
    Ok(out)
}
