// The configurations of the effects table (see effects.rs), written once
// for 2D/3D and f32/f64: included after scene.rs into the same modules.

impl Bench {
    /// A configuration of the effects table on the base of `scene` (gas3d
    /// or gas2d; `None` for another scene or dimension): `balls` balls
    /// (radius 0.5, mass 1, the gas scenes' grid and density, thrown at up
    /// to 3 m/s, never asleep) with no effect at all, no gravity, `d̃ = 0`,
    /// no friction, no spin, no walls, nobody reading the impact events, no
    /// material, and then `effect` alone switched on:
    /// - gravity: 9.81 m/s² along −y;
    /// - dissipation: the law's `d̃ = 0.09` (the pits');
    /// - friction: 0.5 on every ball;
    /// - spin: every ball spinning about z at up to 6 rad/s;
    /// - walls: the gas scenes' closed box of fixed walls;
    /// - events: the user reads every impact event after each step;
    /// - materials: every ball marked with its own material
    ///   (`Kimpact::mark_with`), `d̃ = d̃_w = 0` as the resolver's law, so
    ///   that only the path through the materials differs.
    fn effect(effect: crate::effects::Effect, scene: Scene, balls: usize, mode: Mode) -> Option<Self> {
        use crate::effects::Effect as E;
        if scene.dim() != DIM || !matches!(scene, Scene::Gas2d | Scene::Gas3d) {
            return None;
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(42);
        let gravity = if effect == E::Gravity {
            -Vector::Y * 9.81
        } else {
            Vector::ZERO
        };
        let dissipation = if effect == E::Dissipation { 0.09 } else { 0.0 };
        let mut b = Self::new(mode, dissipation, gravity);
        let material = Material {
            friction: if effect == E::Friction { 0.5 } else { 0.0 },
            restitution: 1.0,
        };
        let law = (effect == E::Materials)
            .then(|| k::Material::new(0.0, 0.0).expect("zero is a valid dissipation"));
        let r = 0.5;
        let half = if DIM == 2 {
            22.0 * (balls as f64 / 500.0).sqrt()
        } else {
            7.0 * (balls as f64 / 500.0).cbrt()
        } as Real;
        if effect == E::Walls {
            b.closed_box(Vector::splat(half), 1.0, material);
        } else {
            // Nothing holds the balls: none escapes, none falls off a floor.
            (b.lo, b.hi, b.floor) = (-Vector::splat(half), Vector::splat(half), -half);
            b.slack = Real::INFINITY;
        }
        let side = per_side(balls);
        let spacing = 2.0 * half / side as Real;
        for i in 0..balls {
            let mut body = RigidBodyBuilder::dynamic()
                .translation(grid_point(i, side, spacing))
                .linvel(random_vector(&mut rng, 3.0))
                .can_sleep(false);
            if effect == E::Spin {
                let w = 6.0 * rng.random_range(-1.0..1.0) as Real;
                body = body.angvel(AngVector::about_z(w));
            }
            b.ball_with(body, r, 1.0, material, law);
        }
        b.read_events = effect == E::Events;
        Some(b)
    }
}
