//! Per-call cost of the triangle-level narrow phase on a fixed batch of random
//! triangle pairs of unit size at random offsets up to 1.5 (about half of them
//! intersecting), the regime of leaf tests in an OBBTree traversal.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::time::Duration;
use tumble_collide::math::{DMat3, DVec3};
use tumble_collide::triangle::{tri_box_overlap, tri_tri_overlap, triangle_contacts, triangle_distance};
use tumble_testkit::{RandomSource, XorShift64};

fn pairs(n: usize) -> Vec<([DVec3; 3], [DVec3; 3])> {
    let mut source = XorShift64(0x9E37_79B9_7F4A_7C15);
    let mut f = move || source.range(-1.0, 1.0);
    (0..n)
        .map(|_| {
            let mut p = || DVec3::new(f(), f(), f()) * 0.5;
            let a = [p(), p(), p()];
            let shift = p() * 3.0;
            let b = [p() + shift, p() + shift, p() + shift];
            (a, b)
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let batch = pairs(1024);
    let mut g = c.benchmark_group("triangle_pair_x1024");
    g.measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(500))
        .sample_size(20);
    g.bench_function("tri_tri_overlap", |bch| {
        bch.iter(|| {
            batch
                .iter()
                .filter(|(a, b)| tri_tri_overlap(black_box(a), black_box(b)))
                .count()
        })
    });
    let axes = DMat3::from_quat(tumble_collide::math::DQuat::from_rotation_z(0.3));
    g.bench_function("tri_box_overlap", |bch| {
        bch.iter(|| {
            batch
                .iter()
                .filter(|(a, b)| tri_box_overlap(black_box(a), b[0], DVec3::splat(0.2), &axes))
                .count()
        })
    });
    g.bench_function("triangle_distance", |bch| {
        bch.iter(|| {
            batch
                .iter()
                .map(|(a, b)| triangle_distance(black_box(a), black_box(b)).distance)
                .sum::<f64>()
        })
    });
    let mut out = Vec::with_capacity(4096);
    g.bench_function("triangle_contacts_margin_0.05", |bch| {
        bch.iter(|| {
            out.clear();
            for (i, (a, b)) in batch.iter().enumerate() {
                let _ = triangle_contacts(black_box(a), i as u32, black_box(b), 0, 0.05, &mut out);
            }
            out.len()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
