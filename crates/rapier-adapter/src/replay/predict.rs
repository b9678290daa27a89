//! When a pair of the replay next meets, and whether the law takes it.

use super::*;

impl Replay {
    /// When pair `i` next meets, from time `from` (within the step), with
    /// the nodes' current velocities. For a candidate first seen overlapping
    /// at the start, the meeting is searched back to `−dt` (a rewind).
    pub(super) fn predict(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        i: usize,
        from: Real,
        dt: Real,
        allow_rewind: bool,
    ) {
        let pair = self.pairs[i];
        let end = dt;
        let Some(hit) = self.cast(bodies, colliders, &pair, from, end - from) else {
            self.queue.set(i, None);
            return;
        };
        let (mut t, mut normal, mut point) = (from + hit.0, hit.1, hit.2);
        if allow_rewind && hit.0 == 0.0 {
            // Overlapping at `from`: look for the true meeting in [−dt, 0].
            if let Some(back) = self.cast(bodies, colliders, &pair, from - dt, dt)
                && back.0 > 0.0
            {
                (t, normal, point) = (from - dt + back.0, back.1, back.2);
            }
        }
        self.pairs[i].normal = normal;
        self.pairs[i].point = point;
        let (na, nb) = (&self.nodes[pair.a], &self.nodes[pair.b]);
        if !self.takes(na, nb, normal, t, dt) {
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
        let rank = (nb.u - na.u).dot(normal);
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

    /// Whether the law takes an impact of nodes `a` and `b` meeting at time
    /// `t` with world normal `normal` (from `a` towards `b`): they approach
    /// faster than the rest speed, and faster than rounding level relative
    /// to their speeds. Slower, the contact is a resting one (rapier's);
    /// and without gravity the rest speed is 0, where a dissipative law
    /// (grazing impacts are clamped to e = 1e-3) would otherwise chase an
    /// inelastic collapse, three touching balls exchanging ever smaller
    /// impulses forever. Anything not finite is taken, for the law's checks
    /// to refuse and count.
    pub(super) fn takes(&self, a: &Node, b: &Node, normal: Vector, t: Real, dt: Real) -> bool {
        let (va, vb) = (a.law_velocity(t, dt), b.law_velocity(t, dt));
        let approach = (va - vb).dot(normal);
        // Not at or below (NaN passes).
        let above = |x: Real| {
            !matches!(
                approach.partial_cmp(&x),
                Some(Ordering::Less | Ordering::Equal)
            )
        };
        above(self.rest_speed) && above(REST_FLOOR * (a.u.length() + b.u.length()))
    }

    /// The linear cast ([`crate::cast`]) of pair `pair` from time `from`, over
    /// `window` seconds: (time after `from`, world normal, world point).
    pub(super) fn cast(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        pair: &Pair,
        from: Real,
        window: Real,
    ) -> Option<(Real, Vector, Vector)> {
        if let Some([b1, b2]) = pair.balls {
            return cast_balls(
                &self.nodes[pair.a],
                b1,
                &self.nodes[pair.b],
                b2,
                from,
                window,
            );
        }
        let pos1 = self.pose(bodies, colliders, pair.a, pair.c1, from)?;
        let pos2 = self.pose(bodies, colliders, pair.b, pair.c2, from)?;
        let s1 = colliders.get(pair.c1)?.shape();
        let s2 = colliders.get(pair.c2)?.shape();
        let (va, vb) = (self.nodes[pair.a].v, self.nodes[pair.b].v);
        crate::cast::cast(&pos1, va, s1, &pos2, vb, s2, window, false)
            .ok()
            .flatten()
    }
}

/// The linear cast ([`crate::cast::ball_ball`]) of two balls riding nodes
/// `n1` and `n2`, each given as (radius, centre offset from its node's path;
/// see [`Pair::balls`]), from time `from` over `window` seconds. The one
/// cast of a pair of balls: `Replay::cast`, and the bulk sweep's test of
/// whether a pair may be deferred, must agree.
pub(super) fn cast_balls(
    n1: &Node,
    (r1, o1): BallOnPath,
    n2: &Node,
    (r2, o2): BallOnPath,
    from: Real,
    window: Real,
) -> Option<crate::cast::Hit> {
    let (c1, c2) = (n1.at(from) + o1, n2.at(from) + o2);
    crate::cast::ball_ball(c1, n1.v, r1, c2, n2.v, r2, window, false)
}
