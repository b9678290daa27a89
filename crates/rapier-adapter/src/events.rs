//! What kimpact reports of the impacts it handles.

use crate::math::{DIM, Real, Vector, from_law};
use crate::rapier::prelude::ColliderHandle;

/// One impact resolved by the law. Pairs that kimpact takes over produce no
/// rapier contact at the step of their impact, so these events replace
/// rapier's `CollisionEvent::Started` for them (see `ARCHITECTURE.md`).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct ImpactEvent {
    /// The first collider (the normal points away from it).
    pub collider1: ColliderHandle,
    /// The second collider (the normal points towards it).
    pub collider2: ColliderHandle,
    /// Time of the impact relative to the start of the step, in seconds, in
    /// `[−dt, dt]` (negative for a pair first seen overlapping whose impact
    /// was rewound into the previous step); `0` when rapier's solver applied
    /// it (see `by_solver`).
    pub time: Real,
    /// `true` when rapier's solver applied the law's restitution for this
    /// impact (in `Restitution` mode, a pair with a marked collider of
    /// another shape than a ball centred on a dynamic body, and a pair of
    /// balls slower than a quarter of their size per step; in `Impulse` and
    /// `Exact` mode, such a rigid pair closing near the rest speed, or
    /// striking from beyond the step's reach beside a contact that touches
    /// without closing): rapier's contact impulses include it. `false` when kimpact changed the velocities itself (the
    /// replays, at the time of impact).
    pub by_solver: bool,
    /// The contact point (world space) at the impact.
    pub point: Vector,
    /// The unit normal from `collider1` towards `collider2`.
    pub normal: Vector,
    /// The impulse along the normal (`+impulse · normal` on collider 2's body).
    pub impulse: Real,
    /// The normal approach speed before the impact.
    pub approach_speed: Real,
    /// The effective restitution `e = u'/u`.
    pub restitution: Real,
    /// The kinetic energy dissipated (`d`).
    pub dissipated: Real,
    /// Whether `d` had to be reduced (the law's complex-root case).
    pub clamped: bool,
    /// The dissipation the law asked for beyond what the impact could take
    /// (`kimpact::Impact::unmet_dissipation`): zero unless `clamped`; about
    /// `1e-6` of the normal energy `½ μ u²` for a clamp from rounding, of
    /// the order of `½ μ u²` or more for a clamp of the law itself (an
    /// oblique impact under a law for a small restitution); `+∞` when the
    /// ask is unbounded (a `FixedPartner::Literal` wall with `d̃ > 0`).
    #[cfg_attr(feature = "serde-serialize", serde(default))]
    pub unmet_dissipation: Real,
}

/// Running totals since the [`crate::Kimpact`] was built: the core's
/// [`kimpact::Stats`], the same type in the four adapter crates.
pub use kimpact::Stats;

/// What the law did at one impact, as an event reports it: from a ball
/// impact ([`kimpact::Impact`]) or a rigid one ([`kimpact::RigidImpact`]).
#[derive(Copy, Clone, Debug)]
pub(crate) struct Outcome {
    normal: Vector,
    impulse: Real,
    approach_speed: Real,
    restitution: Real,
    dissipated: Real,
    clamped: bool,
    unmet_dissipation: Real,
}

/// `From<&$impact> for Outcome`: the law's two impact types report the
/// same fields.
macro_rules! outcome_from {
    ($impact:ty) => {
        impl From<&$impact> for Outcome {
            fn from(impact: &$impact) -> Self {
                Self {
                    normal: from_law(&impact.normal),
                    impulse: impact.impulse,
                    approach_speed: impact.approach_speed,
                    restitution: impact.restitution,
                    dissipated: impact.dissipated,
                    clamped: impact.clamped,
                    unmet_dissipation: impact.unmet_dissipation,
                }
            }
        }
    };
}

outcome_from!(kimpact::Impact<Real, DIM>);
outcome_from!(kimpact::RigidImpact<Real, DIM>);

/// Who applies an impact's change of velocities.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum AppliedBy {
    /// kimpact's replay, after rapier's step.
    Replay,
    /// rapier's solver, with the law's restitution in the pair's manifold.
    Solver,
}

/// A step's impact events and the running totals: what every stage
/// writes its results to.
#[derive(Clone, Debug, Default)]
pub(crate) struct EventLog {
    pub events: Vec<ImpactEvent>,
    pub stats: Stats,
}

impl EventLog {
    /// Record one law impact of the pair of colliders `[collider1,
    /// collider2]` at `time`, touching at `point`.
    pub(crate) fn push(
        &mut self,
        [collider1, collider2]: [ColliderHandle; 2],
        time: Real,
        point: Vector,
        impact: Outcome,
        by: AppliedBy,
    ) {
        self.stats.impacts += 1;
        self.stats.clamped += u64::from(impact.clamped);
        self.stats.dissipated += f64::from(impact.dissipated);
        self.stats.record_unmet(f64::from(impact.unmet_dissipation));
        self.events.push(ImpactEvent {
            collider1,
            collider2,
            time,
            by_solver: by == AppliedBy::Solver,
            point,
            normal: impact.normal,
            impulse: impact.impulse,
            approach_speed: impact.approach_speed,
            restitution: impact.restitution,
            dissipated: impact.dissipated,
            clamped: impact.clamped,
            unmet_dissipation: impact.unmet_dissipation,
        });
    }

    /// Count and log a pair skipped for non-finite body data.
    pub(crate) fn skip(&mut self, [collider1, collider2]: [ColliderHandle; 2]) {
        log::warn!(
            "kimpact: skipped the pair {collider1:?}/{collider2:?}: a body has a non-finite velocity or mass"
        );
        self.stats.skipped_non_finite += 1;
    }

    /// Count a step that hit the event cap.
    pub(crate) fn cap_hit(&mut self) {
        self.stats.event_cap_hits += 1;
    }
}
