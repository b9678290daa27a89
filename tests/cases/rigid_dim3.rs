// The rigid cases' shapes of 3D only (included by tests/adapter.rs into the
// 3D modules; cases/rigid_dim2.rs is the 2D counterpart).

/// The marked shapes of this dimension beyond those of both: the cylinder
/// and the cone (axes along the body's y).
fn dimension_shapes() -> Vec<(&'static str, ColliderBuilder)> {
    vec![
        ("cylinder", ColliderBuilder::cylinder(0.3, 0.25)),
        ("cone", ColliderBuilder::cone(0.3, 0.25)),
    ]
}

/// A flat fixed heightfield whose top lies at y = 0 over [−2, 2]².
fn heightfield_floor() -> ColliderBuilder {
    let heights = k::rapier::parry::utils::Array2::new(3, 3, vec![0.0; 9]);
    ColliderBuilder::heightfield(heights, Vector::new(4.0, 1.0, 4.0)).friction(0.0)
}

/// A fixed heightfield valley along z: x and z in [−2, 2], its top at
/// y = 0.5 at x = ±2 and 0 along x = 0 (an edge between two slopes),
/// frictionless.
fn valley_heightfield() -> ColliderBuilder {
    let heights = vec![0.5, 0.5, 0.5, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5];
    let heights = k::rapier::parry::utils::Array2::new(3, 3, heights);
    ColliderBuilder::heightfield(heights, Vector::new(4.0, 1.0, 4.0)).friction(0.0)
}
