// Every law mode on rigid bodies of any shape (issue 39.2), written once
// for 2D/3D and f32/f64 (included by tests/adapter.rs after
// cases/adapter.rs, whose imports it uses).

/// What a tilted bar dropped on a fixed floor did at its impact.
struct BarDrop {
    /// The step's events.
    events: Vec<k::ImpactEvent>,
    /// Velocity and angular velocity (about z) at the end of the step.
    velocity: Vector,
    spin: f64,
    /// Kinetic energy (translation and rotation) before and after.
    energy: (f64, f64),
    /// rapier's mass and angular inertia about z.
    mass: f64,
    inertia: f64,
}

/// A bar of length `length` and thickness `2 half` (3D: as deep as long),
/// mass 2, turned by `angle` about z, moving down at `speed` without
/// gravity onto a fixed floor at y = 0 (frictionless, unmarked), marked,
/// under the law with wall dissipation `wall` in law mode `mode`: stepped
/// until the step of its first impact.
fn drop_bar(mode: Mode, length: Real, half: Real, angle: Real, speed: Real, wall: Real) -> BarDrop {
    let mut w = TestWorld::with_wall_dissipation(mode, wall, Vector::ZERO);
    w.floor();
    let mut he = Vector::splat(0.5 * length);
    he[1] = half;
    // The lowest corner 0.2 above the floor.
    let (s, c) = (angle.sin(), angle.cos());
    let low = 0.5 * length * s + half * c;
    let body = RigidBodyBuilder::dynamic()
        .translation(Vector::Y * (low + 0.2))
        .rotation(AboutZ::about_z(angle))
        .linvel(Vector::Y * -speed)
        .can_sleep(false);
    let b = w.marked_cuboid(body, he, 2.0);
    let energy = |w: &TestWorld| kinetic_z(&w.world.bodies[b]);
    let before = energy(&w);
    for _ in 0..30 {
        w.step();
        if !w.kimpact.events().is_empty() {
            let rb = &w.world.bodies[b];
            return BarDrop {
                events: w.kimpact.events().to_vec(),
                velocity: rb.linvel(),
                spin: angular_z(rb),
                energy: (before, energy(&w)),
                mass: f64::from(rb.mass()),
                inertia: inertia_z(rb),
            };
        }
    }
    panic!("the bar did not land");
}

/// An angular quantity about z, or its z component, in either dimension
/// (2D: a scalar; 3D: a vector).
trait AboutZ {
    fn about_z(x: Real) -> Self;
    fn z(&self) -> f64;
    /// Its magnitude.
    fn size(&self) -> f64;
}

impl AboutZ for Real {
    fn about_z(x: Real) -> Self {
        x
    }
    fn z(&self) -> f64 {
        f64::from(*self)
    }
    fn size(&self) -> f64 {
        f64::from(self.abs())
    }
}

impl AboutZ for Vector {
    fn about_z(x: Real) -> Self {
        let mut v = Vector::ZERO;
        v[DIM - 1] = x;
        v
    }
    fn z(&self) -> f64 {
        f64::from(self[DIM - 1])
    }
    fn size(&self) -> f64 {
        f64::from(self.length())
    }
}

/// The angular velocity about z.
fn angular_z(rb: &RigidBody) -> f64 {
    rb.angvel().z()
}

/// The angular inertia about z (the bar turns about z only).
fn inertia_z(rb: &RigidBody) -> f64 {
    rb.mass_properties().local_mprops.principal_inertia().z()
}

/// A rod's half-extents: `half_length` along x (3D: and z, a plate),
/// `half` along y.
fn rod(half_length: Real, half: Real) -> Vector {
    let mut he = Vector::splat(half_length);
    he[1] = half;
    he
}

/// Step `w` until a step reports impacts (at most 60 steps): that step's
/// events (none if none came); `apart` sees the world after each step
/// before it.
fn first_impacts(w: &mut TestWorld, mut apart: impl FnMut(&TestWorld)) -> Vec<k::ImpactEvent> {
    for _ in 0..60 {
        w.step();
        let events = w.kimpact.events();
        if !events.is_empty() {
            return events.to_vec();
        }
        apart(w);
    }
    Vec::new()
}

/// The kinetic energy of a body turning about z only: translation and
/// rotation.
fn kinetic_z(rb: &RigidBody) -> f64 {
    let spin = angular_z(rb);
    0.5 * f64::from(rb.mass()) * f64::from(rb.linvel().length_squared())
        + 0.5 * inertia_z(rb) * spin * spin
}

/// Issue 39.2: every law mode governs a marked bar (a cuboid on a dynamic
/// body: a rod, and a square box) landing on its edge at an angle: the
/// law's restitution as rigid bodies, at the manifold's contact (the
/// lowest edge), written into rapier's manifold, and reported (by rapier's
/// solver: impulse and exact mode replay balls only). Against the impulse formula at a point
/// evaluated here: the arm `r` from the centre to the lowest edge, the
/// effective mass `1/m_eff = 1/m + r_x²/I`, `J = m_eff U (1 + e)` along
/// the normal (up), so `v' = −U + J/m` and `ω' = r_x J / I`; `I = m (L² +
/// (2h)²)/12` (checked against rapier's). Elastic: `e = 1` and the energy
/// kept; with wall dissipation `d̃w` the law's
/// `e = √(1 − 2 d̃w m/m_eff)` for a body landing without turning, and the
/// energy less `½ m_eff U² (1 − e²)`. In 3D the edge is two solver
/// contacts, which the hook merges into one at their centroid: bounced
/// one after the other by rapier's solver they gave a 3% larger impulse
/// and raised the elastic bar's energy by 2.8%.
#[test]
fn every_law_mode_bounces_a_tilted_bar_by_the_rigid_law() {
    let speed = 3.0 as Real;
    let cases = LAW_MODES.into_iter().flat_map(|mode| {
        // A rod, and a square box (a cube in 3D).
        [(2.0 as Real, 0.1 as Real), (1.0, 0.5)]
            .into_iter()
            .flat_map(move |bar| [0.3 as Real, 0.6, 1.0].map(move |angle| (mode, bar, angle)))
    });
    for (mode, (length, half), angle) in cases {
        for wall in [0.0 as Real, 0.1] {
            let case = format!("{mode}, {length} × {}, angle {angle}, d̃w = {wall}", 2.0 * half);
            let r = drop_bar(mode, length, half, angle, speed, wall);
            let (l, h, th, u) = (
                f64::from(length),
                f64::from(half),
                f64::from(angle),
                f64::from(speed),
            );
            let m = 2.0;
            let inertia = m * (l * l + 4.0 * h * h) / 12.0;
            assert!((r.mass - m).abs() < tol() * m, "{case}: mass {}", r.mass);
            assert!(
                (r.inertia - inertia).abs() < tol() * inertia,
                "{case}: inertia {} for {inertia}",
                r.inertia
            );
            // The lowest edge: the corner (−L/2, −h) turned by the angle.
            let arm_x = -0.5 * l * th.cos() + h * th.sin();
            let m_eff = 1.0 / (1.0 / m + arm_x * arm_x / inertia);
            let e = (1.0 - 2.0 * f64::from(wall) * m / m_eff).max(0.0).sqrt();
            let impulse = m_eff * u * (1.0 + e);
            let (vy, spin) = (-u + impulse / m, arm_x * impulse / inertia);
            assert_eq!(r.events.len(), 1, "{case}: {:?}", r.events);
            let event = &r.events[0];
            assert_eq!(event.by_solver, mode == Mode::Restitution, "{case}: {event:?}");
            assert!(
                (f64::from(event.restitution) - e).abs() < tol(),
                "{case}: e = {} for {e}",
                event.restitution
            );
            assert!(
                (f64::from(event.impulse) - impulse).abs() < tol() * impulse,
                "{case}: J = {} for {impulse}",
                event.impulse
            );
            let got = (f64::from(r.velocity.y), r.spin);
            assert!(
                (got.0 - vy).abs() < tol() * u && (got.1 - spin).abs() < tol() * u / l,
                "{case}: v = {}, ω = {} for {vy}, {spin}",
                got.0,
                got.1
            );
            let (e0, e1) = r.energy;
            let expected = e0 - 0.5 * m_eff * u * u * (1.0 - e * e);
            assert!(
                (e1 - expected).abs() < tol() * e0,
                "{case}: energy {e0} -> {e1}, expected {expected}"
            );
        }
    }
}

/// A marked box of half-size 0.5 and mass 1 at `position`, moving at
/// `velocity`, frictionless, rapier restitution 0 (only the law bounces
/// it).
fn marked_box(w: &mut TestWorld, position: Vector, velocity: Vector) -> RigidBodyHandle {
    let body = RigidBodyBuilder::dynamic()
        .translation(position)
        .linvel(velocity)
        .can_sleep(false);
    w.marked_cuboid(body, Vector::splat(0.5), 1.0)
}

/// Every law mode on faces (issue 39.3), elastic, no gravity: a box
/// landing flat on a fixed floor (its face is 2 solver contacts in 2D, 4 in
/// 3D, merged into one at their centroid) leaves at its speed without
/// turning; two equal boxes meeting face to face exchange their
/// velocities. One impact each, reported.
#[test]
fn every_law_mode_bounces_faces_as_the_law_does() {
    let speed: Real = 3.0;
    for mode in LAW_MODES {
        // On the floor (the top of a wall at y = 0).
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        w.floor();
        let b = marked_box(&mut w, Vector::Y * 0.8, Vector::Y * -speed);
        for _ in 0..10 {
            w.step();
        }
        let rb = &w.world.bodies[b];
        let (v, spin) = (rb.linvel(), rb.angvel());
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}: {:?}", w.kimpact.stats());
        assert!(
            f64::from((v - Vector::Y * speed).length()) < tol() * f64::from(speed),
            "{mode}: the box left at {v:?}"
        );
        assert!(AboutZ::size(&spin) < tol(), "{mode}: the box turns: {spin:?}");
        // Face to face.
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let a = marked_box(&mut w, Vector::X * -0.7, Vector::X * speed);
        let b = marked_box(&mut w, Vector::X * 0.7, Vector::ZERO);
        for _ in 0..10 {
            w.step();
        }
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}: {:?}", w.kimpact.stats());
        let (va, vb) = (w.vel(a), w.vel(b));
        assert!(
            f64::from(va.length()) < tol() * f64::from(speed)
                && f64::from((vb - Vector::X * speed).length()) < tol() * f64::from(speed),
            "{mode}: {va:?}, {vb:?}"
        );
    }
}

/// A rigid body whose centre stands still while it spins is as fast as its
/// surface: every law mode governs a rod spinning in place (no gravity, no
/// linear velocity) whose end sweeps into a fixed floor. The floor is
/// elastic (`d̃w = 0`), so the law keeps the rod's kinetic energy
/// (translation and rotation) across the step of its one reported impact,
/// and sends its centre up. Before the prepare pass judged a body's speed
/// by its spin too, the hook never saw the pair and rapier's restitution 0
/// took the energy. The energy is judged at the impact: in 3D f32 rapier's
/// own integration of the turning rod drifts it by about 1e-6 a step
/// before it lands.
#[test]
fn every_law_mode_bounces_a_rod_spinning_in_place() {
    let (half_length, half, spin) = (1.0 as Real, 0.05 as Real, 3.0 as Real);
    for mode in LAW_MODES {
        let mut w = TestWorld::with_wall_dissipation(mode, 0.0, Vector::ZERO);
        w.floor();
        // Level, its centre 0.9 above the floor: its end reaches the floor
        // after about a third of a turn.
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::Y * 0.9)
            .angvel(AboutZ::about_z(spin))
            .can_sleep(false);
        let b = w.marked_cuboid(body, rod(half_length, half), 2.0);
        let energy = |w: &TestWorld| kinetic_z(&w.world.bodies[b]);
        let mut before = energy(&w);
        let events = first_impacts(&mut w, |w| before = energy(w));
        assert_eq!(events.len(), 1, "{mode}: {events:?}");
        assert!(!events[0].by_solver || mode == Mode::Restitution, "{mode}: {events:?}");
        let after = energy(&w);
        assert!(
            (after - before).abs() < tol() * before,
            "{mode}: energy {before} -> {after}"
        );
        let rb = &w.world.bodies[b];
        assert!(rb.linvel().y > 0.0, "{mode}: the centre goes {:?}", rb.linvel());
    }
}

/// A kinematic body is the law's immovable partner at the velocity of its
/// material point at the contact: a kinematic rod (a flipper) turning in
/// place strikes a ball at rest in every law mode, by the law (one
/// reported impact), and, the floor-like partner elastic (`d̃w = 0`), sends
/// the ball off at twice the approach speed. The approach is the speed of
/// the rod's face at the contact, `ω √(|p|² − h²)` for the contact point
/// `p` (from the turning axis) on the face at `h` from the rod's axis.
/// Restitution mode: rapier's solver bounces it with the law's
/// restitution at the manifold's contact (to 1%: the event's point lies
/// between the two surfaces); impulse and exact mode: the rigid replay, at
/// the time of impact along the rod's turn, the point on the face (to
/// rounding).
#[test]
fn every_law_mode_bounces_a_ball_off_a_turning_kinematic_rod() {
    let (half_length, half, spin) = (1.0 as Real, 0.05 as Real, 3.0 as Real);
    for mode in LAW_MODES {
        let mut w = TestWorld::with_wall_dissipation(mode, 0.0, Vector::ZERO);
        let body = RigidBodyBuilder::kinematic_velocity_based().angvel(AboutZ::about_z(spin));
        let flipper = w.world.insert_body(body);
        let collider = world::cuboid(rod(half_length, half))
            .friction(0.0)
            .restitution(0.0);
        w.world.insert_collider(collider, Some(flipper));
        let (ball, _) = w.ball(Vector::X * 0.7 + Vector::Y * 0.3, Vector::ZERO, 0.1, 1.0);
        let events = first_impacts(&mut w, |_| {});
        assert_eq!(events.len(), 1, "{mode}: {events:?}");
        let e = &events[0];
        // Restitution mode: rapier's solver, at the manifold's contact at
        // the start of the step; impulse and exact: the rigid replay, at
        // the time of impact along the rod's turn.
        let replayed = mode != Mode::Restitution;
        assert_eq!(e.by_solver, !replayed, "{mode}: {e:?}");
        let p = f64::from(e.point.length());
        let h = f64::from(half);
        let expected = f64::from(spin) * (p * p - h * h).sqrt();
        let approach = f64::from(e.approach_speed);
        let within = if replayed { tol() } else { 1e-2 };
        assert!(
            (approach - expected).abs() < within * expected,
            "{mode}: approach {approach} for {expected}: {e:?}"
        );
        let speed = f64::from(w.vel(ball).length());
        assert!(
            (speed - 2.0 * approach).abs() < tol() * approach,
            "{mode}: the ball leaves at {speed} for {}",
            2.0 * approach
        );
    }
}
