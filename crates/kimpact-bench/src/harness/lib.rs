//! `kimpact_harness`: every simulator of the accuracy study behind one
//! interface ([`Sim`]: the exact reference, and the adapter's four builds as
//! [`Backend`]s), the scenes it runs, the measurements it takes and the
//! colour of each simulator; and what the package's tools hand each other:
//! the records ([`BenchRow`], [`AccuracySummary`]) and whole-file writes
//! ([`write_files`]). Used by `kimpact-accuracy` and `tests/accuracy.rs`.
#![warn(missing_docs)]
// `f64::from(x)` converts in the f32 builds and is the identity in the f64 ones.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

mod backend;
mod files;
mod measure;
mod plot;
mod records;
mod scenes;
mod sim;
mod stacks;
mod stats;

pub use backend::{B2_F32, B2_F64, B3_F32, B3_F64, Backend};
pub use files::{WriteError, machine, write_files};
pub use measure::{GasSeries, ShortResult, gas_series, kinetic, momentum, short_run};
pub use plot::{Panel, color, decimal, legend, svg};
pub use records::{AccuracySummary, BenchRow, EffectRow, ErrorRow};
pub use scenes::{
    DT, R, Setup, State, V, ball_volume, cradle_setup, gas_setup, two_ball_setup, z_setup,
};
pub use sim::{HarnessError, Method, RefSim, Sim};
pub use stacks::is_kimpact;
pub use stats::{ks, ks_maxwell, mean_and_error};
