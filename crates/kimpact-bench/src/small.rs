// The small scenes of the bench (a step of a few microseconds, where
// kimpact's fixed cost per step shows): rapier's own restitution example and
// a pinball table. Included after scene.rs into the same modules.

impl Bench {
    /// rapier's examples3d/restitution3.rs (examples2d/restitution2.rs in
    /// 2D), as it is there: a fixed floor (half-extents 20 × 1 × 2, top at
    /// y = 0, restitution 1) and two rows of 11 balls (radius 0.5, rapier's
    /// default density, x = −10…10 every 2 m, dropped from y = 10 and 20)
    /// whose restitution runs from 0 to 1 along the row, sleeping allowed
    /// and rapier's default integration parameters. Every ball is marked
    /// with a material of that restitution against the other balls and of
    /// rapier's combined one (the average with the floor's 1) against the
    /// floor, `LawParams::from_restitution(e, (1 + e)/2)`.
    fn restitution(mode: Mode) -> Self {
        let mut b = Self::new(mode, 0.0, -Vector::Y * 9.81);
        let (ground_size, ground_height) = (20.0, 1.0);
        let mut he = Vector::splat(2.0);
        he[0] = ground_size;
        he[1] = ground_height;
        let floor = RigidBodyBuilder::fixed().translation(-Vector::Y * ground_height);
        b.world
            .insert(floor, cuboid(he).restitution(1.0));
        let (num, rad) = (10usize, 0.5);
        for j in 0..2 {
            for i in 0..=num {
                let x = i as Real - num as Real / 2.0;
                let e = i as Real / num as Real;
                let body =
                    RigidBodyBuilder::dynamic().translation(xy(2.0 * x, 10.0 * (j as Real + 1.0)));
                let collider = b.hooked_if_asked(ColliderBuilder::ball(rad).restitution(e));
                let (_, c) = b.world.insert(body, collider);
                let material = LawParams::from_restitution(e, 0.5 * (1.0 + e))
                    .and_then(k::Material::from_params)
                    .expect("restitutions in [0, 1]");
                b.kimpact
                    .mark_with(&b.world.colliders, c, material)
                    .expect("inserted just above");
            }
        }
        b
    }

    /// A pinball table seen from above, in SI units: 0.5 × 1 m, tilted by
    /// 6.5° (gravity 9.81 sin 6.5° down the table, along −y), its outline a
    /// closed polyline (walls, a rounded top, the inlanes down to the
    /// flippers' pivots and a drain below them), three fixed round bumpers,
    /// two kinematic flippers (8 cm) swung up and down together through 0.9 rad
    /// every 0.25 s (a sinusoidal angular velocity set before each step), and
    /// three marked balls (radius 13.5 mm, 80 g, CCD on, never asleep) thrown
    /// from the top at up to 1 m/s. The law: `d̃` of restitution 0.8 between
    /// balls, 0.6 against the table (`LawParams::from_restitution`).
    fn pinball(mode: Mode, rng: &mut Xoshiro256PlusPlus) -> Self {
        let params = LawParams::from_restitution(0.8, 0.6).expect("in [0, 1]");
        let mut b = Self::new(
            mode,
            params.dissipation,
            -Vector::Y * (9.81 * (6.5f64).to_radians().sin()) as Real,
        );
        b.kimpact
            .set_law(params)
            .expect("from_restitution gives a valid law");
        let wall = (0.1, 0.6);
        let ball = (0.1, 0.8);
        let (half_w, top) = (0.25, 1.0);
        let (pivot_x, pivot_y) = (0.1, 0.12);
        let mut outline = vec![
            xy(-pivot_x, pivot_y),
            xy(-half_w, 0.25),
            xy(-half_w, 0.85),
        ];
        // The rounded top: a half circle through the side walls' tops.
        let arc = 12;
        for i in 1..arc {
            let a = std::f64::consts::PI as Real * (1.0 - i as Real / arc as Real);
            outline.push(xy(half_w * a.cos(), 0.85 + (top - 0.85) * a.sin()));
        }
        outline.extend([
            xy(half_w, 0.85),
            xy(half_w, 0.25),
            xy(pivot_x, pivot_y),
            xy(pivot_x, 0.0),
            xy(-pivot_x, 0.0),
            xy(-pivot_x, pivot_y),
        ]);
        let table = b.world.insert_body(RigidBodyBuilder::fixed());
        let collider = ColliderBuilder::polyline(outline, None)
            .friction(wall.0)
            .restitution(wall.1);
        b.world.insert_collider(collider, Some(table));
        for (x, y) in [(-0.08, 0.62), (0.08, 0.62), (0.0, 0.74)] {
            let bumper = RigidBodyBuilder::fixed().translation(xy(x, y));
            let collider = ColliderBuilder::ball(0.025)
                .friction(wall.0)
                .restitution(0.9);
            b.world.insert(bumper, collider);
        }
        // Flippers: a bar from the pivot, resting 0.5 rad below the
        // horizontal, swung up by 0.9 rad and back, period 0.25 s.
        let (length, thickness, rest) = (0.08, 0.008, 0.5);
        let mut bar = Vector::splat(thickness);
        bar[0] = 0.5 * length;
        for side in [-1.0, 1.0] {
            let body = RigidBodyBuilder::kinematic_velocity_based()
                .translation(xy(side * (pivot_x - 0.005), pivot_y + 0.005))
                .rotation(about_z(side * rest));
            let collider = cuboid(bar)
                .translation(xy(-side * 0.5 * length, 0.0))
                .friction(wall.0)
                .restitution(wall.1);
            let (h, _) = b.world.insert(body, collider);
            b.drives.push(Drive {
                body: h,
                amplitude: 0.45,
                period: 0.25,
                // up: counterclockwise on the left, clockwise on the right
                sign: -side,
            });
        }
        for x in [-0.12, 0.0, 0.12] {
            let mut v = random_vector(rng, 1.0);
            for axis in (0..DIM).skip(2) {
                v[axis] = 0.0;
            }
            let body = RigidBodyBuilder::dynamic()
                .translation(xy(x, 0.85))
                .linvel(v)
                .ccd_enabled(true)
                .can_sleep(false);
            b.ball(body, 0.0135, 0.08, ball);
        }
        b
    }
}
