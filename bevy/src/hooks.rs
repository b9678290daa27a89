//! kimpact's contact hook as bevy_rapier's hooks parameter.

use bevy::ecs::system::{StaticSystemParam, SystemParam, SystemParamItem};
use bevy::prelude::Res;

use crate::bevy_rapier::pipeline::{
    BevyPhysicsHooks, ContactModificationContextView, PairFilterContextView,
};
use crate::kimpact_rapier::rapier::prelude::{
    ContactModificationContext, PairFilterContext, PhysicsHooks, SolverFlags,
};
use crate::state::KimpactState;

/// bevy_rapier's hooks parameter with kimpact's contact hook: use it as
/// `RapierPhysicsPlugin::<KimpactHooks>` (or `KimpactHooks<MyHooks>` to keep
/// your own [`BevyPhysicsHooks`] `MyHooks`, which it chains).
///
/// Your hooks decide every pair's filters, and their
/// `modify_solver_contacts` runs for the pairs whose colliders carry your
/// own `ActiveHooks::MODIFY_SOLVER_CONTACTS` flag, before kimpact's; kimpact
/// sets and clears that flag on the marked colliders that need its hook
/// (and leaves a flag you set alone). Without [`KimpactPlugin`](crate::KimpactPlugin)
/// only your hooks run.
#[derive(SystemParam)]
pub struct KimpactHooks<'w, 's, H = ()>
where
    H: BevyPhysicsHooks + 'static,
{
    state: Option<Res<'w, KimpactState>>,
    user: StaticSystemParam<'w, 's, H>,
}

/// A user's [`BevyPhysicsHooks`] as rapier's [`PhysicsHooks`] (what
/// bevy_rapier's own adapter does, which is private to it).
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

impl<H> BevyPhysicsHooks for KimpactHooks<'_, '_, H>
where
    H: BevyPhysicsHooks + 'static,
    for<'w, 's> SystemParamItem<'w, 's, H>: BevyPhysicsHooks,
{
    fn filter_contact_pair(&self, context: PairFilterContextView) -> Option<SolverFlags> {
        self.user.filter_contact_pair(context)
    }

    fn filter_intersection_pair(&self, context: PairFilterContextView) -> bool {
        self.user.filter_intersection_pair(context)
    }

    fn modify_solver_contacts(&self, context: ContactModificationContextView) {
        let user = UserHooks(&*self.user);
        let raw = context.raw;
        match &self.state {
            // A pair of the governed context with a marked collider: kimpact's
            // hook (which runs the user's first, for the user's flags).
            Some(state)
                if state.marks.owns(raw.colliders, raw.collider1)
                    || state.marks.owns(raw.colliders, raw.collider2) =>
            {
                state.kimpact.hooks(&user).modify_solver_contacts(raw);
            }
            // No marked collider (or another rapier context): kimpact sets no
            // flag there, so rapier calls this for the user's flags only.
            _ => user.modify_solver_contacts(raw),
        }
    }
}
