//! The accuracy ladder: [`kimpact::Mode`], defined once in the core crate
//! and shared by the four adapter crates, the CLI and the bench.

pub use kimpact::{Mode, ParseModeError};
