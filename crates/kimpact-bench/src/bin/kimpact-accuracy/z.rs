//! The compressibility factor Z = P/(ρ kT) of hard disks and spheres, from
//! the wall impulses and the density away from the walls.

use kimpact_harness::{
    Backend, DT, HarnessError, Method, R, Setup, Sim, V, ball_volume, kinetic, mean_and_error,
    z_setup,
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
/// one used (a fifth of the shortest accessible length, at least `w_min`:
/// the density oscillates over a few σ near a wall), one σ closer and one
/// σ farther.
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
/// walls; Z with the walls' excess near their ends eliminated, ± its
/// standard error over the blocks; the naive Z (total wall force over the
/// whole surface, density N/V); the single-wall Z (the walls of axis 0,
/// bulk density) ± its error; (w, bulk η, Z) for each of [`ws`]; the
/// relative change of kT; the impacts; then as [`Sim`]'s; why the run
/// stopped early.
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

impl ZResult {
    /// A run of `n` balls that measured nothing (yet).
    fn new(n: usize) -> Self {
        Self {
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
        }
    }
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

/// `t` rounded to whole base steps.
fn steps_of(t: f64) -> f64 {
    (t / DT).round() * DT
}

/// kT of `state`.
fn kt<const D: usize>(setup: &Setup<D>, state: &[(V<D>, V<D>)]) -> f64 {
    2.0 * kinetic(setup, state) / (D * setup.balls.len()) as f64
}

/// One block of `samples` samples, one every [`SAMPLE`] time units: the
/// mean densities in the regions at least [`ws`] from every wall, and the
/// mean kT.
fn block<const D: usize>(
    sim: &mut dyn Sim<D>,
    setup: &Setup<D>,
    (ell, w_min): (&V<D>, f64),
    samples: f64,
) -> Result<([f64; NW], f64), HarnessError> {
    let size = setup.bounds.size();
    let (mut rho, mut temp) = ([0.0; NW], 0.0);
    for _ in 0..samples as usize {
        sim.advance_to(steps_of(sim.time() + SAMPLE))?;
        let state = sim.state();
        for (i, &w) in ws(ell, w_min).iter().enumerate() {
            let within = |p: &V<D>| (0..D).all(|k| p[k] >= w && p[k] <= size[k] - w);
            let inside = state.iter().filter(|(p, _)| within(p)).count();
            rho[i] += inside as f64 / size.add_scalar(-2.0 * w).product();
        }
        temp += kt(setup, &state);
    }
    Ok((rho.map(|r| r / samples), temp / samples))
}

/// Z from a run: equilibrate for `t_eq`, then measure over `t_run` in
/// `blocks` [`block`]s. A run that stops early returns what it has, with
/// `error` set.
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
    let mut out = ZResult::new(n);
    if let Err(e) = sim.advance_to(steps_of(t_eq)) {
        out.error = Some(e);
        return Ok(out);
    }
    let kt0 = kt(setup, &sim.state());
    let mut last = sim.totals();
    let mut t_last = sim.time();
    let samples = ((t_run / blocks as f64) / SAMPLE).round().max(1.0);
    let (mut z_blocks, mut single_blocks) = (Vec::new(), Vec::new());
    let (mut sum_f, mut sum_t, mut sum_kt) = ([0.0; D], 0.0, 0.0);
    let mut sum_rho = [0.0; NW];
    let mut impulse_total = 0.0;
    for _ in 0..blocks {
        let (rho, temp) = match block(&mut *sim, setup, (&ell, w_min), samples) {
            Ok(measured) => measured,
            Err(e) => {
                out.error = Some(e);
                return Ok(out);
            }
        };
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
        sum_rho.iter_mut().zip(rho).for_each(|(s, r)| *s += r);
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
    let at = |(w, &r): (f64, &f64)| (w, r * ball_volume(D, R), p / (r * temp));
    out.by_w = ws(&ell, w_min).into_iter().zip(&rho).map(at).collect();
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
