//! [`Kimpact`], the resolver: the law, the mode, the marked colliders, and
//! the three stages of a step around rapier's own.

use std::sync::atomic::{AtomicU64, Ordering};

use kimpact::{Law, LawError, LawParams};

use crate::candidates::Candidates;
use crate::config::{ResolverConfig, ResolverConfigError};
use crate::events::{AppliedBy, EventLog, ImpactEvent, Outcome, Stats};
use crate::frame::StepFrame;
use crate::hook::StepHooks;
use crate::marks::Marks;
use crate::material::Material;
use crate::math::{Real, Vector, to_law};
use crate::mode::Mode;
use crate::pair_filter::PairFilter;
use crate::policy::{Policy, Response};
use crate::prepare::{Joining, Prepare, PrepareInput, Prepared};
use crate::rapier::prelude::*;
use crate::replay::{Replay, ReplayInput, ReplayOutput, ReplaySets};
use crate::rigid_replay::{RigidInput, RigidReplay};
use crate::shared_frame::free_fall_velocity;
use crate::snapshot::{Saving, Snapshot, SnapshotError};
use crate::step_sets::StepSets;
use crate::touches::Touches;

/// A collider handle that is not in the collider set it was checked
/// against.
#[derive(Copy, Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum HandleError {
    /// The handle was never inserted, its collider was removed, its
    /// generation is stale (rapier put another collider in its slot), or it
    /// is `ColliderHandle::invalid()`. Nothing was changed.
    #[error(
        "collider {0:?} is not in the collider set (never inserted, removed, stale or invalid); nothing was changed"
    )]
    UnknownCollider(ColliderHandle),
    /// The collider is not marked (a material needs a marked collider).
    /// Nothing was changed.
    #[error("collider {0:?} is not marked; nothing was changed")]
    NotMarked(ColliderHandle),
}

/// The step [`Kimpact::before_step`] prepared: [`Kimpact::hooks`] reads it
/// during `PhysicsPipeline::step` and [`Kimpact::after_step`] consumes it,
/// so the three stages can only run in their order (there is no finishing
/// a step that was not prepared, nor finishing one twice).
///
/// It holds the step's gravity, integration parameters and what its mode
/// does as `before_step` fixed them, and what its prepare pass produced
/// (the colliders it flagged, where the bodies start); hand it to the same
/// [`Kimpact`], which keeps what lives across steps.
#[derive(Debug)]
#[must_use = "a prepared step is finished by Kimpact::after_step"]
pub struct PreparedStep {
    frame: StepFrame,
    policy: Policy,
    /// What the prepare pass produced: the flagged colliders, the starts.
    prepared: Prepared,
}

/// kimpact's resolver: the law, the mode, the marked colliders, and the state
/// kept between steps. See the crate docs for the drop-in.
///
/// A step has three stages around rapier's own, which [`Kimpact::step`]
/// (and [`Kimpact::step_world`]) compose; a program that calls
/// `PhysicsPipeline::step` itself (a Bevy app, a game with its own loop or
/// substeps) calls them in turn:
///
/// ```text
/// let mut sets = StepSets { islands: &mut islands, /* … rapier's sets … */ };
/// let prepared = kimpact.before_step(gravity, &params, &mut sets);
/// pipeline.step(gravity, &params, sets.islands, /* … the same sets … */,
///     &kimpact.hooks(&prepared, &user_hooks), &events);
/// kimpact.after_step(prepared, &mut sets, &user_hooks);
/// ```
///
/// (`examples/stages.rs` runs it.)
///
/// [`Kimpact::snapshot`] saves its state between steps and
/// [`Kimpact::from_snapshot`] restores it: with rapier's world of the same
/// moment, the simulation continues bit for bit.
pub struct Kimpact {
    law: Law<Real>,
    mode: Mode,
    config: ResolverConfig,
    /// The marked colliders.
    marks: Marks,
    /// The hook flags kept between steps.
    prepare: Prepare,
    /// What joins the next step beyond rapier's active set: colliders
    /// marked since the last step, bodies the replays woke.
    joining: Joining,
    /// The hook's record of the colliders it left touching.
    touches: Touches,
    /// The last step's [`Prepared`], whose buffers the next pass reuses.
    spare: Prepared,
    /// The pairs the hook hands over during the step.
    candidates: Candidates,
    /// Pairs the hook's runtime guard cut off during the step.
    guarded: AtomicU64,
    /// This step's events and the totals.
    log: EventLog,
    replay: Replay,
    /// Impulse and exact mode: the rigid bodies' impacts at their time of
    /// impact.
    rigid_replay: RigidReplay,
}

/// The user's state (law, mode, configuration, how many colliders are
/// marked), this step's events and the totals; not the scratch of a step.
impl std::fmt::Debug for Kimpact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Kimpact")
            .field("law", &self.law)
            .field("mode", &self.mode)
            .field("config", &self.config)
            .field("marked", &self.marks.len())
            .field("events", &self.log.events)
            .field("stats", &self.log.stats)
            .finish_non_exhaustive()
    }
}

impl Kimpact {
    /// A resolver applying `law` in `mode`, with the default [`ResolverConfig`].
    pub fn new(law: Law<Real>, mode: Mode) -> Self {
        Self::build(law, mode, ResolverConfig::default())
    }

    /// A resolver with an explicit [`ResolverConfig`].
    ///
    /// # Errors
    /// A [`ResolverConfigError`] naming the first invalid field of `config`.
    pub fn with_config(
        law: Law<Real>,
        mode: Mode,
        config: ResolverConfig,
    ) -> Result<Self, ResolverConfigError> {
        config.validate()?;
        Ok(Self::build(law, mode, config))
    }

    fn build(law: Law<Real>, mode: Mode, config: ResolverConfig) -> Self {
        Self {
            law,
            mode,
            config,
            marks: Marks::default(),
            prepare: Prepare::default(),
            joining: Joining::default(),
            touches: Touches::default(),
            spare: Prepared::default(),
            candidates: Candidates::default(),
            guarded: AtomicU64::new(0),
            log: EventLog::default(),
            replay: Replay::default(),
            rigid_replay: RigidReplay::default(),
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
    pub fn config(&self) -> &ResolverConfig {
        &self.config
    }

    /// Change the configuration between steps.
    ///
    /// # Errors
    /// A [`ResolverConfigError`] naming the first invalid field; the old
    /// configuration stays in force.
    pub fn set_config(&mut self, config: ResolverConfig) -> Result<(), ResolverConfigError> {
        config.validate()?;
        self.config = config;
        Ok(())
    }

    /// Mark `collider` of `colliders`: its contacts with other marked
    /// colliders (and with fixed or kinematic bodies, see
    /// [`ResolverConfig::fixed_partners`]) follow the law. Marking costs nothing
    /// until the collider's body moves; marking a marked collider again
    /// changes nothing.
    ///
    /// A ball centred on its dynamic body's origin follows the law as a
    /// point (in `Impulse` and `Exact`, replayed at its time of impact).
    /// Whether it is one is read when marking: mark again after changing
    /// the shape. A marked collider of any other shape on a dynamic body
    /// follows the law for rigid bodies (`kimpact::Law::resolve_rigid`) in
    /// every law mode. In `Impulse` and `Exact` its impacts are replayed
    /// at their time of impact along the motion rapier gave the bodies (at
    /// the centroid of the contact patch there, a box rocking on a corner
    /// too); in `Restitution` (and in the others for an impact near the
    /// rest speed) the restitution of its impacts is the law's at
    /// the manifold's contact (the centroid of its solver contacts, which
    /// rapier's solver then takes as one), with the effective mass of both
    /// bodies there, applied by rapier's solver and reported. As a fixed or
    /// kinematic partner any shape follows the law.
    ///
    /// # Errors
    /// [`HandleError::UnknownCollider`] when `collider` is not in
    /// `colliders` (never inserted, removed, stale generation, invalid):
    /// then nothing changes, and no other collider's mark is touched.
    pub fn mark(
        &mut self,
        colliders: &ColliderSet,
        collider: ColliderHandle,
    ) -> Result<(), HandleError> {
        let Some(co) = colliders.get(collider) else {
            return Err(HandleError::UnknownCollider(collider));
        };
        self.marks
            .insert(collider, crate::marks::is_point_collider(co));
        self.joining.marked.push(collider);
        Ok(())
    }

    /// Mark `collider` of `colliders` with its own law parameters
    /// (`material`, combined with its partners' as [`Material`] says);
    /// marking it again replaces its material.
    ///
    /// # Errors
    /// As [`Kimpact::mark`]; nothing changes then.
    pub fn mark_with(
        &mut self,
        colliders: &ColliderSet,
        collider: ColliderHandle,
        material: Material,
    ) -> Result<(), HandleError> {
        self.mark(colliders, collider)?;
        self.marks.set_material(collider, Some(material));
        Ok(())
    }

    /// Change (or, with `None`, remove) the material of marked collider
    /// `collider` between steps.
    ///
    /// # Errors
    /// [`HandleError::NotMarked`] when `collider` is not marked; nothing
    /// changes then.
    pub fn set_material(
        &mut self,
        collider: ColliderHandle,
        material: Option<Material>,
    ) -> Result<(), HandleError> {
        if !self.marks.contains(collider) {
            return Err(HandleError::NotMarked(collider));
        }
        self.marks.set_material(collider, material);
        Ok(())
    }

    /// The material of `collider`, if it is marked with one.
    pub fn material(&self, collider: ColliderHandle) -> Option<Material> {
        self.marks.material(collider).copied()
    }

    /// Unmark `collider`: rapier's own response again from the next step.
    /// Whether it was marked; a handle that is not marked (never marked,
    /// stale, invalid) changes nothing and gives `false`.
    pub fn unmark(&mut self, collider: ColliderHandle) -> bool {
        self.marks.remove(collider)
    }

    /// Whether `collider` is marked (`false` for any handle that is not,
    /// stale or invalid ones included).
    pub fn is_marked(&self, collider: ColliderHandle) -> bool {
        self.marks.contains(collider)
    }

    /// The impacts the law resolved during the last step, in the order they
    /// were applied.
    pub fn events(&self) -> &[ImpactEvent] {
        &self.log.events
    }

    /// Totals since the resolver was built.
    pub fn stats(&self) -> Stats {
        self.log.stats
    }

    /// This resolver's [`Snapshot`]; take it between steps (after
    /// [`Kimpact::after_step`], or [`Kimpact::step`]).
    pub fn snapshot(&self) -> Snapshot {
        Snapshot::save(Saving {
            law: &self.law,
            mode: self.mode,
            config: &self.config,
            marks: &self.marks,
            stats: self.log.stats,
            carried: self.prepare.carried(&self.joining),
        })
    }

    /// The resolver `snapshot` saved, to step on with rapier's world of the
    /// same moment, whose collider set is `colliders`. A marked collider
    /// that is no longer in `colliders` (removed before the snapshot was
    /// taken) is not marked again: its handle can never be valid again.
    ///
    /// # Errors
    /// [`SnapshotError::Format`] for a snapshot of another format than
    /// [`Snapshot::FORMAT`]; [`SnapshotError::Config`] or
    /// [`SnapshotError::Material`] naming an invalid field of one read from
    /// serde data.
    pub fn from_snapshot(
        snapshot: Snapshot,
        colliders: &ColliderSet,
    ) -> Result<Self, SnapshotError> {
        let saved = snapshot.restore(colliders)?;
        let mut kimpact = Self::with_config(saved.law, saved.mode, saved.config)?;
        kimpact.marks = saved.marks;
        (kimpact.prepare, kimpact.joining) = Prepare::from_carried(saved.carried);
        kimpact.log.stats = saved.stats;
        Ok(kimpact)
    }

    /// Step a [`PhysicsWorld`] through kimpact (see [`Kimpact::step`]).
    pub fn step_world(
        &mut self,
        world: &mut PhysicsWorld,
        hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) {
        let (gravity, integration_parameters) = (world.gravity, world.integration_parameters);
        let (pipeline, sets) = StepSets::of_world(world);
        self.step(
            pipeline,
            gravity,
            &integration_parameters,
            sets,
            hooks,
            events,
        );
    }

    /// `PhysicsPipeline::step` through kimpact: the pipeline, gravity and
    /// integration parameters, rapier's sets borrowed together
    /// ([`StepSets`]), and the hooks and event handler. `hooks` are the
    /// user's own hooks (or `&()`); they keep working, chained before
    /// kimpact's. The composition of [`Kimpact::before_step`],
    /// `pipeline.step` with [`Kimpact::hooks`], and [`Kimpact::after_step`].
    pub fn step(
        &mut self,
        pipeline: &mut PhysicsPipeline,
        gravity: Vector,
        integration_parameters: &IntegrationParameters,
        mut sets: StepSets<'_>,
        hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) {
        let prepared = self.before_step(gravity, integration_parameters, &mut sets);
        sets.step_pipeline(
            pipeline,
            gravity,
            integration_parameters,
            &self.hooks(&prepared, hooks),
            events,
        );
        self.after_step(prepared, &mut sets, hooks);
    }

    /// Stage 1 of a step, before `PhysicsPipeline::step`: sets kimpact's
    /// hook flag (`ActiveHooks::MODIFY_SOLVER_CONTACTS`) on the marked
    /// colliders of the bodies that could start an impact this step (and
    /// clears the flags it set last step on others), stores where the
    /// bodies start, and, in `Restitution` mode, notes the bodies too fast
    /// for rapier's contacts (more than a quarter of their size per step), whose
    /// pairs the replay takes after the step. Clears [`Kimpact::events`].
    ///
    /// Takes the same gravity and integration parameters as the step that
    /// follows, and rapier's sets as they are before it. Returns the
    /// [`PreparedStep`] that [`Kimpact::hooks`] and [`Kimpact::after_step`]
    /// take; preparing again before `after_step` starts the step over
    /// (finish it with the newest one).
    pub fn before_step(
        &mut self,
        gravity: Vector,
        integration_parameters: &IntegrationParameters,
        sets: &mut StepSets<'_>,
    ) -> PreparedStep {
        let StepSets {
            islands,
            broad_phase,
            narrow_phase,
            bodies,
            colliders,
            ..
        } = sets;
        let (islands, broad_phase, narrow_phase) = (&**islands, &**broad_phase, &**narrow_phase);
        self.log.events.clear();
        self.log.stats.steps += 1;
        self.candidates.clear();
        *self.guarded.get_mut() = 0;
        let mut frame = StepFrame::new(gravity, integration_parameters, self.config.rest_speed);
        let policy = Policy::new(self.mode, &self.config, &frame);
        if policy.acts() {
            // `prepare` flags every body faster than half the rest speed.
            let threshold = 0.5 * frame.rest_speed;
            frame.shared =
                free_fall_velocity(islands, bodies, colliders, frame.gravity_dt(), threshold);
        }
        let input = PrepareInput {
            islands,
            bodies,
            broad_phase,
            narrow_phase,
            frame,
            marks: &self.marks,
            policy,
            fixed_partners: self.config.fixed_partners,
            calm_neighbourhoods: self.config.calm_neighbourhoods,
            keep_moving_awake: self.config.keep_moving_awake,
        };
        let spare = std::mem::take(&mut self.spare);
        let prepared = self.prepare.run(
            &input,
            colliders,
            &mut self.joining,
            &mut self.touches,
            spare,
        );
        self.log.stats.calm_bodies += prepared.calm_bodies;
        prepared.wake_moving(bodies);
        self.rigid_replay
            .begin(policy, &prepared.rigid, bodies, colliders);
        PreparedStep {
            frame,
            policy,
            prepared,
        }
    }

    /// Stage 2: the [`PhysicsHooks`] to pass to `PhysicsPipeline::step`
    /// for the step `prepared` ([`Kimpact::before_step`]'s), before
    /// [`Kimpact::after_step`] finishes it. `user` are the user's own hooks
    /// (or `&()`), chained before kimpact's: their filters decide every
    /// pair, and their `modify_solver_contacts` runs for the pairs whose
    /// colliders carry the user's own hook flag.
    ///
    /// It takes `&self` (the hook appends to a mutex-guarded list), so it
    /// can be built from a shared borrow inside the step, on several
    /// threads with rapier's `parallel` feature.
    pub fn hooks<'a>(
        &'a self,
        prepared: &PreparedStep,
        user: &'a dyn PhysicsHooks,
    ) -> StepHooks<'a> {
        StepHooks {
            law: &self.law,
            frame: prepared.frame,
            policy: prepared.policy,
            marks: &self.marks,
            prepare: &self.prepare,
            touches: &self.touches,
            epoch: prepared.prepared.epoch,
            candidates: &self.candidates,
            claims: &self.rigid_replay.claims,
            guarded: &self.guarded,
            user,
        }
    }

    /// Stage 3, after `PhysicsPipeline::step`: the replay of the step's
    /// impacts in time order (positions and velocities of the bodies it
    /// bends are written into `bodies`): every impact governed by the point
    /// law in `Impulse` and `Exact` mode, those of the bodies too fast for
    /// rapier's contacts in `Restitution` mode; then, in `Impulse` and
    /// `Exact` mode, the rigid bodies' impacts (the rigid replay, with
    /// rotation); and the report of the impacts rapier's solver bounced with
    /// the law's restitution (restitution mode's rigid bodies and slow
    /// balls, the rigid contacts the other modes leave to it). Fills
    /// [`Kimpact::events`] and [`Kimpact::stats`].
    ///
    /// Takes rapier's sets as its step left them, and the user's hooks
    /// (`hooks`, or `&()`) given to [`Kimpact::hooks`]: they and the joints
    /// decide whether a pair kimpact's sweeps find may touch, as they do
    /// for rapier's narrow phase.
    pub fn after_step(
        &mut self,
        prepared: PreparedStep,
        sets: &mut StepSets<'_>,
        hooks: &dyn PhysicsHooks,
    ) {
        let PreparedStep {
            frame,
            policy,
            prepared,
        } = prepared;
        let guarded = self.guarded.swap(0, Ordering::Relaxed);
        if guarded > 0 {
            log::warn!(
                "kimpact: {guarded} contact(s) of bodies with non-finite velocity or mass were cut off"
            );
            self.log.stats.skipped_non_finite += guarded;
        }
        self.candidates.collect();
        if policy.acts() {
            let filter = PairFilter::new(sets.impulse_joints, sets.multibody_joints, hooks);
            let sets = ReplaySets {
                bodies: sets.bodies,
                colliders: sets.colliders,
                narrow_phase: sets.narrow_phase,
                broad_phase: sets.broad_phase,
            };
            self.replay_step(frame, policy, &prepared, sets, filter);
        }
        self.spare = prepared;
    }

    /// Stage 3's work in a law mode: the report of the impacts rapier's
    /// solver bounced, then the replays.
    fn replay_step(
        &mut self,
        frame: StepFrame,
        policy: Policy,
        prepared: &Prepared,
        mut sets: ReplaySets,
        filter: PairFilter,
    ) {
        // The impacts rapier's solver bounced with the law's restitution:
        // every mode's rigid bodies, restitution mode's slow balls.
        self.report_by_solver(sets.narrow_phase);
        // The colliders the replay sweeps: restitution mode's fast bodies'
        // (when there are none, every impact was rapier's solver's), every
        // flagged one in the others.
        let swept = match policy.response {
            Response::SolverAndFastReplay if prepared.swept.is_empty() => return,
            Response::SolverAndFastReplay => &prepared.swept,
            Response::Replay | Response::Rapier => &prepared.flagged,
        };
        let input = ReplayInput {
            law: &self.law,
            policy,
            config: &self.config,
            marks: &self.marks,
            flagged: swept,
            starts: &prepared.starts,
            candidates: self.candidates.sorted(),
            frame,
            filter,
        };
        let mut out = ReplayOutput {
            log: &mut self.log,
            woken: &mut self.joining.woken,
        };
        self.replay.run(&input, sets.reborrow(), &mut out);
        if policy.replays_rigid() {
            let input = RigidInput {
                law: &self.law,
                config: &self.config,
                marks: &self.marks,
                rigid: &prepared.rigid,
                starts: &prepared.starts,
                frame,
                filter,
                policy,
            };
            self.rigid_replay.run(&input, &mut out, sets);
        }
    }

    /// The pairs rapier's solver bounced with the law's restitution (in
    /// every law mode those of a marked collider of another shape than a
    /// centred ball on a dynamic body, in restitution mode also the slow
    /// balls'): report the law's outcome for the velocities it saw at
    /// detection, for each pair whose contact carried an impulse this step.
    ///
    /// The impulses are read from the manifolds rapier's solver solved
    /// (`ContactPair::solver_manifolds`): where rapier clusters a composite
    /// shape's manifolds (`IntegrationParameters::contact_clustering`, a
    /// trimesh in 3D) the solver's impulses are in the clusters, and the
    /// per-triangle manifolds keep none.
    fn report_by_solver(&mut self, narrow_phase: &NarrowPhase) {
        for c in self.candidates.sorted() {
            if c.applied_by == AppliedBy::Replay {
                continue;
            }
            let bounced = narrow_phase
                .contact_pair(c.collider1, c.collider2)
                .is_some_and(|cp| {
                    cp.solver_manifolds()
                        .iter()
                        .any(|m| m.points.iter().any(|p| p.data.impulse > 0.0))
                });
            if !bounced {
                continue;
            }
            if let Some(impact) = &c.rigid {
                let outcome = Outcome::from(impact);
                self.log
                    .push(c.colliders(), 0.0, c.point, outcome, AppliedBy::Solver);
                continue;
            }
            let (Ok(b1), Ok(b2)) = (c.start1.checked(), c.start2.checked()) else {
                self.log.skip(c.colliders());
                continue;
            };
            let law = self.marks.law(&self.law, c.collider1, c.collider2);
            if let Some(impact) = law.resolve_unit(&b1, &b2, &to_law(c.normal)) {
                let outcome = Outcome::from(&impact);
                self.log
                    .push(c.colliders(), 0.0, c.point, outcome, AppliedBy::Solver);
            }
        }
    }
}

#[cfg(test)]
mod sweep_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DIM;
    use crate::test_rng::TestRng;

    /// The graze test's crowding, which the hook records for the colliders
    /// flagged in the last step too, says what the narrow phase says
    /// (`ContactPair::has_any_active_contact`) for every collider flagged in
    /// every step of a pit whose balls land on a floor and on each other
    /// (restitution mode, rapier's default activation).
    #[test]
    fn the_hook_s_record_of_touching_colliders_matches_the_narrow_phase() {
        let mut world = PhysicsWorld::default();
        let law = Law::from_restitution(0.5, 0.5).expect("valid restitutions");
        let mut kimpact = Kimpact::new(law, Mode::Restitution);
        let floor = world.bodies.insert(RigidBodyBuilder::fixed());
        #[cfg(feature = "dim2")]
        let shape = ColliderBuilder::cuboid(6.0, 0.5);
        #[cfg(feature = "dim3")]
        let shape = ColliderBuilder::cuboid(6.0, 0.5, 6.0);
        world
            .colliders
            .insert_with_parent(shape, floor, &mut world.bodies);
        let mut rng = TestRng::new(11);
        let count = if DIM == 2 { 60 } else { 120 };
        for _ in 0..count {
            let mut p = Vector::ZERO;
            for k in 0..DIM {
                p[k] = 10.0 * rng.next() - 5.0;
            }
            p[1] = 1.5 + 12.0 * rng.next();
            let body = world
                .bodies
                .insert(RigidBodyBuilder::dynamic().translation(p));
            let ball = world.colliders.insert_with_parent(
                ColliderBuilder::ball(0.4),
                body,
                &mut world.bodies,
            );
            kimpact.mark(&world.colliders, ball).expect("inserted");
        }
        let (mut carried_crowded, mut carried_free, mut fresh) = (0, 0, 0);
        for _ in 0..240 {
            // The narrow phase as `before_step` reads it: rapier's last step's.
            let touching: Vec<(ColliderHandle, bool)> = world
                .colliders
                .iter()
                .map(|(ch, _)| {
                    let mut pairs = world.narrow_phase.contact_pairs_with(ch);
                    (ch, pairs.any(|cp| cp.has_any_active_contact()))
                })
                .collect();
            let carried_before: Vec<ColliderHandle> = world
                .colliders
                .iter()
                .map(|(ch, _)| ch)
                .filter(|&ch| kimpact.prepare.is_ours(ch))
                .collect();
            kimpact.step_world(&mut world, &(), &());
            // This step's flags and crowding stay in place until the next.
            for &ch in kimpact.prepare.hooked() {
                let touching = touching
                    .iter()
                    .find_map(|&(c, t)| (c == ch).then_some(t))
                    .expect("the collider was there before the step");
                assert_eq!(kimpact.prepare.is_crowded(ch), touching, "collider {ch:?}");
                match (carried_before.contains(&ch), touching) {
                    (true, true) => carried_crowded += 1,
                    (true, false) => carried_free += 1,
                    (false, _) => fresh += 1,
                }
            }
        }
        // The test saw both answers from the hook's record, and fresh flags.
        assert!(
            carried_crowded > 100,
            "{carried_crowded} carried and crowded"
        );
        assert!(carried_free > 100, "{carried_free} carried and free");
        assert!(fresh > 0);
    }
}
