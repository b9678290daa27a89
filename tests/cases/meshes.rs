// Impacts on composite fixed shapes (triangle meshes, polylines), written
// once for 2D/3D and f32/f64 (included by tests/adapter.rs).

/// A point from its coordinates (`z` is dropped in 2D).
fn point(x: Real, y: Real, z: Real) -> Vector {
    let mut p = Vector::ZERO;
    p[0] = x;
    p[1] = y;
    if DIM == 3 {
        p[DIM - 1] = z;
    }
    p
}

/// A fixed floor made of two triangles whose top lies at y = 0 (3D: the
/// square [−2, 2]² split along its diagonal; 2D: the rectangle [−2, 2] ×
/// [−1, 0] split along its diagonal), or, in 2D, a polyline of two
/// segments along y = 0 meeting at x = 0.
fn mesh_floor(kind: &str) -> ColliderBuilder {
    let collider = match (kind, DIM) {
        ("trimesh", 3) => ColliderBuilder::trimesh(
            vec![
                point(-2.0, 0.0, -2.0),
                point(2.0, 0.0, -2.0),
                point(2.0, 0.0, 2.0),
                point(-2.0, 0.0, 2.0),
            ],
            vec![[0, 2, 1], [0, 3, 2]],
        )
        .unwrap(),
        ("trimesh", _) => ColliderBuilder::trimesh(
            vec![
                point(-2.0, -1.0, 0.0),
                point(2.0, -1.0, 0.0),
                point(2.0, 0.0, 0.0),
                point(-2.0, 0.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap(),
        _ => ColliderBuilder::polyline(
            vec![point(-2.0, 0.0, 0.0), point(0.0, 0.0, 0.0), point(2.0, 0.0, 0.0)],
            None,
        ),
    };
    collider.friction(0.0)
}

/// What a ball dropped on a mesh floor did: kimpact's events over the run,
/// its totals, and the speed of the ball at the floor's contact height
/// (its flight energy, see `flight_energy`) before and after the bounce.
struct MeshDrop {
    events: Vec<k::ImpactEvent>,
    stats: k::Stats,
    ball: ColliderHandle,
    floor: ColliderHandle,
    speed_before: f64,
    speed_after: f64,
}

/// A frictionless ball of radius 0.3 (rapier restitution 0.5, so that only
/// the law can make it bounce elastically) dropped from rest with its
/// lowest point `HEIGHT` above the floor `kind` at `(x, z)`, under an
/// elastic law in `mode`, with rapier's contact clustering on or off;
/// 50 steps (the ball lands after 27 and is still rising at the end).
fn drop_on_mesh(mode: Mode, kind: &str, clustering: bool, x: Real, z: Real) -> MeshDrop {
    let mut w = TestWorld::new(mode, 0.0, Vector::Y * -G);
    w.world.integration_parameters.contact_clustering = clustering;
    let floor_body = w.world.insert_body(RigidBodyBuilder::fixed());
    let floor = w.world.insert_collider(mesh_floor(kind), Some(floor_body));
    let radius: Real = 0.3;
    let body = RigidBodyBuilder::dynamic()
        .translation(point(x, radius + HEIGHT, z))
        .can_sleep(false);
    let collider = ColliderBuilder::ball(radius)
        .mass(1.0)
        .friction(0.0)
        .restitution(0.5);
    let (b, ball) = w.world.insert(body, collider);
    w.kimpact.mark(&w.world.colliders, ball).unwrap();
    let contact = f64::from(radius);
    let speed = |w: &TestWorld| (2.0 * flight_energy(w, b, contact)).sqrt();
    let speed_before = speed(&w);
    let mut events = Vec::new();
    for _ in 0..50 {
        w.step();
        events.extend(w.kimpact.events().iter().copied());
    }
    assert!(w.vel(b).y > 0.0, "{mode} {kind}: the ball is not rising at the end");
    MeshDrop {
        events,
        stats: w.kimpact.stats(),
        ball,
        floor,
        speed_before,
        speed_after: speed(&w),
    }
}

/// Gravity of the mesh drops (m/s², along −y).
const G: Real = 9.81;
/// Fall height of the mesh drops (m).
const HEIGHT: Real = 1.0;

/// Issue 37.1: a ball dropped on a fixed mesh under an elastic law makes
/// one impact, reported once (one event, `Stats::impacts == 1`), and
/// bounces at the speed it arrived with, in every law mode, with rapier's
/// contact clustering on (its default: rapier's solver then solves merged
/// manifolds, which hold the impulses) and off, whether it lands inside one
/// triangle or on the edge two share.
///
/// The closed forms: the ball meets the floor at `u = √(2 g h)`; its flight
/// speed at the contact height (`flight_energy`, on the parabola rapier's
/// substeps of length `τ` trace) is `√(u² + (g τ/2)²)`, before the bounce
/// and, elastic, after it. Impulse and exact mode keep it to rounding;
/// restitution mode's bounce is rapier's solver's, which reflects the
/// normal velocity a substep starts with, and so returns it short by up to
/// one substep of gravity, `g τ`. The event's approach speed is the law's:
/// at the time of impact on rapier's parabola in impulse and exact mode
/// (within `g τ/2` of `u`), at the start of the step that detected it in
/// restitution mode (at most one step's `g dt` before the impact).
#[test]
fn a_ball_dropped_on_a_mesh_reports_its_one_impact_in_every_mode() {
    let g = f64::from(G);
    let (dt, substeps) = (1.0 / 60.0, 4.0);
    let tau = dt / substeps;
    let impact_speed = (2.0 * g * f64::from(HEIGHT)).sqrt();
    let flight_speed = (impact_speed * impact_speed + (0.5 * g * tau).powi(2)).sqrt();
    let kinds: &[&str] = if DIM == 2 { &["trimesh", "polyline"] } else { &["trimesh"] };
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        for &kind in kinds {
            for clustering in [true, false] {
                // Inside a triangle, and on the edge two triangles (or two
                // segments) share.
                for (x, z) in [(0.7, -0.4), (0.0, 0.0)] {
                    let case = format!("{mode} {kind} at ({x}, {z}), clustering {clustering}");
                    let r = drop_on_mesh(mode, kind, clustering, x, z);
                    assert_eq!(r.events.len(), 1, "{case}: events {:?}", r.events);
                    assert_eq!(r.stats.impacts, 1, "{case}: {:?}", r.stats);
                    let e = &r.events[0];
                    let pair = [e.collider1, e.collider2];
                    assert!(pair.contains(&r.ball) && pair.contains(&r.floor), "{case}: {e:?}");
                    assert_eq!(e.by_solver, mode == Mode::Restitution, "{case}: {e:?}");
                    assert_eq!(f64::from(e.restitution), 1.0, "{case}: {e:?}");
                    let approach = f64::from(e.approach_speed);
                    let (lo, hi) = match mode {
                        Mode::Restitution => (impact_speed - g * dt, impact_speed),
                        _ => (impact_speed - 0.5 * g * tau, impact_speed + 0.5 * g * tau),
                    };
                    assert!(
                        (lo..=hi).contains(&approach),
                        "{case}: approach speed {approach}, impact speed {impact_speed}"
                    );
                    assert!(
                        (r.speed_before - flight_speed).abs() <= ROUNDING * flight_speed,
                        "{case}: fell at {} for {flight_speed}",
                        r.speed_before
                    );
                    let short = match mode {
                        Mode::Restitution => g * tau,
                        _ => 0.0,
                    };
                    let after = r.speed_after;
                    assert!(
                        after <= flight_speed * (1.0 + ROUNDING)
                            && after >= flight_speed * (1.0 - ROUNDING) - short,
                        "{case}: bounced at {after} for {flight_speed}"
                    );
                }
            }
        }
    }
}
