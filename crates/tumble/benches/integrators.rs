//! One integration step of 10,000 free, spinning bodies under gravity, per integrator.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use tumble::collide::math::{DQuat, DVec3};
use tumble::collide::Pose;
use tumble::integrate::{integrate, integrate_with_field, Integrator};
use tumble::{BodyState, RigidBody};

const N: usize = 10_000;

fn bodies() -> Vec<RigidBody> {
    (0..N)
        .map(|i| {
            let f = i as f64;
            let pose = Pose::new(
                DVec3::new(f.sin(), f.cos(), 0.01 * f),
                DQuat::from_euler(glam::EulerRot::ZYX, 0.1 * f, 0.2, -0.3),
            )
            .unwrap();
            let mut b =
                RigidBody::new_dynamic(1.0 + 0.1 * (i % 7) as f64, DVec3::new(0.4, 0.6, 0.8), pose).unwrap();
            b.set_linear_velocity(DVec3::new(1.0, 0.0, 2.0)).unwrap();
            b.set_angular_velocity(DVec3::new(0.3 * f.cos(), 2.0, -1.0))
                .unwrap();
            b
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let gravity = DVec3::new(0.0, 0.0, -9.81);
    let mut group = c.benchmark_group("integrate_10k");
    group.throughput(Throughput::Elements(N as u64));
    for integrator in Integrator::ALL {
        let mut set = bodies();
        group.bench_function(BenchmarkId::new("free", format!("{integrator:?}")), |b| {
            b.iter(|| integrate(black_box(&mut set), gravity, 1.0 / 240.0, integrator).unwrap())
        });
        let mut set = bodies();
        let spring = |_: usize, s: &BodyState, _: f64| (-s.position * 10.0, DVec3::ZERO);
        group.bench_function(BenchmarkId::new("spring_field", format!("{integrator:?}")), |b| {
            b.iter(|| {
                integrate_with_field(
                    black_box(&mut set),
                    gravity,
                    0.0,
                    1.0 / 240.0,
                    integrator,
                    &spring,
                )
                .unwrap()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
