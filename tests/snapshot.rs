//! Snapshots: kimpact's snapshot serializes with rapier's world, and a
//! restored simulation continues bit for bit (the basis of rollback
//! netcode); a snapshot holds the user's state under a format version, and
//! one of another format is refused by its version.

use kimpact3d::math::{Real, Vector};
use kimpact3d::rapier::prelude::*;
use kimpact3d::{
    Kimpact, Law, LawParams, Material, Mode, ResolverConfig, ResolverConfigError, Snapshot,
    SnapshotError,
};
use serde_json::{Value, json};

fn build(mode: Mode) -> (PhysicsWorld, Kimpact, Vec<RigidBodyHandle>) {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, -9.81, 0.0);
    let law = Law::new(LawParams {
        dissipation: 0.01,
        ..Default::default()
    })
    .unwrap();
    let mut kimpact = Kimpact::new(law, mode);
    let floor =
        world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, -1.0, 0.0)));
    world.insert_collider(
        ColliderBuilder::cuboid(10.0, 1.0, 10.0).friction(0.0),
        Some(floor),
    );
    let mut balls = Vec::new();
    for i in 0..30 {
        let p = Vector::new(
            (i % 5) as f32 * 1.2 - 2.4,
            1.0 + (i / 5) as f32 * 1.1,
            ((i * 3) % 5) as f32 * 0.3,
        );
        let v = Vector::new(((i * 7) % 5) as f32 - 2.0, 0.0, ((i * 3) % 4) as f32 - 1.5);
        let body = RigidBodyBuilder::dynamic().translation(p).linvel(v);
        let (b, c) = world.insert(body, ColliderBuilder::ball(0.5).friction(0.0));
        kimpact
            .mark(&world.colliders, c)
            .expect("inserted just above");
        balls.push(b);
    }
    (world, kimpact, balls)
}

fn bits(world: &PhysicsWorld, balls: &[RigidBodyHandle]) -> Vec<u32> {
    balls
        .iter()
        .flat_map(|&b| {
            let rb = &world.bodies[b];
            let (p, v) = (rb.translation(), rb.linvel());
            [p.x, p.y, p.z, v.x, v.y, v.z].map(f32::to_bits)
        })
        .collect()
}

/// Save `world` and `kimpact` as JSON and read them back.
fn save_and_restore(world: &PhysicsWorld, kimpact: &Kimpact) -> (PhysicsWorld, Kimpact) {
    let saved_world = serde_json::to_string(world).unwrap();
    let saved_kimpact = serde_json::to_string(&kimpact.snapshot()).unwrap();
    let world: PhysicsWorld = serde_json::from_str(&saved_world).unwrap();
    let snapshot: Snapshot = serde_json::from_str(&saved_kimpact).unwrap();
    let kimpact = Kimpact::from_snapshot(snapshot, &world.colliders).unwrap();
    (world, kimpact)
}

#[test]
fn a_restored_snapshot_continues_bit_for_bit() {
    for mode in Mode::ALL {
        let (mut world, mut kimpact, balls) = build(mode);
        for _ in 0..60 {
            kimpact.step_world(&mut world, &(), &());
        }
        let (mut world2, mut kimpact2) = save_and_restore(&world, &kimpact);
        assert_eq!(
            kimpact2.stats(),
            kimpact.stats(),
            "{mode}: the totals are kept"
        );
        for _ in 0..120 {
            kimpact.step_world(&mut world, &(), &());
            kimpact2.step_world(&mut world2, &(), &());
            assert_eq!(
                kimpact.events(),
                kimpact2.events(),
                "{mode}: the events differ"
            );
        }
        assert_eq!(
            bits(&world, &balls),
            bits(&world2, &balls),
            "{mode}: the continuation differs"
        );
        assert_eq!(
            kimpact.stats(),
            kimpact2.stats(),
            "{mode}: kimpact's totals differ"
        );
        assert!(kimpact.stats().impacts > 0 || mode == Mode::Native);
    }
}

/// A block of 343 balls flying as a whole (enough fast bodies for the calm
/// neighbourhoods test, rest speed 0.1) at a row of marked balls asleep: what a
/// step carries to the next (hook flags, the calm test's schedule, the
/// bodies kimpact woke) matters, and a snapshot taken after any step
/// continues as the run does.
#[test]
fn a_snapshot_after_any_step_of_a_calm_block_continues_bit_for_bit() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let (mut world, mut kimpact, balls) = calm_block(mode);
        let steps = 36;
        let mut saved = Vec::new();
        let mut trace = Vec::new();
        for _ in 0..steps {
            saved.push(save_and_restore(&world, &kimpact));
            kimpact.step_world(&mut world, &(), &());
            trace.push(bits(&world, &balls));
        }
        let stats = kimpact.stats();
        assert!(
            stats.calm_bodies > 0,
            "{mode}: the calm test left bodies unhooked"
        );
        assert!(stats.impacts > 0, "{mode}: the block hit the sleepers");
        for (from, (mut world2, mut kimpact2)) in saved.into_iter().enumerate() {
            for (step, expected) in trace.iter().enumerate().skip(from) {
                kimpact2.step_world(&mut world2, &(), &());
                assert_eq!(
                    &bits(&world2, &balls),
                    expected,
                    "{mode}: restored after step {from}, step {step} differs"
                );
            }
            assert_eq!(
                kimpact2.stats(),
                stats,
                "{mode}: restored after step {from}"
            );
        }
    }
}

/// See [`a_snapshot_after_any_step_of_a_calm_block_continues_bit_for_bit`].
fn calm_block(mode: Mode) -> (PhysicsWorld, Kimpact, Vec<RigidBodyHandle>) {
    let mut world = PhysicsWorld::new();
    let config = ResolverConfig {
        rest_speed: Some(0.1),
        ..ResolverConfig::default()
    };
    let mut kimpact = Kimpact::with_config(Law::elastic(), mode, config).unwrap();
    let mut balls = Vec::new();
    let (n, spacing) = (7, 1.2);
    for i in 0..n * n * n {
        let cell = [i % n, (i / n) % n, i / (n * n)];
        let p = Vector::new(
            cell[0] as Real * spacing,
            cell[1] as Real * spacing,
            cell[2] as Real * spacing,
        );
        // A jitter well under the rest speed: the block moves as a whole.
        let jitter = ((i * 7) % 5) as Real * 0.005;
        let body = RigidBodyBuilder::dynamic()
            .translation(p)
            .linvel(Vector::new(3.0 + jitter, 0.0, 0.0));
        let (b, c) = world.insert(body, ColliderBuilder::ball(0.5).friction(0.0));
        kimpact.mark(&world.colliders, c).unwrap();
        balls.push(b);
    }
    // The sleepers, a row in front of the block's middle row, each less
    // than a step's travel from the next: one woken by an impact strikes
    // the next at once, or in the next step (where rapier has not made it
    // active yet).
    let mid = (n / 2) as Real * spacing;
    for k in 0..4 {
        let x = (n - 1) as Real * spacing + 2.0 + k as Real * 1.03;
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(x, mid, mid))
            .sleeping(true);
        let (b, c) = world.insert(body, ColliderBuilder::ball(0.5).friction(0.0));
        kimpact.mark(&world.colliders, c).unwrap();
        balls.push(b);
    }
    (world, kimpact, balls)
}

/// The keys of JSON object `value`, sorted.
fn keys(value: &Value) -> Vec<&str> {
    let mut keys: Vec<&str> = value
        .as_object()
        .expect("an object")
        .keys()
        .map(String::as_str)
        .collect();
    keys.sort_unstable();
    keys
}

/// A resolver with a material on one of its two marked balls, stepped once.
fn with_material() -> (PhysicsWorld, Kimpact, ColliderHandle, Material) {
    let mut world = PhysicsWorld::new();
    let mut kimpact = Kimpact::new(Law::elastic(), Mode::Impulse);
    let ball = |x: Real, v: Real| {
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(x, 0.0, 0.0))
            .linvel(Vector::new(v, 0.0, 0.0))
    };
    let (_, plain) = world.insert(ball(0.0, 1.0), ColliderBuilder::ball(0.5));
    let (_, rubber) = world.insert(ball(3.0, 0.0), ColliderBuilder::ball(0.5));
    let material = Material::new(0.02, 0.03)
        .unwrap()
        .with_combine_rule(CoefficientCombineRule::Max)
        .with_impact_friction(0.4, 0.25)
        .unwrap();
    kimpact.mark(&world.colliders, plain).unwrap();
    kimpact
        .mark_with(&world.colliders, rubber, material)
        .unwrap();
    kimpact.step_world(&mut world, &(), &());
    (world, kimpact, rubber, material)
}

#[test]
fn a_snapshot_holds_the_user_s_state_under_its_format() {
    let (world, kimpact, rubber, material) = with_material();
    let value = serde_json::to_value(kimpact.snapshot()).unwrap();
    assert_eq!(keys(&value), ["format", "state"]);
    assert_eq!(value["format"], json!(Snapshot::FORMAT));
    assert_eq!(Snapshot::FORMAT, 1);
    let state = &value["state"];
    assert_eq!(
        keys(state),
        ["carried", "config", "law", "marks", "mode", "stats"]
    );
    assert_eq!(state["mode"], json!("impulse"));
    assert_eq!(state["marks"].as_array().map(Vec::len), Some(2));
    assert_eq!(state["stats"]["steps"], json!(1));
    // Read back (keys in any order, as serde_json's map sorts them): the
    // same snapshot, the same material, the same settings.
    let snapshot: Snapshot = serde_json::from_value(value).unwrap();
    assert_eq!(snapshot, kimpact.snapshot());
    let restored = Kimpact::from_snapshot(snapshot, &world.colliders).unwrap();
    assert_eq!(restored.material(rubber), Some(material));
    assert_eq!(restored.law(), kimpact.law());
    assert_eq!(restored.mode(), kimpact.mode());
    assert_eq!(restored.config(), kimpact.config());
    assert_eq!(restored.stats(), kimpact.stats());
    assert!(restored.events().is_empty(), "a step's events are not kept");
    assert_eq!(restored.snapshot(), kimpact.snapshot());
}

#[test]
fn a_snapshot_of_another_format_is_refused_by_its_format() {
    let (world, kimpact, _, _) = with_material();
    let mut value = serde_json::to_value(kimpact.snapshot()).unwrap();
    // The same state under another format, and a state this build cannot
    // read under another format: both are read as their format alone.
    value["format"] = json!(2);
    let mut other = value.clone();
    other["state"] = json!({ "bodies": [1, 2, 3] });
    for value in [value, other] {
        let snapshot: Snapshot = serde_json::from_value(value.clone()).unwrap();
        assert_eq!(snapshot.format(), 2);
        let refused = Kimpact::from_snapshot(snapshot, &world.colliders).unwrap_err();
        assert_eq!(
            refused,
            SnapshotError::Format {
                found: 2,
                expected: 1
            }
        );
        assert!(refused.to_string().contains("format 2"), "{refused}");
        // As written (the format first), before the state is read.
        let text = serde_json::to_string(&value).unwrap();
        let snapshot: Snapshot = serde_json::from_str(&text).unwrap();
        assert_eq!(snapshot.format(), 2);
    }
    let mut missing = serde_json::to_value(kimpact.snapshot()).unwrap();
    missing.as_object_mut().unwrap().remove("format");
    let error = serde_json::from_value::<Snapshot>(missing).unwrap_err();
    assert!(error.to_string().contains("format"), "{error}");
}

#[test]
fn a_snapshot_with_invalid_settings_is_refused_naming_them() {
    let (world, kimpact, rubber, _) = with_material();
    let value = serde_json::to_value(kimpact.snapshot()).unwrap();

    let mut bad_config = value.clone();
    bad_config["state"]["config"]["max_events_per_step"] = json!(0);
    let snapshot: Snapshot = serde_json::from_value(bad_config).unwrap();
    assert_eq!(
        Kimpact::from_snapshot(snapshot, &world.colliders).unwrap_err(),
        SnapshotError::Config(ResolverConfigError::MaxEventsPerStep)
    );

    let mut bad_material = value.clone();
    let marks = bad_material["state"]["marks"].as_array_mut().unwrap();
    let mark = marks
        .iter_mut()
        .find(|m| m.get("material").is_some())
        .unwrap();
    mark["material"]["tangential_restitution"] = json!(1.5);
    let snapshot: Snapshot = serde_json::from_value(bad_material).unwrap();
    let refused = Kimpact::from_snapshot(snapshot, &world.colliders).unwrap_err();
    assert!(
        matches!(refused, SnapshotError::Material { collider, .. } if collider == rubber),
        "{refused:?}"
    );
    assert!(
        refused.to_string().contains("tangential_restitution"),
        "{refused}"
    );

    let mut bad_law = value;
    bad_law["state"]["law"]["dissipation"] = json!(-1.0);
    let error = serde_json::from_value::<Snapshot>(bad_law).unwrap_err();
    assert!(error.to_string().contains("dissipation"), "{error}");
}

#[test]
fn a_collider_removed_before_the_snapshot_is_not_marked_again() {
    let (mut world, mut kimpact, rubber, _) = with_material();
    world.remove_collider(rubber);
    let restored = Kimpact::from_snapshot(kimpact.snapshot(), &world.colliders).unwrap();
    assert!(!restored.is_marked(rubber));
    assert_eq!(restored.material(rubber), None);
    // The other ball stays marked, and both resolvers step on alike.
    let (mut world2, mut restored) = save_and_restore(&world, &restored);
    for _ in 0..30 {
        kimpact.step_world(&mut world, &(), &());
        restored.step_world(&mut world2, &(), &());
        assert_eq!(kimpact.events(), restored.events());
    }
}

/// A ball inserted and marked between steps, just before the snapshot,
/// strikes at the next step: the restored resolver takes the impact as
/// the running one does.
#[test]
fn a_collider_marked_just_before_the_snapshot_is_taken_up_by_the_next_step() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let mut world = PhysicsWorld::new();
        let mut kimpact = Kimpact::new(Law::elastic(), mode);
        let ball = |x: Real, v: Real| {
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, 0.0, 0.0))
                .linvel(Vector::new(v, 0.0, 0.0))
        };
        let (target, c) = world.insert(ball(0.0, 0.0), ColliderBuilder::ball(0.5).friction(0.0));
        kimpact.mark(&world.colliders, c).unwrap();
        for _ in 0..5 {
            kimpact.step_world(&mut world, &(), &());
        }
        let (striker, c) = world.insert(ball(-1.05, 6.0), ColliderBuilder::ball(0.5).friction(0.0));
        kimpact.mark(&world.colliders, c).unwrap();
        let (mut world2, mut kimpact2) = save_and_restore(&world, &kimpact);
        for _ in 0..3 {
            kimpact.step_world(&mut world, &(), &());
            kimpact2.step_world(&mut world2, &(), &());
            assert_eq!(kimpact.events(), kimpact2.events(), "{mode}");
        }
        assert_eq!(
            kimpact.stats().impacts,
            1,
            "{mode}: the law took the impact"
        );
        let balls = [target, striker];
        assert_eq!(bits(&world, &balls), bits(&world2, &balls), "{mode}");
    }
}
