//! Whose code an allocation's stack leads to: the rule of the bench's
//! allocation attribution, on the source paths of the stack's frames.

/// kimpact's sources: the core, the adapter and the four crates by which
/// rustc names the adapter's files.
const KIMPACT_SOURCES: [&str; 6] = [
    "crates/kimpact/src/",
    "rapier-adapter/src/",
    "crates/kimpact2d/src/",
    "crates/kimpact3d/src/",
    "crates/kimpact2d-f64/src/",
    "crates/kimpact3d-f64/src/",
];

/// Whether a stack (its frames' paths, innermost first) reaches kimpact's
/// sources before rapier's pipeline step. An allocation in rapier's
/// `RigidBodySet` is rapier's: its list of modified bodies starts each step
/// empty and regrows for whoever sets a velocity, kimpact or the user.
pub fn is_kimpact<'a>(paths: impl IntoIterator<Item = &'a str>) -> bool {
    for path in paths {
        if KIMPACT_SOURCES.iter().any(|dir| path.contains(dir)) {
            return true;
        }
        if path.contains("/src/pipeline/physics_pipeline")
            || path.contains("/src/dynamics/rigid_body_set.rs")
        {
            return false;
        }
    }
    false
}
