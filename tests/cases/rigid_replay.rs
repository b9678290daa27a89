// The rigid replay of impulse and exact mode (issue 39): rigid bodies'
// impacts at their time of impact, written once for 2D/3D and f32/f64
// (included by tests/adapter.rs after cases/rigid_modes.rs, whose helpers it
// uses). The dice in a box are f64 only (`dice_check`, called from
// adapter.rs).

/// The two modes whose replay moves rigid bodies.
const REPLAY_MODES: [Mode; 2] = [Mode::Impulse, Mode::Exact];

/// A marked, frictionless cube of half-size `half` and mass 1 at
/// `position`, moving at `velocity`, that never sleeps.
fn replay_cube(w: &mut TestWorld, position: Vector, velocity: Vector, half: Real) -> RigidBodyHandle {
    let body = RigidBodyBuilder::dynamic()
        .translation(position)
        .linvel(velocity)
        .can_sleep(false);
    let collider = world::cuboid(Vector::splat(half))
        .mass(1.0)
        .friction(0.0)
        .restitution(0.0);
    let (b, c) = w.world.insert(body, collider);
    w.kimpact.mark(&w.world.colliders, c).unwrap();
    b
}

/// A Newton's cradle of four equal cubes face to face along x, elastic,
/// without gravity: the first, moving at 2 m/s, strikes the row; its
/// velocity passes to the last (an elastic impact of equal masses at a
/// face's centre exchanges the velocities), and the others end at rest,
/// unturned, in one step of impacts: three events, in order along the row.
#[test]
fn a_cradle_of_cubes_passes_the_first_s_velocity_to_the_last() {
    let speed = 2.0 as Real;
    for mode in REPLAY_MODES {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let half = 0.25;
        let first = replay_cube(&mut w, Vector::X * -0.6, Vector::X * speed, half);
        let row: Vec<RigidBodyHandle> = (0..3)
            .map(|i| replay_cube(&mut w, Vector::X * (i as Real * 2.0 * half), Vector::ZERO, half))
            .collect();
        let mut events = Vec::new();
        for _ in 0..30 {
            w.step();
            events.extend(w.kimpact.events().iter().copied());
        }
        let last = *row.last().unwrap();
        let scale = f64::from(speed);
        let got = w.vel(last).to_xyz();
        assert!(
            (got[0] - scale).abs() < tol() * scale && got[1].abs() + got[2].abs() < tol() * scale,
            "{mode}: the last cube moves at {got:?}; events {events:?}"
        );
        for b in std::iter::once(first).chain(row[..2].iter().copied()) {
            let v = w.vel(b).to_xyz();
            let spin = AboutZ::size(&w.world.bodies[b].angvel());
            assert!(dot3(v, v).sqrt() < tol() * scale, "{mode}: a cube still moves at {v:?}");
            assert!(spin < tol() * scale, "{mode}: a cube turns at {spin}");
        }
        assert_eq!(events.len(), 3, "{mode}: {events:?}");
        assert!(events.iter().all(|e| !e.by_solver && f64::from(e.restitution) == 1.0));
        assert!(events.windows(2).all(|p| p[0].time <= p[1].time && p[0].point.x < p[1].point.x));
    }
}

/// A capsule lying across a heightfield's valley (3D: spinning about its
/// own axis) lands on both its slopes at once (two manifolds, one per
/// triangle or segment), without gravity, elastic: the replay resolves the
/// two contacts one after the other, each by the law, and the kinetic
/// energy (translation and rotation) is never above its start by more than
/// rounding over the run.
#[test]
fn a_capsule_landing_in_a_heightfield_valley_never_gains_energy() {
    for mode in REPLAY_MODES {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let fixed = w.world.insert_body(RigidBodyBuilder::fixed());
        w.world.insert_collider(valley_heightfield(), Some(fixed));
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::Y * 1.0)
            .linvel(Vector::Y * -3.0)
            .angvel(AngVector::xyz(2.0, 0.0, 0.0))
            .can_sleep(false);
        let capsule = ColliderBuilder::capsule_x(0.6, 0.2).mass(1.0).friction(0.0).restitution(0.0);
        let (_, c) = w.world.insert(body, capsule);
        w.kimpact.mark(&w.world.colliders, c).unwrap();
        let e0 = kinetic_with_rotation(&w);
        let (mut rise, mut impacts, mut most_in_a_step) = (0.0f64, 0usize, 0usize);
        for _ in 0..60 {
            w.step();
            let n = w.kimpact.events().iter().filter(|e| !e.by_solver).count();
            impacts += n;
            most_in_a_step = most_in_a_step.max(n);
            rise = rise.max(kinetic_with_rotation(&w) / e0 - 1.0);
        }
        eprintln!("{mode}: {impacts} impacts, at most {most_in_a_step} in a step; energy rise {rise:e}");
        assert!(impacts >= 2 && most_in_a_step >= 2, "{mode}: {impacts} impacts, {most_in_a_step} in a step");
        assert!(rise <= ROUNDING, "{mode}: the energy rose by {rise:e}");
    }
}

/// A fast cube skimming a room made of one fixed compound collider (a
/// floor and a thin wall, marked) strikes the floor and, within the same
/// step, the wall, which it would otherwise cross whole before the
/// step's end: in both replay modes both impacts are the law's, the cube
/// comes back from the wall (elastic, its x velocity reversed) and never
/// ends a step beyond it.
#[test]
fn a_cube_bouncing_off_a_compound_floor_meets_its_wall() {
    let (half, wall_x, wall_half) = (0.1, 0.3, 0.01);
    for mode in REPLAY_MODES {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let mut floor_half = Vector::splat(2.0);
        floor_half[1] = 0.5;
        let mut wall_extents = Vector::splat(2.0);
        wall_extents[0] = wall_half;
        let mut wall_at = Vector::Y * 2.0;
        wall_at[0] = wall_x + wall_half;
        let room = ColliderBuilder::compound(vec![
            (
                Pose::from_translation(Vector::Y * -0.5),
                SharedShape::new(k::rapier::parry::shape::Cuboid::new(floor_half)),
            ),
            (
                Pose::from_translation(wall_at),
                SharedShape::new(k::rapier::parry::shape::Cuboid::new(wall_extents)),
            ),
        ])
        .friction(0.0)
        .restitution(0.0);
        let fixed = w.world.insert_body(RigidBodyBuilder::fixed());
        let room = w.world.insert_collider(room, Some(fixed));
        w.kimpact.mark(&w.world.colliders, room).unwrap();
        // 1 cm above the floor, 60 m/s towards the wall 0.2 m ahead: the
        // floor at 3.3 ms, the wall at 5 ms, past it by 8.7 ms.
        let mut v = Vector::Y * -3.0;
        v[0] = 60.0;
        let cube = replay_cube(&mut w, Vector::Y * (half + 0.01), v, half);
        let mut walls = 0;
        for step in 0..3 {
            w.step();
            walls += w
                .kimpact
                .events()
                .iter()
                .filter(|e| !e.by_solver && e.normal[0].abs() > 0.9)
                .count();
            let x = w.pos(cube)[0];
            assert!(x < wall_x, "{mode}, step {step}: the cube is at x = {x}, beyond the wall");
        }
        assert_eq!(walls, 1, "{mode}: the wall's impacts");
        assert!(w.vel(cube)[0] < -59.0, "{mode}: {:?}", w.vel(cube));
    }
}

/// Dice of mixed sizes (cubes of half-size 0.15 to 0.35), random
/// orientations, velocities and spins, elastic, in a closed box without
/// gravity, rapier's default sleeping, exact mode: the kinetic energy
/// (translation and rotation) is kept to 1e-9 over `steps` steps, every
/// die stays in the box, and after the first 30 steps no overlap is
/// deeper than 1 mm. Cubes turn freely at a constant angular velocity
/// (their inertia is the same about every axis), so every change of energy
/// would be an impact's. The dice may turn faster than rapier's cap of π/4
/// per step (`RigidBody::set_allow_fast_rotation`), which would otherwise
/// take the energy of a light die spun up by a corner impact. `seed`
/// throws the dice. f64 (called from adapter.rs).
#[allow(dead_code)]
fn dice_check(steps: usize, seed: u64) {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
    let half_box = 2.0;
    w.closed_box(half_box, 0.5);
    let mut dice = Vec::new();
    let count = if DIM == 2 { 10 } else { 12 };
    let unit = |rng: &mut rand::rngs::Xoshiro256PlusPlus| rng.random_range(-1.0..1.0) as Real;
    for i in 0..count {
        // On a grid 0.8 apart: two large dice turned towards each other
        // may overlap at the start (they part within a few steps).
        let mut p = Vector::ZERO;
        p[0] = -1.2 + 0.8 * (i % 4) as Real;
        p[1] = -1.2 + 0.8 * ((i / 4) % 4) as Real;
        let mut v = Vector::ZERO;
        for a in 0..DIM {
            v[a] = 3.0 * unit(&mut rng);
        }
        let half = 0.15 + 0.2 * (0.5 + 0.5 * unit(&mut rng));
        let body = RigidBodyBuilder::dynamic()
            .translation(p)
            .rotation(AngVector::xyz(3.0 * unit(&mut rng), 3.0 * unit(&mut rng), 3.0 * unit(&mut rng)))
            .linvel(v)
            .angvel(AngVector::xyz(4.0 * unit(&mut rng), 4.0 * unit(&mut rng), 4.0 * unit(&mut rng)));
        let collider = world::cuboid(Vector::splat(half))
            .density(1.0)
            .friction(0.0)
            .restitution(0.0);
        let (b, c) = w.world.insert(body, collider);
        // rapier caps a body's turn at π/4 per step (47 rad/s at 60 Hz)
        // unless told otherwise: a light die struck on a corner spins
        // faster, and the cap would take energy the law gave it.
        w.world.bodies[b].set_allow_fast_rotation(true);
        w.kimpact.mark(&w.world.colliders, c).unwrap();
        dice.push(b);
    }
    let e0 = kinetic_with_rotation(&w);
    let mut worst = 0.0f64;
    let mut deepest = 0.0f64;
    for step in 0..steps {
        w.step();
        let e = kinetic_with_rotation(&w);
        worst = worst.max(((e - e0) / e0).abs());
        assert!(
            worst < 1e-9,
            "seed {seed}, step {step}: energy {e0} -> {e} ({worst:e}); events {:?}",
            w.kimpact.events()
        );
        // The deepest overlap rapier's narrow phase meets (at the start of
        // the step), once the dice placed overlapping on the grid have
        // parted (by step 16 in seeds 1 to 24).
        if step > 30 {
            for cp in w.world.narrow_phase.contact_pairs() {
                for m in cp.manifolds() {
                    for p in &m.points {
                        deepest = deepest.min(p.dist as f64);
                    }
                }
            }
        }
    }
    let inside = dice.iter().all(|&b| {
        let p = w.pos(b);
        (0..DIM).all(|a| p[a].abs() < half_box)
    });
    eprintln!(
        "dice {DIM}D, seed {seed}: {steps} steps, {} impacts, energy kept to {worst:e}, deepest overlap {deepest:e}",
        w.kimpact.stats().impacts
    );
    assert!(inside, "a die left the box");
    // The impacts are met at their times: no die sinks into another or a
    // wall by more than 1 mm (a third of a percent of the smallest die's
    // side, 0.3).
    assert!(deepest > -1e-3, "seed {seed}: an overlap of {deepest}");
}

/// Exact mode keeps the dice's energy over a few hundred steps in every
/// build (`dice_check`; the 10,000-step run is f64's, in adapter.rs).
#[test]
fn dice_in_a_box_keep_their_energy_in_exact_mode() {
    if std::mem::size_of::<Real>() == 8 {
        dice_check(600, 7);
    }
}
