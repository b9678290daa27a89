//! The names a rapier simulation needs to take kimpact in, for one glob
//! import beside rapier's own prelude:
//!
//! ```
//! # #[cfg(all(feature = "dim3", feature = "f32"))] use kimpact3d as kimpact_rapier;
//! # #[cfg(all(feature = "dim2", feature = "f32"))] use kimpact2d as kimpact_rapier;
//! # #[cfg(all(feature = "dim3", feature = "f64"))] use kimpact3d_f64 as kimpact_rapier;
//! # #[cfg(all(feature = "dim2", feature = "f64"))] use kimpact2d_f64 as kimpact_rapier;
//! use kimpact_rapier::prelude::*; // kimpact3d::prelude::* in a user's crate
//! use kimpact_rapier::rapier::prelude::*; // or rapier3d::prelude::*
//!
//! let mut world = PhysicsWorld::new();
//! let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
//! let (_, collider) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5));
//! kimpact.mark(&world.colliders, collider)?;
//! kimpact.step_world(&mut world, &(), &());
//! # Ok::<(), HandleError>(())
//! ```
//!
//! None of these names is in rapier's prelude, so both globs can be imported
//! together. The rapier crate itself is [`crate::rapier`].

pub use crate::{
    FixedPartner, HandleError, ImpactEvent, Kimpact, Law, LawError, LawParams, Material, Mode,
    PreparedStep, ResolverConfig, ResolverConfigError, Stats, StepHooks, StepSets,
};
