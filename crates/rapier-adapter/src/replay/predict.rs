//! When a pair of the replay next meets, and whether the law takes it.

use std::cmp::Ordering;

use super::context::Run;
use super::node::{BallOnPath, Hit, Node, Pair};
use super::state::Replay;
use crate::cast::{CastOutcome, InContact, Moving, MovingBall, Rewind, Touch, ball_ball};
use crate::math::{Real, Vector};

/// Approach speeds below this times the sum of the two bodies' speeds are
/// resting contacts: rounding level (7.6e-6 in f32, 1.4e-14 in f64).
const REST_FLOOR: Real = 64.0 * Real::EPSILON;

/// A cast of a pair: its touch, with the radius of each collider that is
/// a ball (the contact's arm on a ball is its radius along the normal).
struct Cast {
    touch: Touch,
    radii: [Option<Real>; 2],
}

impl Replay {
    /// When pair `i` next meets, from time `from` (within the step), with
    /// the nodes' current velocities; the pair is queued then if the law
    /// takes the meeting.
    pub(super) fn predict(&mut self, run: &Run, i: usize, from: Real, rewind: Rewind) {
        let pair = self.pairs[i];
        let dt = run.dt;
        let end = dt;
        let Some(found) = self.cast(run, &pair, from, end - from) else {
            self.queue.set(i, None);
            return;
        };
        let (mut t, mut touch) = (from + found.touch.time, found.touch);
        if rewind == Rewind::Allowed && found.touch.time == 0.0 {
            // Overlapping at `from`: look for the true meeting in [−dt, 0].
            if let Some(back) = self.cast(run, &pair, from - dt, dt)
                && back.touch.time > 0.0
            {
                (t, touch) = (from - dt + back.touch.time, back.touch);
            }
        }
        let (na, nb) = (&self.nodes[pair.a], &self.nodes[pair.b]);
        let hit = hit_at(t, touch, found.radii, [na, nb]);
        self.pairs[i].hit = hit;
        if !takes(run, na, nb, hit.normal, t) {
            // The law would not act there: not queued at all (two thirds
            // of the meetings a landing pile predicts are overlapping
            // pairs that rapier's paths bring together but that approach
            // slower than the rest speed).
            self.queue.set(i, None);
            return;
        }
        // Meetings at the same instant (a pile's overlapping cluster) are
        // taken the fastest approach first: the order then does not depend
        // on the order in which the pairs were found (rapier's collider
        // indices), and the cluster settles in fewer impacts than in the
        // order the pairs were found.
        let rank = (nb.body.linvel - na.body.linvel).dot(hit.normal);
        self.queue.set(i, Some((t, rank)));
    }

    /// After an impact at instant `at` (≥ 0, after the step), whether pair
    /// `i` is two balls apart then: it cannot meet at that instant, and
    /// where it meets later depends only on the velocities its bodies have
    /// when the instant is over, so it is predicted once then (pushed to
    /// [`Replay::apart`]), not after every impact of the instant. Its
    /// bodies' positions at `at` do not change within the instant (a path
    /// bends there), so the test holds for the whole instant. Before the
    /// step a path restarts from the start of the step, and an impact
    /// rewound before it (`t < 0`) moves the bodies at `0`: neither defers.
    pub(super) fn defer_if_apart(&mut self, i: usize, at: Real) -> bool {
        let pair = &self.pairs[i];
        if pair.apart_at == at {
            return true;
        }
        let Some([(r1, o1), (r2, o2)]) = pair.balls else {
            return false;
        };
        // As `cast::ball_ball` tests it.
        let gap = (self.nodes[pair.b].at(at) + o2) - (self.nodes[pair.a].at(at) + o1);
        let reach = r1 + r2;
        if (gap.length_squared() - reach * reach).partial_cmp(&0.0) != Some(Ordering::Greater) {
            return false;
        }
        self.pairs[i].apart_at = at;
        self.apart.push(i as u32);
        true
    }

    /// The linear cast ([`crate::cast`]) of pair `pair` from time `from`,
    /// over `window` seconds (its time after `from`).
    fn cast(&self, run: &Run, pair: &Pair, from: Real, window: Real) -> Option<Cast> {
        if let Some([b1, b2]) = pair.balls {
            let (n1, n2) = (&self.nodes[pair.a], &self.nodes[pair.b]);
            let touch = cast_balls([(n1, b1), (n2, b2)], from, window)?;
            return Some(Cast {
                touch,
                radii: [Some(b1.0), Some(b2.0)],
            });
        }
        let pos1 = self.pose(run, pair.a, pair.c1, from)?;
        let pos2 = self.pose(run, pair.b, pair.c2, from)?;
        let s1 = run.colliders.get(pair.c1)?.shape();
        let s2 = run.colliders.get(pair.c2)?.shape();
        let (va, vb) = (self.nodes[pair.a].v, self.nodes[pair.b].v);
        let a = Moving {
            pose: &pos1,
            velocity: va,
            shape: s1,
        };
        let b = Moving {
            pose: &pos2,
            velocity: vb,
            shape: s2,
        };
        match crate::cast::cast(a, b, window, InContact::MeetsIfClosing) {
            CastOutcome::Touch(touch) => Some(Cast {
                touch,
                radii: [
                    s1.as_ball().map(|b| b.radius),
                    s2.as_ball().map(|b| b.radius),
                ],
            }),
            CastOutcome::Miss | CastOutcome::Unsupported => None,
        }
    }
}

/// The hit of a pair of nodes `nodes` meeting at time `t` as `touch` says
/// (normal and point), with the contact's arm on each body: a ball's
/// radius (from `radii`) along the normal, otherwise from where the node
/// is at `t` to the point.
fn hit_at(t: Real, touch: Touch, radii: [Option<Real>; 2], nodes: [&Node; 2]) -> Hit {
    let normal = touch.normal;
    let arm = |side: usize, towards: Real| -> Vector {
        match radii[side] {
            // A ball centred on its body: exactly along the normal.
            Some(radius) => normal * (towards * radius),
            None => touch.point - nodes[side].at(t),
        }
    };
    Hit {
        time: t,
        point: touch.point,
        normal,
        arms: [arm(0, 1.0), arm(1, -1.0)],
    }
}

/// Whether the law takes an impact of nodes `a` and `b` meeting at time
/// `t` with world normal `normal` (from `a` towards `b`): they approach
/// faster than the rest speed, and faster than rounding level relative
/// to their speeds. Slower, the contact is a resting one (rapier's);
/// and without gravity the rest speed is 0, where a dissipative law
/// (grazing impacts are clamped to e = 1e-3) would otherwise chase an
/// inelastic collapse, three touching balls exchanging ever smaller
/// impulses forever. Anything not finite is taken, for the law's checks
/// to refuse and count.
fn takes(run: &Run, a: &Node, b: &Node, normal: Vector, t: Real) -> bool {
    let (va, vb) = (a.law_velocity(t, run.dt), b.law_velocity(t, run.dt));
    let approach = (va - vb).dot(normal);
    // Not at or below (NaN passes).
    let above = |x: Real| {
        !matches!(
            approach.partial_cmp(&x),
            Some(Ordering::Less | Ordering::Equal)
        )
    };
    let speeds = a.body.linvel.length() + b.body.linvel.length();
    above(run.rest_speed) && above(REST_FLOOR * speeds)
}

/// The linear cast ([`crate::cast::ball_ball`]) of two balls riding nodes,
/// each given with its (radius, centre offset from its node's path; see
/// [`Pair::balls`]), from time `from` over `window` seconds. The one cast
/// of a pair of balls: `Replay::predict`, and the bulk sweep's test of
/// whether a pair may be deferred, must agree.
pub(super) fn cast_balls(
    [(n1, (r1, o1)), (n2, (r2, o2))]: [(&Node, BallOnPath); 2],
    from: Real,
    window: Real,
) -> Option<Touch> {
    let ball = |n: &Node, radius: Real, offset: Vector| MovingBall {
        centre: n.at(from) + offset,
        velocity: n.v,
        radius,
    };
    let (a, b) = (ball(n1, r1, o1), ball(n2, r2, o2));
    ball_ball(a, b, window, InContact::MeetsIfClosing)
}
