//! Broad phase timing: sweep-and-prune update under coherent random motion for
//! 1k, 10k and 100k boxes, against brute-force O(n^2) (1k, 10k); the same with
//! speeds scaled so that the swaps per box are the same at every n; and the
//! incoherent case (every box teleports every frame, forcing the rebuild path).
//!
//! Scene: unit cubes, centres uniform in a cube of side 2 n^(1/3) m (about one
//! neighbour per box), velocities uniform in [-1, 1]^3 m/s, reflected at the walls,
//! 60 Hz steps. Throughput is in boxes, so criterion's "elem/s" reads as bodies
//! per second; time per body = 1 / that.
//!
//! Run: `cargo bench -p tumble-collide --bench broad_phase -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use tumble_collide::broad::{Aabb, PairEvent, ProxyId, SweepAndPrune};
use tumble_collide::DVec3;

const DT: f64 = 1.0 / 60.0;
const HALF: f64 = 0.5;

/// Deterministic xorshift64 generator (`tumble-testkit`).
use tumble_testkit::{RandomSource, XorShift64 as Rng};

/// A point with each coordinate uniform in [0, 1).
fn unit_point(rng: &mut Rng) -> DVec3 {
    DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64())
}

/// Boxes in coherent motion.
struct Scene {
    side: f64,
    centers: Vec<DVec3>,
    velocities: Vec<DVec3>,
    rng: Rng,
}

impl Scene {
    fn new(n: usize) -> Scene {
        Scene::with_speed(n, 1.0)
    }

    /// Velocities uniform in `[-speed, speed]^3` m/s.
    fn with_speed(n: usize, speed: f64) -> Scene {
        let side = 2.0 * (n as f64).cbrt();
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let centers = (0..n).map(|_| unit_point(&mut rng) * side).collect();
        let velocities = (0..n)
            .map(|_| (unit_point(&mut rng) * 2.0 - 1.0) * speed)
            .collect();
        Scene {
            side,
            centers,
            velocities,
            rng,
        }
    }

    fn aabb(&self, i: usize) -> Aabb {
        Aabb::from_center_half_extents(self.centers[i], DVec3::splat(HALF)).unwrap()
    }

    /// One 60 Hz step with reflection at the walls of the cube.
    fn step(&mut self) {
        for (c, v) in self.centers.iter_mut().zip(&mut self.velocities) {
            *c += *v * DT;
            for k in 0..3 {
                if c[k] < 0.0 || c[k] > self.side {
                    v[k] = -v[k];
                    c[k] = c[k].clamp(0.0, self.side);
                }
            }
        }
    }

    /// Every box jumps to a random place.
    fn teleport(&mut self) {
        for c in &mut self.centers {
            *c = unit_point(&mut self.rng) * self.side;
        }
    }
}

fn build(scene: &Scene) -> (SweepAndPrune, Vec<ProxyId>, Vec<PairEvent>) {
    let mut sap = SweepAndPrune::new();
    let ids = (0..scene.centers.len())
        .map(|i| sap.insert(i as u32, scene.aabb(i)).unwrap())
        .collect();
    let mut events = Vec::new();
    sap.update(&mut events);
    (sap, ids, events)
}

/// Moves every box (one step or a teleport) and writes the new boxes.
fn advance(scene: &mut Scene, sap: &mut SweepAndPrune, ids: &[ProxyId], teleport: bool) {
    if teleport {
        scene.teleport();
    } else {
        scene.step();
    }
    for (i, &id) in ids.iter().enumerate() {
        sap.set_aabb(id, scene.aabb(i)).unwrap();
    }
}

/// Prints the work behind the timings: the swap count grows with the number of
/// endpoints crossed per step, which grows as n^(2/3) at fixed 3D density.
fn describe(n: usize, speed: f64, teleport: bool) {
    let mut scene = Scene::with_speed(n, speed);
    let (mut sap, ids, mut events) = build(&scene);
    advance(&mut scene, &mut sap, &ids, teleport);
    let r = sap.update(&mut events);
    eprintln!(
        "n = {n}, speed {speed:.3}{}: swaps/body {:.1} (predicted {:.1}), rebuilt {}, pairs {}, events {}",
        if teleport { " (teleport)" } else { "" },
        r.swaps as f64 / n as f64,
        r.estimated_swaps as f64 / n as f64,
        r.rebuilt,
        r.pairs,
        r.begins + r.ends
    );
}

/// Incremental sweep and prune on the moving scene, velocities uniform in
/// `[-speed(n), speed(n)]^3` m/s; `teleport`: every box jumps to a random place
/// each step instead of moving a little.
fn sap_moving(c: &mut Criterion, name: &str, speed: fn(usize) -> f64, teleport: bool) {
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    for n in [1_000, 10_000, 100_000] {
        let speed = speed(n);
        describe(n, speed, teleport);
        let mut scene = Scene::with_speed(n, speed);
        let (mut sap, ids, mut events) = build(&scene);
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| {
                advance(&mut scene, &mut sap, &ids, teleport);
                black_box(sap.update(&mut events))
            })
        });
    }
    group.finish();
}

/// Speed 1 m/s at every n.
fn unit_speed(_: usize) -> f64 {
    1.0
}

fn sap_coherent(c: &mut Criterion) {
    sap_moving(c, "sap_coherent", unit_speed, false);
}

/// Same scene with speeds scaled by `(1000 / n)^(2/3)`, so that each box passes
/// the same number of endpoints per step at every n (the endpoint spacing on an
/// axis shrinks as n^(-2/3) at fixed 3D density): isolates the O(n + swaps) cost.
fn sap_fixed_crossings(c: &mut Criterion) {
    sap_moving(
        c,
        "sap_fixed_crossings",
        |n| (1000.0 / n as f64).powf(2.0 / 3.0),
        false,
    );
}

fn sap_teleport(c: &mut Criterion) {
    sap_moving(c, "sap_teleport", unit_speed, true);
}

fn brute_force(c: &mut Criterion) {
    let mut group = c.benchmark_group("brute_force");
    group.sample_size(10);
    for n in [1_000, 10_000] {
        let mut scene = Scene::new(n);
        let mut boxes: Vec<Aabb> = (0..n).map(|i| scene.aabb(i)).collect();
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| {
                scene.step();
                for (i, b) in boxes.iter_mut().enumerate() {
                    *b = scene.aabb(i);
                }
                pairs.clear();
                for i in 0..n {
                    for j in i + 1..n {
                        if boxes[i].overlaps(&boxes[j]) {
                            pairs.push((i as u32, j as u32));
                        }
                    }
                }
                black_box(pairs.len())
            })
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    sap_coherent,
    sap_fixed_crossings,
    sap_teleport,
    brute_force
);
criterion_main!(benches);
