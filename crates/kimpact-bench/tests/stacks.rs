//! The allocation attribution's rule (`kimpact_harness::is_kimpact`) on
//! stacks written by hand: the innermost known frame decides.

use kimpact_harness::is_kimpact;

#[test]
fn attribution_reads_the_innermost_known_frame() {
    let hook = [
        "/r/alloc/src/raw_vec.rs:1",
        "./crates/rapier-adapter/src/resolver.rs:270",
        "/c/rapier3d-0.36.1/src/pipeline/physics_pipeline.rs:1",
    ];
    assert!(is_kimpact(hook));
    // The adapter's files as rustc names them, through a crate's link.
    for krate in ["kimpact2d", "kimpact3d", "kimpact2d-f64", "kimpact3d-f64"] {
        let file = format!("./crates/{krate}/src/replay.rs:1");
        assert!(is_kimpact(["/r/alloc/src/raw_vec.rs:1", file.as_str()]));
    }
    let rapier = [
        "/r/alloc/src/raw_vec.rs:1",
        "/c/rapier3d-0.36.1/src/pipeline/physics_pipeline/mod.rs:1",
        "./crates/rapier-adapter/src/resolver.rs:1",
    ];
    assert!(!is_kimpact(rapier));
    // rapier's modified-bodies list regrowing under kimpact's velocity
    // write is rapier's.
    let write = [
        "/r/alloc/src/raw_vec.rs:1",
        "/c/rapier2d-0.36.1/src/dynamics/rigid_body_set.rs:277",
        "./crates/rapier-adapter/src/replay.rs:1",
    ];
    assert!(!is_kimpact(write));
    // Neither: rapier's (the user's own code, std).
    assert!(!is_kimpact(["/r/alloc/src/raw_vec.rs:1", "?"]));
}
