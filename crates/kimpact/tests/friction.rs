//! Impact friction (Walton's three-parameter model) against published and
//! closed-form answers: the throw of a cut shot between two solid spheres
//! (Alciatore, TP A-14), a spinning ball hitting a wall obliquely in the
//! sticking and the sliding regime; 2D and 3D, f32 and f64; typed errors.

use approx::assert_relative_eq;
use kimpact::nalgebra::{Matrix3, RealField, Vector2, Vector3};
use kimpact::{
    Contact, FixedPartner, FrictionRegime, ImpactFriction, Law, LawError, LawParams, RigidBody,
};

const R: f64 = 0.028_575;
const M: f64 = 0.17;

fn sphere_inertia() -> f64 {
    0.4 * M * R * R
}

/// The cut shot of TP A-14 (stun: neither ball spins), elastic normal law,
/// β = 0, constant μ, in free space. The cue ball moves at v along x; the
/// line of centres n̄ (cue towards object) is at the cut angle φ to it.
///
/// Why `tan θ = min(μ, tan φ / 7)` holds for this model: the contact
/// points' relative velocity has the normal part `U = v cos φ` and the
/// tangential part `|g| = v sin φ` (no spin; the centred normal impulse
/// couples nothing into it). For two free solid spheres (`I = 2mR²/5`,
/// arms `±R n̄`) the tangential inverse effective mass is
/// `K_tt = 1/m + 1/m + R²/I + R²/I = (2/m)(1 + 5/2) = 7/m`, against the
/// normal `K_nn = 2/m`; so `J_n = (m/2) U (1 + 1) = m v cos φ` and the
/// impulse that stops the tangential motion (β = 0: `g' = 0`, Walton's
/// sticking, which A-14's "rolling" contact also is) is
/// `|P_t| = |g|/K_tt = m v sin φ / 7`. Sticking while `|P_t| ≤ μ J_n`,
/// i.e. `tan φ / 7 ≤ μ`, else sliding with `|P_t| = μ J_n`. The object
/// ball leaves along `J_n n̄ + P_t`, off the line of centres by θ with
/// `tan θ = |P_t|/J_n = min(μ, tan φ / 7)`.
#[test]
fn cut_shot_throw_matches_alciatore_tp_a14() {
    let mu = 0.06;
    let friction = ImpactFriction::new(mu, 0.0).unwrap();
    let (mut stuck, mut slid) = (0, 0);
    for tenth in 0..=600 {
        let phi = f64::to_radians(f64::from(tenth) / 10.0);
        let expected = mu.min(phi.tan() / 7.0);
        let n = Vector3::new(phi.cos(), phi.sin(), 0.0);
        let t = Vector3::new(-phi.sin(), phi.cos(), 0.0);
        let inverse = Matrix3::identity() / sphere_inertia();
        let cue =
            RigidBody::new(M, Vector3::new(1.7, 0.0, 0.0), Vector3::zeros(), inverse).unwrap();
        let object = RigidBody::new(M, Vector3::zeros(), Vector3::zeros(), inverse).unwrap();
        let contact = Contact::new(n * R, -n * R, n).unwrap();
        let impact = Law::elastic()
            .resolve_rigid_with_friction(&cue, &object, &contact, &friction)
            .unwrap();
        let v = impact.delta_v_b;
        // The cue's cut is towards +y of n̄: the object is thrown towards −t.
        let throw = (-v.dot(&t)).atan2(v.dot(&n)).tan();
        assert!(
            (throw - expected).abs() < 1e-9,
            "φ = {}°: tan θ = {throw}, A-14 {expected}",
            f64::from(tenth) / 10.0
        );
        match impact.friction {
            FrictionRegime::Stick => stuck += 1,
            FrictionRegime::Slide => slid += 1,
            FrictionRegime::None => assert_eq!(tenth, 0),
            FrictionRegime::Limited => panic!("spheres are never limited"),
        }
        // The same in 2D (disks given the sphere's inertia: the spins are
        // about the table's normal).
        let n2 = n.xy();
        let cue = RigidBody::new(M, Vector2::new(1.7, 0.0), 0.0, 1.0 / sphere_inertia()).unwrap();
        let object = RigidBody::new(M, Vector2::zeros(), 0.0, 1.0 / sphere_inertia()).unwrap();
        let contact = Contact::new(n2 * R, -n2 * R, n2).unwrap();
        let impact = Law::elastic()
            .resolve_rigid_with_friction(&cue, &object, &contact, &friction)
            .unwrap();
        let v = impact.delta_v_b;
        let throw = (-v.dot(&t.xy())).atan2(v.dot(&n2)).tan();
        assert!((throw - expected).abs() < 1e-9, "2D φ = {phi}");
        // f32, as a sanity check.
        let c = |x: f64| x as f32;
        let cue =
            RigidBody::new(c(M), Vector2::new(1.7, 0.0), 0.0, c(1.0 / sphere_inertia())).unwrap();
        let object =
            RigidBody::new(c(M), Vector2::zeros(), 0.0, c(1.0 / sphere_inertia())).unwrap();
        let n32 = n2.map(c);
        let contact = Contact::new(n32 * c(R), -n32 * c(R), n32).unwrap();
        let impact = Law::elastic()
            .resolve_rigid_with_friction(
                &cue,
                &object,
                &contact,
                &ImpactFriction::new(0.06_f32, 0.0).unwrap(),
            )
            .unwrap();
        let v = impact.delta_v_b;
        let throw = (-v.dot(&t.xy().map(c))).atan2(v.dot(&n32)).tan();
        assert!((f64::from(throw) - expected).abs() < 1e-5, "f32 φ = {phi}");
    }
    // Both regimes are covered (the switch is at tan φ = 7 μ, φ = 22.8°).
    assert!(stuck > 100 && slid > 100, "{stuck} stuck, {slid} slid");
}

/// A ball of radius R spinning at ω hits a fixed wall (normal x̄ from the
/// ball) with velocity (v_n, v_t). The contact point's tangential velocity
/// is `u_t = v_t + ω_z R` (3D: `v_t + ω × r` in the wall's plane); the
/// normal law gives `J_n = m v_n (1 + e)`, `e = sqrt(1 − 2 d̃_w ρ)`,
/// `ρ = 1 + |u_t|²/v_n²`. For a solid sphere `K_tt = 1/m + R²/I = 7/(2m)`:
///
/// - stick (`(1 + β)(2/7)|u_t| ≤ μ (1 + e) v_n`): `Δv_t = −(1 + β)(2/7) u_t`,
///   `Δω = −(1 + β)(5/7) (x̄ × u_t)/R` (3D; `−(1 + β)(5/7) u_t/R` about z);
/// - slide: `Δv_t = −μ (1 + e) v_n û_t`, `Δω = −(5/2) μ (1 + e) v_n (x̄ × û_t)/R`.
///
/// Spin about the normal is untouched; `v_n' = −e v_n`.
fn wall_closed_form(
    v: Vector3<f64>,
    omega: Vector3<f64>,
    d_wall: f64,
    mu: f64,
    beta: f64,
    sticks: bool,
) {
    let law = Law::new(LawParams {
        dissipation: 0.0,
        wall_dissipation: Some(d_wall),
        fixed_partner: FixedPartner::OwnMass,
    })
    .unwrap();
    let friction = ImpactFriction::new(mu, beta).unwrap();
    let arm = Vector3::x() * R;
    let u = v + omega.cross(&arm);
    let u_t = Vector3::new(0.0, u.y, u.z);
    let rho = 1.0 + u_t.norm_squared() / (v.x * v.x);
    let e = (1.0 - 2.0 * d_wall * rho).sqrt();
    let jn_per_m = v.x * (1.0 + e);
    let stick = (1.0 + beta) * (2.0 / 7.0) * u_t.norm() <= mu * jn_per_m;
    assert_eq!(stick, sticks, "the case is in the regime it is meant for");
    let (dv_t, dw) = if stick {
        (
            -u_t * ((1.0 + beta) * 2.0 / 7.0),
            -Vector3::x().cross(&u_t) * ((1.0 + beta) * 5.0 / 7.0 / R),
        )
    } else {
        let dir = u_t / u_t.norm();
        (
            -dir * (mu * jn_per_m),
            -Vector3::x().cross(&dir) * (2.5 * mu * jn_per_m / R),
        )
    };
    let v_after = Vector3::new(-e * v.x, v.y + dv_t.y, v.z + dv_t.z);
    let w_after = omega + dw;
    let what = format!("v {v:?} ω {omega:?} d̃_w {d_wall} μ {mu} β {beta} stick {stick}");

    // 3D.
    let inverse = Matrix3::identity() / sphere_inertia();
    let ball = RigidBody::new(M, v, omega, inverse).unwrap();
    let wall = RigidBody::immovable(Vector3::zeros(), Vector3::zeros()).unwrap();
    let contact = Contact::new(arm, Vector3::new(0.0, 1.0, -2.0), Vector3::x()).unwrap();
    let impact = law
        .resolve_rigid_with_friction(&ball, &wall, &contact, &friction)
        .unwrap();
    let expected_regime = if stick {
        FrictionRegime::Stick
    } else {
        FrictionRegime::Slide
    };
    assert_eq!(impact.friction, expected_regime, "{what}");
    let (after, _) = impact.apply(&ball, &wall);
    assert_relative_eq!(*after.velocity(), v_after, epsilon = 1e-12 * v.norm());
    assert_relative_eq!(
        *after.angular_velocity(),
        w_after,
        epsilon = 1e-12 * (omega.norm() + v.norm() / R)
    );
    // Energy: the sphere's, before less after, is what the impact reports.
    let energy = |b: &RigidBody<f64, 3>| {
        0.5 * M * b.velocity().norm_squared()
            + 0.5 * sphere_inertia() * b.angular_velocity().norm_squared()
    };
    let lost = energy(&ball) - energy(&after);
    assert!(lost >= -1e-12 * energy(&ball), "{what}: energy rose");
    assert_relative_eq!(lost, impact.dissipated, epsilon = 1e-12 * energy(&ball));
    // A stuck contact point leaves at −β u_t.
    if stick {
        let u_after = after.point_velocity(&arm);
        assert_relative_eq!(u_after.yz(), -u_t.yz() * beta, epsilon = 1e-12 * u.norm());
    }

    // 2D (the motion in the x-y plane, spin about z).
    if v.z == 0.0 && omega.x == 0.0 && omega.y == 0.0 {
        let ball = RigidBody::new(M, v.xy(), omega.z, 1.0 / sphere_inertia()).unwrap();
        let wall = RigidBody::immovable(Vector2::zeros(), 0.0).unwrap();
        let contact = Contact::new(arm.xy(), Vector2::zeros(), Vector2::x()).unwrap();
        let impact = law
            .resolve_rigid_with_friction(&ball, &wall, &contact, &friction)
            .unwrap();
        assert_eq!(impact.friction, expected_regime, "2D {what}");
        let (after, _) = impact.apply(&ball, &wall);
        assert_relative_eq!(*after.velocity(), v_after.xy(), epsilon = 1e-12 * v.norm());
        assert_relative_eq!(
            *after.angular_velocity(),
            w_after.z,
            epsilon = 1e-12 * (omega.norm() + v.norm() / R)
        );
        // f32 sanity.
        let c = |x: f64| x as f32;
        let ball =
            RigidBody::new(c(M), v.xy().map(c), c(omega.z), c(1.0 / sphere_inertia())).unwrap();
        let wall = RigidBody::immovable(Vector2::<f32>::zeros(), 0.0).unwrap();
        let contact = Contact::new(arm.xy().map(c), Vector2::zeros(), Vector2::x()).unwrap();
        let law32 = Law::new(law.params().map(c)).unwrap();
        let friction32 = ImpactFriction::new(c(mu), c(beta)).unwrap();
        let impact = law32
            .resolve_rigid_with_friction(&ball, &wall, &contact, &friction32)
            .unwrap();
        let (after, _) = impact.apply(&ball, &wall);
        assert_relative_eq!(
            after.velocity().map(f64::from),
            v_after.xy(),
            epsilon = 1e-5 * v.norm()
        );
    }
}

#[test]
fn a_spinning_ball_hits_a_wall_obliquely_stick_and_slide() {
    // Sticking: a small tangential contact speed against a large normal one.
    wall_closed_form(
        Vector3::new(3.0, 0.4, 0.0),
        Vector3::new(0.0, 0.0, -5.0),
        0.0,
        0.3,
        0.0,
        true,
    );
    wall_closed_form(
        Vector3::new(3.0, 0.4, 0.0),
        Vector3::new(0.0, 0.0, 20.0),
        0.05,
        0.5,
        0.4,
        true,
    );
    wall_closed_form(
        Vector3::new(2.0, -0.3, 0.2),
        Vector3::new(4.0, 10.0, -6.0),
        0.02,
        0.4,
        -0.5,
        true,
    );
    // Sliding: a fast slip (spin against the motion), low μ.
    wall_closed_form(
        Vector3::new(1.0, 2.0, 0.0),
        Vector3::new(0.0, 0.0, 60.0),
        0.0,
        0.1,
        0.0,
        false,
    );
    wall_closed_form(
        Vector3::new(1.5, 1.0, 0.0),
        Vector3::new(0.0, 0.0, -80.0),
        0.08,
        0.2,
        0.6,
        false,
    );
    wall_closed_form(
        Vector3::new(1.0, 0.5, -1.5),
        Vector3::new(7.0, -30.0, 20.0),
        0.0,
        0.15,
        0.3,
        false,
    );
    // β = −1 sticks with no impulse: spin and tangential velocity kept.
    wall_closed_form(
        Vector3::new(1.0, 0.5, 0.0),
        Vector3::new(0.0, 0.0, 9.0),
        0.0,
        0.5,
        -1.0,
        true,
    );
}

/// μ = 0 is the frictionless law bit for bit, whatever β.
#[test]
fn zero_friction_is_the_frictionless_law() {
    let inverse = Matrix3::from_diagonal(&Vector3::new(2.0, 3.0, 5.0));
    let a = RigidBody::new(
        1.3,
        Vector3::new(1.0, 0.2, -0.4),
        Vector3::new(3.0, -1.0, 2.0),
        inverse,
    )
    .unwrap();
    let b = RigidBody::new(
        0.7,
        Vector3::new(-1.0, 0.5, 0.1),
        Vector3::new(0.0, 2.0, 1.0),
        inverse,
    )
    .unwrap();
    let contact = Contact::new(
        Vector3::new(0.3, 0.1, 0.2),
        Vector3::new(-0.2, 0.4, 0.0),
        Vector3::new(1.0, 0.2, 0.1),
    )
    .unwrap();
    let law = Law::from_restitution(0.7, 0.7).unwrap();
    let plain = law.resolve_rigid(&a, &b, &contact).unwrap();
    for beta in [-1.0, 0.0, 1.0] {
        let with = law
            .resolve_rigid_with_friction(&a, &b, &contact, &ImpactFriction::new(0.0, beta).unwrap())
            .unwrap();
        assert_eq!(with, plain);
    }
    assert_eq!(plain.tangential_impulse, Vector3::zeros());
    assert_eq!(plain.friction, FrictionRegime::None);
    assert_eq!(
        law.resolve_rigid_with_friction(&a, &b, &contact, &ImpactFriction::default())
            .unwrap(),
        plain
    );
}

fn expect_err<T: RealField + Copy>(mu: T, beta: T, parameter: &str) {
    match ImpactFriction::new(mu, beta) {
        Err(e @ LawError::InvalidFriction { parameter: p, .. }) => {
            assert_eq!(p, parameter);
            assert!(e.to_string().contains(parameter), "{e}");
        }
        other => panic!("μ {mu:?} β {beta:?}: {other:?}"),
    }
}

#[test]
fn bad_friction_parameters_are_typed_errors_naming_the_field() {
    expect_err(f64::NAN, 0.0, "impact_friction");
    expect_err(-0.1, 0.0, "impact_friction");
    expect_err(f64::INFINITY, 0.0, "impact_friction");
    expect_err(0.2, f64::NAN, "tangential_restitution");
    expect_err(0.2, 1.01, "tangential_restitution");
    expect_err(0.2_f32, -1.5, "tangential_restitution");
    for (mu, beta) in [(0.0, -1.0), (0.0, 1.0), (5.0, 0.0), (-0.0, 0.5)] {
        let f = ImpactFriction::new(mu, beta).unwrap();
        assert_eq!(
            (f.impact_friction(), f.tangential_restitution()),
            (mu, beta)
        );
    }
    let e = ImpactFriction::new(0.2, 2.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "tangential_restitution must be in [-1, 1], got 2"
    );
}

/// The throw table of `docs/friction.md`: the object ball's throw angle
/// the law gives (3D, f64) against TP A-14's closed form, for μ = 0.06
/// and cut angles 0–60°. `KIMPACT_BLESS=1 cargo test -p kimpact --test
/// friction` rewrites it.
#[test]
fn the_docs_throw_table_is_the_computed_one() {
    use std::fmt::Write as _;
    let mu = 0.06;
    let friction = ImpactFriction::new(mu, 0.0).unwrap();
    let inverse = Matrix3::identity() / sphere_inertia();
    let mut table = String::from(
        "| cut angle φ | throw θ, law | throw θ, TP A-14 | regime |\n| ---: | ---: | ---: | --- |\n",
    );
    for deg in (0..=60).step_by(5) {
        let phi = f64::to_radians(f64::from(deg));
        let n = Vector3::new(phi.cos(), phi.sin(), 0.0);
        let t = Vector3::new(-phi.sin(), phi.cos(), 0.0);
        let cue =
            RigidBody::new(M, Vector3::new(1.7, 0.0, 0.0), Vector3::zeros(), inverse).unwrap();
        let object = RigidBody::new(M, Vector3::zeros(), Vector3::zeros(), inverse).unwrap();
        let contact = Contact::new(n * R, -n * R, n).unwrap();
        let impact = Law::elastic()
            .resolve_rigid_with_friction(&cue, &object, &contact, &friction)
            .unwrap();
        let v = impact.delta_v_b;
        // (+ 0.0 turns the head-on −0 into 0.)
        let law = (-v.dot(&t)).atan2(v.dot(&n)).to_degrees() + 0.0;
        let a14 = mu.min(phi.tan() / 7.0).atan().to_degrees();
        let regime = match impact.friction {
            FrictionRegime::Stick => "stick",
            FrictionRegime::Slide => "slide",
            FrictionRegime::None => "none (head-on)",
            FrictionRegime::Limited => "limited",
        };
        let _ = writeln!(table, "| {deg}° | {law:.4}° | {a14:.4}° | {regime} |");
    }
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/friction.md");
    let doc = std::fs::read_to_string(&path).expect("docs/friction.md");
    let begin = "<!-- throw table: begin (generated by crates/kimpact/tests/friction.rs) -->\n";
    let end = "<!-- throw table: end -->";
    let start = doc.find(begin).expect("begin marker") + begin.len();
    let stop = start + doc[start..].find(end).expect("end marker");
    if std::env::var_os("KIMPACT_BLESS").is_some() {
        std::fs::write(&path, format!("{}{table}{}", &doc[..start], &doc[stop..])).unwrap();
        return;
    }
    assert!(
        doc[start..stop] == table,
        "docs/friction.md is stale: KIMPACT_BLESS=1 cargo test -p kimpact --test friction\n{table}"
    );
}
