//! Property tests of the law in f32 and f64, 2D and 3D.
//!
//! Masses are log-uniform over 24 decades (1e-12 to 1e12), speeds over 15
//! (1e-9 to 1e6), tangential speeds independently of normal ones (grazing
//! impacts), and d̃ is zero a quarter of the time, log-uniform over
//! [1e-6, 1] otherwise. Each property runs `KIMPACT_PROPTEST_CASES` cases
//! (default 10,000; 5 properties × 4 variants = 200,000 in CI).
//!
//! Checks are computed in f64 from the values the law returned, with
//! tolerances in units of the type's epsilon scaled to the quantities
//! involved (the honest bound of rounding, not a loosened one).

use kimpact::nalgebra::{RealField, SVector};
use kimpact::{Body, Impact, Law, LawParams};
use proptest::prelude::*;
use proptest::test_runner::Config;

fn cases() -> u32 {
    std::env::var("KIMPACT_PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000)
}

/// One generated impact, in f64 before conversion to the type under test.
#[derive(Clone, Debug)]
struct Case {
    m_a: f64,
    m_b: f64,
    v_a: Vec<f64>,
    normal: Vec<f64>,
    approach: f64,
    tangential: Vec<f64>,
    dissipation: f64,
}

fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..hi.log10()).prop_map(|e| 10f64.powf(e))
}

fn signed_log(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (log_uniform(lo, hi), any::<bool>()).prop_map(|(x, s)| if s { x } else { -x })
}

fn case(dim: usize) -> impl Strategy<Value = Case> {
    (
        log_uniform(1e-12, 1e12),
        log_uniform(1e-12, 1e12),
        prop::collection::vec(signed_log(1e-9, 1e6), dim),
        prop::collection::vec(-1.0..1.0f64, dim).prop_filter("non-zero normal", |n| {
            n.iter().map(|x| x * x).sum::<f64>() > 1e-4
        }),
        log_uniform(1e-9, 1e6),
        prop::collection::vec(signed_log(1e-9, 1e6), dim),
        prop_oneof![1 => Just(0.0), 3 => log_uniform(1e-6, 1.0)],
    )
        .prop_map(
            |(m_a, m_b, v_a, normal, approach, tangential, dissipation)| Case {
                m_a,
                m_b,
                v_a,
                normal,
                approach,
                tangential,
                dissipation,
            },
        )
}

struct Setup<T: RealField + Copy, const D: usize> {
    a: Body<T, D>,
    b: Body<T, D>,
    n: SVector<T, D>,
    law: Law<T>,
}

fn to64<T: RealField + Copy, const D: usize>(v: &SVector<T, D>) -> SVector<f64, D> {
    v.map(|x| x.to_subset().unwrap())
}

fn setup<T: RealField + Copy, const D: usize>(c: &Case) -> Setup<T, D> {
    let from = |x: f64| T::from_subset(&x);
    let n = SVector::<f64, D>::from_iterator(c.normal.iter().copied()).normalize();
    let t = SVector::<f64, D>::from_iterator(c.tangential.iter().copied());
    let t = t - n * t.dot(&n);
    let v_a = SVector::<f64, D>::from_iterator(c.v_a.iter().copied());
    // b approaches a along n at speed `approach`, with a tangential part.
    let v_b = v_a - n * c.approach + t;
    Setup {
        a: Body::new(from(c.m_a), v_a.map(from)).unwrap(),
        b: Body::new(from(c.m_b), v_b.map(from)).unwrap(),
        n: n.map(from),
        law: Law::new(LawParams {
            dissipation: from(c.dissipation),
            ..Default::default()
        })
        .unwrap(),
    }
}

fn eps<T: RealField + Copy>() -> f64 {
    T::default_epsilon().to_subset().unwrap()
}

/// Resolve, returning None when the rounded inputs no longer approach.
fn run<T: RealField + Copy, const D: usize>(s: &Setup<T, D>) -> Option<Impact<T, D>> {
    s.law.resolve(&s.a, &s.b, &s.n).unwrap()
}

fn mass<T: RealField + Copy, const D: usize>(b: &Body<T, D>) -> f64 {
    match b.mass() {
        kimpact::Mass::Finite(m) => m.to_subset().unwrap(),
        kimpact::Mass::Infinite => unreachable!(),
    }
}

/// Final velocities as a simulation would store them, in f64.
fn finals<T: RealField + Copy, const D: usize>(
    s: &Setup<T, D>,
    i: &Impact<T, D>,
) -> (SVector<f64, D>, SVector<f64, D>) {
    (
        to64(&(s.a.velocity() + i.delta_v_a)),
        to64(&(s.b.velocity() + i.delta_v_b)),
    )
}

fn momentum_is_conserved<T: RealField + Copy, const D: usize>(
    c: &Case,
    rel: f64,
) -> Result<(), TestCaseError> {
    let s = setup::<T, D>(c);
    let Some(i) = run(&s) else { return Ok(()) };
    let (ma, mb) = (mass(&s.a), mass(&s.b));
    let (va, vb) = (to64(s.a.velocity()), to64(s.b.velocity()));
    let (va2, vb2) = finals(&s, &i);
    let before = va * ma + vb * mb;
    let after = va2 * ma + vb2 * mb;
    let scale = ma * va.norm() + mb * vb.norm() + ma * va2.norm() + mb * vb2.norm();
    prop_assert!(
        (after - before).norm() <= rel * scale,
        "momentum changed by {:e} of {:e}",
        (after - before).norm(),
        scale
    );
    Ok(())
}

fn energy_never_rises<T: RealField + Copy, const D: usize>(c: &Case) -> Result<(), TestCaseError> {
    let s = setup::<T, D>(c);
    let Some(i) = run(&s) else { return Ok(()) };
    let (ma, mb) = (mass(&s.a), mass(&s.b));
    let (va2, vb2) = finals(&s, &i);
    let e0 = 0.5 * ma * to64(s.a.velocity()).norm_squared()
        + 0.5 * mb * to64(s.b.velocity()).norm_squared();
    let e1 = 0.5 * ma * va2.norm_squared() + 0.5 * mb * vb2.norm_squared();
    // Rounding bound: the approach speed u = −(v_b − v_a)·n carries an error
    // δu <= (D + 2) ε |w|, which changes the energy by at most 2 μ u δu <=
    // 4 (D + 2) ε E (as ½ μ |w|² <= E); storing v' adds 2 ε E. Hence 32 ε.
    prop_assert!(
        e1 <= e0 * (1.0 + 32.0 * eps::<T>()),
        "energy rose from {e0:e} to {e1:e}"
    );
    Ok(())
}

fn energy_loss_is_d<T: RealField + Copy, const D: usize>(
    c: &Case,
    rel: f64,
) -> Result<(), TestCaseError> {
    let s = setup::<T, D>(c);
    let Some(i) = run(&s) else { return Ok(()) };
    if i.clamped {
        return Ok(());
    }
    let (ma, mb) = (mass(&s.a), mass(&s.b));
    let (va, vb) = (to64(s.a.velocity()), to64(s.b.velocity()));
    let (va2, vb2) = finals(&s, &i);
    let e0 = 0.5 * ma * va.norm_squared() + 0.5 * mb * vb.norm_squared();
    let e1 = 0.5 * ma * va2.norm_squared() + 0.5 * mb * vb2.norm_squared();
    // The note's d, computed independently in f64.
    let d = c.dissipation_used::<T>() * (ma + mb) * (vb - va).norm_squared();
    prop_assert!(
        ((e0 - e1) - d).abs() <= rel * e0,
        "lost {:e}, d = {d:e}, E = {e0:e}",
        e0 - e1
    );
    let reported: f64 = i.dissipated.to_subset().unwrap();
    prop_assert!(
        (reported - d).abs() <= rel * d.max(f64::MIN_POSITIVE),
        "reported d {reported:e} vs {d:e}"
    );
    Ok(())
}

impl Case {
    /// d̃ as the type under test holds it.
    fn dissipation_used<T: RealField + Copy>(&self) -> f64 {
        T::from_subset(&self.dissipation).to_subset().unwrap()
    }
}

fn not_approaching_after<T: RealField + Copy, const D: usize>(
    c: &Case,
) -> Result<(), TestCaseError> {
    let s = setup::<T, D>(c);
    let Some(i) = run(&s) else { return Ok(()) };
    let n = to64(&i.normal);
    let u: f64 = i.approach_speed.to_subset().unwrap();
    // In exact terms of the returned changes: the normal relative velocity
    // changes by s = u (1 + e) >= u.
    let change = (to64(&i.delta_v_b) - to64(&i.delta_v_a)).dot(&n);
    prop_assert!(
        change >= u * (1.0 - 8.0 * eps::<T>()),
        "change {change:e} < u {u:e}"
    );
    // In stored velocities: up to the rounding of u (<= (D + 2) ε |w|) and of
    // storing v + Δv (<= ε per velocity): 16 ε of the speeds involved.
    let (va2, vb2) = finals(&s, &i);
    let scale = to64(s.a.velocity()).norm() + to64(s.b.velocity()).norm() + change.abs();
    prop_assert!((vb2 - va2).dot(&n) >= -16.0 * eps::<T>() * scale);
    Ok(())
}

fn everything_finite<T: RealField + Copy, const D: usize>(c: &Case) -> Result<(), TestCaseError> {
    let s = setup::<T, D>(c);
    let Some(i) = run(&s) else { return Ok(()) };
    let e: f64 = i.restitution.to_subset().unwrap();
    prop_assert!((0.0..=1.0).contains(&e), "e = {e}");
    if i.clamped {
        prop_assert!((e - 1e-3).abs() < 1e-3 * 1e-3, "clamped e = {e}");
    }
    for x in i
        .delta_v_a
        .iter()
        .chain(i.delta_v_b.iter())
        .chain(i.normal.iter())
    {
        prop_assert!(x.is_finite());
    }
    let energies = i.energies(&s.a, &s.b);
    for x in [
        i.k(s.a.mass(), s.b.mass()),
        i.impulse,
        i.restitution,
        energies.before,
        energies.after,
        i.dissipated,
        i.approach_speed,
    ] {
        prop_assert!(x.is_finite() && x >= T::zero(), "{x:?}");
    }
    let (va2, vb2) = finals(&s, &i);
    prop_assert!(va2.iter().chain(vb2.iter()).all(|x| x.is_finite()));
    Ok(())
}

macro_rules! variant {
    ($name:ident, $t:ty, $d:literal, $mom:expr, $energy:expr) => {
        mod $name {
            use super::*;
            proptest! {
                #![proptest_config(Config { cases: cases(), ..Config::default() })]
                #[test]
                fn momentum(c in case($d)) { momentum_is_conserved::<$t, $d>(&c, $mom)?; }
                #[test]
                fn energy(c in case($d)) { energy_never_rises::<$t, $d>(&c)?; }
                #[test]
                fn dissipation(c in case($d)) { energy_loss_is_d::<$t, $d>(&c, $energy)?; }
                #[test]
                fn separating(c in case($d)) { not_approaching_after::<$t, $d>(&c)?; }
                #[test]
                fn finite(c in case($d)) { everything_finite::<$t, $d>(&c)?; }
            }
        }
    };
}

variant!(f64_2d, f64, 2, 1e-12, 1e-12);
variant!(f64_3d, f64, 3, 1e-12, 1e-12);
variant!(f32_2d, f32, 2, 1e-5, 1e-5);
variant!(f32_3d, f32, 3, 1e-5, 1e-5);
