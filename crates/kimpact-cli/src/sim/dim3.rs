// 3D helpers, included by `sim3d` and `sim3d_f64` (see mod.rs).

/// Scene vector → rapier vector.
fn vector(v: &[f64]) -> k::math::Vector {
    use k::math::Real;
    k::math::Vector::new(v[0] as Real, v[1] as Real, v[2] as Real)
}

/// rapier vector → scene vector.
fn to_vec(v: k::math::Vector) -> Vec<f64> {
    vec![v.x as f64, v.y as f64, v.z as f64]
}

/// rapier vector → a point of the crossing check (`z = 0` in 2D).
fn to_point(v: k::math::Vector) -> super::crossing::Point {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// The collider of a scene shape.
fn collider(shape: &crate::scene::Shape) -> k::rapier::prelude::ColliderBuilder {
    use k::math::Real;
    match shape {
        crate::scene::Shape::Ball { radius } => {
            k::rapier::prelude::ColliderBuilder::ball(*radius as Real)
        }
        crate::scene::Shape::Box { half_extents: h } => {
            k::rapier::prelude::ColliderBuilder::cuboid(h[0] as Real, h[1] as Real, h[2] as Real)
        }
    }
}

/// The body's orientation: quaternion `[x, y, z, w]`.
fn rotation(rb: &k::rapier::prelude::RigidBody) -> Vec<f64> {
    let q = rb.rotation();
    vec![q.x as f64, q.y as f64, q.z as f64, q.w as f64]
}
