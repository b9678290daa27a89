//! The bench's worlds and a child's run, written once (`scene.rs`,
//! `small.rs`) and compiled for each adapter crate: native and the law
//! modes run the same code, only the `Mode` differs.

use std::process::ExitCode;

use kimpact::Precision;
use rayon::ThreadPoolBuilder;

use crate::cli::Cli;

/// The scenes and one measured run for the adapter crate `$krate`, whose
/// angles and angular velocities about z are `$about_z` of a scalar, and
/// from components `[x, y, z]` are `$xyz` of them (2D: the angle `z`).
macro_rules! build {
    ($($module:ident: $krate:ident, $about_z:expr, $xyz:expr;)*) => {$(
        mod $module {
            use $krate as k;
            use k::math::Real;
            use k::rapier::math::AngVector;

            /// An angle or angular velocity `a` about z.
            fn about_z(a: Real) -> AngVector {
                ($about_z)(a)
            }

            /// An angle or angular velocity of components `[x, y, z]`.
            fn xyz(x: Real, y: Real, z: Real) -> AngVector {
                ($xyz)(x, y, z)
            }

            include!("scene.rs");
            include!("small.rs");
            include!("rigid_scenes.rs");
        }
    )*};
}
build! {
    d2: kimpact2d, |a| a, |_, _, z| z;
    d3: kimpact3d, |a| k::math::Vector::Z * a, k::math::Vector::new;
    d2_f64: kimpact2d_f64, |a| a, |_, _, z| z;
    d3_f64: kimpact3d_f64, |a| k::math::Vector::Z * a, k::math::Vector::new;
}

/// In a child: run what `--pair` or `--solo` asks and print it as JSON.
pub fn child_main(cli: &Cli) -> ExitCode {
    let run = || match (cli.scene[0].dim(), cli.precision[0]) {
        (2, Precision::F32) => d2::run(cli),
        (2, Precision::F64) => d2_f64::run(cli),
        (_, Precision::F32) => d3::run(cli),
        (_, Precision::F64) => d3_f64::run(cli),
    };
    // `--threads`: the steps run inside a pool of that many threads (rapier
    // and kimpact's passes use the pool they run in).
    let pool = |n: u16| ThreadPoolBuilder::new().num_threads(n.into()).build();
    let json = match cli.threads.map(pool) {
        None => run(),
        Some(Ok(pool)) => {
            crate::memory::WALL_CLOCK.store(true, std::sync::atomic::Ordering::Relaxed);
            pool.install(run)
        }
        Some(Err(e)) => {
            eprintln!("cannot start {} threads: {e}", cli.threads.unwrap_or(0));
            return ExitCode::FAILURE;
        }
    };
    println!("{json}");
    ExitCode::SUCCESS
}
