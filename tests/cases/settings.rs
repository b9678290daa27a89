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
    let variants: [(&str, Set); 6] = [
        ("dt 1/240", |p| p.dt = 1.0 / 240.0),
        ("dt 1/30", |p| p.dt = 1.0 / 30.0),
        ("1 substep", |p| p.num_solver_iterations = 1),
        ("8 substeps", |p| p.num_solver_iterations = 8),
        ("prediction 0.0005", |p| p.normalized_prediction_distance = 0.0005),
        ("prediction 0.2", |p| p.normalized_prediction_distance = 0.2),
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

/// Rows kinematic bodies and `Config::fixed_partners`: a kinematic body
/// is an immovable partner moving at its velocity. A marked ball moving
/// towards a kinematic paddle meets it by the law in every law mode (the
/// elastic law mirrors the ball's velocity in the paddle's frame). A
/// marked ball at rest struck by the paddle is not (known gap, pinned:
/// kimpact flags only moving bodies, and an unmarked kinematic body
/// carries no flag, so the pair is rapier's: restitution 0, the ball leaves
/// with the paddle). With `fixed_partners` off both pairs are rapier's,
/// no law impact.
#[test]
fn settings_kinematic_bodies_are_immovable_partners() {
    for fixed_partners in [true, false] {
        for ball_speed in [-0.5, 0.0] {
            for mode in LAW_MODES {
                let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
                let config = k::Config {
                    fixed_partners,
                    ..k::Config::default()
                };
                w.kimpact.set_config(config).unwrap();
                let paddle = w.world.insert_body(
                    RigidBodyBuilder::kinematic_velocity_based()
                        .translation(Vector::X * -1.05)
                        .linvel(Vector::X),
                );
                let he = Vector::splat(0.5);
                w.world.insert_collider(
                    k::math::cuboid(he).friction(0.0).restitution(0.0),
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
                if fixed_partners && ball_speed != 0.0 {
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

/// Row dominance: Exact and Impulse ignore it (the law takes both masses:
/// equal masses exchange their velocities); Restitution mode leaves the
/// pair to rapier's solver, which honours it (the dominant ball keeps its
/// velocity, no law impact).
#[test]
fn settings_dominance_is_ignored_by_exact_and_impulse() {
    let (va, vb) = law_along_x(0.0, Some(1.0), Vector::X, Some(1.0), Vector::ZERO);
    for mode in LAW_MODES {
        let (w, a, b) = settings_pair(mode, 0.0, 0.5, |w, [a, _], _| {
            w.world.bodies[a].set_dominance_group(1);
        });
        if mode == Mode::Restitution {
            assert_eq!(w.vel(a), Vector::X, "{mode}: the dominant ball keeps its velocity");
            assert_eq!(w.kimpact.stats().impacts, 0, "{mode}");
        } else {
            let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
            assert!(err < tol(), "{mode}: {:?} {:?}", w.vel(a), w.vel(b));
        }
    }
}

/// Row locked translations: Restitution mode honours them (rapier's solver
/// bounces the ball off the locked one as off a wall, with the law's
/// restitution 1); Exact and Impulse do not (known gap, pinned: the law
/// sets the locked ball moving along its locked axis, and it moves).
#[test]
fn settings_locked_translations_hold_only_in_restitution_mode() {
    for mode in LAW_MODES {
        let (w, a, b) = settings_pair(mode, 0.0, 0.5, |w, [_, b], _| {
            w.world.bodies[b].lock_translations(true, true);
        });
        if mode == Mode::Restitution {
            assert!(rel_err(w.vel(a), -Vector::X) < tol(), "{mode}: {:?}", w.vel(a));
            assert_eq!(w.pos(b), Vector::X * 1.05, "{mode}: the locked ball stays");
        } else {
            assert!(w.pos(b)[0] > 1.4, "{mode}: {:?}", w.pos(b));
        }
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
