//! The README's drop-in, written as a user would, against the packaged
//! crates: Newton's cradle (five touching balls, a sixth arriving at 1 m/s)
//! through `Kimpact::step_world` in `Mode::Exact`, in 3D (with the user's
//! own `rapier3d`) and in 2D (with the rapier `kimpact2d` re-exports).
//! `cargo test` checks that the last ball leaves at 1 m/s and the others
//! are at rest; `cargo run` prints the velocities.

/// 3D, the user's own rapier3d beside kimpact3d's prelude.
mod d3 {
    use kimpact3d::prelude::*;
    use rapier3d::prelude::*;

    /// The balls' velocities along the row after two seconds.
    pub fn cradle() -> Vec<f32> {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
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
            let collider = ColliderBuilder::ball(0.5).restitution(1.0).friction(0.0);
            let (ball, collider) = world.insert(body, collider);
            kimpact
                .mark(&world.colliders, collider)
                .expect("inserted just above");
            balls.push(ball);
        }
        for _ in 0..120 {
            kimpact.step_world(&mut world, &(), &());
        }
        balls.iter().map(|&b| world.bodies[b].linvel().x).collect()
    }
}

/// 2D, through the rapier kimpact2d was built against.
mod d2 {
    use kimpact2d::prelude::*;
    use kimpact2d::rapier::prelude::*;

    /// The balls' velocities along the row after two seconds.
    pub fn cradle() -> Vec<f32> {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
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
            let (ball, collider) = world.insert(body, collider);
            kimpact
                .mark(&world.colliders, collider)
                .expect("inserted just above");
            balls.push(ball);
        }
        for _ in 0..120 {
            kimpact.step_world(&mut world, &(), &());
        }
        balls.iter().map(|&b| world.bodies[b].linvel().x).collect()
    }
}

/// The core law and the reference simulator, from their packages too: two
/// equal balls meeting head on swap velocities.
fn reference_swap() -> f64 {
    use kimpact::prelude::*;
    use kimpact_reference::nalgebra::Vector2;
    use kimpact_reference::{Ball, BoxBounds, Reference};

    let balls = vec![
        Ball::new(0.1, 1.0, Vector2::new(0.25, 0.5), Vector2::new(1.0, 0.0)),
        Ball::new(0.1, 1.0, Vector2::new(0.75, 0.5), Vector2::new(-1.0, 0.0)),
    ];
    let bounds = BoxBounds::new(Vector2::zeros(), Vector2::new(1.0, 1.0));
    let mut sim = Reference::new(balls, bounds, Vector2::zeros(), Law::elastic()).unwrap();
    sim.advance_to(0.2).unwrap();
    sim.balls()[0].velocity.x
}

fn main() {
    println!("3D cradle: {:?}", d3::cradle());
    println!("2D cradle: {:?}", d2::cradle());
    println!("reference: first ball after the swap {}", reference_swap());
}

#[cfg(test)]
mod tests {
    /// The last ball leaves at 1 m/s, the others are at rest.
    fn check(v: &[f32]) {
        assert_eq!(v.len(), 6);
        for (i, &vi) in v.iter().enumerate() {
            let expect = if i == 5 { 1.0 } else { 0.0 };
            assert!((vi - expect).abs() < 1e-5, "ball {i}: {vi}, all: {v:?}");
        }
    }

    #[test]
    fn cradle_3d_passes_the_velocity_down_the_row() {
        check(&super::d3::cradle());
    }

    #[test]
    fn cradle_2d_passes_the_velocity_down_the_row() {
        check(&super::d2::cradle());
    }

    #[test]
    fn the_reference_swaps_equal_balls() {
        assert!((super::reference_swap() + 1.0).abs() < 1e-12);
    }
}
