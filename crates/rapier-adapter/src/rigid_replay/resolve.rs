//! One impact of the rigid replay: the pair's contact patch at its time of
//! impact, the law there, and the two paths bent.

use kimpact::Contact;

use crate::body_view::{dominated, law_body};
use crate::events::{AppliedBy, Outcome};
use crate::math::{Pose, Real, Vector, from_law, to_law};
use crate::rapier::parry::query::ContactManifold;
use crate::rapier::prelude::*;

use super::motion::{angular_speed, from_law_angular};
use super::patch::{all_part, deepest_striking, patch};
use super::toi::{Mover, closing_bound, gap, last_apart, manifolds_at};
use super::{Key, PATCH_TOLERANCES, REST_FLOOR, RigidInput, RigidReplay};
use crate::replay::ReplayOutput;

/// Why [`RigidReplay::impact`] did nothing.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Idle {
    /// Every contact its manifold lists at the touch parts faster than the
    /// rest speed, or it lists none there (the law just left it parting, a
    /// turning body grazes it, two edges pass): another feature may strike
    /// within the step ([`RigidReplay::reentry`]).
    Parting,
    /// No contact strikes at the touch, and its manifold lists one farther
    /// off that would (a box pivoting on one corner as its other corner
    /// comes down): that one may strike within the step
    /// ([`RigidReplay::strikes_later`]).
    Held,
    /// Anything else: resting or sliding, a body the law does not take,
    /// data that cannot enter it.
    Other,
}

impl RigidReplay {
    /// Pair `i` at time `t`: if its patch closes faster than the rest
    /// speed, apply the law there, bend both paths and report the impact;
    /// returns whether each body's path was bent (an immovable or dominant
    /// one's is not), or why nothing happened.
    pub(super) fn impact(
        &mut self,
        input: &RigidInput,
        out: &mut ReplayOutput,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        i: usize,
        t: Real,
    ) -> Result<[bool; 2], Idle> {
        let patch = self.closing_patch(input, colliders, i, t)?;
        self.apply(input, out, bodies, i, t, patch)
            .ok_or(Idle::Other)
    }

    /// The law at pair `i`'s patch `(point, n)` at time `t` (see
    /// [`RigidReplay::impact`]).
    fn apply(
        &mut self,
        input: &RigidInput,
        out: &mut ReplayOutput,
        bodies: &RigidBodySet,
        i: usize,
        t: Real,
        (point, n): (Vector, Vector),
    ) -> Option<[bool; 2]> {
        let dt = input.frame.dt;
        let pair = self.pairs[i];
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

    /// For pair `i`, idle at `t` as [`Idle::Parting`]: the instant in
    /// `(t, dt]` at which it meets again, if any ([`meets_again`]). A body
    /// turning fast brings another corner into the partner its last one
    /// just left, which the search from `t` does not see past the parting
    /// touch it starts from: the search starts after the window in which
    /// no such corner can sink deeper than [`BLIND_DEPTH`] of the smaller
    /// body's reach ([`blind_window`]).
    pub(super) fn reentry(
        &mut self,
        input: &RigidInput,
        colliders: &ColliderSet,
        i: usize,
        t: Real,
    ) -> Option<Real> {
        let dt = input.frame.dt;
        let again = self.on_movers(colliders, i, |a, b, tolerance, manifolds| {
            Some(meets_again(a, b, (t, dt), tolerance, manifolds))
        })?;
        match again {
            Again::At(s) => Some(s),
            Again::SearchFrom(s) => self.time_of_impact(colliders, i, s, dt),
            Again::Never => None,
        }
    }

    /// For pair `i`, idle at `t` as [`Idle::Held`] (touching without
    /// striking: a box pivoting on one corner): an instant in
    /// `(t, dt]` at which another of its contacts strikes (closes faster
    /// than the rest speed), if one overlaps at the step's end (with a
    /// composite partner, at the end of any window of
    /// [`through_the_step`]) by more than [`reentry_depth`] beyond twice
    /// the deepest at `t` ([`strikes_again`]): the box's other corner
    /// landing, which the search from `t` does not see past the touch it
    /// starts from.
    pub(super) fn strikes_later(
        &mut self,
        input: &RigidInput,
        colliders: &ColliderSet,
        i: usize,
        t: Real,
    ) -> Option<Real> {
        let (dt, rest_speed) = (input.frame.dt, input.frame.rest_speed);
        let pair = self.pairs[i];
        let (na, nb) = (self.nodes[pair.a], self.nodes[pair.b]);
        let strikes = |s: Real| {
            move |point: Vector, n: Vector| {
                let w = nb.point_velocity(point, s, dt) - na.point_velocity(point, s, dt);
                -w.dot(n) > rest_speed
            }
        };
        self.on_movers(colliders, i, |a, b, tolerance, manifolds| {
            strikes_again(a, b, (t, dt), tolerance, strikes, manifolds)
        })
    }

    /// The centroid and normal of pair `i`'s contact patch at time `t`, if
    /// its material points there close faster than the rest speed (and a
    /// floor relative to the bodies' speeds); else whether it parts.
    fn closing_patch(
        &mut self,
        input: &RigidInput,
        colliders: &ColliderSet,
        i: usize,
        t: Real,
    ) -> Result<(Vector, Vector), Idle> {
        let dt = input.frame.dt;
        let pair = self.pairs[i];
        let tolerance = self.tolerance(colliders, i);
        let mut manifolds = std::mem::take(&mut self.manifolds);
        let (Some(a), Some(b)) = (
            self.mover(colliders, pair.a, pair.c1),
            self.mover(colliders, pair.b, pair.c2),
        ) else {
            self.manifolds = manifolds;
            return Err(Idle::Other);
        };
        let (na, nb) = (&self.nodes[pair.a], &self.nodes[pair.b]);
        let approach = |point: Vector, n: Vector| {
            let w = nb.point_velocity(point, t, dt) - na.point_velocity(point, t, dt);
            -w.dot(n)
        };
        let depth = PATCH_TOLERANCES * tolerance;
        let (pa, pb) = (a.placed_at(t), b.placed_at(t));
        let reach = tolerance + depth;
        let rest_speed = input.frame.rest_speed;
        let found = patch(pa, pb, (reach, depth), rest_speed, approach, &mut manifolds);
        let poses = (&pa.pose, &pb.pose);
        let idle = if found.is_some() {
            Idle::Other
        } else if all_part(&manifolds, poses, reach, |p, n| {
            approach(p, n) < -rest_speed
        }) {
            Idle::Parting
        } else if deepest_striking(&manifolds, poses, Real::INFINITY, |p, n| {
            approach(p, n) > rest_speed
        })
        .is_some()
        {
            Idle::Held
        } else {
            Idle::Other
        };
        self.manifolds = manifolds;
        let Some(found) = found else {
            return Err(idle);
        };
        let (point, n) = (found.point, found.normal);
        let (ua, ub) = (
            na.point_velocity(point, t, dt),
            nb.point_velocity(point, t, dt),
        );
        let approach = -(ub - ua).dot(n);
        let floor = REST_FLOOR * (ua.length() + ub.length());
        if !(approach > rest_speed.max(floor) && approach.is_finite()) {
            return Err(Idle::Other);
        }
        Ok((point, n))
    }
}

/// How deep, relative to the smaller body's reach, a corner may sink
/// unseen in the window after a parting touch ([`blind_window`]).
const BLIND_DEPTH: Real = 1e-3;

/// What [`meets_again`] found.
#[derive(Copy, Clone, Debug, PartialEq)]
enum Again {
    /// The pair meets again at this instant.
    At(Real),
    /// The pair is apart at this instant: its time of impact is searched
    /// from there.
    SearchFrom(Real),
    /// The pair does not meet again within the step.
    Never,
}

/// [`RigidReplay::reentry`] of `a` and `b` after their parting touch at
/// `t`. Two convex shapes: at the end `s` of the [`blind_window`] (or the
/// step's end if that comes first), if they overlap then by more than
/// [`reentry_depth`] beyond twice their overlap at `t`, the last instant
/// in `(t, s]` they overlap by less ([`first_overlap`]); if they are
/// apart then, a search from `s`; if they still touch then, the same look
/// at the step's end. Other pairs (a composite partner, whose other parts
/// the body can meet, and cross, anywhere on its path): the same look at
/// the end of each window of the shorter of the [`blind_window`] and the
/// [`crossing_window`] in turn, up to the step's end.
/// The parting touch at `t` is within a tolerance or so of zero (parry's
/// clipping moves its contact's distance by a few tolerances as the
/// bodies turn): the depth keeps the bisection off it, and the impact is
/// met that deep.
fn meets_again(
    a: &Mover,
    b: &Mover,
    (t, dt): (Real, Real),
    tolerance: Real,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) -> Again {
    let overlap = |t: Real, end: Real, manifolds: &mut Vec<ContactManifold<(), ()>>| {
        first_overlap(a, b, (t, end), tolerance, manifolds, |_, manifolds, _| {
            gap(manifolds)
        })
    };
    let again = |found: Result<Real, Option<Real>>| found.map_or(Again::Never, Again::At);
    if !convex(a, b) {
        return again(
            through_the_step(a, b, (t, dt), |from, end| {
                overlap(from, end, manifolds).ok()
            })
            .ok_or(None),
        );
    }
    // (A window below the rounding of `t` is none: the step's end.)
    let end = t + blind_window(a, b);
    if end.is_nan() || end >= dt || end <= t {
        return again(overlap(t, dt, manifolds));
    }
    match overlap(t, end, manifolds) {
        Ok(s) => Again::At(s),
        // Apart at the window's end (no contact within the tolerance).
        Err(None) => Again::SearchFrom(end),
        Err(Some(d)) if d > tolerance => Again::SearchFrom(end),
        Err(Some(_)) => again(overlap(end, dt, manifolds)),
    }
}

/// At most this many looks through a step for a pair with a composite
/// partner ([`through_the_step`]).
const MAX_LOOKS: Real = 64.0;

/// How long `a` and `b` take at least to close the thicker one's
/// thickness (parry's `ccd_thickness`: about half a convex shape's least
/// width): a body cannot cross a thin part of its partner within it
/// without overlapping it at one end or the other. Infinite where both
/// are thin (two meshes): then the windows of [`MAX_LOOKS`].
fn crossing_window(a: &Mover, b: &Mover) -> Real {
    let thickness = a.shape.ccd_thickness().max(b.shape.ccd_thickness());
    let window = thickness / closing_bound(a, b);
    if window > 0.0 { window } else { Real::INFINITY }
}

/// The window after a parting touch of `a` and `b` in which no other
/// contact of theirs can sink deeper than [`BLIND_DEPTH`] of the smaller
/// reach unseen. A material point's distance to the partner's surface,
/// non-negative at both ends of a window `h` long, is at least `−C h²/8`
/// within it, `C` a bound of its second derivative: with `ωᵢ` the angular
/// speeds, `rᵢ` the reaches and `v` the centres' relative speed,
///
/// ```text
/// C = ω_a² r_a + ω_b² r_b + 2 ω_a ω_b (r_a + r_b) + 2 (ω_a + ω_b) v
/// ```
///
/// (a point turning on its arm, the partner's surface normal turning
/// under the relative motion). Bodies that do not turn have no such
/// contact: the window is the whole step.
fn blind_window(a: &Mover, b: &Mover) -> Real {
    let (wa, wb) = (
        angular_speed(a.motion.angvel),
        angular_speed(b.motion.angvel),
    );
    let v = (a.motion.linvel - b.motion.linvel).length();
    let curvature = wa * wa * a.reach
        + wb * wb * b.reach
        + 2.0 * wa * wb * (a.reach + b.reach)
        + 2.0 * (wa + wb) * v;
    let depth = BLIND_DEPTH * a.reach.min(b.reach);
    let window = (8.0 * depth / curvature).sqrt();
    if window.is_nan() {
        Real::INFINITY
    } else {
        window
    }
}

/// [`RigidReplay::strikes_later`] of `a` and `b` over `(t, dt]`: if a
/// contact that strikes (`strikes(s)(point, normal)` at time `s`) overlaps
/// at the step's end (a composite partner: at the end of a window of
/// [`through_the_step`]) by more than [`reentry_depth`] beyond twice the
/// deepest one at `t` (at the window's start), bisection for the last
/// instant none does. A contact
/// resting or sliding at `t` may sink meanwhile: it does not strike.
fn strikes_again<F: Fn(Vector, Vector) -> bool>(
    a: &Mover,
    b: &Mover,
    (t, dt): (Real, Real),
    tolerance: Real,
    strikes: impl Fn(Real) -> F,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) -> Option<Real> {
    let reach = tolerance + reentry_depth(a, b, tolerance);
    let mut striking = |from: Real, end: Real| {
        first_overlap(
            a,
            b,
            (from, end),
            tolerance,
            manifolds,
            |s, manifolds, poses| {
                deepest_striking(manifolds, poses, reach.max(0.0), strikes(s)).map(|(_, d)| d)
            },
        )
        .ok()
    };
    if convex(a, b) {
        striking(t, dt)
    } else {
        through_the_step(a, b, (t, dt), striking)
    }
}

/// Whether `a` and `b` are both convex shapes (parry's support maps).
fn convex(a: &Mover, b: &Mover) -> bool {
    a.shape.as_support_map().is_some() && b.shape.as_support_map().is_some()
}

/// For a pair with a composite partner, whose other parts the body can
/// meet anywhere on its path and, thin, cross whole before the step's
/// end: `look(from, end)` over the windows of `(t, dt]` in turn, each
/// the shorter of the [`blind_window`] and the [`crossing_window`] (at
/// most [`MAX_LOOKS`] of them); the first instant a look finds.
fn through_the_step(
    a: &Mover,
    b: &Mover,
    (t, dt): (Real, Real),
    mut look: impl FnMut(Real, Real) -> Option<Real>,
) -> Option<Real> {
    let window = blind_window(a, b)
        .min(crossing_window(a, b))
        .max((dt - t) / MAX_LOOKS);
    let mut from = t;
    while from < dt {
        // A window below the rounding of `from` (a look from just before
        // the step's end) goes to the end at once.
        let end = (from + window).min(dt);
        let end = if end > from { end } else { dt };
        if let Some(s) = look(from, end) {
            return Some(s);
        }
        from = end;
    }
    None
}

/// The last instant in `(t, dt]` before `a` and `b` overlap by more than
/// [`reentry_depth`] beyond twice their overlap at `t`, as `depth_at` measures
/// it (a distance, negative overlapping, from their manifolds at an
/// instant and their poses then; `None`: no contact), if they do at `dt`:
/// bisection, down to the time the pair needs to close `tolerance` at its
/// closing bound. Otherwise the depth measured at `dt` (`None`: no contact
/// within the tolerance, or nothing measured).
fn first_overlap(
    a: &Mover,
    b: &Mover,
    (t, dt): (Real, Real),
    tolerance: Real,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
    depth_at: impl Fn(Real, &[ContactManifold<(), ()>], (&Pose, &Pose)) -> Option<Real>,
) -> Result<Real, Option<Real>> {
    if t >= dt || t.is_nan() {
        return Err(None);
    }
    let bound = closing_bound(a, b);
    // Only overlaps count: the manifolds need list no contact farther
    // apart than the tolerance (parry stops at the separating axis then).
    let reach = tolerance.max(0.0);
    let mut measure = |s: Real| {
        let (pa, pb) = (a.pose_at(s), b.pose_at(s));
        manifolds_at(a.shape, &pa, b.shape, &pb, reach, manifolds);
        depth_at(s, manifolds, (&pa, &pb))
    };
    // The step's end first: most pairs do not overlap there by even the
    // least depth looked for, and need no look at `t`.
    let depth = reentry_depth(a, b, tolerance);
    let at_dt = measure(dt);
    if !at_dt.is_some_and(|d| d < -depth) {
        return Err(at_dt);
    }
    // Twice the overlap at `t`: a pair whose overlap creeps (parry's
    // clipped points sliding as two faces turn) meets again only as often
    // as its overlap doubles.
    let below = 2.0 * measure(t).map_or(0.0, |d| d.min(0.0)) - depth;
    if !at_dt.is_some_and(|d| d < below) {
        return Err(at_dt);
    }
    let mut overlaps = |s: Real| measure(s).is_some_and(|d| d < below);
    let lo = last_apart(t, dt, bound, tolerance, |s| !overlaps(s));
    if lo > t { Ok(lo) } else { Err(at_dt) }
}

/// How deep a pair meeting again after a parting touch is met: a
/// millionth of the smaller body's reach, or a patch's depth where the
/// tolerance is coarser (f32).
fn reentry_depth(a: &Mover, b: &Mover, tolerance: Real) -> Real {
    (1e-6 * a.reach.min(b.reach)).max(PATCH_TOLERANCES * tolerance)
}

#[cfg(test)]
#[path = "resolve_tests.rs"]
mod tests;
