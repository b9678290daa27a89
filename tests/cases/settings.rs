// What kimpact does with the settings a rapier user sets, one test per
// row of docs/settings.md that claims a behaviour, written once for
// 2D/3D and f32/f64 (included by tests/adapter.rs after cases/adapter.rs,
// whose `tol` and `rel_err` it uses).

/// The core law's velocities after an impact along +x of a body of mass
/// `m1` at `v1` with one of mass `m2` (`None`: immovable) at `v2`.
fn law_along_x(d: Real, m1: Option<Real>, v1: Vector, m2: Option<Real>, v2: Vector) -> (Vector, Vector) {
    let law = Law::new(LawParams {
        dissipation: d,
        ..Default::default()
    })
    .unwrap();
    let body = |m: Option<Real>, v: Vector| match m {
        Some(m) => kimpact::Body::new(m, to_law(v)).unwrap(),
        None => kimpact::Body::immovable(to_law(v)).unwrap(),
    };
    let (a, b) = (body(m1, v1), body(m2, v2));
    let i = law.resolve(&a, &b, &to_law(Vector::X)).unwrap().unwrap();
    (v1 + k::math::from_law(&i.delta_v_a), v2 + k::math::from_law(&i.delta_v_b))
}

/// Ball A (radius 0.5, mass 1, at 1 m/s along x) meets ball B (radius 0.5,
/// mass 1, at rest) 0.05 s in, both marked, the law's d̃ `d`; `tweak` sets
/// the world, bodies and colliders up before the first step. The world
/// after `seconds`.
fn settings_pair(
    mode: Mode,
    d: Real,
    seconds: Real,
    tweak: impl FnOnce(&mut TestWorld, [RigidBodyHandle; 2], [ColliderHandle; 2]),
) -> (TestWorld, RigidBodyHandle, RigidBodyHandle) {
    let mut w = TestWorld::new(mode, d, Vector::ZERO);
    let (a, ca) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
    let (b, cb) = w.ball(Vector::X * 1.05, Vector::ZERO, 0.5, 1.0);
    tweak(&mut w, [a, b], [ca, cb]);
    let steps = (seconds / w.world.integration_parameters.dt).round() as usize;
    for _ in 0..steps {
        w.step();
    }
    (w, a, b)
}

const LAW_MODES: [Mode; 3] = [Mode::Restitution, Mode::Impulse, Mode::Exact];

/// Rows dt, substeps, prediction distance: the impact is the law's
/// whatever rapier's integration parameters.
#[test]
fn settings_integration_parameters_leave_the_impact_to_the_law() {
    let (va, vb) = law_along_x(0.02, Some(1.0), Vector::X, Some(1.0), Vector::ZERO);
    type Set = fn(&mut IntegrationParameters);
    let variants: [(&str, Set); 10] = [
        ("dt 1/240", |p| p.dt = 1.0 / 240.0),
        ("dt 1/30", |p| p.dt = 1.0 / 30.0),
        ("1 substep", |p| p.num_solver_iterations = 1),
        ("8 substeps", |p| p.num_solver_iterations = 8),
        ("prediction 0.0005", |p| p.normalized_prediction_distance = 0.0005),
        ("prediction 0.2", |p| p.normalized_prediction_distance = 0.2),
        ("no contact recycling", |p| p.contact_recycling = false),
        ("max_ccd_substeps 4", |p| p.max_ccd_substeps = 4),
        ("soft contacts", |p| {
            p.contact_softness = SpringCoefficients::new(5.0, 1.0);
        }),
        ("stiff contacts", |p| {
            p.contact_softness = SpringCoefficients::new(120.0, 20.0);
        }),
    ];
    for (name, set) in variants {
        for mode in LAW_MODES {
            let (w, a, b) = settings_pair(mode, 0.02, 0.5, |w, _, _| set(&mut w.world.integration_parameters));
            let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
            assert!(err < tol(), "{name}, {mode}: {:?} {:?}", w.vel(a), w.vel(b));
            assert_eq!(w.kimpact.stats().impacts, 1, "{name}, {mode}");
        }
    }
}

/// Row gravity scale: the law's paths bend with each body's own gravity
/// scale (here 0: a horizontal impact under gravity stays the law's).
#[test]
fn settings_gravity_scale_shapes_the_law_s_paths() {
    let (va, vb) = law_along_x(0.0, Some(1.0), Vector::X, Some(1.0), Vector::ZERO);
    for mode in LAW_MODES {
        let (w, a, b) = settings_pair(mode, 0.0, 0.5, |w, [a, b], _| {
            w.world.gravity = Vector::Y * -9.81;
            for h in [a, b] {
                w.world.bodies[h].set_gravity_scale(0.0, true);
            }
        });
        let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
        assert!(err < tol(), "{mode}: {:?} {:?}", w.vel(a), w.vel(b));
    }
}

/// Row additional mass: the law takes the body's mass as rapier has it,
/// collider masses plus the body's additional mass.
#[test]
fn settings_additional_mass_counts_in_the_law() {
    let (va, vb) = law_along_x(0.0, Some(1.0), Vector::X, Some(3.0), Vector::ZERO);
    for mode in LAW_MODES {
        let (w, a, b) = settings_pair(mode, 0.0, 0.5, |w, [_, b], _| {
            w.world.bodies[b].set_additional_mass(2.0, true);
        });
        let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
        assert!(err < tol(), "{mode}: {:?} {:?} vs {va:?} {vb:?}", w.vel(a), w.vel(b));
    }
}

/// Row restitution and its combine rule: ignored for a pair the law
/// governs (here the elastic law, whatever the colliders say).
#[test]
fn settings_restitution_and_its_combine_rule_are_ignored_by_the_law() {
    let (va, vb) = law_along_x(0.0, Some(1.0), Vector::X, Some(1.0), Vector::ZERO);
    for (e, rule) in [(0.0, CoefficientCombineRule::Min), (0.5, CoefficientCombineRule::Max)] {
        for mode in LAW_MODES {
            let (w, a, b) = settings_pair(mode, 0.0, 0.5, |w, _, cs| {
                for c in cs {
                    let co = &mut w.world.colliders[c];
                    co.set_restitution(e);
                    co.set_restitution_combine_rule(rule);
                }
            });
            let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
            assert!(err < tol(), "e {e} {rule:?}, {mode}: {:?} {:?}", w.vel(a), w.vel(b));
        }
    }
}

/// Rows kinematic bodies and `ResolverConfig::fixed_partners`: a kinematic body
/// is an immovable partner moving at its velocity. A marked ball moving
/// towards a kinematic paddle, or at rest and struck by it, meets it by the
/// law in every law mode (the elastic law mirrors the ball's velocity in
/// the paddle's frame: the ball at rest leaves at twice the paddle's
/// speed). With `fixed_partners` off both pairs are rapier's (restitution
/// 0: the ball leaves with the paddle), no law impact.
#[test]
fn settings_kinematic_bodies_are_immovable_partners() {
    for fixed_partners in [true, false] {
        for ball_speed in [-0.5, 0.0] {
            for mode in LAW_MODES {
                let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
                let config = k::ResolverConfig {
                    fixed_partners,
                    ..k::ResolverConfig::default()
                };
                w.kimpact.set_config(config).unwrap();
                let paddle = w.world.insert_body(
                    RigidBodyBuilder::kinematic_velocity_based()
                        .translation(Vector::X * -1.05)
                        .linvel(Vector::X),
                );
                let he = Vector::splat(0.5);
                w.world.insert_collider(
                    world::cuboid(he).friction(0.0).restitution(0.0),
                    Some(paddle),
                );
                let v0 = Vector::X * ball_speed;
                let body = RigidBodyBuilder::dynamic().linvel(v0).can_sleep(false);
                let collider = ColliderBuilder::ball(0.5).mass(1.0).friction(0.0).restitution(0.0);
                let (ball, c) = w.world.insert(body, collider);
                w.kimpact.mark(&w.world.colliders, c).unwrap();
                for _ in 0..30 {
                    w.step();
                }
                let v = w.vel(ball);
                let case = format!("{mode}, ball at {ball_speed}, fixed_partners {fixed_partners}");
                if fixed_partners {
                    let (_, law) = law_along_x(0.0, None, Vector::X, Some(1.0), v0);
                    assert!(rel_err(v, law) < tol(), "{case}: {v:?} vs {law:?}");
                    assert_eq!(w.kimpact.stats().impacts, 1, "{case}");
                } else {
                    assert!(rel_err(v, Vector::X) < 1e-3, "{case}, rapier's: {v:?}");
                    assert_eq!(w.kimpact.stats().impacts, 0, "{case}");
                }
            }
        }
    }
}

/// Row dominance: in a pair of bodies of different dominance groups the
/// dominant one is an immovable partner for the law. A striker meeting a
/// dominant ball at rest bounces off it as off a wall (the law's wall d̃),
/// which stays, in every law mode. A dominant striker keeps its velocity;
/// in Impulse and Exact mode the struck ball leaves as off a moving wall;
/// in Restitution mode rapier's solver, which takes a dominant dynamic
/// body as at rest, gives it no velocity (it is only pushed aside, as in
/// `Mode::Native`), and no law impact is counted.
#[test]
fn settings_dominance_makes_the_dominant_body_immovable() {
    let d = 0.02;
    let (_, struck) = law_along_x(d, None, Vector::X, Some(1.0), Vector::ZERO);
    let (striker, _) = law_along_x(d, Some(1.0), Vector::X, None, Vector::ZERO);
    for mode in LAW_MODES {
        let (w, a, b) = settings_pair(mode, d, 0.5, |w, [a, _], _| {
            w.world.bodies[a].set_dominance_group(1);
        });
        assert_eq!(w.vel(a), Vector::X, "{mode}: the dominant ball keeps its velocity");
        if mode == Mode::Restitution {
            assert_eq!(w.vel(b), Vector::ZERO, "{mode}: rapier's solver");
            assert!(w.pos(b)[0] > 1.1, "{mode}: pushed aside: {:?}", w.pos(b));
            assert_eq!(w.kimpact.stats().impacts, 0, "{mode}");
        } else {
            assert!(rel_err(w.vel(b), struck) < tol(), "{mode}: {:?} vs {struck:?}", w.vel(b));
            assert_eq!(w.kimpact.stats().impacts, 1, "{mode}");
        }
        let (w, a, b) = settings_pair(mode, d, 0.5, |w, [_, b], _| {
            w.world.bodies[b].set_dominance_group(1);
        });
        assert!(rel_err(w.vel(a), striker) < tol(), "{mode}: {:?} vs {striker:?}", w.vel(a));
        assert_eq!(w.vel(b), Vector::ZERO, "{mode}: the dominant ball stays");
        assert_eq!(w.pos(b), Vector::X * 1.05, "{mode}: the dominant ball stays");
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}");
    }
}

/// Row locked translations: a ball whose every translation is locked is an
/// immovable partner for the law, marked or not, in every law mode (the
/// other bounces off it as off a wall, with the law's wall d̃, and it stays
/// where it is); a ball with only some translations locked leaves its
/// pairs to rapier (here restitution 0: both balls end at 0.5 m/s, no law
/// impact).
#[test]
fn settings_locked_translations() {
    let d = 0.02;
    let (v_a, _) = law_along_x(d, Some(1.0), Vector::X, None, Vector::ZERO);
    for mode in LAW_MODES {
        for marked in [true, false] {
            let (w, a, b) = settings_pair(mode, d, 0.5, |w, [_, b], [_, cb]| {
                w.world.bodies[b].lock_translations(true, true);
                if !marked {
                    w.kimpact.unmark(cb);
                }
            });
            let case = format!("{mode}, all locked, marked {marked}");
            assert!(rel_err(w.vel(a), v_a) < tol(), "{case}: {:?} vs {v_a:?}", w.vel(a));
            assert_eq!(w.pos(b), Vector::X * 1.05, "{case}: the locked ball stays");
            assert_eq!(w.kimpact.stats().impacts, 1, "{case}");
        }
        let (w, a, b) = settings_pair(mode, d, 0.5, |w, [_, b], cs| {
            w.world.bodies[b].set_locked_axes(LockedAxes::TRANSLATION_LOCKED_Y, true);
            for c in cs {
                w.world.colliders[c].set_restitution(0.0);
            }
        });
        let half = Vector::X * 0.5;
        assert!(rel_err(w.vel(a), half) < 1e-3, "{mode}, y locked: {:?}", w.vel(a));
        assert!(rel_err(w.vel(b), half) < 1e-3, "{mode}, y locked: {:?}", w.vel(b));
        assert_eq!(w.kimpact.stats().impacts, 0, "{mode}, y locked");
    }
}

/// Row linear damping: rapier damps every velocity, the law's impact (an
/// elastic exchange) happens in every law mode: the struck ball ends with
/// the damped speed the striking one would have had, the striker at rest.
#[test]
fn settings_linear_damping_is_rapier_s_and_the_impact_the_law_s() {
    let (w, _, b) = settings_pair(Mode::Exact, 0.0, 0.5, |w, [a, b], _| {
        for h in [a, b] {
            w.world.bodies[h].set_linear_damping(1.0);
        }
    });
    let reference = w.vel(b);
    assert!(reference[0] < 0.7 && reference[0] > 0.5, "damped: {reference:?}");
    assert_eq!(w.kimpact.stats().impacts, 1);
    for mode in LAW_MODES {
        let (w, a, b) = settings_pair(mode, 0.0, 0.5, |w, [a, b], cs| {
            for h in [a, b] {
                w.world.bodies[h].set_linear_damping(1.0);
            }
            // rapier alone would make the impact plastic.
            for c in cs {
                w.world.colliders[c].set_restitution(0.0);
            }
        });
        assert!(f64::from(w.vel(a).length()) < tol(), "{mode}: {:?}", w.vel(a));
        assert!(rel_err(w.vel(b), reference) < tol(), "{mode}: {:?}", w.vel(b));
    }
}

/// Row velocity caps: rapier caps the velocities
/// (`normalized_max_linear_velocity`), and the law meets the capped ones.
#[test]
fn settings_the_law_meets_rapier_s_capped_velocities() {
    let (va, vb) = law_along_x(0.0, Some(1.0), Vector::X * 0.5, Some(1.0), Vector::ZERO);
    for mode in LAW_MODES {
        let (w, a, b) = settings_pair(mode, 0.0, 0.5, |w, _, _| {
            w.world.integration_parameters.normalized_max_linear_velocity = 0.5;
        });
        let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
        assert!(err < tol(), "{mode}: {:?} {:?}", w.vel(a), w.vel(b));
    }
}

/// Row friction: an Impulse- or Exact-mode impact is frictionless whatever
/// the colliders' friction (the law changes the normal velocities only, no
/// spin); in Restitution mode rapier's solver bounced this oblique pair,
/// and its friction changes the outcome.
#[test]
fn settings_friction_at_an_impact() {
    let oblique = |mode: Mode, friction: Real| {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let body = |p: Vector, v: Vector| {
            RigidBodyBuilder::dynamic().translation(p).linvel(v).can_sleep(false)
        };
        let collider = || ColliderBuilder::ball(0.5).mass(1.0).friction(friction).restitution(1.0);
        let (a, ca) = w.world.insert(body(Vector::ZERO, Vector::X), collider());
        let mut p = Vector::X * 0.9;
        p[1] = 0.5;
        let (b, cb) = w.world.insert(body(p, Vector::ZERO), collider());
        for c in [ca, cb] {
            w.kimpact.mark(&w.world.colliders, c).unwrap();
        }
        for _ in 0..30 {
            w.step();
        }
        // The ball's rotational energy: rapier's total minus its translation.
        let rb = &w.world.bodies[a];
        let spin = f64::from(rb.kinetic_energy() - 0.5 * rb.mass() * rb.linvel().length_squared());
        (w.vel(a), w.vel(b), spin)
    };
    // The law at the contact: the balls touch with centres 0.5 apart
    // across the path, so the normal is (sqrt(1 - 0.5²), 0.5).
    let y: Real = 0.5;
    let x = (1.0 - y * y).sqrt();
    let mut n = Vector::X * x;
    n[1] = y;
    let law = Law::elastic();
    let i = law
        .resolve(
            &kimpact::Body::new(1.0, to_law(Vector::X)).unwrap(),
            &kimpact::Body::new(1.0, to_law(Vector::ZERO)).unwrap(),
            &to_law(n),
        )
        .unwrap()
        .unwrap();
    let va = Vector::X + k::math::from_law(&i.delta_v_a);
    for mode in LAW_MODES {
        let (a1, _, spin1) = oblique(mode, 1.0);
        let (a0, _, _) = oblique(mode, 0.0);
        if mode != Mode::Restitution {
            assert!(rel_err(a1, va) < tol(), "{mode}: {a1:?} vs {va:?}");
            assert!(spin1.abs() < tol(), "{mode}: no spin ({spin1})");
        } else {
            assert!(rel_err(a1, a0) > 1e-2, "{mode}: friction changed nothing: {a1:?} {a0:?}");
            assert!(spin1 > 1e-3, "{mode}: rapier's friction spins the ball ({spin1})");
        }
    }
}

/// Rows body type and removal: a marked ball made fixed between steps is
/// an immovable partner from then on (the other bounces off it as off a
/// wall), and removing a marked ball's body leaves the other ball alone,
/// in every mode, without a panic.
#[test]
fn settings_body_type_changes_and_removal() {
    let (_, v_wall) = law_along_x(0.0, None, Vector::ZERO, Some(1.0), -Vector::X);
    for mode in LAW_MODES {
        let (w, a, _) = settings_pair(mode, 0.0, 0.5, |w, [_, b], _| {
            w.world.bodies[b].set_body_type(RigidBodyType::Fixed, true);
        });
        // The law with the wall as body 1: the ball (body 2) arrives at -1
        // along the normal from the wall to the ball... mirrored: +1 towards
        // the wall, so it leaves at -1.
        assert!(rel_err(w.vel(a), -v_wall) < tol(), "{mode}: {:?}", w.vel(a));
        let (mut w, a, b) = settings_pair(mode, 0.0, 0.02, |_, _, _| {});
        w.world.bodies.remove(
            b,
            &mut w.world.islands,
            &mut w.world.colliders,
            &mut w.world.impulse_joints,
            &mut w.world.multibody_joints,
            &mut w.world.soft_bodies,
            true,
        );
        for _ in 0..30 {
            w.step();
        }
        assert_eq!(w.vel(a), Vector::X, "{mode}: the other ball flies on");
        assert_eq!(w.kimpact.stats().impacts, 0, "{mode}");
    }
}

/// Free flight is rapier's: a marked ball that meets nothing moves bit for
/// bit as its unmarked twin, under gravity with its own gravity scale,
/// damping, additional mass, locked rotations, CCD and a velocity cap, in
/// every mode.
#[test]
fn settings_free_flight_is_rapier_s_bit_for_bit() {
    for mode in Mode::ALL {
        let mut twins = [true, false].map(|marked| {
            let mut w = TestWorld::new(mode, 0.0, Vector::Y * -9.81);
            w.world.integration_parameters.normalized_max_linear_velocity = 12.0;
            let body = RigidBodyBuilder::dynamic()
                .linvel(Vector::X * 3.0)
                .gravity_scale(1.5)
                .linear_damping(0.2)
                .angular_damping(0.3)
                .additional_mass(0.5)
                .lock_rotations()
                .ccd_enabled(true);
            let (b, c) = w.world.insert(body, ColliderBuilder::ball(0.5).mass(1.0));
            if marked {
                w.kimpact.mark(&w.world.colliders, c).unwrap();
            }
            (w, b)
        });
        for _ in 0..120 {
            for (w, _) in &mut twins {
                w.step();
            }
        }
        let [(marked, a), (plain, b)] = &twins;
        assert_eq!(marked.bits(&[*a]), plain.bits(&[*b]), "{mode}");
        assert!(f64::from(marked.vel(*a).length()) >= 11.9, "{mode}: the cap was reached");
    }
}

/// Row soft CCD: a fast marked ball (30 m/s, 0.5 m a step) with a soft
/// CCD prediction of 1 m meets a ball and a thin wall by the law in every
/// law mode, once each: the struck ball leaves at 30 m/s and the striker
/// stops; the ball bounces off the wall at -30 m/s (in Restitution and
/// Exact mode back where it started after 10 steps, as rapier's own
/// bounce; Impulse mode turns it before the step in which it meets the
/// wall, so it is up to two steps' flight behind).
#[test]
fn settings_soft_ccd_on_a_fast_marked_ball() {
    let v0 = Vector::X * 30.0;
    let (va, vb) = law_along_x(0.0, Some(1.0), v0, Some(1.0), Vector::ZERO);
    for mode in LAW_MODES {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, _) = w.ball(Vector::ZERO, v0, 0.5, 1.0);
        let (b, _) = w.ball(Vector::X * 3.05, Vector::ZERO, 0.5, 1.0);
        w.world.bodies[a].set_soft_ccd_prediction(1.0);
        for _ in 0..10 {
            w.step();
        }
        let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
        assert!(err < tol(), "{mode}, ball: {:?} {:?}", w.vel(a), w.vel(b));
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}, ball");
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, _) = w.ball(Vector::ZERO, v0, 0.5, 1.0);
        w.world.bodies[a].set_soft_ccd_prediction(1.0);
        w.wall(Vector::X * 3.05, Vector::splat(0.05) + Vector::Y * 2.0);
        for _ in 0..10 {
            w.step();
        }
        assert!(rel_err(w.vel(a), -v0) < tol(), "{mode}, wall: {:?}", w.vel(a));
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}, wall");
        assert!(f64::from(w.pos(a).length()) < 1e-3, "{mode}, wall: {:?}", w.pos(a));
    }
}

/// Row length unit: a scene scaled by 100 (radii 50 m, 100 m/s, d̃ 0.02)
/// with `length_unit` 100 gives the law's impact in every law mode.
#[test]
fn settings_length_unit_scales_with_the_scene() {
    let s: Real = 100.0;
    let (va, vb) = law_along_x(0.02, Some(1.0), Vector::X * s, Some(1.0), Vector::ZERO);
    for mode in LAW_MODES {
        let mut w = TestWorld::new(mode, 0.02, Vector::ZERO);
        w.world.integration_parameters.length_unit = s;
        let (a, _) = w.ball(Vector::ZERO, Vector::X * s, 0.5 * s, 1.0);
        let (b, _) = w.ball(Vector::X * (1.05 * s), Vector::ZERO, 0.5 * s, 1.0);
        for _ in 0..30 {
            w.step();
        }
        let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
        assert!(err < tol(), "{mode}: {:?} {:?} vs {va:?} {vb:?}", w.vel(a), w.vel(b));
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}");
    }
}

/// Collects rapier's contact force events.
fn force_collector() -> (
    ChannelEventCollector,
    std::sync::mpsc::Receiver<ContactForceEvent>,
) {
    let (tx, _rx) = std::sync::mpsc::channel();
    let (ftx, frx) = std::sync::mpsc::channel();
    let (stx, _srx) = std::sync::mpsc::channel();
    (ChannelEventCollector::new(tx, ftx, stx), frx)
}

/// Row contact force events: a marked pair with `CONTACT_FORCE_EVENTS`
/// (threshold 1 N) at a law impact exchanging 1 N s in one step of 1/60 s.
/// rapier reports the force its solver applied: one 60 N event in
/// `Mode::Native` and Restitution mode (the solver applies the law's
/// restitution), none in Impulse and Exact mode (the law's change is made
/// outside rapier's solver; kimpact's `ImpactEvent` reports it).
#[test]
fn settings_contact_force_events_at_a_law_impact() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, ca) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
        let (b, cb) = w.ball(Vector::X * 1.05, Vector::ZERO, 0.5, 1.0);
        for c in [ca, cb] {
            let co = &mut w.world.colliders[c];
            co.set_active_events(ActiveEvents::CONTACT_FORCE_EVENTS);
            co.set_contact_force_event_threshold(1.0);
        }
        let (collector, frx) = force_collector();
        let mut ours = 0;
        for _ in 0..30 {
            w.kimpact.step_world(&mut w.world, &(), &collector);
            ours += w.kimpact.events().len();
        }
        let forces: Vec<f64> = frx.try_iter().map(|e| f64::from(e.total_force_magnitude)).collect();
        assert!(rel_err(w.vel(b), Vector::X) < 1e-3 && f64::from(w.vel(a).length()) < 1e-3, "{mode}");
        if matches!(mode, Mode::Native | Mode::Restitution) {
            assert_eq!(forces.len(), 1, "{mode}: {forces:?}");
            assert!((forces[0] - 60.0).abs() < 60.0 * 1e-3, "{mode}: {forces:?}");
        } else {
            assert!(forces.is_empty(), "{mode}: {forces:?}");
        }
        assert_eq!(ours, usize::from(mode != Mode::Native), "{mode}: kimpact's events");
    }
}

/// A user's `modify_solver_contacts` that makes every contact it sees
/// plastic (restitution 0).
struct Plastic;
impl PhysicsHooks for Plastic {
    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        if let Some(rigid) = context.rigid_mut() {
            *rigid.restitution = 0.0;
        }
    }
}

/// Row `modify_solver_contacts`: a user's hook (here: every contact it
/// sees plastic) on a collider with the user's own hook flag keeps working
/// with kimpact's hooks installed. On an unmarked pair it decides the
/// outcome in every mode (both balls at 0.5 m/s); on a marked pair it runs
/// first and kimpact's hook after it replaces its restitution (Restitution,
/// Impulse) or takes the impact over (Exact): the law's elastic exchange,
/// one law impact; in `Mode::Native` the user's hook alone (plastic).
#[test]
fn settings_a_user_s_solver_contact_hook_is_chained() {
    let (va, vb) = law_along_x(0.0, Some(1.0), Vector::X, Some(1.0), Vector::ZERO);
    let half = Vector::X * 0.5;
    for marked in [false, true] {
        for mode in Mode::ALL {
            let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
            let (a, ca) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
            let (b, cb) = w.ball(Vector::X * 1.05, Vector::ZERO, 0.5, 1.0);
            if !marked {
                for c in [ca, cb] {
                    w.kimpact.unmark(c);
                }
            }
            w.world.colliders[ca].set_active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS);
            for _ in 0..30 {
                w.kimpact.step_world(&mut w.world, &Plastic, &());
            }
            let case = format!("{mode}, marked {marked}");
            let (ea, eb, impacts) = if marked && mode != Mode::Native {
                (va, vb, 1)
            } else {
                (half, half, 0)
            };
            let err = rel_err(w.vel(a), ea).max(rel_err(w.vel(b), eb));
            assert!(err < 1e-3, "{case}: {:?} {:?} vs {ea:?} {eb:?}", w.vel(a), w.vel(b));
            assert_eq!(w.kimpact.stats().impacts, impacts, "{case}");
        }
    }
}

/// Row joints at an impact: marked ball A (1 kg, 1 m/s) strikes marked
/// ball B (1 kg), which a fixed joint holds to an unmarked ball C (1 kg)
/// beyond it on the line of impact. The law sees each body's own mass: in
/// every law mode A stops and B takes its velocity, then the joint shares
/// it with C (B and C at 0.5 m/s): momentum is kept, half the energy is
/// lost to the joint. rapier alone (`Mode::Native`, restitution 1) solves
/// the contact and the joint together and bounces A back.
#[test]
fn settings_a_jointed_ball_at_an_impact() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, _) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
        let (b, _) = w.ball(Vector::X * 1.05, Vector::ZERO, 0.5, 1.0);
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::X * 3.05)
            .can_sleep(false);
        let (c, _) = w.world.insert(body, ColliderBuilder::ball(0.5).mass(1.0).friction(0.0));
        let joint = FixedJointBuilder::new()
            .local_anchor1(Vector::X)
            .local_anchor2(-Vector::X);
        w.world.impulse_joints.insert(b, c, joint, true);
        for _ in 0..60 {
            w.step();
        }
        let momentum = w.vel(a) + w.vel(b) + w.vel(c);
        assert!(rel_err(momentum, Vector::X) < 1e-6, "{mode}: momentum {momentum:?}");
        let half = Vector::X * 0.5;
        if mode == Mode::Native {
            assert!(w.vel(a)[0] < -0.1, "{mode}: rapier bounces A back: {:?}", w.vel(a));
            assert_eq!(w.kimpact.stats().impacts, 0, "{mode}");
        } else {
            assert!(f64::from(w.vel(a).length()) < 1e-6, "{mode}: A stops: {:?}", w.vel(a));
            for h in [b, c] {
                assert!(rel_err(w.vel(h), half) < 1e-6, "{mode}: {:?}", w.vel(h));
            }
            assert!((w.kinetic() - 0.25).abs() < 1e-6, "{mode}: {}", w.kinetic());
            assert_eq!(w.kimpact.stats().impacts, 1, "{mode}");
        }
    }
}
