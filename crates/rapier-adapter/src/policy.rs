//! What a mode does at each stage of a step, decided in one place: a
//! [`Policy`] built once per step from the mode and the configuration, and
//! read by the prepare pass, the hook and the replay.

use crate::config::ResolverConfig;
use crate::frame::StepFrame;
use crate::marks::Partners;
use crate::math::Real;
use crate::mode::Mode;

/// Who responds to the contacts the law governs as points (balls centred
/// on their bodies).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Response {
    /// Native mode: rapier's own response everywhere; kimpact flags,
    /// replays and reports nothing.
    Rapier,
    /// Restitution mode: rapier's solver bounces each pair with the law's
    /// restitution (and kimpact reports it); the replay resolves only the
    /// pairs of the bodies too fast for rapier's contacts (more than a
    /// quarter of their size per step).
    SolverAndFastReplay,
    /// Impulse and exact mode: the replay resolves every such pair after
    /// rapier's step, at its time of impact.
    Replay,
}

/// How far a body must move to be swept by the replay, and how long a
/// struck body chains on.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Reach {
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

/// Which moving rigid bodies the rigid replay sweeps for partners that
/// rapier's contacts did not reach.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum RigidSweep {
    /// None: there is no rigid replay (native and restitution mode).
    Nobody,
    /// Those that fall (move along gravity): a landing rapier's contacts
    /// did not see coming is resolved at its time, not rewound from an
    /// overlap (impulse mode).
    Falling,
    /// Every one (exact mode).
    Every,
}

/// What kimpact does in one step.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Policy {
    /// The mode this policy carries out (shown by `Debug`).
    pub mode: Mode,
    /// Who responds to the law's point contacts.
    pub response: Response,
    /// The replay's sweeps and chains.
    pub reach: Reach,
    /// Which pairs of a marked collider the law governs.
    pub partners: Partners,
    /// Which rigid bodies the rigid replay sweeps.
    pub rigid_sweep: RigidSweep,
}

impl Policy {
    /// The policy of a step in `mode` with `config`, in `frame`.
    ///
    /// rapier's contacts (hence the hook's candidates) reach `prediction`
    /// beyond the start-of-step shapes. Two bodies each moving at most
    /// half of that close at most all of it, so they were seen; a body
    /// moving more may reach a partner unseen (a gas ball at 3 m/s moves
    /// 0.05 per step at 60 Hz, the prediction is 0.02), and is swept in
    /// exact mode. Impulse mode sweeps only what could tunnel: a pair
    /// rapier did not reach is first seen overlapping next step, and
    /// rewound. Restitution mode hands over only the bodies that move more
    /// than a quarter of their size (`Prepare::is_swept`): each is swept.
    /// Impulse mode sweeps a falling body as exact mode does: it lands on
    /// partners at rest, and a landing rapier first sees overlapping the
    /// pile costs rapier's narrow phase more, at every step of the landing,
    /// than the sweep costs (a gas has no gravity: nothing falls).
    ///
    /// Restitution mode's replay keeps fast bodies from tunnelling; a body
    /// an impact slows below a quarter of its size per step is a slow body
    /// like any other, whose pairs rapier's solver bounces.
    pub(crate) fn new(mode: Mode, config: &ResolverConfig, frame: &StepFrame) -> Self {
        let prediction = frame.prediction;
        let half = 0.5 * prediction;
        let (response, sweep, fall, chain_share, rigid_sweep) = match mode {
            Mode::Native => (Response::Rapier, 0.0, 0.0, 0.0, RigidSweep::Nobody),
            Mode::Restitution => (
                Response::SolverAndFastReplay,
                0.0,
                0.0,
                crate::body_view::SWEPT_SHARE,
                RigidSweep::Nobody,
            ),
            Mode::Impulse => (
                Response::Replay,
                Real::INFINITY,
                half,
                0.0,
                RigidSweep::Falling,
            ),
            Mode::Exact => (Response::Replay, half, half, 0.0, RigidSweep::Every),
        };
        Self {
            mode,
            response,
            reach: Reach {
                sweep,
                fall,
                chain_share,
            },
            partners: Partners::of(config.fixed_partners),
            rigid_sweep,
        }
    }

    /// Whether kimpact acts at all this step (every mode but native).
    pub(crate) fn acts(&self) -> bool {
        self.mode != Mode::Native
    }

    /// Whether the prepare pass notes which flagged colliders the replay
    /// sweeps and which touch something (restitution mode: the hook hands
    /// only the fast bodies' pairs over, and tests the others for grazes).
    pub(crate) fn notes_fast_bodies(&self) -> bool {
        self.response == Response::SolverAndFastReplay
    }

    /// Whether the rigid replay resolves the impacts of rigid bodies
    /// (impulse and exact mode) after the point replay; otherwise rapier's
    /// solver bounces them with the law's restitution.
    pub(crate) fn replays_rigid(&self) -> bool {
        self.response == Response::Replay
    }
}
