//! Behaviour fingerprint of the adapters: a ball pit (under gravity,
//! d̃ = 0.01) and an elastic gas, stepped 300 steps, and dice thrown
//! spinning into a closed box (rigid bodies, d̃ = 0.01), stepped 200 steps,
//! each in every mode, 2D and 3D, f32 and f64; one line per run with an
//! FNV-1a hash of every body's final position and velocity bits (the
//! dice's orientation and angular velocity too) and of kimpact's totals. A refactor that
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

            /// An angular quantity of this dimension (2D: a number; 3D: a
            /// vector).
            trait Angular: Sized {
                /// From three numbers (2D keeps the last).
                fn from3(w: [Real; 3]) -> Self;
                /// Its components.
                fn parts(self) -> Vec<Real>;
            }

            impl Angular for Real {
                fn from3(w: [Real; 3]) -> Self {
                    w[2]
                }
                fn parts(self) -> Vec<Real> {
                    vec![self]
                }
            }

            impl Angular for Vector {
                fn from3(w: [Real; 3]) -> Self {
                    let mut v = Vector::ZERO;
                    for a in 0..DIM {
                        v[a] = w[a];
                    }
                    v
                }
                fn parts(self) -> Vec<Real> {
                    (0..DIM).map(|a| self[a]).collect()
                }
            }

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
                        print_line(label, scene, mode, h, &w);
                    }
                }
                for mode in Mode::ALL {
                    let (mut w, dice) = dice_world(mode);
                    for _ in 0..200 {
                        w.step();
                    }
                    let mut h = super::Fnv::new();
                    for &b in &dice {
                        let rb = &w.world.bodies[b];
                        let mut parts = Vec::new();
                        for a in 0..DIM {
                            parts.push(rb.translation()[a]);
                            parts.push(rb.linvel()[a]);
                            // The body's axes in the world: its orientation.
                            let mut axis = Vector::ZERO;
                            axis[a] = 1.0;
                            let turned = *rb.position() * axis;
                            parts.extend((0..DIM).map(|k| turned[k]));
                        }
                        parts.extend(rb.angvel().parts());
                        for x in parts {
                            h.write(&x.to_bits().to_le_bytes());
                        }
                    }
                    print_line(label, "dice", mode, h, &w);
                }
            }

            /// The run's line: `h` (its bodies' bits) with kimpact's totals.
            fn print_line(label: &str, scene: &str, mode: Mode, mut h: super::Fnv, w: &TestWorld) {
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

            /// 16 boxes of two sizes on a grid, turned and spinning, thrown
            /// into a closed box under gravity (d̃ = 0.01); every one marked.
            fn dice_world(mode: Mode) -> (TestWorld, Vec<RigidBodyHandle>) {
                let mut w = TestWorld::new(mode, 0.01, {
                    let mut g = Vector::ZERO;
                    g[1] = -9.81;
                    g
                });
                w.closed_box(2.0, 0.5);
                let mut state: u32 = 11;
                let mut unit = move || {
                    state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                    ((state >> 8) as Real / (1u32 << 24) as Real) * 2.0 - 1.0
                };
                let mut dice = Vec::new();
                for i in 0..16 {
                    let mut p = Vector::ZERO;
                    p[0] = -1.2 + 0.8 * (i % 4) as Real;
                    p[1] = -0.8 + 0.8 * (i / 4) as Real;
                    let mut v = Vector::ZERO;
                    for a in 0..DIM {
                        v[a] = 3.0 * unit();
                    }
                    let half = if i % 3 == 0 { 0.3 } else { 0.2 };
                    let body = RigidBodyBuilder::dynamic()
                        .translation(p)
                        .rotation(AngVector::from3([1.5 * unit(), 1.5 * unit(), 1.5 * unit()]))
                        .linvel(v)
                        .angvel(AngVector::from3([4.0 * unit(), 4.0 * unit(), 4.0 * unit()]));
                    let collider = world::cuboid(Vector::splat(half)).density(1.0);
                    let (b, c) = w.world.insert(body, collider);
                    w.kimpact.mark(&w.world.colliders, c).unwrap();
                    dice.push(b);
                }
                (w, dice)
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
