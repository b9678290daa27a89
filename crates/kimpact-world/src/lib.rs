//! A kimpact scene ([`kimpact_scene::Scene`]) as a rapier world and its
//! kimpact resolver, built one way for every program that runs scenes: the
//! `kimpact` CLI and the testbed app take the same bodies, shapes,
//! orientations, masses, coefficients, effects, joints, marks, CCD and
//! contact recycling from this crate, so the same scene gives the same world
//! in both.
//!
//! The builder is written once (`build.rs`) and compiled for each adapter
//! crate behind its feature: [`dim2`] (kimpact2d), [`dim2_f64`],
//! [`dim3`] and [`dim3_f64`], with the few dimension-specific conversions of
//! `dim2.rs` and `dim3.rs`.
//!
//! What a mode changes in the world, `SceneWorld::set_mode` (for instance
//! [`dim2::SceneWorld::set_mode`]) sets at build and on every switch: in
//! native mode, soft CCD on the scene's fast bodies and contact recycling off (rapier's own response needs them to
//! catch fast pairs); in the law modes neither (kimpact resolves moving
//! pairs itself, and rapier's solver would stop a ball at a predicted
//! contact before the law sees the impact). The law's bodies are marked in
//! every mode, so that the mode can change while a scene runs: in native
//! mode kimpact leaves marked pairs to rapier, and the world steps as
//! unmarked.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

use kimpact::LawError;

/// Why a scene cannot be built in a given adapter build.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The scene's dimension is not the build's.
    #[error("{file}: a {scene}D scene in a {world}D world")]
    Dimension {
        /// The scene file.
        file: String,
        /// The scene's dimension.
        scene: usize,
        /// The world's dimension.
        world: usize,
    },
    /// The law or a material does not hold in the build's precision.
    #[error("{file}: {what}: {source}")]
    Law {
        /// The scene file.
        file: String,
        /// `law`, or the material's name.
        what: String,
        /// The law's own error.
        source: LawError,
    },
}

/// A scene in rapier2d (f32), kimpact2d.
#[cfg(feature = "dim2")]
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
pub mod dim2 {
    use kimpact2d as k;
    include!("dim2.rs");
    include!("build.rs");
}

/// A scene in rapier2d-f64, kimpact2d-f64.
#[cfg(feature = "dim2-f64")]
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
pub mod dim2_f64 {
    use kimpact2d_f64 as k;
    include!("dim2.rs");
    include!("build.rs");
}

/// A scene in rapier3d (f32), kimpact3d.
#[cfg(feature = "dim3")]
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
pub mod dim3 {
    use kimpact3d as k;
    include!("dim3.rs");
    include!("build.rs");
}

/// A scene in rapier3d-f64, kimpact3d-f64.
#[cfg(feature = "dim3-f64")]
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
pub mod dim3_f64 {
    use kimpact3d_f64 as k;
    include!("dim3.rs");
    include!("build.rs");
}
