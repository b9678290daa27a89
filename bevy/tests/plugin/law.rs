//! The law through the plugin: Newton's cradle and an elastic gas in every
//! timestep mode and with substeps, native mode bit for bit bevy_rapier's,
//! and kimpact standing aside from a second rapier step.

use bevy::prelude::*;

use crate::bk::bevy_rapier::prelude::*;
use crate::bk::prelude::*;
use crate::harness::{CRADLE_FRAMES, Cradle, DIM, Rapier, Setup, Timing, cradle, gas, vect};

/// The cradle's law result: (0, 0, 0, 0, 0, 1) to 1e-5, its energy kept
/// to 1e-5, one impact message per touching pair, in order down the row.
fn assert_law_cradle(c: &Cradle, timing: Timing) {
    for (i, &b) in c.balls.iter().enumerate() {
        let expect = if i == 5 { 1.0 } else { 0.0 };
        let v = c.test.vel(b);
        assert!(
            (v - vect(expect, 0.0, 0.0)).length() < 1e-5,
            "{timing:?}: ball {i} has {v:?}"
        );
    }
    assert!(
        ((c.e1 - c.e0) / c.e0).abs() < 1e-5,
        "{timing:?}: energy {} -> {}",
        c.e0,
        c.e1
    );
    let pairs: Vec<_> = c
        .messages
        .iter()
        .map(|m| {
            let i = c.balls.iter().position(|&b| b == m.collider1).unwrap();
            let j = c.balls.iter().position(|&b| b == m.collider2).unwrap();
            (i.min(j), i.max(j))
        })
        .collect();
    assert_eq!(
        pairs,
        [(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)],
        "{timing:?}"
    );
    assert_eq!(c.test.state().stats().impacts, 5, "{timing:?}");
}

#[test]
fn exact_newtons_cradle_passes_the_velocity_down_the_row() {
    for timing in [
        Timing::Fixed(1),
        Timing::Variable(1),
        Timing::FixedUpdate(1),
        Timing::Interpolated {
            rounds: 1.0,
            substeps: 1,
        },
    ] {
        let c = cradle(Setup::new().timing(timing));
        assert_law_cradle(&c, timing);
    }
}

#[test]
fn every_step_of_a_frame_of_several_follows_the_law() {
    // Substeps, and rounds of `Interpolated` (two or three a frame).
    let timings = [
        Timing::Fixed(3),
        Timing::Variable(3),
        Timing::FixedUpdate(2),
        Timing::Interpolated {
            rounds: 2.5,
            substeps: 1,
        },
        Timing::Interpolated {
            rounds: 3.0,
            substeps: 2,
        },
    ];
    for timing in timings {
        let c = cradle(Setup::new().timing(timing));
        assert_law_cradle(&c, timing);
        // kimpact's stages ran around every pipeline step: the frames of the
        // run (the first update and the cradle's) at the steps per frame.
        let steps = c.test.state().stats().steps;
        let frames = CRADLE_FRAMES as u64 + 1;
        let expect = match timing {
            Timing::Fixed(n) => frames * n as u64,
            // Variable's first frame has no time (no step).
            Timing::Variable(n) => (frames - 1) * n as u64,
            // One fixed tick a frame but the first.
            Timing::FixedUpdate(n) => (frames - 1) * n as u64,
            Timing::Interpolated { rounds, substeps } => {
                ((frames - 1) as f32 * rounds).round() as u64 * substeps as u64
            }
        };
        // Interpolated's rounds follow the render by float sums: one round
        // more or less.
        let slack = match timing {
            Timing::Interpolated { substeps, .. } => substeps as u64,
            _ => 0,
        };
        assert!(
            steps.abs_diff(expect) <= slack,
            "{timing:?}: {steps} steps through kimpact, {expect} expected"
        );
    }
}

/// The gas in exact mode for `frames`: its energy kept to 1e-5, one message
/// per impact, no ball out of the box.
fn assert_gas_keeps_its_energy(timing: Timing, frames: usize) {
    let mut test = Setup::new().timing(timing).build();
    let balls = gas(&mut test, 100);
    test.app.update();
    let e0 = test.kinetic(&balls);
    let messages = test.run(frames);
    let e1 = test.kinetic(&balls);
    let stats = test.state().stats();
    eprintln!(
        "gas {DIM}D {timing:?}: {} steps, {} impacts, energy {e0} -> {e1} ({:.2e})",
        stats.steps,
        stats.impacts,
        (e1 - e0) / e0
    );
    assert!(
        stats.impacts > 500,
        "{timing:?}: only {} impacts",
        stats.impacts
    );
    assert_eq!(
        messages.len() as u64,
        stats.impacts,
        "one message per impact"
    );
    assert!(
        ((e1 - e0) / e0).abs() < 1e-5,
        "{timing:?}: energy {e0} -> {e1}"
    );
    for &(b, _) in &balls {
        let p = test.pos(b);
        assert!(p.abs().max_element() < 5.0, "{b} escaped to {p:?}");
    }
}

#[test]
fn an_elastic_gas_keeps_its_energy_in_exact_mode() {
    assert_gas_keeps_its_energy(Timing::Fixed(1), 600);
}

#[test]
fn an_elastic_gas_keeps_its_energy_over_substeps() {
    // The same 10 s, in steps of half the frame.
    assert_gas_keeps_its_energy(Timing::Fixed(2), 600);
    assert_gas_keeps_its_energy(Timing::Variable(2), 600);
}

/// Bits of every ball's position, rotation and velocity after `frames` (and
/// of the context's dt and time behind the render), and bevy_rapier's
/// collision events.
fn gas_bits(setup: Setup, frames: usize) -> (Vec<u32>, Vec<CollisionEvent>) {
    let mut test = setup.build();
    let balls = gas(&mut test, 100);
    let (_, collisions) = test.run_with_collisions(frames);
    let world = test.app.world_mut();
    let (simulation, to_render) = world
        .query::<(&RapierContextSimulation, &SimulationToRenderTime)>()
        .single(world)
        .expect("one context");
    let mut bits = vec![
        simulation.integration_parameters.dt.to_bits(),
        to_render.diff.to_bits(),
    ];
    for &(b, _) in &balls {
        let world = test.app.world();
        let t = world.get::<Transform>(b).unwrap();
        let v = world.get::<Velocity>(b).unwrap();
        bits.extend(t.translation.to_array().map(f32::to_bits));
        bits.extend(t.rotation.to_array().map(f32::to_bits));
        bits.extend(v.linear.to_array().map(f32::to_bits));
        #[cfg(feature = "dim2")]
        bits.push(v.angular.to_bits());
        #[cfg(feature = "dim3")]
        bits.extend(v.angular.to_array().map(f32::to_bits));
    }
    (bits, collisions)
}

#[test]
fn native_mode_leaves_bevy_rapier_unchanged_bit_for_bit() {
    // kimpact's step system runs bevy_rapier's steps one by one: the same
    // bodies (interpolated ones too) and collision events as bevy_rapier's
    // own step system, in every timestep mode. The reference is the same
    // app with bevy_rapier's own step (kimpact standing aside): bevy_rapier's
    // results change by rounding with the app's archetypes (one more
    // resource is enough), so the two apps have the same plugins.
    let timings = [
        Timing::Fixed(1),
        Timing::Fixed(3),
        Timing::Variable(2),
        Timing::Interpolated {
            rounds: 2.5,
            substeps: 2,
        },
        Timing::FixedUpdate(2),
    ];
    for timing in timings {
        let rapiers = gas_bits(Setup::new().rapier(Rapier::AlsoBefore).timing(timing), 200);
        assert!(!rapiers.1.is_empty(), "{timing:?}: no collision event");
        let native = gas_bits(Setup::new().mode(Mode::Native).timing(timing), 200);
        assert!(native.0 == rapiers.0, "{timing:?}: the bodies differ");
        assert_eq!(
            native.1, rapiers.1,
            "{timing:?}: the collision events differ"
        );
        // The comparison can tell: kimpact's law changes this scene.
        if timing == Timing::Fixed(1) {
            assert_ne!(gas_bits(Setup::new().timing(timing), 200).0, rapiers.0);
        }
    }
}

#[test]
fn a_rapier_plugin_beside_kimpacts_makes_kimpact_stand_aside() {
    // A user's RapierPhysicsPlugin added before KimpactPlugin (which adds
    // its own), or bevy_rapier's step system added by hand: kimpact logs an
    // error and steps nothing, bevy_rapier runs as without it (not twice:
    // the same bodies to rounding, see the native test).
    let without = cradle(Setup::without_kimpact());
    for rapier in [Rapier::AlsoBefore, Rapier::OwnStepByHand] {
        let c = cradle(Setup::new().rapier(rapier));
        assert!(c.messages.is_empty(), "{rapier:?}: {:?}", c.messages);
        let state = c.test.state();
        assert_eq!(state.stats().steps, 0, "{rapier:?}");
        assert!(!state.is_marked(c.balls[0]), "{rapier:?}");
        for (&b, &w) in c.balls.iter().zip(&without.balls) {
            let (p, pw) = (c.test.pos(b), without.test.pos(w));
            let (v, vw) = (c.test.vel(b), without.test.vel(w));
            assert!((p - pw).length() < 1e-5, "{rapier:?}: {p:?} vs {pw:?}");
            assert!((v - vw).length() < 1e-5, "{rapier:?}: {v:?} vs {vw:?}");
        }
        // rapier's own cradle does not pass the velocity down the row.
        assert!(c.test.vel(c.balls[5]).x < 0.9, "{rapier:?}");
    }
}
