//! The determinism check: a ball pit (300 marked balls under gravity in a
//! closed box, d̃ = 0.01) and an elastic gas (200 balls, no gravity), each in
//! every mode, 300 steps, rapier3d (f32) built with `enhanced-determinism`
//! (and `parallel` with `--features parallel`). Each scene runs twice in the
//! process (the two runs must agree bit for bit, or the program exits with
//! status 1) and prints one line per scene and mode: an FNV-1a hash of the
//! bit patterns of every ball's final position and velocity and of kimpact's
//! totals. `run.sh` compares the lines across builds and thread counts.
//!
//! The scenes are `tests/cases/soak.rs`'s (`pit_world`, `gas_world`), on the
//! test world of `tests/cases/world.rs`.

use std::process::ExitCode;

use kimpact3d as k;

mod world {
    use kimpact3d as k;
    include!("../../cases/world.rs");
}
use self::world::TestWorld;
use k::Mode;
use k::math::{DIM, Real, Vector};
use k::rapier::prelude::*;
include!("../../cases/soak.rs");

const STEPS: usize = 300;

/// FNV-1a, 64 bits.
struct Fnv(u64);
impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// The hash of one run and kimpact's impact count.
fn run(scene: &str, mode: Mode) -> (u64, u64) {
    let (mut w, balls) = match scene {
        "pit" => pit_world(mode, 300, pit_half(300)),
        _ => gas_world(mode, 200, gas_half(200)),
    };
    for _ in 0..STEPS {
        w.step();
    }
    let mut h = Fnv::new();
    for &b in &balls {
        let (p, v) = (w.pos(b), w.vel(b));
        for a in 0..DIM {
            h.write(&p[a].to_bits().to_le_bytes());
            h.write(&v[a].to_bits().to_le_bytes());
        }
    }
    let s = w.kimpact.stats();
    for x in [s.impacts, s.clamped, s.skipped_non_finite, s.event_cap_hits] {
        h.write(&x.to_le_bytes());
    }
    h.write(&s.dissipated.to_bits().to_le_bytes());
    (h.0, s.impacts)
}

fn main() -> ExitCode {
    let parallel = cfg!(feature = "parallel");
    let threads = std::env::var("RAYON_NUM_THREADS").unwrap_or_else(|_| "default".into());
    eprintln!("determinism: parallel={parallel} RAYON_NUM_THREADS={threads}");
    let mut ok = true;
    for scene in ["pit", "gas"] {
        for mode in Mode::ALL {
            let (a, impacts) = run(scene, mode);
            let (b, _) = run(scene, mode);
            if a != b {
                eprintln!("{scene} {mode}: two runs in one process differ ({a:016x} vs {b:016x})");
                ok = false;
            }
            // stdout carries only what must match across builds.
            println!("{scene} {:<11} {a:016x} impacts={impacts}", mode.name());
        }
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
