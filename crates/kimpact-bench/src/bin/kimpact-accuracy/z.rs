//! The compressibility factor Z = P/(ρ kT) of hard disks and spheres, from
//! the wall impulses and the density away from the walls.

use kimpact_harness::{
    Backend, DT, HarnessError, Method, R, Setup, V, ball_volume, kinetic, mean_and_error, z_setup,
};

/// The equation of state of the dimension: Henderson's for hard disks
/// (2D), Carnahan–Starling for hard spheres (3D).
pub fn eos(d: usize, eta: f64) -> f64 {
    match d {
        2 => (1.0 + eta * eta / 8.0) / (1.0 - eta).powi(2),
        _ => (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3),
    }
}

/// The distances from the walls beyond which the density is counted: the
/// one used (first), one σ closer and one σ farther, to show how much the
/// result depends on it. A fifth of the shortest accessible length, at
/// least `w_min` (3.5 σ in the full run: the density oscillations near a
/// wall decay over a few σ).
fn ws<const D: usize>(ell: &V<D>, w_min: f64) -> [f64; 3] {
    let w = (0.2 * ell.min()).max(w_min);
    [w, w - 1.0, w + 1.0]
}

/// How many distances from the walls [`ws`] gives.
const NW: usize = 3;

/// The number of balls that gives the bulk packing fraction `eta` in the
/// box `ell`: the nominal count `eta ℓ^D / v`, corrected twice by short
/// reference runs of `t` time units (the walls hold some balls back).
///
/// # Errors
/// A box too small for its balls, or a reference run that stopped.
pub fn calibrate<const D: usize>(
    b: &Backend<D>,
    eta: f64,
    ell: V<D>,
    t: f64,
    w_min: f64,
) -> Result<usize, HarnessError> {
    let mut n = (eta * ell.product() / ball_volume(D, R)).round() as usize;
    for _ in 0..2 {
        let setup = z_setup::<D>(n, ell, 11)?;
        let z = z_run(b, &setup, Method::Reference, ell, (0.2 * t, t, 4), w_min)?;
        if let Some(e) = z.error {
            return Err(e);
        }
        n = (n as f64 * eta / z.eta_bulk).round() as usize;
    }
    Ok(n)
}

/// What a Z run measured: its balls; the packing fraction away from the
/// walls; Z with the walls' excess near their ends eliminated, and its
/// standard error over the blocks; the naive Z (total wall force over the
/// whole surface, nominal density N/V); the single-wall Z (force on the
/// walls of axis 0 over their accessible area, bulk density) and its
/// standard error; (w, bulk η, Z) for each distance from the walls; the
/// relative change of kT; the impacts; ms per rapier step (NaN for the
/// reference); the wall-impulse residual; why the run stopped early and
/// what the simulator counted that is unusual.
#[derive(Clone)]
pub struct ZResult {
    pub n: usize,
    pub eta_bulk: f64,
    pub z: f64,
    pub z_err: f64,
    pub z_naive: f64,
    pub z_single: f64,
    pub z_single_err: f64,
    pub by_w: Vec<(f64, f64, f64)>,
    pub kt_drift: f64,
    pub impacts: u64,
    pub ms_per_step: f64,
    pub residual: f64,
    pub error: Option<HarnessError>,
    pub diagnostics: Option<String>,
}

/// Pressure from the mean forces on the walls of each axis, `f[k]`, with
/// the walls' excess near edges and corners eliminated (see the doc):
/// 2D, `F_k = P ℓ_j − 2γ`; 3D, square cross-section `ℓ = (a, a, c)`,
/// `F_k = P A_k − 2γ Per_k` (edge line tension neglected).
fn pressure<const D: usize>(f: &[f64; D], ell: &V<D>) -> f64 {
    if D == 2 {
        (f[1] - f[0]) / (ell[0] - ell[1])
    } else {
        let (a, c) = (ell[0], ell[2]);
        let fx = 0.5 * (f[0] + f[1]);
        (2.0 * fx - (a + c) * f[2] / a) / (a * (c - a))
    }
}

/// Time units between two samples of the density.
const SAMPLE: f64 = 0.5;

/// Z from a run: equilibrate for `t_eq`, then measure over `t_run` in
/// `blocks` blocks, counting the centres in the regions at least `ws(&ell)[i]`
/// from every wall every [`SAMPLE`] time units. A run that stops early
/// returns what it has, with `error` set.
///
/// # Errors
/// A scene the simulator refuses.
pub fn z_run<const D: usize>(
    b: &Backend<D>,
    setup: &Setup<D>,
    method: Method,
    ell: V<D>,
    (t_eq, t_run, blocks): (f64, f64, usize),
    w_min: f64,
) -> Result<ZResult, HarnessError> {
    let n = setup.balls.len();
    let mut sim = b.sim(setup, method)?;
    let size = setup.bounds.size();
    let region = |w: f64| size.add_scalar(-2.0 * w).product();
    let mut out = ZResult {
        n,
        eta_bulk: f64::NAN,
        z: f64::NAN,
        z_err: f64::NAN,
        z_naive: f64::NAN,
        z_single: f64::NAN,
        z_single_err: f64::NAN,
        by_w: Vec::new(),
        kt_drift: f64::NAN,
        impacts: 0,
        ms_per_step: f64::NAN,
        residual: 0.0,
        error: None,
        diagnostics: None,
    };
    let steps_of = |t: f64| (t / DT).round() * DT;
    if let Err(e) = sim.advance_to(steps_of(t_eq)) {
        out.error = Some(e);
        return Ok(out);
    }
    let kt = |state: &[(V<D>, V<D>)]| 2.0 * kinetic(setup, state) / (D * n) as f64;
    let kt0 = kt(&sim.state());
    let mut last = sim.totals();
    let mut t_last = sim.time();
    let samples_per_block = ((t_run / blocks as f64) / SAMPLE).round().max(1.0) as usize;
    let (mut z_blocks, mut single_blocks) = (Vec::new(), Vec::new());
    let (mut sum_f, mut sum_t, mut sum_kt) = ([0.0; D], 0.0, 0.0);
    let mut sum_rho = [0.0; NW];
    let mut impulse_total = 0.0;
    for _ in 0..blocks {
        let (mut rho, mut temp) = ([0.0; NW], 0.0);
        for _ in 0..samples_per_block {
            let target = steps_of(sim.time() + SAMPLE);
            if let Err(e) = sim.advance_to(target) {
                out.error = Some(e);
                return Ok(out);
            }
            let state = sim.state();
            for (i, &w) in ws(&ell, w_min).iter().enumerate() {
                let within = |p: &V<D>| (0..D).all(|k| p[k] >= w && p[k] <= size[k] - w);
                let inside = state.iter().filter(|(p, _)| within(p)).count();
                rho[i] += inside as f64 / region(w);
            }
            temp += kt(&state);
        }
        for r in &mut rho {
            *r /= samples_per_block as f64;
        }
        temp /= samples_per_block as f64;
        let now = sim.totals();
        let dt_block = sim.time() - t_last;
        let mut f = [0.0; D];
        for k in 0..D {
            let j = now.wall_impulse[k][0] + now.wall_impulse[k][1]
                - last.wall_impulse[k][0]
                - last.wall_impulse[k][1];
            f[k] = 0.5 * j / dt_block;
            impulse_total += j;
            sum_f[k] += f[k] * dt_block;
        }
        z_blocks.push(pressure(&f, &ell) / (rho[0] * temp));
        single_blocks.push(f[0] / (ell.product() / ell[0]) / (rho[0] * temp));
        sum_t += dt_block;
        for i in 0..NW {
            sum_rho[i] += rho[i];
        }
        sum_kt += temp;
        last = now;
        t_last = sim.time();
    }
    let f: [f64; D] = std::array::from_fn(|k| sum_f[k] / sum_t);
    let temp = sum_kt / blocks as f64;
    let p = pressure(&f, &ell);
    let rho: Vec<f64> = sum_rho.iter().map(|r| r / blocks as f64).collect();
    out.z = p / (rho[0] * temp);
    out.z_err = mean_and_error(&z_blocks).1;
    out.eta_bulk = rho[0] * ball_volume(D, R);
    let by_w = ws(&ell, w_min).into_iter().zip(&rho);
    out.by_w = by_w
        .map(|(w, &r)| (w, r * ball_volume(D, R), p / (r * temp)))
        .collect();
    let area: f64 = (0..D).map(|k| 2.0 * size.product() / size[k]).sum();
    let p_naive = impulse_total / sum_t / area;
    out.z_naive = p_naive / (n as f64 / size.product() * temp);
    out.z_single = f[0] / (ell.product() / ell[0]) / (rho[0] * temp);
    out.z_single_err = mean_and_error(&single_blocks).1;
    out.kt_drift = temp / kt0 - 1.0;
    out.impacts = sim.totals().impacts();
    out.ms_per_step = sim.ms_per_step();
    out.residual = sim.impulse_residual();
    out.diagnostics = sim.diagnostics();
    Ok(out)
}
