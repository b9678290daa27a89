//! Scene → rapier world (kimpact-world's builder, shared with the testbed)
//! → run, written once (`body.rs`) and compiled for the four adapter crates.
//! Everything leaving this module is `f64` and dimension-free.

use indicatif::ProgressBar;

pub mod crossing;
mod output;

pub use output::{BodyState, Frame, RunOutput, Sample};

use crate::scene::{Mode, Precision, Scene};

/// Run `scene` in `mode` for `steps` steps, recording frames at the given
/// step indices (sorted), ticking `progress` once per step.
pub fn run(
    scene: &Scene,
    mode: Mode,
    steps: u64,
    frame_steps: &[u64],
    progress: Option<&ProgressBar>,
) -> RunOutput {
    match (scene.dim, scene.precision) {
        (2, Precision::F32) => sim2d::run(scene, mode, steps, frame_steps, progress),
        (2, Precision::F64) => sim2d_f64::run(scene, mode, steps, frame_steps, progress),
        (_, Precision::F32) => sim3d::run(scene, mode, steps, frame_steps, progress),
        (_, Precision::F64) => sim3d_f64::run(scene, mode, steps, frame_steps, progress),
    }
}

/// rapier2d (f32).
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
mod sim2d {
    use kimpact_world::dim2 as w;
    use kimpact2d as k;
    include!("body.rs");
}

/// rapier2d-f64.
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
mod sim2d_f64 {
    use kimpact_world::dim2_f64 as w;
    use kimpact2d_f64 as k;
    include!("body.rs");
}

/// rapier3d (f32).
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
mod sim3d {
    use kimpact_world::dim3 as w;
    use kimpact3d as k;
    include!("body.rs");
}

/// rapier3d-f64.
#[allow(clippy::unnecessary_cast, clippy::useless_conversion)]
mod sim3d_f64 {
    use kimpact_world::dim3_f64 as w;
    use kimpact3d_f64 as k;
    include!("body.rs");
}
