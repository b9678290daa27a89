//! Fuzz target `law`: the public API of the core crate (`kimpact`) fed raw
//! floats — NaN, ±∞, ±0, subnormals, the extremes of the type and ordinary
//! values — in f32 and f64, 2D and 3D.
//!
//! The first byte picks the variant; every float is then decoded from the
//! input by [`Float::decode`] (raw bits, a table of special values, a
//! moderate `±(1 + f)·2^e` or a small integer), so that both the checked
//! rejections and the arithmetic of valid impacts are explored.
//!
//! Asserted (a panic is a finding), beyond "no panic":
//!
//! - `LawParams` → `Law::new`/`set_params`: `Ok` exactly when `dissipation`
//!   and `wall_dissipation` are finite and `>= 0`, else the
//!   `InvalidDissipation` error naming the parameter; `set_params` leaves the
//!   law unchanged on error; `params()` round-trips.
//! - `Body::new`, `Body::immovable`, `Mass::finite`: `Ok` exactly when the
//!   mass is finite and `> 0` and every velocity component is finite, else
//!   the error naming the first bad quantity.
//! - `Law::resolve`: `NonFiniteNormal`/`ZeroNormal` exactly for a non-finite
//!   or zero normal; `None` exactly when both bodies are immovable, the
//!   approach speed `u` is not positive and finite, or `u (1 + e)`
//!   overflows (`u > max/2`, documented); equal to
//!   `resolve_unit` with the unit normal, and mirror-symmetric (`b, a, −n`).
//! - Every `Impact`: no NaN anywhere; `e ∈ [0, 1]`, `e = 1e-3` when clamped,
//!   `e = 1` for `d̃ = 0`, clamped for a literal wall with `d̃ > 0`; the
//!   immovable partner's `Δv` is zero; velocities, `u`, `e`, the impulse,
//!   `d` and the energies are finite whenever their exact values are
//!   representable with headroom.
//! - Where the mass ratio is a normal number of the type (the documented
//!   domain, "ratios the type can hold"): momentum conserved to the property
//!   tests' tolerance (1e-12 f64, 1e-5 f32, relative), kinetic energy never
//!   rises beyond `32 ε` relative, the normal relative velocity changes by
//!   at least `u (1 − 8 ε)`, and `e² = 1 − q` for the note's
//!   `q = 2 d̃ (|w|/u)² (m₁+m₂)²/(m₁m₂)` computed independently in f64 where
//!   that is well conditioned. Underflow to subnormal results is allowed an
//!   absolute error of a few smallest subnormals.
//! - `Law::restitution`: the errors in their documented order, `None` for
//!   `u <= 0` or two immovable masses, `e ∈ [0, 1]`.
#![no_main]
// `ensure!(a <= b)` fails on NaN as it should: `!(a <= b)` is meant.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[path = "law/float.rs"]
mod float;

use arbitrary::{Result, Unstructured};
use kimpact::nalgebra::SVector;
use kimpact::{Body, FixedPartner, Impact, Law, LawError, LawParams, Mass, Which};
use libfuzzer_sys::fuzz_target;

use float::{Float, exponent_to_unit, norm, norm_squared, times_pow2, to64, unit, vector};

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    // Running out of input is fine: it just ends the case.
    let _ = match u.int_in_range(0u8..=3) {
        Ok(0) => case::<f32, 2>(&mut u),
        Ok(1) => case::<f32, 3>(&mut u),
        Ok(2) => case::<f64, 2>(&mut u),
        Ok(_) => case::<f64, 3>(&mut u),
        Err(e) => Err(e),
    };
});

fn valid_dissipation<T: Float>(x: T) -> bool {
    x.is_finite() && x >= T::zero()
}

/// `a == b` as f64, treating NaN as equal to NaN (error payloads).
fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

fn params<T: Float>(u: &mut Unstructured<'_>) -> Result<LawParams<T>> {
    let dissipation = T::decode(u)?;
    let wall_dissipation = if u.arbitrary()? {
        Some(T::decode(u)?)
    } else {
        None
    };
    let fixed_partner = if u.arbitrary()? {
        FixedPartner::Literal
    } else {
        FixedPartner::OwnMass
    };
    Ok(LawParams {
        dissipation,
        wall_dissipation,
        fixed_partner,
    })
}

/// `Law::new` accepts exactly the valid parameters.
fn law<T: Float>(p: LawParams<T>) -> Option<Law<T>> {
    let result = Law::new(p);
    let bad = if !valid_dissipation(p.dissipation) {
        Some(("dissipation", p.dissipation))
    } else {
        p.wall_dissipation
            .filter(|w| !valid_dissipation(*w))
            .map(|w| ("wall_dissipation", w))
    };
    match (result, bad) {
        (Ok(law), None) => {
            assert_eq!(law.params(), p, "params() must round-trip");
            assert_eq!(law.dissipation(), p.dissipation);
            assert_eq!(
                law.wall_dissipation(),
                p.wall_dissipation.unwrap_or(p.dissipation)
            );
            assert_eq!(law.fixed_partner(), p.fixed_partner);
            assert_eq!(Law::try_from(p), Ok(law));
            Some(law)
        }
        (Err(e), Some((name, value))) => {
            match &e {
                LawError::InvalidDissipation {
                    parameter,
                    value: v,
                } => {
                    assert_eq!(*parameter, name, "{e}");
                    assert!(same(*v, value.to64()), "{e} for {value:?}");
                }
                other => panic!("Law::new({p:?}): wrong error {other:?}"),
            }
            assert!(!e.to_string().is_empty());
            None
        }
        (Ok(law), Some(bad)) => panic!("Law::new({p:?}) accepted invalid {bad:?}: {law:?}"),
        (Err(e), None) => panic!("Law::new({p:?}) rejected valid parameters: {e}"),
    }
}

/// A body: finite mass or immovable, built through the checked constructors.
fn body<T: Float, const D: usize>(u: &mut Unstructured<'_>) -> Result<Option<Body<T, D>>> {
    let immovable = u.ratio(1u8, 4)?;
    let mass = T::decode(u)?;
    let velocity = vector::<T, D>(u)?;
    let bad_velocity = velocity.iter().position(|c| !c.is_finite());
    let check_velocity_error = |e: &LawError, component: usize| match e {
        LawError::NonFiniteVelocity {
            which: Which::Body,
            component: c,
            value,
        } => {
            assert_eq!(*c, component, "{e}");
            assert!(same(*value, velocity[component].to64()), "{e}");
        }
        other => panic!("velocity {velocity:?}: wrong error {other:?}"),
    };
    if immovable {
        let result = Body::immovable(velocity);
        return Ok(match (result, bad_velocity) {
            (Ok(b), None) => {
                assert_eq!(b.mass(), Mass::Infinite);
                assert_eq!(b.velocity(), &velocity);
                assert_eq!(b.kinetic_energy(), T::zero());
                Some(b)
            }
            (Err(e), Some(c)) => {
                check_velocity_error(&e, c);
                None
            }
            (r, _) => panic!("Body::immovable({velocity:?}) = {r:?}"),
        });
    }
    let mass_error = if !mass.is_finite() {
        Some("NonFiniteMass")
    } else if mass <= T::zero() {
        Some("NonPositiveMass")
    } else {
        None
    };
    let check_mass_error = |e: &LawError, kind: &str, which: Which| match (e, kind) {
        (LawError::NonFiniteMass { which: w, value }, "NonFiniteMass")
        | (LawError::NonPositiveMass { which: w, value }, "NonPositiveMass") => {
            assert_eq!(*w, which, "{e}");
            assert!(same(*value, mass.to64()), "{e}");
            assert!(!e.to_string().is_empty());
        }
        _ => panic!("mass {mass:?}: wrong error {e:?}, expected {kind}"),
    };
    match (Mass::finite(mass), mass_error) {
        (Ok(m), None) => assert_eq!(m, Mass::Finite(mass)),
        (Err(e), Some(kind)) => check_mass_error(&e, kind, Which::Body),
        (r, _) => panic!("Mass::finite({mass:?}) = {r:?}"),
    }
    let result = Body::new(mass, velocity);
    Ok(match (result, mass_error, bad_velocity) {
        (Ok(b), None, None) => {
            assert_eq!(b.mass(), Mass::Finite(mass));
            assert_eq!(b.velocity(), &velocity);
            Some(b)
        }
        (Err(e), Some(kind), _) => {
            check_mass_error(&e, kind, Which::Body);
            None
        }
        (Err(e), None, Some(c)) => {
            check_velocity_error(&e, c);
            None
        }
        (r, m, v) => panic!("Body::new({mass:?}, {velocity:?}) = {r:?} ({m:?}, {v:?})"),
    })
}

fn mass64<T: Float>(m: Mass<T>) -> Option<f64> {
    match m {
        Mass::Finite(m) => Some(m.to64()),
        Mass::Infinite => None,
    }
}

fn field_values<T: Float, const D: usize>(i: &Impact<T, D>) -> Vec<(&'static str, T)> {
    let mut out = vec![
        ("approach_speed", i.approach_speed),
        ("impulse", i.impulse),
        ("restitution", i.restitution),
        ("dissipated", i.dissipated),
    ];
    out.extend(i.normal.iter().map(|x| ("normal", *x)));
    out.extend(i.delta_v_a.iter().map(|x| ("delta_v_a", *x)));
    out.extend(i.delta_v_b.iter().map(|x| ("delta_v_b", *x)));
    out
}

fn case<T: Float, const D: usize>(u: &mut Unstructured<'_>) -> Result<()> {
    let p = params::<T>(u)?;
    let p2 = params::<T>(u)?;
    let normal = vector::<T, D>(u)?;
    let a = body::<T, D>(u)?;
    let b = body::<T, D>(u)?;
    let approach = T::decode(u)?;
    let tangential = T::decode(u)?;

    let first = law(p);
    let second = law(p2);
    let mut law = first.unwrap_or_else(Law::elastic);
    // set_params: all or nothing.
    let before = law;
    match (law.set_params(p2), second) {
        (Ok(()), Some(expected)) => assert_eq!(law, expected),
        (Err(_), None) => assert_eq!(law, before, "set_params changed the law on error"),
        (r, s) => panic!("set_params({p2:?}) = {r:?}, Law::new = {s:?}"),
    }
    if u.arbitrary()? {
        law = before;
    }

    if let (Some(a), Some(b)) = (a, b) {
        restitution(&law, a.mass(), b.mass(), approach, tangential);
        resolve(&law, &a, &b, &normal);
    } else {
        // Invalid masses must be reported by `restitution` too, naming the body.
        restitution(
            &law,
            Mass::Finite(approach),
            Mass::Infinite,
            T::one(),
            T::zero(),
        );
    }
    Ok(())
}

fn restitution<T: Float>(law: &Law<T>, a: Mass<T>, b: Mass<T>, approach: T, tangential: T) {
    let bad_mass = |m: Mass<T>| match m {
        Mass::Finite(x) => !(x.is_finite() && x > T::zero()),
        Mass::Infinite => false,
    };
    let r = law.restitution(a, b, approach, tangential);
    let expected_error = if bad_mass(a) {
        Some("first")
    } else if bad_mass(b) {
        Some("second")
    } else if !approach.is_finite() {
        Some("approach_speed")
    } else if !(tangential.is_finite() && tangential >= T::zero()) {
        Some("tangential_speed")
    } else {
        None
    };
    match (r, expected_error) {
        (Err(e), Some(what)) => {
            let ok = match &e {
                LawError::NonFiniteMass { which, .. } | LawError::NonPositiveMass { which, .. } => {
                    (what, *which) == ("first", Which::First)
                        || (what, *which) == ("second", Which::Second)
                }
                LawError::InvalidSpeed { quantity, .. } => *quantity == what,
                _ => false,
            };
            assert!(ok, "restitution: expected a {what} error, got {e:?}");
            assert!(!e.to_string().is_empty());
        }
        (Ok(None), None) => assert!(
            approach <= T::zero() || (a.is_infinite() && b.is_infinite()),
            "restitution: None for u = {approach:?}"
        ),
        (Ok(Some(r)), None) => {
            assert!(approach > T::zero());
            let e = r.coefficient.to64();
            assert!((0.0..=1.0).contains(&e), "restitution e = {e}");
            if r.clamped {
                assert!((e - 1e-3).abs() < 1e-6, "clamped e = {e}");
            }
            let wall = a.is_infinite() || b.is_infinite();
            let d = if wall && law.fixed_partner() == FixedPartner::OwnMass {
                law.wall_dissipation()
            } else {
                law.dissipation()
            };
            if d == T::zero() {
                assert!(e == 1.0 && !r.clamped, "d̃ = 0 but e = {e}");
            } else if wall && law.fixed_partner() == FixedPartner::Literal {
                assert!(r.clamped, "literal wall with d̃ > 0 not clamped");
            }
        }
        (r, expected) => panic!(
            "restitution({a:?}, {b:?}, {approach:?}, {tangential:?}) = {r:?}, expected error {expected:?}"
        ),
    }
}

fn resolve<T: Float, const D: usize>(
    law: &Law<T>,
    a: &Body<T, D>,
    b: &Body<T, D>,
    normal: &SVector<T, D>,
) {
    let result = law.resolve(a, b, normal);
    if let Some(c) = normal.iter().position(|x| !x.is_finite()) {
        match result {
            Err(LawError::NonFiniteNormal { component, value }) => {
                assert_eq!(component, c);
                assert!(same(value, normal[c].to64()));
            }
            r => panic!("non-finite normal {normal:?}: {r:?}"),
        }
        return;
    }
    if normal.iter().all(|x| *x == T::zero()) {
        assert_eq!(result, Err(LawError::ZeroNormal));
        return;
    }
    let result = result.unwrap_or_else(|e| panic!("valid normal {normal:?} rejected: {e}"));
    let n = unit(normal);
    let unit_result = law.resolve_unit(a, b, &n);
    assert!(
        same_impact(&result, &unit_result),
        "resolve {result:?} != resolve_unit {unit_result:?}"
    );
    // Mirror: b, a, −n gives the same impact with the roles swapped.
    let mirror = law.resolve(b, a, &-normal).expect("valid normal");
    let swapped = result.map(|i| Impact {
        normal: -i.normal,
        delta_v_a: i.delta_v_b,
        delta_v_b: i.delta_v_a,
        ..i
    });
    assert!(
        same_impact(&mirror, &swapped),
        "mirror {mirror:?} != swapped {swapped:?}"
    );

    let w = b.velocity() - a.velocity();
    let approach = -w.dot(&n);
    let both_immovable = a.mass().is_infinite() && b.mass().is_infinite();
    let Some(i) = result else {
        // Also None when s = u (1 + e) <= 2u overflows (documented).
        assert!(
            both_immovable
                || !(approach > T::zero() && approach.is_finite())
                || approach.to64() > T::MAX / 2.0,
            "None for approaching pair, u = {approach:?}"
        );
        return;
    };
    assert!(!both_immovable, "impact between two immovable bodies");
    check_impact(law, a, b, &i);
}

fn same_impact<T: Float, const D: usize>(
    x: &Option<Impact<T, D>>,
    y: &Option<Impact<T, D>>,
) -> bool {
    match (x, y) {
        (None, None) => true,
        (Some(x), Some(y)) => {
            x.clamped == y.clamped
                && field_values(x)
                    .iter()
                    .zip(field_values(y))
                    .all(|((_, p), (_, q))| *p == q || p.bits() == q.bits())
        }
        _ => false,
    }
}

fn check_impact<T: Float, const D: usize>(
    law: &Law<T>,
    a: &Body<T, D>,
    b: &Body<T, D>,
    i: &Impact<T, D>,
) {
    // Failures name the law and the bodies.
    macro_rules! ensure {
        ($cond:expr, $($arg:tt)+) => {
            if !$cond {
                panic!("{}\n  law {law:?}\n  a {a:?}\n  b {b:?}", format!($($arg)+))
            }
        };
    }
    // Never NaN.
    for (name, x) in field_values(i) {
        ensure!(!x.to64().is_nan(), "{name} is NaN in {i:?}");
    }
    let eps = T::EPS;
    let n = to64(&i.normal);
    ensure!(
        (norm(&n) - 1.0).abs() <= 4.0 * eps,
        "normal not unit: {n:?}"
    );
    let u = i.approach_speed.to64();
    ensure!(u > 0.0 && u.is_finite(), "u = {u}");
    let e = i.restitution.to64();
    ensure!((0.0..=1.0).contains(&e), "e = {e}");
    if i.clamped {
        ensure!((e - 1e-3).abs() < 1e-6, "clamped e = {e}");
    }
    let (ma, mb) = (mass64(a.mass()), mass64(b.mass()));
    let wall = ma.is_none() || mb.is_none();
    let literal = law.fixed_partner() == FixedPartner::Literal;
    let d = if wall && !literal {
        law.wall_dissipation()
    } else {
        law.dissipation()
    };
    if d == T::zero() {
        ensure!(
            e == 1.0 && !i.clamped,
            "d̃ = 0 but e = {e}, clamped {}",
            i.clamped
        );
        ensure!(
            i.dissipated == T::zero(),
            "d̃ = 0 but d = {:?}",
            i.dissipated
        );
    } else if wall && literal {
        ensure!(i.clamped, "literal wall with d̃ > 0 not clamped");
    }
    if ma.is_none() {
        ensure!(
            i.delta_v_a.iter().all(|x| *x == T::zero()),
            "immovable a moved: {i:?}"
        );
    }
    if mb.is_none() {
        ensure!(
            i.delta_v_b.iter().all(|x| *x == T::zero()),
            "immovable b moved: {i:?}"
        );
    }
    // Computed on demand (not by `resolve`), checked the same way.
    let energies = i.energies(a, b);
    let k = i.k(a.mass(), b.mass());
    ensure!(!k.to64().is_nan(), "k is NaN in {i:?}");
    ensure!(
        !energies.before.to64().is_nan() && !energies.after.to64().is_nan(),
        "energy NaN in {i:?}"
    );
    for x in [i.impulse, energies.before, energies.after, i.dissipated, k] {
        ensure!(x >= T::zero(), "negative output in {i:?}");
    }

    // Finite whenever the exact values fit with headroom: |Δv| <= s = u (1 + e)
    // <= 2 |w|, J <= m_min s, E <= ½ m (|v| + s)².
    let (va, vb) = (to64(a.velocity()), to64(b.velocity()));
    let w = vb - va;
    let s_bound = 2.0 * norm(&w);
    let fits = |x: f64| x.is_finite() && x <= T::MAX / 8.0;
    let speed_bound = norm(&va).max(norm(&vb)) + s_bound;
    let finals = (
        to64(&(a.velocity() + i.delta_v_a)),
        to64(&(b.velocity() + i.delta_v_b)),
    );
    if fits(speed_bound) {
        for x in i.delta_v_a.iter().chain(i.delta_v_b.iter()) {
            ensure!(x.is_finite(), "Δv overflowed in {i:?}");
        }
        ensure!(
            finals
                .0
                .iter()
                .chain(finals.1.iter())
                .all(|x| x.is_finite()),
            "final velocity overflowed in {i:?}"
        );
        let m_min = ma.unwrap_or(f64::INFINITY).min(mb.unwrap_or(f64::INFINITY));
        if fits(m_min * s_bound) {
            ensure!(i.impulse.is_finite(), "impulse overflowed in {i:?}");
        }
        let energy_bound = [ma, mb]
            .into_iter()
            .flatten()
            .map(|m| m * speed_bound * speed_bound)
            .sum::<f64>();
        if fits(energy_bound) && fits(speed_bound * speed_bound) {
            for x in [energies.before, energies.after, i.dissipated] {
                ensure!(x.is_finite(), "energy overflowed in {i:?}");
            }
        }
    }
    let all_finite = field_values(i).iter().all(|(_, x)| x.is_finite())
        && energies.before.is_finite()
        && energies.after.is_finite()
        && finals
            .0
            .iter()
            .chain(finals.1.iter())
            .all(|x| x.is_finite());
    if !all_finite {
        return;
    }

    // The law's domain for its accuracy claims: a mass ratio that is a
    // normal number of the type ("ratios the type can hold").
    let ratio_ok = match (ma, mb) {
        (Some(x), Some(y)) => x.min(y) / x.max(y) >= T::MIN_POSITIVE,
        _ => true,
    };
    if !ratio_ok {
        return;
    }
    let (va2, vb2) = finals;
    let dv_a = to64(&i.delta_v_a);
    let dv_b = to64(&i.delta_v_b);
    let tiny = T::DENORM_MIN;
    let d64 = D as f64;

    // The normal relative velocity changes by s = u (1 + e) >= u.
    let change = (dv_b - dv_a).dot(&n);
    ensure!(
        change >= u * (1.0 - 8.0 * eps) - 4.0 * d64 * tiny,
        "normal velocity change {change:e} < u {u:e} in {i:?}"
    );
    let scale = norm(&va) + norm(&vb) + change.abs();
    if scale.is_finite() {
        ensure!(
            (vb2 - va2).dot(&n) >= -16.0 * eps * scale - 4.0 * d64 * tiny,
            "still approaching after the impact: {i:?}"
        );
    }

    // Momentum and energy are homogeneous in the masses and in the
    // velocities: the checks scale both by powers of two (exactly) so that
    // the largest mass and the largest velocity component are in [1, 2),
    // and the check's own f64 products neither under- nor overflow.
    let km = exponent_to_unit([ma, mb].into_iter().flatten().fold(0.0, f64::max));
    let kv = exponent_to_unit(
        [va, vb, va2, vb2, dv_a, dv_b]
            .iter()
            .flat_map(|v| v.iter())
            .fold(0.0, |m: f64, x| m.max(x.abs())),
    );
    let sm = |m: Option<f64>| m.map(|m| times_pow2(m, km));
    let sv = |v: &SVector<f64, D>| v.map(|x| times_pow2(x, kv));
    let (ma_s, mb_s) = (sm(ma), sm(mb));
    let (va_s, vb_s, va2_s, vb2_s) = (sv(&va), sv(&vb), sv(&va2), sv(&vb2));
    // The absolute error of a velocity component of the type that
    // underflowed (a few subnormals), in scaled units.
    let tiny_v = times_pow2(tiny, kv);

    // Momentum, for two finite masses.
    if let (Some(ma), Some(mb)) = (ma_s, mb_s) {
        let rel = if T::EPS < 1e-10 { 1e-12 } else { 1e-5 };
        let before = va_s * ma + vb_s * mb;
        let after = va2_s * ma + vb2_s * mb;
        let scale = ma * norm(&va_s) + mb * norm(&vb_s) + ma * norm(&va2_s) + mb * norm(&vb2_s);
        let floor = 4.0 * d64 * (ma + mb) * tiny_v;
        let err = norm(&(after - before));
        ensure!(
            err <= rel * scale + floor,
            "momentum changed by {err:e} of {scale:e} (scaled by 2^{km}, 2^{kv}) in {i:?}"
        );
    }

    // Energy never rises (in the frame of an immovable partner, which the
    // impact leaves unchanged: only a wall at rest is checked), and d is at
    // most the energy.
    let wall_at_rest = match (ma, mb) {
        (None, _) => va.iter().all(|x| *x == 0.0),
        (_, None) => vb.iter().all(|x| *x == 0.0),
        _ => true,
    };
    if wall_at_rest {
        let ke = |m: Option<f64>, v: &SVector<f64, D>| m.map_or(0.0, |m| 0.5 * m * norm_squared(v));
        let e0 = ke(ma_s, &va_s) + ke(mb_s, &vb_s);
        let e1 = ke(ma_s, &va2_s) + ke(mb_s, &vb2_s);
        let momentum =
            ma_s.map_or(0.0, |m| m * norm(&va2_s)) + mb_s.map_or(0.0, |m| m * norm(&vb2_s));
        let floor = 4.0 * d64 * momentum * tiny_v;
        ensure!(
            e1 <= e0 * (1.0 + 32.0 * eps) + floor,
            "energy rose from {e0:e} to {e1:e} (scaled by 2^{km}, 2^{kv}) in {i:?}"
        );
        // d = ½ μ u² q, a value of the type computed left to right: it may
        // itself underflow (a few subnormals), and so may ½ μ (half a
        // subnormal, times u² q) and ½ μ u (times u q).
        let u_s = times_pow2(u, kv);
        let reported = times_pow2(i.dissipated.to64(), km + 2 * kv);
        let floor_d = floor
            + times_pow2(8.0 * tiny, km + 2 * kv)
            + times_pow2(tiny, km) * u_s * u_s
            + times_pow2(tiny, km + kv) * u_s;
        ensure!(
            reported <= e0 * (1.0 + 32.0 * eps) + floor_d,
            "d = {reported:e} exceeds the energy {e0:e} (scaled by 2^{km}, 2^{kv}) in {i:?}"
        );
    }

    // e² = 1 − q with the note's q, computed independently in f64, where
    // the rounding of u (δu <= (D + 2) ε |w|) cannot move q across 1.
    let growth = match (ma, mb) {
        (Some(x), Some(y)) => {
            let t = x.min(y) / x.max(y);
            Some(t + 2.0 + 1.0 / t)
        }
        _ if literal => None,
        _ => Some(1.0),
    };
    let dt = d.to64();
    if let Some(growth) = growth
        && dt > 0.0
    {
        let wn = norm(&w);
        let rho_sqrt = wn / u;
        let q = 2.0 * dt * rho_sqrt * rho_sqrt * growth;
        // Relative error of the law's ρ: rounding of u and w, and for a
        // subnormal u, its absolute error of about D subnormals.
        let rel = 4.0 * (d64 + 2.0) * eps * rho_sqrt + 16.0 * eps + 4.0 * d64 * tiny / u;
        if q.is_finite() && rel < 0.5 {
            if q * (1.0 + rel) < 1.0 {
                ensure!(!i.clamped, "q = {q:e} < 1 but clamped: {i:?}");
                let e2 = e * e;
                ensure!(
                    (e2 - (1.0 - q)).abs() <= q * rel + 8.0 * eps,
                    "e² = {e2:e}, 1 − q = {:e} in {i:?}",
                    1.0 - q
                );
            } else if q * (1.0 - rel) > 1.0 {
                ensure!(i.clamped, "q = {q:e} > 1 but not clamped: {i:?}");
            }
        }
    }
}
