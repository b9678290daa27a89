//! The replay's two ways of sweeping many bodies (in bulk, or one query of
//! rapier's broad phase each) against each other.
// One source for f32 and f64: `x as Real` casts in one build and not the other.
#![allow(clippy::unnecessary_cast)]

use super::*;
use crate::math::DIM;

/// The positions and velocities of `balls`, as bits.
fn bits(world: &PhysicsWorld, balls: &[RigidBodyHandle]) -> Vec<u64> {
    balls
        .iter()
        .flat_map(|&b| {
            let rb = &world.bodies[b];
            let (p, v) = (rb.translation(), rb.linvel());
            (0..DIM).flat_map(move |k| [f64::from(p[k]).to_bits(), f64::from(v[k]).to_bits()])
        })
        .collect()
}

/// The elastic gas of the root package's long tests (`tests/cases/soak.rs`),
/// 300 balls: radius 0.5, mass 1, velocity components uniform in
/// `[−speed, speed]` (rand's Xoshiro256++ seeded 42; `speed` is 3 there),
/// on a grid in a closed box whose inner half-size keeps the density of
/// 500 balls in 22 (2D) or 7 (3D), no gravity, elastic, in `mode`, fast
/// bodies swept in bulk or (`per_body`) one broad-phase query each.
fn gas(mode: Mode, speed: Real, per_body: bool) -> (PhysicsWorld, Kimpact, Vec<RigidBodyHandle>) {
    let mut gas = open_gas(mode, speed, per_body, None);
    gas.0.gravity = Vector::ZERO;
    gas
}

/// [`gas`], in its closed box, or, with `fall`, without the box (and under
/// rapier's default gravity), every ball moving at `fall` more.
fn open_gas(
    mode: Mode,
    speed: Real,
    per_body: bool,
    fall: Option<Vector>,
) -> (PhysicsWorld, Kimpact, Vec<RigidBodyHandle>) {
    use rand::{RngExt, SeedableRng};
    let n = 300;
    let base: Real = if DIM == 2 { 22.0 } else { 7.0 };
    let half = base * ((n as f64 / 500.0).powf(1.0 / DIM as f64)) as Real;
    let mut world = PhysicsWorld::new();
    let mut kimpact = Kimpact::new(Law::elastic(), mode);
    kimpact.replay.per_body_sweep = per_body;
    for axis in (0..DIM).filter(|_| fall.is_none()) {
        for sign in [-1.0, 1.0] {
            let mut centre = Vector::ZERO;
            centre[axis] = sign * (half + 1.0);
            let mut he = Vector::splat(half + 2.0);
            he[axis] = 1.0;
            let wall = world
                .bodies
                .insert(RigidBodyBuilder::fixed().translation(centre));
            let shape = crate::rapier::parry::shape::Cuboid::new(he);
            world.colliders.insert_with_parent(
                ColliderBuilder::new(SharedShape::new(shape))
                    .friction(0.0)
                    .restitution(1.0),
                wall,
                &mut world.bodies,
            );
        }
    }
    let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(42);
    let per_side = (n as f64).powf(1.0 / DIM as f64).ceil() as usize;
    let spacing = 2.0 * half / per_side as Real;
    let mut balls = Vec::new();
    for i in 0..n {
        let (mut p, mut v) = (Vector::ZERO, Vector::ZERO);
        let mut rest = i;
        for k in 0..DIM {
            p[k] = -half + spacing * (0.5 + (rest % per_side) as Real);
            rest /= per_side;
        }
        for k in 0..DIM {
            v[k] = speed * rng.random_range(-1.0..1.0) as Real;
        }
        v += fall.unwrap_or(Vector::ZERO);
        let body = world.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(p)
                .linvel(v)
                .can_sleep(false),
        );
        let ball = world.colliders.insert_with_parent(
            ColliderBuilder::ball(0.5)
                .mass(1.0)
                .friction(0.0)
                .restitution(1.0),
            body,
            &mut world.bodies,
        );
        kimpact.mark(&world.colliders, ball).expect("inserted");
        balls.push(body);
    }
    (world, kimpact, balls)
}

/// An impact as compared between the two sweeps: the colliders (in index
/// order) and the time, as bits.
fn impact_key(e: &ImpactEvent) -> (u32, u32, u64) {
    let (a, b) = (
        e.collider1.into_raw_parts().0,
        e.collider2.into_raw_parts().0,
    );
    (a.min(b), a.max(b), f64::from(e.time).to_bits())
}

/// The bulk sweep (a grid of the swept boxes against every leaf of rapier's
/// broad-phase tree, used when many bodies are swept, as every ball of a
/// gas is) takes the pairs in the same order as one broad-phase query per
/// body, and finds every pair such a query finds. A query through rapier's
/// tree can miss a pair under an inner node not yet refitted, which the
/// bulk sweep does not.
///
/// Exact mode sweeps every ball that moves more than half rapier's
/// prediction distance per step: in a gas at 3 m/s the missed pairs do not
/// meet, and the bodies are the same bit for bit over 200 steps. Impulse
/// mode sweeps the balls that move more than half their size per step: in
/// a gas at 40 m/s the queries miss pairs that meet (from the third step),
/// so the two agree bit for bit until a step whose impacts differ, and
/// there the bulk sweep's are those of the queries and more.
#[test]
fn sweeping_in_bulk_finds_what_per_body_queries_find() {
    for (mode, speed) in [(Mode::Exact, 3.0), (Mode::Impulse, 40.0)] {
        let (mut bulk_world, mut bulk, balls) = gas(mode, speed, false);
        let (mut single_world, mut single, _) = gas(mode, speed, true);
        let start = bits(&bulk_world, &balls);
        let mut differed = None;
        for step in 0..200 {
            bulk.step_world(&mut bulk_world, &(), &());
            single.step_world(&mut single_world, &(), &());
            if bits(&bulk_world, &balls) == bits(&single_world, &balls) {
                continue;
            }
            let found: Vec<_> = bulk.events().iter().map(impact_key).collect();
            for e in single.events() {
                assert!(
                    found.contains(&impact_key(e)),
                    "{mode} step {step}: the bulk sweep missed {e:?}"
                );
            }
            assert!(found.len() > single.events().len(), "{mode} step {step}");
            differed = Some(step);
            break;
        }
        let bulk_runs = bulk.replay.bulk_sweeps;
        assert_eq!(single.replay.bulk_sweeps, 0, "{mode}");
        match mode {
            Mode::Exact => {
                assert_eq!(differed, None, "{mode}");
                assert!(bulk_runs >= 150, "{mode}: {bulk_runs} runs swept in bulk");
                assert!(
                    bits(&bulk_world, &balls) != start,
                    "{mode}: the gas does not move"
                );
            }
            _ => assert!(
                differed.is_some() && bulk_runs >= 2,
                "{mode}: differed at {differed:?}, {bulk_runs} runs swept in bulk"
            ),
        }
    }
}

/// A frictionless ball of mass `mass` at `p` moving at `v`, marked.
fn ball(
    world: &mut PhysicsWorld,
    kimpact: &mut Kimpact,
    p: Vector,
    v: Vector,
    mass: Real,
) -> ColliderHandle {
    let body = RigidBodyBuilder::dynamic()
        .translation(p)
        .linvel(v)
        .can_sleep(false);
    let collider = ColliderBuilder::ball(0.5)
        .mass(mass)
        .friction(0.0)
        .restitution(1.0);
    let (_, c) = world.insert(body, collider);
    kimpact.mark(&world.colliders, c).expect("inserted");
    c
}

/// After the step, two swept balls whose boxes meet but whose balls do not
/// meet on the paths they start the step on are deferred, not predicted;
/// an impact that bends either path must bring the pair in within the same
/// step, even when the bent path lies inside the box already swept (then no
/// new query runs). Ball A runs at a heavy ball B, bounces back late in the
/// step and meets ball C, which rises towards A's path after A has passed
/// above it. The same with one broad-phase query per body.
#[test]
fn a_pair_deferred_by_the_sweep_still_meets_after_an_impact() {
    let at = |x: Real, y: Real| Vector::X * x + Vector::Y * y;
    for per_body in [false, true] {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
        kimpact.replay.per_body_sweep = per_body;
        let k = &mut kimpact;
        // On their first paths A and C stay 0.04 apart; A meets B at
        // t = 0.01, its path back stays inside its first swept box and
        // reaches C at t ≈ 0.0124 (dt = 1/60).
        let ca = ball(&mut world, k, at(0.0, 0.0), at(60.0, 0.0), 1.0);
        let cb = ball(&mut world, k, at(1.6, 0.0), Vector::ZERO, 1000.0);
        let cc = ball(&mut world, k, at(0.3, -1.1), at(0.0, 9.0), 1.0);
        // Far away, apart and moving: enough swept balls for the bulk sweep.
        for i in 0..80 {
            let p = at(
                100.0 + 3.0 * (i % 10) as Real,
                100.0 + 3.0 * (i / 10) as Real,
            );
            ball(&mut world, k, p, at(2.0, 0.0), 1.0);
        }
        kimpact.step_world(&mut world, &(), &());
        assert_eq!(kimpact.replay.bulk_sweeps, u64::from(!per_body));
        let time = |x: ColliderHandle, y: ColliderHandle| {
            kimpact
                .events()
                .iter()
                .find(|e| {
                    (e.collider1 == x && e.collider2 == y) || (e.collider1 == y && e.collider2 == x)
                })
                .map(|e| f64::from(e.time))
        };
        let ab = time(ca, cb).expect("A meets B in the first step");
        let ac = time(ca, cc);
        assert!(
            ac.is_some_and(|t| t > ab && t < 1.0 / 60.0),
            "per-body sweep {per_body}: A met B at {ab}, then C at {ac:?}, not in the same step"
        );
    }
}

/// A gas falling as a whole under gravity, 35 m/s faster than its balls
/// move against each other, is swept as the same gas at rest: the sweeps
/// judge each ball's motion against the frame the falling world shares
/// (`StepFrame::shared`), and build its box there (`StepFrame::lag`), so
/// the bulk sweep's boxes are as long, and meet as many others, as
/// without the fall; and the impacts are the same pairs. (Built in the
/// world, each box would be 0.6 m longer than a ball's own motion, and
/// meet three times as many in 2D.)
#[test]
fn a_falling_gas_is_swept_as_the_same_gas_at_rest() {
    let steps = 60;
    let run = |fall: Vector| {
        let (mut world, mut kimpact, _) = open_gas(Mode::Exact, 3.0, false, Some(fall));
        if fall == Vector::ZERO {
            world.gravity = Vector::ZERO;
        }
        let mut pairs = Vec::new();
        for step in 0..steps {
            kimpact.step_world(&mut world, &(), &());
            if step < 20 {
                let mut now: Vec<_> = kimpact.events().iter().map(|e| impact_key(e).0).collect();
                now.sort_unstable();
                pairs.push(now);
            }
        }
        let replay = &kimpact.replay;
        (replay.swept_overlaps, replay.bulk_sweeps, pairs)
    };
    let (at_rest, rest_runs, rest_pairs) = run(Vector::ZERO);
    let (falling, fall_runs, fall_pairs) = run(-Vector::Y * 35.0);
    assert!(
        rest_runs >= steps / 2,
        "{rest_runs} steps of the gas at rest swept in bulk"
    );
    assert_eq!(fall_runs, rest_runs, "steps swept in bulk");
    assert!(at_rest > 0);
    let ratio = falling as f64 / at_rest as f64;
    assert!(
        (0.9..=1.1).contains(&ratio),
        "the falling gas's swept boxes met {falling} others, the gas at rest's {at_rest}"
    );
    assert!(
        rest_pairs.iter().any(|p| !p.is_empty()),
        "no impacts at rest"
    );
    // Over the first 20 steps (until rounding, which differs where the
    // balls are far from the origin, tips an impact into another step).
    assert_eq!(
        fall_pairs, rest_pairs,
        "the impacts' first colliders, step by step"
    );
}
