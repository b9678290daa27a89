//! The budget "no heap allocation per step in steady state in kimpact's own
//! code", checked through the bench's own attribution (every allocation of
//! the measured steps classified from its stack as kimpact's or rapier's):
//! none is kimpact's once a small pile has settled, while the first steps,
//! in which kimpact's scratch lists grow, are seen as kimpact's; the same
//! once rapier's restitution example (every ball marked with its own
//! material) has landed, and in the pinball's steady state. Counts, not
//! timings.

mod common;

/// `kimpact-bench --solo --attribute` on one configuration: (allocations of
/// the measured steps, and of the attributed pass: classified, kimpact's).
fn attribute(scene: &str, mode: &str, warmup: usize, steps: usize) -> (u64, u64, u64) {
    let (warmup, steps) = (warmup.to_string(), steps.to_string());
    let args = vec![
        "--solo",
        "--attribute",
        "--scene",
        scene,
        "--mode",
        mode,
        "--precision",
        "f32",
        "--balls",
        "1000",
        "--warmup",
        &warmup,
        "--steps",
        &steps,
    ];
    let stdout = common::run_bench(args);
    let solo: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON line");
    let (seen, own) = (&solo["attributed"][0], &solo["attributed"][1]);
    let count = |v: &serde_json::Value| {
        v.as_u64()
            .unwrap_or_else(|| panic!("not attributed: {solo}"))
    };
    (count(&solo["allocs"]), count(seen), count(own))
}

#[test]
fn kimpact_allocates_nothing_in_a_settled_pile() {
    for mode in ["restitution", "impulse", "exact"] {
        let (allocs, seen, own) = attribute("pit3d", mode, 200, 30);
        // rapier allocates in every step; the attributed pass repeats the
        // counted one (serial rapier is deterministic) and classifies each
        // of its allocations, not the classifier's own.
        assert!(seen > 0, "{mode}: no allocation seen");
        assert_eq!(seen, allocs, "{mode}: every allocation classified");
        assert_eq!(own, 0, "{mode}: {own} of {seen} allocations are kimpact's");
    }
}

#[test]
fn the_first_steps_allocations_of_kimpact_are_seen() {
    // The replay's lists grow from nothing in the first steps of a falling
    // pile: the attribution must find them.
    let (allocs, seen, own) = attribute("pit3d", "exact", 0, 5);
    assert_eq!(seen, allocs, "every allocation classified");
    assert!(own > 0 && own < seen, "{own} of {seen}");
}

#[test]
fn kimpact_allocates_nothing_once_the_restitution_example_has_landed() {
    for mode in ["restitution", "impulse", "exact"] {
        let (allocs, seen, own) = attribute("restitution3", mode, 300, 30);
        assert!(seen > 0, "{mode}: no allocation seen");
        assert_eq!(seen, allocs, "{mode}: every allocation classified");
        assert_eq!(own, 0, "{mode}: {own} of {seen} allocations are kimpact's");
    }
}

#[test]
fn kimpact_allocates_nothing_in_the_pinball_s_steady_state() {
    // Balls rolling along the polyline table and struck by the flippers:
    // the replay's casts against the table's segments start touching.
    for mode in ["restitution", "impulse", "exact"] {
        let (allocs, seen, own) = attribute("pinball", mode, 600, 300);
        assert!(seen > 0, "{mode}: no allocation seen");
        assert_eq!(seen, allocs, "{mode}: every allocation classified");
        assert_eq!(own, 0, "{mode}: {own} of {seen} allocations are kimpact's");
    }
}
