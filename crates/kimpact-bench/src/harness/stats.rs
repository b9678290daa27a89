//! The statistics of the study: Kolmogorov–Smirnov distances (two samples,
//! and speeds against Maxwell–Boltzmann) and a mean with its standard error.

use std::f64::consts::PI;

/// The two-sample Kolmogorov–Smirnov distance of `a` and `b` (sorted in
/// place).
pub fn ks(a: &mut [f64], b: &mut [f64]) -> f64 {
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] <= x {
            i += 1;
        }
        while j < b.len() && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// The Kolmogorov–Smirnov distance of speeds in units of the rms speed
/// (`x`, sorted in place) from Maxwell–Boltzmann in `d` dimensions.
pub fn ks_maxwell(d: usize, x: &mut [f64]) -> f64 {
    x.sort_by(f64::total_cmp);
    let cdf = |u: f64| {
        if d == 2 {
            1.0 - (-u * u).exp()
        } else {
            // a = v_rms/√3; F = erf(v/(√2 a)) − √(2/π) (v/a) e^{−v²/2a²}.
            let w = u * 3f64.sqrt();
            libm::erf(w / 2f64.sqrt()) - (2.0 / PI).sqrt() * w * (-w * w / 2.0).exp()
        }
    };
    let n = x.len() as f64;
    let gap = |(i, &u): (usize, &f64)| {
        let f = cdf(u);
        (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
    };
    x.iter().enumerate().map(gap).fold(0.0, f64::max)
}

/// The mean of `x` and its standard error.
pub fn mean_and_error(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, (var / n).sqrt())
}
