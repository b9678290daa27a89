//! The free-fall frame: the velocity a world that falls as a whole shares,
//! against which the sweeps judge how far a body moves.
//!
//! rapier moves every body along a straight path over a step, so two
//! dynamic bodies close by `(v₁ − v₂) dt`: the same for any velocity `w`
//! taken off both. Where every collider of the world rides an awake
//! dynamic body, a body whose path velocity differs from `w` by little
//! cannot cross any partner unseen, however fast the world falls: under
//! gravity every free body's path differs from the straight one by the same
//! `½ g t²`. A fixed, kinematic or sleeping partner (or a collider without
//! a body) does not fall with the rest: with any, no frame is shared and
//! each body is judged by its own motion in the world.
//!
//! The frame is looked for only under gravity (without it a world rarely
//! drifts as a whole) and only when there are no more colliders than awake
//! bodies (a world with static geometry or sleeping bodies is turned away
//! without reading a body).

use crate::body_view::path_velocity;
use crate::math::{Real, Vector};
use crate::rapier::prelude::*;

/// The velocity every collider's body shares this step, if every collider
/// of `colliders` rides an awake (in `islands`' active set) dynamic body
/// with free translations and one gravity scale, faster than `threshold`
/// (half the rest speed: `prepare` flags every one, so that its pairs
/// reach kimpact's hook): the mean of their path velocities
/// (`path_velocity` with `gravity_dt`, rapier's `g dt`). `None` without
/// gravity, or when any collider rides anything else, or when the mean is
/// not finite.
///
/// (A body slow in the world may move fast against the frame; unflagged,
/// its pairs would be judged by its partners' motion against the frame
/// alone.)
pub(crate) fn free_fall_velocity(
    islands: &IslandManager,
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
    gravity_dt: Vector,
    threshold: Real,
) -> Option<Vector> {
    let awake = islands.num_active_bodies();
    if gravity_dt == Vector::ZERO || awake == 0 || colliders.len() > awake {
        return None;
    }
    let mut scale = None;
    let mut sum = Vector::ZERO;
    let mut riders = 0usize;
    let mut movers = 0usize;
    for handle in islands.active_bodies() {
        let rb = bodies.get(handle)?;
        if !rb.is_dynamic()
            || rb.locked_axes().intersects(LockedAxes::TRANSLATION_LOCKED)
            || rb.is_sleeping()
            || rb.linvel().length_squared() <= threshold * threshold
        {
            return None;
        }
        let s = rb.gravity_scale();
        if *scale.get_or_insert(s) != s {
            return None;
        }
        sum += path_velocity(rb, gravity_dt);
        riders += rb.colliders().len();
        movers += 1;
    }
    // Every collider counted belongs to one awake body: equal counts leave
    // no collider on anything else.
    if riders != colliders.len() {
        return None;
    }
    let w = sum / movers as Real;
    w.is_finite().then_some(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A world of two balls moving at `velocity` and three times it, and
    /// a fixed collider if `floor`; one step taken without gravity so that
    /// rapier's active set is filled.
    fn world(velocity: Vector, floor: bool) -> PhysicsWorld {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        for (i, v) in [velocity, velocity * 3.0].into_iter().enumerate() {
            let rb = RigidBodyBuilder::dynamic()
                .translation(Vector::X * (4.0 * i as Real))
                .linvel(v)
                .can_sleep(false);
            let h = world.bodies.insert(rb);
            world
                .colliders
                .insert_with_parent(ColliderBuilder::ball(0.5), h, &mut world.bodies);
        }
        if floor {
            // Any collider without a body: a fixed ball far below.
            world
                .colliders
                .insert(ColliderBuilder::ball(10.0).translation(-Vector::Y * 50.0));
        }
        world.step();
        world
    }

    fn shared(world: &PhysicsWorld, gravity_dt: Vector) -> Option<Vector> {
        free_fall_velocity(
            &world.islands,
            &world.bodies,
            &world.colliders,
            gravity_dt,
            0.1,
        )
    }

    #[test]
    fn a_falling_world_shares_the_mean_path_velocity() {
        let v = Vector::X * 2.0;
        let g_dt = -Vector::Y * 0.5;
        let w =
            shared(&world(v, false), g_dt).expect("two awake balls and nothing else share a frame");
        // Independent answer: the two path velocities, v + g dt and 3 v + g dt.
        let expected = (v + g_dt + v * 3.0 + g_dt) / 2.0;
        assert!((w - expected).length() <= 1e-6 * expected.length());
    }

    #[test]
    fn a_fixed_floor_or_no_gravity_shares_no_frame() {
        let v = Vector::X * 2.0;
        assert!(shared(&world(v, true), -Vector::Y * 0.5).is_none());
        assert!(shared(&world(v, false), Vector::ZERO).is_none());
    }
}
