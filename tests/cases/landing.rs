// The rebound cut-off (`ResolverConfig::rebound_cutoff`) on a struck row of
// three balls, against the law's sequence worked out here in closed form.

/// The law's dissipation in these tests: a head-on impact of two equal
/// balls then has the restitution `e = √(1 − 8 d̃)` (the law dissipates
/// `d = d̃ (m₁ + m₂) u²`, and `½ μ u² (1 − e²)` with `μ = ½`).
const ROW_DISSIPATION: Real = 0.09;

/// The law's events of one step: the two colliders' indices in the row
/// (in order) and the approach speed.
type RowEvents = Vec<([usize; 2], f64)>;

/// A row along x, no gravity: ball A (speed 1) meets B, which touches C,
/// all of mass 1 and radius 0.5, in mode `mode` with the rebound cut-off
/// `cutoff`, with impact friction (`μ = 0.5`, nothing to slip on head-on)
/// if `friction`. Steps `steps` times; the law's events of each step, and
/// the balls' velocities along x at the end.
fn struck_row(mode: Mode, cutoff: Option<Real>, friction: bool, steps: usize) -> (Vec<RowEvents>, [f64; 3]) {
    let mut w = TestWorld::new(mode, ROW_DISSIPATION, Vector::ZERO);
    let config = k::ResolverConfig {
        rebound_cutoff: cutoff,
        ..k::ResolverConfig::default()
    };
    w.kimpact.set_config(config).unwrap();
    let (r, dt) = (0.5, w.world.integration_parameters.dt);
    // A meets B half-way through the first step.
    let (a, ca) = w.ball(Vector::X * -(2.0 * r + 0.5 * dt), Vector::X, r, 1.0);
    let (b, cb) = w.ball(Vector::ZERO, Vector::ZERO, r, 1.0);
    let (c, cc) = w.ball(Vector::X * (2.0 * r), Vector::ZERO, r, 1.0);
    if friction {
        let material = k::Material::new(ROW_DISSIPATION, ROW_DISSIPATION)
            .unwrap()
            .with_impact_friction(0.5, 0.0)
            .unwrap();
        for c in [ca, cb, cc] {
            w.kimpact.mark_with(&w.world.colliders, c, material).unwrap();
        }
    }
    let index = |ch: ColliderHandle| [ca, cb, cc].iter().position(|&x| x == ch).unwrap();
    let mut log = Vec::new();
    for _ in 0..steps {
        w.step();
        let step = w
            .kimpact
            .events()
            .iter()
            .map(|e| {
                let mut pair = [index(e.collider1), index(e.collider2)];
                pair.sort_unstable();
                (pair, f64::from(e.approach_speed))
            })
            .collect();
        log.push(step);
    }
    let v = [a, b, c].map(|h| f64::from(w.vel(h).x));
    (log, v)
}

/// The law's sequence in the row, by hand: A–B at 1, B–C at `(1 + e)/2`,
/// and A catching B again at `(1 − e)²/4`, all at the instant A meets B
/// (B and C touch). The restitution and the approach speeds.
fn row_sequence() -> (f64, [f64; 3]) {
    let e = (1.0 - 8.0 * f64::from(ROW_DISSIPATION)).sqrt();
    (e, [1.0, 0.5 * (1.0 + e), 0.25 * (1.0 - e).powi(2)])
}

#[test]
fn landing_a_rebound_below_the_cutoff_waits_for_the_next_step() {
    let (e, [u1, u2, u3]) = row_sequence();
    let tol = 10.0 * f64::from(tol());
    for (mode, friction) in [Mode::Impulse, Mode::Exact].into_iter().flat_map(|m| [(m, false), (m, true)]) {
        // Without the cut-off: the law's three impacts, in the first step.
        let (log, _) = struck_row(mode, None, friction, 1);
        let seen = &log[0];
        assert_eq!(seen.len(), 3, "{mode}, friction {friction}: {seen:?}");
        for (&(pair, u), (want_pair, want_u)) in seen.iter().zip([([0, 1], u1), ([1, 2], u2), ([0, 1], u3)]) {
            assert_eq!(pair, want_pair, "{mode}, friction {friction}: {seen:?}");
            assert!((u - want_u).abs() < tol, "{mode}, friction {friction}: approach {u}, closed form {want_u}");
        }
        let (_, plain) = struck_row(mode, None, friction, 3);
        // A cut-off between the rebound's approach and the others: the
        // rebound waits for the next step, where the law strikes it as
        // the pair's first impact there, and the row ends as without it.
        let cutoff = 2.0 * u3;
        let (log, v) = struck_row(mode, Some(cutoff as Real), friction, 3);
        let first: Vec<_> = log[0].iter().map(|&(pair, _)| pair).collect();
        assert_eq!(first, [[0, 1], [1, 2]], "{mode}, friction {friction}: {:?}", log[0]);
        assert_eq!(log[1].len(), 1, "{mode}, friction {friction}: {:?}", log[1]);
        let (pair, u) = log[1][0];
        assert_eq!(pair, [0, 1], "{mode}, friction {friction}: {:?}", log[1]);
        assert!((u - u3).abs() < tol, "{mode}, friction {friction}: the rebound's approach {u}, closed form {u3}");
        assert!(log[2].is_empty(), "{mode}, friction {friction}: {:?}", log[2]);
        let after = [
            0.5 * (1.0 - e) - 0.5 * (1.0 + e) * u3,
            0.25 * (1.0 - e * e) + 0.5 * (1.0 + e) * u3,
            0.25 * (1.0 + e).powi(2),
        ];
        for i in 0..3 {
            assert!((v[i] - after[i]).abs() < tol, "{mode}, friction {friction}: {v:?}, closed form {after:?}");
            assert!((plain[i] - after[i]).abs() < tol, "{mode}, friction {friction}: without the cut-off {plain:?}, closed form {after:?}");
        }
    }
}

#[test]
fn landing_the_cutoff_leaves_a_step_without_rebounds_bit_for_bit() {
    // An elastic Newton's cradle meets each pair once: the same bits with
    // and without a cut-off far above every approach.
    let run = |cutoff: Option<Real>| {
        let mut w = TestWorld::new(Mode::Exact, 0.0, Vector::ZERO);
        let config = k::ResolverConfig {
            rebound_cutoff: cutoff,
            ..k::ResolverConfig::default()
        };
        w.kimpact.set_config(config).unwrap();
        let dt = w.world.integration_parameters.dt;
        let mut balls = vec![w.ball(Vector::X * -(1.0 + 2.5 * dt), Vector::X, 0.5, 1.0).0];
        for i in 0..5 {
            balls.push(w.ball(Vector::X * i as Real, Vector::ZERO, 0.5, 1.0).0);
        }
        for _ in 0..20 {
            w.step();
        }
        (w.bits(&balls), w.kimpact.stats().impacts)
    };
    let (plain, impacts) = run(None);
    assert!(impacts >= 5, "the cradle's impacts: {impacts}");
    assert_eq!(run(Some(10.0)), (plain, impacts));
}
