//! The contact hook's side of the rigid replay: which pairs of rigid
//! bodies the replay takes from rapier's solver this step (their solver
//! contacts are cleared, so rapier's solver does not respond to them).

use std::sync::Mutex;

use crate::body_view::law_body;
use crate::math::{Real, Vector};
use crate::rapier::prelude::*;

/// Below this share of the rest speed a closing contact is resting for
/// certain: far beyond the rounding by which the hook's rigid path, which
/// measures the approach by the law's arithmetic, may differ.
const RESTING_SHARE: Real = 0.999;

/// What [`Claims::claim`] made of a pair.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Claim {
    /// The rigid replay's: its solver contacts are cleared.
    Claimed,
    /// Not an impact: rapier's solver keeps it, with no bounce.
    Resting,
    /// For the hook's rigid path to decide (rapier's solver keeps it).
    Solver,
}

/// The pairs the hook handed to the rigid replay this step.
#[derive(Debug, Default)]
pub(crate) struct Claims {
    list: Mutex<Vec<(ColliderHandle, ColliderHandle)>>,
    sorted: Vec<(ColliderHandle, ColliderHandle)>,
}

impl Claims {
    /// In impulse and exact mode, a pair of a marked collider of another
    /// shape than a centred ball on a dynamic body that the law governs
    /// (`Marks::governs_rigid`): take it for the rigid replay when one of
    /// its contacts strikes: its material points (their velocities at the
    /// start of the step) close faster than `rest_speed`. Other contacts
    /// of the pair may rest or slide meanwhile (a box rocking on one corner
    /// as the other lands): the replay meets the striking one at its time
    /// of impact, if it is near enough to touch within the step (`dt`,
    /// gravity adding `gravity_speed` to its approach; twice that reach,
    /// for a turning body's corner). Farther, the pair stays rapier's
    /// solver's this step, which holds the touching contact the replay
    /// would leave unheld. A pair whose every contact parts faster than
    /// `rest_speed` is claimed too: the replay looks out for another of its
    /// features striking within the step, which rapier's contacts do not
    /// list. A claimed pair's solver contacts are cleared:
    /// rapier's solver leaves it alone and the replay resolves it after the
    /// step. A pair not claimed is either resting (no contact closes clearly
    /// faster than `rest_speed`: the hook's rigid path would not bounce it,
    /// and its caller gives it no bounce without asking) or the hook's
    /// rigid path's (near the rest speed, or striking from too far).
    pub(crate) fn claim(
        &self,
        context: &mut ContactModificationContext,
        (rest_speed, gravity_speed, dt): (Real, Real, Real),
    ) -> Claim {
        let (bodies, rb1, rb2) = (context.bodies, context.rigid_body1, context.rigid_body2);
        let (c1, c2) = (context.collider1, context.collider2);
        // A body with some translations locked, or non-finite data: the
        // hook's rigid path decides (and guards).
        let finite = |rb| law_body(bodies, rb).is_some_and(|b| b.is_finite());
        if !(finite(rb1) && finite(rb2)) {
            return Claim::Solver;
        }
        let Some(rigid) = context.rigid_mut() else {
            return Claim::Solver;
        };
        let n = *rigid.normal;
        let (body1, body2) = (
            rb1.and_then(|h| bodies.get(h)),
            rb2.and_then(|h| bodies.get(h)),
        );
        let velocity = |rb: Option<&RigidBody>, point| {
            rb.map_or(Vector::ZERO, |rb| rb.velocity_at_point(point))
        };
        let relative = |point: Vector| velocity(body2, point) - velocity(body1, point);
        let (mut fastest, mut parting) = (Real::NEG_INFINITY, true);
        let (mut strikes, mut strikes_near, mut held) = (false, false, false);
        for c in rigid.solver_contacts.iter() {
            let point = (c.anchor1 + c.anchor2) * 0.5;
            let approach = -relative(point).dot(n);
            parting &= approach < -rest_speed;
            fastest = fastest.max(approach);
            if approach > rest_speed && approach.is_finite() {
                strikes = true;
                strikes_near |= c.dist <= 2.0 * (approach + gravity_speed) * dt;
            } else if c.dist <= 0.0 && approach > -rest_speed {
                // Touching, resting or sliding: rapier's solver holds it.
                held = true;
            }
        }
        if strikes_near || (strikes && !held) || (parting && !rigid.solver_contacts.is_empty()) {
            // Striking: the replay's. Every contact parting faster than the
            // rest speed (a die just bounced off a wall): the replay's too,
            // which looks out for its next corner striking within the step;
            // rapier's solver would not see that corner come.
            return self.take(rigid, (c1, c2));
        }
        // The rigid path measures the approach again by the law's own
        // arithmetic: near the rest speed, or for a striking contact too far
        // to touch within the step beside a held one, it decides.
        if fastest > RESTING_SHARE * rest_speed {
            Claim::Solver
        } else {
            Claim::Resting
        }
    }

    /// Clear the solver contacts of pair `(c1, c2)` and list it for the
    /// rigid replay.
    fn take(
        &self,
        rigid: &mut ModifiableManifold,
        pair: (ColliderHandle, ColliderHandle),
    ) -> Claim {
        rigid.solver_contacts.clear();
        let mut list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        list.push(pair);
        Claim::Claimed
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
