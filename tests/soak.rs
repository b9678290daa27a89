//! The soak, short (the CI version of `examples/soak.rs`, same code:
//! `tests/cases/soak.rs`): the 1,000-ball elastic gas in `exact` mode and the
//! 1,000-ball pit in every mode, f64, 2D and 3D, checked after every step:
//! no NaN, no ball outside its box, the gas's energy within 1e-9 relative
//! and the pit's never more than 1e-3 above its start (energies from the
//! floor). `cargo test --test soak -- --nocapture` prints the summaries.
// `f64::from(x)` in the shared test world is the identity in f64.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

/// Steps of the gas (the 1,000,000-step run is `examples/soak.rs`).
const GAS_STEPS: u64 = 2_000;
/// Steps of each pit: the pile lands and settles within them.
const PIT_STEPS: u64 = 600;

macro_rules! soak_tests {
    ($name:ident, $k:ident) => {
        mod $name {
            use $k as k;
            mod world {
                use $k as k;
                include!("cases/world.rs");
            }
            use self::world::TestWorld;
            use k::Mode;
            use k::math::{DIM, Real, Vector};
            use k::rapier::prelude::*;
            include!("cases/soak.rs");

            fn check(s: &Soak) {
                eprintln!("{}", s.summary());
                assert_eq!(s.nan, 0, "NaN: {}", s.summary());
                assert_eq!(s.nan_energy_steps, 0, "NaN energy: {}", s.summary());
                assert_eq!(s.escaped, 0, "escaped: {}", s.summary());
                assert!(s.passed(), "energy out of bounds: {}", s.summary());
            }

            #[test]
            fn exact_gas_keeps_its_energy_and_its_balls() {
                let s = soak("gas", Mode::Exact, 1000, super::GAS_STEPS, 0, None);
                assert!(s.drift <= GAS_EXACT_TOL);
                assert!(s.stats.impacts > 0);
                check(&s);
            }

            #[test]
            fn pits_keep_their_balls_and_never_gain_energy() {
                for mode in Mode::ALL {
                    let s = soak("pit", mode, 1000, super::PIT_STEPS, 0, None);
                    assert!(s.rise <= PIT_RISE_TOL);
                    check(&s);
                }
            }
        }
    };
}

soak_tests!(d2, kimpact2d_f64);
soak_tests!(d3, kimpact3d_f64);
