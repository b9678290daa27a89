//! Behaviour fingerprint of the adapters: a ball pit (under gravity,
//! d̃ = 0.01) and an elastic gas, each in every mode, 2D and 3D, f32 and f64,
//! stepped 300 steps; one line per run with an FNV-1a hash of every ball's
//! final position and velocity bits and of kimpact's totals. A refactor that
//! must not change behaviour prints the same lines before and after:
//!
//!     cargo run --release --example state_hash > before.txt
//!
//! The scenes are `tests/cases/soak.rs`'s, on `tests/cases/world.rs`.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast, dead_code)]

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
            use k::math::{DIM, Real, Vector};
            use k::rapier::prelude::*;
            include!("../tests/cases/soak.rs");

            pub fn print(label: &str) {
                for scene in ["pit", "gas"] {
                    for mode in Mode::ALL {
                        let (mut w, balls) = match scene {
                            "pit" => pit_world(mode, 300, pit_half(300)),
                            _ => gas_world(mode, 200, gas_half(200)),
                        };
                        for _ in 0..300 {
                            w.step();
                        }
                        let mut h = super::Fnv::new();
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
                        println!(
                            "{label} {scene} {:<11} {:016x} impacts={}",
                            mode.name(),
                            h.0,
                            s.impacts
                        );
                    }
                }
            }
        }
    };
}

variant!(d2, kimpact2d);
variant!(d3, kimpact3d);
variant!(d2_f64, kimpact2d_f64);
variant!(d3_f64, kimpact3d_f64);

fn main() {
    d2::print("2d-f32");
    d3::print("3d-f32");
    d2_f64::print("2d-f64");
    d3_f64::print("3d-f64");
}
