//! Scene files: the serde structs (`*File`), read from `.json`, `.ron` or
//! `.toml`, and their validation into a typed [`Scene`].
//!
//! Every error names the file and the field (`bodies[3].radius: must be > 0,
//! got 0`), with line and column for parse errors. See `docs/scenes.md` for
//! every key.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod body;
mod check;
mod derived;
mod file;
mod generator;
mod joint;
mod model;
mod overlap;
mod parse;
mod shape;
mod validate;

pub use file::{
    Angular, BodyFile, BodyRef, GeneratorFile, JointFile, LawFile, MaterialFile, SceneFile,
    ViewFile,
};
pub use kimpact::{FixedPartner, Mode, Precision};
pub use model::{
    Body, CombineRule, Effect, Joint, JointEnd, JointKind, MAX_BODIES, MAX_STEPS, Material,
    ParseCombineRuleError, Scene, SceneError, View,
};
pub use parse::{load, parse};
pub use shape::{Shape, rotate};
pub use validate::validate;
