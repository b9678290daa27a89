//! Impacts per second of the core law: f32/f64, 2D/3D, the ball law and
//! the rigid-body law.
//!
//! `cargo bench -p kimpact --bench law`. Each iteration resolves a batch of
//! 1,024 random approaching pairs (masses over 6 decades, random normals;
//! for rigid bodies also random spins, arms and inverse inertias), so
//! criterion's throughput is in impacts per second.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kimpact::nalgebra::{Const, Matrix3, RealField, Rotation3, SVector, Vector3};
use kimpact::{Body, Contact, Law, LawParams, RigidBody, RigidDim};
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

/// Random angular velocities and inverse inertias in 2D and 3D.
trait Spin<T: RealField + Copy, const D: usize>: RigidDim<T, D> {
    fn omega(rng: &mut Xoshiro256PlusPlus) -> Self::Angular;
    fn inverse(rng: &mut Xoshiro256PlusPlus) -> Self::InverseInertia;
}

fn conv<T: RealField + Copy>(x: f64) -> T {
    T::from_subset(&x)
}

impl<T: RealField + Copy> Spin<T, 2> for Const<2> {
    fn omega(rng: &mut Xoshiro256PlusPlus) -> T {
        conv(4.0 * rng.random::<f64>() - 2.0)
    }
    fn inverse(rng: &mut Xoshiro256PlusPlus) -> T {
        conv(10f64.powf(4.0 * rng.random::<f64>() - 2.0))
    }
}

impl<T: RealField + Copy> Spin<T, 3> for Const<3> {
    fn omega(rng: &mut Xoshiro256PlusPlus) -> Vector3<T> {
        Vector3::from_fn(|_, _| conv(4.0 * rng.random::<f64>() - 2.0))
    }
    fn inverse(rng: &mut Xoshiro256PlusPlus) -> Matrix3<T> {
        let axis = Vector3::from_fn(|_, _| rng.random::<f64>() - 0.5);
        let r = Rotation3::new(axis * 6.0);
        let scale = 10f64.powf(4.0 * rng.random::<f64>() - 2.0);
        let diag = Vector3::from_fn(|_, _| scale * (1.0 + rng.random::<f64>()));
        (r.matrix() * Matrix3::from_diagonal(&diag) * r.matrix().transpose()).map(conv)
    }
}

type RigidCase<T, const D: usize> = (RigidBody<T, D>, RigidBody<T, D>, Contact<T, D>);

fn rigid_cases<T: RealField + Copy, const D: usize>() -> Vec<RigidCase<T, D>>
where
    Const<D>: Spin<T, D>,
{
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(0x9E37_79B9_7F4A_7C15);
    let mut out = Vec::with_capacity(BATCH);
    let vector = |rng: &mut Xoshiro256PlusPlus, scale: f64| {
        SVector::<T, D>::from_fn(|_, _| conv(scale * (rng.random::<f64>() - 0.5)))
    };
    while out.len() < BATCH {
        let n = vector(&mut rng, 1.0);
        if n.norm() < conv(0.1) {
            continue;
        }
        let body = |rng: &mut Xoshiro256PlusPlus| {
            let mass = conv(10f64.powf(6.0 * rng.random::<f64>() - 3.0));
            let v = vector(rng, 4.0);
            RigidBody::new(mass, v, <Const<D>>::omega(rng), <Const<D>>::inverse(rng)).unwrap()
        };
        let (a, b) = (body(&mut rng), body(&mut rng));
        let contact = Contact::new(vector(&mut rng, 2.0), vector(&mut rng, 2.0), n).unwrap();
        let w = b.point_velocity(contact.arm_b()) - a.point_velocity(contact.arm_a());
        if w.dot(contact.normal()) >= T::zero() {
            continue;
        }
        out.push((a, b, contact));
    }
    out
}

fn bench_rigid<T: RealField + Copy, const D: usize>(c: &mut Criterion, name: &str)
where
    Const<D>: Spin<T, D>,
{
    let law = Law::new(LawParams {
        dissipation: T::from_subset(&0.01),
        ..Default::default()
    })
    .unwrap();
    let cases = rigid_cases::<T, D>();
    let mut group = c.benchmark_group("law");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(format!("resolve_rigid/{name}"), |bench| {
        bench.iter(|| {
            for (a, b, contact) in &cases {
                black_box(law.resolve_rigid(black_box(a), black_box(b), black_box(contact)));
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
    bench_rigid::<f64, 3>(c, "f64-3d");
    bench_rigid::<f64, 2>(c, "f64-2d");
    bench_rigid::<f32, 3>(c, "f32-3d");
    bench_rigid::<f32, 2>(c, "f32-2d");
}

criterion_group!(benches, law);
criterion_main!(benches);
