// Long f64 runs: the elastic gas in a closed box and the ball pit. The
// scenes and their helpers (`gas_world`, `pit_world`, `fill`, `inside`) are
// in `soak.rs`, shared with the soak command (`examples/soak.rs`).

/// 500 elastic balls in a closed box, no gravity, 10,000 steps.
fn gas(mode: Mode, steps: usize) -> (f64, f64, bool) {
    let half = if DIM == 2 { 22.0 } else { 7.0 };
    let (mut w, balls) = gas_world(mode, 500, half);
    let e0 = w.kinetic();
    for _ in 0..steps {
        w.step();
    }
    (e0, w.kinetic(), inside(&w, &balls, half))
}

/// The exact mode keeps a 500-ball elastic gas's energy to 1e-9 over
/// 10,000 steps (f64 only; called from `adapter.rs`).
fn exact_gas_check() {
    let (e0, e1, inside) = gas(Mode::Exact, 10_000);
    assert!(inside, "a ball escaped the box");
    assert!(
        ((e1 - e0) / e0).abs() < 1e-9,
        "exact: energy {e0} -> {e1} (relative {:e})",
        (e1 - e0) / e0
    );
}

/// 1,000 balls of mixed masses dropped into an open box under gravity.
fn pit(mode: Mode, steps: usize) -> (f64, f64, bool) {
    let half = if DIM == 2 { 12.0 } else { 4.0 };
    let (mut w, balls) = pit_world(mode, 1000, half);
    let total = |w: &TestWorld| w.kinetic() + w.potential();
    let e0 = total(&w);
    let mut max_rise: f64 = 0.0;
    for _ in 0..steps {
        w.step();
        max_rise = max_rise.max(total(&w) - e0);
    }
    // Energies are measured from the floor, so the scale is the pile's
    // potential energy plus its kinetic energy.
    let floor = w
        .world
        .bodies
        .iter()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(_, b)| f64::from(b.mass()) * 9.81 * f64::from(half))
        .sum::<f64>();
    (
        max_rise / (e0 + floor),
        w.kinetic(),
        inside(&w, &balls, half),
    )
}

#[test]
fn ball_pits_never_gain_energy_in_any_mode() {
    for mode in Mode::ALL {
        let (rise, kinetic, inside) = pit(mode, 400);
        eprintln!(
            "pit {DIM}D {mode}: largest energy rise {rise:.2e} of the total; final kinetic {kinetic:.3e}"
        );
        assert!(inside, "{mode}: a ball left the pit");
        assert!(kinetic.is_finite());
        // rapier's own contact correction may add a little (it does in
        // native mode); the law must not add more than that allowance.
        assert!(rise < 1e-3, "{mode}: energy rose by {rise:e} of the total");
    }
}
