//! The hook's record of the flagged colliders it leaves touching
//! something, for the next step's prepare pass.

use std::sync::atomic::{AtomicU32, Ordering};

use crate::handle_map::HandleMap;
use crate::rapier::prelude::*;

/// The hook's record of which flagged colliders it left with solver
/// contacts, and at which step (see [`Touches::touch`]): written by the
/// hook during rapier's step, read by the next step's prepare pass
/// (`Prepare::is_crowded`).
#[derive(Default)]
pub(crate) struct Touches {
    /// Per collider: the step (`epoch`) at which kimpact's hook left one of
    /// its pairs with solver contacts, made by the prepare pass for the
    /// colliders it flags.
    at: HandleMap<ColliderHandle, AtomicU32>,
}

impl Touches {
    /// Give collider `ch` a slot (the prepare pass, for each collider it
    /// flags): the hook records only colliders with one.
    pub(crate) fn add(&mut self, ch: ColliderHandle) {
        self.at.get_or_insert_with(ch, || AtomicU32::new(0));
    }

    /// Called by kimpact's hook, at step `epoch`, for each collider of a
    /// pair it leaves with solver contacts (rapier's
    /// `ContactPair::has_any_active_contact`). Lock-free, so that the hook
    /// stays `Sync`.
    pub(crate) fn touch(&self, ch: ColliderHandle, epoch: u32) {
        if let Some(t) = self.at.get(ch) {
            t.store(epoch, Ordering::Relaxed);
        }
    }

    /// Whether the hook touched `ch` at step `epoch`.
    pub(crate) fn touched_at(&self, ch: ColliderHandle, epoch: u32) -> bool {
        self.at
            .get(ch)
            .is_some_and(|t| t.load(Ordering::Relaxed) == epoch)
    }
}
