//! The pairs kimpact's contact hook hands over during rapier's step.

use std::sync::Mutex;

use crate::body_view::LawBody;
use crate::events::AppliedBy;
use crate::math::{DIM, Real, Vector};
use crate::rapier::prelude::ColliderHandle;

/// A pair the hook handed to kimpact during the step.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Candidate {
    pub collider1: ColliderHandle,
    pub collider2: ColliderHandle,
    pub normal: Vector,
    pub point: Vector,
    /// The smallest solver-contact distance at detection (negative: overlap).
    pub dist: Real,
    /// The bodies as the law saw them at detection (start of step).
    pub start1: LawBody,
    /// See `start1`.
    pub start2: LawBody,
    /// The replay when it resolves the pair after the step (its solver
    /// contacts were cleared); the solver when rapier's solver bounced it
    /// with the law's restitution (a rigid pair, or restitution mode's
    /// slow balls), to be reported.
    pub applied_by: AppliedBy,
    /// A pair with a collider of another shape than a centred ball on a
    /// dynamic body (every law mode): the law's impact as rigid bodies at
    /// the manifold's contact, at detection (the report's outcome).
    pub rigid: Option<kimpact::RigidImpact<Real, DIM>>,
}

impl Candidate {
    /// Its colliders, in order.
    pub(crate) fn colliders(&self) -> [ColliderHandle; 2] {
        [self.collider1, self.collider2]
    }

    fn key(&self) -> (u32, u32, u32, u32) {
        let (a, b) = self.collider1.into_raw_parts();
        let (c, d) = self.collider2.into_raw_parts();
        (a, b, c, d)
    }
}

/// The hook's list (appended to from rapier's hook threads) and the step's
/// candidates, sorted once rapier's step is over.
#[derive(Debug, Default)]
pub(crate) struct Candidates {
    list: Mutex<Vec<Candidate>>,
    sorted: Vec<Candidate>,
}

impl Candidates {
    /// Append a candidate (from any hook thread).
    pub(crate) fn push(&self, candidate: Candidate) {
        // A poisoned lock only means another hook thread panicked; the list
        // itself is still valid.
        let mut list = self.list.lock().unwrap_or_else(|e| e.into_inner());
        list.push(candidate);
    }

    /// Move the hook's list into the sorted list, in a deterministic order
    /// (the hook may run on several threads), without duplicates (CCD
    /// substeps call the hook again for the same pair).
    pub(crate) fn collect(&mut self) {
        self.sorted.clear();
        {
            let list = self.list.get_mut().unwrap_or_else(|e| e.into_inner());
            self.sorted.append(list);
        }
        // Unstable (no scratch allocation), with a total order on what can
        // differ between duplicates, so the result never depends on the order
        // the hook threads pushed in.
        let bits = |v: Vector| v.to_array().map(|x| x.to_bits());
        self.sorted.sort_unstable_by(|a, b| {
            a.key()
                .cmp(&b.key())
                .then(a.dist.total_cmp(&b.dist))
                .then_with(|| bits(a.normal).cmp(&bits(b.normal)))
                .then_with(|| bits(a.point).cmp(&bits(b.point)))
        });
        self.sorted.dedup_by_key(|c| c.key());
    }

    /// This step's candidates, sorted (after [`Candidates::collect`]).
    pub(crate) fn sorted(&self) -> &[Candidate] {
        &self.sorted
    }

    /// Forget the hook's list (a step prepared but never collected).
    pub(crate) fn clear(&mut self) {
        self.list
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.sorted.clear();
    }
}
