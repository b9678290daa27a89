//! An elastic hard-disk gas in a closed box, rapier2d, every mode, written
//! with `PhysicsPipeline::step` and its sets (the other drop-in form; see
//! `cradle2d.rs` for `PhysicsWorld`).
//!
//! `cargo run -p kimpact2d --example gas2d`
//!
//! 200 disks with restitution 1 bounce in a box for 3,000 steps. Plain
//! rapier loses kinetic energy; kimpact's `exact` mode keeps it to rounding.
//! The lines marked `kimpact:` are the whole change.

use kimpact2d::prelude::*;
use kimpact2d::rapier::prelude::*;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

fn run(mode: Mode) -> (f32, f32, u64) {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let mut pipeline = PhysicsPipeline::new();
    let params = IntegrationParameters::default();
    let mut islands = IslandManager::new();
    let mut broad_phase = DefaultBroadPhase::default();
    let mut narrow_phase = NarrowPhase::new();
    let mut impulse_joints = ImpulseJointSet::new();
    let mut multibody_joints = MultibodyJointSet::new();
    let mut soft_bodies = SoftBodySet::new();
    let mut ccd = CCDSolver::new();
    let mut kimpact = Kimpact::new(Law::elastic(), mode); // kimpact: the resolver

    let half = 15.0;
    for (c, h) in [
        (Vector::new(half + 1.0, 0.0), Vector::new(1.0, half + 2.0)),
        (Vector::new(-half - 1.0, 0.0), Vector::new(1.0, half + 2.0)),
        (Vector::new(0.0, half + 1.0), Vector::new(half + 2.0, 1.0)),
        (Vector::new(0.0, -half - 1.0), Vector::new(half + 2.0, 1.0)),
    ] {
        let wall = bodies.insert(RigidBodyBuilder::fixed().translation(c));
        let collider = ColliderBuilder::cuboid(h.x, h.y)
            .restitution(1.0)
            .friction(0.0);
        colliders.insert_with_parent(collider, wall, &mut bodies);
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let mut rnd = || rng.random_range(-1.0f32..1.0);
    for i in 0..200 {
        let p = Vector::new(-14.0 + 2.0 * (i % 15) as f32, -14.0 + 2.0 * (i / 15) as f32);
        let v = Vector::new(3.0 * rnd(), 3.0 * rnd());
        let body = bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(p)
                .linvel(v)
                .can_sleep(false),
        );
        let collider = ColliderBuilder::ball(0.5).restitution(1.0).friction(0.0);
        let handle = colliders.insert_with_parent(collider, body, &mut bodies);
        kimpact
            .mark(&colliders, handle)
            .expect("inserted just above"); // kimpact: this disk follows the law
    }
    let energy = |b: &RigidBodySet| {
        b.iter()
            .map(|(_, b)| 0.5 * b.mass() * b.linvel().length_squared())
            .sum::<f32>()
    };
    let e0 = energy(&bodies);
    for _ in 0..3000 {
        // kimpact: was `pipeline.step(Vector::ZERO, &params, ..., &(), &())`
        let sets = StepSets {
            islands: &mut islands,
            broad_phase: &mut broad_phase,
            narrow_phase: &mut narrow_phase,
            bodies: &mut bodies,
            colliders: &mut colliders,
            impulse_joints: &mut impulse_joints,
            multibody_joints: &mut multibody_joints,
            soft_bodies: &mut soft_bodies,
            ccd_solver: &mut ccd,
        };
        kimpact.step(&mut pipeline, Vector::ZERO, &params, sets, &(), &());
    }
    (e0, energy(&bodies), kimpact.stats().impacts)
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
