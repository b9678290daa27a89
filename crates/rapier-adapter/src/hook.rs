//! kimpact's contact hook: the [`PhysicsHooks`] handed to rapier's step.

use std::sync::atomic::{AtomicU64, Ordering};

use kimpact::Law;

use crate::body_view::{LawBody, dominated, law_body, path_velocity};
use crate::candidates::{Candidate, Candidates};
use crate::frame::StepFrame;
use crate::marks::Marks;
use crate::math::{Real, Vector};
use crate::mode::Mode;
use crate::prepare::Prepare;
use crate::rapier::prelude::*;
use crate::rigid_replay::Claims;
use crate::rigid_view::point_velocity;

/// The [`PhysicsHooks`] of one step, from [`crate::Kimpact::hooks`]: pass it
/// to `PhysicsPipeline::step` between [`crate::Kimpact::before_step`] and
/// [`crate::Kimpact::after_step`]. It runs the user's own hooks first (for
/// the pairs whose colliders carry the user's own hook flags), then kimpact's
/// for the pairs the law governs. It only reads kimpact's state and appends
/// to a mutex-guarded list, so it is `Sync` and works with rapier's
/// `parallel` feature.
pub struct StepHooks<'a> {
    pub(crate) law: &'a Law<Real>,
    /// `None` outside a prepared step: then only the user's hooks run.
    pub(crate) frame: Option<StepFrame>,
    pub(crate) mode: Mode,
    pub(crate) marks: &'a Marks,
    /// The step's hook flags: which colliders kimpact flagged (not the
    /// user, [`Prepare::ours`]) and which of them touch something
    /// ([`Prepare::is_crowded`]).
    pub(crate) prepare: &'a Prepare,
    pub(crate) fixed_partners: bool,
    pub(crate) candidates: &'a Candidates,
    /// The rigid replay's pairs (impulse and exact mode).
    pub(crate) claims: &'a Claims,
    /// Pairs cut off by the runtime guard this step.
    pub(crate) guarded: &'a AtomicU64,
    pub(crate) user: &'a dyn PhysicsHooks,
}

/// The step's frame and mode (the user's hooks are not `Debug`).
impl std::fmt::Debug for StepHooks<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StepHooks")
            .field("law", self.law)
            .field("frame", &self.frame)
            .field("mode", &self.mode)
            .field("fixed_partners", &self.fixed_partners)
            .finish_non_exhaustive()
    }
}

/// How far past the step's end (relative to `dt`) the hook's graze test
/// still takes a meeting as in this step (rounding at the step's end).
const GRAZE_HORIZON: Real = 1e-3;

/// The friction coefficient of a manifold whose fresh impact carries the
/// law's tangential part (its slip is the solver contacts' target): large
/// enough that rapier's Coulomb bound never cuts the impulse that reaches
/// the target, small enough that `friction × impulse` stays finite.
const UNBOUNDED_FRICTION: Real = 1e6;

impl StepHooks<'_> {
    fn user_flagged(&self, colliders: &ColliderSet, c: ColliderHandle) -> bool {
        let (index, _) = c.into_raw_parts();
        colliders.get(c).is_some_and(|co| {
            co.active_hooks()
                .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        }) && !self
            .prepare
            .ours
            .get(index as usize)
            .copied()
            .unwrap_or(false)
    }
}

impl PhysicsHooks for StepHooks<'_> {
    fn filter_contact_pair(&self, context: &PairFilterContext) -> Option<SolverFlags> {
        self.user.filter_contact_pair(context)
    }

    fn filter_intersection_pair(&self, context: &PairFilterContext) -> bool {
        self.user.filter_intersection_pair(context)
    }

    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        let (c1, c2) = (context.collider1, context.collider2);
        if self.user_flagged(context.colliders, c1) || self.user_flagged(context.colliders, c2) {
            self.user.modify_solver_contacts(context);
        }
        self.respond(context);
        // What rapier's `has_any_active_contact` will say of the pair, for
        // the next step's graze test (a soft pair counts as touching).
        let touching = match &context.contacts {
            ModifiableContacts::Rigid(rigid) => !rigid.solver_contacts.is_empty(),
            ModifiableContacts::Soft(_) => true,
        };
        if touching {
            self.prepare.touch(c1);
            self.prepare.touch(c2);
        }
    }
}

impl StepHooks<'_> {
    /// kimpact's response to one pair the hook sees: the law's, rapier's
    /// unbounced, or none (the replay's, or a graze).
    fn respond(&self, context: &mut ContactModificationContext) {
        let (c1, c2) = (context.collider1, context.collider2);
        let Some(frame) = self.frame else {
            return;
        };
        if self.mode == Mode::Native {
            return;
        }
        let (colliders, bodies) = (context.colliders, context.bodies);
        if !self
            .marks
            .governs(self.fixed_partners, colliders, bodies, c1, c2)
        {
            if self
                .marks
                .governs_rigid(self.fixed_partners, colliders, bodies, c1, c2)
            {
                // Impulse and exact mode: an impact is the rigid replay's.
                let replayed = matches!(self.mode, Mode::Impulse | Mode::Exact)
                    && self.claims.claim(context, frame.rest_speed);
                if !replayed {
                    self.respond_rigid(context, &frame);
                }
            }
            return;
        }
        let (dt, rest_speed, margin) = (frame.dt, frame.rest_speed, frame.gravity_speed);
        let (bodies, colliders) = (context.bodies, context.colliders);
        let (rb1, rb2) = (context.rigid_body1, context.rigid_body2);
        let Some((b1, b2)) = self.law_bodies(context) else {
            return;
        };
        let Some(rigid) = context.rigid_mut() else {
            return;
        };
        let n = *rigid.normal;
        let w = b2.velocity - b1.velocity;
        let approach = -w.dot(n);
        // Newness as rapier's solver decides it: the contact carried no
        // impulse at the previous step.
        let fresh = rigid
            .solver_contacts
            .iter()
            .all(|c| c.contact_id[0] & NEW_CONTACT_BIT != 0);
        let (dist, point) = rigid
            .solver_contacts
            .iter()
            .map(|c| (c.dist, (c.anchor1 + c.anchor2) * 0.5))
            .fold(
                (Real::MAX, Vector::ZERO),
                |acc, x| if x.0 < acc.0 { x } else { acc },
            );
        // rapier's speculative contact is linear: it takes a pair whose gap
        // closes by more than the gap along the normal as meeting, even when
        // the bodies' real paths pass each other (a graze), and bounces it
        // ("ghost" collisions). Such a pair keeps no contact
        // this step: it is apart now and does not meet on its path. Unless
        // either collider touches something else: rapier's solver may then
        // push its body off that path (a ball in a landing pile, bounced up
        // by the balls under it, into one falling onto it), and only the
        // contact keeps the two apart.
        let reach = (approach + margin) * dt;
        // The replay's pairs: every pair in impulse and exact mode; in
        // restitution mode those of a body too fast for rapier's contacts
        // (swept by the replay after the step).
        let by_replay = match self.mode {
            Mode::Native => false,
            Mode::Restitution => self.prepare.is_swept(c1) || self.prepare.is_swept(c2),
            Mode::Impulse | Mode::Exact => true,
        };
        if !by_replay
            && self.mode == Mode::Restitution
            && approach > rest_speed
            && dist > 0.0
            && dist <= reach
            && !self.prepare.is_crowded(c1)
            && !self.prepare.is_crowded(c2)
            && !self.meets(&frame, bodies, colliders, c1, c2, rb1, rb2)
        {
            rigid.solver_contacts.clear();
            return;
        }
        // Not an impact (resting, sliding, separating): hand it to rapier
        // with no bounce. A NaN approach fails the comparison and lands
        // here too.
        if !(approach > rest_speed && approach.is_finite()) {
            *rigid.restitution = 0.0;
            return;
        }
        if by_replay {
            if fresh {
                // rapier leaves the pair alone this step; kimpact resolves
                // it after the step.
                rigid.solver_contacts.clear();
                self.record(context, n, point, dist, b1, b2, true);
            } else {
                // A contact rapier has been carrying: rapier's, unbounced.
                *rigid.restitution = 0.0;
            }
            return;
        }
        // Here the mode is Restitution (native returned first; impulse and
        // exact pairs are all the replay's).
        if self.mode != Mode::Restitution {
            return;
        }
        if !self.marks.friction(c1, c2).is_frictionless() {
            // Impact friction turns the balls: the rigid law at the contact.
            self.respond_rigid(context, &frame);
            return;
        }
        let tangential = (w + n * approach).length();
        let law = self.marks.law(self.law, c1, c2);
        match law.restitution(b1.mass, b2.mass, approach, tangential) {
            Ok(Some(r)) => {
                // A carried contact that still approaches (a ball pressed on
                // by a third in a cluster) bounces by the law too, as rapier's
                // own coefficient bounces it in native mode (with no bounce,
                // an elastic gas lost its energy faster than native rapier);
                // it is not a new impact, and not reported.
                *rigid.restitution = r.coefficient;
                // A fresh one is kept for the report if the bodies can meet
                // within the step; reported if rapier's contact then carried
                // an impulse (a speculative contact further away gets none,
                // and stays fresh for the next step).
                if fresh && dist <= reach * 1.01 + Real::EPSILON {
                    self.record(context, n, point, dist, b1, b2, false);
                }
            }
            // Invalid masses (a NaN mass reached rapier): no bounce, and the
            // post-step pass reports it.
            _ => *rigid.restitution = 0.0,
        }
    }

    /// The pair's two bodies as the law sees them (dominance applied), if
    /// the pair has solver contacts for the law to act on: `None` for a
    /// body with some translations locked (the pair is rapier's), and for
    /// a body with a non-finite velocity or mass, whose pair's contacts are
    /// cleared (runtime guard: rapier's solver would spread the NaN).
    fn law_bodies(&self, context: &mut ContactModificationContext) -> Option<(LawBody, LawBody)> {
        let (bodies, rb1, rb2) = (context.bodies, context.rigid_body1, context.rigid_body2);
        let (b1, b2) = (law_body(bodies, rb1)?, law_body(bodies, rb2)?);
        let (b1, b2) = dominated(bodies, (rb1, b1), (rb2, b2));
        let rigid = context.rigid_mut()?;
        if rigid.solver_contacts.is_empty() {
            return None;
        }
        if !(b1.is_finite() && b2.is_finite()) {
            rigid.solver_contacts.clear();
            self.guarded.fetch_add(1, Ordering::Relaxed);
            return None;
        }
        Some((b1, b2))
    }

    /// A pair with a marked collider of another shape than a centred ball
    /// on a dynamic body, in restitution mode (in impulse and exact mode,
    /// one the rigid replay did not claim): the law's restitution for the two
    /// as rigid bodies at the manifold's contact, written into the manifold
    /// for rapier's solver. The contact is the centroid of the solver
    /// contacts whose material points close (their velocities at the start
    /// of the step), which are merged into one there; the others (the
    /// corner a rocking box pivots on) stay as they are, and rapier's
    /// solver never bounces them (its restitution takes only the contacts
    /// that close). No bounce when the contact points close at most at the
    /// rest speed. With impact friction, the manifold's friction
    /// coefficient is the pair's `μ` for a fresh impact. The pair is never
    /// the point replay's (which moves bodies as points) and has no graze
    /// test (its cast is linear, the bodies turn).
    fn respond_rigid(&self, context: &mut ContactModificationContext, frame: &StepFrame) {
        let (bodies, rb1, rb2) = (context.bodies, context.rigid_body1, context.rigid_body2);
        let (c1, c2) = (context.collider1, context.collider2);
        let Some((b1, b2)) = self.law_bodies(context) else {
            return;
        };
        let Some(rigid) = context.rigid_mut() else {
            return;
        };
        let n = *rigid.normal;
        // Whether a solver contact's material points close along the
        // normal (a NaN fails: not closing).
        let closes = |c: &SolverContact| {
            let point = (c.anchor1 + c.anchor2) * 0.5;
            let u = point_velocity(bodies, rb2, point) - point_velocity(bodies, rb1, point);
            -u.dot(n) > 0.0
        };
        let mut first = None;
        let (mut a1, mut a2, mut gap, mut dist) = (Vector::ZERO, Vector::ZERO, 0.0, Real::MAX);
        let (mut count, mut fresh) = (0usize, true);
        for (i, c) in rigid.solver_contacts.iter().enumerate() {
            if closes(c) {
                first.get_or_insert(i);
                a1 += c.anchor1;
                a2 += c.anchor2;
                gap += c.dist;
                dist = dist.min(c.dist);
                count += 1;
                fresh &= c.contact_id[0] & NEW_CONTACT_BIT != 0;
            }
        }
        let Some(first) = first else {
            *rigid.restitution = 0.0;
            return;
        };
        let inverse = 1.0 / count as Real;
        let point = (a1 + a2) * (0.5 * inverse);
        let law = self.marks.law(self.law, c1, c2);
        let friction = self.marks.friction(c1, c2);
        let impact =
            crate::rigid_view::resolve(&law, &friction, bodies, (rb1, &b1), (rb2, &b2), point, n);
        let Some((impact, slip)) = impact.filter(|(i, _)| i.approach_speed > frame.rest_speed)
        else {
            *rigid.restitution = 0.0;
            return;
        };
        *rigid.restitution = impact.restitution;
        let rough = fresh && !friction.is_frictionless();
        // rapier's solver bounces each solver contact of a manifold by the
        // restitution, one after another: with several (a bar landing on
        // its edge, a box on its face) their impulses together differ from
        // the law's at the contact, and can raise the energy of an elastic
        // impact. One contact at the centroid takes the law's impulse
        // exactly (a single constraint: the contact point leaves at `e U`).
        if count > 1 {
            for i in (first + 1..rigid.solver_contacts.len()).rev() {
                if closes(&rigid.solver_contacts[i]) {
                    rigid.solver_contacts.remove(i);
                }
            }
            let merged = &mut rigid.solver_contacts[first];
            merged.anchor1 = a1 * inverse;
            merged.anchor2 = a2 * inverse;
            merged.dist = gap * inverse;
        }
        if rough {
            // The law's tangential part as rapier's friction: the solver
            // drives the contact's tangential slip to `tangent_velocity`
            // within `friction` times the normal impulse, so a bound it never
            // reaches leaves the slip the law gives (sticking or sliding).
            *rigid.friction = UNBOUNDED_FRICTION;
            for c in rigid.solver_contacts.iter_mut() {
                c.tangent_velocity = slip;
            }
        }
        let reach = (impact.approach_speed + frame.gravity_speed) * frame.dt;
        if fresh && dist <= reach * 1.01 + Real::EPSILON {
            self.candidates.push(Candidate {
                collider1: c1,
                collider2: c2,
                normal: n,
                point,
                dist,
                start1: b1,
                start2: b2,
                by_replay: false,
                rigid: Some(impact),
            });
        }
    }

    /// Whether colliders `c1` and `c2` meet within this step on the straight
    /// paths rapier is about to integrate (velocity plus gravity), by a
    /// linear cast (closed form for two balls and for a ball and a cuboid,
    /// parry's shape cast otherwise).
    #[allow(clippy::too_many_arguments)]
    fn meets(
        &self,
        frame: &StepFrame,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        c1: ColliderHandle,
        c2: ColliderHandle,
        rb1: Option<RigidBodyHandle>,
        rb2: Option<RigidBodyHandle>,
    ) -> bool {
        let path = |h: Option<RigidBodyHandle>| {
            h.and_then(|h| bodies.get(h))
                .map_or(Vector::ZERO, |rb| path_velocity(rb, frame.gravity_dt()))
        };
        let (Some(co1), Some(co2)) = (colliders.get(c1), colliders.get(c2)) else {
            return true;
        };
        // Anything but a clear "no" (an unsupported shape pair) is a meeting.
        !matches!(
            crate::cast::cast(
                co1.position(),
                path(rb1),
                co1.shape(),
                co2.position(),
                path(rb2),
                co2.shape(),
                frame.dt * (1.0 + GRAZE_HORIZON),
                true,
            ),
            Ok(None)
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn record(
        &self,
        context: &ContactModificationContext,
        normal: Vector,
        point: Vector,
        dist: Real,
        start1: LawBody,
        start2: LawBody,
        by_replay: bool,
    ) {
        self.candidates.push(Candidate {
            collider1: context.collider1,
            collider2: context.collider2,
            normal,
            point,
            dist,
            start1,
            start2,
            by_replay,
            rigid: None,
        });
    }
}
