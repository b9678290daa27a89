//! The statistics of the accuracy study (`kimpact_harness::{ks,
//! ks_maxwell, mean_and_error}`) against values computed by hand.

use kimpact_harness::{ks, ks_maxwell, mean_and_error};

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
    // 1 − exp(−u²), so u = sqrt(−ln(1 − p)); in 3D (speeds over the rms
    // speed, w = u √3), F = erf(w/√2) − √(2/π) w exp(−w²/2), inverted here
    // by bisection.
    let n = 1000;
    let p = |i: usize| (i as f64 + 0.5) / n as f64;
    let mut maxwell2: Vec<f64> = (0..n).map(|i| (-(1.0 - p(i)).ln()).sqrt()).collect();
    assert!(ks_maxwell(2, &mut maxwell2) < 1e-3);
    let cdf3 = |u: f64| {
        let w = u * 3f64.sqrt();
        libm::erf(w / 2f64.sqrt()) - (2.0 / std::f64::consts::PI).sqrt() * w * (-w * w / 2.0).exp()
    };
    let invert = |q: f64| {
        let (mut lo, mut hi) = (0.0, 10.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if cdf3(mid) < q { lo = mid } else { hi = mid }
        }
        lo
    };
    let mut maxwell3: Vec<f64> = (0..n).map(|i| invert(p(i))).collect();
    assert!(ks_maxwell(3, &mut maxwell3) < 1e-3);
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
