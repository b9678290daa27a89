//! `kimpact_harness`: every simulator of the accuracy study behind one
//! interface, the scenes it runs, the measurements it takes and the colour
//! each simulator is drawn in; and what the package's tools hand each
//! other: the records the bench and the study write and the ladder reads
//! ([`BenchRow`], [`AccuracySummary`]), and whole-file writes
//! ([`write_files`]).
//!
//! The rapier side is the adapter built four times (`kimpact2d`,
//! `kimpact3d`, `kimpact2d-f64`, `kimpact3d-f64`); one macro wraps each into
//! the same [`Sim`] interface as the exact event-driven reference
//! (`kimpact-reference`), so that every experiment is written once, generic
//! over the dimension, and run on the same initial balls in every
//! simulator. The `kimpact-accuracy` binary of this package and the CI
//! comparisons (`tests/accuracy.rs` of the workspace) are built on it.
#![warn(missing_docs)]
// `f64::from(x)` converts in the f32 builds and is the identity in the f64 ones.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

mod backend;
mod error;
mod files;
mod measure;
mod method;
mod plot;
mod records;
mod scenes;
mod sim;
mod stacks;
mod stats;

pub use backend::{B2_F32, B2_F64, B3_F32, B3_F64, Backend};
pub use error::HarnessError;
pub use files::{WriteError, machine, write_files};
pub use measure::{GasSeries, ShortResult, gas_series, kinetic, momentum, short_run};
pub use method::Method;
pub use plot::{Panel, color, svg};
pub use records::{AccuracySummary, BenchRow, EffectRow, ErrorRow};
pub use scenes::{
    DT, R, Setup, State, V, Velocities, ball_volume, cradle_setup, gas_setup, lattice,
    two_ball_setup, z_setup,
};
pub use sim::{RefSim, Sim};
pub use stacks::is_kimpact;
pub use stats::{ks, ks_maxwell, mean_and_error};
