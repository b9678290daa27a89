//! The rapier adapters against the core law: the same cases in 2D and 3D,
//! f32 and f64 (one source, included four times).
// `f64::from(x)` converts in the f32 builds and is the identity in the f64 ones.
#![allow(clippy::useless_conversion, clippy::unnecessary_cast)]

mod d2 {
    use kimpact2d as k;
    mod world {
        use kimpact2d as k;
        include!("cases/world.rs");
    }
    include!("cases/adapter.rs");
    include!("cases/calm.rs");
    include!("cases/clamps.rs");
    include!("cases/rigid.rs");
    include!("cases/rigid_dim2.rs");
    include!("cases/rigid_modes.rs");
    include!("cases/rigid_replay.rs");
    include!("cases/contract.rs");
    include!("cases/user_worlds.rs");
    include!("cases/settings.rs");
    include!("cases/meshes.rs");
    include!("cases/friction.rs");
    include!("cases/landing.rs");
}

mod d3 {
    use kimpact3d as k;
    mod world {
        use kimpact3d as k;
        include!("cases/world.rs");
    }
    include!("cases/adapter.rs");
    include!("cases/calm.rs");
    include!("cases/clamps.rs");
    include!("cases/rigid.rs");
    include!("cases/rigid_dim3.rs");
    include!("cases/rigid_modes.rs");
    include!("cases/rigid_replay.rs");
    include!("cases/contract.rs");
    include!("cases/user_worlds.rs");
    include!("cases/settings.rs");
    include!("cases/meshes.rs");
    include!("cases/friction.rs");
    include!("cases/landing.rs");
}

mod d2_f64 {
    use kimpact2d_f64 as k;
    mod world {
        use kimpact2d_f64 as k;
        include!("cases/world.rs");
    }
    include!("cases/adapter.rs");
    include!("cases/calm.rs");
    include!("cases/clamps.rs");
    include!("cases/rigid.rs");
    include!("cases/rigid_dim2.rs");
    include!("cases/rigid_modes.rs");
    include!("cases/rigid_replay.rs");
    include!("cases/contract.rs");
    include!("cases/user_worlds.rs");
    include!("cases/settings.rs");
    include!("cases/meshes.rs");
    include!("cases/friction.rs");
    include!("cases/landing.rs");
    include!("cases/soak.rs");
    include!("cases/long.rs");

    #[test]
    fn exact_elastic_gas_keeps_its_energy_for_10000_steps() {
        exact_gas_check();
    }

    /// Eight throws of the dice (seeds 1 to 8), each kept to 1e-9.
    #[test]
    fn exact_elastic_dice_keep_their_energy_for_10000_steps() {
        for seed in 1..=8 {
            dice_check(10_000, seed);
        }
    }
}

mod d3_f64 {
    use kimpact3d_f64 as k;
    mod world {
        use kimpact3d_f64 as k;
        include!("cases/world.rs");
    }
    include!("cases/adapter.rs");
    include!("cases/calm.rs");
    include!("cases/clamps.rs");
    include!("cases/rigid.rs");
    include!("cases/rigid_dim3.rs");
    include!("cases/rigid_modes.rs");
    include!("cases/rigid_replay.rs");
    include!("cases/contract.rs");
    include!("cases/user_worlds.rs");
    include!("cases/settings.rs");
    include!("cases/meshes.rs");
    include!("cases/friction.rs");
    include!("cases/landing.rs");
    include!("cases/soak.rs");
    include!("cases/long.rs");

    #[test]
    fn exact_elastic_gas_keeps_its_energy_for_10000_steps() {
        exact_gas_check();
    }

    /// Eight throws of the dice (seeds 1 to 8), each kept to 1e-9.
    #[test]
    fn exact_elastic_dice_keep_their_energy_for_10000_steps() {
        for seed in 1..=8 {
            dice_check(10_000, seed);
        }
    }
}

/// The four adapter crates share one `Mode` and one `Stats` (the core's):
/// a value of one crate's type is a value of every other's.
#[test]
fn the_adapter_crates_share_one_mode_and_one_stats() {
    let modes: [kimpact2d::Mode; 4] = [
        kimpact3d::Mode::Native,
        kimpact2d_f64::Mode::Restitution,
        kimpact3d_f64::Mode::Impulse,
        kimpact::Mode::Exact,
    ];
    assert_eq!(modes, kimpact::Mode::ALL);
    let stats: kimpact3d_f64::Stats = kimpact2d::Stats::default();
    assert_eq!(stats, kimpact::Stats::default());
}
