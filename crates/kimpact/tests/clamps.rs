//! Clamp reporting: how much of the asked dissipation a clamped impact
//! could not take (`Impact::unmet_dissipation`, `Stats`), and the table of
//! effective restitution against impact angle that `LawParams::
//! from_restitution` and `docs/restitution.md` show, computed here from the
//! closed form and checked against the law's impacts.
//!
//! Regenerate both tables after a change of the law:
//!
//! ```text
//! KIMPACT_BLESS=1 cargo test -p kimpact --test clamps
//! ```

use std::fmt::Write as _;
use std::path::PathBuf;

use kimpact::nalgebra::{Vector2, Vector3};
use kimpact::{Body, CLAMP_TOLERANCE, FixedPartner, Law, LawParams, Mass, Stats};

/// `½ μ u²` for masses `m1`, `m2` and approach speed `u`.
fn normal_energy(m1: f64, m2: f64, u: f64) -> f64 {
    0.5 * m1 * m2 / (m1 + m2) * u * u
}

/// A law clamp: `e = 0` (`d̃ = 1/8`) between equal masses at 45° asks for
/// `q = (1 − 0²)(1 + tan²45°) = 2`, twice the normal energy. The unmet
/// share is `q − (1 − tol)`: `½ μ u² (1 + 10⁻⁶)` here.
#[test]
fn a_law_clamp_reports_the_closed_form_unmet_share() {
    let law = Law::from_restitution(0.0_f64, 0.0).unwrap();
    for &(m1, m2, speed) in &[(1.0, 1.0, 2.0), (0.17, 0.17, 7.5), (3e5, 3e5, 1e-2)] {
        let u = speed;
        // Relative velocity at 45° to the normal x: w = b − a = (−u, −u).
        let a = Body::new(m1, Vector2::new(u, u)).unwrap();
        let b = Body::new(m2, Vector2::zeros()).unwrap();
        let impact = law.resolve(&a, &b, &Vector2::x()).unwrap().unwrap();
        assert!(impact.clamped);
        let energy = normal_energy(m1, m2, u);
        let rho = 1.0 + 45f64.to_radians().tan().powi(2);
        let q = 2.0 * law.dissipation() * rho * 4.0;
        let expected = energy * (q - 1.0 + CLAMP_TOLERANCE);
        let err = (impact.unmet_dissipation - expected).abs() / expected;
        assert!(
            err < 1e-12,
            "unmet {} against {expected}",
            impact.unmet_dissipation
        );
        // Asked d = d̃ (m₁+m₂)|w|², used d, unmet: the three add up.
        let asked = law.dissipation() * (m1 + m2) * 2.0 * u * u;
        let sum = impact.dissipated + impact.unmet_dissipation;
        assert!(
            (sum - asked).abs() <= 1e-12 * asked,
            "{sum} against {asked}"
        );
        // A large share: about the normal energy itself.
        assert!(impact.unmet_dissipation > 0.99 * energy);
        // Restitution mode's view reports the same.
        let r = law
            .restitution(Mass::Finite(m1), Mass::Finite(m2), u, u)
            .unwrap()
            .unwrap();
        assert!(r.clamped);
        assert!((r.unmet_dissipation - impact.unmet_dissipation).abs() <= 1e-12 * expected);
    }
}

/// A rounding clamp: `e = 0` head-on along a normal off the axes, where
/// `ρ = (|w|/u)²` rounds a few ulps above 1. The unmet share is the clamp's
/// tolerance and those ulps, about 1e-6 of the normal energy.
#[test]
fn a_rounding_clamp_reports_a_tiny_unmet_share() {
    let law = Law::from_restitution(0.0_f64, 0.0).unwrap();
    let mut rounding_clamps = 0;
    for i in 0..400 {
        let phi = 0.013 + f64::from(i) * 0.0157;
        let n = Vector3::new(phi.cos(), phi.sin() * 0.6, phi.sin() * 0.8);
        let a = Body::new(1.0, n * 2.0).unwrap();
        let b = Body::new(1.0, Vector3::zeros()).unwrap();
        let impact = law.resolve(&a, &b, &n).unwrap().unwrap();
        let energy = normal_energy(1.0, 1.0, impact.approach_speed);
        if impact.clamped {
            rounding_clamps += 1;
            let share = impact.unmet_dissipation / energy;
            assert!(
                (CLAMP_TOLERANCE * (1.0 - 1e-9)..CLAMP_TOLERANCE + 1e-14).contains(&share),
                "share {share}"
            );
        } else {
            assert_eq!(impact.unmet_dissipation, 0.0);
        }
    }
    // Some of these head-on impacts do round over 1 (else the test would
    // check nothing).
    assert!(rounding_clamps > 10, "{rounding_clamps} rounding clamps");
}

/// A wall under `OwnMass`: `q = 2 d̃_w ρ`, unmet `½ m u² (q − 1 + tol)`.
/// A literal wall with `d̃ > 0`: unbounded, `+∞`, counted apart by `Stats`.
#[test]
fn walls_report_finite_or_unbounded_unmet_dissipation() {
    let law = Law::from_restitution(0.5_f64, 0.5).unwrap();
    let (m, u, deg) = (2.5, 3.0, 60.0_f64);
    let v = Vector2::new(u, u * deg.to_radians().tan());
    let a = Body::new(m, v).unwrap();
    let wall = Body::immovable(Vector2::zeros()).unwrap();
    let impact = law.resolve(&a, &wall, &Vector2::x()).unwrap().unwrap();
    let q = 2.0 * law.wall_dissipation() * (1.0 + deg.to_radians().tan().powi(2));
    assert!(q > 1.0 && impact.clamped);
    let expected = 0.5 * m * u * u * (q - 1.0 + CLAMP_TOLERANCE);
    assert!((impact.unmet_dissipation - expected).abs() <= 1e-12 * expected);

    let literal = Law::new(LawParams {
        dissipation: 0.01,
        fixed_partner: FixedPartner::Literal,
        ..Default::default()
    })
    .unwrap();
    let head_on = Body::new(m, Vector2::new(u, 0.0)).unwrap();
    let impact = literal
        .resolve(&head_on, &wall, &Vector2::x())
        .unwrap()
        .unwrap();
    assert!(impact.clamped);
    assert_eq!(impact.unmet_dissipation, f64::INFINITY);
    let elastic_literal = Law::new(LawParams {
        fixed_partner: FixedPartner::Literal,
        ..Default::default()
    })
    .unwrap();
    let impact = elastic_literal
        .resolve(&head_on, &wall, &Vector2::x())
        .unwrap()
        .unwrap();
    assert!(!impact.clamped);
    assert_eq!(impact.unmet_dissipation, 0.0);

    let mut stats = Stats::default();
    stats.record_unmet(expected);
    stats.record_unmet(f64::INFINITY);
    stats.record_unmet(0.0);
    stats.record_unmet(f64::NAN);
    stats.record_unmet(f64::MAX);
    stats.record_unmet(f64::MAX);
    assert_eq!(stats.unbounded_clamps, 1);
    assert!(stats.unmet_dissipation.is_finite());
    assert_eq!(stats.unmet_dissipation, f64::MAX);
}

/// A grazing impact whose `ρ = (|w|/u)²` overflows: `q` is infinite, the
/// impact is clamped, the unmet dissipation `+∞`, never NaN; f32 too.
#[test]
fn an_overflowing_ask_is_infinite_never_nan() {
    let law = Law::from_restitution(0.9_f64, 0.9).unwrap();
    let a = Body::new(1.0, Vector2::new(1e-200, 1e200)).unwrap();
    let b = Body::new(1.0, Vector2::zeros()).unwrap();
    let impact = law.resolve(&a, &b, &Vector2::x()).unwrap().unwrap();
    assert!(impact.clamped);
    assert_eq!(impact.unmet_dissipation, f64::INFINITY);

    let law = Law::from_restitution(0.9_f32, 0.9).unwrap();
    let a = Body::new(1.0_f32, Vector2::new(1e-30, 1e30)).unwrap();
    let b = Body::new(1.0_f32, Vector2::zeros()).unwrap();
    let impact = law.resolve(&a, &b, &Vector2::x()).unwrap().unwrap();
    assert!(impact.clamped);
    assert_eq!(impact.unmet_dissipation, f32::INFINITY);
    // A law clamp in f32: e = 0 at 45°, unmet ½ μ u² (2 − 1 + 10⁻⁶).
    let law = Law::from_restitution(0.0_f32, 0.0).unwrap();
    let a = Body::new(1.0_f32, Vector2::new(1.0, 1.0)).unwrap();
    let impact = law.resolve(&a, &b, &Vector2::x()).unwrap().unwrap();
    let expected = 0.25 * (1.0 + CLAMP_TOLERANCE);
    assert!((f64::from(impact.unmet_dissipation) - expected).abs() < 1e-6);
}

/// The impact angles of the table (none on a clamp's onset, where the
/// closed form and the law's rounding could fall on either side).
const ANGLES: [f64; 10] = [0.0, 10.0, 20.0, 25.0, 35.0, 45.0, 60.0, 63.0, 66.0, 80.0];
/// The reference restitutions of the table.
const COEFFICIENTS: [f64; 3] = [0.0, 0.5, 0.9];

/// The closed form for equal masses under `from_restitution(e, _)`:
/// `q = (1 − e²)(1 + tan²θ)`; `e_eff = sqrt(1 − q)` if `q ≤ 1`.
fn closed_form(e: f64, deg: f64) -> f64 {
    (1.0 - e * e) * (1.0 + deg.to_radians().tan().powi(2))
}

/// The cell for reference `e` at `deg`, checked against the law's impact
/// (measured restitution, clamp flag, unmet share).
fn cell(e: f64, deg: f64) -> String {
    let q = closed_form(e, deg);
    let law = Law::from_restitution(e, e).unwrap();
    let (s, c) = deg.to_radians().sin_cos();
    let a = Body::new(1.0, Vector2::new(c, s) * 1.7).unwrap();
    let b = Body::new(1.0, Vector2::zeros()).unwrap();
    let impact = law.resolve(&a, &b, &Vector2::x()).unwrap().unwrap();
    let u = impact.approach_speed;
    let measured = (impact.delta_v_b - impact.delta_v_a - Vector2::new(u, 0.0)).x / u;
    let energy = normal_energy(1.0, 1.0, u);
    if q <= 1.0 {
        assert!(!impact.clamped, "e {e} at {deg}°: clamped, q = {q}");
        assert!(
            (measured - (1.0 - q).sqrt()).abs() < 1e-7,
            "e {e} at {deg}°"
        );
        assert_eq!(impact.unmet_dissipation, 0.0);
        format!("{:.4}", (1.0 - q).sqrt())
    } else {
        assert!(impact.clamped, "e {e} at {deg}°: not clamped, q = {q}");
        assert!((measured - CLAMP_TOLERANCE.sqrt()).abs() < 1e-12);
        let share = impact.unmet_dissipation / energy;
        assert!((share - (q - 1.0 + CLAMP_TOLERANCE)).abs() < 1e-12 * q);
        format!("clamped, q = {q:.2}")
    }
}

/// The table, each line prefixed by `prefix`.
fn table(prefix: &str) -> String {
    let mut s = String::new();
    let _ = write!(s, "{prefix}| impact angle θ |");
    for e in COEFFICIENTS {
        let _ = write!(s, " e = {e} |");
    }
    let _ = writeln!(s);
    let _ = write!(s, "{prefix}| ---: |");
    for _ in COEFFICIENTS {
        let _ = write!(s, " ---: |");
    }
    let _ = writeln!(s);
    for deg in ANGLES {
        let _ = write!(s, "{prefix}| {deg}° |");
        for e in COEFFICIENTS {
            let _ = write!(s, " {} |", cell(e, deg));
        }
        let _ = writeln!(s);
    }
    let _ = write!(s, "{prefix}| clamps beyond |");
    for e in COEFFICIENTS {
        let _ = write!(s, " {:.1}° |", e.asin().to_degrees());
    }
    let _ = writeln!(s);
    s
}

/// Replace (bless) or check the text between `begin` and `end` in `file`.
fn check_block(file: &str, begin: &str, end: &str, block: &str) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(file);
    let text = std::fs::read_to_string(&path).expect("the file");
    let start = text.find(begin).expect("the begin marker") + begin.len();
    let stop = start + text[start..].find(end).expect("the end marker");
    if std::env::var_os("KIMPACT_BLESS").is_some() {
        let new = format!("{}{block}{}", &text[..start], &text[stop..]);
        std::fs::write(&path, new).expect("write");
        return;
    }
    assert!(
        text[start..stop] == *block,
        "{file} is stale: KIMPACT_BLESS=1 cargo test -p kimpact --test clamps\n{block}"
    );
}

/// `docs/restitution.md` and the rustdoc of `LawParams::from_restitution`
/// hold the table computed here.
#[test]
fn the_angle_tables_are_the_computed_ones() {
    check_block(
        "../../docs/restitution.md",
        "<!-- angle table: begin (generated by crates/kimpact/tests/clamps.rs) -->\n",
        "<!-- angle table: end -->",
        &table(""),
    );
    check_block(
        "src/params.rs",
        "    // table: begin (generated by crates/kimpact/tests/clamps.rs)\n",
        "    // table: end",
        &table("    /// "),
    );
}
