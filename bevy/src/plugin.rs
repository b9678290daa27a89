//! The plugin: its component, settings, message, and the systems around
//! bevy_rapier's step.

use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::ecs::system::{StaticSystemParam, SystemParamItem};
use bevy::prelude::*;

use crate::bevy_rapier::pipeline::BevyPhysicsHooks;
use crate::bevy_rapier::plugin::context::{
    RapierContextColliders, RapierContextEntityLink, RapierContextJoints, RapierContextSimulation,
    RapierRigidBodySet, SimulationToRenderTime,
};
use crate::bevy_rapier::plugin::{
    DefaultRapierContext, PhysicsSet, RapierConfiguration, SimulationMode, TimestepMode,
};
use crate::bevy_rapier::prelude::RapierColliderHandle;
use crate::hooks::UserHooks;
use crate::kimpact_rapier::math::Real;
use crate::kimpact_rapier::{Config, ImpactEvent, Kimpact, Law, LawParams, Material, Mode};
use crate::state::{KimpactState, PreparedStep};
use crate::steps::planned_steps;

/// Marks the collider of its entity for kimpact: the collider's contacts with
/// other marked colliders (and with fixed and kinematic bodies, see
/// [`Config::fixed_partners`]) follow the law. Put it beside bevy_rapier's
/// `Collider`; removing it, or despawning the entity, unmarks the collider.
///
/// `KimpactCollider::default()` follows the law of [`KimpactSettings`];
/// [`KimpactCollider::with_material`] gives the collider a [`Material`] of
/// its own (combined with a partner's as [`Material`] says). Changing the
/// component changes the collider's material from the next step.
#[derive(Component, Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct KimpactCollider {
    /// The collider's own law parameters (`None`: the settings' law).
    pub material: Option<Material>,
}

impl KimpactCollider {
    /// A marker following the law of [`KimpactSettings`] (the same as
    /// `default()`).
    pub const fn new() -> Self {
        Self { material: None }
    }

    /// A marker with the collider's own `material`.
    pub const fn with_material(material: Material) -> Self {
        Self {
            material: Some(material),
        }
    }
}

/// The mode and the law, a resource read before every step: change it at any
/// time, the next step uses it. An invalid law (a negative or non-finite
/// dissipation) is logged and not applied: the last valid one stays in force
/// (see [`KimpactState::law`]).
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct KimpactSettings {
    /// How kimpact takes part in the step (default [`Mode::Exact`]).
    pub mode: Mode,
    /// The law's parameters (default elastic: no dissipation).
    pub law: LawParams<Real>,
}

impl Default for KimpactSettings {
    fn default() -> Self {
        Self {
            mode: Mode::Exact,
            law: LawParams::default(),
        }
    }
}

/// One impact the law resolved, with the entities involved: sent after the
/// step it happened in (read it with `MessageReader<ImpactMessage>`).
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct ImpactMessage {
    /// The entity of the first collider (the normal points away from it).
    pub collider1: Entity,
    /// The entity of the second collider (the normal points towards it).
    pub collider2: Entity,
    /// The entity of the first collider's rigid body (`None` for a collider
    /// without one).
    pub body1: Option<Entity>,
    /// The entity of the second collider's rigid body.
    pub body2: Option<Entity>,
    /// The impact: time within the step, point, normal, impulse, approach
    /// speed, restitution, energy dissipated (its collider handles are
    /// rapier's).
    pub impact: ImpactEvent,
}

/// The plugin's systems, for ordering your own around them.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KimpactSet {
    /// Marks and unmarks colliders, applies [`KimpactSettings`], runs
    /// kimpact's stage before the step (after [`PhysicsSet::SyncBackend`]).
    BeforeStep,
    /// Runs kimpact's stage after the step (after
    /// [`PhysicsSet::StepSimulation`], before [`PhysicsSet::Writeback`]) and
    /// sends the [`ImpactMessage`]s.
    AfterStep,
}

/// kimpact for bevy_rapier: add it beside `RapierPhysicsPlugin::<KimpactHooks>`
/// (see the crate docs), in the same schedule.
pub struct KimpactPlugin {
    schedule: Interned<dyn ScheduleLabel>,
    config: Config,
    /// Adds the stage systems, for the user's hooks (`with_hooks`).
    systems: fn(&mut App, Interned<dyn ScheduleLabel>),
}

impl Default for KimpactPlugin {
    fn default() -> Self {
        Self {
            schedule: PostUpdate.intern(),
            config: Config::default(),
            systems: add_stage_systems::<()>,
        }
    }
}

impl KimpactPlugin {
    /// Your own `BevyPhysicsHooks` `H`, the same as in
    /// [`KimpactHooks<H>`](crate::KimpactHooks): kimpact's sweeps ask their
    /// `filter_contact_pair` whether a pair they find may touch, as rapier's
    /// narrow phase does.
    pub fn with_hooks<H>(mut self) -> Self
    where
        H: BevyPhysicsHooks + 'static,
        for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
    {
        self.systems = add_stage_systems::<H>;
        self
    }

    /// Run in `FixedUpdate`, as `RapierPhysicsPlugin::in_fixed_schedule` does.
    pub fn in_fixed_schedule(self) -> Self {
        self.in_schedule(FixedUpdate)
    }

    /// Run in `schedule`: the one bevy_rapier's systems run in (default
    /// `PostUpdate`, as bevy_rapier's).
    pub fn in_schedule(mut self, schedule: impl ScheduleLabel) -> Self {
        self.schedule = schedule.intern();
        self
    }

    /// kimpact's tuning of the hand-over to rapier (rest speed, fixed
    /// partners, event cap); the default suits most scenes. An invalid
    /// configuration is logged and the default used.
    pub fn with_config(mut self, config: Config) -> Self {
        self.config = config;
        self
    }
}

impl Plugin for KimpactPlugin {
    fn build(&self, app: &mut App) {
        let kimpact = Kimpact::with_config(Law::elastic(), Mode::Exact, self.config)
            .unwrap_or_else(|e| {
                log::error!("kimpact: invalid configuration ({e}); using the default");
                Kimpact::new(Law::elastic(), Mode::Exact)
            });
        app.add_message::<ImpactMessage>()
            .init_resource::<KimpactSettings>()
            .insert_resource(KimpactState::new(kimpact))
            .configure_sets(
                self.schedule,
                (
                    KimpactSet::BeforeStep
                        .after(PhysicsSet::SyncBackend)
                        .before(PhysicsSet::StepSimulation),
                    KimpactSet::AfterStep
                        .after(PhysicsSet::StepSimulation)
                        .before(PhysicsSet::Writeback),
                ),
            )
            // Every frame, whatever the physics schedule: removals are kept
            // only two frames, and a fixed schedule may not run for longer.
            .add_systems(PostUpdate, unmark_removed.before(KimpactSet::BeforeStep));
        (self.systems)(app, self.schedule);
    }
}

fn add_stage_systems<H>(app: &mut App, schedule: Interned<dyn ScheduleLabel>)
where
    H: BevyPhysicsHooks + 'static,
    for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
{
    app.add_systems(
        schedule,
        (
            before_step::<H>.in_set(KimpactSet::BeforeStep),
            after_step::<H>.in_set(KimpactSet::AfterStep),
        ),
    );
}

/// The context entities kimpact may govern, with what its stages need.
type Contexts<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static mut RapierContextSimulation,
        &'static mut RapierContextColliders,
        &'static mut RapierRigidBodySet,
        &'static RapierContextJoints,
        &'static RapierConfiguration,
        Option<&'static SimulationToRenderTime>,
        Has<DefaultRapierContext>,
    ),
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

/// The governed context: the default one, else the only one.
fn governed(contexts: &Contexts, state: &mut KimpactState) -> Option<Entity> {
    let mut only = None;
    let mut count = 0usize;
    for (entity, .., is_default) in contexts.iter() {
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
fn unmark_removed(
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

/// Before bevy_rapier's step: marks, settings, kimpact's first stage.
#[allow(clippy::too_many_arguments)]
fn before_step<H>(
    mut state: ResMut<KimpactState>,
    hooks: StaticSystemParam<H>,
    settings: Res<KimpactSettings>,
    timestep: Option<Res<TimestepMode>>,
    time: Res<Time>,
    mut contexts: Contexts,
    new_marks: NewMarks,
) where
    H: BevyPhysicsHooks + 'static,
    for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
{
    let state = &mut *state;
    // A step prepared but never finished (its context went away): restore
    // the mode it overrode.
    if let Some(PreparedStep {
        restore: Some(mode),
        ..
    }) = state.step.take()
    {
        state.kimpact.set_mode(mode);
    }
    if settings.is_changed() || state.applied.is_none() {
        apply_settings(state, &settings);
    }
    let Some(context) = governed(&contexts, state) else {
        return;
    };
    let Ok((_, simulation, mut colliders, mut bodies, joints, config, to_render, _)) =
        contexts.get_mut(context)
    else {
        return;
    };
    let simulation_tick = simulation.last_changed();
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
    let Some(timestep) = timestep else {
        return;
    };
    if !config.physics_pipeline_active {
        return;
    }
    let planned = planned_steps(
        *timestep,
        simulation.integration_parameters,
        &time,
        to_render.map_or(0.0, |t| t.diff),
    );
    if planned.count == 0 {
        return;
    }
    // kimpact's stages bracket one pipeline step: a frame of several (or a
    // collision-only one) runs rapier's own response.
    let restore = if planned.count > 1 || config.simulation_mode != SimulationMode::Full {
        if !state.warned.several_steps {
            state.warned.several_steps = true;
            log::warn!(
                "kimpact: bevy_rapier runs {} step(s) in this frame ({:?}, {:?}); kimpact takes part in frames of one full step, so these run rapier's own response",
                planned.count,
                *timestep,
                config.simulation_mode
            );
        }
        let mode = state.kimpact.mode();
        state.kimpact.set_mode(Mode::Native);
        Some(mode)
    } else {
        None
    };
    // Read only: its change tick tells the after system whether
    // bevy_rapier's step (which changes it) ran in between.
    let simulation: &RapierContextSimulation = &simulation;
    state.kimpact.before_step(
        config.gravity,
        &planned.parameters,
        &simulation.islands,
        &simulation.broad_phase,
        &simulation.narrow_phase,
        &mut bodies.bodies,
        &mut colliders.colliders,
        &joints.impulse_joints,
        &joints.multibody_joints,
        &UserHooks(&*hooks),
    );
    state.step = Some(PreparedStep {
        context,
        steps: planned.count,
        restore,
        simulation_tick,
    });
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

/// After bevy_rapier's step: kimpact's last stage, and the messages.
fn after_step<H>(
    mut state: ResMut<KimpactState>,
    hooks: StaticSystemParam<H>,
    mut contexts: Contexts,
    mut messages: MessageWriter<ImpactMessage>,
) where
    H: BevyPhysicsHooks + 'static,
    for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
{
    let state = &mut *state;
    let Some(step) = state.step.take() else {
        return;
    };
    let Ok((_, simulation, colliders, mut bodies, joints, ..)) = contexts.get_mut(step.context)
    else {
        if let Some(mode) = step.restore {
            state.kimpact.set_mode(mode);
        }
        return;
    };
    let stepped = simulation.last_changed() != step.simulation_tick;
    let ran = if stepped {
        simulation.step_stats().num_steps
    } else {
        0
    };
    if ran != step.steps && !state.warned.step_mismatch {
        state.warned.step_mismatch = true;
        log::warn!(
            "kimpact: bevy_rapier ran {ran} step(s) where kimpact expected {}; run KimpactPlugin in the schedule of RapierPhysicsPlugin, with RapierPhysicsPlugin::<KimpactHooks>",
            step.steps
        );
    }
    if let Err(e) = state.kimpact.after_step(
        &simulation.narrow_phase,
        &simulation.broad_phase,
        &mut bodies.bodies,
        &colliders.colliders,
        &joints.impulse_joints,
        &joints.multibody_joints,
        &UserHooks(&*hooks),
    ) {
        log::debug!("kimpact: {e}");
    }
    if let Some(mode) = step.restore {
        state.kimpact.set_mode(mode);
        return;
    }
    let entity = |h| colliders.collider_entity(h);
    let body = |h| {
        colliders
            .colliders
            .get(h)
            .and_then(|co| co.parent())
            .and_then(|b| bodies.rigid_body_entity(b))
    };
    messages.write_batch(state.kimpact.events().iter().filter_map(|impact| {
        Some(ImpactMessage {
            collider1: entity(impact.collider1)?,
            collider2: entity(impact.collider2)?,
            body1: body(impact.collider1),
            body2: body(impact.collider2),
            impact: *impact,
        })
    }));
}
