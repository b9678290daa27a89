// A small rapier world for the tests, written once for 2D/3D and f32/f64:
// included into modules that alias the adapter crate as `k`.
#[allow(unused_imports)]
use k::math::{DIM, Real, Vector};
#[allow(unused_imports)]
use k::rapier::prelude::*;
#[allow(unused_imports)]
use k::{Kimpact, Law, LawParams, Mode};

/// A cuboid collider from its half-extents, in either dimension (rapier's
/// `ColliderBuilder::cuboid` takes one argument per axis).
pub fn cuboid(half_extents: Vector) -> ColliderBuilder {
    let shape = k::rapier::parry::shape::Cuboid::new(half_extents);
    ColliderBuilder::new(SharedShape::new(shape))
}

pub struct TestWorld {
    pub world: PhysicsWorld,
    pub kimpact: Kimpact,
}

#[allow(dead_code)]
impl TestWorld {
    pub fn new(mode: Mode, dissipation: Real, gravity: Vector) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = gravity;
        let law = Law::new(LawParams {
            dissipation,
            ..Default::default()
        })
        .unwrap();
        Self {
            world,
            kimpact: Kimpact::new(law, mode),
        }
    }

    /// A world in `mode` under `gravity`, the law elastic but for the wall
    /// dissipation `wall` (d̃w, against fixed partners).
    pub fn with_wall_dissipation(mode: Mode, wall: Real, gravity: Vector) -> Self {
        let mut w = Self::new(mode, 0.0, gravity);
        w.kimpact
            .set_law(LawParams {
                wall_dissipation: Some(wall),
                ..Default::default()
            })
            .unwrap();
        w
    }

    /// A fixed frictionless floor whose top is at y = 0 (a wall 2 thick and
    /// 40 wide).
    pub fn floor(&mut self) -> ColliderHandle {
        self.wall(Vector::Y * -1.0, Vector::splat(20.0) - Vector::Y * 19.0)
    }

    /// A marked cuboid of half-extents `half` and mass `mass` on `body`,
    /// frictionless, rapier's restitution 0 (only the law bounces it).
    pub fn marked_cuboid(&mut self, body: RigidBodyBuilder, half: Vector, mass: Real) -> RigidBodyHandle {
        let collider = cuboid(half).mass(mass).friction(0.0).restitution(0.0);
        let (b, c) = self.world.insert(body, collider);
        self.kimpact
            .mark(&self.world.colliders, c)
            .expect("inserted just above");
        b
    }

    /// A frictionless ball of mass `mass`, marked.
    pub fn ball(
        &mut self,
        position: Vector,
        velocity: Vector,
        radius: Real,
        mass: Real,
    ) -> (RigidBodyHandle, ColliderHandle) {
        let body = RigidBodyBuilder::dynamic()
            .translation(position)
            .linvel(velocity)
            .can_sleep(false);
        let collider = ColliderBuilder::ball(radius)
            .mass(mass)
            .friction(0.0)
            .restitution(1.0);
        let (b, c) = self.world.insert(body, collider);
        self.kimpact
            .mark(&self.world.colliders, c)
            .expect("inserted just above");
        (b, c)
    }

    /// A fixed box (a wall), frictionless, unmarked (walls meet the law as
    /// fixed partners).
    pub fn wall(&mut self, center: Vector, half_extents: Vector) -> ColliderHandle {
        let body = RigidBodyBuilder::fixed().translation(center);
        let b = self.world.insert_body(body);
        let collider = cuboid(half_extents).friction(0.0).restitution(1.0);
        self.world.insert_collider(collider, Some(b))
    }

    /// A closed box of inner half-size `half` centred at the origin, walls
    /// `thickness` thick.
    pub fn closed_box(&mut self, half: Real, thickness: Real) {
        let t = thickness;
        for axis in 0..DIM {
            for sign in [-1.0, 1.0] {
                let mut center = Vector::ZERO;
                center[axis] = sign * (half + t);
                let mut he = Vector::splat(half + 2.0 * t);
                he[axis] = t;
                self.wall(center, he);
            }
        }
    }

    pub fn step(&mut self) {
        self.kimpact.step_world(&mut self.world, &(), &());
    }

    pub fn vel(&self, b: RigidBodyHandle) -> Vector {
        self.world.bodies[b].linvel()
    }

    pub fn pos(&self, b: RigidBodyHandle) -> Vector {
        self.world.bodies[b].translation()
    }

    /// Positions and velocities of `balls`, as bits (for bit-for-bit
    /// comparisons).
    pub fn bits(&self, balls: &[RigidBodyHandle]) -> Vec<u64> {
        balls
            .iter()
            .flat_map(|&b| {
                let (p, v) = (self.pos(b), self.vel(b));
                (0..DIM).flat_map(move |a| [f64::from(p[a]).to_bits(), f64::from(v[a]).to_bits()])
            })
            .collect()
    }

    pub fn kinetic(&self) -> f64 {
        self.world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(_, b)| 0.5 * f64::from(b.mass()) * f64::from(b.linvel().length_squared()))
            .sum()
    }

    pub fn potential(&self) -> f64 {
        let g = self.world.gravity;
        self.world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(_, b)| -f64::from(b.mass()) * f64::from(g.dot(b.translation())))
            .sum()
    }
}
