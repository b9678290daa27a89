// Adapter tests, written once, included for 2D/3D and f32/f64 (see adapter.rs).
use self::world::TestWorld;
#[allow(unused_imports)]
use k::math::{DIM, Real, Vector, to_law};
#[allow(unused_imports)]
use k::rapier::prelude::*;
use k::{Law, LawParams, Mode};

fn tol() -> f64 {
    if std::mem::size_of::<Real>() == 8 {
        1e-9
    } else {
        1e-5
    }
}

/// Error relative to the speeds involved (the incoming ball moves at 1).
fn rel_err(a: Vector, b: Vector) -> f64 {
    f64::from((a - b).length()) / f64::from(b.length().max(1.0))
}

/// Two balls meeting mid-step, head-on or oblique: the final velocities
/// against the core law's outcome at the contact geometry of the impact.
fn two_balls(
    mode: Mode,
    m2: Real,
    dissipation: Real,
    offset: Real,
) -> (f64, Vector, Vector, Vector, Vector) {
    let mut w = TestWorld::new(mode, dissipation, Vector::ZERO);
    let r = 0.5;
    let dt = w.world.integration_parameters.dt;
    // Start 0.3 steps short of contact along x (plus a lateral offset).
    let mut p2 = Vector::ZERO;
    p2[1] = offset;
    let lateral = offset;
    let gap_x = ((2.0 * r) * (2.0 * r) - lateral * lateral).sqrt();
    p2[0] = gap_x + 2.3 * dt;
    let (a, _) = w.ball(Vector::ZERO, Vector::X, r, 1.0);
    let (b, _) = w.ball(p2, Vector::ZERO, r, m2);
    for _ in 0..10 {
        w.step();
    }
    // The law at the exact contact geometry: at impact, centres differ by
    // (gap_x, lateral).
    let mut n = Vector::ZERO;
    n[0] = gap_x;
    n[1] = lateral;
    let n = n / n.length();
    let law = Law::new(LawParams {
        dissipation,
        ..Default::default()
    })
    .unwrap();
    let ba = kimpact::Body::new(1.0, to_law(Vector::X)).unwrap();
    let bb = kimpact::Body::new(m2, to_law(Vector::ZERO)).unwrap();
    let impact = law.resolve(&ba, &bb, &to_law(n)).unwrap().unwrap();
    let va = Vector::X + k::math::from_law(&impact.delta_v_a);
    let vb = k::math::from_law(&impact.delta_v_b);
    let err = rel_err(w.vel(a), va).max(rel_err(w.vel(b), vb));
    (err, w.vel(a), va, w.vel(b), vb)
}

#[test]
fn head_on_and_oblique_match_the_core_law() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        for m2 in [1.0, 10.0, 1000.0] {
            for d in [0.0, 0.01, 0.05] {
                let (err, ..) = two_balls(mode, m2, d, 0.0);
                assert!(
                    err < tol(),
                    "{mode} head-on m2={m2} d={d}: relative error {err:e}"
                );
                let (err, va, ea, vb, eb) = two_balls(mode, m2, d, 0.6);
                // The oblique case: exact uses the normal at the time of
                // impact; the others the normal seen at detection.
                let bound = if mode == Mode::Exact { tol() } else { 0.05 };
                if d == 0.0 && m2 == 10.0 {
                    eprintln!("{mode} oblique m2=10: relative error {err:.3e}");
                }
                assert!(
                    err < bound,
                    "{mode} oblique m2={m2} d={d}: relative error {err:e}: {va:?} vs {ea:?}, {vb:?} vs {eb:?}"
                );
            }
        }
    }
}

/// Newton's cradle: five touching balls and one incoming, elastic, at
/// several phases of the step and with small gaps.
fn cradle(mode: Mode, phase: Real, gap: Real) -> (Vec<Vector>, f64, f64) {
    let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
    let r = 0.5;
    let dt = w.world.integration_parameters.dt;
    let mut handles = Vec::new();
    let mut x = -(2.0 * r + gap + (3.0 + phase) * dt);
    handles.push(w.ball(Vector::X * x, Vector::X, r, 1.0).0);
    x = 0.0;
    for _ in 0..5 {
        handles.push(w.ball(Vector::X * x, Vector::ZERO, r, 1.0).0);
        x += 2.0 * r + gap;
    }
    let e0 = w.kinetic();
    for _ in 0..30 {
        w.step();
    }
    let v = handles.iter().map(|&h| w.vel(h)).collect();
    (v, e0, w.kinetic())
}

#[test]
fn exact_newtons_cradle_passes_the_velocity_down_the_row() {
    for phase in [0.0, 0.25, 0.5, 0.9] {
        for gap in [0.0, 1e-3] {
            let (v, e0, e1) = cradle(Mode::Exact, phase, gap);
            for (i, vi) in v.iter().enumerate() {
                let expect = if i == 5 { 1.0 } else { 0.0 };
                assert!(
                    f64::from((*vi - Vector::X * expect).length()) < tol(),
                    "phase {phase} gap {gap}: ball {i} has {vi:?}, all: {v:?}"
                );
            }
            assert!(((e1 - e0) / e0).abs() < tol(), "energy {e0} -> {e1}");
        }
    }
}

#[test]
fn cradle_in_every_mode_never_gains_energy() {
    for mode in Mode::ALL {
        let (v, e0, e1) = cradle(mode, 0.5, 0.0);
        eprintln!(
            "cradle {mode}: kept {:.4} of the energy; last ball {:?}",
            e1 / e0,
            v[5]
        );
        assert!(e1 <= e0 * (1.0 + tol()), "{mode}: energy rose {e0} -> {e1}");
    }
}

#[test]
fn sleeping_ball_wakes_when_hit_and_unmarking_restores_rapier() {
    let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
    let (a, _) = w.ball(Vector::X * -2.0, Vector::X * 3.0, 0.5, 1.0);
    let body = RigidBodyBuilder::dynamic()
        .translation(Vector::ZERO)
        .sleeping(true);
    let (b, cb) = w
        .world
        .insert(body, ColliderBuilder::ball(0.5).mass(1.0).friction(0.0));
    w.kimpact.mark(&w.world.colliders, cb).unwrap();
    assert!(w.world.bodies[b].is_sleeping());
    for _ in 0..60 {
        w.step();
    }
    assert!(!w.world.bodies[b].is_sleeping());
    assert!(
        f64::from((w.vel(b) - Vector::X * 3.0).length()) < tol(),
        "{:?}",
        w.vel(b)
    );
    assert!(f64::from(w.vel(a).length()) < tol());
    assert!(w.kimpact.stats().impacts >= 1);
    assert!(w.kimpact.is_marked(cb));
    w.kimpact.unmark(cb);
    assert!(!w.kimpact.is_marked(cb));
}

/// A ball moving five diameters per step at a thin fixed wall, with rapier's
/// CCD on: it must bounce back in every law mode.
#[test]
fn fast_balls_with_ccd_do_not_tunnel_through_walls() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let r = 0.1;
        // 60 m/s at dt = 1/60: five diameters per step.
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::X * 0.3)
            .linvel(Vector::X * 60.0)
            .ccd_enabled(true)
            .can_sleep(false);
        let (fast, cf) = w.world.insert(
            body,
            ColliderBuilder::ball(r)
                .mass(1.0)
                .friction(0.0)
                .restitution(1.0),
        );
        w.kimpact.mark(&w.world.colliders, cf).unwrap();
        let mut he = Vector::splat(5.0);
        he[0] = 0.05;
        w.wall(Vector::X * 12.0, he);
        for step in 0..40 {
            w.step();
            let x = w.pos(fast)[0];
            assert!(
                x < 12.0,
                "{mode} step {step}: the ball passed through the wall (x = {x})"
            );
        }
        let v = w.vel(fast)[0];
        assert!(v < 0.0, "{mode}: the ball did not bounce (v = {v})");
        if mode != Mode::Native {
            assert!(
                (f64::from(v) + 60.0).abs() < 60.0 * tol(),
                "{mode}: elastic wall, v = {v}"
            );
        }
    }
}

/// A ball five diameters per step at another *dynamic* ball: rapier
/// 0.36.1's CCD lets it pass through natively; every law mode sweeps fast
/// marked bodies along their path and resolves the impact itself.
#[test]
fn law_modes_stop_fast_balls_tunnelling_through_balls() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (fast, _) = w.ball(Vector::ZERO, Vector::X * 60.0, 0.1, 1.0);
        let (target, _) = w.ball(Vector::X * 5.0, Vector::ZERO, 0.1, 1.0);
        for step in 0..8 {
            w.step();
            let (xf, xt) = (w.pos(fast)[0], w.pos(target)[0]);
            assert!(xf < xt, "{mode} step {step}: tunnelled ({xf} >= {xt})");
        }
        // Equal masses, elastic: the velocities are exchanged.
        assert!(
            f64::from(w.vel(fast).length()) < tol() * 60.0,
            "{mode}: {:?}",
            w.vel(fast)
        );
        assert!(
            f64::from((w.vel(target) - Vector::X * 60.0).length()) < tol() * 60.0,
            "{mode}: {:?}",
            w.vel(target)
        );
        assert_eq!(w.kimpact.stats().impacts, 1, "{mode}");
    }
}

#[test]
fn only_moving_marked_bodies_carry_the_hook() {
    let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
    let (_, moving) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
    let (_, resting) = w.ball(Vector::X * 10.0, Vector::ZERO, 0.5, 1.0);
    // An unmarked moving ball never gets the hook.
    let body = RigidBodyBuilder::dynamic()
        .translation(Vector::X * -10.0)
        .linvel(Vector::X);
    let (_, unmarked) = w.world.insert(body, ColliderBuilder::ball(0.5));
    w.step();
    w.step();
    let hooked = |c: ColliderHandle| {
        w.world.colliders[c]
            .active_hooks()
            .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS)
    };
    assert!(hooked(moving));
    assert!(!hooked(resting));
    assert!(!hooked(unmarked));
}

#[test]
fn non_finite_velocities_never_spread() {
    let mut w = TestWorld::new(Mode::Impulse, 0.0, Vector::ZERO);
    let (a, _) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
    let (b, _) = w.ball(Vector::X * 1.01, Vector::ZERO, 0.5, 1.0);
    // Corrupt a's velocity after rapier accepted it.
    w.world.bodies[a].set_linvel(Vector::X * Real::NAN, true);
    for _ in 0..5 {
        w.step();
    }
    assert!(
        w.vel(b).is_finite() && w.pos(b).is_finite(),
        "NaN reached the partner: {:?}",
        w.vel(b)
    );
}

/// A small gas with a wall box, every mode: the positions and velocities
/// after 300 steps, as bits.
fn gas_bits(mode: Mode) -> Vec<u64> {
    let mut w = TestWorld::new(mode, 0.02, Vector::ZERO);
    w.closed_box(5.0, 1.0);
    let mut balls = Vec::new();
    for i in 0..40 {
        let mut p = Vector::ZERO;
        p[0] = -4.0 + 2.0 * (i % 5) as Real;
        p[1] = -4.0 + 1.1 * (i / 5) as Real;
        let mut v = Vector::ZERO;
        v[0] = ((i * 7 % 11) as Real - 5.0) * 0.7;
        v[1] = ((i * 5 % 13) as Real - 6.0) * 0.5;
        balls.push(w.ball(p, v, 0.4, 1.0 + (i % 3) as Real).0);
    }
    for _ in 0..300 {
        w.step();
    }
    w.bits(&balls)
}

#[test]
fn the_same_scene_twice_gives_bit_identical_bodies() {
    for mode in Mode::ALL {
        assert_eq!(gas_bits(mode), gas_bits(mode), "{mode}: not deterministic");
    }
}

#[test]
fn invalid_law_changes_at_run_time_are_rejected() {
    let mut w = TestWorld::new(Mode::Exact, 0.01, Vector::ZERO);
    let err = w.kimpact.set_law(LawParams {
        dissipation: -1.0,
        ..Default::default()
    });
    assert!(matches!(
        err,
        Err(kimpact::LawError::InvalidDissipation {
            parameter: "dissipation",
            ..
        })
    ));
    assert_eq!(
        w.kimpact.law().dissipation(),
        0.01,
        "the old value stays in force"
    );
    w.kimpact
        .set_law(LawParams {
            dissipation: 0.02,
            ..Default::default()
        })
        .unwrap();
    assert_eq!(w.kimpact.law().dissipation(), 0.02);
    let _ = Law::<Real>::elastic();
}

/// Two equal balls closing slowly (0.2 per second: a pair enters rapier's
/// prediction distance several steps before it touches) swap velocities in
/// the law's modes, as the elastic law says. (A contact rapier has carried
/// for a few steps is no longer "new" when the balls meet; impulse mode
/// once let rapier resolve it, plastically.)
#[test]
fn slow_approaches_are_elastic_impacts() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, _) = w.ball(Vector::ZERO, Vector::X * 0.1, 0.5, 1.0);
        let (b, _) = w.ball(Vector::X * 1.05, Vector::X * -0.1, 0.5, 1.0);
        for _ in 0..40 {
            w.step();
        }
        let err = rel_err(w.vel(a), Vector::X * -0.1).max(rel_err(w.vel(b), Vector::X * 0.1));
        eprintln!("{mode}: slow approach, relative velocity error {err:.2e}");
        let bound = if mode == Mode::Restitution {
            0.05
        } else {
            tol()
        };
        assert!(
            err < bound,
            "{mode}: {:?} {:?} after a slow elastic impact",
            w.vel(a),
            w.vel(b)
        );
    }
}

/// Impulse mode resolves a touching row as a chain before rapier's step:
/// Newton's cradle ends as (0, …, 0, 1).
#[test]
fn impulse_newtons_cradle_passes_the_velocity_down_the_row() {
    for phase in [0.0, 0.5, 0.9] {
        let (v, e0, e1) = cradle(Mode::Impulse, phase, 0.0);
        for (i, vi) in v.iter().enumerate() {
            let expect = if i == 5 { 1.0 } else { 0.0 };
            assert!(
                f64::from((*vi - Vector::X * expect).length()) < tol(),
                "phase {phase}: ball {i} has {vi:?}, all: {v:?}"
            );
        }
        assert!(((e1 - e0) / e0).abs() < tol(), "energy {e0} -> {e1}");
    }
}

/// Two balls passing each other with a gap of 1e-3 never touch, though
/// rapier's linear speculative contact takes them for meeting at the step
/// before the closest approach (a "ghost" collision): native rapier bounces
/// them (their velocities change by a fifth; the test asserts more than a
/// hundredth, so that the scene stays a ghost collision), and the law's
/// modes leave them alone (velocities unchanged to rounding, no impact).
#[test]
fn grazing_passes_are_not_impacts() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let mut p = Vector::ZERO;
        p[0] = 1.0;
        p[1] = 1.0 + 1e-3;
        let (a, _) = w.ball(Vector::ZERO, Vector::X * 3.0, 0.5, 1.0);
        let (b, _) = w.ball(p, Vector::X * -3.0, 0.5, 1.0);
        for _ in 0..30 {
            w.step();
        }
        let err = rel_err(w.vel(a), Vector::X * 3.0).max(rel_err(w.vel(b), Vector::X * -3.0));
        if mode == Mode::Native {
            assert!(
                err > 1e-2,
                "native: rapier no longer bounces the graze (velocity change {err:e}): the test lost its ghost collision"
            );
        } else {
            assert!(
                err < tol(),
                "{mode}: a pass 1e-3 apart changed the velocities: {:?} {:?}",
                w.vel(a),
                w.vel(b)
            );
            assert_eq!(w.kimpact.stats().impacts, 0, "{mode}: {:?}", w.kimpact.stats());
        }
    }
}

/// One kimpact `ImpactEvent` per law impact, naming both colliders, in every
/// law mode; rapier's `CollisionEvent` started/stopped still arrive.
#[test]
fn each_law_impact_is_one_kimpact_event() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let mut w = TestWorld::new(mode, 0.01, Vector::ZERO);
        let (_, ca) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
        let (_, cb) = w.ball(Vector::X * 1.1, Vector::ZERO, 0.5, 2.0);
        let (tx, rx) = std::sync::mpsc::channel();
        let (ftx, _frx) = std::sync::mpsc::channel();
        let (stx, _srx) = std::sync::mpsc::channel();
        let collector = ChannelEventCollector::new(tx, ftx, stx);
        for c in [ca, cb] {
            w.world.colliders[c].set_active_events(ActiveEvents::COLLISION_EVENTS);
        }
        let mut ours = Vec::new();
        for _ in 0..30 {
            w.kimpact.step_world(&mut w.world, &(), &collector);
            ours.extend(w.kimpact.events().iter().copied());
        }
        let rapier: Vec<_> = rx.try_iter().collect();
        eprintln!(
            "{mode}: kimpact events {}, rapier collision events {:?}",
            ours.len(),
            rapier
                .iter()
                .map(|e| if e.started() { "started" } else { "stopped" })
                .collect::<Vec<_>>()
        );
        assert_eq!(ours.len(), 1, "{mode}: {ours:?}");
        let e = &ours[0];
        let pair = [e.collider1, e.collider2];
        assert!(pair.contains(&ca) && pair.contains(&cb), "{mode}: {e:?}");
        assert!(e.impulse > 0.0 && e.dissipated > 0.0, "{mode}: {e:?}");
        assert_eq!(e.by_solver, mode == Mode::Restitution, "{mode}: {e:?}");
        // rapier's own events keep arriving for the marked pair.
        assert!(
            rapier.iter().any(|e| e.started()) && rapier.iter().any(|e| e.stopped()),
            "{mode}: rapier's collision events {rapier:?}"
        );
    }
}

/// A row of sleeping balls with gaps, hit by a moving one: each woken ball
/// must carry the impact on to the next, in every law mode, ending with the
/// last ball at the incoming velocity (elastic, equal masses). A ball woken
/// by kimpact joins rapier's active set only inside the next step, so its
/// first free flight must not be lost.
#[test]
fn woken_balls_pass_the_impact_on() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, _) = w.ball(Vector::X * -1.5, Vector::X * 3.0, 0.5, 1.0);
        let mut row = Vec::new();
        for i in 0..3 {
            let body = RigidBodyBuilder::dynamic()
                .translation(Vector::X * (1.03 * i as Real))
                .sleeping(true);
            // rapier's own coefficient 0: only the law can make these bounce.
            let collider = ColliderBuilder::ball(0.5)
                .mass(1.0)
                .friction(0.0)
                .restitution(0.0);
            let (b, c) = w.world.insert(body, collider);
            w.kimpact.mark(&w.world.colliders, c).unwrap();
            row.push(b);
        }
        for _ in 0..60 {
            w.step();
        }
        let last = *row.last().unwrap();
        let err = rel_err(w.vel(last), Vector::X * 3.0);
        let rest = std::iter::once(a)
            .chain(row[..2].iter().copied())
            .map(|b| f64::from(w.vel(b).length()) / 3.0)
            .fold(0.0, f64::max);
        eprintln!("{mode}: last ball error {err:.2e}, others up to {rest:.2e}");
        assert!(
            err < tol() && rest < tol(),
            "{mode}: {:?} {:?}",
            w.vel(last),
            row.iter().map(|&b| w.vel(b)).collect::<Vec<_>>()
        );
    }
}

/// Pairs rapier's narrow phase keeps apart are never given the law, however
/// fast (the replay's sweeps find every box they pass, sensors and
/// filtered colliders included): a fast ball passes a fixed sensor and a
/// disabled wall, and two fast balls pass each other when their collision
/// groups or their solver groups exclude each other, with their velocities
/// untouched and no law impact, in every mode.
#[test]
fn filtered_pairs_pass_through_each_other_in_every_mode() {
    let apart = InteractionGroups::new(Group::GROUP_1, Group::GROUP_1, InteractionTestMode::And);
    let other = InteractionGroups::new(Group::GROUP_2, Group::GROUP_2, InteractionTestMode::And);
    for case in ["sensor", "disabled wall", "collision groups", "solver groups"] {
        for mode in Mode::ALL {
            let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
            // 30 m/s at dt = 1/60: five radii per step, swept in every law mode.
            let (fast, cf) = w.ball(Vector::ZERO, Vector::X * 30.0, 0.1, 1.0);
            let mut balls = vec![(fast, Vector::X * 30.0)];
            let mut he = Vector::splat(1.0);
            he[0] = 0.05;
            match case {
                "sensor" => {
                    let b = w.world.insert_body(RigidBodyBuilder::fixed().translation(Vector::X * 3.0));
                    w.world.insert_collider(world::cuboid(he).sensor(true), Some(b));
                }
                "disabled wall" => {
                    let c = w.wall(Vector::X * 3.0, he);
                    w.world.colliders[c].set_enabled(false);
                }
                _ => {
                    let (slow, cs) = w.ball(Vector::X * 3.0, Vector::X * -30.0, 0.1, 1.0);
                    balls.push((slow, Vector::X * -30.0));
                    for (c, groups) in [(cf, apart), (cs, other)] {
                        let co = &mut w.world.colliders[c];
                        if case == "collision groups" {
                            co.set_collision_groups(groups);
                        } else {
                            co.set_solver_groups(groups);
                        }
                    }
                }
            }
            for _ in 0..12 {
                w.step();
            }
            assert!(w.pos(fast)[0] > 4.0, "{case}, {mode}: the ball was stopped");
            for (b, v) in balls {
                assert_eq!(w.vel(b), v, "{case}, {mode}: a velocity changed");
            }
            assert_eq!(w.kimpact.stats().impacts, 0, "{case}, {mode}");
        }
    }
}

/// After the step, a pair of balls apart at the instant of an impact that
/// bends either ball's path is predicted again once that instant is over
/// (not after each of its impacts), and still meets within the step. Ball
/// D creeps towards ball B (it would take 0.1 s to touch it), so their
/// pair is in the replay, predicted not to meet this step; ball A then
/// hits B head-on a half step in, and B must carry its speed on into D
/// within the same step.
#[test]
fn a_pair_apart_at_an_impact_is_predicted_again_after_that_instant() {
    let at = |x: Real, y: Real| Vector::X * x + Vector::Y * y;
    let speed: Real = 6.0;
    let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
    // A meets B at t = 0.05 / 6 (dt = 1/60); B is then 0.01 from D.
    let (_, ca) = w.ball(at(-1.05, 0.0), at(speed, 0.0), 0.5, 1.0);
    let (_, cb) = w.ball(at(0.0, 0.0), Vector::ZERO, 0.5, 1.0);
    let (d, cd) = w.ball(at(1.01, 0.0), at(-0.1, 0.0), 0.5, 1.0);
    w.step();
    let time = |x: ColliderHandle, y: ColliderHandle| {
        w.kimpact
            .events()
            .iter()
            .find(|e| (e.collider1 == x && e.collider2 == y) || (e.collider1 == y && e.collider2 == x))
            .map(|e| f64::from(e.time))
    };
    let ab = time(ca, cb).expect("A meets B in the first step");
    assert!(ab > 0.0, "A met B at {ab}, not within the step");
    let bd = time(cb, cd);
    assert!(
        bd.is_some_and(|t| t > ab && t < 1.0 / 60.0),
        "A met B at {ab}, then B met D at {bd:?}, not in the same step"
    );
    // Elastic, equal masses, head-on: D leaves with A's speed (and its own
    // small one given to B).
    assert!(f64::from(w.vel(d).x) > 0.99 * f64::from(speed), "{:?}", w.vel(d));
}

/// Impacts at one instant are taken the fastest approach first, whatever
/// order the bodies were added in: a ball driven into two balls it
/// overlaps, one straight ahead and one at 53°, gives the head-on one all
/// of its momentum (equal masses, elastic), with the balls added in either
/// order. (Taken in the order the replay found the pairs instead, the
/// oblique pair went first, in both orders.)
#[test]
fn simultaneous_impacts_do_not_depend_on_the_order_balls_were_added() {
    let at = |x: Real, y: Real| Vector::X * x + Vector::Y * y;
    let speed: Real = 10.0;
    let run = |ahead_first: bool| -> [Vector; 4] {
        let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
        // A meets B a third of the way into the step.
        let (a, _) = w.ball(at(-1.05, 0.0), at(speed, 0.0), 0.5, 1.0);
        let (b, _) = w.ball(at(0.0, 0.0), Vector::ZERO, 0.5, 1.0);
        // Both overlap B by 0.001.
        let ahead = at(0.999, 0.0);
        let oblique = at(0.6, 0.8) * 0.999;
        let mut add = |p: Vector| w.ball(p, Vector::ZERO, 0.5, 1.0).0;
        let (c, d) = if ahead_first {
            let c = add(ahead);
            (c, add(oblique))
        } else {
            let d = add(oblique);
            (add(ahead), d)
        };
        w.step();
        [a, b, c, d].map(|h| w.vel(h))
    };
    let (x, y) = (run(true), run(false));
    for (i, (u, v)) in x.iter().zip(&y).enumerate() {
        assert!(
            f64::from((*u - *v).length()) < 1e-3 * f64::from(speed),
            "ball {i}: {u:?} added one way, {v:?} the other"
        );
    }
    // The head-on ball has A's momentum, the oblique one almost none.
    assert!(f64::from(x[2].x) > 0.99 * f64::from(speed), "{x:?}");
    assert!(f64::from(x[3].length()) < 0.01 * f64::from(speed), "{x:?}");
}

/// Impulse and exact mode sweep a falling ball, which rapier's contacts
/// (0.02 ahead) first see inside its partner when it falls 0.07-0.13 per
/// step: it lands on a ball at rest at its time of impact, and no step
/// ends with the two overlapping.
#[test]
fn a_falling_ball_never_ends_a_step_inside_the_ball_it_lands_on() {
    for mode in [Mode::Impulse, Mode::Exact] {
        let mut w = TestWorld::new(mode, 0.0, Vector::Y * -9.81);
        let (low, _) = w.ball(Vector::ZERO, Vector::ZERO, 0.5, 1.0);
        if let Some(rb) = w.world.bodies.get_mut(low) {
            rb.set_gravity_scale(0.0, true);
        }
        let (high, _) = w.ball(Vector::Y * 3.0, Vector::Y * -4.0, 0.5, 1.0);
        let mut landed = false;
        for step in 0..60 {
            w.step();
            let gap = (w.pos(high) - w.pos(low)).length() - 1.0;
            assert!(gap > -1e-3, "{mode:?}, step {step}: the balls overlap by {}", -gap);
            landed |= w.vel(low).y < -1.0;
        }
        assert!(landed, "{mode:?}: the ball did not land");
    }
}

/// A ball fast enough to be swept strikes a row of touching balls at rest.
/// Restitution mode's replay chains on from a struck ball only while it
/// moves more than a quarter of its size over the rest of the step (it
/// could tunnel): a light striker sets the row's first ball moving slowly,
/// and the rest of the row is rapier's solver's, from the next step; an
/// equal one sets it moving as fast, and the replay takes the whole row in
/// the striker's step. Exact mode takes the whole row either way. The
/// momentum reaches the end of the row in every case.
#[test]
fn restitution_chains_through_a_row_only_while_the_struck_balls_move_fast() {
    for (mode, striker_mass, chain) in [
        (Mode::Restitution, 1.0, false),
        (Mode::Restitution, 10.0, true),
        (Mode::Exact, 1.0, true),
        (Mode::Exact, 10.0, true),
    ] {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let row: Vec<_> = (0..5)
            .map(|i| w.ball(Vector::X * i as Real, Vector::ZERO, 0.5, 10.0).0)
            .collect();
        // 40 m/s: two thirds of a metre per step at 60 Hz (the radius is
        // 0.5), meeting the row within its first step.
        let striker = w.ball(Vector::X * -1.3, Vector::X * 40.0, 0.5, striker_mass).0;
        let p0 = striker_mass * 40.0;
        w.step();
        let replayed: Vec<_> = w
            .kimpact
            .events()
            .iter()
            .filter(|e| !e.by_solver)
            .collect();
        let expect = if chain { 5 } else { 1 };
        assert_eq!(
            replayed.len(),
            expect,
            "{mode:?}, striker of mass {striker_mass}: the replay's impacts {replayed:?}"
        );
        for _ in 0..60 {
            w.step();
        }
        let last = w.vel(row[4]).x;
        assert!(
            f64::from(last) > 0.1 * f64::from(p0) / 10.0,
            "{mode:?}, striker of mass {striker_mass}: the last ball moves at {last}"
        );
        let p: Real = row.iter().chain([&striker]).map(|&b| {
            let m = if b == striker { striker_mass } else { 10.0 };
            m * w.vel(b).x
        }).sum();
        assert!(
            f64::from((p - p0).abs()) < 1e-3 * f64::from(p0),
            "{mode:?}, striker of mass {striker_mass}: momentum {p0} -> {p}"
        );
    }
}
