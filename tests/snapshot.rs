//! Snapshots: kimpact's state serializes with rapier's world, and a restored
//! simulation continues bit for bit (the basis of rollback netcode).

use kimpact3d::math::Vector;
use kimpact3d::rapier::prelude::*;
use kimpact3d::{Kimpact, Law, LawParams, Mode};

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

#[test]
fn a_restored_snapshot_continues_bit_for_bit() {
    for mode in Mode::ALL {
        let (mut world, mut kimpact, balls) = build(mode);
        for _ in 0..60 {
            kimpact.step_world(&mut world, &(), &());
        }
        let saved_world = serde_json::to_string(&world).unwrap();
        let saved_kimpact = serde_json::to_string(&kimpact).unwrap();
        for _ in 0..120 {
            kimpact.step_world(&mut world, &(), &());
        }
        let mut world2: PhysicsWorld = serde_json::from_str(&saved_world).unwrap();
        let mut kimpact2: Kimpact = serde_json::from_str(&saved_kimpact).unwrap();
        for _ in 0..120 {
            kimpact2.step_world(&mut world2, &(), &());
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
