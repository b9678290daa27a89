//! The statistics of the study: Kolmogorov–Smirnov distances (two samples,
//! and speeds against Maxwell–Boltzmann) and a mean with its standard error.
//! Small enough to keep here rather than pull in a statistics crate for
//! `erf`.

use std::f64::consts::PI;

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

/// erf, Abramowitz & Stegun 7.1.26 (|error| < 1.5e-7).
pub fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.3275911 * x.abs());
    let y = 1.0
        - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t
            + 0.254829592)
            * t
            * (-x * x).exp();
    if x >= 0.0 { y } else { -y }
}

/// KS distance of speeds in units of the rms speed from Maxwell–Boltzmann.
pub fn ks_maxwell(d: usize, x: &mut [f64]) -> f64 {
    x.sort_by(f64::total_cmp);
    let cdf = |u: f64| {
        if d == 2 {
            1.0 - (-u * u).exp()
        } else {
            // a = v_rms/√3; F = erf(v/(√2 a)) − √(2/π) (v/a) e^{−v²/2a²}.
            let w = u * 3f64.sqrt();
            erf(w / 2f64.sqrt()) - (2.0 / PI).sqrt() * w * (-w * w / 2.0).exp()
        }
    };
    let n = x.len() as f64;
    x.iter()
        .enumerate()
        .map(|(i, &u)| {
            let f = cdf(u);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

/// The mean of `x` and its standard error.
pub fn mean_and_error(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, (var / n).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_matches_known_values_to_its_stated_accuracy() {
        for (x, want) in [
            (0.0, 0.0),
            (0.5, 0.520_499_877_8),
            (1.0, 0.842_700_792_9),
            (2.0, 0.995_322_265_0),
        ] {
            assert!((erf(x) - want).abs() < 1.5e-7, "erf({x}) = {}", erf(x));
            assert!((erf(-x) + want).abs() < 1.5e-7);
        }
    }

    #[test]
    fn two_sample_ks_is_zero_for_equal_samples_and_one_for_disjoint_ones() {
        let mut a = vec![3.0, 1.0, 2.0];
        assert_eq!(ks(&mut a.clone(), &mut a), 0.0);
        assert_eq!(ks(&mut [1.0, 2.0], &mut [3.0, 4.0]), 1.0);
        assert!((ks(&mut [1.0, 2.0, 3.0, 4.0], &mut [3.0, 4.0, 5.0, 6.0]) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn ks_against_maxwell_is_small_for_maxwell_speeds_and_large_for_equal_ones() {
        // Speeds whose CDF values are evenly spaced: the 2D Maxwell CDF is
        // 1 − exp(−u²), so u = sqrt(−ln(1 − p)).
        let n = 1000;
        let mut maxwell: Vec<f64> = (0..n)
            .map(|i| (-(1.0 - (i as f64 + 0.5) / n as f64).ln()).sqrt())
            .collect();
        assert!(ks_maxwell(2, &mut maxwell) < 1e-3);
        let mut same = vec![1.0; n];
        assert!(ks_maxwell(2, &mut same) > 0.3);
        assert!(ks_maxwell(3, &mut same) > 0.3);
    }

    #[test]
    fn mean_and_standard_error_of_a_small_sample() {
        let (m, se) = mean_and_error(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(m, 2.5);
        // Sample variance 5/3, standard error sqrt(5/12).
        assert!((se - (5.0f64 / 12.0).sqrt()).abs() < 1e-12);
    }
}
