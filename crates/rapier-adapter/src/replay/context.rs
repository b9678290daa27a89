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
use crate::mode::Mode;
use crate::pair_filter::PairFilter;
use crate::rapier::prelude::*;

/// What a replay run reads: the law, the mode, the settings and marks in
/// force, the colliders flagged this step, where the bodies started it,
/// the pairs the hook handed over, and the step's constants.
pub(crate) struct ReplayInput<'a> {
    pub law: &'a Law<Real>,
    pub mode: Mode,
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

/// What a replay run produces besides the bodies it changes: the impact
/// events and totals, and the bodies it gave a new velocity (woken).
pub(crate) struct ReplayOutput<'a> {
    pub log: &'a mut EventLog,
    pub woken: &'a mut Vec<RigidBodyHandle>,
}

/// How far a body must move to be swept, and how long a struck body
/// chains on, in the run's mode.
#[derive(Copy, Clone, Debug)]
pub(super) struct Reach {
    /// How far a body must move this step (besides more than half its
    /// size) to be swept for partners.
    pub sweep: Real,
    /// `sweep` for a body that falls (moves along gravity).
    pub fall: Real,
    /// Restitution mode: a body an impact bends chains on only while it
    /// moves more than this share of its half-size over the rest of the
    /// step; zero (always) in the others.
    pub chain_share: Real,
}

impl Reach {
    /// The reaches of `mode`, with rapier's prediction distance
    /// `prediction`.
    ///
    /// rapier's contacts (hence the candidates) reach `prediction` beyond
    /// the start-of-step shapes. Two bodies each moving at most half of
    /// that close at most all of it, so they were seen; a body moving
    /// more may reach a partner unseen (a gas ball at 3 m/s moves 0.05
    /// per step at 60 Hz, the prediction is 0.02), and is swept in exact
    /// mode. Impulse mode sweeps only what could tunnel: a pair rapier
    /// did not reach is first seen overlapping next step, and rewound.
    /// Restitution mode hands over only the bodies that move more than
    /// a quarter of their size (`Prepare::is_swept`): each is swept.
    /// Impulse mode sweeps a falling body as exact mode does: it lands
    /// on partners at rest, and a landing rapier first sees overlapping
    /// the pile costs rapier's narrow phase more, at every step of the
    /// landing, than the sweep costs (a gas has no gravity: nothing
    /// falls).
    ///
    /// Restitution mode's replay keeps fast bodies from tunnelling
    /// (`Prepare::is_swept`'s quarter of their size per step); a body
    /// an impact slows below that is a slow body like any other, whose
    /// pairs rapier's solver bounces.
    pub(super) fn of(mode: Mode, prediction: Real) -> Self {
        let sweep = match mode {
            Mode::Exact => 0.5 * prediction,
            Mode::Impulse => Real::INFINITY,
            Mode::Native | Mode::Restitution => 0.0,
        };
        let fall = match mode {
            Mode::Impulse => 0.5 * prediction,
            _ => sweep,
        };
        let chain_share = match mode {
            Mode::Restitution => crate::body_view::SWEPT_SHARE,
            _ => 0.0,
        };
        Self {
            sweep,
            fall,
            chain_share,
        }
    }
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
            reach: Reach::of(input.mode, frame.prediction),
            partners: Partners::of(input.config.fixed_partners),
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
