//! Impacts per second of the reference simulator: an elastic 2D gas of
//! 1,000 disks at packing fraction 0.3 in a unit box.
//!
//! `cargo bench -p kimpact-reference --bench gas -- --measurement-time 3`.
//! The gas is equilibrated first; each iteration then advances it by the
//! time in which it makes `IMPACTS` impacts on average (measured during the
//! equilibration: an elastic gas in a closed box is stationary), so
//! criterion's throughput is in impacts per second. The exact count of
//! impacts over the measurement is also printed.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kimpact::Law;
use kimpact_reference::{Ball, BoxBounds, Reference};
use nalgebra::Vector2;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

const N: usize = 1000;
const PACKING: f64 = 0.3;
const IMPACTS: u64 = 10_000;

/// 1,000 disks on a 32 × 32 lattice of the unit box, random velocities.
fn gas() -> Reference<2> {
    let radius = (PACKING / (N as f64 * std::f64::consts::PI)).sqrt();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(0x2545_F491_4F6C_DD1D);
    let side = 32;
    let balls = (0..N)
        .map(|i| {
            let (x, y) = ((i % side) as f64 + 0.5, (i / side) as f64 + 0.5);
            let position = Vector2::new(x, y) / side as f64;
            let velocity = Vector2::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
            Ball::new(radius, 1.0, position, velocity)
        })
        .collect();
    let bounds = BoxBounds::new(Vector2::zeros(), Vector2::new(1.0, 1.0));
    Reference::new(balls, bounds, Vector2::zeros(), Law::elastic()).expect("valid gas")
}

fn bench(c: &mut Criterion) {
    let mut sim = gas();
    // Equilibrate over ~100 impacts per disk, then measure the impact rate.
    while sim.stats().impacts() < 100 * N as u64 {
        sim.advance_by(0.1).unwrap();
    }
    let (t0, i0) = (sim.time(), sim.stats().impacts());
    while sim.stats().impacts() - i0 < 100 * IMPACTS {
        sim.advance_by(0.1).unwrap();
    }
    let rate = (sim.stats().impacts() - i0) as f64 / (sim.time() - t0);
    let dt = IMPACTS as f64 / rate;

    let mut wall = Duration::ZERO;
    let mut impacts = 0;
    let mut group = c.benchmark_group("reference");
    group.sample_size(20);
    group.throughput(Throughput::Elements(IMPACTS));
    group.bench_function("gas2d/1000 disks, packing 0.3, elastic", |b| {
        b.iter_custom(|iters| {
            let before = sim.stats().impacts();
            let start = Instant::now();
            for _ in 0..iters {
                sim.advance_by(dt).unwrap();
            }
            let elapsed = start.elapsed();
            wall += elapsed;
            impacts += sim.stats().impacts() - before;
            black_box(sim.time());
            elapsed
        })
    });
    group.finish();
    let s = sim.stats();
    eprintln!(
        "reference gas2d: {impacts} impacts in {:.3} s = {:.3e} impacts/s \
         (ball {}, wall {}, crossings {}, stale {})",
        wall.as_secs_f64(),
        impacts as f64 / wall.as_secs_f64(),
        s.ball_impacts,
        s.wall_impacts,
        s.cell_crossings,
        s.stale_events,
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
