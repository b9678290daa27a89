// The law's promises in the worlds users build (rapier's defaults, gravity,
// non-ball shapes, very fast balls, overlapping spawns), written once for
// 2D/3D and f32/f64 (included by tests/adapter.rs).

/// Relative rounding of one step's energy.
const ROUNDING: f64 = if std::mem::size_of::<Real>() == 4 { 1e-5 } else { 1e-9 };

/// The energy per unit mass of the flight of a ball rapier integrates under
/// gravity `g` (pointing along −y), measured from the height `contact` at
/// which it touches the floor: `½ |v + g h/2|² + |g| (y − contact)`, with
/// `h` rapier's substep. rapier's substeps put the ball on a parabola whose
/// velocity is `v + g h/2` at the step ends, so this is constant over a
/// free flight and `|g|` times the height of its apex above the contact.
fn flight_energy(w: &TestWorld, b: RigidBodyHandle, contact: f64) -> f64 {
    let params = &w.world.integration_parameters;
    let h = f64::from(params.dt) / params.num_solver_iterations as f64;
    let g = -f64::from(w.world.gravity.y);
    let (v, y) = (w.vel(b), f64::from(w.pos(b).y));
    let speed_sq: f64 = (0..DIM)
        .map(|a| {
            let c = f64::from(v[a]) - if a == 1 { 0.5 * g * h } else { 0.0 };
            c * c
        })
        .sum();
    0.5 * speed_sq + g * (y - contact)
}

/// A frictionless ball dropped from 4.5 m onto a fixed floor under the law
/// with wall dissipation `wall`, for 1,200 steps: the energy of each flight
/// ([`flight_energy`]) while the ball is clear of the floor, one list per
/// flight.
fn bounce_flights(mode: Mode, wall: Real) -> Vec<Vec<f64>> {
    let mut w = TestWorld::with_wall_dissipation(mode, wall, Vector::Y * -9.81);
    w.wall(Vector::Y * -5.5, Vector::splat(5.0));
    let radius = 0.5;
    let (b, _) = w.ball(Vector::Y * 4.5, Vector::ZERO, radius, 1.0);
    let contact = -0.5 + f64::from(radius);
    let mut flights: Vec<Vec<f64>> = vec![vec![flight_energy(&w, b, contact)]];
    let mut falling = true;
    for _ in 0..1200 {
        w.step();
        let vy = w.vel(b).y;
        if falling && vy > 0.0 {
            flights.push(Vec::new());
        }
        falling = vy <= 0.0;
        // Clear of the floor by more than rapier's contact reach and a step.
        if f64::from(w.pos(b).y) - contact > 0.25 {
            flights.last_mut().unwrap().push(flight_energy(&w, b, contact));
        }
    }
    flights.retain(|f| !f.is_empty());
    flights
}

/// Issue 21.2: an elastic bounce under gravity keeps the apex to rounding in
/// exact and impulse mode, and `wall_dissipation` `d̃w` multiplies it by
/// `e² = 1 − 2 d̃w`. Exact mode meets the floor on the straight line between
/// the step's ends, which is off rapier's parabola by at most `g dt²/8`:
/// the dissipated share of the apex is off by at most `(1 − e²) g² dt²/8`
/// of the flight's energy. Impulse mode sees the floor when rapier's
/// contact does, often overlapping, and rewinds along the step's line
/// extended into the step before, off the parabola by at most `g dt²`
/// there: off by at most `(1 − e²) g² dt²`.
#[test]
fn a_bounce_under_gravity_keeps_its_apex() {
    let (g, dt) = (9.81, 1.0 / 60.0);
    for mode in [Mode::Impulse, Mode::Exact] {
        for wall in [0.0, 0.1] {
            let e2 = 1.0 - 2.0 * f64::from(wall);
            let flights = bounce_flights(mode, wall);
            assert!(flights.len() >= 10, "{mode}, d̃w = {wall}: {} flights", flights.len());
            for (i, f) in flights.iter().enumerate() {
                let (lo, hi) = f.iter().fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
                assert!(
                    hi - lo <= ROUNDING * hi,
                    "{mode}, d̃w = {wall}: flight {i} is not free ({lo} to {hi})"
                );
            }
            for pair in flights.windows(2) {
                let (before, after) = (pair[0][0], pair[1][0]);
                let off = match mode {
                    Mode::Exact => (1.0 - e2) * g * g * dt * dt / 8.0,
                    _ => (1.0 - e2) * g * g * dt * dt,
                } / before;
                let ratio = after / before;
                assert!(
                    (ratio - e2).abs() <= off + 4.0 * ROUNDING,
                    "{mode}, d̃w = {wall}: apex ratio {ratio}, e² = {e2} (bound {off:e})"
                );
            }
        }
    }
}

/// The corners of a box of half-extents `half` (bit `a` of the index: the
/// sign along axis `a`).
fn box_corners(half: Vector) -> Vec<Vector> {
    (0..(1usize << DIM))
        .map(|i| {
            let mut v = Vector::ZERO;
            for a in 0..DIM {
                v[a] = if i >> a & 1 == 1 { half[a] } else { -half[a] };
            }
            v
        })
        .collect()
}

/// A collider of every kind of shape the law cannot move as a point: a
/// cuboid, a capsule, a convex hull, a triangle mesh, and a ball off its
/// body's centre.
fn extended_shapes() -> Vec<(&'static str, ColliderBuilder)> {
    let half = Vector::splat(0.3) + Vector::X * 0.2;
    let mut hull = box_corners(half);
    for (i, c) in hull.iter_mut().enumerate() {
        *c *= 1.0 + 0.15 * (i % 3) as Real;
    }
    let indices: Vec<[u32; 3]> = if DIM == 2 {
        vec![[0, 1, 3], [0, 3, 2]]
    } else {
        vec![
            [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5], [0, 1, 5], [0, 5, 4],
            [2, 6, 7], [2, 7, 3], [0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6],
        ]
    };
    vec![
        ("cuboid", world::cuboid(half)),
        ("capsule", ColliderBuilder::capsule_y(0.3, 0.25)),
        ("convex hull", ColliderBuilder::convex_hull(&hull).unwrap()),
        ("trimesh", ColliderBuilder::trimesh(box_corners(half), indices).unwrap()),
        ("offset ball", ColliderBuilder::ball(0.3).translation(Vector::Y * 0.1)),
    ]
}

/// Issue 21.3, issue 39.2: a marked collider the law cannot move as a point
/// (any shape but a ball centred on its body) is governed as a rigid body
/// in every law mode, the marked ball beside it as a point: their impacts
/// with the walls are the law's (elastic here: `e = 1`), the shape's
/// bounced by rapier's solver with the law's restitution and reported,
/// and every body stays finite.
#[test]
fn a_marked_non_ball_body_follows_the_rigid_law_in_every_mode() {
    for mode in LAW_MODES {
        for (name, shape) in extended_shapes() {
            let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
            w.closed_box(2.0, 0.5);
            let mut v = Vector::X * 3.0;
            v[1] = 0.4;
            let mut p = Vector::X * -1.2;
            p[1] = 0.1;
            let body = RigidBodyBuilder::dynamic()
                .translation(p)
                .linvel(v)
                .can_sleep(false);
            let collider = shape.clone().mass(1.0).friction(0.0).restitution(1.0);
            let (b, c) = w.world.insert(body, collider);
            w.kimpact.mark(&w.world.colliders, c).unwrap();
            let (ball, cb) = w.ball(Vector::X * 0.5, Vector::Y * 2.0, 0.3, 1.0);
            let mut shape_impacts = Vec::new();
            let mut ball_impacts = 0;
            for _ in 0..300 {
                w.step();
                for e in w.kimpact.events() {
                    if e.collider1 == c || e.collider2 == c {
                        shape_impacts.push((e.by_solver, f64::from(e.restitution)));
                    } else if e.collider1 == cb || e.collider2 == cb {
                        ball_impacts += 1;
                    }
                }
            }
            assert!(ball_impacts > 0, "{mode}, {name}: the ball met no wall under the law");
            assert!(!shape_impacts.is_empty(), "{mode}, {name}: no impact of the shape");
            // rapier's solver bounces them in restitution mode; the rigid
            // replay at their time of impact in impulse and exact mode.
            let solver = mode == Mode::Restitution;
            assert!(
                shape_impacts.iter().all(|&x| x == (solver, 1.0)),
                "{mode}, {name}: {shape_impacts:?}"
            );
            let bits = w.bits(&[b, ball]);
            assert!(bits.iter().all(|&x| f64::from_bits(x).is_finite()), "{mode}, {name}");
        }
    }
}

/// Issue 21.4: a ball at rapier's speed cap (400 m/s, nearly two box
/// widths per step), and one at 10 km/s with rapier's cap lifted (40 box
/// widths per step), in a closed box stay inside it in every law mode,
/// without spending the event cap on going back and forth, and keep their
/// energy (elastic law and walls). A body faster than half its size per
/// step (a quarter, in restitution mode) is the replay's: its line is bent at every wall
/// and it is written back inside.
#[test]
fn a_ball_at_rapier_s_speed_cap_stays_in_its_box() {
    for speed in [399.0, 1e4] {
        for mode in LAW_MODES {
            let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
            w.world.integration_parameters.normalized_max_linear_velocity = 1e7;
            let half = 2.0;
            w.closed_box(half, 0.5);
            let mut v = Vector::X * speed;
            v[1] = 7.0;
            let (b, _) = w.ball(Vector::ZERO, v, 0.2, 1.0);
            let e0 = w.kinetic();
            for step in 0..60 {
                w.step();
                let p = w.pos(b);
                assert!(
                    (0..DIM).all(|a| f64::from(p[a].abs()) < f64::from(half)),
                    "{mode}, {speed} m/s: the ball left the box at step {step}: {p:?}"
                );
            }
            let s = w.kimpact.stats();
            assert_eq!(s.event_cap_hits, 0, "{mode}, {speed} m/s: the event cap was hit");
            let e = w.kinetic();
            assert!((e / e0 - 1.0).abs() <= 4.0 * ROUNDING, "{mode}, {speed} m/s: energy {e0} -> {e}");
        }
    }
}

/// Issue 21.4: a ball at rest in the path of one at 10 km/s (rapier's cap
/// lifted) is hit within the first step, in every law mode, and the pair
/// keeps its momentum and energy (the elastic law: the equal balls
/// exchange velocities, so the fast one stops and the struck one leaves
/// at its speed).
#[test]
fn a_ball_in_a_very_fast_ball_s_path_is_hit() {
    for mode in LAW_MODES {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        w.world.integration_parameters.normalized_max_linear_velocity = 1e7;
        let speed: Real = 1e4;
        let (a, _) = w.ball(Vector::ZERO, Vector::X * speed, 0.2, 1.0);
        let (b, _) = w.ball(Vector::X * 3.0, Vector::ZERO, 0.2, 1.0);
        w.step();
        let (va, vb) = (w.vel(a), w.vel(b));
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}: one impact");
        assert!(rel_err(vb, Vector::X * speed) < tol(), "{mode}: the struck ball {vb:?}");
        assert!(f64::from(va.length()) < f64::from(speed) * tol(), "{mode}: the striker {va:?}");
    }
}

/// Issue 21.5: balls spawned overlapping at one point (a spawn bug) are
/// rapier's to separate: in every law mode no ball becomes non-finite and
/// no pair is skipped for non-finite data. (Their cost, against native
/// rapier's: `cargo run --release --example overlapping_spawn`.)
#[test]
fn balls_spawned_into_each_other_stay_finite() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.0, Vector::Y * -9.81);
        w.closed_box(5.0, 0.5);
        let balls: Vec<_> = (0..60)
            .map(|_| w.ball(Vector::ZERO, Vector::ZERO, 0.1, 1.0).0)
            .collect();
        for _ in 0..5 {
            w.step();
        }
        for &b in &balls {
            assert!(
                w.pos(b).is_finite() && w.vel(b).is_finite(),
                "{mode}: a ball is not finite"
            );
        }
        assert_eq!(w.kimpact.stats().skipped_non_finite, 0, "{mode}");
    }
}
