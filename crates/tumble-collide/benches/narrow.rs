//! Narrow-phase cost per call for the pairs a box stack exercises (box-box
//! resting, box-ground) and for hulls, through the dispatch table.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use tumble_collide::mesh::cylinder_mesh;
use tumble_collide::{contact_shapes, ConvexHull, Cuboid, DQuat, DVec3, HalfSpace, Pose, Shape, Sphere};

fn bench(c: &mut Criterion) {
    let cube: Shape = Cuboid::new(DVec3::splat(0.5)).unwrap().into();
    let ground: Shape = HalfSpace::ground().into();
    let ball: Shape = Sphere::new(0.5).unwrap().into();
    let hull: Shape = ConvexHull::from_mesh(&cylinder_mesh(0.5, 0.5, 16).unwrap())
        .unwrap()
        .into();
    let below = Pose::IDENTITY;
    let above = Pose::new(DVec3::new(0.1, 0.05, 0.999), DQuat::from_rotation_z(0.2)).unwrap();
    let mut out = Vec::with_capacity(16);
    let mut run = |name: &str, a: &Shape, pa: &Pose, b: &Shape, pb: &Pose| {
        c.bench_function(name, |bench| {
            bench.iter(|| {
                out.clear();
                contact_shapes(
                    black_box(a),
                    black_box(pa),
                    black_box(b),
                    black_box(pb),
                    0.02,
                    &mut out,
                )
                .unwrap();
                black_box(out.len())
            })
        });
    };
    run("box_on_box_resting", &cube, &above, &cube, &below);
    run(
        "box_on_ground",
        &cube,
        &Pose::from_translation(DVec3::new(0.0, 0.0, 0.499)),
        &ground,
        &below,
    );
    run("sphere_on_box", &ball, &above, &cube, &below);
    run("hull16_on_hull16_resting", &hull, &above, &hull, &below);
}

criterion_group!(benches, bench);
criterion_main!(benches);
