//! The cost of a spawn bug users make: `N` balls created overlapping at one
//! point, in a closed box under gravity, stepped a few steps in each mode.
//! Prints each mode's CPU time per step and its ratio to native rapier's,
//! measured in the same run, and checks every ball stays finite:
//!
//!     cargo run --release --example overlapping_spawn -- 1000 3
//!
//! Pairs that start overlapping and are not approaching are rapier's to
//! separate: the law modes should cost about what native rapier does.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast, dead_code)]

macro_rules! variant {
    ($name:ident, $k:ident) => {
        mod $name {
            use $k as k;
            mod world {
                use $k as k;
                include!("../tests/cases/world.rs");
            }
            use self::world::TestWorld;
            use k::Mode;
            use k::math::Vector;

            /// Prints each mode's seconds per step and its ratio to native.
            pub fn run(label: &str, n: usize, steps: usize) {
                let mut native = None;
                for mode in Mode::ALL {
                    let mut w = TestWorld::new(mode, 0.0, Vector::Y * -9.81);
                    w.closed_box(5.0, 0.5);
                    let balls: Vec<_> = (0..n)
                        .map(|_| w.ball(Vector::ZERO, Vector::ZERO, 0.1, 1.0).0)
                        .collect();
                    let start = std::time::Instant::now();
                    for _ in 0..steps {
                        w.step();
                    }
                    let per_step = start.elapsed().as_secs_f64() / steps as f64;
                    let finite = balls
                        .iter()
                        .all(|&b| w.pos(b).is_finite() && w.vel(b).is_finite());
                    assert!(finite, "{label} {mode}: a ball is not finite");
                    let base = *native.get_or_insert(per_step);
                    println!(
                        "{label} {mode:<11} {n} balls: {:8.3} s/step  {:5.2}x native  impacts {}",
                        per_step,
                        per_step / base,
                        w.kimpact.stats().impacts
                    );
                }
            }
        }
    };
}

variant!(d2, kimpact2d);
variant!(d3, kimpact3d);

fn main() {
    let mut args = std::env::args().skip(1).map(|a| a.parse::<usize>());
    let n = args.next().and_then(Result::ok).unwrap_or(1000);
    let steps = args.next().and_then(Result::ok).unwrap_or(3);
    d3::run("3D", n, steps);
    d2::run("2D", n, steps);
}
