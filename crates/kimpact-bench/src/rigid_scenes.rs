// The rigid-body scenes (marked boxes, whose impacts every law mode governs
// as rigid bodies). Included after scene.rs into the same modules.

impl Bench {
    /// 3D dice, the bundled `scenes/dice3d.ron` at scale: `count` cubes
    /// (edges 10 and 16 cm at 1 g/cm³, alternately) on a grid filling a
    /// closed box, thrown with random orientations, velocities (≤ 2 m/s)
    /// and spins (≤ 9 rad/s) under gravity; restitution 0.5 everywhere.
    fn dice(mode: Mode, count: usize, rng: &mut Xoshiro256PlusPlus) -> Self {
        let mut b = Self::new(mode, Law::from_restitution(0.5, 0.5), -Vector::Y * 9.81);
        let material = (0.4, 0.5);
        let spacing = 0.4;
        let side = per_side(count);
        b.closed_box(Vector::splat(0.5 * spacing * side as Real), 0.1, material);
        // Velocities from their own generator (the uniform draws borrow
        // `rng` for the orientations and spins).
        let mut rng_velocity = Xoshiro256PlusPlus::seed_from_u64(rng.random());
        let mut uniform = |scale: Real| scale * rng.random_range(-1.0..1.0) as Real;
        let pi = std::f64::consts::PI as Real;
        for i in 0..count {
            let (half, mass) = [(0.05, 1.0), (0.08, 4.096)][i % 2];
            let rotation = xyz(uniform(pi), uniform(pi), uniform(pi));
            let velocity = random_vector(&mut rng_velocity, 2.0);
            let spin = xyz(uniform(9.0), uniform(9.0), uniform(9.0));
            let body = RigidBodyBuilder::dynamic()
                .translation(grid_point(i, side, spacing))
                .rotation(rotation)
                .linvel(velocity)
                .angvel(spin);
            b.mark(body, cuboid(Vector::splat(half)), mass, material);
        }
        b
    }

    /// 2D dominoes, the bundled `scenes/dominoes2d.ron` in rows: `count`
    /// dominoes (2 × 10 cm, 10 g) 6 cm apart in rows of 20 on one floor, the
    /// first of each row turning at 10 rad/s so that every row topples;
    /// steps of 1/120 s, restitution 0.3 everywhere.
    fn dominoes(mode: Mode, count: usize) -> Self {
        let mut b = Self::new(mode, Law::from_restitution(0.3, 0.3), -Vector::Y * 9.81);
        b.world.integration_parameters.dt = 1.0 / 120.0;
        let material = (0.5, 0.3);
        let (per_row, pitch) = (20usize, 0.06);
        let row_length = pitch * per_row as Real + 0.4;
        let rows = count.div_ceil(per_row);
        let half_floor = 0.5 * row_length * rows as Real + 0.5;
        // The floor's top at y = 0 (3D: 1 m deep; the scene is 2D).
        let mut floor = Vector::splat(1.0);
        (floor[0], floor[1]) = (half_floor, 0.05);
        let body = RigidBodyBuilder::fixed().translation(-Vector::Y * 0.05);
        let floor = cuboid(floor).friction(material.0).restitution(material.1);
        b.world.insert(body, floor);
        let mut he = Vector::splat(0.05);
        he[0] = 0.01;
        for i in 0..count {
            let (row, j) = (i / per_row, i % per_row);
            let x = -half_floor + 0.5 + row as Real * row_length + pitch * j as Real;
            let mut body = RigidBodyBuilder::dynamic().translation(xy(x, 0.05));
            if j == 0 {
                body = body.angvel(about_z(-10.0));
            }
            b.mark(body, cuboid(he), 0.01, material);
        }
        b
    }
}
