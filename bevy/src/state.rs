//! The resolver as a Bevy resource, and which collider entity it marked.

use bevy::platform::collections::HashMap;
use bevy::prelude::{Entity, Resource};

use crate::kimpact_rapier::rapier::prelude::{ColliderHandle, ColliderSet};
use crate::kimpact_rapier::{Kimpact, Law, LawParams, Material, Mode, Stats};

/// kimpact's resolver for the governed rapier context, with the collider
/// entities it marked (a resource the plugin inserts).
///
/// Read it for the totals of the run ([`KimpactState::stats`]) and the mode
/// and law in force; change them through
/// [`KimpactSettings`](crate::KimpactSettings), and mark colliders with
/// [`KimpactCollider`](crate::KimpactCollider).
#[derive(Resource)]
pub struct KimpactState {
    pub(crate) kimpact: Kimpact,
    pub(crate) marks: Marks,
    /// The settings in force (the last valid ones applied).
    pub(crate) applied: Option<(Mode, LawParams<crate::kimpact_rapier::math::Real>)>,
    /// Another step system steps bevy_rapier (found when the app was
    /// finished): kimpact marks nothing and steps nothing.
    pub(crate) standing_aside: bool,
    pub(crate) warned: Warned,
}

/// Warnings given once per run.
#[derive(Copy, Clone, Debug, Default)]
pub(crate) struct Warned {
    pub collision_only: bool,
    pub no_timestep: bool,
    pub other_context: bool,
    pub several_contexts: bool,
}

impl std::fmt::Debug for KimpactState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KimpactState")
            .field("mode", &self.kimpact.mode())
            .field("law", self.kimpact.law())
            .field("stats", &self.kimpact.stats())
            .field("marked_entities", &self.marks.by_entity.len())
            .field("standing_aside", &self.standing_aside)
            .finish_non_exhaustive()
    }
}

impl KimpactState {
    pub(crate) fn new(kimpact: Kimpact) -> Self {
        Self {
            kimpact,
            marks: Marks::default(),
            applied: None,
            standing_aside: false,
            warned: Warned::default(),
        }
    }

    /// The resolver (read only: its marks follow the
    /// [`KimpactCollider`](crate::KimpactCollider) components, its mode and
    /// law the [`KimpactSettings`](crate::KimpactSettings)).
    pub fn kimpact(&self) -> &Kimpact {
        &self.kimpact
    }

    /// Totals since the app started: impacts, energy dissipated, steps.
    pub fn stats(&self) -> Stats {
        self.kimpact.stats()
    }

    /// The mode in force.
    pub fn mode(&self) -> Mode {
        self.kimpact.mode()
    }

    /// The law in force (the last valid [`KimpactSettings::law`](crate::KimpactSettings::law)).
    pub fn law(&self) -> &Law<crate::kimpact_rapier::math::Real> {
        self.kimpact.law()
    }

    /// Whether the collider of `entity` is marked (it has a
    /// [`KimpactCollider`](crate::KimpactCollider) and its rapier collider
    /// exists in the governed context).
    pub fn is_marked(&self, entity: Entity) -> bool {
        self.marks
            .handle(entity)
            .is_some_and(|h| self.kimpact.is_marked(h))
    }

    /// How many collider entities are marked.
    pub fn marked_count(&self) -> usize {
        self.marks.by_entity.len()
    }

    /// Mark the collider `handle` of `entity` with `material` (unmarking the
    /// entity's previous collider, if rapier gave it a new one; a collider
    /// marked already only takes the material).
    pub(crate) fn mark(
        &mut self,
        colliders: &ColliderSet,
        entity: Entity,
        handle: ColliderHandle,
        material: Option<Material>,
    ) {
        if let Some(old) = self.marks.handle(entity) {
            if old == handle && self.kimpact.is_marked(handle) {
                if self.kimpact.material(handle) != material
                    && let Err(e) = self.kimpact.set_material(handle, material)
                {
                    log::debug!("kimpact: {entity}'s material not set: {e}");
                }
                return;
            }
            self.unmark(entity);
        }
        let marked = match material {
            Some(m) => self.kimpact.mark_with(colliders, handle, m),
            None => self.kimpact.mark(colliders, handle),
        };
        match marked {
            Ok(()) => self.marks.insert(entity, handle),
            Err(e) => log::debug!("kimpact: {entity} not marked: {e}"),
        }
    }

    /// Unmark the collider of `entity`, if it was marked.
    pub(crate) fn unmark(&mut self, entity: Entity) {
        if let Some(handle) = self.marks.remove(entity) {
            self.kimpact.unmark(handle);
        }
    }
}

/// The marked colliders by entity.
#[derive(Default)]
pub(crate) struct Marks {
    by_entity: HashMap<Entity, ColliderHandle>,
}

impl Marks {
    pub fn handle(&self, entity: Entity) -> Option<ColliderHandle> {
        self.by_entity.get(&entity).copied()
    }

    fn insert(&mut self, entity: Entity, handle: ColliderHandle) {
        self.by_entity.insert(entity, handle);
    }

    fn remove(&mut self, entity: Entity) -> Option<ColliderHandle> {
        self.by_entity.remove(&entity)
    }
}
