//! The thesis' torus pair (shared/scenes.md, "tori"): two 5,000-triangle tori,
//! B sliding through A over 200 poses. Times the all-pairs OBBTree traversal
//! (leaf pairs handed to a counting callback, no triangle test) and the
//! first-contact traversal, and prints the BV tests and triangle pairs summed
//! over the 200 poses per leaf size (the measurement behind the default).

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use tumble_collide::bvh::{collide, BuildOptions, ObbTree, Traverse};
use tumble_collide::math::{DQuat, DVec3};
use tumble_collide::mesh::torus_mesh;
use tumble_collide::Pose;

fn poses() -> Vec<Pose> {
    let q = DQuat::from_rotation_z(0.1) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    (0..200)
        .map(|k| Pose::new(DVec3::new(-3.0 + 6.0 * k as f64 / 199.0, 0.05, 0.02), q).unwrap())
        .collect()
}

fn tori(c: &mut Criterion) {
    let mesh = torus_mesh(1.0, 0.3, 50, 50).unwrap();
    let poses = poses();
    let id = Pose::IDENTITY;
    for leaf_size in 1..=4 {
        let t = ObbTree::build_with(&mesh, &BuildOptions { leaf_size }).unwrap();
        let (mut bv, mut tp) = (0u64, 0u64);
        for p in &poses {
            let s = collide(&t, &id, &t, p, 0.0, |_, _| Traverse::Continue).unwrap();
            bv += s.bv_tests;
            tp += s.triangle_pairs;
        }
        println!(
            "leaf_size {leaf_size}: {} bytes/tree, 200 poses: {bv} BV tests, {tp} triangle pairs",
            t.memory_bytes()
        );
    }
    let t = ObbTree::build(&mesh).unwrap();
    c.bench_function("tori_all_pairs_200_poses", |b| {
        b.iter(|| {
            let mut n = 0u64;
            for p in &poses {
                collide(&t, &id, &t, p, 0.0, |_, _| {
                    n += 1;
                    Traverse::Continue
                })
                .unwrap();
            }
            black_box(n)
        })
    });
    // The all-pairs bench above but for the callback's answer (Stop, not
    // Continue): each timed body is written out so that the code measured is
    // the code on the page, with nothing between criterion and `collide`.
    c.bench_function("tori_first_pair_200_poses", |b| {
        b.iter(|| {
            let mut n = 0u64;
            for p in &poses {
                collide(&t, &id, &t, p, 0.0, |_, _| {
                    n += 1;
                    Traverse::Stop
                })
                .unwrap();
            }
            black_box(n)
        })
    });
}

criterion_group!(benches, tori);
criterion_main!(benches);
