//! The rigid-body law against textbook impulse formulas, evaluated here
//! (never from the implementation): rods dropped on a floor in 2D and 3D,
//! off-centre hits, a spinning ball on a wall, a kinematic paddle; and the
//! typed errors of the rigid constructors.

use approx::assert_relative_eq;
use kimpact::nalgebra::{Matrix3, Rotation3, Vector2, Vector3};
use kimpact::{Body, Contact, FixedPartner, Law, LawError, LawParams, RigidBody, Which};

const TOL: f64 = 1e-12;

fn law(d: f64, d_wall: f64) -> Law<f64> {
    Law::new(LawParams {
        dissipation: d,
        wall_dissipation: Some(d_wall),
        fixed_partner: FixedPartner::OwnMass,
    })
    .unwrap()
}

/// A uniform rod (mass m, length L, I = mL²/12) at angle θ above the
/// horizontal falls at v₀ without turning; its lower end hits a fixed
/// floor. The textbook impulse at the end, with `c = cos θ`:
/// `1/m_eff = 1/m + (L c/2)²/I = (1 + 3c²)/m`, `J = m_eff v₀ (1 + e)`,
/// `v' = −v₀ + J/m`, `ω' = (r × J ŷ)/I = −(L c/2) J / I`.
/// Elastic (`e = 1`) and with `d̃_w` (`q = 2 d̃_w ρ m/m_eff`, `ρ = 1` for a
/// rod that does not turn: the end moves along the normal).
#[test]
fn a_rod_dropped_on_a_floor_in_2d() {
    let (m, length, v0) = (2.0, 1.5, 3.0);
    let inertia = m * length * length / 12.0;
    for deg in [0.0, 10.0, 30.0, 45.0, 60.0, 80.0] {
        for d_wall in [0.0, 0.05, 0.1] {
            let (s, c) = f64::to_radians(deg).sin_cos();
            let arm = Vector2::new(-0.5 * length * c, -0.5 * length * s);
            let rod = RigidBody::new(m, Vector2::new(0.0, -v0), 0.0, 1.0 / inertia).unwrap();
            let floor = RigidBody::immovable(Vector2::zeros(), 0.0).unwrap();
            // The floor's arm is any: it does not move.
            let contact =
                Contact::new(arm, Vector2::new(3.0, 0.25), Vector2::new(0.0, -1.0)).unwrap();
            let impact = law(0.0, d_wall)
                .resolve_rigid(&rod, &floor, &contact)
                .unwrap();

            let m_eff = m / (1.0 + 3.0 * c * c);
            let q = 2.0 * d_wall * m / m_eff;
            let e = (1.0 - q).sqrt();
            let j = m_eff * v0 * (1.0 + e);
            assert_relative_eq!(impact.impulse, j, max_relative = TOL);
            assert_relative_eq!(impact.effective_mass, m_eff, max_relative = TOL);
            assert_relative_eq!(impact.restitution, e, max_relative = TOL);
            let (after, floor_after) = impact.apply(&rod, &floor);
            assert_relative_eq!(
                after.velocity().y,
                -v0 + j / m,
                max_relative = TOL,
                epsilon = 1e-15
            );
            assert_eq!(after.velocity().x, 0.0);
            let omega = -(0.5 * length * c) * j / inertia;
            assert_relative_eq!(
                *after.angular_velocity(),
                omega,
                max_relative = TOL,
                epsilon = 1e-15
            );
            assert_eq!(floor_after, floor);
            // Energy: the textbook sum, less d = d̃_w m v₀².
            let energy = |b: &RigidBody<f64, 2>| {
                0.5 * m * b.velocity().norm_squared() + 0.5 * inertia * b.angular_velocity().powi(2)
            };
            let d = d_wall * m * v0 * v0;
            assert_relative_eq!(
                energy(&rod) - energy(&after),
                d,
                epsilon = TOL * energy(&rod)
            );
            assert_relative_eq!(impact.dissipated, d, epsilon = TOL * energy(&rod));
            // The end leaves the floor at e times its approach speed.
            assert_relative_eq!(-after.point_velocity(&arm).y, -e * v0, epsilon = TOL * v0);
        }
    }
}

/// The 3D rod: a square bar (length L, width w: `I_⊥ = m(L² + w²)/12`,
/// `I_∥ = m w²/6`) whose axis is tilted θ above the floor and turned ψ
/// about the vertical, falling at v₀ onto a fixed floor (normal `−z` from
/// the bar). `k = r × n̄` is perpendicular to the axis, so only `I_⊥`
/// counts: `1/m_eff = 1/m + (L c/2)²/I_⊥`; `ω' = (r × J ẑ)/I_⊥`.
#[test]
fn a_rod_dropped_on_a_floor_in_3d() {
    let (m, length, width, v0) = (1.3, 2.0, 0.1, 2.5);
    let i_perp = m * (length * length + width * width) / 12.0;
    let i_axial = m * width * width / 6.0;
    for (deg, psi) in [(10.0, 0.0), (30.0, 0.7), (45.0, 2.0), (70.0, -1.1)] {
        let theta = f64::to_radians(deg);
        let rotation = Rotation3::from_axis_angle(&Vector3::z_axis(), psi)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), -theta);
        let axis = rotation * Vector3::x();
        assert!(axis.z > 0.0);
        let r = rotation.matrix();
        let inverse = r
            * Matrix3::from_diagonal(&Vector3::new(1.0 / i_axial, 1.0 / i_perp, 1.0 / i_perp))
            * r.transpose();
        let bar =
            RigidBody::new(m, Vector3::new(0.0, 0.0, -v0), Vector3::zeros(), inverse).unwrap();
        let floor = RigidBody::immovable(Vector3::zeros(), Vector3::zeros()).unwrap();
        let arm = -axis * (0.5 * length);
        let contact = Contact::new(arm, Vector3::new(1.0, 2.0, 0.0), -Vector3::z()).unwrap();
        let impact = Law::elastic()
            .resolve_rigid(&bar, &floor, &contact)
            .unwrap();

        let c = theta.cos();
        let m_eff = 1.0 / (1.0 / m + (0.5 * length * c).powi(2) / i_perp);
        let j = 2.0 * m_eff * v0;
        assert_relative_eq!(impact.impulse, j, max_relative = TOL);
        let (after, _) = impact.apply(&bar, &floor);
        assert_relative_eq!(
            *after.velocity(),
            Vector3::new(0.0, 0.0, -v0 + j / m),
            epsilon = TOL
        );
        let omega = arm.cross(&(Vector3::z() * j)) / i_perp;
        assert_relative_eq!(
            *after.angular_velocity(),
            omega,
            epsilon = TOL * omega.norm()
        );
        assert_eq!(impact.dissipated, 0.0);
    }
}

/// A ball (centred: its arm is along the normal, so its inertia does not
/// count) hits a free rod at height h from the rod's centre, head-on:
/// `1/m_eff = 1/m + 1/M + h²/I`, `J = m_eff U (1 + e)` with `U` the
/// approach speed of the contact points (the rod may spin: its point at
/// height h moves at `ω₀ × r`), `q = 2 d̃ (m + M) ρ / m_eff` (`ρ = 1`:
/// head-on), `v_ball' = v − J/m`, `V' = J/M`, `ω' = ω₀ − h J / I`.
#[test]
fn an_off_centre_hit_on_a_rod_in_2d_and_3d() {
    let (m, big_m, length, v): (f64, f64, f64, f64) = (0.5, 3.0, 2.0, 4.0);
    let inertia = big_m * length * length / 12.0;
    let ball_inertia = 0.4 * m * 0.1 * 0.1;
    for h in [0.0, 0.3, 0.6, 1.0] {
        for omega0 in [0.0, 1.5, -2.0] {
            for d in [0.0, 0.02] {
                let m_eff = 1.0 / (1.0 / m + 1.0 / big_m + h * h / inertia);
                let u = v + omega0 * h;
                let q = 2.0 * d * (m + big_m) / m_eff;
                let e = (1.0 - q).sqrt();
                let j = m_eff * u * (1.0 + e);

                // 2D: the ball at (−0.1, h) moving +x, the rod along y.
                let ball =
                    RigidBody::new(m, Vector2::new(v, 0.0), 0.0, 1.0 / ball_inertia).unwrap();
                let rod = RigidBody::new(big_m, Vector2::zeros(), omega0, 1.0 / inertia).unwrap();
                let contact =
                    Contact::new(Vector2::new(0.1, 0.0), Vector2::new(0.0, h), Vector2::x())
                        .unwrap();
                let impact = law(d, 0.0).resolve_rigid(&ball, &rod, &contact).unwrap();
                assert!(!impact.clamped);
                assert_relative_eq!(impact.impulse, j, max_relative = TOL);
                assert_relative_eq!(impact.approach_speed, u, max_relative = TOL);
                let (ball2, rod2) = impact.apply(&ball, &rod);
                assert_relative_eq!(
                    ball2.velocity().x,
                    v - j / m,
                    max_relative = TOL,
                    epsilon = TOL
                );
                assert_eq!(*ball2.angular_velocity(), 0.0);
                assert_relative_eq!(rod2.velocity().x, j / big_m, max_relative = TOL);
                assert_relative_eq!(
                    *rod2.angular_velocity(),
                    omega0 - h * j / inertia,
                    epsilon = TOL
                );
                assert_relative_eq!(impact.dissipated, d * (m + big_m) * u * u, epsilon = TOL);

                // 3D: the same in the plane z = 0, the rod's inertia
                // tensor that of a thin rod along y.
                let inverse =
                    Matrix3::from_diagonal(&Vector3::new(1.0 / inertia, 0.0, 1.0 / inertia));
                let ball = RigidBody::new(
                    m,
                    Vector3::new(v, 0.0, 0.0),
                    Vector3::zeros(),
                    Matrix3::identity() / ball_inertia,
                )
                .unwrap();
                let rod = RigidBody::new(big_m, Vector3::zeros(), Vector3::z() * omega0, inverse)
                    .unwrap();
                let contact =
                    Contact::new(Vector3::x() * 0.1, Vector3::y() * h, Vector3::x()).unwrap();
                let impact = law(d, 0.0).resolve_rigid(&ball, &rod, &contact).unwrap();
                assert_relative_eq!(impact.impulse, j, max_relative = TOL);
                let (ball2, rod2) = impact.apply(&ball, &rod);
                assert_relative_eq!(
                    ball2.velocity().x,
                    v - j / m,
                    max_relative = TOL,
                    epsilon = TOL
                );
                assert_eq!(*ball2.angular_velocity(), Vector3::zeros());
                assert_relative_eq!(
                    *rod2.angular_velocity(),
                    Vector3::z() * (omega0 - h * j / inertia),
                    epsilon = TOL
                );
            }
        }
    }
}

/// A spinning ball hitting a wall head-on without friction keeps its spin
/// (its arm is along the normal: no torque) and, elastic, reverses its
/// normal velocity. With `d̃_w > 0` the law counts the surface speed
/// `|ω × r| = ω R` in `d` (the contact points' relative velocity):
/// `ρ = 1 + (ω R / v)²`, `e = sqrt(1 − 2 d̃_w ρ)`.
#[test]
fn a_spinning_ball_hits_a_wall_head_on_and_keeps_its_spin() {
    let (m, radius, v, spin) = (0.17, 0.028, 2.0, 30.0);
    let inverse = Matrix3::identity() / (0.4 * m * radius * radius);
    let omega = Vector3::new(0.0, spin, 0.0);
    let ball = RigidBody::new(m, Vector3::new(v, 0.0, 0.0), omega, inverse).unwrap();
    let wall = RigidBody::immovable(Vector3::zeros(), Vector3::zeros()).unwrap();
    let contact = Contact::new(Vector3::x() * radius, Vector3::zeros(), Vector3::x()).unwrap();
    for d_wall in [0.0, 0.1] {
        let impact = law(0.0, d_wall)
            .resolve_rigid(&ball, &wall, &contact)
            .unwrap();
        let (after, _) = impact.apply(&ball, &wall);
        assert_eq!(*after.angular_velocity(), omega);
        let rho = 1.0 + (spin * radius / v).powi(2);
        let e = (1.0 - 2.0 * d_wall * rho).sqrt();
        assert_relative_eq!(after.velocity().x, -e * v, max_relative = TOL);
        assert_eq!(after.velocity().yz(), Vector2::zeros());
    }
    // The ball law's result for the same ball without spin, bit for bit.
    let still = Body::new(m, Vector3::new(v, 0.0, 0.0)).unwrap();
    let wall_body = Body::immovable(Vector3::zeros()).unwrap();
    let ball_law = law(0.0, 0.1)
        .resolve_unit(&still, &wall_body, &Vector3::x())
        .unwrap();
    let rigid = law(0.0, 0.1)
        .resolve_rigid(
            &RigidBody::new(m, Vector3::new(v, 0.0, 0.0), Vector3::zeros(), inverse).unwrap(),
            &wall,
            &contact,
        )
        .unwrap();
    assert_eq!(rigid.delta_v_a, ball_law.delta_v_a);
    assert_eq!(rigid.restitution, ball_law.restitution);
    assert_eq!(rigid.dissipated, ball_law.dissipated);
}

/// A kinematic paddle turning at Ω about its pivot meets a ball at rest at
/// arm r: the paddle's contact point moves at `Ω × r`, the ball leaves at
/// `2 (Ω × r)·n̄` along the normal (elastic, infinite partner), and the
/// paddle is unchanged.
#[test]
fn a_kinematic_paddle_bats_a_ball() {
    let big_omega = 5.0;
    let arm = Vector2::new(0.4, 0.0);
    let paddle = RigidBody::immovable(Vector2::zeros(), big_omega).unwrap();
    let ball = RigidBody::new(0.1, Vector2::zeros(), 0.0, 250.0).unwrap();
    // Normal from the paddle (a) towards the ball (b): +y.
    let contact = Contact::new(arm, Vector2::new(0.0, -0.02), Vector2::y()).unwrap();
    let impact = Law::elastic()
        .resolve_rigid(&paddle, &ball, &contact)
        .unwrap();
    assert_eq!(impact.delta_v_a, Vector2::zeros());
    assert_eq!(impact.delta_omega_a, 0.0);
    let surface = big_omega * arm.x;
    assert_relative_eq!(
        impact.delta_v_b,
        Vector2::new(0.0, 2.0 * surface),
        max_relative = TOL
    );
    assert_eq!(impact.delta_omega_b, 0.0);
    // Moving apart: nothing to resolve.
    let receding = RigidBody::immovable(Vector2::zeros(), -big_omega).unwrap();
    assert!(
        Law::elastic()
            .resolve_rigid(&receding, &ball, &contact)
            .is_none()
    );
}

#[test]
fn bad_rigid_input_is_a_typed_error() {
    let v = Vector3::zeros();
    let w = Vector3::zeros();
    let ok = Matrix3::identity();
    match RigidBody::new(1.0, v, Vector3::new(0.0, f64::NAN, 0.0), ok) {
        Err(LawError::NonFiniteAngularVelocity {
            which: Which::Body,
            component: 1,
            value,
        }) => {
            assert!(value.is_nan())
        }
        other => panic!("{other:?}"),
    }
    let mut m = ok;
    m[(2, 1)] = f64::INFINITY;
    assert_eq!(
        RigidBody::new(1.0, v, w, m),
        Err(LawError::NonFiniteInertia {
            which: Which::Body,
            row: 2,
            column: 1,
            value: f64::INFINITY
        })
    );
    let mut m = ok;
    m[(0, 2)] = 0.5;
    match RigidBody::new(1.0, v, w, m) {
        Err(LawError::AsymmetricInertia {
            row: 0,
            column: 2,
            difference,
            ..
        }) => {
            assert_eq!(difference, 0.5)
        }
        other => panic!("{other:?}"),
    }
    // Symmetric with eigenvalues 3, 1, −1: not semidefinite.
    let m = Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    match RigidBody::new(1.0, v, w, m) {
        Err(LawError::NegativeInertia {
            which: Which::Body,
            value,
        }) => {
            assert_relative_eq!(value, -1.0, epsilon = 1e-12)
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        RigidBody::new(1.0, Vector2::zeros(), 0.0, -1.0),
        Err(LawError::NegativeInertia {
            which: Which::Body,
            value: -1.0
        })
    );
    assert_eq!(
        RigidBody::new(-1.0, Vector2::zeros(), 0.0, 1.0),
        Err(LawError::NonPositiveMass {
            which: Which::Body,
            value: -1.0
        })
    );
    let e = Contact::new(
        Vector2::new(0.0, f64::INFINITY),
        Vector2::zeros(),
        Vector2::x(),
    )
    .unwrap_err();
    assert_eq!(
        e,
        LawError::NonFiniteArm {
            which: Which::First,
            component: 1,
            value: f64::INFINITY
        }
    );
    assert!(e.to_string().contains("first body"), "{e}");
    assert_eq!(
        Contact::new(Vector2::zeros(), Vector2::zeros(), Vector2::<f64>::zeros()),
        Err(LawError::ZeroNormal)
    );
    // A singular (locked) inverse inertia and a rounding-level asymmetry
    // are fine; the matrix is used exactly symmetric.
    let mut locked = Matrix3::from_diagonal(&Vector3::new(1.0, 0.0, 2.0));
    locked[(0, 2)] = 1e-17;
    let body = RigidBody::new(1.0, v, w, locked).unwrap();
    let used = body.inverse_inertia();
    assert_eq!(used[(0, 2)], used[(2, 0)]);
    // Messages name the field.
    let e = RigidBody::new(1.0, Vector2::zeros(), 0.0, f64::NAN).unwrap_err();
    assert!(e.to_string().contains("inverse inertia"), "{e}");
}

/// A body spinning fast strikes a wall elastically far out on a long arm
/// whose line of action passes close to its centre (2D, f32, the scene
/// turned by `φ`): the contact point moves mostly along the wall
/// (`|ω × r| = 2720` m/s) and closes at only `v + ω (r × n̄) = 13.05` m/s.
/// The law's approach speed takes the spin's part as `ω (r × n̄)`, the
/// arm `k = r × n̄` the impulse turns the body through: the kinetic
/// energy, translation and rotation, is kept to the rounding of the
/// result. (`U` taken from the summed contact velocity differs from
/// `v·n̄ + ω k` by its rounding, `ε |ω × r|`, and the impulse then changes
/// the energy by `2 m_eff U δU`: up to 5e-5 of it here.)
#[test]
fn a_fast_spin_struck_near_its_centre_keeps_its_energy_in_f32() {
    let (m, inverse, spin, speed) = (1.0f32, 323.0f32, 160.0f32, 0.25f32);
    let law = Law::<f32>::new(LawParams {
        dissipation: 0.0,
        wall_dissipation: Some(0.0),
        fixed_partner: FixedPartner::OwnMass,
    })
    .unwrap();
    let energy = |v: &Vector2<f32>, w: f32| {
        0.5 * f64::from(m) * f64::from(v.norm_squared())
            + 0.5 * f64::from(w) * f64::from(w) / f64::from(inverse)
    };
    let mut worst = 0.0f64;
    for k in 0..64 {
        let phi = 0.1 * k as f32;
        let turn = |x: f32, y: f32| {
            let (s, c) = phi.sin_cos();
            Vector2::new(c * x - s * y, s * x + c * y)
        };
        for (arm_x, arm_y) in [(17.0f32, -0.08f32), (-17.0, -0.08), (5.0, -0.3)] {
            let (v, r, n) = (turn(speed, 0.0), turn(arm_x, arm_y), turn(1.0, 0.0));
            let body = RigidBody::new(m, v, spin, inverse).unwrap();
            let wall = RigidBody::immovable(Vector2::zeros(), 0.0).unwrap();
            let contact = Contact::new(r, Vector2::zeros(), n).unwrap();
            let impact = law.resolve_rigid(&body, &wall, &contact).unwrap();
            // The approach speed in closed form, of the f32 inputs as they
            // are: v·n̄ + ω (r × n̄), to the rounding of `r × n̄` in f32
            // (`ε |r|`, of the order of the arm's offset's rounding).
            let (v, r, n) = (v.cast::<f64>(), r.cast::<f64>(), n.cast::<f64>());
            let expected = v.dot(&n) + f64::from(spin) * (r.x * n.y - r.y * n.x);
            let rounding = 4.0 * f64::from(f32::EPSILON) * f64::from(spin) * r.norm();
            assert!(
                (f64::from(impact.approach_speed) - expected).abs() < rounding,
                "φ {phi}: U = {}, closed form {expected}",
                impact.approach_speed
            );
            let (after, _) = impact.apply(&body, &wall);
            let (e0, e1) = (
                energy(body.velocity(), *body.angular_velocity()),
                energy(after.velocity(), *after.angular_velocity()),
            );
            worst = worst.max(((e1 - e0) / e0).abs());
        }
    }
    assert!(
        worst < 64.0 * f64::from(f32::EPSILON),
        "energy changed by {worst:e}"
    );
}
