//! The budget "no heap allocation per step in steady state in kimpact's own
//! code", checked through the bench's own attribution (every allocation of
//! the measured steps classified from its stack as kimpact's or rapier's):
//! none is kimpact's once a small pile has settled, while the first steps,
//! in which kimpact's scratch lists grow, are seen as kimpact's. Counts,
//! not timings.

mod common;

/// `kimpact-bench --solo --attribute` on one configuration: (allocations of
/// the measured steps, and of the attributed pass: classified, kimpact's).
fn attribute(scene: &str, mode: &str, warmup: usize, steps: usize) -> (u64, u64, u64) {
    let (warmup, steps) = (warmup.to_string(), steps.to_string());
    let stdout = common::run_bench([
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
    ]);
    let solo: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON line");
    assert_eq!(solo["attributed"], true, "{solo}");
    let field = |name: &str| solo[name].as_u64().expect(name);
    (field("allocs"), field("attr_seen"), field("attr_own"))
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
