//! The plugin's systems: marks and settings before the step, and the step
//! system that runs in place of bevy_rapier's, with kimpact's stages
//! around every pipeline step of the governed context.

use bevy::ecs::system::{StaticSystemParam, SystemParam, SystemParamItem};
use bevy::prelude::*;

use crate::bevy_rapier::dynamics::{
    RapierRigidBodyHandle, RigidBodyDisabled, SoftBodyDisabled, TransformInterpolation,
};
use crate::bevy_rapier::geometry::ColliderDisabled;
use crate::bevy_rapier::pipeline::{
    BevyPhysicsHooks, CollisionEvent, ContactForceEvent, PhysicsQuarantineEvent,
};
use crate::bevy_rapier::plugin::context::{
    RapierContextColliders, RapierContextEntityLink, RapierContextJoints, RapierContextSimulation,
    RapierRigidBodySet, SimulationToRenderTime,
};
use crate::bevy_rapier::plugin::{
    DefaultRapierContext, RapierConfiguration, SimulationMode, TimestepMode,
};
use crate::bevy_rapier::prelude::RapierColliderHandle;
use crate::components::{ImpactMessage, KimpactCollider, KimpactSettings};
use crate::hooks::UserHooks;
use crate::kimpact_rapier::StepSets;
use crate::kimpact_rapier::math::Real;
use crate::kimpact_rapier::rapier::prelude::PhysicsHooks;
use crate::state::KimpactState;
use crate::steps::{MAX_ROUNDS, PlannedSteps, planned_steps};

/// The context entities, with what a step needs (the query of bevy_rapier's
/// step system, and whether a context is the default one).
type Contexts<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static mut RapierContextSimulation,
        &'static mut RapierContextColliders,
        &'static mut RapierContextJoints,
        &'static mut RapierRigidBodySet,
        &'static RapierConfiguration,
        &'static mut SimulationToRenderTime,
        Has<DefaultRapierContext>,
    ),
>;

/// The context entities, for marking.
type ContextColliders<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static RapierContextColliders,
        Has<DefaultRapierContext>,
    ),
    With<RapierContextSimulation>,
>;

/// Marked collider entities whose marker or rapier collider is new or
/// changed.
type NewMarks<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static KimpactCollider,
        &'static RapierColliderHandle,
        Option<&'static RapierContextEntityLink>,
    ),
    Or<(Changed<KimpactCollider>, Changed<RapierColliderHandle>)>,
>;

/// The bodies bevy_rapier interpolates (`TimestepMode::Interpolated`).
type Interpolated<'w, 's> = Query<
    'w,
    's,
    (
        &'static RapierRigidBodyHandle,
        &'static mut TransformInterpolation,
    ),
>;

/// The governed context: the default one, else the only one.
fn governed(
    contexts: impl Iterator<Item = (Entity, bool)>,
    state: &mut KimpactState,
) -> Option<Entity> {
    let mut only = None;
    let mut count = 0usize;
    for (entity, is_default) in contexts {
        if is_default {
            return Some(entity);
        }
        only = Some(entity);
        count += 1;
    }
    if count > 1 {
        if !state.warned.several_contexts {
            state.warned.several_contexts = true;
            log::warn!(
                "kimpact: several rapier contexts and none is the DefaultRapierContext; kimpact governs none"
            );
        }
        return None;
    }
    only
}

/// Unmark the colliders whose entity lost its [`KimpactCollider`] or its
/// rapier collider (removed or despawned).
pub(crate) fn unmark_removed(
    mut state: ResMut<KimpactState>,
    mut removed_markers: RemovedComponents<KimpactCollider>,
    mut removed_handles: RemovedComponents<RapierColliderHandle>,
    current: Query<&RapierColliderHandle, With<KimpactCollider>>,
) {
    for entity in removed_markers.read().chain(removed_handles.read()) {
        let Some(old) = state.marks.handle(entity) else {
            continue;
        };
        // Removed and inserted again since: still marked.
        if current.get(entity).is_ok_and(|h| h.0 == old) {
            continue;
        }
        state.unmark(entity);
    }
}

/// Before the step: the settings, and the new or changed marks.
pub(crate) fn prepare(
    mut state: ResMut<KimpactState>,
    settings: Res<KimpactSettings>,
    contexts: ContextColliders,
    new_marks: NewMarks,
) {
    let state = &mut *state;
    if state.standing_aside {
        return;
    }
    if settings.is_changed() || state.applied.is_none() {
        apply_settings(state, &settings);
    }
    let Some(context) = governed(contexts.iter().map(|(e, _, d)| (e, d)), state) else {
        return;
    };
    let Ok((_, colliders, _)) = contexts.get(context) else {
        return;
    };
    for (entity, marker, handle, link) in &new_marks {
        if link.is_some_and(|l| l.0 != context) {
            if !state.warned.other_context {
                state.warned.other_context = true;
                log::warn!(
                    "kimpact: {entity} has a KimpactCollider in a rapier context kimpact does not govern; it is left to rapier"
                );
            }
            state.unmark(entity);
            continue;
        }
        state.mark(&colliders.colliders, entity, handle.0, marker.material);
    }
}

fn apply_settings(state: &mut KimpactState, settings: &KimpactSettings) {
    let applied = (settings.mode, settings.law);
    if state.applied == Some(applied) {
        return;
    }
    state.kimpact.set_mode(settings.mode);
    match state.kimpact.set_law(settings.law) {
        Ok(()) => state.applied = Some(applied),
        Err(e) => {
            log::error!(
                "kimpact: the law of KimpactSettings is invalid ({e}); the last valid law stays in force"
            );
            state.applied = Some((settings.mode, state.kimpact.law().params()));
        }
    }
}

/// The messages one step sends: bevy_rapier's and kimpact's impacts.
#[derive(SystemParam)]
pub(crate) struct StepMessages<'w> {
    collision_events: MessageWriter<'w, CollisionEvent>,
    contact_force_events: MessageWriter<'w, ContactForceEvent>,
    quarantine_events: MessageWriter<'w, PhysicsQuarantineEvent>,
    impacts: MessageWriter<'w, ImpactMessage>,
}

/// bevy_rapier's step system, with kimpact's stages around each pipeline
/// step of the governed context: the same steps, events and bookkeeping as
/// `bevy_rapier::plugin::systems::step_simulation`, which it replaces. The
/// governed context's frame runs one step at a time (each a one-step
/// `TimestepMode::Fixed` of the frame's step `dt`, bit for bit the step
/// bevy_rapier would run); the others step as bevy_rapier steps them.
pub(crate) fn step<H>(
    mut state: ResMut<KimpactState>,
    hooks: StaticSystemParam<H>,
    timestep: Option<Res<TimestepMode>>,
    time: Res<Time>,
    mut contexts: Contexts,
    mut interpolated: Interpolated,
    mut messages: StepMessages,
) where
    H: BevyPhysicsHooks + 'static,
    for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
{
    let state = &mut *state;
    if state.standing_aside {
        return;
    }
    let Some(timestep) = timestep.map(|t| *t) else {
        if !state.warned.no_timestep {
            state.warned.no_timestep = true;
            log::warn!("kimpact: no TimestepMode resource; nothing steps");
        }
        return;
    };
    let user = UserHooks(&*hooks);
    let governed = governed(contexts.iter().map(|c| (c.0, c.7)), state);
    let StepMessages {
        collision_events,
        contact_force_events,
        quarantine_events,
        impacts,
    } = &mut messages;
    for (entity, mut simulation, mut colliders, mut joints, mut bodies, config, mut to_render, _) in
        contexts.iter_mut()
    {
        let mut frame = Frame {
            simulation: &mut simulation,
            colliders: &mut colliders,
            joints: &mut joints,
            bodies: &mut bodies,
            config,
            to_render: &mut to_render,
            time: &time,
            collision_events: &mut *collision_events,
            contact_force_events: &mut *contact_force_events,
        };
        if !config.physics_pipeline_active {
            frame
                .bodies
                .propagate_modified_body_positions_to_colliders(frame.colliders);
        } else {
            frame.simulation.set_num_threads(config.num_threads);
            let planned = planned_steps(timestep, &time, frame.to_render.diff);
            if governed != Some(entity) || planned.count == 0 {
                frame.as_rapier(timestep, &user, &mut interpolated);
            } else if config.simulation_mode != SimulationMode::Full {
                if !state.warned.collision_only {
                    state.warned.collision_only = true;
                    log::warn!(
                        "kimpact: the governed rapier context runs collision detection only ({:?}): no contact response, no law",
                        config.simulation_mode
                    );
                }
                frame.as_rapier(timestep, &user, &mut interpolated);
            } else {
                frame.with_kimpact(planned, state, &user, &mut interpolated, impacts);
            }
        }
        frame
            .simulation
            .send_bevy_events(frame.collision_events, frame.contact_force_events);
        frame
            .simulation
            .send_quarantine_events(entity, quarantine_events);
    }
}

/// bevy_rapier's quarantine, mirrored on the entities as its step system
/// does (so that removing the component re-enables them), from the
/// quarantine messages the step sent.
pub(crate) fn mirror_quarantine(
    mut commands: Commands,
    mut quarantined: MessageReader<PhysicsQuarantineEvent>,
) {
    for event in quarantined.read() {
        for &entity in &event.bodies {
            commands.entity(entity).try_insert(RigidBodyDisabled);
        }
        for &entity in &event.colliders {
            commands.entity(entity).try_insert(ColliderDisabled);
        }
        for &entity in &event.soft_bodies {
            commands.entity(entity).try_insert(SoftBodyDisabled);
        }
    }
}

/// One context's frame.
struct Frame<'a, 'c, 'f> {
    simulation: &'a mut RapierContextSimulation,
    colliders: &'a mut RapierContextColliders,
    joints: &'a mut RapierContextJoints,
    bodies: &'a mut RapierRigidBodySet,
    config: &'a RapierConfiguration,
    to_render: &'a mut SimulationToRenderTime,
    time: &'a Time,
    collision_events: &'a mut MessageWriter<'c, CollisionEvent>,
    contact_force_events: &'a mut MessageWriter<'f, ContactForceEvent>,
}

impl Frame<'_, '_, '_> {
    /// The frame as bevy_rapier's step system runs it.
    fn as_rapier(
        &mut self,
        timestep: TimestepMode,
        hooks: &dyn PhysicsHooks,
        interpolated: &mut Interpolated,
    ) {
        self.simulation.step_simulation(
            self.colliders,
            self.joints,
            self.bodies,
            self.config.gravity,
            self.config.simulation_mode,
            timestep,
            Some((&*self.collision_events, &*self.contact_force_events)),
            hooks,
            self.time,
            self.to_render,
            Some(interpolated),
        );
    }

    /// The frame's `planned` steps one by one, each between kimpact's
    /// stages, in the rounds and with the bookkeeping of bevy_rapier's
    /// `RapierContextSimulation::step_simulation`.
    fn with_kimpact<H: BevyPhysicsHooks>(
        &mut self,
        planned: PlannedSteps,
        state: &mut KimpactState,
        user: &UserHooks<H>,
        interpolated: &mut Interpolated,
        impacts: &mut MessageWriter<ImpactMessage>,
    ) {
        match planned.round_dt {
            None => {
                for _ in 0..planned.substeps {
                    self.one_step(planned.step_dt, state, user, impacts);
                }
            }
            Some(dt) => {
                // bevy_rapier's rounds: while the simulation is behind the
                // render, one round of substeps; before the last one, the
                // interpolation's start.
                self.to_render.diff += self.time.delta_secs();
                let mut rounds = 0;
                while self.to_render.diff > 0.0 && rounds < MAX_ROUNDS {
                    if self.to_render.diff - dt <= 0.0 {
                        for (handle, mut interpolation) in interpolated.iter_mut() {
                            if let Some(body) = self.bodies.bodies.get(handle.0) {
                                interpolation.start = Some(*body.position());
                                interpolation.end = None;
                            }
                        }
                    }
                    for _ in 0..planned.substeps {
                        self.one_step(planned.step_dt, state, user, impacts);
                    }
                    self.to_render.diff -= dt;
                    rounds += 1;
                }
            }
        }
        // What bevy_rapier leaves there (each step set it to its own dt).
        self.simulation.integration_parameters.dt = planned.frame_dt;
    }

    /// The context's rapier sets, borrowed together for kimpact's stages.
    fn sets(&mut self) -> StepSets<'_> {
        let simulation = &mut *self.simulation;
        StepSets {
            islands: &mut simulation.islands,
            broad_phase: &mut simulation.broad_phase,
            narrow_phase: &mut simulation.narrow_phase,
            bodies: &mut self.bodies.bodies,
            colliders: &mut self.colliders.colliders,
            impulse_joints: &mut self.joints.impulse_joints,
            multibody_joints: &mut self.joints.multibody_joints,
            soft_bodies: &mut self.bodies.soft_bodies,
            ccd_solver: &mut simulation.ccd_solver,
        }
    }

    /// One pipeline step of `dt` between kimpact's stages; its impacts sent.
    fn one_step<H: BevyPhysicsHooks>(
        &mut self,
        dt: Real,
        state: &mut KimpactState,
        user: &UserHooks<H>,
        impacts: &mut MessageWriter<ImpactMessage>,
    ) {
        let mut parameters = self.simulation.integration_parameters;
        parameters.dt = dt;
        let prepared =
            state
                .kimpact
                .before_step(self.config.gravity, &parameters, &mut self.sets());
        // One step of `dt` (`dt / 1` is `dt`, bit for bit).
        self.simulation.step_simulation(
            self.colliders,
            self.joints,
            self.bodies,
            self.config.gravity,
            SimulationMode::Full,
            TimestepMode::Fixed { dt, substeps: 1 },
            Some((&*self.collision_events, &*self.contact_force_events)),
            &state.kimpact.hooks(&prepared, user),
            self.time,
            self.to_render,
            None,
        );
        // Each step_simulation keeps only its own events: send them now.
        self.simulation
            .send_bevy_events(self.collision_events, self.contact_force_events);
        state.kimpact.after_step(prepared, &mut self.sets(), user);
        let colliders = &*self.colliders;
        let bodies = &*self.bodies;
        let entity = |h| colliders.collider_entity(h);
        let body = |h| {
            colliders
                .colliders
                .get(h)
                .and_then(|co| co.parent())
                .and_then(|b| bodies.rigid_body_entity(b))
        };
        impacts.write_batch(state.kimpact.events().iter().filter_map(|impact| {
            Some(ImpactMessage {
                collider1: entity(impact.collider1)?,
                collider2: entity(impact.collider2)?,
                body1: body(impact.collider1),
                body2: body(impact.collider2),
                impact: *impact,
            })
        }));
    }
}
