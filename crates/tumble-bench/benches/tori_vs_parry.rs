//! tumble against parry3d on the thesis' tori (shared/scenes.md, "tori") in
//! one criterion run, so that the ratio of the two comes from the same
//! machine state. Both see the same poses per mode and do what the harness
//! peers do (`tumble bench --scene tori`, `peer-parry`):
//!
//! - `first_contact`: all 200 poses; tumble `collide` Boolean with
//!   `stop_at_first`, parry `query::intersection_test` on the two meshes;
//! - `all_pairs`: all 200 poses; tumble `collide` TrianglePairs (exact
//!   closed triangle test), parry `Bvh::leaf_pairs` + GJK triangle test;
//! - `all_pairs_with_contacts`: all 200 poses; tumble `collide` Contacts
//!   (margin 0, merged), parry composite `contact_manifolds` (prediction 0);
//! - `distance`: 20 of the 78 separated poses (every 4th; parry needs tens
//!   of ms per query here); tumble exact `distance`, parry `query::distance`.
//!
//! One iteration = the whole pose set; per query = time / poses. Before the
//! timings, the two sides' answers are checked against each other (first
//! contact booleans, distances) and the pair totals printed, so that a fast
//! wrong answer cannot pass unnoticed.
//!
//! Run: `nice -n 10 cargo bench -p tumble-bench --bench tori_vs_parry`.

use criterion::{criterion_group, criterion_main, Criterion};
use parry3d::bounding_volume::BoundingVolume;
use parry3d::math::Pose as PPose;
use parry3d::query::{self as pq, ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
use parry3d::shape::TriMesh as PMesh;
use std::hint::black_box;
use std::time::Duration;
use tumble::scenes;
use tumble_bench::parry_scenes;
use tumble_collide::query::{self as tq, CollideOptions, DistanceOptions, MeshShape, ReportMode};
use tumble_collide::Pose;

struct Scene {
    torus: MeshShape,
    parry: PMesh,
    poses: Vec<(Pose, PPose)>,
    separated: Vec<usize>,
}

fn first_opts() -> CollideOptions {
    CollideOptions {
        stop_at_first: true,
        report: ReportMode::Boolean,
        contact_margin: 0.0,
    }
}

fn contact_opts() -> CollideOptions {
    CollideOptions {
        report: ReportMode::Contacts,
        ..CollideOptions::default()
    }
}

fn scene() -> Scene {
    let torus = MeshShape::new(scenes::tori_torus().expect("torus")).expect("tree");
    let parry: PMesh = parry_scenes::torus().expect("parry mesh");
    let poses: Vec<(Pose, PPose)> = (0..scenes::TORI_POSES)
        .map(|k| {
            let ours = scenes::tori_pose(k);
            (ours, parry_scenes::pose(&ours))
        })
        .collect();
    let separated: Vec<usize> = (0..scenes::TORI_POSES)
        .filter(|&k| {
            !tq::collide(&torus, &Pose::IDENTITY, &torus, &poses[k].0, &first_opts())
                .expect("valid query")
                .intersect
        })
        .step_by(4)
        .collect();
    Scene {
        torus,
        parry,
        poses,
        separated,
    }
}

fn parry_all_pairs(m: &PMesh, pos12: &PPose) -> usize {
    let check = |n1: &parry3d::partitioning::BvhNode, n2: &parry3d::partitioning::BvhNode| {
        n1.aabb().intersects(&n2.aabb().transform_by(pos12))
    };
    let mut count = 0;
    for (i, j) in m.bvh().leaf_pairs(m.bvh(), check) {
        if let Ok(hit) = pq::intersection_test(&PPose::identity(), &m.triangle(i), pos12, &m.triangle(j)) {
            count += hit.intersecting as usize;
        }
    }
    count
}

fn parry_manifolds(m: &PMesh, pos12: &PPose) -> usize {
    let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
    let mut workspace = None;
    let _ = DefaultQueryDispatcher.contact_manifolds(pos12, m, m, 0.0, &mut manifolds, &mut workspace);
    manifolds.iter().map(|x| x.points.len()).sum()
}

/// The two libraries agree before they race.
fn cross_check(s: &Scene) {
    let id = Pose::IDENTITY;
    let (mut ours, mut theirs, mut hits) = (0usize, 0usize, 0usize);
    for (pb, ppb) in &s.poses {
        let b = tq::collide(&s.torus, &id, &s.torus, pb, &first_opts())
            .expect("query")
            .intersect;
        let p = pq::intersection_test(&PPose::identity(), &s.parry, ppb, &s.parry).expect("parry query");
        assert_eq!(b, p.intersecting, "first contact disagrees");
        hits += b as usize;
        ours += tq::collide(&s.torus, &id, &s.torus, pb, &CollideOptions::default())
            .expect("query")
            .pairs
            .len();
        theirs += parry_all_pairs(&s.parry, ppb);
    }
    println!(
        "colliding poses {hits}; all pairs over 200 poses: tumble {ours}, parry3d {theirs} (truth 36782)"
    );
    for &k in &s.separated {
        let d = tq::distance(
            &s.torus,
            &id,
            &s.torus,
            &s.poses[k].0,
            &DistanceOptions::default(),
        )
        .expect("query");
        let p = pq::distance(&PPose::identity(), &s.parry, &s.poses[k].1, &s.parry).expect("parry query");
        // parry works in f32.
        let p = p.distance as f64;
        assert!((d.distance - p).abs() < 1e-4, "pose {k}: {} vs {p}", d.distance);
    }
}

fn tori(c: &mut Criterion) {
    let s = scene();
    cross_check(&s);
    let id = Pose::IDENTITY;
    let pid = PPose::identity();

    // The four groups below (one per mode) are alike in shape on purpose: each
    // closure calls its library directly, so what is timed is read at the group,
    // with no shared driver between criterion and the query.
    let mut g = c.benchmark_group("tori_first_contact_200_poses");
    g.sample_size(20).measurement_time(Duration::from_secs(5));
    g.bench_function("tumble", |b| {
        b.iter(|| {
            s.poses
                .iter()
                .filter(|(p, _)| {
                    tq::collide(&s.torus, &id, &s.torus, p, &first_opts()).is_ok_and(|r| r.intersect)
                })
                .count()
        })
    });
    g.bench_function("parry3d", |b| {
        b.iter(|| {
            s.poses
                .iter()
                .filter(|(_, p)| {
                    pq::intersection_test(&pid, &s.parry, p, &s.parry).is_ok_and(|r| r.intersecting)
                })
                .count()
        })
    });
    g.finish();

    let mut g = c.benchmark_group("tori_all_pairs_200_poses");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let all = CollideOptions::default();
    g.bench_function("tumble", |b| {
        b.iter(|| {
            s.poses
                .iter()
                .map(|(p, _)| tq::collide(&s.torus, &id, &s.torus, p, &all).map_or(0, |r| r.pairs.len()))
                .sum::<usize>()
        })
    });
    g.bench_function("parry3d", |b| {
        b.iter(|| {
            s.poses
                .iter()
                .map(|(_, p)| parry_all_pairs(&s.parry, p))
                .sum::<usize>()
        })
    });
    g.finish();

    let mut g = c.benchmark_group("tori_all_pairs_with_contacts_200_poses");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    g.bench_function("tumble", |b| {
        b.iter(|| {
            s.poses
                .iter()
                .map(|(p, _)| {
                    tq::collide(&s.torus, &id, &s.torus, p, &contact_opts()).map_or(0, |r| r.contacts.len())
                })
                .sum::<usize>()
        })
    });
    g.bench_function("parry3d", |b| {
        b.iter(|| {
            s.poses
                .iter()
                .map(|(_, p)| parry_manifolds(&s.parry, p))
                .sum::<usize>()
        })
    });
    g.finish();

    let mut g = c.benchmark_group("tori_distance_20_separated_poses");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    let exact = DistanceOptions::default();
    g.bench_function("tumble", |b| {
        b.iter(|| {
            for &k in &s.separated {
                black_box(
                    tq::distance(&s.torus, &id, &s.torus, &s.poses[k].0, &exact)
                        .map(|d| d.distance)
                        .ok(),
                );
            }
        })
    });
    g.bench_function("parry3d", |b| {
        b.iter(|| {
            for &k in &s.separated {
                black_box(pq::distance(&pid, &s.parry, &s.poses[k].1, &s.parry).ok());
            }
        })
    });
    g.finish();
}

criterion_group!(benches, tori);
criterion_main!(benches);
