// Calm neighbourhoods (blocks of balls moving as a whole, left without
// the contact hook), written once for 2D/3D and f32/f64 (included by
// tests/adapter.rs after cases/adapter.rs, whose imports it uses).

/// What a calm-neighbourhood scene is run for: a block of balls moving as a
/// whole (a little jitter in their velocities, well under the rest speed)
/// towards a partner.
#[derive(Copy, Clone, Debug)]
enum CalmPartner {
    /// A second block, flying at the first.
    Block,
    /// A fixed wall (unmarked: a fixed partner).
    Wall,
    /// A marked ball, asleep.
    Sleeper,
}

/// An impact as compared between runs: its colliders, and its time and
/// impulse as bits.
type ImpactBits = (ColliderHandle, ColliderHandle, u64, u64);

/// What a calm-neighbourhood run found at its first law impact.
struct CalmOutcome {
    /// The step it came at.
    step: usize,
    /// That step's impacts.
    events: Vec<ImpactBits>,
    /// Fast bodies left unhooked so far.
    calm: u64,
    /// Whether an impact of that step involves the partner.
    hit: bool,
}

/// An empty world without gravity for the calm-neighbourhood tests: an
/// elastic law in `mode`, a rest speed of 0.1, the test on or off.
fn calm_world(mode: Mode, calm: bool) -> TestWorld {
    let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
    let config = k::ResolverConfig {
        rest_speed: Some(0.1),
        calm_neighbourhoods: calm,
        ..Default::default()
    };
    let law = Law::new(LawParams::default()).unwrap();
    w.kimpact = k::Kimpact::with_config(law, mode, config).unwrap();
    w
}

/// An angular velocity of `spin` rad/s about the first axis, in either
/// dimension (2D: a scalar; 3D: about x).
trait Spin {
    fn about_first_axis(spin: Real) -> Self;
}

impl Spin for Real {
    fn about_first_axis(spin: Real) -> Self {
        spin
    }
}

impl Spin for Vector {
    fn about_first_axis(spin: Real) -> Self {
        Vector::X * spin
    }
}

/// One calm-neighbourhood run: steps until the first law impact (at most
/// 40). The moving block's balls spin at `spin` rad/s (about the first
/// axis of the angular velocity: z in 2D, x in 3D).
fn calm_run(mode: Mode, partner: CalmPartner, calm: bool, spin: Real) -> CalmOutcome {
    let mut w = calm_world(mode, calm);
    // 256 balls in 2D, 343 in 3D: enough fast bodies for the test to run.
    let n: usize = if DIM == 2 { 16 } else { 7 };
    let (r, spacing, speed): (Real, Real, Real) = (0.5, 1.2, 3.0);
    let half = 0.5 * spacing * (n - 1) as Real;
    let block = |w: &mut TestWorld, x0: Real, velocity: Vector, seed: usize| {
        let mut list = Vec::new();
        for i in 0..n.pow(DIM as u32) {
            let mut p = Vector::ZERO;
            let mut v = velocity;
            let mut rest = i;
            for axis in 0..DIM {
                p[axis] = -half + spacing * (rest % n) as Real;
                rest /= n;
                v[axis] += 0.01 * (((i * 7 + axis * 3 + seed) % 5) as Real - 2.0);
            }
            p[0] += x0;
            let body = RigidBodyBuilder::dynamic().translation(p).linvel(v).can_sleep(false);
            let collider = ColliderBuilder::ball(r).mass(1.0).friction(0.0).restitution(0.0);
            let (h, c) = w.world.insert(body, collider);
            if seed == 0 && spin != 0.0 {
                w.world.bodies[h].set_angvel(Spin::about_first_axis(spin), true);
            }
            w.kimpact.mark(&w.world.colliders, c).unwrap();
            list.push(c);
        }
        list
    };
    // The block's front surface starts 1.0 short of the partner's: it
    // arrives within about 10 steps.
    let x0 = -(half + r + 0.5);
    block(&mut w, x0, Vector::X * speed, 0);
    let target: Vec<ColliderHandle> = match partner {
        CalmPartner::Block => block(&mut w, -x0, -Vector::X * speed, 1),
        CalmPartner::Wall => {
            let mut he = Vector::splat(half + 2.0);
            he[0] = 0.5;
            vec![w.wall(Vector::X * 1.0, he)]
        }
        CalmPartner::Sleeper => {
            let body = RigidBodyBuilder::dynamic().translation(Vector::X * 1.0).sleeping(true);
            let collider = ColliderBuilder::ball(r).mass(1.0).friction(0.0).restitution(0.0);
            let (_, c) = w.world.insert(body, collider);
            w.kimpact.mark(&w.world.colliders, c).unwrap();
            vec![c]
        }
    };
    for step in 1..=40 {
        w.step();
        let events = w.kimpact.events();
        if !events.is_empty() {
            let hit = events
                .iter()
                .any(|e| target.contains(&e.collider1) != target.contains(&e.collider2));
            let list = events
                .iter()
                .map(|e| {
                    (
                        e.collider1,
                        e.collider2,
                        f64::from(e.time).to_bits(),
                        f64::from(e.impulse).to_bits(),
                    )
                })
                .collect();
            return CalmOutcome {
                step,
                events: list,
                calm: w.kimpact.stats().calm_bodies,
                hit,
            };
        }
    }
    panic!("{mode} {partner:?}: no impact in 40 steps");
}

/// A block of balls moving as a whole is left unhooked (rapier keeps
/// recycling its contacts), and still meets its partners through the law
/// exactly as when every fast ball is hooked: a second block flying at it,
/// a fixed wall, a sleeping ball. The first impacts come at the same step,
/// between the same colliders, at the same times with the same impulses,
/// in every law mode. (Judged from where the balls are at the start of the
/// step alone, without their motion over it, the blocks' meeting came a
/// step late; without the leaves of rapier's tree, the wall and the sleeper
/// were met by rapier's solver.)
#[test]
fn calm_blocks_go_unhooked_and_meet_their_partners_as_hooked_ones_do() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        for partner in [CalmPartner::Block, CalmPartner::Wall, CalmPartner::Sleeper] {
            let on = calm_run(mode, partner, true, 0.0);
            let off = calm_run(mode, partner, false, 0.0);
            assert_eq!(off.calm, 0, "{mode} {partner:?}: the test ran while switched off");
            assert!(on.calm > 0, "{mode} {partner:?}: no body was left unhooked");
            assert!(on.hit, "{mode} {partner:?}: the first impacts do not involve the partner");
            assert_eq!(
                (on.step, &on.events),
                (off.step, &off.events),
                "{mode} {partner:?}: unhooked calm bodies changed the first impacts"
            );
        }
    }
}

/// A spinning ball reaches no farther than a still one (a ball is the
/// same shape however it turns): a block of balls spinning at 60 rad/s
/// (a turn per step) is left unhooked as a still one is, and
/// meets a wall exactly as when every ball is hooked, in every law mode.
#[test]
fn spinning_calm_balls_stay_calm() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let on = calm_run(mode, CalmPartner::Wall, true, 60.0);
        let off = calm_run(mode, CalmPartner::Wall, false, 60.0);
        let still = calm_run(mode, CalmPartner::Wall, true, 0.0);
        assert!(on.hit, "{mode}: the first impacts do not involve the wall");
        assert_eq!(on.calm, still.calm, "{mode}: spinning balls were judged less calm");
        assert_eq!(
            (on.step, &on.events),
            (off.step, &off.events),
            "{mode}: unhooked spinning balls changed the first impacts"
        );
    }
}

/// A ball whose velocity turns NaN inside a block of touching balls that
/// moves as a whole (so its balls are calm, and unhooked) keeps its
/// neighbours hooked, so that the hook's runtime guard sees their pairs,
/// while the rest of the block stays unhooked; nothing else turns NaN, in
/// every law mode.
#[test]
fn a_nan_ball_inside_a_calm_block_keeps_its_neighbours_hooked() {
    for mode in [Mode::Restitution, Mode::Impulse, Mode::Exact] {
        let mut w = calm_world(mode, true);
        let n: usize = if DIM == 2 { 16 } else { 7 };
        let (r, spacing) = (0.5 as Real, 1.005 as Real);
        let mut balls = Vec::new();
        for i in 0..n.pow(DIM as u32) {
            let mut p = Vector::ZERO;
            let mut rest = i;
            for axis in 0..DIM {
                p[axis] = spacing * (rest % n) as Real;
                rest /= n;
            }
            let body = RigidBodyBuilder::dynamic()
                .translation(p)
                .linvel(Vector::X * 3.0)
                .can_sleep(false);
            let collider = ColliderBuilder::ball(r).mass(1.0).friction(0.0).restitution(0.0);
            let (b, c) = w.world.insert(body, collider);
            w.kimpact.mark(&w.world.colliders, c).unwrap();
            balls.push((b, c));
        }
        for _ in 0..3 {
            w.step();
        }
        // The ball at the block's centre.
        let centre_index: usize = (0..DIM).map(|axis| (n / 2) * n.pow(axis as u32)).sum();
        let (middle, _) = balls[centre_index];
        w.world.bodies[middle].set_linvel(Vector::X * Real::NAN, true);
        let centre = w.pos(middle);
        w.step();
        let hooked = |c: ColliderHandle| {
            w.world.colliders[c]
                .active_hooks()
                .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        };
        let (mut near, mut far_unhooked) = (0, 0);
        for &(b, c) in &balls {
            if b == middle {
                continue;
            }
            assert!(
                w.vel(b).is_finite() && w.pos(b).is_finite(),
                "{mode}: NaN reached a neighbour: {:?}",
                w.vel(b)
            );
            let d = f64::from((w.pos(b) - centre).length());
            if d < 1.1 {
                near += 1;
                assert!(hooked(c), "{mode}: a neighbour of the NaN ball is unhooked");
            } else if d > 4.0 && !hooked(c) {
                far_unhooked += 1;
            }
        }
        assert_eq!(near, 2 * DIM, "{mode}: the NaN ball's neighbours");
        assert!(far_unhooked > 0, "{mode}: the block was not calm");
    }
}
