//! What the plugin promises its app: impact messages naming colliders and
//! bodies, marks following the components (despawned, removed), settings
//! changed at run time, the user's hooks and filters chained, other rapier
//! contexts left alone, materials, quarantine of non-finite bodies, `Debug`.

use bevy::prelude::*;

use crate::bk::bevy_rapier::prelude::*;
use crate::bk::prelude::*;
use crate::harness::{Ball, Ghost, Setup, Timing, Vect, cradle, gas, vect};

#[test]
fn impact_messages_name_the_colliders_and_bodies() {
    let mut test = Setup::new().build();
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(2.0, 0.0, 0.0));
    let b = test.ball(vect(1.5, 0.0, 0.0), Vect::ZERO);
    let w = test.wall(vect(3.5, 0.0, 0.0), vect(0.5, 2.0, 2.0));
    // An unmarked pair meets too: rapier's, no message.
    let c = test.spawn(Ball::at(vect(0.0, 5.0, 0.0), vect(2.0, 0.0, 0.0)).unmarked());
    let d = test.spawn(Ball::at(vect(1.5, 5.0, 0.0), Vect::ZERO).unmarked());
    let messages = test.run(120);
    let named: Vec<_> = messages
        .iter()
        .map(|m| {
            assert_eq!(m.body1, Some(m.collider1), "the collider is on its body");
            assert_eq!(m.body2, Some(m.collider2));
            (m.collider1, m.collider2)
        })
        .collect();
    // a hits b, b the wall, b comes back to hit a.
    assert!(named.len() >= 3, "{named:?}");
    let same = |x: (Entity, Entity), y: (Entity, Entity)| x == y || x == (y.1, y.0);
    assert!(same(named[0], (a, b)), "{named:?}");
    assert!(same(named[1], (b, w)), "{named:?}");
    assert!(same(named[2], (a, b)), "{named:?}");
    for m in &messages {
        assert!(![c, d].contains(&m.collider1) && ![c, d].contains(&m.collider2));
    }
    // The normal points from collider 1 towards collider 2.
    let first = &messages[0];
    let towards = if first.collider1 == a { 1.0 } else { -1.0 };
    assert!((first.impact.normal.x - towards).abs() < 1e-5, "{first:?}");
    assert!(
        (first.impact.approach_speed - 2.0).abs() < 1e-5,
        "{first:?}"
    );
    // The unmarked pair did collide (rapier's response).
    assert!(test.vel(d).x > 1.0, "{:?}", test.vel(d));
}

#[test]
fn despawning_marked_balls_mid_run_keeps_the_others_impacts() {
    let mut test = Setup::new().build();
    let balls = gas(&mut test, 100);
    test.run(100);
    let gone: Vec<_> = balls.iter().step_by(10).map(|&(e, _)| e).collect();
    for &e in &gone {
        test.app.world_mut().despawn(e);
    }
    let rest: Vec<_> = balls
        .iter()
        .copied()
        .filter(|(e, _)| !gone.contains(e))
        .collect();
    let e0 = test.kinetic(&rest);
    let messages = test.run(300);
    let e1 = test.kinetic(&rest);
    let state = test.state();
    assert_eq!(state.marked_count(), 90);
    assert!(gone.iter().all(|&e| !state.is_marked(e)));
    assert!(messages.len() > 100, "only {} impacts", messages.len());
    for m in &messages {
        assert!(
            !gone.contains(&m.collider1) && !gone.contains(&m.collider2),
            "{m:?}"
        );
    }
    assert!(((e1 - e0) / e0).abs() < 1e-5, "energy {e0} -> {e1}");
}

#[test]
fn removing_the_component_hands_the_collider_back_to_rapier() {
    // A lossy law (rapier's restitution is 1): kimpact's impacts are told
    // apart by the speed they leave.
    let lossy = LawParams {
        dissipation: 0.2,
        ..Default::default()
    };
    let speed_after = |unmark: bool| {
        let mut test = Setup::new().law(lossy).build();
        let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
        let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
        test.run(3);
        assert!(test.state().is_marked(b));
        if unmark {
            test.app
                .world_mut()
                .entity_mut(b)
                .remove::<KimpactCollider>();
        }
        let messages = test.run(30);
        assert_eq!(test.state().is_marked(b), !unmark);
        (messages.len(), test.vel(a).x + test.vel(b).x, test.vel(b).x)
    };
    let (n_law, momentum_law, b_law) = speed_after(false);
    let (n_rapier, momentum_rapier, b_rapier) = speed_after(true);
    assert_eq!(n_law, 1);
    assert_eq!(n_rapier, 0, "an unmarked pair sends no message");
    assert!((momentum_law - 1.0).abs() < 1e-5 && (momentum_rapier - 1.0).abs() < 1e-3);
    assert!(
        b_rapier > b_law + 0.02,
        "rapier's {b_rapier} vs the law's {b_law}"
    );
}

#[test]
fn settings_change_at_run_time_and_an_invalid_law_is_refused() {
    let mut test = Setup::new().build();
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    // A second pair, meeting after the switch to native mode.
    test.ball(vect(0.0, 4.0, 0.0), vect(1.0, 0.0, 0.0));
    let d = test.ball(vect(3.0, 4.0, 0.0), Vect::ZERO);
    test.run(2);
    test.app
        .world_mut()
        .resource_mut::<KimpactSettings>()
        .law
        .dissipation = -1.0;
    let messages = test.run(30);
    assert_eq!(test.state().law().dissipation(), 0.0, "the valid law stays");
    assert_eq!(messages.len(), 1, "a and b meet under the elastic law");
    assert!((test.vel(b).x - 1.0).abs() < 1e-5 && test.vel(a).x.abs() < 1e-5);
    test.app.world_mut().resource_mut::<KimpactSettings>().mode = Mode::Native;
    let messages = test.run(150);
    assert_eq!(test.state().mode(), Mode::Native);
    assert!(messages.is_empty(), "native mode sends none: {messages:?}");
    assert!(
        test.vel(d).x > 0.5,
        "the second pair met (rapier's): {:?}",
        test.vel(d)
    );
}

#[test]
fn the_users_hooks_are_chained() {
    let mut test = Setup::new().user_hooks().build();
    // The user's flag on an unmarked ball hitting a wall, and on a marked
    // one: the user's hook runs for both, and the law still takes the
    // marked pair.
    let u = test.spawn(Ball::at(vect(0.0, 4.0, 0.0), vect(2.0, 0.0, 0.0)).unmarked());
    test.app
        .world_mut()
        .entity_mut(u)
        .insert(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    test.wall(vect(2.5, 4.0, 0.0), vect(0.5, 1.0, 1.0));
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    test.app
        .world_mut()
        .entity_mut(a)
        .insert(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    let messages = test.run(80);
    assert!(test.user_calls() > 0, "the user's hook never ran");
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!((test.vel(b).x - 1.0).abs() < 1e-5 && test.vel(a).x.abs() < 1e-5);
    assert!(test.vel(u).x < 0.0, "u bounced off the wall");
}

#[test]
fn the_users_contact_filter_decides_marked_and_unmarked_pairs() {
    // Ghosts (the user's filter_contact_pair) pass through a marked ball
    // and an unmarked one; the same pairs without the ghost meet (by the law
    // and by rapier), in every timestep mode.
    for timing in [
        Timing::Fixed(1),
        Timing::Variable(2),
        Timing::Interpolated {
            rounds: 2.0,
            substeps: 1,
        },
    ] {
        let mut test = Setup::new().user_hooks().timing(timing).build();
        let mut pairs = Vec::new();
        for (row, (marked, ghost)) in [(true, true), (false, true), (true, false), (false, false)]
            .into_iter()
            .enumerate()
        {
            let y = 3.0 * row as f32;
            let mut first = Ball::at(vect(0.0, y, 0.0), vect(1.0, 0.0, 0.0));
            let mut second = Ball::at(vect(1.3, y, 0.0), Vect::ZERO);
            if !marked {
                (first, second) = (first.unmarked(), second.unmarked());
            }
            let (a, b) = (test.spawn(first), test.spawn(second));
            if ghost {
                test.app
                    .world_mut()
                    .entity_mut(a)
                    .insert((Ghost, ActiveHooks::FILTER_CONTACT_PAIRS));
            }
            pairs.push((a, b));
        }
        let messages = test.run(180);
        let [marked_ghost, ghost, marked, rapier] = pairs[..] else {
            unreachable!()
        };
        for (a, b) in [marked_ghost, ghost] {
            assert_eq!(test.vel(a).x, 1.0, "{timing:?}: the ghost was touched");
            assert_eq!(test.vel(b).x, 0.0, "{timing:?}: the ghost touched");
            assert!(test.pos(a).x > test.pos(b).x + 1.0, "{timing:?}: no pass");
        }
        for (a, b) in [marked, rapier] {
            assert!(test.vel(a).x.abs() < 1e-3, "{timing:?}: {:?}", test.vel(a));
            assert!((test.vel(b).x - 1.0).abs() < 1e-3, "{timing:?}");
        }
        // One impact, the marked pair's without a ghost.
        let named: Vec<_> = messages
            .iter()
            .map(|m| (m.collider1, m.collider2))
            .collect();
        assert!(
            named == [marked] || named == [(marked.1, marked.0)],
            "{timing:?}: {named:?}"
        );
    }
}

#[test]
fn another_rapier_context_keeps_rapiers_response_and_the_users_hooks() {
    let mut test = Setup::new().user_hooks().build();
    test.app.update();
    let other = test
        .app
        .world_mut()
        .spawn((
            RapierContextSimulation::default(),
            RapierConfiguration {
                gravity: Vect::ZERO,
                ..RapierConfiguration::new(1.0)
            },
        ))
        .id();
    // The same pair in both contexts: their collider handles coincide.
    let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    let c = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
    let d = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
    for e in [c, d] {
        test.app.world_mut().entity_mut(e).insert((
            RapierContextEntityLink(other),
            ActiveHooks::MODIFY_SOLVER_CONTACTS,
        ));
    }
    let messages = test.run(40);
    let named: Vec<_> = messages
        .iter()
        .map(|m| (m.collider1, m.collider2))
        .collect();
    assert!(named == [(a, b)] || named == [(b, a)], "{named:?}");
    let state = test.state();
    assert!(state.is_marked(a) && !state.is_marked(c) && !state.is_marked(d));
    assert!((test.vel(b).x - 1.0).abs() < 1e-5 && test.vel(a).x.abs() < 1e-5);
    // rapier's response (and the user's hook) in the other context.
    assert!(test.user_calls() > 0);
    assert!(test.vel(d).x > 0.5, "c and d met: {:?}", test.vel(d));
    assert!(test.pos(d).x > test.pos(c).x + 0.9, "c went through d");
}

#[test]
fn a_colliders_material_gives_its_pairs_their_own_law() {
    let mut test = Setup::new().build();
    let lossy = Material::new(0.2, 0.2).unwrap();
    // Three head-on pairs at rows y = 0, 3, 6: both balls lossy; none yet
    // (one gets the material at run time); none (the settings' elastic law).
    let pairs: Vec<_> = (0..3)
        .map(|row| {
            let y = 3.0 * row as f32;
            let a = test.ball(vect(0.0, y, 0.0), vect(1.0, 0.0, 0.0));
            (a, test.ball(vect(1.3, y, 0.0), Vect::ZERO))
        })
        .collect();
    for e in [pairs[0].0, pairs[0].1] {
        test.app
            .world_mut()
            .entity_mut(e)
            .insert(KimpactCollider::with_material(lossy));
    }
    test.run(3);
    test.app
        .world_mut()
        .get_mut::<KimpactCollider>(pairs[1].0)
        .unwrap()
        .material = Some(lossy);
    let messages = test.run(30);
    let restitution = |(a, b): (Entity, Entity)| {
        let m: Vec<_> = messages
            .iter()
            .filter(|m| [a, b].contains(&m.collider1) && [a, b].contains(&m.collider2))
            .collect();
        assert_eq!(m.len(), 1, "{m:?}");
        m[0].impact.restitution
    };
    let (lossy_both, lossy_one, elastic) = (
        restitution(pairs[0]),
        restitution(pairs[1]),
        restitution(pairs[2]),
    );
    assert!(lossy_both < 0.95, "{lossy_both}");
    // One side's material is the pair's law.
    assert!(
        (lossy_one - lossy_both).abs() < 1e-5,
        "{lossy_one} vs {lossy_both}"
    );
    assert!((elastic - 1.0).abs() < 1e-5, "{elastic}");
    let handle = test
        .app
        .world()
        .get::<RapierColliderHandle>(pairs[1].0)
        .unwrap()
        .0;
    assert_eq!(test.state().kimpact().material(handle), Some(lossy));
}

#[test]
fn a_non_finite_body_is_quarantined_as_bevy_rapier_does() {
    // A marked ball whose velocity becomes NaN on a collision course: no
    // panic, rapier's quarantine disables it (RigidBodyDisabled, as
    // bevy_rapier's own step system marks it), the others keep going.
    for setup in [Setup::without_kimpact(), Setup::new()] {
        let mut test = setup.build();
        let a = test.ball(vect(0.0, 0.0, 0.0), vect(1.0, 0.0, 0.0));
        let b = test.ball(vect(1.3, 0.0, 0.0), Vect::ZERO);
        let c = test.ball(vect(0.0, 4.0, 0.0), vect(1.0, 0.0, 0.0));
        test.run(2);
        test.app
            .world_mut()
            .get_mut::<Velocity>(a)
            .unwrap()
            .linear
            .x = f32::NAN;
        test.run(30);
        let world = test.app.world();
        assert!(
            world.get::<RigidBodyDisabled>(a).is_some(),
            "a is not quarantined"
        );
        assert!(world.get::<RigidBodyDisabled>(c).is_none());
        assert!(test.vel(c).x == 1.0 && test.pos(c).x > 0.4);
        let _ = b;
    }
}

#[test]
fn the_plugin_and_the_state_are_debug() {
    let plugin = KimpactPlugin::default().with_rapier(|rapier| rapier.with_length_unit(2.0));
    let shown = format!("{plugin:?}");
    assert!(shown.starts_with("KimpactPlugin"), "{shown}");
    assert!(shown.contains("configures_rapier: true"), "{shown}");
    let c = cradle(Setup::new());
    let shown = format!("{:?}", c.test.state());
    assert!(shown.contains("mode: Exact"), "{shown}");
    assert!(
        shown.contains(&format!("impacts: {}", c.test.state().stats().impacts)),
        "{shown}"
    );
}
