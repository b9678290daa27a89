// Long-run scenes (the elastic gas and the ball pit) and the soak runner,
// written once for 2D/3D in f64. Included into modules that alias an f64
// adapter crate as `k` and bring `TestWorld`, `Mode`, `DIM`, `Real`, `Vector`
// and rapier's prelude into scope: by `tests/adapter.rs` (for `long.rs`), by
// `tests/soak.rs` (the short CI version) and by `examples/soak.rs` (the soak
// command).

/// `n` balls of radius `r` on a grid inside a box of inner half-size `half`.
fn fill(
    w: &mut TestWorld,
    n: usize,
    r: Real,
    half: Real,
    speed: Real,
    masses: &[Real],
) -> Vec<RigidBodyHandle> {
    use rand::{RngExt, SeedableRng};
    // The seeded generator of positions and velocities.
    let mut rng = rand::rngs::Xoshiro256PlusPlus::seed_from_u64(42);
    let per_side = ((n as f64).powf(1.0 / DIM as f64).ceil()) as usize;
    let spacing = 2.0 * half / per_side as Real;
    assert!(spacing > 2.0 * r, "the grid must not overlap");
    let mut out = Vec::new();
    let mut i = 0usize;
    while out.len() < n {
        let mut p = Vector::ZERO;
        let mut rest = i;
        for axis in 0..DIM {
            p[axis] = -half + spacing * (0.5 + (rest % per_side) as Real);
            rest /= per_side;
        }
        let mut v = Vector::ZERO;
        for axis in 0..DIM {
            v[axis] = speed * rng.random_range(-1.0..1.0) as Real;
        }
        let m = masses[out.len() % masses.len()];
        out.push(w.ball(p, v, r, m).0);
        i += 1;
    }
    out
}

/// Whether every ball's centre is finite and inside the box.
#[allow(dead_code)]
fn inside(w: &TestWorld, balls: &[RigidBodyHandle], half: Real) -> bool {
    balls.iter().all(|&b| ball_inside(w, b, half))
}

fn ball_inside(w: &TestWorld, b: RigidBodyHandle, half: Real) -> bool {
    let p = w.pos(b);
    p.is_finite() && (0..DIM).all(|a| p[a].abs() <= half)
}

/// Gravity of the pit (m/s², along −y).
const PIT_G: Real = 9.81;

/// The elastic gas: `n` balls of radius 0.5 and mass 1, velocity components
/// uniform in [−3, 3], in a closed box of inner half-size `half`, no
/// gravity, d̃ = 0.
fn gas_world(mode: Mode, n: usize, half: Real) -> (TestWorld, Vec<RigidBodyHandle>) {
    let mut w = TestWorld::new(mode, 0.0, Vector::ZERO);
    w.closed_box(half, WALL);
    let balls = fill(&mut w, n, 0.5, half, 3.0, &[1.0]);
    (w, balls)
}

/// The ball pit: `n` balls of radius 0.25 and masses 1, 2, 0.5 in turn,
/// velocity components uniform in [−1, 1], dropped in a closed box of inner
/// half-size `half` under gravity, d̃ = 0.01.
fn pit_world(mode: Mode, n: usize, half: Real) -> (TestWorld, Vec<RigidBodyHandle>) {
    let mut w = TestWorld::new(mode, 0.01, -Vector::Y * PIT_G);
    w.closed_box(half, WALL);
    let balls = fill(&mut w, n, 0.25, half, 1.0, &[1.0, 2.0, 0.5]);
    (w, balls)
}

/// The box of `long.rs`'s 500-ball gas (half-size 22 in 2D, 7 in 3D),
/// scaled to keep its density for `n` balls.
#[allow(dead_code)]
fn gas_half(n: usize) -> Real {
    let base: Real = if DIM == 2 { 22.0 } else { 7.0 };
    base * ((n as f64 / 500.0).powf(1.0 / DIM as f64)) as Real
}

/// The box of `long.rs`'s 1,000-ball pit (half-size 12 in 2D, 4 in 3D),
/// scaled to keep its density for `n` balls.
#[allow(dead_code)]
fn pit_half(n: usize) -> Real {
    let base: Real = if DIM == 2 { 12.0 } else { 4.0 };
    base * ((n as f64 / 1000.0).powf(1.0 / DIM as f64)) as Real
}

/// The soak's bound on the exact gas's energy: |E − E₀|/E₀ at every step.
#[allow(dead_code)]
const GAS_EXACT_TOL: f64 = 1e-9;

/// The soak's bound on the pit's energy rise: (E − E₀)/E₀ at every step,
/// energies measured from the floor (potential plus kinetic). rapier's own
/// contact correction may add a little (it does natively); the same
/// allowance as `long.rs`'s 400-step test.
#[allow(dead_code)]
const PIT_RISE_TOL: f64 = 1e-3;

/// Wall thickness of the soak's boxes (`closed_box(half, WALL)`).
const WALL: Real = 1.0;

/// The outcome of one soak run.
#[allow(dead_code)]
#[derive(Clone, Debug)]
struct Soak {
    scene: &'static str,
    mode: Mode,
    balls: usize,
    /// Steps run (fewer than asked when the CPU-time limit stopped the run).
    steps: u64,
    /// Steps asked for.
    asked: u64,
    wall: std::time::Duration,
    /// CPU time of the run's thread (user + system, from
    /// `/proc/thread-self/stat`; NaN where unavailable).
    cpu: f64,
    /// Energy at the start (gas: kinetic; pit: kinetic plus potential,
    /// measured from the floor).
    e_start: f64,
    e_end: f64,
    e_max: f64,
    e_min: f64,
    /// max (E − E₀)/E₀ over every step.
    rise: f64,
    /// max |E − E₀|/E₀ over every step.
    drift: f64,
    /// Balls that escaped: centre outside the box at the end, or beyond a
    /// wall's outer face at some step.
    escaped: usize,
    /// Balls whose centre went past a wall's inner face at some step (sank
    /// deeper than their radius into a wall), whether or not they came back.
    excursions: usize,
    /// The first step a centre was past a wall's inner face, and where.
    first_excursion: Option<(u64, Vector)>,
    /// The deepest any ball sank into a wall, in radii (1: centre on the
    /// wall's inner face).
    max_penetration: f64,
    /// Balls whose position or velocity was non-finite at some step.
    nan: usize,
    /// Steps whose total energy was non-finite.
    nan_energy_steps: u64,
    /// The first step a ball's position or velocity was non-finite.
    first_nan: Option<u64>,
    stats: k::Stats,
}

#[allow(dead_code)]
impl Soak {
    /// The energy bound this run is held to (`None`: reported only; the
    /// non-exact modes lose the gas's energy and are not bounded).
    fn bound(&self) -> Option<(&'static str, f64, f64)> {
        match (self.scene, self.mode) {
            ("gas", Mode::Exact) => Some(("|E-E0|/E0", self.drift, GAS_EXACT_TOL)),
            ("pit", _) => Some(("(E-E0)/E0", self.rise, PIT_RISE_TOL)),
            _ => None,
        }
    }

    /// No NaN, no ball escaped, the energy within its bound.
    fn passed(&self) -> bool {
        self.escaped == 0
            && self.nan == 0
            && self.nan_energy_steps == 0
            && self.bound().is_none_or(|(_, v, tol)| v <= tol)
    }

    /// One line: steps, wall time, energies, escaped and NaN counts.
    fn summary(&self) -> String {
        let secs = self.wall.as_secs_f64();
        let first = |s: Option<u64>| s.map_or("-".to_owned(), |s| s.to_string());
        let first_excursion = self.first_excursion.map_or("-".to_owned(), |(s, p)| {
            let p: Vec<String> = (0..DIM).map(|a| format!("{:.3}", p[a])).collect();
            format!("{s} at ({})", p.join(", "))
        });
        let bound = match self.bound() {
            Some((what, v, tol)) => format!("{what} max {v:.3e} (bound {tol:.0e})"),
            None => format!("rise {:.3e} drift {:.3e} (no bound)", self.rise, self.drift),
        };
        format!(
            "SOAK {scene} {DIM}D {mode} balls={balls} steps={steps}/{asked} wall={secs:.1}s cpu={cpu:.1}s ({us:.0} us cpu/step) \
             E start={e0:.9e} end={e1:.9e} max={emax:.9e} min={emin:.9e} {bound} \
             escaped={escaped} nan={nan} (first: step {first_nan}) \
             past_inner_face={excursions} (first: step {first_excursion}) \
             max_penetration={pen:.3}r impacts={impacts} clamped={clamped} \
             skipped_non_finite={skipped} event_cap_hits={caps} {verdict}",
            scene = self.scene,
            mode = self.mode,
            balls = self.balls,
            steps = self.steps,
            asked = self.asked,
            cpu = self.cpu,
            us = 1e6 * self.cpu / (self.steps.max(1) as f64),
            e0 = self.e_start,
            e1 = self.e_end,
            emax = self.e_max,
            emin = self.e_min,
            escaped = self.escaped,
            nan = self.nan,
            first_nan = first(self.first_nan),
            excursions = self.excursions,
            pen = self.max_penetration,
            impacts = self.stats.impacts,
            clamped = self.stats.clamped,
            skipped = self.stats.skipped_non_finite,
            caps = self.stats.event_cap_hits,
            verdict = if self.passed() { "PASS" } else { "FAIL" },
        )
    }
}

/// CPU time of the calling thread so far, in seconds (Linux; NaN
/// elsewhere). Per thread, so that tests running side by side do not count
/// each other's time.
#[allow(dead_code)]
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").unwrap_or_default();
    // Fields after the command name: state is field 3, utime 14, stime 15,
    // in clock ticks (100 per second on Linux).
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or("", |(_, rest)| rest)
        .split_whitespace()
        .collect();
    let tick = |i: usize| fields.get(i).and_then(|x| x.parse::<f64>().ok());
    match (tick(11), tick(12)) {
        (Some(u), Some(s)) => (u + s) / 100.0,
        _ => f64::NAN,
    }
}

/// Run `scene` ("gas" or "pit") with `balls` balls in `mode` for `steps`
/// steps (or until its thread has used `cpu_limit` seconds of CPU time: a
/// budget that does not depend on what else the machine runs),
/// checking every ball and the energy after every step; print a progress
/// line every `every` steps (0: never).
#[allow(dead_code)]
fn soak(
    scene: &'static str,
    mode: Mode,
    balls: usize,
    steps: u64,
    every: u64,
    cpu_limit: Option<f64>,
) -> Soak {
    let (mut w, handles, half, r, floor) = match scene {
        "gas" => {
            let half = gas_half(balls);
            let (w, h) = gas_world(mode, balls, half);
            (w, h, half, 0.5, None)
        }
        "pit" => {
            let half = pit_half(balls);
            let (mut w, h) = pit_world(mode, balls, half);
            // Unlike `long.rs`'s pit, the soak's pile may fall asleep once it
            // settles (rapier's default), as in a game.
            for &b in &h {
                *w.world.bodies[b].activation_mut() = RigidBodyActivation::active();
            }
            // Potential energy measured from the floor (y = −half).
            let floor: f64 = h
                .iter()
                .map(|&b| (w.world.bodies[b].mass() * PIT_G * half) as f64)
                .sum();
            (w, h, half, 0.25, Some(floor))
        }
        other => panic!("unknown scene {other:?}: expected gas or pit"),
    };
    let energy = |w: &TestWorld| match floor {
        None => w.kinetic(),
        Some(floor) => w.kinetic() + w.potential() + floor,
    };
    let e_start = energy(&w);
    // Per ball: beyond a wall's outer face, past its inner face, non-finite.
    let mut gone = vec![false; handles.len()];
    let mut past = vec![false; handles.len()];
    let mut bad = vec![false; handles.len()];
    let count = |v: &[bool]| v.iter().filter(|&&x| x).count();
    let (mut e_max, mut e_min, mut e_end) = (e_start, e_start, e_start);
    let (mut rise, mut drift) = (0.0f64, 0.0f64);
    let mut reach: Real = 0.0;
    let mut nan_energy_steps = 0u64;
    let mut first_excursion = None;
    let mut first_nan = None;
    let start = std::time::Instant::now();
    let cpu_start = cpu_seconds();
    let mut done = 0;
    for step in 1..=steps {
        if step % 100 == 1 && cpu_limit.is_some_and(|l| cpu_seconds() - cpu_start >= l) {
            break;
        }
        w.step();
        done = step;
        for (i, &b) in handles.iter().enumerate() {
            let rb = &w.world.bodies[b];
            let p = rb.translation();
            if !(p.is_finite() && rb.linvel().is_finite()) {
                bad[i] = true;
                first_nan = first_nan.or(Some(step));
                continue;
            }
            let far = (0..DIM).map(|a| p[a].abs()).fold(0.0, Real::max);
            reach = reach.max(far);
            if far > half {
                past[i] = true;
                first_excursion = first_excursion.or(Some((step, p)));
            }
            if far > half + WALL {
                gone[i] = true;
            }
        }
        let e = energy(&w);
        if e.is_finite() {
            e_max = e_max.max(e);
            e_min = e_min.min(e);
            rise = rise.max((e - e_start) / e_start);
            drift = drift.max(((e - e_start) / e_start).abs());
        } else {
            nan_energy_steps += 1;
        }
        e_end = e;
        if every > 0 && step % every == 0 {
            let secs = start.elapsed().as_secs_f64();
            let eta = secs / step as f64 * (steps - step) as f64;
            let cpu = cpu_seconds() - cpu_start;
            println!(
                "  {scene} {DIM}D {mode}: step {step}/{steps} {secs:.1}s cpu {cpu:.1}s (eta {eta:.0}s) \
                 E={e:.12e} rise={rise:.3e} drift={drift:.3e} beyond_walls={} past_inner_face={} \
                 nan={} impacts={}",
                count(&gone),
                count(&past),
                count(&bad),
                w.kimpact.stats().impacts,
            );
        }
    }
    for (i, &b) in handles.iter().enumerate() {
        if !ball_inside(&w, b, half) {
            gone[i] = true;
        }
    }
    Soak {
        scene,
        mode,
        balls,
        steps: done,
        asked: steps,
        wall: start.elapsed(),
        cpu: cpu_seconds() - cpu_start,
        e_start,
        e_end,
        e_max,
        e_min,
        rise,
        drift,
        escaped: count(&gone),
        excursions: count(&past),
        first_excursion,
        max_penetration: ((reach - (half - r)) / r) as f64,
        nan: count(&bad),
        nan_energy_steps,
        first_nan,
        stats: w.kimpact.stats(),
    }
}
