//! When two colliders riding their bodies' motions ([`Motion`]) first
//! touch within an interval: conservative advancement until the gap is
//! within the tolerance. Two convex shapes step on the closing speed along
//! the normal of their closest points (parry's GJK), the contact manifold
//! confirming the touch. Other pairs get a head start from parry's
//! nonlinear shape cast (`cast_shapes_nonlinear`), then advance on the
//! distance of the pair's contact manifold (parry's `contact_manifolds`,
//! which takes every pair rapier's narrow phase takes: heightfields too):
//! parry's "no impact" is checked by the advancement (it steps over the
//! contact of a rod turning fast from flat), and it answers "no impact"
//! for a composite shape against a heightfield, which the advancement
//! alone takes.

use crate::cast::Rewind;
use crate::math::{Pose, Real, Vector};
use crate::rapier::parry::query::sat;
use crate::rapier::parry::query::{
    ClosestPoints, ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher,
    QueryDispatcher,
};
use crate::rapier::parry::shape::{Cuboid, Shape};

use super::motion::Motion;
use super::patch::Placed;

/// Conservative advancement steps at most (each a contact manifold); a
/// pair still apart then is left for the next instant.
const MAX_ADVANCES: usize = 200;

/// A collider riding a body's motion.
#[derive(Copy, Clone)]
pub(crate) struct Mover<'a> {
    pub motion: &'a Motion,
    /// The collider's pose in its body's frame (`None`: the motion is the
    /// collider's own).
    pub offset: Option<Pose>,
    pub shape: &'a dyn Shape,
    /// How far the shape reaches from the body's centre of mass.
    pub reach: Real,
}

impl<'a> Mover<'a> {
    /// The collider's shape at its world pose at time `t`.
    pub(crate) fn placed_at(&self, t: Real) -> Placed<'a> {
        Placed {
            shape: self.shape,
            pose: self.pose_at(t),
        }
    }

    /// The collider's world pose at time `t`.
    pub(crate) fn pose_at(&self, t: Real) -> Pose {
        let body = self.motion.pose_at(t);
        match self.offset {
            Some(offset) => body * offset,
            None => body,
        }
    }

    /// An upper bound of how fast a point of the shape moves relative to
    /// the body's centre of mass.
    fn turn_bound(&self) -> Real {
        self.motion.turn_speed(self.reach)
    }

    /// An upper bound of how fast a point of the shape moves along the
    /// unit vector `n` relative to the body's centre of mass.
    fn turn_bound_along(&self, n: Vector) -> Real {
        self.motion.turn_speed_along(n, self.reach)
    }
}

/// The contact manifolds of `a` and `b` at poses `pa`, `pb` with contacts
/// up to `prediction` apart, into `manifolds` (empty when parry does not
/// support the pair).
pub(crate) fn manifolds_at(
    a: &dyn Shape,
    pa: &Pose,
    b: &dyn Shape,
    pb: &Pose,
    prediction: Real,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) {
    manifolds.clear();
    let pos12 = pa.inv_mul(pb);
    let mut workspace = None;
    let dispatcher = DefaultQueryDispatcher;
    if dispatcher
        .contact_manifolds(&pos12, a, b, prediction, manifolds, &mut workspace)
        .is_err()
    {
        manifolds.clear();
    }
}

/// [`manifolds_at`] of two movers at their poses at time `t`.
fn movers_manifolds(
    a: &Mover,
    b: &Mover,
    t: Real,
    prediction: Real,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) {
    manifolds_at(
        a.shape,
        &a.pose_at(t),
        b.shape,
        &b.pose_at(t),
        prediction,
        manifolds,
    );
}

/// parry's distance of `a` (at `pa`) and `b` (at `pb`) if within `reach`:
/// where a manifold lists no contact (parry's segment against a box, an end
/// within 1e-8 of the face).
pub(crate) fn distance(
    a: &dyn Shape,
    pa: &Pose,
    b: &dyn Shape,
    pb: &Pose,
    reach: Real,
) -> Option<Real> {
    let d = DefaultQueryDispatcher
        .distance(&pa.inv_mul(pb), a, b)
        .ok()?
        .distance;
    (d <= reach).then_some(d)
}

/// The smallest distance of the manifolds' contacts (negative: overlap),
/// `None` without contacts.
pub(crate) fn gap(manifolds: &[ContactManifold<(), ()>]) -> Option<Real> {
    manifolds
        .iter()
        .flat_map(|m| m.points.iter().map(|p| p.dist))
        .fold(None, |acc: Option<Real>, d| {
            Some(acc.map_or(d, |a| a.min(d)))
        })
}

/// How many halvings the rewind of an overlapping pair takes at most.
const REWIND_HALVINGS: usize = 64;

/// The first time in `[from, to]` at which `a` and `b` come within
/// `tolerance` of each other, `None` if they stay farther apart. A pair
/// overlapping at `from` meets at `from`, or, with [`Rewind::Allowed`] (a
/// pair first seen overlapping, which met in the previous step unseen), at
/// the last instant of `[from − (to − from), from]` at which it was apart
/// along the same motions (found by bisection; `from` if it was never apart
/// then).
/// `manifolds` is scratch.
pub(crate) fn time_of_impact(
    a: &Mover,
    b: &Mover,
    from: Real,
    to: Real,
    tolerance: Real,
    rewind: Rewind,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) -> Option<Real> {
    if from.is_nan() || to.is_nan() || from > to {
        return None;
    }
    if rewind == Rewind::Allowed {
        movers_manifolds(a, b, from, tolerance.max(0.0), manifolds);
        if gap(manifolds).is_some_and(|d| d < -tolerance) {
            return Some(rewound(
                a,
                b,
                from,
                from - (to - from),
                tolerance,
                manifolds,
            ));
        }
    }
    match at_start(a, b, from, to, tolerance) {
        AtStart::BeyondReach => return None,
        AtStart::Touching => return Some(from),
        AtStart::InReach => {}
    }
    // Two convex shapes (but a segment, whose manifold with a box lists no
    // contact within 1e-8 of the face): advancement along their normal
    // (GJK) down to the tolerance, the manifolds' gap taking over within
    // GJK's own tolerance of a touch.
    if stepped_on_normal(a.shape) && stepped_on_normal(b.shape) {
        let start = advance_convex(a, b, from, to, tolerance)?;
        return advance(a, b, start, to, tolerance, manifolds).map(|(t, _)| t);
    }
    let dispatcher = DefaultQueryDispatcher;
    let motion = |m: &Mover| {
        let nonlinear = m.motion.nonlinear_at(from);
        match m.offset {
            Some(offset) => nonlinear.prepend(offset),
            None => nonlinear,
        }
    };
    // parry's cast answers `None` for a composite shape against a shape it
    // cannot cast (a heightfield): conservative advancement alone then.
    let castable = |s: &dyn Shape| s.as_heightfield().is_none() && s.as_voxels().is_none();
    if !(castable(a.shape) && castable(b.shape)) {
        return advance(a, b, from, to, tolerance, manifolds).map(|(t, _)| t);
    }
    let start = match dispatcher.cast_shapes_nonlinear(
        &motion(a),
        a.shape,
        &motion(b),
        b.shape,
        0.0,
        to - from,
        true,
    ) {
        // parry's conservative advancement can step over a contact (a rod
        // turning fast from flat): its "none" is checked from `from`.
        Ok(None) | Err(_) => from,
        Ok(Some(hit)) => from + hit.time_of_impact.clamp(0.0, to - from),
    };
    match advance(a, b, start, to, tolerance, manifolds) {
        // parry stopped past the contact (overlapping, or a manifold too
        // deep to list): advanced from `from` instead.
        found if start > from && found.is_none_or(|(_, d)| d < -tolerance) => {
            advance(a, b, from, to, tolerance, manifolds).map(|(t, _)| t)
        }
        found => found.map(|(t, _)| t),
    }
}

/// Whether two convex shapes `a` and `b` are within `tolerance` of each
/// other at `t`: what the start of [`time_of_impact`] from `t` judges
/// (parry's distance; bounding spheres first). `None` for other shapes,
/// whose search decides.
pub(crate) fn touching_at(a: &Mover, b: &Mover, t: Real, tolerance: Real) -> Option<bool> {
    if a.shape.as_support_map().is_none() || b.shape.as_support_map().is_none() {
        return None;
    }
    let centres = (a.motion.com_at(t) - b.motion.com_at(t)).length();
    if centres - a.reach - b.reach > tolerance {
        return Some(false);
    }
    let (pa, pb) = (a.pose_at(t), b.pose_at(t));
    Some(distance(a.shape, &pa, b.shape, &pb, tolerance).is_some())
}

/// Whether a pair of such shapes is searched by [`advance_convex`]: a
/// convex shape but a segment.
fn stepped_on_normal(shape: &dyn Shape) -> bool {
    shape.as_support_map().is_some() && shape.as_segment().is_none()
}

/// Where a pair stands at the start of a time-of-impact search.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum AtStart {
    /// Farther apart than they can close by the interval's end: they
    /// cannot meet in it.
    BeyondReach,
    /// Within the tolerance (touching or overlapping): they meet now.
    Touching,
    /// Apart, and may meet: searched.
    InReach,
}

/// Where `a` and `b` stand at `from` for a search up to `to`, on the bound
/// of their closing speed that conservative advancement steps by: first
/// their bounding spheres about the centres of mass, then, for two convex
/// shapes, parry's distance (GJK; for composite shapes parry's distance
/// is not always a bound, a heightfield's partner gets `f32::MAX`: in
/// reach).
fn at_start(a: &Mover, b: &Mover, from: Real, to: Real, tolerance: Real) -> AtStart {
    let reach = closing_bound(a, b) * (to - from) + tolerance;
    let centres = (a.motion.com_at(from) - b.motion.com_at(from)).length();
    if centres - a.reach - b.reach > reach {
        return AtStart::BeyondReach;
    }
    if a.shape.as_support_map().is_none() || b.shape.as_support_map().is_none() {
        return AtStart::InReach;
    }
    let (pa, pb) = (a.pose_at(from), b.pose_at(from));
    match distance(a.shape, &pa, b.shape, &pb, Real::INFINITY) {
        Some(d) if d > reach => AtStart::BeyondReach,
        Some(d) if d <= tolerance => AtStart::Touching,
        _ => AtStart::InReach,
    }
}

/// Whether `a` and `b`, which rapier's narrow phase saw farther apart than
/// its prediction distance `prediction` at `from` (a contact pair without
/// contacts), stay apart until `to`: two convex shapes whose closing bound
/// over the interval, with the tolerance on both sides, is below
/// `prediction`. Then [`time_of_impact`] from `from` answers `None` (its
/// start test finds them beyond reach), without its distance query.
pub(crate) fn apart_for_narrow_phase(
    a: &Mover,
    b: &Mover,
    from: Real,
    to: Real,
    tolerance: Real,
    prediction: Real,
) -> bool {
    let convex = a.shape.as_support_map().is_some() && b.shape.as_support_map().is_some();
    convex && closing_bound(a, b) * (to - from) + 2.0 * tolerance < prediction
}

/// What `a` and `b` close by at most per unit of time: their relative
/// speed plus how fast each one's turning moves its surface.
pub(crate) fn closing_bound(a: &Mover, b: &Mover) -> Real {
    (a.motion.linvel - b.motion.linvel).length() + a.turn_bound() + b.turn_bound()
}

/// Conservative advancement from `start` (apart or touching then) to the
/// first time in `[start, to]` the gap of `a` and `b` is within `tolerance`
/// (with the gap then): steps of the gap over the largest speed at which
/// it can close.
fn advance(
    a: &Mover,
    b: &Mover,
    start: Real,
    to: Real,
    tolerance: Real,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) -> Option<(Real, Real)> {
    let bound = closing_bound(a, b);
    let mut t = start;
    for _ in 0..MAX_ADVANCES {
        let reach = bound * (to - t) + tolerance;
        let (pa, pb) = (a.pose_at(t), b.pose_at(t));
        manifolds_at(a.shape, &pa, b.shape, &pb, reach, manifolds);
        let d = gap(manifolds).or_else(|| distance(a.shape, &pa, b.shape, &pb, reach))?;
        if d <= tolerance {
            return Some((t, d));
        }
        if bound.is_nan() || bound <= 0.0 {
            return None;
        }
        t += d / bound;
        if t > to {
            return None;
        }
    }
    Some((t, 0.0))
}

/// Conservative advancement of two convex shapes from `start` until they
/// are within `near` of each other: the first such time, `None` if they
/// stay farther apart until `to`. It steps on the bound along the
/// normal of their closest points: with `n` from `a`'s closest point to
/// `b`'s, `a` stays on its side of the plane through its closest point
/// normal to `n` and `b` on the far side of the parallel plane through
/// its own, and the gap between the planes (the distance `d` now) closes
/// no faster than `(vₐ − v_b)·n + |n × ωₐ| reachₐ + |n × ω_b| reach_b`
/// (Danskin: a support point's speed along `n`). Two boxes well apart
/// step on parry's SAT axis instead ([`cuboid_separation`]: the same two
/// planes, found without the closest points). A pair
/// not closing along `n` never meets within the interval; one that closes
/// steps by `d` over that speed. Fewer steps than the bound on the whole
/// relative speed, which the gap of two boxes sliding past each other
/// (dominoes in a row) closes only slowly against.
fn advance_convex(a: &Mover, b: &Mover, start: Real, to: Real, near: Real) -> Option<Real> {
    let bound = closing_bound(a, b);
    if !bound.is_finite() {
        return None;
    }
    let dispatcher = DefaultQueryDispatcher;
    let cuboids = a.shape.as_cuboid().zip(b.shape.as_cuboid());
    let mut t = start;
    for _ in 0..MAX_ADVANCES {
        let reach = (bound * (to - t) + near).max(0.0);
        let (pa, pb) = (a.pose_at(t), b.pose_at(t));
        // Two boxes well apart: a step on the separating axis of parry's
        // SAT, a fraction of GJK's cost; near a touch, GJK's closest points.
        if let Some((ca, cb)) = cuboids {
            let (gap, normal) = cuboid_separation(ca, &pa, cb, &pb);
            if gap > reach {
                return None;
            }
            if gap > near {
                t += step_on(a, b, gap, normal)?;
                if t > to {
                    return None;
                }
                continue;
            }
        }
        let (near_a, near_b) =
            match dispatcher.closest_points(&pa.inv_mul(&pb), a.shape, b.shape, reach) {
                Ok(ClosestPoints::Disjoint) => return None,
                Ok(ClosestPoints::WithinMargin(p1, p2)) => (pa * p1, pb * p2),
                // Touching within GJK's own tolerance (or a query parry does
                // not answer): the caller's search decides.
                Ok(ClosestPoints::Intersecting) | Err(_) => return Some(t),
            };
        let d = (near_b - near_a).length();
        if d <= near {
            return Some(t);
        }
        t += step_on(a, b, d, (near_b - near_a) / d)?;
        if t > to {
            return None;
        }
    }
    Some(t)
}

/// How long `a` and `b`, separated by two parallel planes `gap` apart
/// with unit normal `normal` (from `a` towards `b`), take at least to
/// close that gap (see [`advance_convex`]); `None` if they do not close
/// along it.
fn step_on(a: &Mover, b: &Mover, gap: Real, normal: Vector) -> Option<Real> {
    let turn = a.turn_bound_along(normal) + b.turn_bound_along(normal);
    let closing = (a.motion.linvel - b.motion.linvel).dot(normal) + turn;
    (closing > 0.0).then(|| gap / closing)
}

/// The largest separation of cuboids `a` (at `pa`) and `b` (at `pb`) over
/// parry's SAT axes (the faces' normals, and in 3D the edges' crossings)
/// and its world axis, from `a` towards `b`: the gap between two parallel
/// planes separating them, so a lower bound of their distance (negative
/// when they overlap).
fn cuboid_separation(a: &Cuboid, pa: &Pose, b: &Cuboid, pb: &Pose) -> (Real, Vector) {
    let pos12 = pa.inv_mul(pb);
    let (s1, n1) = sat::cuboid_cuboid_find_local_separating_normal_oneway(a, b, &pos12);
    let (s2, n2) = sat::cuboid_cuboid_find_local_separating_normal_oneway(b, a, &pos12.inverse());
    let mut best = (s1, pa.rotation * n1);
    if s2 > best.0 {
        best = (s2, -(pb.rotation * n2));
    }
    #[cfg(feature = "dim3")]
    {
        let (s3, n3) = sat::cuboid_cuboid_find_local_separating_edge_twoway(a, b, &pos12);
        if s3 > best.0 {
            best = (s3, pa.rotation * n3);
        }
    }
    best
}

/// An instant in `[back, from]` at which `a` and `b`, overlapping at
/// `from`, were apart and within `tolerance` of touching: the last one the
/// bisection meets (`from` if they overlap at `back` too). The bisection
/// stops once its interval is shorter than the time the pair needs to
/// close the tolerance at its closing bound.
fn rewound(
    a: &Mover,
    b: &Mover,
    from: Real,
    back: Real,
    tolerance: Real,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) -> Real {
    let bound = closing_bound(a, b);
    let reach = bound * (from - back) + tolerance;
    let apart = |t: Real, manifolds: &mut Vec<ContactManifold<(), ()>>| {
        movers_manifolds(a, b, t, reach, manifolds);
        gap(manifolds).is_none_or(|d| d > 0.0)
    };
    if !apart(back, manifolds) {
        return from;
    }
    last_apart(back, from, bound, tolerance, |t| apart(t, manifolds))
}

/// Bisection of `[lo, hi]`, `apart` at `lo` and not at `hi`, for the last
/// instant found apart: it stops once the interval is shorter than the
/// time a pair closing at `bound` needs to close `tolerance` (or at the
/// rounding of the interval).
pub(crate) fn last_apart(
    mut lo: Real,
    mut hi: Real,
    bound: Real,
    tolerance: Real,
    mut apart: impl FnMut(Real) -> bool,
) -> Real {
    let span = hi - lo;
    for _ in 0..REWIND_HALVINGS {
        let mid = 0.5 * (lo + hi);
        if !(mid > lo && mid < hi) {
            break;
        }
        if apart(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= Real::EPSILON * span || bound * (hi - lo) <= tolerance {
            break;
        }
    }
    lo
}

#[cfg(test)]
#[path = "toi_tests.rs"]
mod tests;
