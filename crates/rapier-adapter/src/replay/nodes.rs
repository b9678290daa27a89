//! The replay's nodes (a body, or a collider without one) and pairs: made
//! once per run, found by collider and body index.

use super::context::Run;
use super::node::{BallOnPath, Hit, Key, Motion, NO_PAIR, Node, Pair, RigidState, Slot};
use super::state::Replay;
use crate::body_view::{translations_locked, translations_partly_locked};
use crate::math::{Pose, Real, Vector};
use crate::rapier::prelude::*;
use crate::rigid_view::{angular, inverse_inertia, zero_angular};

/// A node with this many pairs is crowded (a body spawned into others, a
/// dense pile): whether a pair of it is in the run is looked up in
/// `Replay::crowd_pairs` rather than by walking its list.
const CROWD: u32 = 32;

/// The pair of colliders `c1` and `c2`, in either order, as one key.
fn pair_key(c1: ColliderHandle, c2: ColliderHandle) -> u64 {
    let (i, j) = (c1.into_raw_parts().0, c2.into_raw_parts().0);
    (u64::from(i.min(j)) << 32) | u64::from(i.max(j))
}

impl Replay {
    pub(super) fn clear(&mut self) {
        self.nodes.clear();
        self.ends.clear();
        self.degrees.clear();
        self.crowd_pairs.clear();
        self.hit.clear();
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            // Wrapped: forget every old stamp.
            self.body_slots.clear();
            self.collider_slots.clear();
            self.sweeping.clear();
            self.stamp = 1;
        }
        self.pairs.clear();
        self.bent.clear();
        self.apart.clear();
        self.deferred_range.clear();
        self.queue.clear();
        self.leaves.clear();
    }

    /// The node of collider `collider` (whose parent is `parent`): its
    /// body's, or its own for a collider without a body; made if the run
    /// has none yet.
    pub(super) fn node(
        &mut self,
        run: &Run,
        collider: ColliderHandle,
        parent: Option<RigidBodyHandle>,
    ) -> usize {
        if let Some(n) = self.collider_node(collider) {
            return n;
        }
        // A body's node may have been made for another of its colliders.
        let n = match parent {
            Some(h) => match self.body_node(Some(h)) {
                Some(n) => n,
                None => self.new_node(run, Key::Body(h)),
            },
            None => self.new_node(run, Key::Collider(collider)),
        };
        let slot = Slot {
            stamp: self.stamp,
            node: n as u32,
        };
        self.collider_slots.insert(collider, slot);
        n
    }

    /// The node of collider `c` in this run, if it has one.
    pub(super) fn collider_node(&self, c: ColliderHandle) -> Option<usize> {
        let slot = self.collider_slots.get(c)?;
        (slot.stamp == self.stamp).then_some(slot.node as usize)
    }

    /// Colliders `c1` and `c2` are a pair of the replay already (in either
    /// order). Reads only the replay's own arrays: most colliders a sweep
    /// meets in a pile are paired already, and reading them from rapier is
    /// a cache miss each.
    pub(super) fn has_pair(&self, c1: ColliderHandle, c2: ColliderHandle) -> bool {
        let (Some(a), Some(b)) = (self.collider_node(c1), self.collider_node(c2)) else {
            return false;
        };
        if self.degrees[a].max(self.degrees[b]) >= CROWD {
            return self.crowd_pairs.contains(&pair_key(c1, c2));
        }
        self.pairs_of(a).any(|i| {
            let p = &self.pairs[i];
            (p.c1 == c1 && p.c2 == c2) || (p.c1 == c2 && p.c2 == c1)
        })
    }

    /// A new node for `key` (a body, or a collider without one).
    fn new_node(&mut self, run: &Run, key: Key) -> usize {
        let node = match key.body().and_then(|h| run.bodies.get(h)) {
            // A dynamic body whose every translation is locked does not
            // move: an immovable node, as a fixed body's.
            Some(rb) if rb.is_dynamic() && !translations_locked(rb) => {
                let start = key.body().and_then(|h| run.input.starts.of(h));
                moving_node(run, key, rb, start)
            }
            Some(rb) => still_node(key, rb, run.dt),
            None => still(key, Vector::ZERO, run.dt),
        };
        let i = self.nodes.len();
        self.nodes.push(node);
        self.ends.push([NO_PAIR; 2]);
        self.degrees.push(0);
        if let Key::Body(h) = key {
            let slot = Slot {
                stamp: self.stamp,
                node: i as u32,
            };
            self.body_slots.insert(h, slot);
        }
        i
    }

    /// Bring the pair of colliders `c1` and `c2` into the run (making
    /// their nodes), unless it is in already or rapier would not let it
    /// touch; its number.
    pub(super) fn add_pair(
        &mut self,
        run: &Run,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> Option<usize> {
        // Already in (a node has a handful of pairs: a scan beats a set).
        if self.has_pair(c1, c2) {
            return None;
        }
        let colliders = run.colliders;
        let (co1, co2) = (colliders.get(c1)?, colliders.get(c2)?);
        let (p1, p2) = (co1.parent(), co2.parent());
        let a = self.node(run, c1, p1);
        let b = self.node(run, c2, p2);
        let dynamic = self.nodes[a].dynamic() || self.nodes[b].dynamic();
        if a == b
            || !run
                .input
                .filter
                .admits(run.bodies, colliders, [(c1, co1), (c2, co2)], dynamic)
        {
            return None;
        }
        let balls = match (self.ball(run, a, c1), self.ball(run, b, c2)) {
            (Some(b1), Some(b2)) => Some([b1, b2]),
            _ => None,
        };
        let i = self.pairs.len();
        self.pairs.push(Pair {
            a,
            b,
            c1,
            c2,
            balls,
            hit: Hit::NONE,
            apart_at: Real::NEG_INFINITY,
            struck: false,
            next: [NO_PAIR; 2],
        });
        for n in [a, b] {
            match self.ends[n] {
                [NO_PAIR, _] => self.ends[n] = [i as u32; 2],
                [_, last] => {
                    let last = last as usize;
                    let side = self.pairs[last].side(n);
                    self.pairs[last].next[side] = i as u32;
                    self.ends[n][1] = i as u32;
                }
            }
            self.degrees[n] += 1;
            if self.degrees[n] == CROWD {
                // Crowded from now on: its pairs are looked up in the set.
                let mut j = self.ends[n][0];
                while j != NO_PAIR {
                    let p = &self.pairs[j as usize];
                    self.crowd_pairs.insert(pair_key(p.c1, p.c2));
                    j = self.next_pair(j as usize, n);
                }
            }
        }
        if self.degrees[a].max(self.degrees[b]) >= CROWD {
            self.crowd_pairs.insert(pair_key(c1, c2));
        }
        Some(i)
    }

    /// The pair after pair `i` in node `n`'s list (`n` is one of its two).
    pub(super) fn next_pair(&self, i: usize, n: usize) -> u32 {
        let p = &self.pairs[i];
        p.next[p.side(n)]
    }

    /// Node `n`'s pairs, in the order they were added.
    pub(super) fn pairs_of(&self, n: usize) -> impl Iterator<Item = usize> + '_ {
        let mut i = self.ends[n][0];
        std::iter::from_fn(move || {
            let this = (i != NO_PAIR).then_some(i as usize)?;
            i = self.next_pair(this, n);
            Some(this)
        })
    }

    /// The node of body `h` in this run, if it has one.
    pub(super) fn body_node(&self, h: Option<RigidBodyHandle>) -> Option<usize> {
        let h = h?;
        let slot = self.body_slots.get(h)?;
        (slot.stamp == self.stamp).then_some(slot.node as usize)
    }

    /// The pose of collider `c` of node `n` at time `t`. Taken from the
    /// body's pose (rapier syncs collider poses only inside its step, so
    /// before the step a body the user moved has a stale collider pose).
    pub(super) fn pose(&self, run: &Run, n: usize, c: ColliderHandle, t: Real) -> Option<Pose> {
        let rest = rest_pose(run.bodies, run.colliders.get(c)?);
        Some(self.nodes[n].moved(rest, t))
    }

    /// Collider `c` of node `n`, if it is a ball: its radius and its
    /// centre's offset from the node's path (see [`Pair::balls`]).
    pub(super) fn ball(&self, run: &Run, n: usize, c: ColliderHandle) -> Option<BallOnPath> {
        let co = run.colliders.get(c)?;
        let radius = co.shape().as_ball()?.radius;
        Some((
            radius,
            rest_pose(run.bodies, co).translation - self.nodes[n].x1,
        ))
    }
}

/// Where collider `co` is: its body's pose composed with its own offset
/// (rapier syncs collider poses only inside its step, so before the step a
/// body the user moved has a stale collider pose), or its own pose when it
/// has no body. The replay shifts it along the body's path.
pub(super) fn rest_pose(bodies: &RigidBodySet, co: &Collider) -> Pose {
    match (
        co.parent().and_then(|h| bodies.get(h)),
        co.position_wrt_parent(),
    ) {
        (Some(rb), Some(local)) => *rb.position() * *local,
        _ => *co.position(),
    }
}

/// The node of a dynamic body `rb` (key `key`) that moves, from `start`
/// (where it started the step, if stored) to where it is now.
fn moving_node(run: &Run, key: Key, rb: &RigidBody, start: Option<Vector>) -> Node {
    let dt = run.dt;
    let x1 = rb.translation();
    let x0 = start.unwrap_or(x1);
    // rapier's velocity when the body moved with it (free flight:
    // exact, where (x₁ − x₀)/dt would round), the chord otherwise;
    // but not the chord of a motion rapier's CCD cut short (a fast
    // body sweeps fixed colliders, a CCD-enabled one everything):
    // that stop is at rapier's time of impact, with rapier's
    // response, which the law replaces (the chord of a ball a CCD
    // pass stopped at a wall is slower than the ball, and the law
    // would meet the wall late).
    let v1 = rb.linvel();
    let moved = x1 - x0;
    let slack = 8.0 * Real::EPSILON * (x1.abs() + x0.abs()).max_element();
    let free = (moved - v1 * dt).abs().max_element() <= slack;
    let v_bar = if free || rb.is_ccd_active() {
        v1
    } else {
        moved / dt
    };
    // Some translations locked, others free: the pair is rapier's.
    let motion = if translations_partly_locked(rb) {
        Motion::PartlyLocked
    } else {
        Motion::Moves
    };
    let mut pose = *rb.position();
    pose.translation = x0;
    let frame = run.input.frame;
    Node {
        motion,
        x1,
        body: RigidState {
            pose,
            linvel: v1,
            inv_mass: rb.mass_properties().local_mprops.inv_mass,
            ..rigid_state(rb)
        },
        v: v_bar,
        t_ref: 0.0,
        g_dt: run.gravity_dt * rb.gravity_scale(),
        g_half: frame.gravity * (rb.gravity_scale() * frame.half_substep(rb)),
        expanded: false,
        dominance: rb.dominance_group(),
        ..still(key, x1, dt)
    }
}

/// The node of body `rb` (key `key`), which the law does not move: where
/// it is at the end of the step, at its velocity.
fn still_node(key: Key, rb: &RigidBody, dt: Real) -> Node {
    let x1 = rb.translation();
    Node {
        body: rigid_state(rb),
        v: rb.linvel(),
        ..still(key, x1, dt)
    }
}

/// Body `rb` as a rigid state where it is now, immovable to the law (the
/// caller sets the inverse mass of one that moves).
fn rigid_state(rb: &RigidBody) -> RigidState {
    RigidState {
        pose: *rb.position(),
        linvel: rb.linvel(),
        angvel: angular(rb),
        inv_mass: 0.0,
        inv_inertia: inverse_inertia(rb),
    }
}

/// An immovable node for `key` at `x1` (at rest, where it is at the end
/// of the step), not yet hit nor swept.
fn still(key: Key, x1: Vector, dt: Real) -> Node {
    Node {
        key,
        motion: Motion::Immovable,
        x1,
        body: RigidState {
            pose: Pose::from_translation(x1),
            linvel: Vector::ZERO,
            angvel: zero_angular(),
            inv_mass: 0.0,
            inv_inertia: Default::default(),
        },
        v: Vector::ZERO,
        // Where the body is now: the end of the step.
        t_ref: dt,
        g_dt: Vector::ZERO,
        g_half: Vector::ZERO,
        expanded: true,
        hit: false,
        swept: None,
        sweep_due: None,
        dominance: 0,
        turn: zero_angular(),
        turned: false,
    }
}
