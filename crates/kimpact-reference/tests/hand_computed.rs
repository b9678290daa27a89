//! Small scenes whose trajectories are computed by hand, checked to 1e-12.

use approx::assert_abs_diff_eq;
use kimpact::{Law, LawParams};
use kimpact_reference::nalgebra::{Vector2, Vector3};
use kimpact_reference::{Ball, BoxBounds, Reference};

mod common;
use common::cube;

const TOL: f64 = 1e-12;

fn sim2(balls: Vec<Ball<2>>, law: Law<f64>) -> Reference<2> {
    Reference::new(balls, cube(1.0), Vector2::zeros(), law).unwrap()
}

#[test]
fn head_on_equal_masses_swap_velocities() {
    // Gap between surfaces 0.3, closing at 2: contact at t = 0.15, at
    // x = 0.4 and 0.6; then they swap velocities.
    let mut sim = sim2(
        vec![
            Ball::new(0.1, 1.0, Vector2::new(0.25, 0.5), Vector2::new(1.0, 0.0)),
            Ball::new(0.1, 1.0, Vector2::new(0.75, 0.5), Vector2::new(-1.0, 0.0)),
        ],
        Law::elastic(),
    );
    sim.advance_to(0.1).unwrap();
    assert_eq!(sim.stats().ball_impacts, 0);
    assert_abs_diff_eq!(sim.balls()[0].position.x, 0.35, epsilon = TOL);
    sim.advance_to(0.3).unwrap();
    assert_eq!(sim.stats().ball_impacts, 1);
    let [a, b] = sim.balls() else { panic!() };
    assert_abs_diff_eq!(a.position, Vector2::new(0.25, 0.5), epsilon = TOL);
    assert_abs_diff_eq!(b.position, Vector2::new(0.75, 0.5), epsilon = TOL);
    assert_abs_diff_eq!(a.velocity, Vector2::new(-1.0, 0.0), epsilon = TOL);
    assert_abs_diff_eq!(b.velocity, Vector2::new(1.0, 0.0), epsilon = TOL);
    // Each reaches its wall (x = 0.1 and 0.9) at t = 0.45, then they meet
    // again at t = 0.75, back at x = 0.4 and 0.6, and swap again.
    sim.advance_to(0.5).unwrap();
    assert_eq!(sim.stats().wall_impacts, 2);
    assert_eq!(sim.stats().wall_hits, [[1, 1], [0, 0]]);
    assert_abs_diff_eq!(sim.balls()[0].position.x, 0.15, epsilon = TOL);
    assert_abs_diff_eq!(sim.balls()[1].position.x, 0.85, epsilon = TOL);
    assert_abs_diff_eq!(sim.stats().wall_impulse[0][0], 2.0, epsilon = TOL);
    assert_abs_diff_eq!(sim.stats().wall_impulse[0][1], 2.0, epsilon = TOL);
    sim.advance_to(0.8).unwrap();
    assert_eq!(sim.stats().ball_impacts, 2);
    assert_abs_diff_eq!(sim.balls()[0].position.x, 0.35, epsilon = TOL);
    assert_abs_diff_eq!(sim.balls()[0].velocity.x, -1.0, epsilon = TOL);
}

#[test]
fn head_on_unequal_masses() {
    // m = 1 at 2 hits m = 3 at rest: v' = (−1, 1) (textbook elastic).
    // Contact after the gap 0.2 closes at speed 2: t = 0.1 at x = 0.4/0.6.
    let mut sim = sim2(
        vec![
            Ball::new(0.1, 1.0, Vector2::new(0.2, 0.5), Vector2::new(2.0, 0.0)),
            Ball::new(0.1, 3.0, Vector2::new(0.6, 0.5), Vector2::zeros()),
        ],
        Law::elastic(),
    );
    sim.advance_to(0.2).unwrap();
    let [a, b] = sim.balls() else { panic!() };
    assert_abs_diff_eq!(a.velocity, Vector2::new(-1.0, 0.0), epsilon = TOL);
    assert_abs_diff_eq!(b.velocity, Vector2::new(1.0, 0.0), epsilon = TOL);
    assert_abs_diff_eq!(a.position.x, 0.3, epsilon = TOL);
    assert_abs_diff_eq!(b.position.x, 0.7, epsilon = TOL);
    assert_abs_diff_eq!(sim.momentum(), Vector2::new(2.0, 0.0), epsilon = TOL);
}

#[test]
fn head_on_inelastic_loses_exactly_d() {
    // Equal masses 1, approach speed u = 2, head on (ρ = 1): q = 8 d̃,
    // e = √(1 − q), v' = ∓e, d = ½ μ u² q = q.
    let d = 0.02;
    let law = Law::with_dissipation(d).unwrap();
    let mut sim = sim2(
        vec![
            Ball::new(0.1, 1.0, Vector2::new(0.25, 0.5), Vector2::new(1.0, 0.0)),
            Ball::new(0.1, 1.0, Vector2::new(0.75, 0.5), Vector2::new(-1.0, 0.0)),
        ],
        law,
    );
    sim.advance_to(0.2).unwrap();
    let e = (1.0 - 8.0 * d).sqrt();
    let [a, b] = sim.balls() else { panic!() };
    assert_abs_diff_eq!(a.velocity.x, -e, epsilon = TOL);
    assert_abs_diff_eq!(b.velocity.x, e, epsilon = TOL);
    assert_abs_diff_eq!(a.position.x, 0.4 - 0.05 * e, epsilon = TOL);
    assert_abs_diff_eq!(sim.stats().dissipated, 8.0 * d, epsilon = TOL);
    assert_abs_diff_eq!(sim.kinetic_energy(), 1.0 - 8.0 * d, epsilon = TOL);
}

#[test]
fn ball_against_wall() {
    // r = 0.1 at x = 0.5 moving at +2: touches x = 1 at t = 0.2 (centre at
    // 0.9), back to 0.3 at t = 0.5, to the other wall (centre at 0.1) at
    // t = 0.6.
    let mut sim = sim2(
        vec![Ball::new(
            0.1,
            0.5,
            Vector2::new(0.5, 0.5),
            Vector2::new(2.0, 0.0),
        )],
        Law::elastic(),
    );
    sim.advance_to(0.5).unwrap();
    let b = sim.balls()[0];
    assert_abs_diff_eq!(b.position, Vector2::new(0.3, 0.5), epsilon = TOL);
    assert_abs_diff_eq!(b.velocity, Vector2::new(-2.0, 0.0), epsilon = TOL);
    assert_eq!(sim.stats().wall_hits, [[0, 1], [0, 0]]);
    // Impulse 2 m v = 2.
    assert_abs_diff_eq!(sim.stats().wall_impulse[0][1], 2.0, epsilon = TOL);
    sim.advance_to(0.7).unwrap();
    assert_abs_diff_eq!(sim.balls()[0].position.x, 0.3, epsilon = TOL);
    assert_eq!(sim.stats().wall_hits, [[1, 1], [0, 0]]);
}

#[test]
fn oblique_wall_with_wall_dissipation() {
    // Against a wall under FixedPartner::OwnMass, e = √(1 − 2 d̃_w |w|²/u²).
    // Velocity (1, 1) on the wall y = 1: |w|²/u² = 2, d̃_w = 0.09 gives
    // e = √0.64 = 0.8; the tangential velocity is kept.
    let law = Law::new(LawParams {
        dissipation: 0.0,
        wall_dissipation: Some(0.09),
        ..Default::default()
    })
    .unwrap();
    let mut sim = sim2(
        vec![Ball::new(
            0.1,
            2.0,
            Vector2::new(0.2, 0.5),
            Vector2::new(1.0, 1.0),
        )],
        law,
    );
    // Touches y = 0.9 at t = 0.4 (x = 0.6); at t = 0.5: x = 0.7,
    // y = 0.9 − 0.08.
    sim.advance_to(0.5).unwrap();
    let b = sim.balls()[0];
    assert_abs_diff_eq!(b.velocity, Vector2::new(1.0, -0.8), epsilon = TOL);
    assert_abs_diff_eq!(b.position, Vector2::new(0.7, 0.82), epsilon = TOL);
    // d = ½ m u² q with q = 1 − e² = 0.36.
    assert_abs_diff_eq!(sim.stats().dissipated, 0.5 * 2.0 * 0.36, epsilon = TOL);
    assert_abs_diff_eq!(sim.stats().wall_impulse[1][1], 2.0 * 1.8, epsilon = TOL);
}

#[test]
fn oblique_spheres_elastic() {
    // Equal spheres, σ = 0.2; A moves at (1, 0, 0), B rests with impact
    // parameter σ/2. Contact when B − A = σ (√3/2, 1/2, 0): then B takes the
    // normal part (3/4, √3/4, 0) and A keeps (1/4, −√3/4, 0).
    let s3 = 3f64.sqrt();
    let a0 = Vector3::new(0.2, 0.4, 0.5);
    let b0 = Vector3::new(0.6, 0.5, 0.5);
    let t_hit = 0.4 - 0.1 * s3;
    let mut sim = Reference::new(
        vec![
            Ball::new(0.1, 1.0, a0, Vector3::new(1.0, 0.0, 0.0)),
            Ball::new(0.1, 1.0, b0, Vector3::zeros()),
        ],
        cube(1.0),
        Vector3::zeros(),
        Law::elastic(),
    )
    .unwrap();
    let t = t_hit + 0.1;
    sim.advance_to(t).unwrap();
    assert_eq!(sim.stats().ball_impacts, 1);
    let va = Vector3::new(0.25, -s3 / 4.0, 0.0);
    let vb = Vector3::new(0.75, s3 / 4.0, 0.0);
    let [a, b] = sim.balls() else { panic!() };
    assert_abs_diff_eq!(a.velocity, va, epsilon = TOL);
    assert_abs_diff_eq!(b.velocity, vb, epsilon = TOL);
    let a_hit = a0 + Vector3::x() * t_hit;
    assert_abs_diff_eq!(a.position, a_hit + va * 0.1, epsilon = TOL);
    assert_abs_diff_eq!(b.position, b0 + vb * 0.1, epsilon = TOL);
}

#[test]
fn newtons_cradle_passes_the_velocity_down_the_row() {
    // Three touching balls at rest, a fourth hits the row: at the same
    // instant every impulse passes on, and only the last ball moves.
    let y = 0.5;
    let mut sim = sim2(
        vec![
            Ball::new(0.05, 1.0, Vector2::new(0.1, y), Vector2::new(1.0, 0.0)),
            Ball::new(0.05, 1.0, Vector2::new(0.4, y), Vector2::zeros()),
            Ball::new(0.05, 1.0, Vector2::new(0.5, y), Vector2::zeros()),
            Ball::new(0.05, 1.0, Vector2::new(0.6, y), Vector2::zeros()),
        ],
        Law::elastic(),
    );
    // Contact at t = 0.2; at t = 0.3 the last ball is at 0.7.
    sim.advance_to(0.3).unwrap();
    assert_eq!(sim.stats().ball_impacts, 3);
    let xs: Vec<f64> = sim.balls().iter().map(|b| b.position.x).collect();
    let vs: Vec<f64> = sim.balls().iter().map(|b| b.velocity.x).collect();
    for (x, want) in xs.iter().zip([0.3, 0.4, 0.5, 0.7]) {
        assert_abs_diff_eq!(*x, want, epsilon = TOL);
    }
    for (v, want) in vs.iter().zip([0.0, 0.0, 0.0, 1.0]) {
        assert_abs_diff_eq!(*v, want, epsilon = TOL);
    }
}

#[test]
fn free_fall_and_bounce() {
    // Dropped from rest with its bottom 4.9 above the floor, g = 9.8: lands
    // at t = 1 at speed 9.8, is back at the top at t = 2.
    let g = Vector2::new(0.0, -9.8);
    let mut sim = Reference::new(
        vec![Ball::new(
            0.5,
            1.0,
            Vector2::new(1.0, 5.4),
            Vector2::zeros(),
        )],
        BoxBounds::new(Vector2::zeros(), Vector2::new(2.0, 10.0)),
        g,
        Law::elastic(),
    )
    .unwrap();
    sim.advance_to(0.5).unwrap();
    assert_abs_diff_eq!(sim.balls()[0].position.y, 5.4 - 4.9 * 0.25, epsilon = TOL);
    assert_abs_diff_eq!(sim.balls()[0].velocity.y, -4.9, epsilon = TOL);
    sim.advance_to(1.5).unwrap();
    assert_eq!(sim.stats().wall_hits, [[0, 0], [1, 0]]);
    assert_abs_diff_eq!(
        sim.balls()[0].position.y,
        0.5 + 9.8 * 0.5 - 4.9 * 0.25,
        epsilon = TOL
    );
    assert_abs_diff_eq!(sim.balls()[0].velocity.y, 9.8 - 4.9, epsilon = TOL);
    assert_abs_diff_eq!(sim.stats().wall_impulse[1][0], 2.0 * 9.8, epsilon = TOL);
    sim.advance_to(2.0).unwrap();
    assert_abs_diff_eq!(sim.balls()[0].position.y, 5.4, epsilon = TOL);
    assert_abs_diff_eq!(sim.balls()[0].velocity.y, 0.0, epsilon = TOL);
}
