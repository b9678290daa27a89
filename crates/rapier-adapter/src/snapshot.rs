//! Snapshots of a [`crate::Kimpact`]: the user's state (law, mode,
//! configuration, marks and materials), the totals, and what the resolver
//! carries from one step to the next, in a versioned form of their own
//! rather than the layout of the resolver's internals. The resolver saves
//! its state into one ([`Snapshot::save`]) and restores it from one
//! ([`Snapshot::restore`]); this module does not know the resolver.

use kimpact::{Law, LawError};

use crate::config::{ResolverConfig, ResolverConfigError};
use crate::events::Stats;
use crate::marks::Marks;
use crate::material::Material;
use crate::math::Real;
use crate::mode::Mode;
use crate::prepare::Carried;
use crate::rapier::prelude::{CoefficientCombineRule, ColliderHandle, ColliderSet};

#[cfg(feature = "serde-serialize")]
mod serde_form;

/// A [`Kimpact`](crate::Kimpact) as saved, from
/// [`Kimpact::snapshot`](crate::Kimpact::snapshot); restored by
/// [`Kimpact::from_snapshot`](crate::Kimpact::from_snapshot). Taken between steps, with rapier's world of
/// the same moment, it continues bit for bit (the basis of rollback
/// netcode): it holds the law, the mode, the configuration, the marked
/// colliders with their materials and the totals
/// ([`Kimpact::stats`](crate::Kimpact::stats)),
/// and what the next step needs of the last one (the colliders whose hook
/// flag kimpact set in the collider set, the bodies it must look at, when
/// the calm-neighbourhoods test is tried next). The last step's events
/// are not kept: a restored resolver reports none until it steps.
///
/// With the `serde-serialize` feature a snapshot is serde data: its
/// `format` ([`Snapshot::FORMAT`] for this build), then its `state`. A
/// snapshot of another format is read as its format alone and refused by
/// [`Kimpact::from_snapshot`](crate::Kimpact::from_snapshot)
/// ([`SnapshotError::Format`]); in a data format
/// that does not name its fields (bincode) it is refused when read, with
/// the same error's message.
///
/// ```
/// # #[cfg(all(feature = "dim3", feature = "f32"))] use kimpact3d as kimpact_rapier;
/// # #[cfg(all(feature = "dim2", feature = "f32"))] use kimpact2d as kimpact_rapier;
/// # #[cfg(all(feature = "dim3", feature = "f64"))] use kimpact3d_f64 as kimpact_rapier;
/// # #[cfg(all(feature = "dim2", feature = "f64"))] use kimpact2d_f64 as kimpact_rapier;
/// use kimpact_rapier::rapier::prelude::*;
/// use kimpact_rapier::{Kimpact, Law, Mode};
///
/// let mut world = PhysicsWorld::new();
/// let mut kimpact = Kimpact::new(Law::elastic(), Mode::Exact);
/// let (_, ball) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5));
/// kimpact.mark(&world.colliders, ball)?;
/// kimpact.step_world(&mut world, &(), &());
/// // Saved with the world of this moment (serde data with
/// // `serde-serialize`, for rapier's world too)...
/// let saved = kimpact.snapshot();
/// // ...and restored with it: here the world has not moved since.
/// let mut restored = Kimpact::from_snapshot(saved, &world.colliders)?;
/// assert!(restored.is_marked(ball));
/// assert_eq!(restored.stats(), kimpact.stats());
/// restored.step_world(&mut world, &(), &());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    format: u32,
    /// `None` when read from a snapshot of another format.
    state: Option<State>,
}

/// What a snapshot of [`Snapshot::FORMAT`] holds.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
struct State {
    law: Law<Real>,
    mode: Mode,
    config: ResolverConfig,
    /// In collider index order.
    marks: Vec<Mark>,
    stats: Stats,
    carried: Carried,
}

/// One marked collider.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
struct Mark {
    collider: ColliderHandle,
    /// Whether it was a ball centred on its body when marked (the law
    /// moves such a body as a point).
    centred_ball: bool,
    #[cfg_attr(
        feature = "serde-serialize",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    material: Option<MaterialParams>,
}

/// A [`Material`]'s parameters, checked again when restored.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde-serialize",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
struct MaterialParams {
    dissipation: Real,
    wall_dissipation: Real,
    combine_rule: CoefficientCombineRule,
    impact_friction: Real,
    tangential_restitution: Real,
}

impl MaterialParams {
    fn of(material: &Material) -> Self {
        let friction = material.impact_friction();
        Self {
            dissipation: material.dissipation(),
            wall_dissipation: material.wall_dissipation(),
            combine_rule: material.combine_rule(),
            impact_friction: friction.impact_friction(),
            tangential_restitution: friction.tangential_restitution(),
        }
    }

    fn material(&self) -> Result<Material, LawError> {
        Material::new(self.dissipation, self.wall_dissipation)?
            .with_combine_rule(self.combine_rule)
            .with_impact_friction(self.impact_friction, self.tangential_restitution)
    }
}

impl Snapshot {
    /// The snapshot format this build writes and reads.
    pub const FORMAT: u32 = 1;

    /// The snapshot's format ([`Snapshot::FORMAT`] for one this build
    /// wrote).
    pub fn format(&self) -> u32 {
        self.format
    }
}

/// A snapshot [`Kimpact::from_snapshot`](crate::Kimpact::from_snapshot)
/// refuses.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SnapshotError {
    /// The snapshot is of format `found`, this build reads `expected`
    /// ([`Snapshot::FORMAT`]).
    #[error("kimpact snapshot of format {found}: this build reads format {expected}")]
    Format {
        /// The snapshot's format.
        found: u32,
        /// The format this build reads.
        expected: u32,
    },
    /// The snapshot's configuration is invalid (the error names the field).
    #[error("kimpact snapshot's configuration: {0}")]
    Config(#[from] ResolverConfigError),
    /// The material of a marked collider is invalid (the error names the
    /// parameter).
    #[error("kimpact snapshot's material of collider {collider:?}: {error}")]
    Material {
        /// The collider the material is marked on.
        collider: ColliderHandle,
        /// What is wrong with it.
        error: LawError,
    },
}

/// The state a resolver saves in a snapshot and restores from one.
pub(crate) struct Saved {
    pub law: Law<Real>,
    pub mode: Mode,
    pub config: ResolverConfig,
    pub marks: Marks,
    pub stats: Stats,
    pub carried: Carried,
}

/// What a resolver saves in a snapshot, borrowed from it.
pub(crate) struct Saving<'a> {
    pub law: &'a Law<Real>,
    pub mode: Mode,
    pub config: &'a ResolverConfig,
    pub marks: &'a Marks,
    pub stats: Stats,
    pub carried: Carried,
}

impl Snapshot {
    /// The snapshot of `saved`.
    pub(crate) fn save(saved: Saving) -> Snapshot {
        let marks = saved
            .marks
            .iter()
            .map(|(collider, centred_ball, material)| Mark {
                collider,
                centred_ball,
                material: material.map(MaterialParams::of),
            })
            .collect();
        Snapshot {
            format: Snapshot::FORMAT,
            state: Some(State {
                law: *saved.law,
                mode: saved.mode,
                config: *saved.config,
                marks,
                stats: saved.stats,
                carried: saved.carried,
            }),
        }
    }

    /// The state this snapshot saved, for rapier's world of the same moment,
    /// whose collider set is `colliders`. A marked collider that is no
    /// longer in `colliders` (removed before the snapshot was taken) is not
    /// marked again: its handle can never be valid again.
    ///
    /// # Errors
    /// [`SnapshotError::Format`] for a snapshot of another format than
    /// [`Snapshot::FORMAT`]; [`SnapshotError::Config`] or
    /// [`SnapshotError::Material`] naming an invalid field of one read from
    /// serde data.
    pub(crate) fn restore(self, colliders: &ColliderSet) -> Result<Saved, SnapshotError> {
        let Snapshot { format, state } = self;
        let state = match state {
            Some(state) if format == Snapshot::FORMAT => state,
            _ => {
                return Err(SnapshotError::Format {
                    found: format,
                    expected: Snapshot::FORMAT,
                });
            }
        };
        let State {
            law,
            mode,
            config,
            marks,
            stats,
            mut carried,
        } = state;
        config.validate()?;
        let marks = restore_marks(&marks, colliders)?;
        // Per-handle state is kept for live handles only.
        carried.hooked.retain(|&ch| colliders.contains(ch));
        carried
            .marked_since_step
            .retain(|&ch| colliders.contains(ch));
        Ok(Saved {
            law,
            mode,
            config,
            marks,
            stats,
            carried,
        })
    }
}

/// The marks `marks` lists of colliders in `colliders`, their materials
/// checked.
fn restore_marks(marks: &[Mark], colliders: &ColliderSet) -> Result<Marks, SnapshotError> {
    let mut restored = Marks::default();
    for mark in marks {
        if !colliders.contains(mark.collider) {
            continue;
        }
        restored.insert(mark.collider, mark.centred_ball);
        if let Some(params) = &mark.material {
            let material = params.material().map_err(|error| SnapshotError::Material {
                collider: mark.collider,
                error,
            })?;
            restored.set_material(mark.collider, Some(material));
        }
    }
    Ok(restored)
}
