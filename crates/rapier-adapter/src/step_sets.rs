//! rapier's sets borrowed together for one step: what kimpact's stages
//! and `PhysicsPipeline::step` read and write.

use crate::math::Vector;
use crate::rapier::prelude::*;

/// rapier's sets around one step, borrowed together: every set
/// `PhysicsPipeline::step` takes by `&mut`, in its order and under
/// [`PhysicsWorld`]'s names. [`Kimpact::step`](crate::Kimpact::step) takes
/// them by value; [`Kimpact::before_step`](crate::Kimpact::before_step)
/// and [`Kimpact::after_step`](crate::Kimpact::after_step) borrow them
/// around a `pipeline.step` that reads them through the same fields.
///
/// ```
/// # #[cfg(all(feature = "dim3", feature = "f32"))] use kimpact3d as kimpact_rapier;
/// # #[cfg(all(feature = "dim2", feature = "f32"))] use kimpact2d as kimpact_rapier;
/// # #[cfg(all(feature = "dim3", feature = "f64"))] use kimpact3d_f64 as kimpact_rapier;
/// # #[cfg(all(feature = "dim2", feature = "f64"))] use kimpact2d_f64 as kimpact_rapier;
/// # use kimpact_rapier::prelude::*;
/// # use kimpact_rapier::rapier::prelude::*;
/// # let mut pipeline = PhysicsPipeline::new();
/// # let (mut islands, mut broad_phase, mut narrow_phase) =
/// #     (IslandManager::new(), BroadPhaseBvh::new(), NarrowPhase::new());
/// # let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
/// # let (mut impulse_joints, mut multibody_joints) =
/// #     (ImpulseJointSet::new(), MultibodyJointSet::new());
/// # let (mut soft_bodies, mut ccd_solver) = (SoftBodySet::new(), CCDSolver::new());
/// # let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
/// # let (gravity, params) = (Vector::ZERO, IntegrationParameters::default());
/// kimpact.step(
///     &mut pipeline,
///     gravity,
///     &params,
///     StepSets {
///         islands: &mut islands,
///         broad_phase: &mut broad_phase,
///         narrow_phase: &mut narrow_phase,
///         bodies: &mut bodies,
///         colliders: &mut colliders,
///         impulse_joints: &mut impulse_joints,
///         multibody_joints: &mut multibody_joints,
///         soft_bodies: &mut soft_bodies,
///         ccd_solver: &mut ccd_solver,
///     },
///     &(),
///     &(),
/// );
/// ```
pub struct StepSets<'a> {
    /// rapier's islands (awake and sleeping bodies).
    pub islands: &'a mut IslandManager,
    /// rapier's broad phase.
    pub broad_phase: &'a mut BroadPhaseBvh,
    /// rapier's narrow phase (contact pairs and manifolds).
    pub narrow_phase: &'a mut NarrowPhase,
    /// The rigid bodies; kimpact writes the velocities and poses it bends.
    pub bodies: &'a mut RigidBodySet,
    /// The colliders; kimpact sets its hook flag on the marked ones.
    pub colliders: &'a mut ColliderSet,
    /// The impulse joints (a joint's bodies do not collide unless it lets
    /// them).
    pub impulse_joints: &'a mut ImpulseJointSet,
    /// The multibody joints (as `impulse_joints`).
    pub multibody_joints: &'a mut MultibodyJointSet,
    /// The soft bodies (only `PhysicsPipeline::step` reads them).
    pub soft_bodies: &'a mut SoftBodySet,
    /// The CCD solver (only `PhysicsPipeline::step` uses it).
    pub ccd_solver: &'a mut CCDSolver,
}

impl std::fmt::Debug for StepSets<'_> {
    /// rapier's sets are not `Debug`: their sizes stand for them.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StepSets")
            .field("bodies", &self.bodies.len())
            .field("colliders", &self.colliders.len())
            .field("impulse_joints", &self.impulse_joints.len())
            .finish_non_exhaustive()
    }
}

impl<'a> StepSets<'a> {
    /// A [`PhysicsWorld`]'s sets, beside its pipeline (which
    /// [`Kimpact::step`](crate::Kimpact::step) takes apart from them).
    pub fn of_world(world: &'a mut PhysicsWorld) -> (&'a mut PhysicsPipeline, Self) {
        let sets = StepSets {
            islands: &mut world.islands,
            broad_phase: &mut world.broad_phase,
            narrow_phase: &mut world.narrow_phase,
            bodies: &mut world.bodies,
            colliders: &mut world.colliders,
            impulse_joints: &mut world.impulse_joints,
            multibody_joints: &mut world.multibody_joints,
            soft_bodies: &mut world.soft_bodies,
            ccd_solver: &mut world.ccd_solver,
        };
        (&mut world.physics_pipeline, sets)
    }

    /// `pipeline.step` on these sets, with `hooks` and `events`: rapier's
    /// step between [`Kimpact::before_step`](crate::Kimpact::before_step)
    /// and [`Kimpact::after_step`](crate::Kimpact::after_step), with
    /// [`Kimpact::hooks`](crate::Kimpact::hooks) as `hooks`.
    pub fn step_pipeline(
        &mut self,
        pipeline: &mut PhysicsPipeline,
        gravity: Vector,
        integration_parameters: &IntegrationParameters,
        hooks: &dyn PhysicsHooks,
        events: &dyn EventHandler,
    ) {
        pipeline.step(
            gravity,
            integration_parameters,
            self.islands,
            self.broad_phase,
            self.narrow_phase,
            self.bodies,
            self.colliders,
            self.impulse_joints,
            self.multibody_joints,
            self.soft_bodies,
            self.ccd_solver,
            hooks,
            events,
        );
    }
}
