//! The law chosen from restitution coefficients
//! (`LawParams::from_restitution`): the two reference impacts it names (two
//! equal masses head-on; head-on against a fixed wall) resolve back to the
//! coefficients asked for, bad coefficients are typed errors, every other
//! impact follows the closed form of its docs, and the table of
//! `docs/restitution.md` is the one this file computes.
//!
//! Regenerate the table after a change of the law:
//!
//! ```text
//! KIMPACT_BLESS=1 cargo test -p kimpact --test restitution
//! ```

use std::fmt::Write as _;
use std::path::PathBuf;

use kimpact::nalgebra::{RealField, SVector, Vector2, Vector3};
use kimpact::{Body, CLAMP_TOLERANCE, FixedPartner, Law, LawError, LawParams};

/// Coefficients from plastic to elastic, with the ends and values near them.
const COEFFICIENTS: [f64; 11] = [
    0.0, 0.05, 0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.99, 0.999_999, 1.0,
];

/// `x` as an f64.
fn real<T: RealField + Copy>(x: T) -> f64 {
    let y: Option<f64> = x.to_subset();
    y.expect("a real number")
}

/// The measured restitution of `a` (moving) hitting `b` along `n`:
/// normal separation speed after over normal approach speed before, from the
/// velocities after the impact (not from the impact's own `restitution`).
fn measured<T: RealField + Copy, const D: usize>(
    law: &Law<T>,
    a: &Body<T, D>,
    b: &Body<T, D>,
    n: &SVector<T, D>,
) -> (T, kimpact::Impact<T, D>) {
    let impact = law
        .resolve(a, b, n)
        .expect("valid normal")
        .expect("approaching");
    let n = n.normalize();
    let u = -(b.velocity() - a.velocity()).dot(&n);
    let after = (b.velocity() + impact.delta_v_b) - (a.velocity() + impact.delta_v_a);
    (after.dot(&n) / u, impact)
}

/// The two reference impacts, in f64 and f32, for masses and speeds over
/// many orders of magnitude, each e of `COEFFICIENTS`: equal masses head-on
/// along an axis, and head-on against an immovable body. Returns the worst
/// error of the measured e for each.
fn reference_errors<T: RealField + Copy>(tol: f64) -> (f64, f64) {
    let c = |x: f64| T::from_subset(&x);
    let (mut worst_ball, mut worst_wall) = (0.0_f64, 0.0_f64);
    for (i, &e) in COEFFICIENTS.iter().enumerate() {
        // The wall's coefficient is from the other end of the list, so that
        // a swap of the two would be seen.
        let e_wall = COEFFICIENTS[COEFFICIENTS.len() - 1 - i];
        let law = Law::from_restitution(c(e), c(e_wall)).expect("e in [0, 1]");
        assert_eq!(
            law,
            Law::new(LawParams::from_restitution(c(e), c(e_wall)).unwrap()).unwrap()
        );
        assert_eq!(law.fixed_partner(), FixedPartner::OwnMass);
        for &mass in &[1.0, 0.17, 3.0e5, 1.0e-9] {
            for &speed in &[2.0, 1.0e-3, 1.0e4] {
                let v = Vector3::new(c(speed), c(0.0), c(0.0));
                let a = Body::new(c(mass), v).unwrap();
                let b = Body::new(c(mass), Vector3::zeros()).unwrap();
                let (got, impact) = measured(&law, &a, &b, &Vector3::x());
                let err = real((got - c(e)).abs());
                assert!(
                    err <= tol,
                    "equal masses {mass} at {speed}, e = {e}: measured {got:?}"
                );
                assert!(!impact.clamped, "e = {e} is not a clamped impact");
                // The textbook outcome of equal masses: the striker keeps
                // (1 − e)/2 of its speed, the struck ball takes (1 + e)/2.
                let va = real((v + impact.delta_v_a).x) / speed;
                let vb = real(impact.delta_v_b.x) / speed;
                assert!((va - (1.0 - e) / 2.0).abs() <= tol, "striker {va}, e = {e}");
                assert!((vb - (1.0 + e) / 2.0).abs() <= tol, "struck {vb}, e = {e}");
                worst_ball = worst_ball.max(err);

                // Head-on into a wall, from either side of the pair.
                let wall = Body::immovable(Vector3::zeros()).unwrap();
                let (got, impact) = measured(&law, &a, &wall, &Vector3::x());
                let (got_rev, _) = measured(&law, &wall, &a, &(-Vector3::x()));
                for g in [got, got_rev] {
                    let err = real((g - c(e_wall)).abs());
                    assert!(
                        err <= tol,
                        "wall, mass {mass} at {speed}, e = {e_wall}: measured {g:?}"
                    );
                    worst_wall = worst_wall.max(err);
                }
                assert!(!impact.clamped);
                let back = real((v + impact.delta_v_a).x) / speed;
                assert!((back + e_wall).abs() <= tol, "rebound {back}, e = {e_wall}");
            }
        }
    }
    (worst_ball, worst_wall)
}

#[test]
fn the_reference_impacts_give_the_coefficients_back_f64() {
    let (ball, wall) = reference_errors::<f64>(1e-12);
    println!("f64: worst error of e, equal masses {ball:.3e}, wall {wall:.3e}");
}

#[test]
fn the_reference_impacts_give_the_coefficients_back_f32() {
    let (ball, wall) = reference_errors::<f32>(1e-5);
    println!("f32: worst error of e, equal masses {ball:.3e}, wall {wall:.3e}");
}

/// The same reference impacts along normals that are not an axis (2D and
/// 3D, normals of any length): rounding in `u` and `ρ = (|w|/u)²` is a few
/// ulps, so every coefficient but 0 comes back to the same tolerance. At
/// `e = 0` the law sits on its clamp (`q = 1`): `q` a few ulps below 1 gives
/// `e = sqrt(1 − q)`, about `sqrt(ε)` (3.5e-4 in f32), a few ulps above it
/// the clamp's `sqrt(1e-6) = 1e-3`: never more, as the docs of
/// `from_restitution` say.
#[test]
fn oblique_head_on_impacts_give_the_coefficients_back() {
    let normals3 = [
        Vector3::new(1.0, 2.0, -3.0),
        Vector3::new(-0.3, 0.1, 0.7),
        Vector3::new(1e-7, 5e-8, 2e-7),
    ];
    let normals2 = [Vector2::new(0.6, -0.8), Vector2::new(-3.0, 7.0)];
    for &e in &COEFFICIENTS {
        let law = Law::from_restitution(e, e).unwrap();
        let law32 = Law::from_restitution(e as f32, e as f32).unwrap();
        let check = |got: f64, tol: f64, what: &str| {
            if e == 0.0 {
                assert!(
                    (-tol..=CLAMP_TOLERANCE.sqrt() + tol).contains(&got),
                    "{what}, e = 0: {got}"
                );
            } else {
                assert!((got - e).abs() <= tol, "{what}, e = {e}: {got}");
            }
        };
        for n in &normals3 {
            let v = -n.normalize() * 1.7;
            let a = Body::new(0.4, v).unwrap();
            let b = Body::new(0.4, Vector3::zeros()).unwrap();
            check(measured(&law, &b, &a, n).0, 1e-12, "3D equal masses");
            let wall = Body::immovable(Vector3::zeros()).unwrap();
            check(measured(&law, &wall, &a, n).0, 1e-12, "3D wall");
            let n32 = n.cast::<f32>();
            let a32 = Body::new(0.4_f32, v.cast::<f32>()).unwrap();
            let b32 = Body::new(0.4_f32, Vector3::zeros()).unwrap();
            check(
                f64::from(measured(&law32, &b32, &a32, &n32).0),
                1e-5,
                "3D equal masses f32",
            );
        }
        for n in &normals2 {
            let v = n.normalize() * 0.25;
            let a = Body::new(5.0, v).unwrap();
            let b = Body::new(5.0, Vector2::zeros()).unwrap();
            check(measured(&law, &a, &b, n).0, 1e-12, "2D equal masses");
            let wall = Body::immovable(Vector2::zeros()).unwrap();
            check(measured(&law, &a, &wall, n).0, 1e-12, "2D wall");
        }
    }
}

/// Near `e = 0` the law's `e = sqrt(1 − q)` magnifies the rounding of `q`
/// (a few ulps, `ε`) into `δe ≈ δq / (2e)`: a coefficient `e` comes back
/// within `2ε/e` (f64), which exceeds 1e-12 only below `e ≈ 4e-4`. The
/// bound of the docs of `from_restitution`, pinned.
#[test]
fn small_coefficients_come_back_within_their_conditioning() {
    for &e in &[1e-2, 1e-3, 1e-4, 1e-6] {
        let law = Law::from_restitution(e, e).unwrap();
        let a = Body::new(1.0, Vector3::new(2.0, 0.0, 0.0)).unwrap();
        let b = Body::new(1.0, Vector3::zeros()).unwrap();
        let wall = Body::immovable(Vector3::zeros()).unwrap();
        for partner in [b, wall] {
            let (got, impact) = measured(&law, &a, &partner, &Vector3::x());
            assert!(!impact.clamped);
            let bound = 2.0 * f64::EPSILON / e;
            assert!((got - e).abs() <= bound, "e = {e}: {got}, bound {bound:e}");
        }
    }
}

#[test]
fn coefficients_outside_zero_one_are_typed_errors() {
    for bad in [
        -0.1,
        -1e-300,
        1.0 + f64::EPSILON,
        1.5,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        for (params, name) in [
            (LawParams::from_restitution(bad, 0.5), "ball_restitution"),
            (LawParams::from_restitution(0.5, bad), "wall_restitution"),
        ] {
            match params {
                Err(LawError::InvalidRestitution { parameter, value }) => {
                    assert_eq!(parameter, name);
                    assert!(value.is_nan() && bad.is_nan() || value == bad);
                }
                other => panic!("{name} = {bad}: {other:?}"),
            }
        }
        assert!(matches!(
            Law::from_restitution(0.5, bad),
            Err(LawError::InvalidRestitution {
                parameter: "wall_restitution",
                ..
            })
        ));
        // In f32, −1e-300 rounds to −0 and 1 + ε(f64) to 1: both valid.
        let bad32 = bad as f32;
        if !(0.0..=1.0).contains(&bad32) {
            assert!(matches!(
                Law::from_restitution(bad32, 0.5),
                Err(LawError::InvalidRestitution {
                    parameter: "ball_restitution",
                    ..
                })
            ));
        }
    }
    // Both bad: the first is named.
    let err = LawParams::from_restitution(2.0, -1.0).unwrap_err();
    assert_eq!(err.to_string(), "ball_restitution must be in [0, 1], got 2");
    // The ends are valid, −0 included.
    for e in [0.0, -0.0, 1.0] {
        assert!(LawParams::from_restitution(e, e).is_ok(), "{e}");
    }
}

/// The closed form of the docs, `e = sqrt(1 − (1 − e_b²)(r + 2 + 1/r) /
/// (4 cos²θ))` between finite masses and `sqrt(1 − (1 − e_w²)/cos²θ)`
/// against a wall, clamped where negative, against the law's impacts.
#[test]
fn other_impacts_follow_the_documented_closed_form() {
    for &e in &[0.2, 0.8, 0.95, 0.999] {
        let e_wall = 0.9;
        let law = Law::from_restitution(e, e_wall).unwrap();
        for &ratio in &[1.0, 1.7, 2.0, 10.0, 1000.0] {
            for &deg in &[0.0, 10.0, 30.0, 60.0, 80.0] {
                let (got, clamped) = oblique(&law, ratio, deg, false);
                let c2 = deg.to_radians().cos().powi(2);
                let q = (1.0 - e * e) * (ratio + 2.0 + 1.0 / ratio) / (4.0 * c2);
                check_closed_form(got, clamped, q, &format!("e {e}, 1:{ratio}, {deg}°"));
                let (got, clamped) = oblique(&law, ratio, deg, true);
                let q = (1.0 - e_wall * e_wall) / c2;
                check_closed_form(got, clamped, q, &format!("wall, mass {ratio}, {deg}°"));
            }
        }
    }
}

fn check_closed_form(got: f64, clamped: bool, q: f64, what: &str) {
    if q <= 1.0 {
        assert!(!clamped, "{what}: clamped at q = {q}");
        assert!(
            (got - (1.0 - q).sqrt()).abs() < 1e-9,
            "{what}: {got}, q = {q}"
        );
    } else {
        assert!(clamped, "{what}: not clamped at q = {q}");
        assert!(
            (got - CLAMP_TOLERANCE.sqrt()).abs() < 1e-12,
            "{what}: {got}"
        );
    }
}

/// Masses 1 and `ratio` (the heavier one struck, at rest), relative
/// velocity at `deg` degrees to the normal, or a body of mass `ratio`
/// against a wall: the measured restitution and whether it was clamped.
fn oblique(law: &Law<f64>, ratio: f64, deg: f64, wall: bool) -> (f64, bool) {
    let (s, c) = deg.to_radians().sin_cos();
    let v = Vector3::new(c, s, 0.0) * 1.3;
    let (a, b) = if wall {
        (
            Body::new(ratio, v).unwrap(),
            Body::immovable(Vector3::zeros()).unwrap(),
        )
    } else {
        (
            Body::new(1.0, v).unwrap(),
            Body::new(ratio, Vector3::zeros()).unwrap(),
        )
    };
    let (e, impact) = measured(law, &a, &b, &Vector3::x());
    (e, impact.clamped)
}

const BALL_COEFFICIENTS: [f64; 5] = [0.999, 0.99, 0.95, 0.8, 0.5];
const RATIOS: [f64; 4] = [1.0, 2.0, 10.0, 1000.0];
const ANGLES: [f64; 4] = [0.0, 30.0, 60.0, 80.0];

fn cell(law: &Law<f64>, ratio: f64, deg: f64, wall: bool) -> String {
    let (e, clamped) = oblique(law, ratio, deg, wall);
    if clamped {
        "clamped".to_owned()
    } else {
        format!("{e:.4}")
    }
}

/// The tables of `docs/restitution.md`, from the law's impacts.
fn tables() -> String {
    let mut s = String::new();
    let header = |s: &mut String, first: &str| {
        let _ = write!(s, "| {first} |");
        for deg in ANGLES {
            let _ = write!(s, " {deg}° |");
        }
        let _ = writeln!(s);
        let _ = write!(s, "| --- |");
        for _ in ANGLES {
            let _ = write!(s, " ---: |");
        }
        let _ = writeln!(s);
    };
    for e in BALL_COEFFICIENTS {
        let law = Law::from_restitution(e, e).unwrap();
        let _ = writeln!(
            s,
            "**ball_e = {e}** (d̃ = {:.6}): e between two balls of masses 1 and r, over the angle between the relative velocity and the normal\n",
            law.dissipation()
        );
        header(&mut s, "r");
        for r in RATIOS {
            let _ = write!(s, "| {r} |");
            for deg in ANGLES {
                let _ = write!(s, " {} |", cell(&law, r, deg, false));
            }
            let _ = writeln!(s);
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(
        s,
        "**Against a wall** (`FixedPartner::OwnMass`, any mass): e over the angle, for each wall_e"
    );
    let _ = writeln!(s);
    header(&mut s, "wall_e");
    for e in BALL_COEFFICIENTS {
        let law = Law::from_restitution(e, e).unwrap();
        let _ = write!(s, "| {e} (d̃_w = {:.6}) |", law.wall_dissipation());
        for deg in ANGLES {
            let _ = write!(s, " {} |", cell(&law, 1.0, deg, true));
        }
        let _ = writeln!(s);
    }
    s
}

const BEGIN: &str = "<!-- table: begin (generated by crates/kimpact/tests/restitution.rs) -->\n";
const END: &str = "<!-- table: end -->";

/// `docs/restitution.md` holds exactly the tables computed here between its
/// markers; `KIMPACT_BLESS=1` rewrites them instead.
#[test]
fn the_docs_table_is_the_computed_one() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/restitution.md");
    let doc = std::fs::read_to_string(&path).expect("docs/restitution.md");
    let start = doc.find(BEGIN).expect("the begin marker") + BEGIN.len();
    let end = start + doc[start..].find(END).expect("the end marker");
    let table = tables();
    if std::env::var_os("KIMPACT_BLESS").is_some() {
        let new = format!("{}{table}{}", &doc[..start], &doc[end..]);
        std::fs::write(&path, new).expect("write docs/restitution.md");
        return;
    }
    assert!(
        doc[start..end] == table,
        "docs/restitution.md is stale: KIMPACT_BLESS=1 cargo test -p kimpact --test restitution\n{table}"
    );
}
