//! The contact hook's side of the rigid replay: which pairs of rigid
//! bodies the replay takes from rapier's solver this step (their solver
//! contacts are cleared, so rapier's solver does not respond to them).

use std::sync::Mutex;

use crate::body_view::law_body;
use crate::math::{Real, Vector};
use crate::rapier::prelude::*;
use crate::rigid_view::point_velocity;

/// The pairs the hook handed to the rigid replay this step.
#[derive(Debug, Default)]
pub(crate) struct Claims {
    list: Mutex<Vec<(ColliderHandle, ColliderHandle)>>,
    sorted: Vec<(ColliderHandle, ColliderHandle)>,
}

impl Claims {
    /// In impulse and exact mode, a pair of a marked collider of another
    /// shape than a centred ball on a dynamic body that the law governs
    /// (`Marks::governs_rigid`): take it for the rigid replay when its
    /// contacts meet as an impact. That is when the centroid of the solver
    /// contacts whose material points close (their velocities at the start
    /// of the step) approaches faster than `rest_speed`, and no contact
    /// that does not close touches (a box rocking on a corner, a body
    /// sliding on a floor: rapier's solver keeps those, as the hook's
    /// rigid path bounces them). A claimed pair's solver contacts are
    /// cleared: rapier's solver leaves it alone and the replay resolves it
    /// after the step. Whether the pair was claimed (if not, the caller
    /// hands it to the hook's rigid path).
    pub(crate) fn claim(&self, context: &mut ContactModificationContext, rest_speed: Real) -> bool {
        let (bodies, rb1, rb2) = (context.bodies, context.rigid_body1, context.rigid_body2);
        let (c1, c2) = (context.collider1, context.collider2);
        // A body with some translations locked, or non-finite data: the
        // hook's rigid path decides (and guards).
        let finite = |rb| law_body(bodies, rb).is_some_and(|b| b.is_finite());
        if !(finite(rb1) && finite(rb2)) {
            return false;
        }
        let Some(rigid) = context.rigid_mut() else {
            return false;
        };
        let n = *rigid.normal;
        let relative =
            |point: Vector| point_velocity(bodies, rb2, point) - point_velocity(bodies, rb1, point);
        let (mut sum, mut count) = (Vector::ZERO, 0usize);
        for c in rigid.solver_contacts.iter() {
            let point = (c.anchor1 + c.anchor2) * 0.5;
            if -relative(point).dot(n) > 0.0 {
                sum += point;
                count += 1;
            } else if c.dist <= 0.0 {
                return false;
            }
        }
        if count == 0 {
            return false;
        }
        let approach = -relative(sum / count as Real).dot(n);
        if !(approach > rest_speed && approach.is_finite()) {
            return false;
        }
        rigid.solver_contacts.clear();
        let mut list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        list.push((c1, c2));
        true
    }

    /// Move the hook's list into the sorted list, without duplicates, in
    /// an order that does not depend on the hook's threads.
    pub(crate) fn collect(&mut self) {
        self.sorted.clear();
        let list = self.list.get_mut().unwrap_or_else(|e| e.into_inner());
        self.sorted.append(list);
        let key = |p: &(ColliderHandle, ColliderHandle)| {
            let (a, b) = p.0.into_raw_parts();
            let (c, d) = p.1.into_raw_parts();
            (a, b, c, d)
        };
        self.sorted.sort_unstable_by_key(key);
        self.sorted.dedup();
    }

    /// This step's claimed pairs (after [`Claims::collect`]).
    pub(crate) fn sorted(&self) -> &[(ColliderHandle, ColliderHandle)] {
        &self.sorted
    }

    /// Forget the hook's list (a new step).
    pub(crate) fn clear(&mut self) {
        self.list
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.sorted.clear();
    }
}
