//! Newton's cradle in rapier2d, first plain, then with kimpact.
//!
//! `cargo run -p kimpact2d --example cradle2d` (`cradle3d` in kimpact3d)
//!
//! A plain rapier simulation (restitution 1) passes only part of the
//! incoming ball's energy down the row; the same code with kimpact's
//! `exact` mode passes all of it, leaving the first five balls at rest.
//! The lines marked `kimpact:` are the whole change.

use kimpact2d::prelude::*;
use kimpact2d::rapier::prelude::*;

fn run(mode: Mode) -> Vec<Vector> {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::ZERO;
    let mut kimpact = Kimpact::new(Law::elastic(), mode); // kimpact: the resolver
    let mut balls = Vec::new();
    for i in 0..6 {
        let (x, v) = if i == 0 {
            (-2.05, 1.0)
        } else {
            ((i - 1) as f32, 0.0)
        };
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(x, 0.0))
            .linvel(Vector::new(v, 0.0));
        let collider = ColliderBuilder::ball(0.5).restitution(1.0).friction(0.0);
        let (b, c) = world.insert(body, collider);
        kimpact
            .mark(&world.colliders, c)
            .expect("inserted just above"); // kimpact: this ball follows the law
        balls.push(b);
    }
    for _ in 0..120 {
        kimpact.step_world(&mut world, &(), &()); // kimpact: instead of world.step()
    }
    balls.iter().map(|&b| world.bodies[b].linvel()).collect()
}

fn main() {
    for mode in [Mode::Native, Mode::Exact] {
        let v = run(mode);
        let energy: f32 = v.iter().map(|v| 0.5 * v.length_squared()).sum();
        let xs: Vec<String> = v.iter().map(|v| format!("{:+.3}", v.x)).collect();
        println!(
            "{mode:>7}: velocities [{}]  kinetic energy kept: {:.1}%",
            xs.join(", "),
            100.0 * energy / 0.5
        );
    }
}
