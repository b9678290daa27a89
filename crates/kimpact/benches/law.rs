//! Impacts per second of the core law: f32/f64, 2D/3D.
//!
//! `cargo bench -p kimpact --bench law`. Each iteration resolves a batch of
//! 1,024 random approaching pairs (masses over 6 decades, random normals),
//! so criterion's throughput is in impacts per second.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kimpact::nalgebra::{RealField, SVector};
use kimpact::{Body, Law, LawParams};
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};

const BATCH: usize = 1024;

type Case<T, const D: usize> = (Body<T, D>, Body<T, D>, SVector<T, D>);

fn cases<T: RealField + Copy, const D: usize>() -> Vec<Case<T, D>> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(0x9E37_79B9_7F4A_7C15);
    let mut out = Vec::with_capacity(BATCH);
    let conv = |x: f64| T::from_subset(&x);
    while out.len() < BATCH {
        let n = SVector::<T, D>::from_fn(|_, _| conv(rng.random::<f64>() - 0.5));
        let v_a = SVector::<T, D>::from_fn(|_, _| conv(4.0 * rng.random::<f64>() - 2.0));
        let v_b = SVector::<T, D>::from_fn(|_, _| conv(4.0 * rng.random::<f64>() - 2.0));
        if n.norm() < conv(0.1) || (v_b - v_a).dot(&n) >= T::zero() {
            continue;
        }
        let m_a = conv(10f64.powf(6.0 * rng.random::<f64>() - 3.0));
        let m_b = conv(10f64.powf(6.0 * rng.random::<f64>() - 3.0));
        out.push((
            Body::new(m_a, v_a).unwrap(),
            Body::new(m_b, v_b).unwrap(),
            n.normalize(),
        ));
    }
    out
}

fn bench_dim<T: RealField + Copy, const D: usize>(c: &mut Criterion, name: &str) {
    let law = Law::new(LawParams {
        dissipation: T::from_subset(&0.01),
        ..Default::default()
    })
    .unwrap();
    let cases = cases::<T, D>();
    let mut group = c.benchmark_group("law");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(format!("resolve_unit/{name}"), |bench| {
        bench.iter(|| {
            for (a, b, n) in &cases {
                black_box(law.resolve_unit(black_box(a), black_box(b), black_box(n)));
            }
        })
    });
    group.bench_function(format!("resolve/{name}"), |bench| {
        bench.iter(|| {
            for (a, b, n) in &cases {
                black_box(law.resolve(black_box(a), black_box(b), black_box(n)).ok());
            }
        })
    });
    group.finish();
}

fn law(c: &mut Criterion) {
    bench_dim::<f64, 3>(c, "f64-3d");
    bench_dim::<f64, 2>(c, "f64-2d");
    bench_dim::<f32, 3>(c, "f32-3d");
    bench_dim::<f32, 2>(c, "f32-2d");
}

criterion_group!(benches, law);
criterion_main!(benches);
