//! Regression tests from fuzzing the law (`fuzz/`, target `law`; see
//! `docs/reliability-fuzz.md`), and the nastiest inputs the fuzzer feeds:
//! NaN, infinities, signed zeros, subnormals and the extremes of f32 and f64.
//!
//! The first three tests are the contract violations the fuzzer found, each
//! reduced to its essence; the rest pin the typed errors and the "never NaN"
//! promise at the edges of the types.

use kimpact::nalgebra::{RealField, SVector, Vector2, Vector3};
use kimpact::{Body, FixedPartner, Impact, Law, LawError, LawParams, Mass, Which};

/// Every field of an impact and every quantity derived from it (`k`, the
/// energies of the bodies it was resolved with), for "never NaN" checks.
fn fields<T: RealField + Copy, const D: usize>(
    i: &Impact<T, D>,
    a: &Body<T, D>,
    b: &Body<T, D>,
) -> Vec<T> {
    let energies = i.energies(a, b);
    let mut out = vec![
        i.approach_speed,
        i.k(a.mass(), b.mass()),
        i.speed_change(),
        i.impulse,
        i.restitution,
        energies.before,
        energies.after,
        i.dissipated,
    ];
    out.extend(i.normal.iter().chain(&i.delta_v_a).chain(&i.delta_v_b));
    out
}

fn assert_no_nan<T: RealField + Copy, const D: usize>(
    i: &Impact<T, D>,
    a: &Body<T, D>,
    b: &Body<T, D>,
) {
    for x in fields(i, a, b) {
        let x: f64 = x.to_subset().expect("f32 or f64");
        assert!(!x.is_nan(), "NaN in {i:?}");
    }
}

fn law<T: RealField + Copy>(dissipation: T) -> Law<T> {
    Law::new(LawParams {
        dissipation,
        ..Default::default()
    })
    .expect("valid d̃")
}

// Found by the fuzzer (crash-72fae53e…): an approach speed above half the
// largest finite value made s = u (1 + e) infinite, and n̄ · ∞ put NaN into
// the zero components of Δv (and into the energies and d). Now no impact is
// reported, as for an overflowing relative velocity.
#[test]
fn velocity_change_that_overflows_is_no_impact_not_nan() {
    let ball = Body::new(7.539_615e-5_f32, Vector2::new(-9.318_909_5e-11, f32::MAX)).unwrap();
    let wall = Body::immovable(Vector2::zeros()).unwrap();
    let n = Vector2::new(-0.0, 1.0);
    assert_eq!(Law::elastic().resolve(&ball, &wall, &n), Ok(None));
    assert_eq!(law(0.1).resolve(&ball, &wall, &n), Ok(None));

    // f64, two finite bodies, 3D: w = −0.6 max is finite, s = 1.2 max is not.
    let a = Body::new(1.0, Vector3::new(0.0, 0.0, 0.3 * f64::MAX)).unwrap();
    let b = Body::new(2.0, Vector3::new(0.0, 0.0, -0.3 * f64::MAX)).unwrap();
    assert_eq!(Law::elastic().resolve(&a, &b, &Vector3::z()), Ok(None));
    assert_eq!(law(0.01).resolve(&a, &b, &Vector3::z()), Ok(None));

    // Just below the limit the impact is reported, finite.
    let ball = Body::new(1.0_f32, Vector2::new(0.0, 0.49 * f32::MAX)).unwrap();
    let i = Law::elastic()
        .resolve(&ball, &wall, &Vector2::y())
        .unwrap()
        .expect("approaching");
    assert_no_nan(&i, &ball, &wall);
    assert!(i.delta_v_a.iter().all(|x| x.is_finite()));
    assert_eq!(i.delta_v_a, Vector2::new(0.0, -0.98 * f32::MAX));
}

// Found by the fuzzer: d = ½ μ u² q was evaluated as (½ μ u²) · q, so an
// elastic impact (q = 0) whose ½ μ u² overflows reported d = ∞ · 0 = NaN.
#[test]
fn elastic_impact_reports_zero_dissipation_even_when_half_mu_u2_overflows() {
    let a = Body::new(1e30_f32, Vector2::new(1e5, 0.0)).unwrap();
    let b = Body::new(1e30_f32, Vector2::new(-1e5, 0.0)).unwrap();
    let i = Law::elastic()
        .resolve(&a, &b, &Vector2::x())
        .unwrap()
        .expect("approaching");
    assert_eq!(i.dissipated, 0.0);
    assert_eq!(i.restitution, 1.0);
    assert_no_nan(&i, &a, &b);
    // The velocities are exact: equal masses swap their velocities.
    assert_eq!(a.velocity() + i.delta_v_a, Vector2::new(-1e5, 0.0));
    assert_eq!(b.velocity() + i.delta_v_b, Vector2::new(1e5, 0.0));

    let a = Body::new(1e300_f64, Vector3::new(0.0, 1e10, 0.0)).unwrap();
    let wall = Body::immovable(Vector3::zeros()).unwrap();
    let i = Law::elastic()
        .resolve(&a, &wall, &Vector3::y())
        .unwrap()
        .expect("approaching");
    assert_eq!(i.dissipated, 0.0);
    assert_no_nan(&i, &a, &wall);
}

// Found by the fuzzer (crash-519d3989…): for a subnormal approach speed,
// 1/u overflowed, a zero component of w became ∞ · 0 = NaN in
// ρ = |w/u|², and the impact was misread as clamped (e = 1e-3 instead of
// sqrt(1 − q) ≈ 0.99).
#[test]
fn subnormal_approach_speed_keeps_the_true_restitution() {
    fn check<T: RealField + Copy, const D: usize>(speed: T) {
        let law = law(T::from_subset(&0.01));
        let mut v = SVector::<T, D>::zeros();
        v[0] = speed;
        let ball = Body::new(T::one(), v).unwrap();
        let wall = Body::immovable(SVector::zeros()).unwrap();
        let mut n = SVector::<T, D>::zeros();
        n[0] = T::one();
        let i = law.resolve(&ball, &wall, &n).unwrap().expect("approaching");
        assert_no_nan(&i, &ball, &wall);
        // q = 2 d̃ (|w|/u)² = 0.02 against an own-mass wall.
        let e: f64 = i.restitution.to_subset().unwrap();
        assert!(!i.clamped, "misread as clamped: {i:?}");
        assert!((e - 0.98f64.sqrt()).abs() < 1e-6, "e = {e}");
        let r = law
            .restitution(ball.mass(), Mass::Infinite, speed, T::zero())
            .unwrap()
            .unwrap();
        let e2: f64 = r.coefficient.to_subset().unwrap();
        assert!((e2 - e).abs() < 1e-6 && !r.clamped);
    }
    check::<f32, 2>(1e-40);
    check::<f32, 3>(f32::from_bits(1));
    check::<f64, 2>(1e-310);
    check::<f64, 3>(f64::from_bits(3));
}

#[test]
fn non_finite_and_non_positive_masses_are_typed_errors() {
    let v = Vector2::new(1.0_f64, 0.0);
    for m in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        match Body::new(m, v) {
            Err(LawError::NonFiniteMass {
                which: Which::Body,
                value,
            }) => assert!(value.to_bits() == m.to_bits() || (value.is_nan() && m.is_nan())),
            r => panic!("mass {m}: {r:?}"),
        }
        assert!(Mass::finite(m).is_err());
    }
    for m in [0.0, -0.0, -f64::MIN_POSITIVE, -f64::from_bits(1), -1.0] {
        assert!(
            matches!(
                Body::new(m, v),
                Err(LawError::NonPositiveMass {
                    which: Which::Body,
                    ..
                })
            ),
            "mass {m}"
        );
    }
    // A subnormal mass is finite and positive: valid.
    assert!(Body::new(f64::from_bits(1), v).is_ok());
    assert!(Body::new(f32::from_bits(1), Vector2::new(1.0_f32, 0.0)).is_ok());
    // The first bad quantity is named, mass before velocity.
    assert!(matches!(
        Body::new(f32::NAN, Vector2::new(f32::NAN, 0.0)),
        Err(LawError::NonFiniteMass { .. })
    ));
}

#[test]
fn non_finite_velocities_are_typed_errors_naming_the_component() {
    let bad = Vector3::new(1.0_f32, f32::from_bits(1), f32::NEG_INFINITY);
    assert_eq!(
        Body::new(1.0, bad),
        Err(LawError::NonFiniteVelocity {
            which: Which::Body,
            component: 2,
            value: f64::NEG_INFINITY,
        })
    );
    match Body::<f64, 2>::immovable(Vector2::new(f64::NAN, 0.0)) {
        Err(LawError::NonFiniteVelocity {
            component: 0,
            value,
            ..
        }) => assert!(value.is_nan()),
        r => panic!("{r:?}"),
    }
    let e = Body::new(1.0, bad).unwrap_err().to_string();
    assert!(
        e.contains("velocity component 2") && e.contains("inf"),
        "{e}"
    );
}

#[test]
fn invalid_dissipation_is_rejected_and_set_params_is_all_or_nothing() {
    for d in [f64::NAN, f64::INFINITY, -f64::from_bits(1), -1.0] {
        assert!(
            matches!(
                Law::new(LawParams {
                    dissipation: d,
                    ..Default::default()
                }),
                Err(LawError::InvalidDissipation {
                    parameter: "dissipation",
                    ..
                })
            ),
            "d̃ = {d}"
        );
        assert!(
            matches!(
                Law::new(LawParams {
                    dissipation: 0.1,
                    wall_dissipation: Some(d),
                    fixed_partner: FixedPartner::OwnMass,
                }),
                Err(LawError::InvalidDissipation {
                    parameter: "wall_dissipation",
                    ..
                })
            ),
            "wall d̃ = {d}"
        );
    }
    // −0 and subnormals are finite and >= 0.
    assert!(Law::with_dissipation(-0.0_f32).is_ok());
    assert!(Law::with_dissipation(f32::from_bits(1)).is_ok());
    assert!(Law::with_dissipation(f64::MAX).is_ok());

    let mut law = law(0.25_f64);
    let before = law;
    let bad = LawParams {
        dissipation: 0.5,
        wall_dissipation: Some(f64::NAN),
        fixed_partner: FixedPartner::Literal,
    };
    assert!(law.set_params(bad).is_err());
    assert_eq!(law, before, "set_params changed the law on error");
}

#[test]
fn bad_normals_are_typed_errors_and_extreme_normals_are_normalized() {
    let law = Law::<f32>::elastic();
    let a = Body::new(1.0, Vector2::new(1.0, 0.0)).unwrap();
    let b = Body::new(1.0, Vector2::new(-1.0, 0.0)).unwrap();
    assert_eq!(
        law.resolve(&a, &b, &Vector2::new(0.0, -0.0)),
        Err(LawError::ZeroNormal)
    );
    match law.resolve(&a, &b, &Vector2::new(1.0, f32::NAN)) {
        Err(LawError::NonFiniteNormal {
            component: 1,
            value,
        }) => assert!(value.is_nan()),
        r => panic!("{r:?}"),
    }
    assert!(matches!(
        law.resolve(&a, &b, &Vector2::new(f32::INFINITY, 0.0)),
        Err(LawError::NonFiniteNormal { component: 0, .. })
    ));
    // Neither a subnormal nor a huge normal under- or overflows.
    for n in [
        Vector2::new(f32::from_bits(1), 0.0),
        Vector2::new(f32::MAX, 0.0),
        Vector2::new(f32::MAX, f32::from_bits(1)),
    ] {
        let i = law.resolve(&a, &b, &n).unwrap().expect("approaching");
        assert_eq!(i.normal, Vector2::x(), "normal {n:?}");
        assert_eq!(i.delta_v_a, Vector2::new(-2.0, 0.0));
    }
    let i = law
        .resolve(&a, &b, &Vector2::new(f32::MAX, f32::MAX))
        .unwrap()
        .expect("approaching");
    assert!((i.normal.norm() - 1.0).abs() < 1e-6);
}

#[test]
fn restitution_reports_its_errors_in_order() {
    let law = law(0.1_f64);
    let one = Mass::Finite(1.0);
    assert!(matches!(
        law.restitution(Mass::Finite(f64::NAN), Mass::Finite(-1.0), f64::NAN, -1.0),
        Err(LawError::NonFiniteMass {
            which: Which::First,
            ..
        })
    ));
    assert!(matches!(
        law.restitution(one, Mass::Finite(-0.0), f64::NAN, -1.0),
        Err(LawError::NonPositiveMass {
            which: Which::Second,
            ..
        })
    ));
    assert!(matches!(
        law.restitution(one, one, f64::INFINITY, -1.0),
        Err(LawError::InvalidSpeed {
            quantity: "approach_speed",
            ..
        })
    ));
    assert!(matches!(
        law.restitution(one, one, 1.0, -f64::from_bits(1)),
        Err(LawError::InvalidSpeed {
            quantity: "tangential_speed",
            nonnegative: true,
            ..
        })
    ));
    assert_eq!(law.restitution(one, one, 0.0, 0.0), Ok(None));
    assert_eq!(law.restitution(one, one, -0.0, 0.0), Ok(None));
    assert_eq!(
        law.restitution(Mass::Infinite, Mass::Infinite, 1.0, 0.0),
        Ok(None)
    );
    // A grazing impact whose tangential ratio overflows is clamped, not NaN.
    let r = law
        .restitution(one, one, f64::from_bits(1), f64::MAX)
        .unwrap()
        .unwrap();
    assert!(r.clamped && (r.coefficient - 1e-3).abs() < 1e-9);
}

#[test]
fn extreme_masses_and_speeds_never_give_nan() {
    let tiny = f64::from_bits(1);
    let cases: [(f64, f64, f64); 6] = [
        (f64::MAX, tiny, 1.0),
        (tiny, f64::MAX, 1.0),
        (f64::MAX, f64::MAX, 1e-300),
        (tiny, tiny, 1e300),
        (1.0, f64::MIN_POSITIVE, tiny),
        (f64::MAX, 1.0, 0.2 * f64::MAX),
    ];
    for (m_a, m_b, speed) in cases {
        for d in [0.0, 1e-300, 0.5, f64::MAX] {
            for policy in [FixedPartner::OwnMass, FixedPartner::Literal] {
                let law = Law::new(LawParams {
                    dissipation: d,
                    wall_dissipation: None,
                    fixed_partner: policy,
                })
                .unwrap();
                let a = Body::new(m_a, Vector3::new(speed, 0.0, 0.0)).unwrap();
                let b = Body::new(m_b, Vector3::new(-speed, 0.0, 0.0)).unwrap();
                let wall = Body::immovable(Vector3::zeros()).unwrap();
                for (x, y) in [(&a, &b), (&a, &wall), (&wall, &b)] {
                    let i = law
                        .resolve(x, y, &Vector3::new(1.0, 0.0, 0.0))
                        .unwrap()
                        .expect("approaching");
                    assert_no_nan(&i, x, y);
                    let e = i.restitution;
                    assert!((0.0..=1.0).contains(&e), "e = {e}");
                    assert!(
                        i.delta_v_a
                            .iter()
                            .chain(&i.delta_v_b)
                            .all(|x| x.is_finite()),
                        "{i:?}"
                    );
                    if d == 0.0 {
                        assert_eq!(e, 1.0);
                        assert_eq!(i.dissipated, 0.0);
                    }
                }
            }
        }
    }
}
