//! Hand-computed impacts in f64 (and a few in f32), to 1e-12 relative.
//!
//! Expected values come from textbook formulas or from the note's own
//! quadratic (10) evaluated directly, where it is well conditioned, never
//! from the implementation.

use approx::assert_relative_eq;
use kimpact::nalgebra::{Vector2, Vector3};
use kimpact::{Body, FixedPartner, Law, LawError, LawParams, Mass, Which};

const TOL: f64 = 1e-12;

fn law(d: f64) -> Law<f64> {
    Law::new(LawParams {
        dissipation: d,
        ..Default::default()
    })
    .unwrap()
}

/// The note's equation (10), literally: k = −p/2 + ½ sqrt(p² − 8d/((m₁+m₂)m₁m₂))
/// for p < 0, with p = (2/(m₁+m₂)) (v₁·n̄₂ + v₂·n̄₁).
fn note_k(m1: f64, m2: f64, v1: Vector3<f64>, v2: Vector3<f64>, n1: Vector3<f64>, dt: f64) -> f64 {
    let n2 = -n1;
    let d = dt * (m1 + m2) * (v2 - v1).norm_squared();
    let p = (2.0 / (m1 + m2)) * (v1.dot(&n2) + v2.dot(&n1));
    assert!(p < 0.0, "approaching pairs have p < 0");
    -p / 2.0 + 0.5 * (p * p - 8.0 * d / ((m1 + m2) * m1 * m2)).sqrt()
}

/// Textbook one-dimensional elastic collision.
fn elastic_1d(m1: f64, u1: f64, m2: f64, u2: f64) -> (f64, f64) {
    let m = m1 + m2;
    (
        ((m1 - m2) * u1 + 2.0 * m2 * u2) / m,
        ((m2 - m1) * u2 + 2.0 * m1 * u1) / m,
    )
}

/// The head-on impact of `m1` at 1.5 and `m2` at −0.25 along x: final
/// velocities, the impact, its energies and its `k`.
fn head_on(
    m1: f64,
    m2: f64,
    d: f64,
) -> (
    Vector3<f64>,
    Vector3<f64>,
    kimpact::Impact<f64, 3>,
    kimpact::Energies<f64>,
    f64,
) {
    let v1 = Vector3::new(1.5, 0.0, 0.0);
    let v2 = Vector3::new(-0.25, 0.0, 0.0);
    let a = Body::new(m1, v1).unwrap();
    let b = Body::new(m2, v2).unwrap();
    let impact = law(d).resolve(&a, &b, &Vector3::x()).unwrap().unwrap();
    let energies = impact.energies(&a, &b);
    let k = impact.k(a.mass(), b.mass());
    (
        v1 + impact.delta_v_a,
        v2 + impact.delta_v_b,
        impact,
        energies,
        k,
    )
}

#[test]
fn elastic_head_on_matches_textbook_for_mass_ratios() {
    for (m1, m2) in [
        (1.0, 1.0),
        (1.0, 10.0),
        (10.0, 1.0),
        (1.0, 1000.0),
        (1000.0, 1.0),
    ] {
        let (v1, v2, impact, energies, impact_k) = head_on(m1, m2, 0.0);
        let (e1, e2) = elastic_1d(m1, 1.5, m2, -0.25);
        assert_relative_eq!(v1.x, e1, max_relative = TOL, epsilon = 1e-15);
        assert_relative_eq!(v2.x, e2, max_relative = TOL, epsilon = 1e-15);
        assert_eq!((v1.y, v1.z, v2.y, v2.z), (0.0, 0.0, 0.0, 0.0));
        assert_eq!(impact.restitution, 1.0);
        assert!(!impact.clamped);
        assert_eq!(impact.dissipated, 0.0);
        assert_relative_eq!(energies.after, energies.before, max_relative = TOL);
        // The note's k, and the impulse J = m₁ m₂ k.
        let k = note_k(
            m1,
            m2,
            Vector3::new(1.5, 0.0, 0.0),
            Vector3::new(-0.25, 0.0, 0.0),
            Vector3::x(),
            0.0,
        );
        assert_relative_eq!(impact_k, k, max_relative = TOL);
        assert_relative_eq!(impact.impulse, m1 * m2 * k, max_relative = TOL);
    }
}

#[test]
fn equal_masses_exchange_velocities() {
    let (v1, v2, ..) = head_on(0.17, 0.17, 0.0);
    assert_relative_eq!(v1.x, -0.25, max_relative = TOL);
    assert_relative_eq!(v2.x, 1.5, max_relative = TOL);
}

#[test]
fn extreme_mass_ratio_is_exact() {
    // 1e-12 against 1e12: the naive form multiplies the masses (1e12·1e-12·1e12)
    // and subtracts 1 − 1e-24; the textbook result is v₂' = 2 m₁ v₁/(m₁+m₂).
    let a = Body::new(1e-12, Vector3::new(3.0, 0.0, 0.0)).unwrap();
    let b = Body::new(1e12, Vector3::zeros()).unwrap();
    let impact = law(0.0).resolve(&a, &b, &Vector3::x()).unwrap().unwrap();
    assert_relative_eq!(
        impact.delta_v_b.x,
        6.0e-24 / (1.0 + 1e-24),
        max_relative = TOL
    );
    assert_relative_eq!(impact.delta_v_a.x, -6.0 / (1.0 + 1e-24), max_relative = TOL);
    assert_relative_eq!(impact.impulse, 6.0e-12 / (1.0 + 1e-24), max_relative = TOL);
    // The same in f32.
    let a = Body::new(1e-12f32, Vector3::new(3.0, 0.0, 0.0)).unwrap();
    let b = Body::new(1e12f32, Vector3::zeros()).unwrap();
    let impact = Law::<f32>::elastic()
        .resolve(&a, &b, &Vector3::x())
        .unwrap()
        .unwrap();
    assert_relative_eq!(impact.delta_v_b.x, 6.0e-24, max_relative = 1e-6);
    assert_relative_eq!(impact.delta_v_a.x, -6.0, max_relative = 1e-6);
}

#[test]
fn oblique_elastic_equal_masses_leave_at_right_angles() {
    let n = Vector2::new(30f64.to_radians().cos(), 30f64.to_radians().sin());
    let v1 = Vector2::new(2.0, 0.0);
    let a = Body::new(1.0, v1).unwrap();
    let b = Body::new(1.0, Vector2::zeros()).unwrap();
    let impact = law(0.0).resolve(&a, &b, &(n * 7.0)).unwrap().unwrap();
    let (v1a, v2a) = (v1 + impact.delta_v_a, impact.delta_v_b);
    let un = v1.dot(&n);
    assert_relative_eq!(v2a, n * un, max_relative = TOL);
    assert_relative_eq!(v1a, v1 - n * un, max_relative = TOL, epsilon = 1e-15);
    assert!(v1a.dot(&v2a).abs() < 1e-15);
}

#[test]
fn oblique_dissipative_matches_note_quadratic() {
    let (m1, m2) = (1.0, 3.0);
    let v1 = Vector3::new(1.0, 0.5, -0.25);
    let v2 = Vector3::new(-0.5, 0.25, 0.75);
    let n = Vector3::new(1.0, 0.2, -0.1).normalize();
    for dt in [0.01, 0.05] {
        let (a, b) = (Body::new(m1, v1).unwrap(), Body::new(m2, v2).unwrap());
        let impact = law(dt).resolve(&a, &b, &n).unwrap().unwrap();
        let k = note_k(m1, m2, v1, v2, n, dt);
        assert!(!impact.clamped);
        assert_relative_eq!(impact.k(a.mass(), b.mass()), k, max_relative = TOL);
        assert_relative_eq!(impact.delta_v_a, -n * (m2 * k), max_relative = TOL);
        assert_relative_eq!(impact.delta_v_b, n * (m1 * k), max_relative = TOL);
        // Energy lost equals d exactly.
        let d = dt * (m1 + m2) * (v2 - v1).norm_squared();
        assert_relative_eq!(impact.dissipated, d, max_relative = TOL);
        let before = 0.5 * m1 * v1.norm_squared() + 0.5 * m2 * v2.norm_squared();
        let after = 0.5 * m1 * (v1 + impact.delta_v_a).norm_squared()
            + 0.5 * m2 * (v2 + impact.delta_v_b).norm_squared();
        assert_relative_eq!(before - after, d, max_relative = TOL);
        let energies = impact.energies(&a, &b);
        assert_relative_eq!(energies.before, before, max_relative = TOL);
        assert_relative_eq!(energies.after, after, max_relative = TOL);
    }
}

#[test]
fn complex_roots_clamp_d_and_keep_a_thousandth() {
    // d̃ = 1 is far beyond the admissible: the discriminant would be negative.
    let (m1, m2) = (2.0, 5.0);
    let v1 = Vector3::new(1.0, 0.3, 0.0);
    let v2 = Vector3::new(-1.0, 0.0, 0.2);
    let n = Vector3::x();
    let (a, b) = (Body::new(m1, v1).unwrap(), Body::new(m2, v2).unwrap());
    let impact = law(1.0).resolve(&a, &b, &n).unwrap().unwrap();
    let energies = impact.energies(&a, &b);
    assert!(impact.clamped);
    let before = (v2 - v1).dot(&n);
    let after = (v2 + impact.delta_v_b - v1 - impact.delta_v_a).dot(&n);
    assert_relative_eq!(after, -1e-3 * before, max_relative = 1e-9);
    let mu = m1 * m2 / (m1 + m2);
    let d_max = 0.5 * mu * before * before;
    assert_relative_eq!(impact.dissipated, (1.0 - 1e-6) * d_max, max_relative = TOL);
    assert_relative_eq!(
        energies.before - energies.after,
        impact.dissipated,
        max_relative = 1e-9
    );
}

#[test]
fn fixed_partner_policies() {
    let v = Vector3::new(-3.0, 1.0, 0.0);
    let ball = Body::new(2.0, v).unwrap();
    let wall = Body::immovable(Vector3::zeros()).unwrap();
    let towards_wall = -Vector3::x();
    // Elastic: the normal component reverses, the tangential stays.
    let impact = law(0.0)
        .resolve(&ball, &wall, &towards_wall)
        .unwrap()
        .unwrap();
    assert_relative_eq!(
        v + impact.delta_v_a,
        Vector3::new(3.0, 1.0, 0.0),
        max_relative = TOL
    );
    assert_eq!(impact.delta_v_b, Vector3::zeros());
    assert_relative_eq!(impact.impulse, 12.0, max_relative = TOL);
    // OwnMass with d̃_w = 0.1: d = d̃_w m |w|² = 0.1·2·10 = 2.
    let own = Law::new(LawParams {
        dissipation: 0.5,
        wall_dissipation: Some(0.1),
        fixed_partner: FixedPartner::OwnMass,
    })
    .unwrap();
    let impact = own.resolve(&ball, &wall, &towards_wall).unwrap().unwrap();
    assert!(!impact.clamped);
    assert_relative_eq!(impact.dissipated, 2.0, max_relative = TOL);
    let energies = impact.energies(&ball, &wall);
    assert_relative_eq!(energies.before - energies.after, 2.0, max_relative = TOL);
    let e = (1.0f64 - 2.0 * 0.1 * 10.0 / 9.0).sqrt();
    assert_relative_eq!((v + impact.delta_v_a).x, 3.0 * e, max_relative = TOL);
    // The wall on the other side of the pair gives the mirror result.
    let mirrored = own.resolve(&wall, &ball, &-towards_wall).unwrap().unwrap();
    assert_relative_eq!(mirrored.delta_v_b, impact.delta_v_a, max_relative = TOL);
    // Literal: any d̃ > 0 is plastic up to the tolerance; d̃ = 0 is elastic.
    let literal = Law::new(LawParams {
        dissipation: 1e-9,
        wall_dissipation: None,
        fixed_partner: FixedPartner::Literal,
    })
    .unwrap();
    let impact = literal
        .resolve(&ball, &wall, &towards_wall)
        .unwrap()
        .unwrap();
    assert!(impact.clamped);
    assert_relative_eq!((v + impact.delta_v_a).x, 3.0e-3, max_relative = 1e-9);
    let literal0 = Law::new(LawParams {
        dissipation: 0.0,
        wall_dissipation: None,
        fixed_partner: FixedPartner::Literal,
    })
    .unwrap();
    let impact = literal0
        .resolve(&ball, &wall, &towards_wall)
        .unwrap()
        .unwrap();
    assert_relative_eq!((v + impact.delta_v_a).x, 3.0, max_relative = TOL);
    // A moving (kinematic) partner: relative velocity is what matters.
    let paddle = Body::immovable(Vector3::new(1.0, 0.0, 0.0)).unwrap();
    let impact = law(0.0)
        .resolve(&ball, &paddle, &towards_wall)
        .unwrap()
        .unwrap();
    assert_relative_eq!((v + impact.delta_v_a).x, 5.0, max_relative = TOL);
    // Two immovable bodies: no impulse.
    assert!(
        law(0.1)
            .resolve(&wall, &paddle, &towards_wall)
            .unwrap()
            .is_none()
    );
}

#[test]
fn no_impulse_unless_approaching() {
    let l = law(0.05);
    let a = Body::new(1.0, Vector3::new(-1.0, 0.0, 0.0)).unwrap();
    let b = Body::new(1.0, Vector3::new(1.0, 0.0, 0.0)).unwrap();
    assert!(
        l.resolve(&a, &b, &Vector3::x()).unwrap().is_none(),
        "separating"
    );
    let rest = Body::new(1.0, Vector3::new(0.0, 5.0, 0.0)).unwrap();
    assert!(
        l.resolve(&rest, &rest, &Vector3::x()).unwrap().is_none(),
        "sliding, no normal approach"
    );
}

#[test]
fn restitution_view_matches_resolve() {
    let l = Law::new(LawParams {
        dissipation: 0.01,
        ..Default::default()
    })
    .unwrap();
    let v1 = Vector3::new(1.0f64, 0.4, 0.0);
    let v2 = Vector3::new(-0.2, -0.1, 0.0);
    let impact = l
        .resolve(
            &Body::new(1.0, v1).unwrap(),
            &Body::new(10.0, v2).unwrap(),
            &Vector3::x(),
        )
        .unwrap()
        .unwrap();
    let w = v2 - v1;
    let r = l
        .restitution(
            Mass::Finite(1.0),
            Mass::Finite(10.0),
            -w.x,
            (w.y * w.y + w.z * w.z).sqrt(),
        )
        .unwrap()
        .unwrap();
    assert_relative_eq!(r.coefficient, impact.restitution, max_relative = TOL);
    let after = (v2 + impact.delta_v_b - v1 - impact.delta_v_a).x;
    assert_relative_eq!(after, -w.x * r.coefficient, max_relative = TOL);
    assert!(
        l.restitution(Mass::Finite(1.0), Mass::Finite(1.0), -1.0, 0.0)
            .unwrap()
            .is_none()
    );
}

#[test]
fn bad_input_is_a_typed_error() {
    use Which::Body as B;
    assert!(
        matches!(Body::new(f64::NAN, Vector3::zeros()), Err(LawError::NonFiniteMass { which: B, value }) if value.is_nan())
    );
    assert!(matches!(
        Body::new(f64::INFINITY, Vector3::zeros()),
        Err(LawError::NonFiniteMass { which: B, .. })
    ));
    assert_eq!(
        Body::new(0.0, Vector3::zeros()).unwrap_err(),
        LawError::NonPositiveMass {
            which: B,
            value: 0.0
        }
    );
    assert_eq!(
        Body::new(-1.0, Vector3::zeros()).unwrap_err(),
        LawError::NonPositiveMass {
            which: B,
            value: -1.0
        }
    );
    assert_eq!(
        Body::new(1.0, Vector3::new(0.0, f64::INFINITY, 0.0)).unwrap_err(),
        LawError::NonFiniteVelocity {
            which: B,
            component: 1,
            value: f64::INFINITY
        }
    );
    assert!(matches!(
        Body::<f32, 2>::immovable(Vector2::new(f32::NAN, 0.0)),
        Err(LawError::NonFiniteVelocity { component: 0, .. })
    ));
    let a = Body::new(1.0, Vector3::x()).unwrap();
    let b = Body::new(1.0, Vector3::zeros()).unwrap();
    assert_eq!(
        law(0.0).resolve(&a, &b, &Vector3::zeros()).unwrap_err(),
        LawError::ZeroNormal
    );
    assert!(matches!(
        law(0.0).resolve(&a, &b, &Vector3::new(1.0, f64::NAN, 0.0)),
        Err(LawError::NonFiniteNormal { component: 1, .. })
    ));
    for bad in [-0.1, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            Law::new(LawParams {
                dissipation: bad,
                ..Default::default()
            }),
            Err(LawError::InvalidDissipation {
                parameter: "dissipation",
                ..
            })
        ));
        assert!(matches!(
            Law::new(LawParams {
                dissipation: 0.0,
                wall_dissipation: Some(bad),
                ..Default::default()
            }),
            Err(LawError::InvalidDissipation {
                parameter: "wall_dissipation",
                ..
            })
        ));
    }
    assert!(matches!(
        law(0.0).restitution(Mass::Finite(-1.0), Mass::Finite(1.0), 1.0, 0.0),
        Err(LawError::NonPositiveMass {
            which: Which::First,
            ..
        })
    ));
    assert!(matches!(
        law(0.0).restitution(Mass::Finite(1.0), Mass::Finite(f64::NAN), 1.0, 0.0),
        Err(LawError::NonFiniteMass {
            which: Which::Second,
            ..
        })
    ));
    assert!(matches!(
        law(0.0).restitution(Mass::Finite(1.0), Mass::Infinite, f64::NAN, 0.0),
        Err(LawError::InvalidSpeed {
            quantity: "approach_speed",
            ..
        })
    ));
    assert!(matches!(
        law(0.0).restitution(Mass::Finite(1.0), Mass::Infinite, 1.0, -1.0),
        Err(LawError::InvalidSpeed {
            quantity: "tangential_speed",
            ..
        })
    ));
    // Messages name the quantity.
    assert_eq!(
        Body::new(-2.0, Vector3::zeros()).unwrap_err().to_string(),
        "body: mass must be positive, got -2"
    );
}

#[test]
fn huge_and_tiny_normals_are_normalized_without_overflow() {
    let a = Body::new(1.0, Vector3::x()).unwrap();
    let b = Body::new(1.0, Vector3::zeros()).unwrap();
    for scale in [1e-300, 1e300] {
        let impact = law(0.0)
            .resolve(&a, &b, &(Vector3::new(1.0, 1.0, 0.0) * scale))
            .unwrap()
            .unwrap();
        assert_relative_eq!(impact.normal.norm(), 1.0, max_relative = TOL);
        assert_relative_eq!(impact.approach_speed, 0.5f64.sqrt(), max_relative = TOL);
    }
}

#[test]
fn parameters_changed_at_run_time_are_checked() {
    let mut l = law(0.01);
    let err = l
        .set_params(LawParams {
            dissipation: -1.0,
            ..Default::default()
        })
        .unwrap_err();
    assert!(matches!(err, LawError::InvalidDissipation { .. }));
    assert_eq!(l.dissipation(), 0.01, "the old value stays in force");
    l.set_params(LawParams {
        dissipation: 0.02,
        ..Default::default()
    })
    .unwrap();
    assert_eq!(l.dissipation(), 0.02);
    assert_eq!(l.params().wall_dissipation, None);
}
