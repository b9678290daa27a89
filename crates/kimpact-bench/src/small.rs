// The small scenes (a step of a few microseconds, where kimpact's fixed cost
// per step shows). Included after scene.rs into the same modules.

impl Bench {
    /// rapier's examples3d/restitution3.rs (examples2d/restitution2.rs in
    /// 2D) as it is there: a floor of restitution 1 and two rows of 11 balls
    /// dropped from y = 10 and 20, whose restitution `e` runs from 0 to 1
    /// along the row. Each ball is marked with the material
    /// `LawParams::from_restitution(e, (1 + e)/2)` (against the floor,
    /// rapier's average of the two).
    fn restitution(mode: Mode) -> Self {
        let mut b = Self::new(mode, Law::with_dissipation(0.0), -Vector::Y * 9.81);
        let (ground_size, ground_height) = (20.0, 1.0);
        let mut he = Vector::splat(2.0);
        he[0] = ground_size;
        he[1] = ground_height;
        let floor = RigidBodyBuilder::fixed().translation(-Vector::Y * ground_height);
        b.world.insert(floor, cuboid(he).restitution(1.0));
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

    /// A pinball table seen from above, 0.5 × 1 m, tilted by 6.5° (gravity
    /// along −y): a closed polyline outline (walls, a rounded top, inlanes
    /// and a drain), three round bumpers, two kinematic flippers swung
    /// together through 0.9 rad every 0.25 s, and three marked balls
    /// (13.5 mm, 80 g, CCD) thrown from the top; the law of restitution 0.8
    /// between balls, 0.6 against the table.
    fn pinball(mode: Mode, rng: &mut Xoshiro256PlusPlus) -> Self {
        let tilted = -Vector::Y * (9.81 * (6.5f64).to_radians().sin()) as Real;
        let mut b = Self::new(mode, Law::from_restitution(0.8, 0.6), tilted);
        let wall = (0.1, 0.6);
        let ball = (0.1, 0.8);
        let (half_w, top) = (0.25, 1.0);
        let (pivot_x, pivot_y) = (0.1, 0.12);
        let mut outline = vec![xy(-pivot_x, pivot_y), xy(-half_w, 0.25), xy(-half_w, 0.85)];
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
        let table = ColliderBuilder::polyline(outline, None);
        let table = table.friction(wall.0).restitution(wall.1);
        b.world.insert(RigidBodyBuilder::fixed(), table);
        for (x, y) in [(-0.08, 0.62), (0.08, 0.62), (0.0, 0.74)] {
            let bumper = RigidBodyBuilder::fixed().translation(xy(x, y));
            let collider = ColliderBuilder::ball(0.025)
                .friction(wall.0)
                .restitution(0.9);
            b.world.insert(bumper, collider);
        }
        // Flippers: a bar from the pivot, resting 0.5 rad below the
        // horizontal, swung up by 0.9 rad and back (see `Bench::step`).
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
            // up: counterclockwise on the left, clockwise on the right
            b.flippers.push((h, -side));
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
            b.mark(body, ColliderBuilder::ball(0.0135), 0.08, ball);
        }
        b
    }
}
