//! The plugin: how it sets up bevy_rapier with kimpact's step.

use std::marker::PhantomData;

use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::ecs::system::{System, SystemParamItem};
use bevy::platform::collections::HashSet;
use bevy::prelude::*;

use crate::bevy_rapier::pipeline::{BevyPhysicsHooks, CollisionEvent};
use crate::bevy_rapier::plugin::{PhysicsSet, RapierPhysicsPlugin, systems};
use crate::components::{ImpactMessage, KimpactSettings};
use crate::kimpact_rapier::{Kimpact, Law, Mode, ResolverConfig};
use crate::state::KimpactState;
use crate::systems::{mirror_quarantine, prepare, step, unmark_removed};

/// The plugin's systems, for ordering your own around them.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KimpactSet {
    /// Marks and unmarks colliders and applies [`KimpactSettings`] (after
    /// [`PhysicsSet::SyncBackend`], before [`PhysicsSet::StepSimulation`]).
    BeforeStep,
    /// kimpact's step system, in [`PhysicsSet::StepSimulation`] in place
    /// of bevy_rapier's: it steps every rapier context as bevy_rapier
    /// would, running kimpact's stages around each step of the governed
    /// one, and sends the [`ImpactMessage`]s.
    Step,
}

/// Configures the bevy_rapier plugin [`KimpactPlugin`] adds.
type ConfigureRapier<H> =
    Box<dyn Fn(RapierPhysicsPlugin<H>) -> RapierPhysicsPlugin<H> + Send + Sync>;

/// kimpact for bevy_rapier, in place of `RapierPhysicsPlugin`: it adds
/// bevy_rapier's plugin itself (with `H`, your own `BevyPhysicsHooks`, `()`
/// without) and steps bevy_rapier's contexts with kimpact's stages around
/// every step (see the crate docs).
///
/// ```no_run
/// # #[cfg(feature = "dim2")] use bevy_kimpact2d as bevy_kimpact;
/// # #[cfg(feature = "dim3")] use bevy_kimpact3d as bevy_kimpact;
/// use bevy::prelude::*;
/// use bevy_kimpact::prelude::*;
///
/// App::new().add_plugins((
///     MinimalPlugins,
///     // RapierPhysicsPlugin::<NoUserData>::default() without kimpact.
///     KimpactPlugin::default(),
/// ));
/// ```
///
/// Your hooks, named once ([`KimpactPlugin::with_hooks`]), and bevy_rapier's
/// settings ([`KimpactPlugin::with_rapier`]):
///
/// ```no_run
/// # #[cfg(feature = "dim2")] use bevy_kimpact2d as bevy_kimpact;
/// # #[cfg(feature = "dim3")] use bevy_kimpact3d as bevy_kimpact;
/// use bevy::ecs::system::SystemParam;
/// use bevy::prelude::*;
/// use bevy_kimpact::bevy_rapier::prelude::*;
/// use bevy_kimpact::prelude::*;
///
/// #[derive(Component)]
/// struct Ghost;
///
/// /// Ghosts touch nothing.
/// #[derive(SystemParam)]
/// struct GhostHooks<'w, 's> {
///     ghosts: Query<'w, 's, (), With<Ghost>>,
/// }
///
/// impl BevyPhysicsHooks for GhostHooks<'_, '_> {
///     fn filter_contact_pair(&self, context: PairFilterContextView) -> Option<SolverFlags> {
///         let ghost = |e| self.ghosts.contains(e);
///         if ghost(context.collider1()) || ghost(context.collider2()) {
///             None
///         } else {
///             Some(SolverFlags::COMPUTE_RIGID_IMPULSES)
///         }
///     }
/// }
///
/// App::new().add_plugins((
///     MinimalPlugins,
///     // RapierPhysicsPlugin::<GhostHooks>::default().with_length_unit(100.0).in_fixed_schedule()
///     KimpactPlugin::default()
///         .with_hooks::<GhostHooks>()
///         .with_rapier(|rapier| rapier.with_length_unit(100.0))
///         .in_fixed_schedule(),
/// ));
/// ```
pub struct KimpactPlugin<H = ()> {
    schedule: Interned<dyn ScheduleLabel>,
    config: ResolverConfig,
    rapier: Option<ConfigureRapier<H>>,
    hooks: PhantomData<fn() -> H>,
}

impl<H> std::fmt::Debug for KimpactPlugin<H> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KimpactPlugin")
            .field("schedule", &self.schedule)
            .field("config", &self.config)
            .field("configures_rapier", &self.rapier.is_some())
            .field("hooks", &std::any::type_name::<H>())
            .finish()
    }
}

impl Default for KimpactPlugin {
    fn default() -> Self {
        Self {
            schedule: PostUpdate.intern(),
            config: ResolverConfig::default(),
            rapier: None,
            hooks: PhantomData,
        }
    }
}

impl<H> KimpactPlugin<H>
where
    H: BevyPhysicsHooks + 'static,
    for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
{
    /// With your own `BevyPhysicsHooks` `U` (the `U` of
    /// `RapierPhysicsPlugin::<U>`, written once): they decide every pair's
    /// filters (also for kimpact's sweeps, as rapier's narrow phase asks
    /// them), and their `modify_solver_contacts` runs for the colliders you
    /// flag with `ActiveHooks::MODIFY_SOLVER_CONTACTS`, before kimpact's
    /// own. Drops a [`KimpactPlugin::with_rapier`] set before.
    pub fn with_hooks<U>(self) -> KimpactPlugin<U>
    where
        U: BevyPhysicsHooks + 'static,
        for<'w, 's> SystemParamItem<'w, 's, U>: BevyPhysicsHooks,
    {
        KimpactPlugin {
            schedule: self.schedule,
            config: self.config,
            rapier: None,
            hooks: PhantomData,
        }
    }

    /// Configures the `RapierPhysicsPlugin` this plugin adds (its length
    /// unit, its context initialization, …): `configure` gets
    /// `RapierPhysicsPlugin::default()` and returns it configured. Its
    /// schedule is this plugin's ([`KimpactPlugin::in_schedule`]), and its
    /// step system is kimpact's: what `configure` sets for those is
    /// replaced.
    pub fn with_rapier(
        mut self,
        configure: impl Fn(RapierPhysicsPlugin<H>) -> RapierPhysicsPlugin<H> + Send + Sync + 'static,
    ) -> Self {
        self.rapier = Some(Box::new(configure));
        self
    }

    /// Run in `FixedUpdate`, with bevy_rapier (`RapierPhysicsPlugin::in_fixed_schedule`).
    pub fn in_fixed_schedule(self) -> Self {
        self.in_schedule(FixedUpdate)
    }

    /// Run in `schedule`, with bevy_rapier (default `PostUpdate`, as
    /// bevy_rapier's).
    pub fn in_schedule(mut self, schedule: impl ScheduleLabel) -> Self {
        self.schedule = schedule.intern();
        self
    }

    /// kimpact's tuning of the hand-over to rapier (rest speed, fixed
    /// partners, event cap); the default suits most scenes. An invalid
    /// configuration is logged and the default used.
    pub fn with_config(mut self, config: ResolverConfig) -> Self {
        self.config = config;
        self
    }
}

impl<H> Plugin for KimpactPlugin<H>
where
    H: BevyPhysicsHooks + 'static,
    for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
{
    fn build(&self, app: &mut App) {
        app.add_message::<ImpactMessage>()
            .init_resource::<KimpactSettings>();
        // bevy_rapier's plugin inserts its collision messages: one is here
        // already, with its own step system.
        let rapier_before = app.world().contains_resource::<Messages<CollisionEvent>>();
        if rapier_before || app.world().contains_resource::<KimpactState>() {
            log::error!(
                "kimpact: a RapierPhysicsPlugin (or another KimpactPlugin) was added before KimpactPlugin, which adds bevy_rapier's plugin itself; remove it (configure bevy_rapier with KimpactPlugin::with_rapier). kimpact stands aside"
            );
            if !app.world().contains_resource::<KimpactState>() {
                let mut state = KimpactState::new(Kimpact::new(Law::elastic(), Mode::Exact));
                state.standing_aside = true;
                app.insert_resource(state);
            }
            return;
        }
        let kimpact = Kimpact::with_config(Law::elastic(), Mode::Exact, self.config)
            .unwrap_or_else(|e| {
                log::error!("kimpact: invalid configuration ({e}); using the default");
                Kimpact::new(Law::elastic(), Mode::Exact)
            });
        app.insert_resource(KimpactState::new(kimpact));

        let rapier = RapierPhysicsPlugin::<H>::default();
        let rapier = match &self.rapier {
            Some(configure) => configure(rapier),
            None => rapier,
        };
        // bevy_rapier's own systems but its step, which is kimpact's.
        app.add_plugins(rapier.in_schedule(self.schedule).with_physics_sets_systems(
            HashSet::from_iter([PhysicsSet::SyncBackend, PhysicsSet::Writeback]),
        ));
        app.configure_sets(
            self.schedule,
            (
                KimpactSet::BeforeStep
                    .after(PhysicsSet::SyncBackend)
                    .before(PhysicsSet::StepSimulation),
                KimpactSet::Step.in_set(PhysicsSet::StepSimulation),
            ),
        )
        .add_systems(
            self.schedule,
            (
                prepare.in_set(KimpactSet::BeforeStep),
                (step::<H>, mirror_quarantine)
                    .chain()
                    .in_set(KimpactSet::Step),
            ),
        )
        // Every frame, whatever the physics schedule: removals are kept
        // only two frames, and a fixed schedule may not run for longer.
        .add_systems(PostUpdate, unmark_removed.before(KimpactSet::BeforeStep));
    }

    fn finish(&self, app: &mut App) {
        // bevy_rapier's own step system, added since (by a
        // RapierPhysicsPlugin added after this one, or by hand): it steps
        // the contexts on its own, kimpact must not step them again.
        let theirs = [
            IntoSystem::into_system(systems::step_simulation::<H>).system_type(),
            IntoSystem::into_system(systems::step_simulation::<()>).system_type(),
        ];
        let found = app
            .world()
            .get_resource::<Schedules>()
            .is_some_and(|schedules| {
                schedules.iter().any(|(_, schedule)| {
                    schedule
                        .graph()
                        .systems
                        .iter()
                        .any(|(_, system, _)| theirs.contains(&system.system_type()))
                })
            });
        if found && let Some(mut state) = app.world_mut().get_resource_mut::<KimpactState>() {
            log::error!(
                "kimpact: bevy_rapier's own step system runs beside KimpactPlugin (a RapierPhysicsPlugin added after it?); KimpactPlugin adds bevy_rapier's plugin itself: remove yours (configure bevy_rapier with KimpactPlugin::with_rapier). kimpact stands aside"
            );
            state.standing_aside = true;
        }
    }
}
