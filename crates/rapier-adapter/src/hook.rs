//! kimpact's contact hook: the [`PhysicsHooks`] handed to rapier's step.

use std::sync::atomic::{AtomicU64, Ordering};

use kimpact::Law;

use crate::body_view::{LawBody, dominated, law_body, path_velocity};
use crate::candidates::{Candidate, Candidates};
use crate::cast::{CastOutcome, InContact, Moving};
use crate::events::AppliedBy;
use crate::frame::StepFrame;
use crate::marks::{Governed, Marks};
use crate::math::{Real, Vector};
use crate::policy::{Policy, Response};
use crate::prepare::Prepare;
use crate::rapier::math::AngVector;
use crate::rapier::prelude::*;
use crate::rigid_replay::{Claim, Claims};
use crate::rigid_view::point_velocity;
use crate::touches::Touches;

/// The [`PhysicsHooks`] of one step, from [`crate::Kimpact::hooks`]: pass it
/// to `PhysicsPipeline::step` between [`crate::Kimpact::before_step`] and
/// [`crate::Kimpact::after_step`]. It runs the user's own hooks first (for
/// the pairs whose colliders carry the user's own hook flags), then kimpact's
/// for the pairs the law governs. It only reads kimpact's state and appends
/// to a mutex-guarded list, so it is `Sync` and works with rapier's
/// `parallel` feature.
pub struct StepHooks<'a> {
    pub(crate) law: &'a Law<Real>,
    pub(crate) frame: StepFrame,
    /// What the step's mode does.
    pub(crate) policy: Policy,
    pub(crate) marks: &'a Marks,
    /// The step's hook flags: which colliders kimpact flagged (not the
    /// user, [`Prepare::is_ours`]) and which of them touch something
    /// ([`Prepare::is_crowded`]).
    pub(crate) prepare: &'a Prepare,
    /// Where the hook records the colliders it leaves touching.
    pub(crate) touches: &'a Touches,
    /// The step's number for `touches`.
    pub(crate) epoch: u32,
    pub(crate) candidates: &'a Candidates,
    /// The rigid replay's pairs (impulse and exact mode).
    pub(crate) claims: &'a Claims,
    /// Pairs cut off by the runtime guard this step.
    pub(crate) guarded: &'a AtomicU64,
    pub(crate) user: &'a dyn PhysicsHooks,
}

/// The step's frame and policy (the user's hooks are not `Debug`).
impl std::fmt::Debug for StepHooks<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StepHooks")
            .field("law", self.law)
            .field("frame", &self.frame)
            .field("policy", &self.policy)
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
        colliders.get(c).is_some_and(|co| {
            co.active_hooks()
                .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        }) && !self.prepare.is_ours(c)
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
            self.touches.touch(c1, self.epoch);
            self.touches.touch(c2, self.epoch);
        }
    }
}

impl StepHooks<'_> {
    /// kimpact's response to one pair the hook sees: the law's, rapier's
    /// unbounced, or none (the replay's, or a graze).
    fn respond(&self, context: &mut ContactModificationContext) {
        if !self.policy.acts() {
            return;
        }
        let (c1, c2) = (context.collider1, context.collider2);
        let (colliders, bodies) = (context.colliders, context.bodies);
        let partners = self.policy.partners;
        let governed = self.marks.governance(partners, colliders, bodies, c1, c2);
        if governed == Some(Governed::Points) {
            // Impulse and exact mode: a ball's impact on a turning kinematic
            // body (a flipper) is the rigid replay's, at its time of impact
            // along the body's turn; anything else the point pair's.
            if self.policy.replays_rigid()
                && (is_turning_kinematic(bodies, context.rigid_body1)
                    || is_turning_kinematic(bodies, context.rigid_body2))
                && self.claims.claim(context, self.claim_speeds()) == Claim::Claimed
            {
                return;
            }
            self.respond_point(context);
        } else if governed == Some(Governed::Rigid) {
            // Impulse and exact mode: an impact is the rigid replay's.
            let claim = if self.policy.replays_rigid() {
                self.claims.claim(context, self.claim_speeds())
            } else {
                Claim::Solver
            };
            match claim {
                Claim::Claimed => {}
                Claim::Resting => {
                    if let Some(rigid) = context.rigid_mut() {
                        *rigid.restitution = 0.0;
                    }
                }
                Claim::Solver => self.respond_rigid(context),
            }
        }
    }

    /// What [`Claims::claim`] judges a contact by: the rest speed, the
    /// approach gravity adds over the step, and the step.
    fn claim_speeds(&self) -> (Real, Real, Real) {
        (
            self.frame.rest_speed,
            self.frame.gravity_speed,
            self.frame.dt,
        )
    }

    /// A pair the law governs as points (two balls centred on their
    /// bodies, or one and an immovable partner): handed to the replay,
    /// cleared as a graze, or bounced by rapier's solver with the law's
    /// restitution, as the step's [`Policy`] says.
    fn respond_point(&self, context: &mut ContactModificationContext) {
        let frame = self.frame;
        let pair = PairIds::of(context);
        let Some((b1, b2)) = self.law_bodies(context) else {
            return;
        };
        let Some(rigid) = context.rigid_mut() else {
            return;
        };
        let seen = Seen::of(rigid);
        // A kinematic partner meets the ball at the velocity of its
        // material point there (a turning flipper).
        let bodies = context.bodies;
        let (b1, b2) = (
            kinematic_at(bodies, context.rigid_body1, b1, seen.point),
            kinematic_at(bodies, context.rigid_body2, b2, seen.point),
        );
        let approach = -(b2.velocity - b1.velocity).dot(seen.normal);
        // The pair's contact reaches this far within the step.
        let reach = (approach + frame.gravity_speed) * frame.dt;
        let candidate = |applied_by| Candidate {
            collider1: pair.c1,
            collider2: pair.c2,
            normal: seen.normal,
            point: seen.point,
            dist: seen.dist,
            start1: b1,
            start2: b2,
            applied_by,
            rigid: None,
        };
        // The point replay and the graze test move bodies on straight
        // paths: a pair with a turning kinematic body (a flipper) the rigid
        // replay did not claim (restitution mode; resting or sliding
        // contacts) is bounced by rapier's solver with the law's
        // restitution.
        let turning =
            is_turning_kinematic(bodies, pair.rb1) || is_turning_kinematic(bodies, pair.rb2);
        let by_replay = !turning
            && match self.policy.response {
                Response::Replay => true,
                // Those of a body too fast for rapier's contacts (swept by
                // the replay after the step).
                _ => self.prepare.is_swept(pair.c1) || self.prepare.is_swept(pair.c2),
            };
        if !by_replay && !turning && self.is_graze(context, &pair, &seen, (approach, reach)) {
            if let Some(rigid) = context.rigid_mut() {
                rigid.solver_contacts.clear();
            }
            return;
        }
        let Some(rigid) = context.rigid_mut() else {
            return;
        };
        // Not an impact (resting, sliding, separating): hand it to rapier
        // with no bounce. A NaN approach fails the comparison and lands
        // here too.
        if !(approach > frame.rest_speed && approach.is_finite()) {
            *rigid.restitution = 0.0;
            return;
        }
        if !by_replay {
            self.bounce_by_solver(context, (b1, b2), &seen, reach, candidate);
        } else if seen.fresh {
            // rapier leaves the pair alone this step; kimpact resolves
            // it after the step.
            rigid.solver_contacts.clear();
            self.candidates.push(candidate(AppliedBy::Replay));
        } else {
            // A contact rapier has been carrying: rapier's, unbounced.
            *rigid.restitution = 0.0;
        }
    }

    /// Whether rapier's solver would bounce a pair it leaves (restitution
    /// mode's slow balls) whose bodies' paths pass each other: rapier's
    /// speculative contact is linear: it takes a pair whose gap closes by
    /// more than the gap along the normal as meeting, even when the
    /// bodies' real paths pass each other (a graze), and bounces it
    /// ("ghost" collisions). Such a pair keeps no contact this step: it is
    /// apart now and does not meet on its path. Unless either collider
    /// touches something else: rapier's solver may then push its body off
    /// that path (a ball in a landing pile, bounced up by the balls under
    /// it, into one falling onto it), and only the contact keeps the two
    /// apart. `(approach, reach)`: the pair's approach speed and how far
    /// it closes within the step.
    fn is_graze(
        &self,
        context: &ContactModificationContext,
        pair: &PairIds,
        seen: &Seen,
        (approach, reach): (Real, Real),
    ) -> bool {
        approach > self.frame.rest_speed
            && seen.dist > 0.0
            && seen.dist <= reach
            && !self.prepare.is_crowded(pair.c1)
            && !self.prepare.is_crowded(pair.c2)
            && !self.meets(context.colliders, context.bodies, pair)
    }

    /// Restitution mode, a pair of slow balls that approach: rapier's
    /// solver bounces it with the law's restitution (impact friction: the
    /// rigid law at the contact), and a fresh one that can meet within the
    /// step (`reach`) is kept for the report.
    fn bounce_by_solver(
        &self,
        context: &mut ContactModificationContext,
        (b1, b2): (LawBody, LawBody),
        seen: &Seen,
        reach: Real,
        candidate: impl FnOnce(AppliedBy) -> Candidate,
    ) {
        let (c1, c2) = (context.collider1, context.collider2);
        if !self.marks.friction(c1, c2).is_frictionless() {
            // Impact friction turns the balls: the rigid law at the contact.
            self.respond_rigid(context);
            return;
        }
        let Some(rigid) = context.rigid_mut() else {
            return;
        };
        let (n, w) = (seen.normal, b2.velocity - b1.velocity);
        let approach = -w.dot(n);
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
                if seen.fresh && seen.dist <= reach * 1.01 + Real::EPSILON {
                    self.candidates.push(candidate(AppliedBy::Solver));
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
    fn respond_rigid(&self, context: &mut ContactModificationContext) {
        let frame = &self.frame;
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
        let Some(closing) = Closing::of(&rigid.solver_contacts[..], closes) else {
            *rigid.restitution = 0.0;
            return;
        };
        let point = closing.point();
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
        let rough = closing.fresh && !friction.is_frictionless();
        closing.merge(rigid, closes);
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
        if closing.fresh && closing.dist <= reach * 1.01 + Real::EPSILON {
            self.candidates.push(Candidate {
                collider1: c1,
                collider2: c2,
                normal: n,
                point,
                dist: closing.dist,
                start1: b1,
                start2: b2,
                applied_by: AppliedBy::Solver,
                rigid: Some(impact),
            });
        }
    }

    /// Whether the colliders of `pair` meet within this step on the
    /// straight paths rapier is about to integrate (velocity plus gravity),
    /// by a linear cast (closed form for two balls and for a ball and a
    /// cuboid, parry's shape cast otherwise).
    fn meets(&self, colliders: &ColliderSet, bodies: &RigidBodySet, pair: &PairIds) -> bool {
        let frame = &self.frame;
        let path = |h: Option<RigidBodyHandle>| {
            h.and_then(|h| bodies.get(h))
                .map_or(Vector::ZERO, |rb| path_velocity(rb, frame.gravity_dt()))
        };
        let (Some(co1), Some(co2)) = (colliders.get(pair.c1), colliders.get(pair.c2)) else {
            return true;
        };
        let a = Moving {
            pose: co1.position(),
            velocity: path(pair.rb1),
            shape: co1.shape(),
        };
        let b = Moving {
            pose: co2.position(),
            velocity: path(pair.rb2),
            shape: co2.shape(),
        };
        let window = frame.dt * (1.0 + GRAZE_HORIZON);
        // Anything but a clear "no" (an unsupported shape pair) is a meeting.
        crate::cast::cast(a, b, window, InContact::Meets) != CastOutcome::Miss
    }
}

/// `b`, the law's view of body `parent`, with the velocity of its material
/// point at `point` if it is kinematic (its centre's otherwise): what a
/// ball meets on a turning kinematic body.
fn kinematic_at(
    bodies: &RigidBodySet,
    parent: Option<RigidBodyHandle>,
    b: LawBody,
    point: Vector,
) -> LawBody {
    match parent.and_then(|h| bodies.get(h)) {
        Some(rb) if rb.is_kinematic() => LawBody {
            velocity: rb.velocity_at_point(point),
            ..b
        },
        _ => b,
    }
}

/// Whether body `parent` is kinematic and turning.
fn is_turning_kinematic(bodies: &RigidBodySet, parent: Option<RigidBodyHandle>) -> bool {
    parent
        .and_then(|h| bodies.get(h))
        .is_some_and(|rb| rb.is_kinematic() && rb.angvel() != AngVector::default())
}

/// The solver contacts of a manifold whose material points close.
struct Closing {
    /// The index of the first.
    first: usize,
    count: usize,
    /// Their anchors on each body, summed.
    anchors: [Vector; 2],
    /// Their distances, summed.
    gap: Real,
    /// The smallest distance.
    dist: Real,
    /// Whether every one is new (carried no impulse at the last step).
    fresh: bool,
}

impl Closing {
    /// The closing ones of `contacts` (`closes`), `None` if none closes.
    fn of(contacts: &[SolverContact], closes: impl Fn(&SolverContact) -> bool) -> Option<Self> {
        let mut closing: Option<Self> = None;
        for (i, c) in contacts.iter().enumerate() {
            if !closes(c) {
                continue;
            }
            let s = closing.get_or_insert(Self {
                first: i,
                count: 0,
                anchors: [Vector::ZERO; 2],
                gap: 0.0,
                dist: Real::MAX,
                fresh: true,
            });
            s.anchors[0] += c.anchor1;
            s.anchors[1] += c.anchor2;
            s.gap += c.dist;
            s.dist = s.dist.min(c.dist);
            s.count += 1;
            s.fresh &= c.contact_id[0] & NEW_CONTACT_BIT != 0;
        }
        closing
    }

    /// Their centroid, midway between the two bodies' anchors.
    fn point(&self) -> Vector {
        (self.anchors[0] + self.anchors[1]) * (0.5 * (1.0 / self.count as Real))
    }

    /// rapier's solver bounces each solver contact of a manifold by the
    /// restitution, one after another: with several (a bar landing on its
    /// edge, a box on its face) their impulses together differ from the
    /// law's at the contact, and can raise the energy of an elastic impact.
    /// One contact at the centroid takes the law's impulse exactly (a
    /// single constraint: the contact point leaves at `e U`): the closing
    /// contacts of `contacts` are merged into the first.
    fn merge(&self, rigid: &mut ModifiableManifold, closes: impl Fn(&SolverContact) -> bool) {
        if self.count <= 1 {
            return;
        }
        let contacts = &mut rigid.solver_contacts;
        for i in (self.first + 1..contacts.len()).rev() {
            if closes(&contacts[i]) {
                contacts.remove(i);
            }
        }
        let inverse = 1.0 / self.count as Real;
        let merged = &mut contacts[self.first];
        merged.anchor1 = self.anchors[0] * inverse;
        merged.anchor2 = self.anchors[1] * inverse;
        merged.dist = self.gap * inverse;
    }
}

/// What the hook reads of a pair's solver contacts.
struct Seen {
    /// The manifold's normal.
    normal: Vector,
    /// The smallest solver-contact distance (negative: overlap).
    dist: Real,
    /// The contact point of the closest solver contact.
    point: Vector,
    /// Newness as rapier's solver decides it: the contact carried no
    /// impulse at the previous step.
    fresh: bool,
}

impl Seen {
    fn of(rigid: &ModifiableManifold) -> Self {
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
        Self {
            normal: *rigid.normal,
            dist,
            point,
            fresh,
        }
    }
}

/// The colliders and bodies of the pair a hook call is about.
struct PairIds {
    c1: ColliderHandle,
    c2: ColliderHandle,
    rb1: Option<RigidBodyHandle>,
    rb2: Option<RigidBodyHandle>,
}

impl PairIds {
    fn of(context: &ContactModificationContext) -> Self {
        Self {
            c1: context.collider1,
            c2: context.collider2,
            rb1: context.rigid_body1,
            rb2: context.rigid_body2,
        }
    }
}
