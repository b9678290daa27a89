//! The contact patch of two colliders at an instant: the centroid of the
//! closing contacts of their contact manifold (a face landing flat: the
//! face's centre; a box on an edge: the edge's midpoint), with its normal.

use crate::math::{Pose, Real, Vector};
use crate::rapier::parry::query::ContactManifold;
use crate::rapier::parry::shape::Shape;

use super::toi::manifolds_at;

/// Where and along what two colliders meet.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Patch {
    /// The centroid of the closing contacts (midway between the two
    /// surfaces), world space.
    pub point: Vector,
    /// Unit normal from the first collider towards the second.
    pub normal: Vector,
}

/// A shape at a pose (world space).
#[derive(Copy, Clone)]
pub(crate) struct Placed<'a> {
    pub shape: &'a dyn Shape,
    pub pose: Pose,
}

/// The patch of `a` and `b`: of the manifold holding the deepest contact
/// that strikes (whose material points close, `approach(point, normal)`,
/// faster than `strike_speed`), the centroid of its closing contacts
/// (approach above zero) within `depth` of that one, above or below. A
/// contact resting or sliding deeper (a box pivoting on a corner as its
/// other corner lands) is not in the patch. Contacts are looked for up to
/// `reach` apart. `None` when no contact strikes. `manifolds` is scratch.
pub(crate) fn patch(
    a: Placed,
    b: Placed,
    (reach, depth): (Real, Real),
    strike_speed: Real,
    approach: impl Fn(Vector, Vector) -> Real,
    manifolds: &mut Vec<ContactManifold<(), ()>>,
) -> Option<Patch> {
    let (pa, pb) = (&a.pose, &b.pose);
    let (a, b) = (a.shape, b.shape);
    manifolds_at(a, pa, b, pb, reach, manifolds);
    let strikes = |p, n| approach(p, n) > strike_speed;
    let Some((i, deepest)) = deepest_striking(manifolds, (pa, pb), reach, strikes) else {
        let listed = manifolds
            .iter()
            .any(|m| m.points.iter().any(|c| c.dist <= reach));
        if listed {
            return None;
        }
        return single_contact(a, pa, b, pb, reach, strikes);
    };
    let m = &manifolds[i];
    let (p1, p2, n) = world_frame(m, pa, pb);
    let (mut sum, mut count) = (Vector::ZERO, 0usize);
    for c in &m.points {
        let point = (p1 * c.local_p1 + p2 * c.local_p2) * 0.5;
        if c.dist <= reach && (c.dist - deepest).abs() <= depth && approach(point, n) > 0.0 {
            sum += point;
            count += 1;
        }
    }
    Some(Patch {
        point: sum / count as Real,
        normal: n,
    })
}

/// Of the contacts `manifolds` (of two shapes at `pa` and `pb`) list within
/// `reach`, the deepest that `strikes(point, normal)`: its manifold's index
/// and its distance.
pub(crate) fn deepest_striking(
    manifolds: &[ContactManifold<(), ()>],
    (pa, pb): (&Pose, &Pose),
    reach: Real,
    strikes: impl Fn(Vector, Vector) -> bool,
) -> Option<(usize, Real)> {
    let mut best: Option<(usize, Real)> = None;
    for (i, m) in manifolds.iter().enumerate() {
        let (p1, p2, n) = world_frame(m, pa, pb);
        for c in &m.points {
            let point = (p1 * c.local_p1 + p2 * c.local_p2) * 0.5;
            // (parry may list a face's contacts beyond the prediction.)
            if c.dist <= reach && c.dist < best.map_or(Real::INFINITY, |b| b.1) && strikes(point, n)
            {
                best = Some((i, c.dist));
            }
        }
    }
    best
}

/// The world frame of manifold `m` of two shapes at `pa` and `pb`: the
/// poses its contacts are given in (a composite's part's) and its normal.
fn world_frame(m: &ContactManifold<(), ()>, pa: &Pose, pb: &Pose) -> (Pose, Pose, Vector) {
    let poses = m.subshape_poses.as_deref();
    let p1 = match poses.and_then(|p| p.pos1) {
        Some(sub) => *pa * sub,
        None => *pa,
    };
    let p2 = match poses.and_then(|p| p.pos2) {
        Some(sub) => *pb * sub,
        None => *pb,
    };
    (p1, p2, p1.rotation * m.local_n1)
}

/// Whether every contact `manifolds` (of two shapes at `pa` and `pb`) list
/// within `reach` has material points that part (`parts(point, normal)`);
/// true when they list none.
pub(crate) fn all_part(
    manifolds: &[ContactManifold<(), ()>],
    (pa, pb): (&Pose, &Pose),
    reach: Real,
    parts: impl Fn(Vector, Vector) -> bool,
) -> bool {
    manifolds.iter().all(|m| {
        let (p1, p2, n) = world_frame(m, pa, pb);
        m.points
            .iter()
            .filter(|c| c.dist <= reach)
            .all(|c| parts((p1 * c.local_p1 + p2 * c.local_p2) * 0.5, n))
    })
}

/// Where the manifolds list no contact at all (parry's segment against a
/// box lists none with an end within 1e-8 of the face): parry's single
/// contact query, if it closes.
fn single_contact(
    a: &dyn Shape,
    pa: &Pose,
    b: &dyn Shape,
    pb: &Pose,
    reach: Real,
    closes: impl Fn(Vector, Vector) -> bool,
) -> Option<Patch> {
    // World space, both points and the normal.
    let contact = crate::rapier::parry::query::contact(pa, a, pb, b, reach).ok()??;
    let point = (contact.point1 + contact.point2) * 0.5;
    let normal = contact.normal1;
    closes(point, normal).then_some(Patch { point, normal })
}
