//! An elastic hard-disk gas in a closed box, rapier2d, every mode.
//!
//! `cargo run --example gas2d`
//!
//! 200 disks with restitution 1 bounce in a box for 3,000 steps. Plain
//! rapier loses kinetic energy; kimpact's `exact` mode keeps it to rounding.

use kimpact2d::rapier::prelude::*;
use kimpact2d::{Kimpact, Law, Mode};

fn run(mode: Mode) -> (f32, f32, u64) {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::ZERO;
    let mut kimpact = Kimpact::new(Law::elastic(), mode);
    let half = 15.0;
    for (c, h) in [
        (Vector::new(half + 1.0, 0.0), Vector::new(1.0, half + 2.0)),
        (Vector::new(-half - 1.0, 0.0), Vector::new(1.0, half + 2.0)),
        (Vector::new(0.0, half + 1.0), Vector::new(half + 2.0, 1.0)),
        (Vector::new(0.0, -half - 1.0), Vector::new(half + 2.0, 1.0)),
    ] {
        let wall = world.insert_body(RigidBodyBuilder::fixed().translation(c));
        world.insert_collider(
            kimpact2d::math::cuboid(h).restitution(1.0).friction(0.0),
            Some(wall),
        );
    }
    let mut seed = 7u32;
    let mut rnd = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
    };
    for i in 0..200 {
        let p = Vector::new(-14.0 + 2.0 * (i % 15) as f32, -14.0 + 2.0 * (i / 15) as f32);
        let body = RigidBodyBuilder::dynamic()
            .translation(p)
            .linvel(Vector::new(3.0 * rnd(), 3.0 * rnd()))
            .can_sleep(false);
        let (_, c) = world.insert(
            body,
            ColliderBuilder::ball(0.5).restitution(1.0).friction(0.0),
        );
        kimpact.mark(c);
    }
    let energy = |w: &PhysicsWorld| {
        w.bodies
            .iter()
            .map(|(_, b)| 0.5 * b.mass() * b.linvel().length_squared())
            .sum::<f32>()
    };
    let e0 = energy(&world);
    for _ in 0..3000 {
        kimpact.step_world(&mut world, &(), &());
    }
    (e0, energy(&world), kimpact.stats().impacts)
}

fn main() {
    for mode in Mode::ALL {
        let (e0, e1, impacts) = run(mode);
        println!(
            "{mode:>11}: kinetic energy {e0:.3} -> {e1:.3} ({:+.4}%), law impacts {impacts}",
            100.0 * (e1 - e0) / e0
        );
    }
}
