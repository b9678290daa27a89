//! Uniform gravity: exact bounces, energy conservation, and the stall
//! guard against the Zeno point of inelastic bouncing.

use approx::assert_abs_diff_eq;
use kimpact::{Law, LawParams};
use kimpact_reference::nalgebra::{SVector, Vector2, Vector3};
use kimpact_reference::{Ball, BoxBounds, Reference, ReferenceError, StallGuard};

mod common;
use common::{Rng, cube, lattice_gas, violations};

const G: f64 = 9.81;

#[test]
fn elastic_bounce_keeps_its_height() {
    // Dropped from rest 2 above the floor (its bottom at 2): it is back at
    // the top, at rest, every 2 t₁, t₁ = √(2h/g).
    let (radius, h) = (0.25, 2.0);
    let y0 = radius + h;
    let t1 = (2.0 * h / G).sqrt();
    let mut sim = Reference::new(
        vec![Ball::new(
            radius,
            3.0,
            Vector2::new(1.0, y0),
            Vector2::zeros(),
        )],
        BoxBounds::new(Vector2::zeros(), Vector2::new(2.0, 5.0)),
        Vector2::new(0.0, -G),
        Law::elastic(),
    )
    .unwrap();
    let mut rng = Rng::new(5);
    let mut highest: f64 = 0.0;
    for k in 1..=1000 {
        // Random times within the bounce never see it higher than y0.
        let mut offsets = [rng.next(), rng.next(), rng.next()];
        offsets.sort_by(f64::total_cmp);
        for u in offsets {
            sim.advance_to(2.0 * t1 * (k as f64 - 1.0 + u)).unwrap();
            highest = highest.max(sim.balls()[0].position.y);
        }
        sim.advance_to(2.0 * t1 * k as f64).unwrap();
        let b = sim.balls()[0];
        assert!(
            (b.position.y - y0).abs() < 1e-9,
            "bounce {k}: apex {}",
            b.position.y
        );
        assert!(
            b.velocity.y.abs() < 1e-8,
            "bounce {k}: apex speed {}",
            b.velocity.y
        );
        highest = highest.max(b.position.y);
    }
    assert!(highest < y0 + 1e-9, "highest {highest}");
    assert_eq!(sim.stats().wall_hits, [[0, 0], [1000, 0]]);
    // Each bounce gives the floor 2 m √(2 g h).
    let impulse = 1000.0 * 2.0 * 3.0 * (2.0 * G * h).sqrt();
    assert_abs_diff_eq!(
        sim.stats().wall_impulse[1][0],
        impulse,
        epsilon = 1e-9 * impulse
    );
}

#[test]
fn elastic_bounce_in_3d_between_walls_keeps_its_height() {
    // A sphere thrown sideways bounces off floor and side walls; its height
    // at rest-in-y is always the drop height.
    let (radius, y0) = (0.1, 1.6);
    let mut sim = Reference::new(
        vec![Ball::new(
            radius,
            1.0,
            Vector3::new(0.5, y0, 0.5),
            Vector3::new(1.3, 0.0, -0.7),
        )],
        cube(2.0),
        Vector3::new(0.0, -G, 0.0),
        Law::elastic(),
    )
    .unwrap();
    let t1 = (2.0 * (y0 - radius) / G).sqrt();
    for k in 1..=300 {
        sim.advance_to(2.0 * t1 * k as f64).unwrap();
        let b = sim.balls()[0];
        assert!(
            (b.position.y - y0).abs() < 1e-9,
            "bounce {k}: apex {}",
            b.position.y
        );
        assert_abs_diff_eq!(b.velocity.x.abs(), 1.3, epsilon = 1e-12);
        assert_abs_diff_eq!(b.velocity.z.abs(), 0.7, epsilon = 1e-12);
    }
    let s = sim.stats();
    assert_eq!(s.wall_hits[1], [300, 0]);
    assert!(s.wall_hits[0][0] > 50 && s.wall_hits[2][0] > 30, "{s:?}");
    let (_, outside) = violations(&sim);
    assert!(outside <= 1e-12);
}

#[test]
fn elastic_gas_under_gravity_conserves_total_energy() {
    let g = SVector::<f64, 2>::new(0.0, -3.0);
    let balls = lattice_gas::<2>(21, 150, &cube(1.0), (0.015, 0.03), (0.5, 2.0), 1.5);
    let mut sim = Reference::new(balls, cube(1.0), g, Law::elastic()).unwrap();
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    let p0 = sim.potential_energy();
    while sim.stats().impacts() < 60_000 {
        sim.advance_by(0.1).unwrap();
        let e = sim.kinetic_energy() + sim.potential_energy();
        assert!(
            (e - e0).abs() < 1e-10 * e0.abs(),
            "drift {:e} at t = {}",
            (e - e0) / e0,
            sim.time()
        );
        let (overlap, outside) = violations(&sim);
        assert!(
            overlap < 1e-12 && outside < 1e-12,
            "{overlap:e} {outside:e}"
        );
    }
    // The gas settled somewhat: potential energy went down.
    assert!(sim.potential_energy() < p0);
}

#[test]
fn inelastic_bounce_stalls_at_the_zeno_time() {
    // Against the wall (FixedPartner::OwnMass) a head-on bounce has
    // e = √(1 − 2 d̃_w) = 0.8: the bounces end at t∞ = t₁ (1 + 2e/(1 − e)).
    let law = Law::new(LawParams {
        dissipation: 0.0,
        wall_dissipation: Some(0.18),
        ..Default::default()
    })
    .unwrap();
    let (radius, h) = (0.25, 1.0);
    let mut sim = Reference::new(
        vec![Ball::new(
            radius,
            1.0,
            Vector2::new(1.0, radius + h),
            Vector2::zeros(),
        )],
        BoxBounds::new(Vector2::zeros(), Vector2::new(2.0, 3.0)),
        Vector2::new(0.0, -G),
        law,
    )
    .unwrap();
    sim.set_stall_guard(StallGuard {
        window: 1e-12,
        max_events: 2_000,
    });
    let e = 0.8;
    let t1 = (2.0 * h / G).sqrt();
    let zeno = t1 * (1.0 + 2.0 * e / (1.0 - e));
    let err = sim.advance_to(zeno + 1.0).unwrap_err();
    let ReferenceError::Stalled {
        time,
        events,
        window,
    } = err
    else {
        panic!("{err:?}")
    };
    assert_eq!((events, window), (2_000, 1e-12));
    assert!(
        (time - zeno).abs() < 1e-9,
        "stalled at {time}, Zeno time {zeno}"
    );
    assert_eq!(sim.time(), time);
    assert_eq!(sim.stats().stalls, 1);
    // Consistent state: on the floor, at rest, energy accounted for.
    let b = sim.balls()[0];
    assert_abs_diff_eq!(b.position.y, radius, epsilon = 1e-12);
    assert!(b.velocity.norm() < 1e-9);
    let lost = G * h - (sim.kinetic_energy() + sim.potential_energy() - G * radius);
    assert_abs_diff_eq!(lost, sim.stats().dissipated, epsilon = 1e-9);
    // Asking again goes on for another max_events, and stalls again.
    assert!(matches!(
        sim.advance_to(zeno + 1.0),
        Err(ReferenceError::Stalled { .. })
    ));
    assert_eq!(sim.stats().stalls, 2);
}

#[test]
fn inelastic_collapse_of_three_balls_stalls() {
    // With d̃ = 0.5 every impact is clamped (e = 1e-3 < 7 − 4√3): three
    // balls in a row become a cluster moving at 1/3, which collapses when
    // it meets the wall (against which the impact is perfectly plastic,
    // e = √(1 − 2 d̃_w) = 0): infinitely many impacts in finite time.
    let law = Law::with_dissipation(0.5).unwrap();
    let y = 0.5;
    let mut sim = Reference::new(
        vec![
            Ball::new(0.05, 1.0, Vector2::new(0.2, y), Vector2::new(1.0, 0.0)),
            Ball::new(0.05, 1.0, Vector2::new(0.4, y), Vector2::zeros()),
            Ball::new(0.05, 1.0, Vector2::new(0.55, y), Vector2::zeros()),
        ],
        cube(1.0),
        Vector2::zeros(),
        law,
    )
    .unwrap();
    sim.set_stall_guard(StallGuard {
        window: 1e-12,
        max_events: 5_000,
    });
    sim.advance_to(1.0).unwrap();
    let s = *sim.stats();
    assert_eq!((s.clamped, s.wall_impacts), (s.ball_impacts, 0), "{s:?}");
    // Momentum is conserved, and the energy is the cluster's.
    assert_abs_diff_eq!(sim.momentum(), Vector2::new(1.0, 0.0), epsilon = 1e-12);
    assert_abs_diff_eq!(s.dissipated, 1.0 / 3.0, epsilon = 1e-6);
    assert_abs_diff_eq!(sim.kinetic_energy() + s.dissipated, 0.5, epsilon = 1e-12);
    let result = sim.advance_to(5.0);
    assert!(
        matches!(result, Err(ReferenceError::Stalled { .. })),
        "{result:?} {:?}",
        sim.stats()
    );
    let s = *sim.stats();
    assert!(s.ball_impacts > 1000 && s.wall_impacts > 0, "{s:?}");
    assert!(sim.time() < 5.0);
    assert_abs_diff_eq!(sim.kinetic_energy() + s.dissipated, 0.5, epsilon = 1e-12);
    let (overlap, _) = violations(&sim);
    assert!(overlap < 1e-9, "overlap {overlap:e}");
}
