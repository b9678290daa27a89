//! One impact of the rigid replay: the pair's contact patch at its time of
//! impact, the law there, and the two paths bent.

use kimpact::Contact;

use crate::body_view::{dominated, law_body};
use crate::events::{AppliedBy, Outcome};
use crate::math::{Real, Vector, from_law, to_law};
use crate::rapier::prelude::*;

use super::motion::from_law_angular;
use super::patch::patch;
use super::{Key, PATCH_TOLERANCES, REST_FLOOR, RigidInput, RigidReplay};
use crate::replay::ReplayOutput;

impl RigidReplay {
    /// Pair `i` at time `t`: if its patch closes faster than the rest
    /// speed, apply the law there, bend both paths and report the impact;
    /// returns whether each body's path was bent (an immovable or dominant
    /// one's is not). `None` when nothing happened (touching without
    /// closing, a body the law does not take, data that cannot enter it).
    pub(super) fn impact(
        &mut self,
        input: &RigidInput,
        out: &mut ReplayOutput,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        i: usize,
        t: Real,
    ) -> Option<[bool; 2]> {
        let dt = input.frame.dt;
        let pair = self.pairs[i];
        let (point, n) = self.closing_patch(input, colliders, i, t)?;
        let (na, nb) = (&self.nodes[pair.a], &self.nodes[pair.b]);
        // The masses as the law takes them (locked translations, dominance).
        let parent = |key: Key| match key {
            Key::Body(h) => Some(h),
            Key::Collider(_) => None,
        };
        let (pa, pb) = (parent(na.key), parent(nb.key));
        let (la, lb) = (law_body(bodies, pa)?, law_body(bodies, pb)?);
        let (la, lb) = dominated(bodies, (pa, la), (pb, lb));
        let body_a = self.law_rigid(pair.a, la.mass, t, dt)?;
        let body_b = self.law_rigid(pair.b, lb.mass, t, dt)?;
        let arm = |n: usize| match self.nodes[n].key {
            Key::Body(_) => to_law(point - self.nodes[n].motion.com_at(t)),
            Key::Collider(_) => to_law(Vector::ZERO),
        };
        let contact = Contact::with_unit_normal(arm(pair.a), arm(pair.b), to_law(n)).ok()?;
        let law = input.marks.law(input.law, pair.c1, pair.c2);
        let friction = input.marks.friction(pair.c1, pair.c2);
        let impact = law.resolve_rigid_with_friction(&body_a, &body_b, &contact, &friction)?;
        let changes = [
            (pair.a, la.mass, impact.delta_v_a, impact.delta_omega_a),
            (pair.b, lb.mass, impact.delta_v_b, impact.delta_omega_b),
        ];
        let mut bent = [false; 2];
        for (k, (node, mass, dv, dw)) in changes.into_iter().enumerate() {
            let node = &mut self.nodes[node];
            // A dominant or immovable body's path stays as it is.
            if !node.dynamic || mass.is_infinite() {
                continue;
            }
            let (dv, dw) = (from_law(&dv), from_law_angular(&dw));
            node.motion.bend(t, dv, dw);
            node.u += dv;
            node.omega += dw;
            node.hit = true;
            bent[k] = true;
        }
        out.log.push(
            [pair.c1, pair.c2],
            t,
            point,
            Outcome::from(&impact),
            AppliedBy::Replay,
        );
        Some(bent)
    }

    /// The centroid and normal of pair `i`'s contact patch at time `t`, if
    /// its material points there close faster than the rest speed (and a
    /// floor relative to the bodies' speeds).
    fn closing_patch(
        &mut self,
        input: &RigidInput,
        colliders: &ColliderSet,
        i: usize,
        t: Real,
    ) -> Option<(Vector, Vector)> {
        let dt = input.frame.dt;
        let pair = self.pairs[i];
        let tolerance = self.tolerance(colliders, i);
        let mut manifolds = std::mem::take(&mut self.manifolds);
        let (a, b) = (
            self.mover(colliders, pair.a, pair.c1)?,
            self.mover(colliders, pair.b, pair.c2)?,
        );
        let (na, nb) = (&self.nodes[pair.a], &self.nodes[pair.b]);
        let closes = |point: Vector, n: Vector| {
            let w = nb.point_velocity(point, t, dt) - na.point_velocity(point, t, dt);
            -w.dot(n) > 0.0
        };
        let depth = PATCH_TOLERANCES * tolerance;
        let found = patch(
            a.placed_at(t),
            b.placed_at(t),
            tolerance + depth,
            depth,
            closes,
            &mut manifolds,
        );
        self.manifolds = manifolds;
        let found = found?;
        let (point, n) = (found.point, found.normal);
        let (ua, ub) = (
            na.point_velocity(point, t, dt),
            nb.point_velocity(point, t, dt),
        );
        let approach = -(ub - ua).dot(n);
        let floor = REST_FLOOR * (ua.length() + ub.length());
        if !(approach > input.frame.rest_speed.max(floor) && approach.is_finite()) {
            return None;
        }
        Some((point, n))
    }
}
