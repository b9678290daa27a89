//! A parting touch's next meeting against a closed form evaluated here.
// One source for f32 and f64: `as Real` is a cast in one build only.
#![allow(clippy::unnecessary_cast)]

use super::*;
use crate::math::Vector;
use crate::rapier::parry::shape::Cuboid;

use super::super::motion::Motion;
use super::super::toi::time_of_impact;
use crate::cast::Rewind;
use crate::rapier::parry::query::ContactManifold;

use super::super::test_support::{about_z, first_root, tol, xy};

/// The half-extents of a flat bar, 1.6 long.
const HALF: (Real, Real) = (0.8, 0.05);

/// Where a bar of [`HALF`], turned from `theta0` at `omega` and rising
/// from the height its lowest corner touches the floor at (y = 0), meets
/// the floor next (first within `(0, end]`), as the replay finds it after
/// that parting touch: [`meets_again`], and the search it may hand on to.
fn next_meeting(theta0: Real, omega: Real, vy: Real, end: Real) -> (Option<Real>, Option<f64>) {
    let (hx, hy) = HALF;
    let lowest_drop =
        |theta: f64| f64::from(hx) * theta.sin().abs() + f64::from(hy) * theta.cos().abs();
    let y0 = lowest_drop(f64::from(theta0));
    let lowest =
        |t: f64| y0 + f64::from(vy) * t - lowest_drop(f64::from(theta0) + f64::from(omega) * t);
    let expected = first_root(lowest, f64::from(end));
    let mut half = Vector::splat(hy);
    half[0] = hx;
    let bar = Cuboid::new(half);
    let motion = Motion {
        pose: Pose::new(xy(0.3, y0 as Real), about_z(theta0)),
        local_com: Vector::ZERO,
        linvel: xy(0.0, vy),
        angvel: about_z(omega),
        t_ref: 0.0,
    };
    let mut floor_half = Vector::splat(10.0);
    floor_half[1] = 1.0;
    let floor = Cuboid::new(floor_half);
    let still = Motion::still(Pose::from_translation(xy(0.0, -1.0)));
    let a = Mover {
        motion: &motion,
        offset: Some(Pose::IDENTITY),
        shape: &bar,
        reach: half.length(),
    };
    let b = Mover {
        motion: &still,
        offset: None,
        shape: &floor,
        reach: floor_half.length(),
    };
    let tolerance = (1e-3 * tol()) as Real;
    let mut manifolds = Vec::new();
    let found = match meets_again(&a, &b, (0.0, end), tolerance, &mut manifolds) {
        Again::At(s) => Some(s),
        Again::SearchFrom(s) => {
            assert!(s > 0.0 && s < end, "a search from {s}");
            time_of_impact(&a, &b, s, end, tolerance, Rewind::Never, &mut manifolds)
        }
        Again::Never => None,
    };
    (found, expected)
}

/// A bar struck on one corner rises turning fast: its other corner swings
/// down through the floor's level and up again before the interval ends.
/// The replay meets it when the lowest corner,
/// `y(t) = y₀ + vy t − (hx|sin θ(t)| + hy|cos θ(t)|)`, `θ(t) = θ₀ + ω t`,
/// first comes back to the floor (its first root after the touch, found by
/// bisection here); a look at the interval's end alone finds the bar clear.
#[test]
fn a_corner_swinging_through_after_a_parting_touch_is_met_in_time() {
    for (theta0, omega, vy) in [(-0.3, 10.0, 2.0), (0.4, -12.0, 2.5), (-0.2, 14.0, 3.0)] {
        let end = 0.3;
        let (found, expected) = next_meeting(theta0, omega, vy, end);
        let expected = expected.expect("the corner comes back to the floor");
        let (hx, hy) = HALF;
        let lowest_at_end = f64::from(hx * (theta0 + omega * end).sin().abs())
            + f64::from(hy * (theta0 + omega * end).cos().abs());
        assert!(
            f64::from(vy * end)
                + f64::from(hx * theta0.sin().abs())
                + f64::from(hy * theta0.cos().abs())
                > lowest_at_end,
            "θ₀ {theta0}, ω {omega}: the bar is to be clear at the end"
        );
        let t = found.unwrap_or_else(|| {
            panic!("θ₀ {theta0}, ω {omega}, vy {vy}: no meeting; closed form {expected}")
        });
        let speed = f64::from(vy.abs() + omega.abs() * hx);
        assert!(
            (f64::from(t) - expected).abs() * speed < tol(),
            "θ₀ {theta0}, ω {omega}, vy {vy}: t = {t}, closed form {expected}"
        );
    }
}

/// A bar rising faster than its corners swing down, or not turning, does
/// not meet the floor again.
#[test]
fn a_bar_that_rises_clear_does_not_meet_again() {
    for (theta0, omega, vy) in [(-0.3, 10.0, 6.0), (-0.3, 0.0, 0.5)] {
        let (found, expected) = next_meeting(theta0, omega, vy, 0.3);
        assert_eq!(expected, None, "θ₀ {theta0}, ω {omega}, vy {vy}");
        assert_eq!(found, None, "θ₀ {theta0}, ω {omega}, vy {vy}");
    }
}

/// The near face of the thin wall of [`room`].
const WALL_X: Real = 0.3;

/// A room made of one compound (not convex): a floor whose top lies at
/// y = 0 and a wall 0.02 thick whose near face lies at x = [`WALL_X`].
fn room() -> crate::rapier::parry::shape::Compound {
    use crate::rapier::parry::shape::{Compound, SharedShape};
    let wall_half = 0.01;
    let mut floor_half = Vector::splat(2.0);
    floor_half[1] = 0.5;
    let mut wall_half_extents = Vector::splat(2.0);
    wall_half_extents[0] = wall_half;
    Compound::new(vec![
        (
            Pose::from_translation(xy(0.0, -0.5)),
            SharedShape::new(Cuboid::new(floor_half)),
        ),
        (
            Pose::from_translation(xy(WALL_X + wall_half, 2.0)),
            SharedShape::new(Cuboid::new(wall_half_extents)),
        ),
    ])
}

/// Where a cube of half-size `h` resting on the floor of [`room`] at
/// x = 0 (touching it at `t = 0`), moving at `(vx, vy)` and turning at
/// `omega` about z, meets the room next within a step of 1/60 s, as
/// `search` finds it from that touch; with the wall's closed-form time
/// `(WALL_X − h)/vx` and the depth the search meets an overlap at.
fn cube_in_room(
    h: Real,
    (vx, vy): (Real, Real),
    omega: Real,
    search: impl FnOnce(
        &Mover,
        &Mover,
        (Real, Real),
        Real,
        &mut Vec<ContactManifold<(), ()>>,
    ) -> Option<Real>,
) -> (Option<Real>, f64, f64) {
    let end = 1.0 as Real / 60.0;
    let room = room();
    let cube = Cuboid::new(Vector::splat(h));
    let motion = Motion {
        pose: Pose::from_translation(xy(0.0, h)),
        local_com: Vector::ZERO,
        linvel: xy(vx, vy),
        angvel: about_z(omega),
        t_ref: 0.0,
    };
    let still = Motion::still(Pose::IDENTITY);
    let a = Mover {
        motion: &motion,
        offset: Some(Pose::IDENTITY),
        shape: &cube,
        reach: h * (crate::math::DIM as Real).sqrt(),
    };
    let b = Mover {
        motion: &still,
        offset: None,
        shape: &room,
        reach: 4.0,
    };
    let tolerance = (1e-3 * tol()) as Real;
    let mut manifolds = Vec::new();
    let found = search(&a, &b, (0.0, end), tolerance, &mut manifolds);
    let depth = f64::from(reentry_depth(&a, &b, tolerance) + 4.0 * tolerance);
    (found, f64::from((WALL_X - h) / vx), depth)
}

/// A box bouncing off the floor of a room made of one compound (a floor
/// and a thin wall: not convex) flies on towards the wall, which it
/// would cross whole before the interval ends. The replay meets it at
/// the wall: when its leading face, `x₀ + h + vx t`, reaches the wall's
/// near face (a look at the interval's end alone finds the box past the
/// wall, clear of the room).
#[test]
fn a_box_leaving_a_compound_s_floor_meets_its_wall() {
    let (found, expected, depth) = cube_in_room(
        0.1,
        (30.0, 3.0),
        0.0,
        |a, b, span, tolerance, manifolds| match meets_again(a, b, span, tolerance, manifolds) {
            Again::At(s) => Some(s),
            Again::SearchFrom(s) => {
                time_of_impact(a, b, s, span.1, tolerance, Rewind::Never, manifolds)
            }
            Again::Never => None,
        },
    );
    let t = found.unwrap_or_else(|| panic!("no meeting; closed form {expected}"));
    // Met within the reentry depth of the wall (and the bisection's stop).
    assert!(
        (f64::from(t) - expected) * 30.0 <= depth + tol() && f64::from(t) >= expected - tol(),
        "t = {t}, closed form {expected}"
    );
}

/// A box sliding on the compound room's floor (touching it without
/// striking: held) towards its thin wall: the wall's contact strikes,
/// and is met, when the leading face reaches it, though the box would be
/// past the wall by the interval's end.
#[test]
fn a_box_sliding_on_a_compound_s_floor_strikes_its_wall() {
    let rest_speed = 0.01;
    let (found, expected, depth) =
        cube_in_room(0.1, (60.0, 0.0), 0.0, |a, b, span, tolerance, manifolds| {
            let velocity = a.motion.linvel;
            // The box's approach along the contact normal (from the box
            // towards the room), the room still.
            let strikes = |_: Real| move |_: Vector, n: Vector| velocity.dot(n) > rest_speed;
            strikes_again(a, b, span, tolerance, strikes, manifolds)
        });
    let t = found.unwrap_or_else(|| panic!("no strike; closed form {expected}"));
    assert!(
        (f64::from(t) - expected) * 60.0 <= depth + tol() && f64::from(t) >= expected - tol(),
        "t = {t}, closed form {expected}"
    );
}

/// The looks through a step end, each one later than the last, even for
/// a body so fast that its windows are below the rounding of an instant
/// a rounding before the step's end.
#[test]
fn the_looks_through_a_step_always_move_on() {
    cube_in_room(0.1, (3e15, 0.0), 1e15, |a, b, (_, end), _, _| {
        // Windows below the rounding of an instant near the step's end.
        assert!(blind_window(a, b).max(crossing_window(a, b)) < 1e-12);
        let just_before = Real::from_bits(end.to_bits() - 1);
        for t in [0.0, 0.5 * end, just_before] {
            let mut looks: Vec<(Real, Real)> = Vec::new();
            let found = through_the_step(a, b, (t, end), |from, to| {
                looks.push((from, to));
                None
            });
            assert_eq!(found, None);
            assert!(
                !looks.is_empty() && looks.len() <= MAX_LOOKS as usize + 1,
                "from {t}: {} looks",
                looks.len()
            );
            assert!(
                looks.iter().all(|&(from, to)| to > from),
                "from {t}: {looks:?}"
            );
            assert_eq!(looks.last().map(|l| l.1), Some(end));
        }
        None
    });
}
