//! Before rapier's step: which colliders get kimpact's contact hook this
//! step, and where the bodies start it.
//!
//! A hook on a pair costs rapier its contact recycling for that pair, so
//! only the marked colliders of bodies that could start an impact get
//! `ActiveHooks::MODIFY_SOLVER_CONTACTS`: bodies faster than half the rest
//! speed (and, with calm neighbourhoods, not moving with every partner
//! they could touch; see the `calm` module).

use crate::body_view::{Starts, half_size, path_velocity};
use crate::calm::{Calm, Frame};
use crate::frame::StepFrame;
use crate::marks::Marks;
use crate::math::{Real, Vector};
use crate::mode::Mode;
use crate::rapier::prelude::*;

/// What [`Prepare::run`] reads of the step.
#[derive(Copy, Clone)]
pub(crate) struct PrepareInput<'a> {
    pub islands: &'a IslandManager,
    pub bodies: &'a RigidBodySet,
    pub broad_phase: &'a BroadPhaseBvh,
    pub frame: StepFrame,
    pub marks: &'a Marks,
    pub mode: Mode,
    pub fixed_partners: bool,
    pub calm_neighbourhoods: bool,
}

/// The hook flags kimpact keeps between steps, and the start of the step.
#[derive(Default)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize)
)]
pub(crate) struct Prepare {
    /// Per collider index: whether `MODIFY_SOLVER_CONTACTS` is set by us.
    pub ours: Vec<bool>,
    /// Colliders whose hook flag we set this step.
    pub flagged: Vec<ColliderHandle>,
    /// Scratch of `run`: last step's `flagged`.
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    previous: Vec<ColliderHandle>,
    /// Per collider index: the step (`epoch`) at which it was last flagged.
    seen: Vec<u32>,
    /// Per collider index: the step (`epoch`) at which it was flagged while
    /// touching something (see [`Prepare::find_crowded`]).
    crowded: Vec<u32>,
    /// Restitution mode: the flagged colliders whose bodies move more than
    /// a quarter of their size this step ([`Prepare::find_swept`]).
    pub swept: Vec<ColliderHandle>,
    /// Per collider index: the step (`epoch`) at which it was last swept.
    swept_at: Vec<u32>,
    epoch: u32,
    /// Colliders marked since the last step: their bodies may not be in
    /// rapier's active set yet (inserted, or woken, since the last step).
    pub pending: Vec<ColliderHandle>,
    /// Bodies kimpact gave a new velocity since the last `run`: rapier adds
    /// a woken body to its active set only inside the next step, so `run`
    /// looks at them then.
    pub woken: Vec<RigidBodyHandle>,
    /// Per body index: start-of-step translation (every law mode).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    pub starts: Starts,
    /// Calm neighbourhoods (`Config::calm_neighbourhoods`).
    calm: Calm,
    /// This step's `Config::fixed_partners`: whether a moving kinematic
    /// body's colliders are flagged (see [`Prepare::flag`]).
    #[cfg_attr(feature = "serde-serialize", serde(skip))]
    partners: bool,
}

impl Prepare {
    /// Set the hook flag on the marked colliders of moving, awake dynamic
    /// bodies (only they can start an impact), clear the flags we set on
    /// others, and store where those bodies start the step.
    ///
    /// Walks rapier's active (awake) bodies, the colliders marked since the
    /// last step and the bodies kimpact woke (rapier adds those to its active
    /// set only inside the next step), never the whole set: a scene of
    /// resting bodies costs nothing. (A sleeping body the user wakes between
    /// steps joins one step later, when rapier has made it active.) Flags
    /// that stay are not touched (rapier treats a collider borrowed mutably
    /// as modified).
    ///
    /// Returns the number of fast bodies left calm (unhooked) this step.
    pub(crate) fn run(&mut self, input: &PrepareInput, colliders: &mut ColliderSet) -> u64 {
        let PrepareInput {
            islands,
            bodies,
            marks,
            mode,
            ..
        } = *input;
        let rest_speed = input.frame.rest_speed;
        self.partners = input.fixed_partners;
        let mut calm_bodies = 0;
        self.epoch = self.epoch.wrapping_add(1).max(1);
        std::mem::swap(&mut self.previous, &mut self.flagged);
        self.flagged.clear();
        if mode != Mode::Native {
            let threshold = 0.5 * rest_speed;
            let replays = crate::mode::replays(mode);
            let fast = if input.calm_neighbourhoods && self.calm.wanted() {
                let (fast, calm) = self.prepare_calm(input, colliders);
                calm_bodies = calm;
                fast
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
                        self.prepare_rb(handle, rb, colliders, marks, mode, threshold);
                    } else if replays {
                        self.starts.store(handle, rb.translation());
                    }
                }
                fast
            };
            self.calm.last_fast = u32::try_from(fast).unwrap_or(u32::MAX);
            self.calm.last_awake = u32::try_from(islands.num_active_bodies()).unwrap_or(u32::MAX);
            let mut pending = std::mem::take(&mut self.pending);
            for &ch in &pending {
                if let Some(handle) = colliders.get(ch).and_then(|co| co.parent()) {
                    self.prepare_body(handle, bodies, colliders, marks, mode, threshold);
                }
            }
            pending.clear();
            self.pending = pending;
            let mut woken = std::mem::take(&mut self.woken);
            for &handle in &woken {
                self.prepare_body(handle, bodies, colliders, marks, mode, threshold);
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
        calm_bodies
    }

    /// Restitution mode: note which flagged colliders' bodies move more
    /// than a quarter of the collider's size this step: two balls slower
    /// than that close by at most a radius per step, so rapier's contacts
    /// never let one sink a radius into the other, where a faster ball can
    /// sink deeper, cross a partner or leave its box between two of
    /// rapier's contacts. The replay sweeps them after the step, and the hook leaves their pairs
    /// to it ([`Prepare::is_swept`]). Reads only the flagged colliders;
    /// allocates nothing in steady state.
    pub(crate) fn find_swept(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        gravity_dt: Vector,
        dt: Real,
    ) {
        self.swept.clear();
        for &ch in &self.flagged {
            let Some(co) = colliders.get(ch) else {
                continue;
            };
            let Some(rb) = co.parent().and_then(|h| bodies.get(h)) else {
                continue;
            };
            if !rb.is_dynamic() {
                continue;
            }
            let half = half_size(co);
            // A NaN velocity is not swept (the hook's guard cuts it off).
            if (path_velocity(rb, gravity_dt) * dt).length() > 0.5 * half {
                let index = ch.into_raw_parts().0 as usize;
                if self.swept_at.len() <= index {
                    self.swept_at.resize(index + 1, 0);
                }
                self.swept_at[index] = self.epoch;
                self.swept.push(ch);
            }
        }
    }

    /// Whether collider `ch` is one of this step's swept colliders
    /// ([`Prepare::find_swept`]).
    pub(crate) fn is_swept(&self, ch: ColliderHandle) -> bool {
        let index = ch.into_raw_parts().0 as usize;
        self.swept_at.get(index) == Some(&self.epoch)
    }

    /// Note which flagged colliders touch something (an active contact in
    /// rapier's narrow phase of the last step): rapier's solver may push
    /// their bodies off the straight path the hook would judge a graze on
    /// (see [`Prepare::is_crowded`]). Reads only the flagged colliders'
    /// contacts; allocates nothing in steady state.
    pub(crate) fn find_crowded(&mut self, narrow_phase: &NarrowPhase) {
        for &ch in &self.flagged {
            if narrow_phase
                .contact_pairs_with(ch)
                .any(|cp| cp.has_any_active_contact())
            {
                let index = ch.into_raw_parts().0 as usize;
                if self.crowded.len() <= index {
                    self.crowded.resize(index + 1, 0);
                }
                self.crowded[index] = self.epoch;
            }
        }
    }

    /// Whether flagged collider `ch` touched something at the start of this
    /// step ([`Prepare::find_crowded`]).
    pub(crate) fn is_crowded(&self, ch: ColliderHandle) -> bool {
        let index = ch.into_raw_parts().0 as usize;
        self.crowded.get(index) == Some(&self.epoch)
    }

    /// Restart the sleep timer (rapier's `wake_up(true)`) of every body
    /// flagged this step that moves faster than `rest_speed` and whose
    /// timer runs, so that rapier never puts a marked body to sleep (and
    /// zeroes its velocity) while it moves faster than the rest speed. A
    /// body at rest (a settled pile) is never flagged and sleeps as rapier
    /// lets it. Reads only the flagged bodies; allocates nothing.
    pub(crate) fn wake_moving(
        &self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
        rest_speed: Real,
    ) {
        for &ch in &self.flagged {
            let Some(handle) = colliders.get(ch).and_then(|co| co.parent()) else {
                continue;
            };
            let runs = bodies.get(handle).is_some_and(|rb| {
                rb.is_dynamic()
                    && rb.activation().time_since_can_sleep > 0.0
                    && rb.linvel().length_squared() > rest_speed * rest_speed
            });
            if runs && let Some(rb) = bodies.get_mut(handle) {
                rb.wake_up(true);
            }
        }
    }

    /// `prepare` for one body (fast ones, and those marked or woken since
    /// the last step).
    fn prepare_body(
        &mut self,
        handle: RigidBodyHandle,
        bodies: &RigidBodySet,
        colliders: &mut ColliderSet,
        marks: &Marks,
        mode: Mode,
        threshold: Real,
    ) {
        if let Some(rb) = bodies.get(handle) {
            self.prepare_rb(handle, rb, colliders, marks, mode, threshold);
        }
    }

    /// [`Kimpact::prepare_body`] with the body at hand.
    fn prepare_rb(
        &mut self,
        handle: RigidBodyHandle,
        rb: &RigidBody,
        colliders: &mut ColliderSet,
        marks: &Marks,
        mode: Mode,
        threshold: Real,
    ) {
        if !rb.is_dynamic() {
            // A kinematic body faster than the threshold may strike a
            // marked body at rest, which is not flagged.
            if rb.is_kinematic() && rb.linvel().length_squared() > threshold * threshold {
                self.flag(rb, colliders, marks);
            }
            return;
        }
        if rb.is_sleeping() {
            return;
        }
        let any_marked = if rb.linvel().length_squared() > threshold * threshold {
            self.flag(rb, colliders, marks)
        } else {
            rb.colliders().iter().any(|&ch| marks.contains(ch))
        };
        if any_marked && crate::mode::replays(mode) {
            self.starts.store(handle, rb.translation());
        }
    }

    /// The pass of `prepare` with calm neighbourhoods (see the `calm`
    /// module): every awake body is taken (its start stored),
    /// judged, and a fast body flagged unless calm. The number of fast
    /// bodies and the number left calm.
    fn prepare_calm(&mut self, input: &PrepareInput, colliders: &mut ColliderSet) -> (usize, u64) {
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
                    ..
                },
            marks,
            mode,
            fixed_partners,
            ..
        } = *input;
        let threshold = 0.5 * rest_speed;
        let replays = crate::mode::replays(mode);
        let mut calm = std::mem::take(&mut self.calm);
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
            };
            for handle in islands.active_bodies() {
                let Some(rb) = bodies.get(handle) else {
                    continue;
                };
                let is_fast = rb.linvel().length_squared() > threshold * threshold;
                if replays {
                    self.starts.store(handle, rb.translation());
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
                self.flag(rb, colliders, marks);
            }
        }
        calm.settle(&judged);
        self.calm = calm;
        (fast, judged.calm as u64)
    }

    /// Set the hook flag on the marked colliders of `rb` (leaving a flag the
    /// user set alone); whether it has any marked collider. A kinematic
    /// body's colliders are all flagged with `Config::fixed_partners` (they
    /// meet marked colliders by the law, marked or not).
    pub(crate) fn flag(
        &mut self,
        rb: &RigidBody,
        colliders: &mut ColliderSet,
        marks: &Marks,
    ) -> bool {
        let mut any_marked = false;
        let partner = self.partners && rb.is_kinematic();
        for &ch in rb.colliders() {
            // An extended collider on a dynamic body is rapier's (see
            // `Marks::governs`): no hook for it.
            if !partner && (!marks.contains(ch) || marks.is_extended(ch)) {
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
}
