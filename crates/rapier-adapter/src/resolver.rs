//! The resolver: marking, flagging, the contact hook, and the step.

use std::sync::Mutex;

use kimpact::{Body, Law, LawError, LawParams, Mass};

use crate::calm::{Calm, Frame};
use crate::events::{ImpactEvent, Stats};
use crate::math::{Real, Vector, from_law, to_law};
use crate::mode::Mode;
use crate::rapier::prelude::*;
use crate::replay::Replay;

/// Tuning of the hand-over between kimpact and rapier.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct Config {
    /// Normal approach speeds at or below this are resting contacts: rapier
    /// keeps them, with zero restitution (no bounce) in a pair kimpact's hook
    /// sees, and with the colliders' own restitution in a pair of two bodies
    /// it leaves unhooked (two bodies that cannot close on each other faster
    /// than this, as rapier itself would treat them). `None` (the default)
    /// means `2 |g| dt`, the speed gravity gives in two steps, so that piles
    /// rest under rapier's solver and only real impacts reach the law.
    pub rest_speed: Option<Real>,
    /// Whether a marked collider meets fixed and kinematic bodies (walls,
    /// cushions, floors, paddles) through the law, with the law's
    /// [`kimpact::FixedPartner`] policy. Default `true`.
    pub fixed_partners: bool,
    /// `Exact` mode: the most impacts resolved in one step before the rest of
    /// the step is left to rapier (a guard against inelastic collapse).
    pub max_events_per_step: usize,
    /// Leave unhooked a fast body whose every possible partner this step
    /// moves with it (velocities at most the rest speed apart): a pile that
    /// creeps or falls as a whole keeps rapier's contact recycling. Tried
    /// when at least 256 bodies, and one in eight awake bodies, are fast,
    /// and less often where it does not pay (few such bodies, or few
    /// contacts among them, as in a gas). Default `true`; `false` hooks
    /// every body faster than half the rest speed.
    pub calm_neighbourhoods: bool,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            rest_speed: None,
            fixed_partners: true,
            max_events_per_step: 100_000,
            calm_neighbourhoods: true,
        }
    }
}

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
}

impl Candidate {
    fn key(&self) -> (u32, u32, u32, u32) {
        let (a, b) = self.collider1.into_raw_parts();
        let (c, d) = self.collider2.into_raw_parts();
        (a, b, c, d)
    }
}

/// What the contact hook reads: a snapshot of the resolver's settings for
/// this step, and the list it appends to (the only shared mutable state; the
/// hook runs on several threads with rapier's `parallel` feature).
struct HookState<'a> {
    law: &'a Law<Real>,
    mode: Mode,
    marked: &'a [u32],
    ours: &'a [bool],
    fixed_partners: bool,
    rest_speed: Real,
    dt: Real,
    margin: Real,
    /// `g dt`: what rapier adds to a dynamic body's velocity this step.
    gravity_dt: Vector,
    candidates: &'a Mutex<Vec<Candidate>>,
    /// Pairs cut off by the runtime guard this step.
    guarded: &'a std::sync::atomic::AtomicU64,
    user: &'a dyn PhysicsHooks,
}

fn finite_body(b: &LawBody) -> bool {
    b.velocity.is_finite()
        && match b.mass {
            Mass::Finite(m) => m.is_finite() && m > 0.0,
            Mass::Infinite => true,
        }
}

/// How a body takes part in the law.
#[derive(Copy, Clone, Debug)]
pub(crate) struct LawBody {
    pub mass: Mass<Real>,
    pub velocity: Vector,
}

/// The body of a collider as the law sees it (`None` for a dynamic body with
/// non-finite data, which is skipped).
pub(crate) fn law_body(bodies: &RigidBodySet, parent: Option<RigidBodyHandle>) -> LawBody {
    match parent.and_then(|h| bodies.get(h)) {
        Some(rb) if rb.is_dynamic() => LawBody {
            mass: Mass::Finite(rb.mass()),
            velocity: rb.linvel(),
        },
        Some(rb) => LawBody {
            mass: Mass::Infinite,
            velocity: rb.linvel(),
        },
        None => LawBody {
            mass: Mass::Infinite,
            velocity: Vector::ZERO,
        },
    }
}

/// A law body, checked: non-finite or non-positive data is an error.
pub(crate) fn checked(b: &LawBody) -> Result<Body<Real, { crate::math::DIM }>, LawError> {
    match b.mass {
        Mass::Finite(m) => Body::new(m, to_law(b.velocity)),
        Mass::Infinite => Body::immovable(to_law(b.velocity)),
    }
}

/// What `Kimpact::prepare` reads of the step.
#[derive(Copy, Clone)]
struct PrepareInput<'a> {
    islands: &'a IslandManager,
    bodies: &'a RigidBodySet,
    broad_phase: &'a BroadPhaseBvh,
    gravity: Vector,
    dt: Real,
    /// rapier's prediction distance.
    prediction: Real,
    rest_speed: Real,
}

/// Record where body `handle` starts the step (exact mode).
#[inline]
fn store_start(start: &mut Vec<Start>, handle: RigidBodyHandle, translation: Vector) {
    let (index, generation) = handle.into_raw_parts();
    let index = index as usize;
    if start.len() <= index {
        start.resize(index + 1, Start::default());
    }
    start[index] = Start {
        tag: generation.wrapping_add(1),
        translation,
    };
}

/// The velocity body `rb` moves along this step, on the straight path
/// rapier integrates: its velocity plus gravity's `gravity_dt` (scaled by
/// its gravity scale) for a dynamic body, its velocity for another.
pub(crate) fn path_velocity(rb: &RigidBody, gravity_dt: Vector) -> Vector {
    if rb.is_dynamic() {
        rb.linvel() + gravity_dt * rb.gravity_scale()
    } else {
        rb.linvel()
    }
}

pub(crate) fn is_marked(marked: &[u32], handle: ColliderHandle) -> bool {
    let (index, generation) = handle.into_raw_parts();
    marked.get(index as usize) == Some(&(generation.wrapping_add(1)))
}

/// Whether the law governs the pair: both marked, or one marked and the
/// other immovable (when `fixed_partners`).
pub(crate) fn governs(
    marked: &[u32],
    fixed_partners: bool,
    colliders: &ColliderSet,
    bodies: &RigidBodySet,
    c1: ColliderHandle,
    c2: ColliderHandle,
) -> bool {
    let (m1, m2) = (is_marked(marked, c1), is_marked(marked, c2));
    if m1 && m2 {
        return true;
    }
    if !(fixed_partners && (m1 || m2)) {
        return false;
    }
    let other = if m1 { c2 } else { c1 };
    let parent = colliders.get(other).and_then(|c| c.parent());
    match parent.and_then(|h| bodies.get(h)) {
        Some(rb) => !rb.is_dynamic(),
        None => true,
    }
}

impl HookState<'_> {
    fn user_flagged(&self, colliders: &ColliderSet, c: ColliderHandle) -> bool {
        let (index, _) = c.into_raw_parts();
        colliders.get(c).is_some_and(|co| {
            co.active_hooks()
                .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS)
        }) && !self.ours.get(index as usize).copied().unwrap_or(false)
    }
}

impl PhysicsHooks for HookState<'_> {
    fn filter_contact_pair(&self, context: &PairFilterContext) -> Option<SolverFlags> {
        self.user.filter_contact_pair(context)
    }

    fn filter_intersection_pair(&self, context: &PairFilterContext) -> bool {
        self.user.filter_intersection_pair(context)
    }

    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        let (c1, c2) = (context.collider1, context.collider2);
        if self.user_flagged(context.colliders, c1) || self.user_flagged(context.colliders, c2) {
            self.user.modify_solver_contacts(context);
        }
        if self.mode == Mode::Native
            || !governs(
                self.marked,
                self.fixed_partners,
                context.colliders,
                context.bodies,
                c1,
                c2,
            )
        {
            return;
        }
        let (bodies, colliders) = (context.bodies, context.colliders);
        let (rb1, rb2) = (context.rigid_body1, context.rigid_body2);
        let b1 = law_body(bodies, context.rigid_body1);
        let b2 = law_body(bodies, context.rigid_body2);
        let Some(rigid) = context.rigid_mut() else {
            return;
        };
        if rigid.solver_contacts.is_empty() {
            return;
        }
        // Runtime guard: a body with a non-finite velocity or mass is cut
        // off from its law partners (rapier's solver would spread the NaN).
        if !(finite_body(&b1) && finite_body(&b2)) {
            rigid.solver_contacts.clear();
            self.guarded
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            return;
        }
        let n = *rigid.normal;
        let w = b2.velocity - b1.velocity;
        let approach = -w.dot(n);
        // Newness as rapier's solver decides it: the contact carried no
        // impulse at the previous step.
        let fresh = rigid
            .solver_contacts
            .iter()
            .all(|c| c.contact_id[0] & NEW_CONTACT_BIT != 0);
        let (dist, point) = rigid
            .solver_contacts
            .iter()
            .map(|c| (c.dist, (c.anchor1 + c.anchor2) * 0.5))
            .fold(
                (Real::MAX, Vector::ZERO),
                |acc, x| if x.0 < acc.0 { x } else { acc },
            );
        // rapier's speculative contact is linear: it takes a pair whose gap
        // closes by more than the gap along the normal as meeting, even when
        // the bodies' real paths pass each other (a graze), and bounces it
        // ("ghost" collisions; in impulse mode these are the pairs the pass
        // before the step found not meeting). Such a pair keeps no contact
        // this step: it is apart now and does not meet on its path.
        let reach = (approach + self.margin) * self.dt;
        if self.mode != Mode::Exact
            && approach > self.rest_speed
            && dist > 0.0
            && dist <= reach
            && !self.meets(bodies, colliders, c1, c2, rb1, rb2)
        {
            rigid.solver_contacts.clear();
            return;
        }
        // Not an impact (resting, sliding, separating, or a contact rapier has
        // been carrying): hand it to rapier with no bounce. A NaN approach
        // fails the comparison and lands here too.
        if !(fresh && approach > self.rest_speed && approach.is_finite()) {
            *rigid.restitution = 0.0;
            return;
        }
        match self.mode {
            Mode::Native => {}
            // Impulse mode resolved the impacts it could see coming before
            // the step (those pairs now separate); a pair it could not see
            // (inserted since the last step, or not yet in rapier's broad
            // phase) gets the law through rapier's restitution instead.
            Mode::Restitution | Mode::Impulse => {
                let tangential = (w + n * approach).length();
                match self.law.restitution(b1.mass, b2.mass, approach, tangential) {
                    Ok(Some(r)) => {
                        *rigid.restitution = r.coefficient;
                        // Kept for the report if the bodies can meet within
                        // the step; reported if rapier's contact then carried
                        // an impulse (a speculative contact further away gets
                        // none, and stays fresh for the next step).
                        if dist <= reach * 1.01 + Real::EPSILON {
                            self.record(context, n, point, dist, b1, b2);
                        }
                    }
                    // Invalid masses (a NaN mass reached rapier): no bounce,
                    // and the post-step pass reports it.
                    _ => *rigid.restitution = 0.0,
                }
            }
            Mode::Exact => {
                // rapier leaves the pair alone this step; kimpact resolves it
                // after the step.
                rigid.solver_contacts.clear();
                self.record(context, n, point, dist, b1, b2);
            }
        }
    }
}

impl HookState<'_> {
    /// Whether colliders `c1` and `c2` meet within this step on the straight
    /// paths rapier is about to integrate (velocity plus gravity), by a
    /// linear cast (closed form for two balls and for a ball and a cuboid,
    /// parry's shape cast otherwise).
    #[allow(clippy::too_many_arguments)]
    fn meets(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        c1: ColliderHandle,
        c2: ColliderHandle,
        rb1: Option<RigidBodyHandle>,
        rb2: Option<RigidBodyHandle>,
    ) -> bool {
        let path = |h: Option<RigidBodyHandle>| {
            h.and_then(|h| bodies.get(h))
                .map_or(Vector::ZERO, |rb| path_velocity(rb, self.gravity_dt))
        };
        let (Some(co1), Some(co2)) = (colliders.get(c1), colliders.get(c2)) else {
            return true;
        };
        // Anything but a clear "no" (an unsupported shape pair) is a meeting.
        !matches!(
            crate::cast::cast(
                co1.position(),
                path(rb1),
                co1.shape(),
                co2.position(),
                path(rb2),
                co2.shape(),
                self.dt * (1.0 + crate::replay::PRE_HORIZON),
                true,
            ),
            Ok(None)
        )
    }

    fn record(
        &self,
        context: &ContactModificationContext,
        normal: Vector,
        point: Vector,
        dist: Real,
        start1: LawBody,
        start2: LawBody,
    ) {
        let candidate = Candidate {
            collider1: context.collider1,
            collider2: context.collider2,
            normal,
            point,
            dist,
            start1,
            start2,
        };
        // A poisoned lock only means another hook thread panicked; the list
        // itself is still valid.
        let mut list = self.candidates.lock().unwrap_or_else(|e| e.into_inner());
        list.push(candidate);
    }
}

/// The start of a step for one body (exact mode).
#[derive(Copy, Clone, Debug, Default)]
pub(crate) struct Start {
    /// Body generation + 1 (0: nothing stored).
    pub tag: u32,
    pub translation: Vector,
}

/// kimpact's resolver: the law, the mode, the marked colliders, and the state
/// kept between steps. See the crate docs for the three-line drop-in.
///
/// With the `serde-serialize` feature it serializes with rapier's world (the
/// scratch space of a step is skipped: it is empty between steps), so a
/// saved and restored simulation continues bit for bit.
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub struct Kimpact {
    law: Law<Real>,
    mode: Mode,
    config: Config,
    /// Per collider index: generation + 1 when marked, 0 otherwise.
    marked: Vec<u32>,
    /// Per collider index: whether `MODIFY_SOLVER_CONTACTS` is set by us.
    ours: Vec<bool>,
    /// Colliders whose hook flag we set this step.
    flagged: Vec<ColliderHandle>,
    /// Scratch of `prepare`: last step's `flagged`.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    previous: Vec<ColliderHandle>,
    /// Per collider index: the step (`epoch`) at which it was last flagged.
    seen: Vec<u32>,
    epoch: u32,
    /// Colliders marked since the last step: their bodies may not be in
    /// rapier's active set yet (inserted, or woken, since the last step).
    pending: Vec<ColliderHandle>,
    /// Bodies kimpact gave a new velocity since the last `prepare`.
    woken: Vec<RigidBodyHandle>,
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    candidates: Mutex<Vec<Candidate>>,
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    guarded: std::sync::atomic::AtomicU64,
    /// Scratch: the candidates of this step, sorted.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    sorted: Vec<Candidate>,
    /// Per body index: start-of-step translation (exact mode).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    start: Vec<Start>,
    events: Vec<ImpactEvent>,
    stats: Stats,
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    replay: Replay,
    /// Calm neighbourhoods (`Config::calm_neighbourhoods`).
    calm: Calm,
}

impl Kimpact {
    /// A resolver applying `law` in `mode`, with the default [`Config`].
    pub fn new(law: Law<Real>, mode: Mode) -> Self {
        Self::with_config(law, mode, Config::default())
    }

    /// A resolver with an explicit [`Config`].
    pub fn with_config(law: Law<Real>, mode: Mode, config: Config) -> Self {
        Self {
            law,
            mode,
            config,
            marked: Vec::new(),
            ours: Vec::new(),
            flagged: Vec::new(),
            previous: Vec::new(),
            seen: Vec::new(),
            epoch: 0,
            pending: Vec::new(),
            woken: Vec::new(),
            candidates: Mutex::new(Vec::new()),
            guarded: std::sync::atomic::AtomicU64::new(0),
            sorted: Vec::new(),
            start: Vec::new(),
            events: Vec::new(),
            stats: Stats::default(),
            replay: Replay::default(),
            calm: Calm::default(),
        }
    }

    /// The law in force.
    pub fn law(&self) -> &Law<Real> {
        &self.law
    }

    /// Change the law's parameters between steps.
    ///
    /// # Errors
    /// A [`LawError`] naming the invalid parameter; the old law stays in force.
    pub fn set_law(&mut self, params: LawParams<Real>) -> Result<(), LawError> {
        self.law.set_params(params)
    }

    /// The mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Switch mode between steps.
    pub fn set_mode(&mut self, mode: Mode) {
        self.mode = mode;
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Mark `collider`: its contacts with other marked colliders (and with
    /// fixed or kinematic bodies, see [`Config::fixed_partners`]) follow the
    /// law. Marking costs nothing until the collider's body moves.
    pub fn mark(&mut self, collider: ColliderHandle) {
        let (index, generation) = collider.into_raw_parts();
        let index = index as usize;
        if self.marked.len() <= index {
            self.marked.resize(index + 1, 0);
        }
        self.marked[index] = generation.wrapping_add(1);
        self.pending.push(collider);
    }

    /// Unmark `collider`: rapier's own response again from the next step.
    pub fn unmark(&mut self, collider: ColliderHandle) {
        let (index, generation) = collider.into_raw_parts();
        if let Some(m) = self.marked.get_mut(index as usize)
            && *m == generation.wrapping_add(1)
        {
            *m = 0;
        }
    }

    /// Whether `collider` is marked.
    pub fn is_marked(&self, collider: ColliderHandle) -> bool {
        is_marked(&self.marked, collider)
    }

    /// The impacts the law resolved during the last step, in the order they
    /// were applied.
    pub fn events(&self) -> &[ImpactEvent] {
        &self.events
    }

    /// Totals since the resolver was built.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Step a [`PhysicsWorld`] through kimpact (see [`Kimpact::step`]).
    pub fn step_world(
        &mut self,
        world: &mut PhysicsWorld,
        hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) {
        self.step(
            &mut world.physics_pipeline,
            world.gravity,
            &world.integration_parameters,
            &mut world.islands,
            &mut world.broad_phase,
            &mut world.narrow_phase,
            &mut world.bodies,
            &mut world.colliders,
            &mut world.impulse_joints,
            &mut world.multibody_joints,
            &mut world.soft_bodies,
            &mut world.ccd_solver,
            hooks,
            events,
        );
    }

    /// `PhysicsPipeline::step` through kimpact: the same arguments, the
    /// pipeline first. `hooks` are the user's own hooks (or `&()`); they keep
    /// working, chained before kimpact's.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        pipeline: &mut PhysicsPipeline,
        gravity: Vector,
        integration_parameters: &IntegrationParameters,
        islands: &mut IslandManager,
        broad_phase: &mut BroadPhaseBvh,
        narrow_phase: &mut NarrowPhase,
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
        impulse_joints: &mut ImpulseJointSet,
        multibody_joints: &mut MultibodyJointSet,
        soft_bodies: &mut SoftBodySet,
        ccd_solver: &mut CCDSolver,
        hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) {
        self.events.clear();
        self.stats.steps += 1;
        let dt = integration_parameters.dt;
        let g = gravity.length();
        let rest_speed = self.config.rest_speed.unwrap_or(2.0 * g * dt);
        let input = PrepareInput {
            islands,
            bodies,
            broad_phase,
            gravity,
            dt,
            prediction: integration_parameters.prediction_distance(),
            rest_speed,
        };
        self.prepare(&input, colliders);
        if matches!(self.mode, Mode::Impulse | Mode::Restitution) {
            // Impulse: the law on every impact seen coming. Restitution: only
            // on those of fast bodies, which rapier could let pass.
            let mut replay = std::mem::take(&mut self.replay);
            replay.run_pre(
                self,
                bodies,
                colliders,
                narrow_phase,
                broad_phase,
                gravity,
                dt,
                rest_speed,
                self.mode == Mode::Impulse,
                integration_parameters.prediction_distance(),
            );
            // Bodies set moving by an impact need the hook this step too.
            for handle in replay.hit_bodies() {
                if let Some(rb) = bodies.get(handle) {
                    self.flag(rb, colliders);
                }
            }
            self.replay = replay;
        }
        {
            let state = HookState {
                law: &self.law,
                mode: self.mode,
                marked: &self.marked,
                ours: &self.ours,
                fixed_partners: self.config.fixed_partners,
                rest_speed,
                dt,
                margin: g * dt,
                gravity_dt: gravity * dt,
                candidates: &self.candidates,
                guarded: &self.guarded,
                user: hooks,
            };
            pipeline.step(
                gravity,
                integration_parameters,
                islands,
                broad_phase,
                narrow_phase,
                bodies,
                colliders,
                impulse_joints,
                multibody_joints,
                soft_bodies,
                ccd_solver,
                &state,
                events,
            );
        }
        let guarded = self.guarded.swap(0, std::sync::atomic::Ordering::Relaxed);
        if guarded > 0 {
            log::warn!(
                "kimpact: {guarded} contact(s) of bodies with non-finite velocity or mass were cut off"
            );
            self.stats.skipped_non_finite += guarded;
        }
        self.collect_candidates();
        match self.mode {
            Mode::Native => {}
            Mode::Restitution | Mode::Impulse => self.report_restitution(narrow_phase),
            Mode::Exact => {
                let mut replay = std::mem::take(&mut self.replay);
                replay.run(
                    self,
                    bodies,
                    colliders,
                    narrow_phase,
                    broad_phase,
                    gravity,
                    dt,
                    rest_speed,
                    integration_parameters.prediction_distance(),
                );
                self.replay = replay;
            }
        }
    }

    /// Set the hook flag on the marked colliders of moving, awake dynamic
    /// bodies (only they can start an impact), clear the flags we set on
    /// others, and, in exact mode, store where those bodies start the step.
    ///
    /// Walks rapier's active (awake) bodies, the colliders marked since the
    /// last step and the bodies kimpact woke (rapier adds those to its active
    /// set only inside the next step), never the whole set: a scene of
    /// resting bodies costs nothing. (A sleeping body the user wakes between
    /// steps joins one step later, when rapier has made it active.) Flags
    /// that stay are not touched (rapier treats a collider borrowed mutably
    /// as modified).
    fn prepare(&mut self, input: &PrepareInput, colliders: &mut ColliderSet) {
        let PrepareInput {
            islands,
            bodies,
            rest_speed,
            ..
        } = *input;
        self.epoch = self.epoch.wrapping_add(1).max(1);
        std::mem::swap(&mut self.previous, &mut self.flagged);
        self.flagged.clear();
        if self.mode != Mode::Native {
            let threshold = 0.5 * rest_speed;
            let exact = self.mode == Mode::Exact;
            let fast = if self.config.calm_neighbourhoods && self.calm.wanted() {
                self.prepare_calm(input, colliders)
            } else {
                // Every awake body, at every step: a tight pass reads only
                // the velocity of a slow body (a body's data spans several
                // cache lines, and this read is a cache miss per body in a
                // large scene; a loop without calls lets the processor
                // overlap them) and, in exact mode, its start (it may join a
                // chain: stored whether or not it has a marked collider; a
                // kinematic body's start is never read). A fast body gets
                // the rest at once, while its lines are in the cache (a
                // second pass over the fast bodies missed them again in a
                // gas, where all are fast).
                let mut fast = 0;
                for handle in islands.active_bodies() {
                    let Some(rb) = bodies.get(handle) else {
                        continue;
                    };
                    if rb.linvel().length_squared() > threshold * threshold {
                        fast += usize::from(rb.is_dynamic());
                        self.prepare_rb(handle, rb, colliders, threshold);
                    } else if exact {
                        store_start(&mut self.start, handle, rb.translation());
                    }
                }
                fast
            };
            self.calm.last_fast = u32::try_from(fast).unwrap_or(u32::MAX);
            self.calm.last_awake = u32::try_from(islands.num_active_bodies()).unwrap_or(u32::MAX);
            let mut pending = std::mem::take(&mut self.pending);
            for &ch in &pending {
                if let Some(handle) = colliders.get(ch).and_then(|co| co.parent()) {
                    self.prepare_body(handle, bodies, colliders, threshold);
                }
            }
            pending.clear();
            self.pending = pending;
            let mut woken = std::mem::take(&mut self.woken);
            for &handle in &woken {
                self.prepare_body(handle, bodies, colliders, threshold);
            }
            woken.clear();
            self.woken = woken;
        } else {
            self.pending.clear();
            self.woken.clear();
        }
        // Last step's flags not renewed: cleared.
        for i in 0..self.previous.len() {
            let handle = self.previous[i];
            let (index, _) = handle.into_raw_parts();
            let index = index as usize;
            if self.seen.get(index) == Some(&self.epoch) {
                continue;
            }
            if let Some(co) = colliders.get_mut(handle) {
                co.set_active_hooks(co.active_hooks() - ActiveHooks::MODIFY_SOLVER_CONTACTS);
            }
            if let Some(o) = self.ours.get_mut(index) {
                *o = false;
            }
        }
        self.previous.clear();
    }

    /// `prepare` for one body (fast ones, and those marked or woken since
    /// the last step).
    fn prepare_body(
        &mut self,
        handle: RigidBodyHandle,
        bodies: &RigidBodySet,
        colliders: &mut ColliderSet,
        threshold: Real,
    ) {
        if let Some(rb) = bodies.get(handle) {
            self.prepare_rb(handle, rb, colliders, threshold);
        }
    }

    /// [`Kimpact::prepare_body`] with the body at hand.
    fn prepare_rb(
        &mut self,
        handle: RigidBodyHandle,
        rb: &RigidBody,
        colliders: &mut ColliderSet,
        threshold: Real,
    ) {
        if !rb.is_dynamic() || rb.is_sleeping() {
            return;
        }
        let any_marked = if rb.linvel().length_squared() > threshold * threshold {
            self.flag(rb, colliders)
        } else {
            rb.colliders().iter().any(|&ch| is_marked(&self.marked, ch))
        };
        if any_marked && self.mode == Mode::Exact {
            store_start(&mut self.start, handle, rb.translation());
        }
    }

    /// The pass of `prepare` with calm neighbourhoods (see the `calm`
    /// module): every awake body is taken (its start stored in exact mode),
    /// judged, and a fast body flagged unless calm. The number of fast
    /// bodies.
    fn prepare_calm(&mut self, input: &PrepareInput, colliders: &mut ColliderSet) -> usize {
        let PrepareInput {
            islands,
            bodies,
            broad_phase,
            gravity,
            dt,
            prediction,
            rest_speed,
        } = *input;
        let threshold = 0.5 * rest_speed;
        let exact = self.mode == Mode::Exact;
        let mut calm = std::mem::take(&mut self.calm);
        calm.begin();
        let judged = {
            let frame = Frame {
                bodies,
                colliders,
                broad_phase,
                marked: &self.marked,
                fixed_partners: self.config.fixed_partners,
                gravity,
                dt,
                prediction,
            };
            for handle in islands.active_bodies() {
                let Some(rb) = bodies.get(handle) else {
                    continue;
                };
                let is_fast = rb.linvel().length_squared() > threshold * threshold;
                if exact {
                    store_start(&mut self.start, handle, rb.translation());
                }
                calm.take(&frame, handle, rb, is_fast);
            }
            calm.judge(&frame, rest_speed)
        };
        let fast = judged.fast;
        for t in calm.taken() {
            if t.fast
                && !t.calm
                && let Some(rb) = bodies.get(t.handle)
            {
                self.flag(rb, colliders);
            }
        }
        calm.settle(&judged);
        self.stats.calm_bodies += judged.calm as u64;
        self.calm = calm;
        fast
    }

    /// Set the hook flag on the marked colliders of `rb` (leaving a flag the
    /// user set alone); whether it has any marked collider.
    fn flag(&mut self, rb: &RigidBody, colliders: &mut ColliderSet) -> bool {
        let mut any_marked = false;
        for &ch in rb.colliders() {
            if !is_marked(&self.marked, ch) {
                continue;
            }
            any_marked = true;
            let (index, _) = ch.into_raw_parts();
            let index = index as usize;
            if self.seen.len() <= index {
                self.seen.resize(index + 1, 0);
            }
            if self.seen[index] == self.epoch {
                continue; // flagged already this step
            }
            if self.ours.get(index).copied().unwrap_or(false) {
                // Ours since last step: keep it, untouched.
                self.seen[index] = self.epoch;
                self.flagged.push(ch);
                continue;
            }
            let Some(co) = colliders.get(ch) else {
                continue;
            };
            if co
                .active_hooks()
                .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS)
            {
                continue; // the user's own flag: the hook runs anyway
            }
            if let Some(co) = colliders.get_mut(ch) {
                co.set_active_hooks(co.active_hooks() | ActiveHooks::MODIFY_SOLVER_CONTACTS);
            }
            if self.ours.len() <= index {
                self.ours.resize(index + 1, false);
            }
            self.ours[index] = true;
            self.seen[index] = self.epoch;
            self.flagged.push(ch);
        }
        any_marked
    }

    /// Move the hook's list into `sorted`, in a deterministic order (the hook
    /// may run on several threads), without duplicates (CCD substeps call
    /// the hook again for the same pair).
    fn collect_candidates(&mut self) {
        self.sorted.clear();
        {
            let mut list = self.candidates.lock().unwrap_or_else(|e| e.into_inner());
            self.sorted.append(&mut list);
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

    /// Restitution mode: rapier's solver applied the law's restitution;
    /// report the law's outcome for the velocities it saw at detection, for
    /// each pair whose contact carried an impulse this step.
    fn report_restitution(&mut self, narrow_phase: &NarrowPhase) {
        for i in 0..self.sorted.len() {
            let c = self.sorted[i];
            let bounced = narrow_phase
                .contact_pair(c.collider1, c.collider2)
                .is_some_and(|cp| {
                    cp.manifolds()
                        .iter()
                        .any(|m| m.points.iter().any(|p| p.data.impulse > 0.0))
                });
            if !bounced {
                continue;
            }
            let (Ok(b1), Ok(b2)) = (checked(&c.start1), checked(&c.start2)) else {
                self.skip(&c);
                continue;
            };
            if let Some(impact) = self.law.resolve_unit(&b1, &b2, &to_law(c.normal)) {
                self.push_event(&c, 0.0, c.point, &impact, true);
            }
        }
    }

    /// Count and log a pair skipped for non-finite body data.
    pub(crate) fn skip(&mut self, c: &Candidate) {
        log::warn!(
            "kimpact: skipped the pair {:?}/{:?}: a body has a non-finite velocity or mass",
            c.collider1,
            c.collider2
        );
        self.stats.skipped_non_finite += 1;
    }

    pub(crate) fn push_event(
        &mut self,
        c: &Candidate,
        time: Real,
        point: Vector,
        impact: &kimpact::Impact<Real, { crate::math::DIM }>,
        by_solver: bool,
    ) {
        self.stats.impacts += 1;
        self.stats.clamped += u64::from(impact.clamped);
        self.stats.dissipated += f64::from(impact.dissipated);
        self.events.push(ImpactEvent {
            collider1: c.collider1,
            collider2: c.collider2,
            time,
            by_solver,
            point,
            normal: from_law(&impact.normal),
            impulse: impact.impulse,
            approach_speed: impact.approach_speed,
            restitution: impact.restitution,
            dissipated: impact.dissipated,
            clamped: impact.clamped,
        });
    }

    pub(crate) fn law_ref(&self) -> &Law<Real> {
        &self.law
    }

    pub(crate) fn config_ref(&self) -> &Config {
        &self.config
    }

    pub(crate) fn marked_ref(&self) -> &[u32] {
        &self.marked
    }

    pub(crate) fn flagged_ref(&self) -> &[ColliderHandle] {
        &self.flagged
    }

    pub(crate) fn candidates_sorted(&self) -> &[Candidate] {
        &self.sorted
    }

    pub(crate) fn start_of(&self, handle: RigidBodyHandle) -> Option<Vector> {
        let (index, generation) = handle.into_raw_parts();
        self.start
            .get(index as usize)
            .filter(|s| s.tag == generation.wrapping_add(1))
            .map(|s| s.translation)
    }

    /// Body `h` was given a new velocity (and woken): rapier adds a woken
    /// body to its active set only inside the next step, so `prepare` looks
    /// at it then.
    pub(crate) fn woke(&mut self, h: RigidBodyHandle) {
        self.woken.push(h);
    }

    /// Testing aid: sweep fast bodies one broad-phase query at a time, never
    /// in bulk (in a gas the bodies come out the same bit for bit either
    /// way; a test checks it).
    #[doc(hidden)]
    pub fn set_per_body_sweep(&mut self, on: bool) {
        self.replay.per_body_sweep = on;
    }

    pub(crate) fn count_cap_hit(&mut self) {
        self.stats.event_cap_hits += 1;
    }
}
