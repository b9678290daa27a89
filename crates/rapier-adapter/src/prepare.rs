//! Before rapier's step: which colliders get kimpact's contact hook this
//! step, and where the bodies start it.
//!
//! A hook on a pair costs rapier its contact recycling for that pair, so
//! only the marked colliders of bodies that could start an impact get
//! `ActiveHooks::MODIFY_SOLVER_CONTACTS`: bodies faster than half the rest
//! speed (and, with calm neighbourhoods, not moving with every partner
//! they could touch; see the `calm` module).
//!
//! Everything stage 1 learns of a flagged collider (whether it touches
//! something, whether restitution hands it to the replay, whether its body's
//! sleep timer must restart) is learnt while flagging it, in the one pass
//! over the awake bodies: no second walk over the flagged colliders.

use crate::body_view::{SWEPT_SHARE, Starts, half_size, path_velocity, turns_fast};
use crate::calm::{Calm, CalmSchedule, Frame};
use crate::frame::StepFrame;
use crate::handle_map::HandleMap;
use crate::marks::Marks;
use crate::math::Real;
#[cfg(feature = "parallel")]
use crate::math::Vector;
use crate::policy::Policy;
use crate::rapier::prelude::*;
use crate::touches::Touches;

/// What [`Prepare::run`] reads of the step.
#[derive(Copy, Clone)]
pub(crate) struct PrepareInput<'a> {
    pub islands: &'a IslandManager,
    pub bodies: &'a RigidBodySet,
    pub broad_phase: &'a BroadPhaseBvh,
    pub narrow_phase: &'a NarrowPhase,
    pub frame: StepFrame,
    pub marks: &'a Marks,
    pub policy: Policy,
    pub fixed_partners: bool,
    pub calm_neighbourhoods: bool,
    pub keep_moving_awake: bool,
}

/// What [`Pass::flag`] needs of the step beyond the body: where to look
/// for its contacts and how it is judged swept or to be kept awake.
#[derive(Copy, Clone)]
struct FlagStep<'a> {
    narrow_phase: &'a NarrowPhase,
    marks: &'a Marks,
    frame: StepFrame,
    /// Half the rest speed: a body faster than this may start an impact.
    threshold: Real,
    /// Whether the swept and crowded colliders are noted (restitution
    /// mode, see [`Policy::notes_fast_bodies`]).
    notes_fast_bodies: bool,
    keep_moving_awake: bool,
    /// `ResolverConfig::fixed_partners`: whether a moving kinematic body's
    /// colliders are flagged (see [`Pass::flag`]).
    fixed_partners: bool,
}

impl<'a> FlagStep<'a> {
    fn new(input: &PrepareInput<'a>) -> Self {
        Self {
            narrow_phase: input.narrow_phase,
            marks: input.marks,
            frame: input.frame,
            threshold: 0.5 * input.frame.rest_speed,
            notes_fast_bodies: input.policy.notes_fast_bodies(),
            keep_moving_awake: input.keep_moving_awake,
            fixed_partners: input.fixed_partners,
        }
    }
}

impl FlagStep<'_> {
    /// Whether body `rb` may start an impact this step: its centre moves
    /// faster than the threshold, or, turning, a point of one of its
    /// extended marked colliders does (of any of its colliders, for a
    /// kinematic body: a flipper).
    fn is_fast(&self, rb: &RigidBody, colliders: &ColliderSet) -> bool {
        let threshold = self.threshold;
        rb.linvel().length_squared() > threshold * threshold || self.spins_fast(rb, colliders)
    }

    /// The turning part of [`FlagStep::is_fast`] (see [`turns_fast`]): of
    /// the extended marked colliders, or of every collider of a kinematic
    /// body. Never for a body with no extended marked collider (a ball
    /// centred on its body spins without moving its surface towards
    /// anything).
    fn spins_fast(&self, rb: &RigidBody, colliders: &ColliderSet) -> bool {
        let kinematic = rb.is_kinematic();
        if !kinematic && !self.marks.has_extended() {
            return false;
        }
        let marks = self.marks;
        turns_fast(rb, colliders, self.threshold, |ch| {
            kinematic || marks.is_extended(ch)
        })
    }
}

/// What [`Prepare`] carries from one step to the next (the rest of its
/// state is the scratch of one step): the hook flags it set in rapier's
/// collider set, the bodies the next step must look at beyond rapier's
/// active set, and when the calm test is tried next. A snapshot holds it.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub(crate) struct Carried {
    /// The colliders whose `MODIFY_SOLVER_CONTACTS` flag kimpact set at the
    /// last step (cleared by the next one unless flagged again).
    pub hooked: Vec<ColliderHandle>,
    /// Colliders marked since the last step.
    pub marked_since_step: Vec<ColliderHandle>,
    /// Bodies kimpact gave a new velocity at the last step.
    pub woken: Vec<RigidBodyHandle>,
    /// When the calm test is tried next.
    pub calm: CalmSchedule,
}

/// What lives across steps for the next prepare pass, beyond rapier's
/// active set: the colliders marked since the last step (their bodies may
/// not be in the active set yet: inserted, or woken, since then) and the
/// bodies the replays gave a new velocity (rapier adds a woken body to its
/// active set only inside the next step). `Kimpact::mark` and the replays
/// add to it; [`Prepare::run`] reads and empties it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Joining {
    pub marked: Vec<ColliderHandle>,
    pub woken: Vec<RigidBodyHandle>,
}

/// What the prepare pass produced for one step: which colliders it
/// flagged, which of them the replay sweeps, where the bodies start, and
/// whose sleep timer restarts. The resolver hands it to the hook and the
/// replays (in [`crate::PreparedStep`]), and gives its buffers back to the
/// next pass.
#[derive(Default)]
pub(crate) struct Prepared {
    /// The step's number, for the hook's [`Touches`].
    pub epoch: u32,
    /// Colliders whose hook flag is set this step, but for those in
    /// `rigid`: in impulse and exact mode, the colliders the replay sweeps.
    pub flagged: Vec<ColliderHandle>,
    /// Extended colliders of dynamic bodies (not balls centred on their
    /// body, see `marks::is_point_collider`) whose hook flag is set this
    /// step: the hook governs their pairs as rigid bodies at the manifold's
    /// contact in restitution mode (the rigid replay's, in impulse and exact
    /// mode), and the point replay, which moves bodies as points, never
    /// sweeps them.
    pub rigid: Vec<ColliderHandle>,
    /// Restitution mode: the flagged colliders whose bodies move more than
    /// a quarter of their size this step (see [`Prepare::is_swept`]).
    pub swept: Vec<ColliderHandle>,
    /// Per body: start-of-step translation (every law mode).
    pub starts: Starts,
    /// Flagged bodies whose sleep timer runs while they move faster than
    /// the rest speed (`ResolverConfig::keep_moving_awake`): woken by
    /// [`Prepared::wake_moving`].
    to_wake: Vec<RigidBodyHandle>,
    /// Fast bodies left calm (unhooked) this step.
    pub calm_bodies: u64,
}

impl std::fmt::Debug for Prepared {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Prepared")
            .field("epoch", &self.epoch)
            .field("flagged", &self.flagged.len())
            .field("rigid", &self.rigid.len())
            .field("swept", &self.swept.len())
            .finish_non_exhaustive()
    }
}

impl Prepared {
    /// Ready for another step: the lists emptied, the starts kept (a body's
    /// entry is overwritten when it is stored again).
    fn reset(&mut self, epoch: u32) {
        self.epoch = epoch;
        self.flagged.clear();
        self.rigid.clear();
        self.swept.clear();
        self.to_wake.clear();
        self.calm_bodies = 0;
    }

    /// Restart the sleep timer (rapier's `wake_up(true)`) of every body
    /// flagged this step that moves faster than `rest_speed`, has no
    /// linear damping, and whose timer runs (noted while flagging, with
    /// `ResolverConfig::keep_moving_awake`), so that rapier never puts such
    /// a marked body to sleep (and zeroes its velocity) while it moves
    /// faster than the rest speed. A body at rest (a settled pile) is never
    /// flagged and sleeps as rapier lets it, and so does a damped one (a
    /// rolling billiard ball), whose motion dies out by the user's choice.
    /// Reads only those bodies; allocates nothing in steady state.
    pub(crate) fn wake_moving(&self, bodies: &mut RigidBodySet) {
        for &handle in &self.to_wake {
            if let Some(rb) = bodies.get_mut(handle) {
                rb.wake_up(true);
            }
        }
    }
}

/// The hook flags kimpact keeps between steps and when the calm test runs
/// next; [`Prepare::run`] is the pass that sets them before each step.
#[derive(Default)]
pub(crate) struct Prepare {
    /// Per collider: whether `MODIFY_SOLVER_CONTACTS` is set by us, and
    /// when it was last flagged, crowded, swept.
    flags: HandleMap<ColliderHandle, Flag>,
    /// The colliders whose flag kimpact set at the last step (cleared by
    /// the next one unless flagged again).
    hooked: Vec<ColliderHandle>,
    /// The `epoch` of this step (counted from 1; 0: none yet).
    epoch: u32,
    /// The `epoch` of the step before this one.
    last_epoch: u32,
    /// Calm neighbourhoods (`ResolverConfig::calm_neighbourhoods`).
    calm: Calm,
    scratch: Scratch,
}

/// The pass's own working space, kept so that a steady state allocates
/// nothing.
#[derive(Default)]
struct Scratch {
    /// Last step's `hooked`, while the pass clears its stale flags.
    previous: Vec<ColliderHandle>,
    /// The awake bodies (the parallel pass).
    #[cfg(feature = "parallel")]
    active: Vec<RigidBodyHandle>,
    /// What the parallel pass read of each awake body.
    #[cfg(feature = "parallel")]
    scans: Vec<Scan>,
}

/// One run of the pass: the flags it sets, what it produces, and the
/// step's settings.
struct Pass<'p, 'a> {
    flags: &'p mut HandleMap<ColliderHandle, Flag>,
    touches: &'p mut Touches,
    out: &'p mut Prepared,
    step: FlagStep<'a>,
    epoch: u32,
    last_epoch: u32,
}

/// What stage 1 keeps of a collider it flagged.
#[derive(Copy, Clone, Debug, Default)]
struct Flag {
    /// Whether `MODIFY_SOLVER_CONTACTS` is set by us.
    ours: bool,
    /// The step (`epoch`) at which it was last flagged.
    seen: u32,
    /// The step (`epoch`) at which it was flagged while touching something
    /// (see [`Prepare::is_crowded`]).
    crowded: u32,
    /// The step (`epoch`) at which it was last swept (see
    /// [`Prepare::is_swept`]).
    swept_at: u32,
}

/// What the parallel pass over the awake bodies reads of one
/// (`Prepare::scan_parallel`).
#[cfg(feature = "parallel")]
#[derive(Copy, Clone)]
enum Scan {
    /// Not in the body set.
    Gone,
    /// Faster than half the rest speed: flagged by the serial part.
    Fast,
    /// Slower: its start of the step.
    Slow(Vector),
}

/// Awake bodies per task of the parallel pass at least (a task reads a
/// few cache lines per body).
#[cfg(feature = "parallel")]
const SCAN_RUN: usize = 256;

impl Prepare {
    /// What this carries to the next step, with what is `joining` it.
    pub(crate) fn carried(&self, joining: &Joining) -> Carried {
        Carried {
            // Every collider carrying our flag (the restored step clears
            // those it does not flag again).
            hooked: self.hooked.clone(),
            marked_since_step: joining.marked.clone(),
            woken: joining.woken.clone(),
            calm: self.calm.schedule,
        }
    }

    /// The state `carried` leaves for the next step, and what joins it.
    /// The epoch starts afresh: the next step reads whether a collider
    /// flagged at the last one touches something from rapier's narrow phase
    /// (as for a collider flagged afresh), which says what the hook
    /// recorded then.
    pub(crate) fn from_carried(carried: Carried) -> (Self, Joining) {
        let Carried {
            hooked,
            marked_since_step,
            woken,
            calm,
        } = carried;
        let mut flags = HandleMap::default();
        for &ch in &hooked {
            let flag = Flag {
                ours: true,
                ..Flag::default()
            };
            flags.insert(ch, flag);
        }
        let prepare = Self {
            flags,
            hooked,
            calm: Calm::with_schedule(calm),
            ..Self::default()
        };
        let joining = Joining {
            marked: marked_since_step,
            woken,
        };
        (prepare, joining)
    }

    /// Set the hook flag on the marked colliders of moving, awake dynamic
    /// bodies (only they can start an impact), clear the flags we set on
    /// others, and store where those bodies start the step, in `out` (the
    /// last step's, whose buffers are reused), which it returns.
    ///
    /// Walks rapier's active (awake) bodies and those `joining` the step
    /// (which it empties), never the whole set: a scene of resting bodies
    /// costs nothing. (A sleeping body the user wakes between steps joins
    /// one step later, when rapier has made it active.) Flags that stay are
    /// not touched (rapier treats a collider borrowed mutably as modified).
    /// `touches` gets a slot for every collider flagged, for the hook.
    pub(crate) fn run(
        &mut self,
        input: &PrepareInput,
        colliders: &mut ColliderSet,
        joining: &mut Joining,
        touches: &mut Touches,
        mut out: Prepared,
    ) -> Prepared {
        let PrepareInput {
            islands,
            bodies,
            policy,
            ..
        } = *input;
        self.last_epoch = self.epoch;
        self.epoch = self.epoch.wrapping_add(1).max(1);
        out.reset(self.epoch);
        let mut pass = Pass {
            flags: &mut self.flags,
            touches,
            out: &mut out,
            step: FlagStep::new(input),
            epoch: self.epoch,
            last_epoch: self.last_epoch,
        };
        if policy.acts() {
            let fast = if input.calm_neighbourhoods && self.calm.wanted() {
                pass.prepare_calm(input, &mut self.calm, colliders)
            } else {
                // Every awake body, at every step: a tight pass reads only
                // the velocity of a slow body (a body's data spans several
                // cache lines, and this read is a cache miss per body in a
                // large scene; a loop without calls lets the processor
                // overlap them) and its start (it may join a chain in the
                // replay: stored whether or not it has a marked collider; a
                // kinematic body's start is never read). A fast body gets
                // the rest at once, while its lines are in the cache (a
                // second pass over the fast bodies missed them again in a
                // gas, where all are fast).
                pass.scan_active(islands, bodies, colliders, &mut self.scratch)
            };
            self.calm.schedule.last_fast = u32::try_from(fast).unwrap_or(u32::MAX);
            self.calm.schedule.last_awake =
                u32::try_from(islands.num_active_bodies()).unwrap_or(u32::MAX);
            for &ch in &joining.marked {
                if let Some(handle) = colliders.get(ch).and_then(|co| co.parent()) {
                    pass.prepare_body(handle, bodies, colliders);
                }
            }
            for &handle in &joining.woken {
                pass.prepare_body(handle, bodies, colliders);
            }
        }
        joining.marked.clear();
        joining.woken.clear();
        // Last step's flags not renewed: cleared.
        let mut previous = std::mem::take(&mut self.scratch.previous);
        std::mem::swap(&mut previous, &mut self.hooked);
        self.unflag_stale(&previous, colliders);
        previous.clear();
        self.scratch.previous = previous;
        self.hooked.extend(out.flagged.iter().chain(&out.rigid));
        out
    }

    /// Clear our hook flag on the colliders of `previous` (flagged last
    /// step) not flagged again this step.
    fn unflag_stale(&mut self, previous: &[ColliderHandle], colliders: &mut ColliderSet) {
        for &handle in previous {
            if self.flags.get(handle).is_some_and(|f| f.seen == self.epoch) {
                continue;
            }
            if let Some(co) = colliders.get_mut(handle) {
                co.set_active_hooks(co.active_hooks() - ActiveHooks::MODIFY_SOLVER_CONTACTS);
            }
            if let Some(flag) = self.flags.get_mut(handle) {
                flag.ours = false;
            }
        }
    }

    /// Whether collider `ch` is one of this step's swept colliders: in
    /// restitution mode, a flagged collider whose body moves more than a
    /// quarter of the collider's size this step. Two balls slower than that
    /// close by at most a radius per step, so rapier's contacts never let
    /// one sink a radius into the other, where a faster ball can sink
    /// deeper, cross a partner or leave its box between two of rapier's
    /// contacts. The replay sweeps them after the step, and the hook leaves
    /// their pairs to it.
    pub(crate) fn is_swept(&self, ch: ColliderHandle) -> bool {
        self.flags.get(ch).is_some_and(|f| f.swept_at == self.epoch)
    }

    /// Whether flagged collider `ch` touched something at the start of this
    /// step (in restitution mode): one of its pairs had solver contacts in
    /// rapier's last step, so rapier's solver may push its body off the
    /// straight path the hook would judge a graze on. For a collider
    /// flagged in the last step too, kimpact's hook saw every one of its
    /// pairs then ([`Touches::touch`]); for one flagged afresh, its
    /// contact pairs in the narrow phase are read.
    pub(crate) fn is_crowded(&self, ch: ColliderHandle) -> bool {
        self.flags.get(ch).is_some_and(|f| f.crowded == self.epoch)
    }

    /// Whether kimpact set `MODIFY_SOLVER_CONTACTS` on collider `ch` (not
    /// the user).
    pub(crate) fn is_ours(&self, ch: ColliderHandle) -> bool {
        self.flags.get(ch).is_some_and(|f| f.ours)
    }

    /// The colliders whose hook flag kimpact set at the last step.
    #[cfg(test)]
    pub(crate) fn hooked(&self) -> &[ColliderHandle] {
        &self.hooked
    }
}

impl Pass<'_, '_> {
    /// The pass over the awake bodies: each fast one flagged, a slow one's
    /// start stored; its reads on rayon's pool with `parallel`, unless
    /// fewer than `SCAN_RUN` bodies are awake (the same stores and flags
    /// either way). The number of fast dynamic bodies.
    #[cfg_attr(not(feature = "parallel"), allow(unused_variables))]
    fn scan_active(
        &mut self,
        islands: &IslandManager,
        bodies: &RigidBodySet,
        colliders: &mut ColliderSet,
        scratch: &mut Scratch,
    ) -> usize {
        #[cfg(feature = "parallel")]
        if islands.num_active_bodies() >= SCAN_RUN {
            return self.scan_parallel(islands, bodies, colliders, scratch);
        }
        self.scan_serial(islands, bodies, colliders)
    }

    /// [`Pass::scan_active`] on this thread.
    fn scan_serial(
        &mut self,
        islands: &IslandManager,
        bodies: &RigidBodySet,
        colliders: &mut ColliderSet,
    ) -> usize {
        let step = self.step;
        let mut fast = 0;
        for handle in islands.active_bodies() {
            let Some(rb) = bodies.get(handle) else {
                continue;
            };
            if step.is_fast(rb, colliders) {
                fast += usize::from(rb.is_dynamic());
                self.prepare_rb(handle, rb, true, colliders);
            } else {
                self.out.starts.store(handle, rb.translation());
            }
        }
        fast
    }

    /// [`Pass::scan_serial`] with its reads on
    /// rayon's pool: each body's speed judged and a slow body's start read
    /// there, in chunks, into `scans` (in the order of the active bodies);
    /// then, in that order, the starts stored and the fast bodies flagged
    /// here. The same stores and flags as the serial pass, in the same
    /// order, at any number of threads. The number of fast dynamic bodies.
    #[cfg(feature = "parallel")]
    fn scan_parallel(
        &mut self,
        islands: &IslandManager,
        bodies: &RigidBodySet,
        colliders: &mut ColliderSet,
        scratch: &mut Scratch,
    ) -> usize {
        use rayon::prelude::*;
        let step = self.step;
        let Scratch { active, scans, .. } = scratch;
        active.clear();
        active.extend(islands.active_bodies());
        let read: &ColliderSet = colliders;
        active
            .par_iter()
            .with_min_len(SCAN_RUN)
            .map(|&handle| match bodies.get(handle) {
                None => Scan::Gone,
                Some(rb) if step.is_fast(rb, read) => Scan::Fast,
                Some(rb) => Scan::Slow(rb.translation()),
            })
            .collect_into_vec(scans);
        let mut fast = 0;
        for (&handle, scan) in active.iter().zip(scans.iter()) {
            match *scan {
                Scan::Gone => {}
                Scan::Slow(start) => self.out.starts.store(handle, start),
                Scan::Fast => {
                    if let Some(rb) = bodies.get(handle) {
                        fast += usize::from(rb.is_dynamic());
                        self.prepare_rb(handle, rb, true, colliders);
                    }
                }
            }
        }
        fast
    }

    /// `prepare` for one body (fast ones, and those marked or woken since
    /// the last step).
    fn prepare_body(
        &mut self,
        handle: RigidBodyHandle,
        bodies: &RigidBodySet,
        colliders: &mut ColliderSet,
    ) {
        if let Some(rb) = bodies.get(handle) {
            let fast = self.step.is_fast(rb, colliders);
            self.prepare_rb(handle, rb, fast, colliders);
        }
    }

    /// [`Pass::prepare_body`] with the body at hand, judged `fast` or not
    /// ([`FlagStep::is_fast`]).
    fn prepare_rb(
        &mut self,
        handle: RigidBodyHandle,
        rb: &RigidBody,
        fast: bool,
        colliders: &mut ColliderSet,
    ) {
        if !rb.is_dynamic() {
            // A kinematic body faster than the threshold (moving or
            // turning) may strike a marked body at rest, which is not
            // flagged.
            if rb.is_kinematic() && fast {
                self.flag(handle, rb, colliders);
            }
            return;
        }
        if rb.is_sleeping() {
            return;
        }
        let any_marked = if fast {
            self.flag(handle, rb, colliders)
        } else {
            rb.colliders()
                .iter()
                .any(|&ch| self.step.marks.contains(ch))
        };
        if any_marked {
            self.out.starts.store(handle, rb.translation());
        }
    }

    /// The pass of `prepare` with calm neighbourhoods (see the `calm`
    /// module): every awake body is taken (its start stored),
    /// judged, and a fast body flagged unless calm. The number of fast
    /// bodies; the number left calm goes into `out.calm_bodies`.
    fn prepare_calm(
        &mut self,
        input: &PrepareInput,
        calm: &mut Calm,
        colliders: &mut ColliderSet,
    ) -> usize {
        let PrepareInput {
            islands,
            bodies,
            broad_phase,
            frame:
                StepFrame {
                    gravity,
                    dt,
                    prediction,
                    rest_speed,
                    shared,
                    ..
                },
            marks,
            fixed_partners,
            ..
        } = *input;
        let step = self.step;
        calm.begin();
        let judged = {
            let frame = Frame {
                bodies,
                colliders,
                broad_phase,
                marks,
                fixed_partners,
                gravity,
                dt,
                prediction,
                shared: shared.unwrap_or(Vector::ZERO),
            };
            for handle in islands.active_bodies() {
                let Some(rb) = bodies.get(handle) else {
                    continue;
                };
                let is_fast = step.is_fast(rb, frame.colliders);
                self.out.starts.store(handle, rb.translation());
                calm.take(&frame, handle, rb, is_fast);
            }
            calm.judge(&frame, rest_speed)
        };
        // The calm test compares the bodies' linear velocities: a body
        // fast by its turning is never calm.
        let mut turning = 0u64;
        for t in calm.taken() {
            if !t.fast {
                continue;
            }
            let Some(rb) = bodies.get(t.handle) else {
                continue;
            };
            let turns = t.calm && step.spins_fast(rb, colliders);
            if !t.calm || turns {
                turning += u64::from(turns);
                self.flag(t.handle, rb, colliders);
            }
        }
        calm.settle(&judged);
        self.out.calm_bodies = (judged.calm as u64).saturating_sub(turning);
        judged.fast
    }

    /// Set the hook flag on the marked colliders of body `handle`, `rb`
    /// (leaving a flag the user set alone); whether it has any marked
    /// collider. A kinematic body's colliders are all flagged with
    /// `ResolverConfig::fixed_partners` (they meet marked colliders by the law,
    /// marked or not). Notes, for each collider flagged, whether it is swept
    /// or crowded (restitution mode), and whether the body's sleep timer
    /// must restart.
    fn flag(
        &mut self,
        handle: RigidBodyHandle,
        rb: &RigidBody,
        colliders: &mut ColliderSet,
    ) -> bool {
        let step = self.step;
        let marks = step.marks;
        let mut any_marked = false;
        let mut flagged = false;
        let partner = step.fixed_partners && rb.is_kinematic();
        // How far the body moves this step (restitution mode's swept test;
        // a NaN is not swept: the hook's guard cuts it off).
        let travel = if step.notes_fast_bodies && rb.is_dynamic() {
            let v = step
                .frame
                .relative(path_velocity(rb, step.frame.gravity_dt()));
            (v * step.frame.dt).length()
        } else {
            0.0
        };
        for &ch in rb.colliders() {
            // An extended collider on a dynamic body: the hook governs its
            // pairs as rigid bodies (see `Marks::governs_rigid`) in every
            // law mode; the replay never sweeps it (`Prepared::rigid`).
            let extended = marks.is_extended(ch);
            if !partner && !marks.contains(ch) {
                continue;
            }
            any_marked = true;
            let epoch = self.epoch;
            let flag = self.flags.get_or_insert_with(ch, Flag::default);
            if flag.seen == epoch {
                continue; // flagged already this step
            }
            let carried = flag.ours;
            if !carried {
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
                flag.ours = true;
            }
            // Ours since last step (`carried`): kept, untouched.
            flag.seen = epoch;
            if extended && rb.is_dynamic() {
                self.out.rigid.push(ch);
            } else {
                self.out.flagged.push(ch);
            }
            flagged = true;
            self.touches.add(ch);
            if step.notes_fast_bodies {
                // The replay moves bodies as points: an extended collider is
                // never swept.
                let travel = if extended { 0.0 } else { travel };
                self.note_restitution(ch, carried, travel, colliders);
            }
        }
        if flagged
            && step.keep_moving_awake
            && rb.is_dynamic()
            && rb.activation().time_since_can_sleep > 0.0
            && rb.linear_damping() == 0.0
            && rb.linvel().length_squared() > step.frame.rest_speed * step.frame.rest_speed
        {
            self.out.to_wake.push(handle);
        }
        any_marked
    }

    /// Restitution mode, for collider `ch` just flagged:
    /// whether it is crowded (see [`Prepare::is_crowded`]; `carried`: it was
    /// flagged last step too) and whether its body's `travel` this step
    /// makes it swept ([`Prepare::is_swept`]).
    fn note_restitution(
        &mut self,
        ch: ColliderHandle,
        carried: bool,
        travel: Real,
        colliders: &ColliderSet,
    ) {
        let seen_by_hook = carried && self.last_epoch != 0;
        let crowded = if seen_by_hook {
            self.touches.touched_at(ch, self.last_epoch)
        } else {
            self.step
                .narrow_phase
                .contact_pairs_with(ch)
                .any(|cp| cp.has_any_active_contact())
        };
        let epoch = self.epoch;
        let flag = self.flags.get_or_insert_with(ch, Flag::default);
        if crowded {
            flag.crowded = epoch;
        }
        if travel > 0.0
            && colliders
                .get(ch)
                .is_some_and(|co| travel > SWEPT_SHARE * half_size(co))
        {
            flag.swept_at = epoch;
            self.out.swept.push(ch);
        }
    }
}
