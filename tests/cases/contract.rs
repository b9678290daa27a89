// The public API's contract, written once for 2D/3D and f32/f64 (included by
// tests/adapter.rs): the stages, handles, checked settings, sleeping.

/// A frictionless ball of mass `mass` with rapier's default activation
/// (it may fall asleep), marked.
fn sleepy_ball(
    w: &mut TestWorld,
    position: Vector,
    velocity: Vector,
    radius: Real,
    mass: Real,
) -> RigidBodyHandle {
    let body = RigidBodyBuilder::dynamic()
        .translation(position)
        .linvel(velocity);
    let collider = ColliderBuilder::ball(radius)
        .mass(mass)
        .friction(0.0)
        .restitution(1.0);
    let (b, c) = w.world.insert(body, collider);
    w.kimpact.mark(&w.world.colliders, c).unwrap();
    b
}

/// A small scene with every kind of work: a closed box, balls of three
/// masses at mixed speeds, gravity, some balls starting in contact.
fn stage_scene(mode: Mode) -> (TestWorld, Vec<RigidBodyHandle>) {
    let mut w = TestWorld::new(mode, 0.05, Vector::Y * -9.81);
    w.closed_box(6.0, 0.5);
    let mut balls = Vec::new();
    for i in 0..40 {
        let mut p = Vector::ZERO;
        let mut v = Vector::ZERO;
        for a in 0..DIM {
            p[a] = -5.0 + ((i * (3 + a) + a) % 10) as Real * 1.05;
            v[a] = (((i * 7 + a * 5) % 11) as Real - 5.0) * 0.8;
        }
        let mass = [0.5, 1.0, 2.0][i % 3];
        balls.push(w.ball(p, v, 0.5, mass).0);
    }
    (w, balls)
}

/// Step `w` through the three public stages around rapier's own step.
fn step_by_stages(w: &mut TestWorld) {
    let (gravity, params) = (w.world.gravity, w.world.integration_parameters);
    let (pipeline, mut sets) = k::StepSets::of_world(&mut w.world);
    let prepared = w.kimpact.before_step(gravity, &params, &mut sets);
    pipeline.step(
        gravity,
        &params,
        sets.islands,
        sets.broad_phase,
        sets.narrow_phase,
        sets.bodies,
        sets.colliders,
        sets.impulse_joints,
        sets.multibody_joints,
        sets.soft_bodies,
        sets.ccd_solver,
        &w.kimpact.hooks(&prepared, &()),
        &(),
    );
    w.kimpact.after_step(prepared, &mut sets, &());
}

#[test]
fn the_stages_give_the_same_bodies_as_step_bit_for_bit() {
    for mode in Mode::ALL {
        let (mut a, balls) = stage_scene(mode);
        let (mut b, _) = stage_scene(mode);
        for _ in 0..150 {
            a.step();
            step_by_stages(&mut b);
            assert_eq!(a.kimpact.events(), b.kimpact.events(), "{mode}");
        }
        assert_eq!(a.bits(&balls), b.bits(&balls), "{mode}");
        assert_eq!(a.kimpact.stats(), b.kimpact.stats(), "{mode}");
        if mode != Mode::Native {
            assert!(a.kimpact.stats().impacts > 0, "{mode}: the scene has impacts");
        }
    }
}

/// Drop every collider's `MODIFY_SOLVER_CONTACTS` flag: the world as if
/// kimpact had never touched it.
fn unhook(w: &mut TestWorld) {
    let handles: Vec<ColliderHandle> = w.world.colliders.iter().map(|(h, _)| h).collect();
    for h in handles {
        let co = &mut w.world.colliders[h];
        co.set_active_hooks(co.active_hooks() - ActiveHooks::MODIFY_SOLVER_CONTACTS);
    }
}

#[test]
fn switching_to_native_between_steps_hands_every_pair_back_to_rapier() {
    for from in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let (mut a, balls) = stage_scene(from);
        let (mut b, _) = stage_scene(from);
        for _ in 0..60 {
            a.step();
            b.step();
        }
        assert_eq!(a.bits(&balls), b.bits(&balls), "{from}: same start");
        assert!(a.kimpact.stats().impacts > 0, "{from}: the scene has impacts");
        // a switches; b is stepped by rapier alone from the same state.
        a.kimpact.set_mode(Mode::Native);
        unhook(&mut b);
        let impacts = a.kimpact.stats().impacts;
        for step in 0..90 {
            a.step();
            b.world.step();
            assert_eq!(a.bits(&balls), b.bits(&balls), "{from} → native, step {step}");
        }
        assert!(a.kimpact.events().is_empty(), "{from} → native");
        assert_eq!(a.kimpact.stats().impacts, impacts, "{from} → native");
    }
}

#[test]
fn switching_from_native_between_steps_takes_the_next_impacts() {
    for to in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let (mut w, balls) = stage_scene(Mode::Native);
        for _ in 0..30 {
            w.step();
        }
        assert_eq!(w.kimpact.stats().impacts, 0, "native reports nothing");
        w.kimpact.set_mode(to);
        for _ in 0..120 {
            w.step();
        }
        assert!(w.kimpact.stats().impacts > 0, "native → {to}: impacts taken");
        for &ball in &balls {
            let (p, v) = (w.pos(ball), w.vel(ball));
            assert!(p.is_finite() && v.is_finite(), "native → {to}");
            for axis in 0..DIM {
                assert!(p[axis].abs() < 6.0, "native → {to}: a ball left the box: {p:?}");
            }
        }
    }
}

/// Two balls of equal mass with restitution 0 (rapier alone makes their
/// head-on impact plastic: 0.5/0.5), the first marked through `mark_first`.
fn plastic_pair(mode: Mode, mark_first: impl FnOnce(&mut TestWorld, ColliderHandle)) -> (Vector, Vector) {
    let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
    let dt = w.world.integration_parameters.dt;
    let body = |x: Real, v: Real| {
        RigidBodyBuilder::dynamic()
            .translation(Vector::X * x)
            .linvel(Vector::X * v)
            .can_sleep(false)
    };
    let collider = || ColliderBuilder::ball(0.5).mass(1.0).friction(0.0).restitution(0.0);
    let (a, ca) = w.world.insert(body(0.0, 1.0), collider());
    let (b, cb) = w.world.insert(body(1.0 + 2.3 * dt, 0.0), collider());
    mark_first(&mut w, ca);
    w.kimpact.mark(&w.world.colliders, cb).unwrap();
    for _ in 0..10 {
        w.step();
    }
    (w.vel(a), w.vel(b))
}

#[test]
fn handles_not_in_the_collider_set_change_nothing() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        // The marked pair meets by the law: 0 / +1.
        let (va, vb) = plastic_pair(mode, |w, c| w.kimpact.mark(&w.world.colliders, c).unwrap());
        assert!(rel_err(va, Vector::ZERO) < tol() && rel_err(vb, Vector::X) < tol(), "{mode}: {va:?} {vb:?}");

        let (va, vb) = plastic_pair(mode, |w, c| {
            // A collider removed, and another put in its slot.
            let ghost = w.world.colliders.insert(ColliderBuilder::ball(0.1).sensor(true));
            w.kimpact.mark(&w.world.colliders, ghost).unwrap();
            w.world.colliders.remove(
                ghost,
                &mut w.world.islands,
                &mut w.world.bodies,
                &mut w.world.soft_bodies,
                false,
            );
            let reused = w.world.colliders.insert(ColliderBuilder::ball(0.1).sensor(true));
            assert_eq!(reused.into_raw_parts().0, ghost.into_raw_parts().0, "rapier reuses the slot");
            w.kimpact.mark(&w.world.colliders, reused).unwrap();
            // The stale handle: not in the set, so neither marking nor
            // unmarking it touches the collider now in its slot.
            assert_eq!(
                w.kimpact.mark(&w.world.colliders, ghost),
                Err(k::HandleError::UnknownCollider(ghost))
            );
            assert!(!w.kimpact.unmark(ghost));
            assert!(!w.kimpact.is_marked(ghost));
            assert!(w.kimpact.is_marked(reused));
            // The invalid handle, and one far beyond the set: an error, no
            // allocation in proportion to the index (that would abort).
            for h in [ColliderHandle::invalid(), ColliderHandle::from_raw_parts(u32::MAX - 1, 0)] {
                assert_eq!(w.kimpact.mark(&w.world.colliders, h), Err(k::HandleError::UnknownCollider(h)));
                assert!(!w.kimpact.unmark(h));
                assert!(!w.kimpact.is_marked(h));
            }
            // A stale handle of the pair's own collider's slot.
            let (index, generation) = c.into_raw_parts();
            let stale = ColliderHandle::from_raw_parts(index, generation.wrapping_add(1));
            assert!(w.kimpact.mark(&w.world.colliders, stale).is_err());
            w.kimpact.mark(&w.world.colliders, c).unwrap();
            assert!(!w.kimpact.unmark(stale));
            assert!(w.kimpact.is_marked(c));
        });
        assert!(rel_err(va, Vector::ZERO) < tol() && rel_err(vb, Vector::X) < tol(), "{mode}: {va:?} {vb:?}");
    }
}

#[test]
fn invalid_settings_are_rejected_and_the_old_ones_kept() {
    use k::{ResolverConfig, ResolverConfigError, Kimpact};
    for bad in [Real::NAN, Real::INFINITY, -1.0] {
        // Each speed field with `bad`, the error it must give, the field
        // its message names.
        let cases = [
            (
                ResolverConfig { rest_speed: Some(bad), ..ResolverConfig::default() },
                ResolverConfigError::RestSpeed(bad),
                "rest_speed",
            ),
            (
                ResolverConfig { rebound_cutoff: Some(bad), ..ResolverConfig::default() },
                ResolverConfigError::ReboundCutoff(bad),
                "rebound_cutoff",
            ),
        ];
        let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
        for (config, error, field) in cases {
            let same = |e: ResolverConfigError| std::mem::discriminant(&e) == std::mem::discriminant(&error);
            assert!(Kimpact::with_config(Law::elastic(), Mode::Exact, config).err().is_some_and(same));
            assert!(kimpact.set_config(config).err().is_some_and(same));
            assert_eq!(*kimpact.config(), ResolverConfig::default());
            let message = error.to_string();
            assert!(message.contains(field), "{message}");
        }
    }
    let zero = ResolverConfig {
        max_events_per_step: 0,
        ..ResolverConfig::default()
    };
    assert_eq!(
        Kimpact::with_config(Law::elastic(), Mode::Exact, zero).err(),
        Some(ResolverConfigError::MaxEventsPerStep)
    );
    let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
    let fine = ResolverConfig {
        rest_speed: Some(0.0),
        max_events_per_step: 1,
        ..ResolverConfig::default()
    };
    kimpact.set_config(fine).unwrap();
    assert_eq!(kimpact.set_config(zero), Err(ResolverConfigError::MaxEventsPerStep));
    assert_eq!(*kimpact.config(), fine);
}

#[test]
fn a_moving_marked_ball_never_falls_asleep() {
    // rapier's default activation: a body slower than 0.1 m/s for 2 s falls
    // asleep and loses its velocity. No gravity: the rest speed is zero.
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let heavy = sleepy_ball(&mut w, Vector::ZERO, Vector::X * 1e-3, 0.5, 1e6);
        let light = sleepy_ball(&mut w, Vector::X * 3.0, Vector::X * -1.0, 0.1, 1e-6);
        let momentum = |w: &TestWorld| {
            w.world.bodies[heavy].linvel() * 1e6 + w.world.bodies[light].linvel() * 1e-6
        };
        let p0 = momentum(&w);
        for _ in 0..300 {
            w.step();
        }
        assert!(!w.world.bodies[heavy].is_sleeping(), "{mode}");
        assert!(rel_err(momentum(&w), p0) < tol(), "{mode}: {:?} vs {p0:?}", momentum(&w));
        assert!(w.kimpact.stats().impacts >= 1, "{mode}: the light ball bounced");
    }
}

#[test]
fn a_damped_marked_ball_sleeps_when_rapier_puts_it_to_sleep() {
    // A ball rolling out on a damped cloth, no gravity (rest speed zero):
    // its motion dies out by the user's choice, so every law mode lets
    // rapier put it to sleep at the step native rapier does.
    let asleep_at = |mode: Mode| {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::ZERO)
            .linvel(Vector::X * 0.2)
            .linear_damping(0.3);
        let collider = ColliderBuilder::ball(0.5).mass(1.0).friction(0.0);
        let (b, c) = w.world.insert(body, collider);
        w.kimpact.mark(&w.world.colliders, c).unwrap();
        (1..=600).find(|_| {
            w.step();
            w.world.bodies[b].is_sleeping()
        })
    };
    let native = asleep_at(Mode::Native);
    assert!(native.is_some(), "native rapier puts the damped ball to sleep");
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        assert_eq!(asleep_at(mode), native, "{mode}");
    }
}

#[test]
fn a_pile_at_rest_still_sleeps() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.1, Vector::Y * -9.81);
        let floor = w.world.insert_body(RigidBodyBuilder::fixed());
        let mut he = Vector::splat(5.0);
        he[1] = 0.5;
        w.world
            .insert_collider(world::cuboid(he).translation(Vector::Y * -0.5), Some(floor));
        let mut balls = Vec::new();
        for i in 0..3 {
            let p = Vector::X * (i as Real * 1.2) + Vector::Y * 0.6;
            balls.push(sleepy_ball(&mut w, p, Vector::ZERO, 0.5, 1.0));
        }
        for _ in 0..400 {
            w.step();
        }
        for &b in &balls {
            assert!(w.world.bodies[b].is_sleeping(), "{mode}: a resting ball sleeps");
        }
    }
}

/// An elastic gas in a closed box with rapier's default activation: speeds
/// from 0.02 m/s (below rapier's sleep threshold) to 3 m/s; the energy
/// change after 600 steps and whether any ball fell asleep.
fn sleepy_gas(keep_moving_awake: bool) -> (f64, bool, u64) {
    let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
    let config = k::ResolverConfig {
        keep_moving_awake,
        ..k::ResolverConfig::default()
    };
    w.kimpact.set_config(config).unwrap();
    w.closed_box(5.0, 0.5);
    for i in 0..40 {
        let mut p = Vector::ZERO;
        let mut v = Vector::ZERO;
        let mut rest = i;
        for a in 0..DIM {
            p[a] = -3.6 + 1.2 * (rest % 7) as Real;
            rest /= 7;
            v[a] = ((i * 5 + a * 3) % 7) as Real - 3.0;
        }
        let speed = if i % 4 == 0 { 0.02 } else { 0.5 + (i % 6) as Real * 0.5 };
        let v = if v.length() > 0.0 { v.normalize() * speed } else { Vector::X * speed };
        let mass = [0.5, 1.0, 2.0][i % 3];
        sleepy_ball(&mut w, p, v, 0.3, mass);
    }
    let e0 = w.kinetic();
    let mut slept = false;
    for _ in 0..600 {
        w.step();
        slept |= w.world.bodies.iter().any(|(_, b)| b.is_dynamic() && b.is_sleeping());
    }
    ((w.kinetic() - e0).abs() / e0, slept, w.kimpact.stats().impacts)
}

#[test]
fn an_elastic_gas_keeps_its_energy_with_sleeping_on() {
    let (rel, slept, impacts) = sleepy_gas(true);
    assert!(rel < tol(), "energy changed by {rel:e}");
    assert!(!slept, "a moving ball fell asleep");
    assert!(impacts > 10);
    // Without kimpact's keep-awake, rapier puts the slow balls to sleep
    // and zeroes their velocities.
    let (rel, slept, _) = sleepy_gas(false);
    assert!(slept && rel > 1e-6, "{slept} {rel:e}");
}

/// The relative speed after a head-on impact of two equal balls at 1 m/s
/// whose colliders carry materials `m1`, `m2` (the resolver's law elastic).
fn head_on_with(mode: Mode, m1: Option<k::Material>, m2: Option<k::Material>) -> f64 {
    let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
    let dt = w.world.integration_parameters.dt;
    let (a, ca) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
    let (b, cb) = w.ball(Vector::X * (1.0 + 2.3 * dt), Vector::ZERO, 0.5, 1.0);
    for (c, m) in [(ca, m1), (cb, m2)] {
        if let Some(m) = m {
            w.kimpact.mark_with(&w.world.colliders, c, m).unwrap();
        }
    }
    for _ in 0..10 {
        w.step();
    }
    f64::from((w.vel(b) - w.vel(a)).dot(Vector::X))
}

/// The law's restitution of a head-on impact of two equal masses.
fn law_e(dissipation: Real) -> f64 {
    let law = Law::new(LawParams {
        dissipation,
        ..Default::default()
    })
    .unwrap();
    let r = law
        .restitution(kimpact::Mass::Finite(1.0), kimpact::Mass::Finite(1.0), 1.0, 0.0)
        .unwrap()
        .unwrap();
    f64::from(r.coefficient)
}

#[test]
fn a_collider_s_material_sets_its_pairs_law() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let rubber = k::Material::new(0.02, 0.1).unwrap();
        // One side with a material: that material's d̃ (the other has none).
        let e = head_on_with(mode, Some(rubber), None);
        assert!((e - law_e(0.02)).abs() < 1e3 * tol(), "{mode}: {e} vs {}", law_e(0.02));
        assert!(e < 0.99, "{mode}: the material dissipates ({e})");
        // No material: the resolver's elastic law.
        let e = head_on_with(mode, None, None);
        assert!((e - 1.0).abs() < 1e3 * tol(), "{mode}: {e}");
    }
}

#[test]
fn materials_combine_by_rapier_s_rule() {
    use k::rapier::prelude::CoefficientCombineRule as Rule;
    let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
    let (_, a) = w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
    let (_, b) = w.ball(Vector::X * 3.0, Vector::ZERO, 0.5, 1.0);
    let soft = k::Material::new(0.02, 0.1).unwrap();
    let hard = k::Material::new(0.04, 0.3).unwrap();
    w.kimpact.set_material(a, Some(soft)).unwrap();
    w.kimpact.set_material(b, Some(hard)).unwrap();
    assert_eq!(w.kimpact.material(a), Some(soft));
    // Average, unless a rule of higher priority is asked for (either
    // side's), as rapier combines restitution and friction.
    let expected = [(Rule::Average, 0.03), (Rule::Max, 0.04), (Rule::Min, 0.02)];
    for (rule, d) in expected {
        for mode in [Mode::Restitution, Mode::Exact] {
            let e = head_on_with(mode, Some(soft), Some(hard.with_combine_rule(rule)));
            assert!((e - law_e(d)).abs() < 1e3 * tol(), "{mode} {rule:?}: {e} vs {}", law_e(d));
            let e = head_on_with(mode, Some(soft.with_combine_rule(rule)), Some(hard));
            assert!((e - law_e(d)).abs() < 1e3 * tol(), "{mode} {rule:?}: {e}");
        }
        w.kimpact.set_material(b, Some(hard.with_combine_rule(rule))).unwrap();
        assert_eq!(w.kimpact.material(b).unwrap().combine_rule(), rule);
    }
    // Bad input: a material needs a marked collider, and checked constants.
    assert!(k::Material::new(-1.0, 0.0).is_err());
    assert!(k::Material::new(0.0, Real::NAN).is_err());
    assert!(w.kimpact.unmark(b));
    assert_eq!(
        w.kimpact.set_material(b, Some(soft)),
        Err(k::HandleError::NotMarked(b))
    );
    assert_eq!(w.kimpact.material(b), None);
}

/// Two marked balls meeting at 100 m/s whose bodies a prismatic joint along
/// x holds with contacts disabled: rapier lets them pass through each
/// other, and so must every mode.
#[test]
fn a_joint_with_contacts_disabled_lets_its_bodies_pass() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, _) = w.ball(Vector::X * -3.0, Vector::X * 50.0, 0.5, 1.0);
        let (b, _) = w.ball(Vector::X * 3.0, Vector::X * -50.0, 0.5, 1.0);
        let joint = PrismaticJointBuilder::new(Vector::X).contacts_enabled(false);
        w.world.impulse_joints.insert(a, b, joint, true);
        for _ in 0..12 {
            w.step();
        }
        assert!(w.pos(a).x > w.pos(b).x, "{mode}: they passed");
        assert!(rel_err(w.vel(a), Vector::X * 50.0) < 1e-3, "{mode}: {:?}", w.vel(a));
        assert_eq!(w.kimpact.stats().impacts, 0, "{mode}");
    }
}

/// A user's hooks that let no pair touch.
struct NoContacts;
impl PhysicsHooks for NoContacts {
    fn filter_contact_pair(&self, _: &PairFilterContext) -> Option<SolverFlags> {
        None
    }
}

/// A user's `filter_contact_pair` is consulted for the pairs kimpact's
/// sweeps find, as rapier consults it for its own.
#[test]
fn a_user_filter_decides_the_pairs_the_sweeps_find() {
    for mode in Mode::ALL {
        let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
        let (a, ca) = w.ball(Vector::X * -3.0, Vector::X * 50.0, 0.5, 1.0);
        let (b, _) = w.ball(Vector::X * 3.0, Vector::X * -50.0, 0.5, 1.0);
        w.world.colliders[ca].set_active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
        for _ in 0..12 {
            w.kimpact.step_world(&mut w.world, &NoContacts, &());
        }
        assert!(w.pos(a).x > w.pos(b).x, "{mode}: they passed");
        assert_eq!(w.kimpact.stats().impacts, 0, "{mode}");
    }
}

/// `Mode`, `Stats` and `Precision` are the core's types, re-exported: one
/// value serves every adapter crate, the CLI and the bench.
#[test]
fn mode_stats_and_precision_are_the_core_s_types() {
    let mode: kimpact::Mode = Mode::Impulse;
    let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
    w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
    w.step();
    let stats: kimpact::Stats = w.kimpact.stats();
    assert_eq!(stats.steps, 1);
    let expected = if std::mem::size_of::<Real>() == 8 {
        kimpact::Precision::F64
    } else {
        kimpact::Precision::F32
    };
    assert_eq!(k::math::PRECISION, expected);
    assert_eq!("impulse".parse::<k::Mode>(), Ok(mode));
}

/// `Kimpact` prints the user's state (law, mode, configuration, how many
/// colliders are marked, the totals), not a step's scratch; a prepared
/// step and its hooks print the step's mode.
#[test]
fn the_resolver_and_its_hooks_are_debug() {
    let mut w = TestWorld::new(Mode::Impulse, 0.0, Vector::ZERO);
    w.ball(Vector::ZERO, Vector::X, 0.5, 1.0);
    w.ball(Vector::X * 3.0, Vector::ZERO, 0.5, 1.0);
    w.step();
    let shown = format!("{:?}", w.kimpact);
    for part in ["Kimpact", "mode: Impulse", "marked: 2", "steps: 1", "config: ResolverConfig"] {
        assert!(shown.contains(part), "{part:?} not in {shown}");
    }
    let (gravity, params) = (w.world.gravity, w.world.integration_parameters);
    let (_, mut sets) = k::StepSets::of_world(&mut w.world);
    let prepared = w.kimpact.before_step(gravity, &params, &mut sets);
    let step = format!("{prepared:?}");
    assert!(step.starts_with("PreparedStep") && step.contains("mode: Impulse"), "{step}");
    let hooks = format!("{:?}", w.kimpact.hooks(&prepared, &()));
    assert!(hooks.starts_with("StepHooks") && hooks.contains("mode: Impulse"), "{hooks}");
}
