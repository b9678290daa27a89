//! kimpact in a program that calls `PhysicsPipeline::step` itself (its own
//! fixed-update loop, substeps, or an engine integration such as Bevy's):
//! the three stages around rapier's step, on Newton's cradle.
//!
//! `cargo run --example stages`
//!
//! The result is bit for bit that of `Kimpact::step` (a test checks it).

use kimpact3d::rapier::prelude::*;
use kimpact3d::{Kimpact, Law, Mode, StepSets};

fn main() {
    let gravity = Vector::ZERO;
    let integration_parameters = IntegrationParameters::default();
    let mut pipeline = PhysicsPipeline::new();
    let mut islands = IslandManager::new();
    let mut broad_phase = BroadPhaseBvh::new();
    let mut narrow_phase = NarrowPhase::new();
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let mut impulse_joints = ImpulseJointSet::new();
    let mut multibody_joints = MultibodyJointSet::new();
    let mut soft_bodies = SoftBodySet::new();
    let mut ccd_solver = CCDSolver::new();
    // Your own hooks and event handler, if any (kimpact chains the hooks).
    let (user_hooks, user_events) = ((), ());

    let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
    let mut balls = Vec::new();
    for i in 0..6 {
        let (x, v) = if i == 0 {
            (-2.05, 1.0)
        } else {
            ((i - 1) as f32, 0.0)
        };
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(x, 0.0, 0.0))
            .linvel(Vector::new(v, 0.0, 0.0));
        let handle = bodies.insert(body);
        let collider = ColliderBuilder::ball(0.5).restitution(1.0).friction(0.0);
        let c = colliders.insert_with_parent(collider, handle, &mut bodies);
        kimpact.mark(&colliders, c).expect("inserted just above");
        balls.push(handle);
    }

    for _ in 0..120 {
        // rapier's sets, borrowed together for the step.
        let mut sets = StepSets {
            islands: &mut islands,
            broad_phase: &mut broad_phase,
            narrow_phase: &mut narrow_phase,
            bodies: &mut bodies,
            colliders: &mut colliders,
            impulse_joints: &mut impulse_joints,
            multibody_joints: &mut multibody_joints,
            soft_bodies: &mut soft_bodies,
            ccd_solver: &mut ccd_solver,
        };
        // Stage 1: hook flags, starts, impulse mode's pass.
        let prepared = kimpact.before_step(gravity, &integration_parameters, &mut sets);
        // Stage 2: rapier's own step, with kimpact's hooks (yours chained).
        pipeline.step(
            gravity,
            &integration_parameters,
            sets.islands,
            sets.broad_phase,
            sets.narrow_phase,
            sets.bodies,
            sets.colliders,
            sets.impulse_joints,
            sets.multibody_joints,
            sets.soft_bodies,
            sets.ccd_solver,
            &kimpact.hooks(&prepared, &user_hooks),
            &user_events,
        );
        // Stage 3: exact mode's replay, the step's impact events.
        kimpact.after_step(prepared, &mut sets, &user_hooks);
        for e in kimpact.events() {
            println!(
                "impact at {:+.4} s: {:?} -> {:?}",
                e.time, e.collider1, e.collider2
            );
        }
    }
    let v: Vec<String> = balls
        .iter()
        .map(|&b| format!("{:+.3}", bodies[b].linvel().x))
        .collect();
    println!("velocities [{}]", v.join(", "));
}
