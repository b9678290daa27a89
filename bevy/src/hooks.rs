//! A user's `BevyPhysicsHooks` as rapier's `PhysicsHooks`, for kimpact's
//! stages and for the steps the plugin runs.

use crate::bevy_rapier::pipeline::{
    BevyPhysicsHooks, ContactModificationContextView, PairFilterContextView,
};
use crate::kimpact_rapier::rapier::prelude::{
    ContactModificationContext, PairFilterContext, PhysicsHooks, SolverFlags,
};

/// A user's [`BevyPhysicsHooks`] as rapier's [`PhysicsHooks`] (what
/// bevy_rapier's own `BevyPhysicsHooksAdapter` does, by reference here: the
/// plugin's step system lends the same hooks to kimpact's stages and to
/// every step of a frame).
pub(crate) struct UserHooks<'a, T>(pub(crate) &'a T);

impl<T: BevyPhysicsHooks> PhysicsHooks for UserHooks<'_, T> {
    fn filter_contact_pair(&self, context: &PairFilterContext) -> Option<SolverFlags> {
        self.0
            .filter_contact_pair(PairFilterContextView { raw: context })
    }

    fn filter_intersection_pair(&self, context: &PairFilterContext) -> bool {
        self.0
            .filter_intersection_pair(PairFilterContextView { raw: context })
    }

    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        self.0
            .modify_solver_contacts(ContactModificationContextView { raw: context });
    }
}
