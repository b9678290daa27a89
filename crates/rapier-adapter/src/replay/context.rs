//! What a replay run takes, what it gives back, and the context every call
//! of a run shares.

use kimpact::Law;

use crate::body_view::Starts;
use crate::candidates::Candidate;
use crate::config::ResolverConfig;
use crate::events::EventLog;
use crate::frame::StepFrame;
use crate::marks::{Marks, Partners};
use crate::math::{Real, Vector};
use crate::pair_filter::PairFilter;
use crate::policy::{Policy, Reach};
use crate::rapier::prelude::*;

/// What a replay run reads: the law, the step's policy, the settings and marks in
/// force, the colliders flagged this step, where the bodies started it,
/// the pairs the hook handed over, and the step's constants.
pub(crate) struct ReplayInput<'a> {
    pub law: &'a Law<Real>,
    pub policy: Policy,
    pub config: &'a ResolverConfig,
    pub marks: &'a Marks,
    pub flagged: &'a [ColliderHandle],
    pub starts: &'a Starts,
    pub candidates: &'a [Candidate],
    pub frame: StepFrame,
    /// Whether rapier would let a pair the sweeps find touch.
    pub filter: PairFilter<'a>,
}

/// rapier's sets as its step left them: the run reads them and writes the
/// bodies it bends back into `bodies`.
pub(crate) struct ReplaySets<'a> {
    pub bodies: &'a mut RigidBodySet,
    pub colliders: &'a ColliderSet,
    pub narrow_phase: &'a NarrowPhase,
    pub broad_phase: &'a BroadPhaseBvh,
}

impl ReplaySets<'_> {
    /// The same sets, borrowed again for one more replay.
    pub(crate) fn reborrow(&mut self) -> ReplaySets<'_> {
        ReplaySets {
            bodies: &mut *self.bodies,
            colliders: self.colliders,
            narrow_phase: self.narrow_phase,
            broad_phase: self.broad_phase,
        }
    }
}

/// What a replay run produces besides the bodies it changes: the impact
/// events and totals, and the bodies it gave a new velocity (woken).
pub(crate) struct ReplayOutput<'a> {
    pub log: &'a mut EventLog,
    pub woken: &'a mut Vec<RigidBodyHandle>,
}

/// What every call of a run shares: its input, rapier's sets (read only
/// while the impacts are resolved), the step's length and the constants
/// of the run.
#[derive(Copy, Clone)]
pub(super) struct Run<'a> {
    pub input: &'a ReplayInput<'a>,
    pub bodies: &'a RigidBodySet,
    pub colliders: &'a ColliderSet,
    pub narrow_phase: &'a NarrowPhase,
    pub broad_phase: &'a BroadPhaseBvh,
    /// The step's length.
    pub dt: Real,
    /// `g dt`: what rapier adds to a dynamic body's velocity this step.
    pub gravity_dt: Vector,
    /// Approach speeds at or below this are resting contacts.
    pub rest_speed: Real,
    /// A pair struck already in this run and approaching slower than this
    /// is not struck again before the next step
    /// (`ResolverConfig::rebound_cutoff`; 0 when off).
    pub rebound_cutoff: Real,
    pub reach: Reach,
    /// Which pairs of a marked collider the law governs.
    pub partners: Partners,
}

impl<'a> Run<'a> {
    /// The context of a run of `input` over `sets` (read only).
    pub(super) fn new(input: &'a ReplayInput<'a>, sets: &'a ReplaySets<'_>) -> Self {
        let frame = input.frame;
        Self {
            input,
            bodies: sets.bodies,
            colliders: sets.colliders,
            narrow_phase: sets.narrow_phase,
            broad_phase: sets.broad_phase,
            dt: frame.dt,
            gravity_dt: frame.gravity * frame.dt,
            rest_speed: frame.rest_speed,
            rebound_cutoff: input.config.rebound_cutoff.unwrap_or(0.0),
            reach: input.policy.reach,
            partners: input.policy.partners,
        }
    }

    /// Whether the law governs the pair `c1`, `c2` (see
    /// [`Marks::governs`]).
    pub(super) fn governs(&self, c1: ColliderHandle, c2: ColliderHandle) -> bool {
        self.input
            .marks
            .governs(self.partners, self.colliders, self.bodies, c1, c2)
    }
}
