// The rigid cases' shapes of 2D only (included by tests/adapter.rs into the
// 2D modules; cases/rigid_dim3.rs is the 3D counterpart).

/// The marked shapes of this dimension beyond those of both: none in 2D
/// (rapier's 2D shapes are those of `rigid_modes.rs`'s list).
fn dimension_shapes() -> Vec<(&'static str, ColliderBuilder)> {
    Vec::new()
}

/// A flat fixed heightfield whose top lies at y = 0 over x in [−2, 2].
fn heightfield_floor() -> ColliderBuilder {
    let mut scale = Vector::ZERO;
    scale[0] = 4.0;
    scale[1] = 1.0;
    ColliderBuilder::heightfield(vec![0.0; 5], scale).friction(0.0)
}

/// A fixed heightfield valley: x in [−2, 2], its top at y = 0.5 at both
/// ends and 0 at x = 0 (a vertex between two slopes), frictionless.
fn valley_heightfield() -> ColliderBuilder {
    let mut scale = Vector::ZERO;
    scale[0] = 4.0;
    scale[1] = 1.0;
    ColliderBuilder::heightfield(vec![0.5, 0.0, 0.5], scale).friction(0.0)
}
