//! Gases of many balls: conservation laws and geometric invariants over
//! many impacts.

use kimpact::Law;
use kimpact_reference::nalgebra::{SVector, Vector2, Vector3};
use kimpact_reference::{Ball, BoxBounds, Reference};

mod common;
use common::{Rng, cube, lattice_gas, violations};

/// Run an elastic gas until it has made `impacts` impacts, checking at
/// checkpoints that kinetic energy is conserved to 1e-12 relative and that
/// no two balls overlap and none leaves the box (beyond rounding).
fn elastic_gas<const D: usize>(balls: Vec<Ball<D>>, impacts: u64, dt: f64) -> Reference<D> {
    let mut sim = Reference::new(balls, cube(1.0), SVector::zeros(), Law::elastic()).unwrap();
    let e0 = sim.kinetic_energy();
    let mut checkpoints = 0;
    while sim.stats().impacts() < impacts {
        sim.advance_by(dt).unwrap();
        let drift = (sim.kinetic_energy() - e0).abs() / e0;
        assert!(
            drift < 1e-12,
            "energy drift {drift:e} at t = {}",
            sim.time()
        );
        let (overlap, outside) = violations(&sim);
        assert!(overlap < 1e-12, "overlap {overlap:e} at t = {}", sim.time());
        assert!(outside < 1e-12, "outside {outside:e} at t = {}", sim.time());
        checkpoints += 1;
    }
    assert!(checkpoints >= 10, "too few checkpoints: {checkpoints}");
    let s = sim.stats();
    assert_eq!(s.clamped, 0);
    assert_eq!(s.dissipated, 0.0);
    assert_eq!(s.stalls, 0);
    assert!(s.ball_impacts > s.wall_impacts, "{s:?}");
    sim
}

#[test]
fn elastic_gas_200_disks() {
    // Packing fraction 200 π r² = 0.4 with r = 0.025.
    let balls = lattice_gas::<2>(1, 200, &cube(1.0), (0.025, 0.025), (1.0, 1.0), 1.0);
    let sim = elastic_gas(balls, 70_000, 0.05);
    assert!(sim.stats().cell_crossings > 0);
}

#[test]
fn elastic_gas_100_spheres() {
    // Packing fraction ~0.3 with r = 0.089.
    let balls = lattice_gas::<3>(2, 100, &cube(1.0), (0.089, 0.089), (1.0, 1.0), 1.0);
    elastic_gas(balls, 40_000, 0.05);
}

#[test]
fn elastic_polydisperse_gas() {
    // Radii over a factor 4 and masses over a factor 100: the cells are
    // sized for the largest ball.
    let balls = lattice_gas::<2>(3, 150, &cube(1.0), (0.008, 0.032), (0.1, 10.0), 1.0);
    elastic_gas(balls, 30_000, 0.05);
    let balls = lattice_gas::<3>(4, 120, &cube(1.0), (0.02, 0.08), (0.1, 10.0), 1.0);
    elastic_gas(balls, 30_000, 0.05);
}

#[test]
fn momentum_conserved_away_from_walls() {
    // A cluster of spheres in the middle of a big box, moving slowly enough
    // that none reaches a wall within the window.
    let inner = BoxBounds::new(Vector3::repeat(46.0), Vector3::repeat(54.0));
    let balls = lattice_gas::<3>(5, 125, &inner, (0.6, 0.75), (0.5, 2.0), 2.0);
    let mut sim = Reference::new(balls, cube(100.0), Vector3::zeros(), Law::elastic()).unwrap();
    let p0 = sim.momentum();
    let scale: f64 = sim.balls().iter().map(|b| b.momentum().norm()).sum();
    let e0 = sim.kinetic_energy();
    for _ in 0..20 {
        sim.advance_by(0.25).unwrap();
        let err = (sim.momentum() - p0).norm() / scale;
        assert!(err < 1e-12, "momentum error {err:e}, {:?}", sim.stats());
    }
    assert_eq!(sim.stats().wall_impacts, 0);
    assert!(sim.stats().ball_impacts > 200, "{:?}", sim.stats());
    assert!((sim.kinetic_energy() - e0).abs() < 1e-12 * e0);
}

#[test]
fn inelastic_gas_loses_exactly_the_dissipated_energy() {
    let balls = lattice_gas::<2>(6, 200, &cube(1.0), (0.02, 0.025), (0.5, 2.0), 1.0);
    let law = Law::with_dissipation(0.002).unwrap();
    let mut sim = Reference::new(balls, cube(1.0), Vector2::zeros(), law).unwrap();
    let e0 = sim.kinetic_energy();
    sim.advance_to(1.0).unwrap();
    let s = *sim.stats();
    assert!(s.impacts() > 2_000, "{s:?}");
    assert!(s.dissipated > 0.01 * e0, "{s:?}");
    let lost = e0 - sim.kinetic_energy();
    assert!(
        (lost - s.dissipated).abs() < 1e-11 * e0,
        "lost {lost}, dissipated {}",
        s.dissipated
    );
}

#[test]
fn trajectory_does_not_depend_on_how_time_is_split() {
    let balls = lattice_gas::<2>(7, 100, &cube(1.0), (0.02, 0.03), (0.5, 2.0), 1.0);
    let mut one = Reference::new(
        balls.clone(),
        cube(1.0),
        Vector2::new(0.0, -1.0),
        Law::elastic(),
    )
    .unwrap();
    let mut many = one.clone();
    one.advance_to(2.0).unwrap();
    let mut rng = Rng::new(99);
    while many.time() < 2.0 {
        let t = (many.time() + rng.range(0.0, 0.01)).min(2.0);
        many.advance_to(t).unwrap();
    }
    assert_eq!(one.balls(), many.balls());
    assert_eq!(one.stats().impacts(), many.stats().impacts());
    assert!(one.stats().impacts() > 1000);
}

#[test]
fn wall_impulse_gives_the_ideal_gas_pressure_when_dilute() {
    // 400 small disks (packing 0.01): P A ≈ N k T per unit area, i.e. the
    // impulse per unit time and length on each wall is close to E / L² for
    // equal masses in 2D (N k T = E in 2D).
    let balls = lattice_gas::<2>(8, 400, &cube(1.0), (0.003, 0.003), (1.0, 1.0), 1.0);
    let mut sim = Reference::new(balls, cube(1.0), Vector2::zeros(), Law::elastic()).unwrap();
    let energy = sim.kinetic_energy();
    sim.advance_to(50.0).unwrap();
    let s = sim.stats();
    let total: f64 = s.wall_impulse.iter().flatten().sum();
    // Four walls of length 1 over a time of 50.
    let pressure = total / (4.0 * 50.0);
    assert!(
        (pressure / energy - 1.0).abs() < 0.05,
        "P = {pressure}, E = {energy}"
    );
}
