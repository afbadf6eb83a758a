//! The time-of-impact query against brute-force sampling of the motion
//! (issue 16): for every shape pair of the narrow phase's table, random
//! motions that translate and turn; the query may never report an impact
//! after the first sampled overlap (it must be safe), nor stop far before it
//! (it must be tight), and a motion that never overlaps gives no impact.
//! Then analytic cases: a ball at a plate, a spinning rod beside a wall.

mod common;
use common::rng;
use tumble_collide::mesh::{icosphere_mesh, torus_mesh};
use tumble_collide::narrow::contact_shapes;
use tumble_collide::query::{time_of_impact, Motion, QueryError, ToiOptions};
use tumble_collide::{Capsule, ConvexHull, Cuboid, DQuat, DVec3, HalfSpace, MeshShape, Pose, Shape, Sphere};

fn shapes() -> Vec<(&'static str, Shape)> {
    vec![
        ("sphere", Shape::Sphere(Sphere::new(0.3).unwrap())),
        (
            "cuboid",
            Shape::Cuboid(Cuboid::new(DVec3::new(0.4, 0.2, 0.05)).unwrap()),
        ),
        ("capsule", Shape::Capsule(Capsule::new(0.1, 0.4).unwrap())),
        (
            "hull",
            Shape::ConvexHull(ConvexHull::from_mesh(&icosphere_mesh(0.3, 1).unwrap()).unwrap()),
        ),
        (
            "mesh",
            Shape::Mesh(MeshShape::new(torus_mesh(0.35, 0.1, 16, 8).unwrap()).unwrap()),
        ),
    ]
}

/// Whether the shapes overlap at these poses (a contact at distance <= 0:
/// the sign of every routine's distance is exact).
fn overlap(a: &Shape, pa: &Pose, b: &Shape, pb: &Pose) -> bool {
    let mut out = Vec::new();
    contact_shapes(a, pa, b, pb, 0.0, &mut out).unwrap();
    out.iter().any(|c| c.distance <= 0.0)
}

/// First sampled time of overlap (`None`: none of the samples overlaps).
fn first_overlap(a: &Shape, ma: &Motion, b: &Shape, mb: &Motion, samples: usize) -> Option<f64> {
    (0..=samples)
        .map(|k| k as f64 / samples as f64)
        .find(|&t| overlap(a, &ma.pose_at(t), b, &mb.pose_at(t)))
}

fn random_rotation(r: &mut impl FnMut() -> f64) -> DQuat {
    let axis = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(DVec3::Z);
    DQuat::from_axis_angle(axis, std::f64::consts::TAU * r())
}

/// A motion of A through the neighbourhood of the origin: from about 2 m
/// away to the other side, turning by up to 2 rad about its centre.
fn random_motion(r: &mut impl FnMut() -> f64) -> Motion {
    let dir = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(DVec3::X);
    let miss = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 1.6;
    let q0 = random_rotation(r);
    let spin = DQuat::from_axis_angle(
        DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(DVec3::Y),
        2.0 * r(),
    );
    Motion::new(
        Pose::new(dir * 2.0 + miss, q0).unwrap(),
        Pose::new(-dir * 2.0 + miss, (spin * q0).normalize()).unwrap(),
        DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 0.1,
    )
}

#[test]
fn every_pair_is_safe_and_tight_against_sampling() {
    const SAMPLES: usize = 2000;
    let options = ToiOptions::default();
    let mut r = rng(16);
    let shapes = shapes();
    let mut hits = 0;
    let mut misses = 0;
    for (name_a, a) in &shapes {
        for (name_b, b) in &shapes {
            for case in 0..6 {
                let ma = random_motion(&mut r);
                let mb = Motion::fixed(Pose::new(DVec3::ZERO, random_rotation(&mut r)).unwrap());
                let found = time_of_impact(a, &ma, b, &mb, &options).unwrap();
                let sampled = first_overlap(a, &ma, b, &mb, SAMPLES);
                let what = format!("{name_a} vs {name_b}, case {case}");
                match (found, sampled) {
                    (Some(hit), Some(t)) => {
                        hits += 1;
                        assert!(hit.converged, "{what}: did not converge ({:?})", hit.stats);
                        assert!(
                            hit.time <= t,
                            "{what}: impact at {} after the overlap at {t}",
                            hit.time
                        );
                        // Overlap begins within a sample (and the
                        // tolerance's worth of travel) after the impact.
                        assert!(
                            t - hit.time <= 2.0 / SAMPLES as f64,
                            "{what}: impact at {}, overlap only at {t}",
                            hit.time
                        );
                        assert!(hit.distance <= options.target + options.tolerance);
                        assert!(hit.normal.is_normalized(), "{what}: normal {:?}", hit.normal);
                        assert!(
                            !overlap(a, &ma.pose_at(hit.time), b, &mb.pose_at(hit.time)),
                            "{what}: overlap at the impact"
                        );
                    }
                    (None, None) => misses += 1,
                    (Some(hit), None) => {
                        // A touch (within the tolerance) that the samples stepped over.
                        let pa = ma.pose_at(hit.time);
                        let mut out = Vec::new();
                        contact_shapes(
                            a,
                            &pa,
                            b,
                            &mb.pose_at(hit.time),
                            options.tolerance * 2.0,
                            &mut out,
                        )
                        .unwrap();
                        assert!(
                            !out.is_empty(),
                            "{what}: impact at {} but the shapes never meet",
                            hit.time
                        );
                    }
                    (None, Some(t)) => panic!("{what}: no impact found, overlap at {t}"),
                }
            }
        }
    }
    // The motions aim at the origin: most cases collide, some pass by.
    assert!(hits > 60 && misses > 10, "{hits} hits, {misses} misses");
}

#[test]
fn both_shapes_moving_and_the_half_space() {
    let mut r = rng(7);
    let ground = Shape::HalfSpace(HalfSpace::new(DVec3::Z, 0.0).unwrap());
    for (name, s) in shapes() {
        for case in 0..8 {
            // Dropped from 1-2 m to 1 m below the ground, tumbling.
            let q0 = random_rotation(&mut r);
            let start = Pose::new(DVec3::new(r(), r(), 1.0 + r()), q0).unwrap();
            let end = Pose::new(
                DVec3::new(r(), r(), -1.0),
                (random_rotation(&mut r) * q0).normalize(),
            )
            .unwrap();
            let m = Motion::between(start, end);
            let hit = time_of_impact(
                &s,
                &m,
                &ground,
                &Motion::fixed(Pose::IDENTITY),
                &ToiOptions::default(),
            )
            .unwrap()
            .unwrap_or_else(|| panic!("{name} {case}: no impact with the ground"));
            let t = first_overlap(&s, &m, &ground, &Motion::fixed(Pose::IDENTITY), 4000).unwrap();
            assert!(
                hit.time <= t && t - hit.time < 1e-3,
                "{name} {case}: {} vs {t}",
                hit.time
            );
            assert!(hit.normal.z > 0.999, "{name} {case}: normal {:?}", hit.normal);
        }
    }
    // Two spheres flying at each other: they meet where the gaps close.
    let ball = Shape::Sphere(Sphere::new(0.5).unwrap());
    let at = |x: f64| Pose::from_translation(DVec3::new(x, 0.0, 0.0));
    let hit = time_of_impact(
        &ball,
        &Motion::between(at(-5.0), at(5.0)),
        &ball,
        &Motion::between(at(5.0), at(-5.0)),
        &ToiOptions::default(),
    )
    .unwrap()
    .unwrap();
    // Centres 10 m apart close at 20 m per unit time until 1 m apart.
    assert!((hit.time - 9.0 / 20.0).abs() < 1e-5, "{}", hit.time);
    assert!(hit.normal.x < -0.999);
}

#[test]
fn a_rod_spinning_beside_a_wall_hits_it_when_its_tip_arrives() {
    // A 1 m rod (capsule, radius 2 cm) turns a quarter turn about its
    // centre, from along z towards x; a wall's face is 0.3 m from the
    // centre. The tip sphere touches when 0.5 sin(theta) + 0.02 = 0.3.
    let rod = Shape::Capsule(Capsule::new(0.02, 0.5).unwrap());
    let wall = Shape::Cuboid(Cuboid::new(DVec3::new(0.005, 2.0, 2.0)).unwrap());
    let quarter = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2);
    let spin = Motion::between(Pose::IDENTITY, Pose::new(DVec3::ZERO, quarter).unwrap());
    let wall_pose = Pose::from_translation(DVec3::new(0.305, 0.0, 0.0));
    let options = ToiOptions {
        tolerance: 1e-6,
        ..ToiOptions::default()
    };
    let hit = time_of_impact(&rod, &spin, &wall, &Motion::fixed(wall_pose), &options)
        .unwrap()
        .unwrap();
    let expected = (0.28f64 / 0.5).asin() / std::f64::consts::FRAC_PI_2;
    assert!((hit.time - expected).abs() < 1e-4, "{} vs {expected}", hit.time);
    assert!(hit.normal.x < -0.999);
    // Not a translation: the rod's centre never moves.
    assert_eq!(spin.pose_at(hit.time).position, DVec3::ZERO);
}

#[test]
fn bad_input_is_refused() {
    let ball = Shape::Sphere(Sphere::new(0.5).unwrap());
    let still = Motion::fixed(Pose::IDENTITY);
    let bad = |o: ToiOptions| time_of_impact(&ball, &still, &ball, &still, &o).unwrap_err();
    assert!(matches!(
        bad(ToiOptions {
            target: -1.0,
            ..ToiOptions::default()
        }),
        QueryError::BadOption {
            option: "ToiOptions::target",
            ..
        }
    ));
    assert!(matches!(
        bad(ToiOptions {
            tolerance: f64::NAN,
            ..ToiOptions::default()
        }),
        QueryError::BadOption {
            option: "ToiOptions::tolerance",
            ..
        }
    ));
    assert!(matches!(
        bad(ToiOptions {
            max_iterations: 0,
            ..ToiOptions::default()
        }),
        QueryError::BadOption {
            option: "ToiOptions::max_iterations",
            ..
        }
    ));
    let nan_pose = Pose {
        position: DVec3::new(f64::NAN, 0.0, 0.0),
        rotation: DQuat::IDENTITY,
    };
    let err = time_of_impact(
        &ball,
        &Motion::between(Pose::IDENTITY, nan_pose),
        &ball,
        &still,
        &ToiOptions::default(),
    );
    assert!(
        matches!(
            err,
            Err(QueryError::BadPose {
                which: "motion_a",
                ..
            })
        ),
        "{err:?}"
    );
    let ground = Shape::HalfSpace(HalfSpace::new(DVec3::Z, 0.0).unwrap());
    let turning = Motion::between(
        Pose::IDENTITY,
        Pose::new(DVec3::ZERO, DQuat::from_rotation_x(0.1)).unwrap(),
    );
    assert!(matches!(
        time_of_impact(&ball, &still, &ground, &turning, &ToiOptions::default()),
        Err(QueryError::BadOption { .. })
    ));
    assert!(matches!(
        time_of_impact(&ground, &still, &ground, &still, &ToiOptions::default()),
        Err(QueryError::Narrow(_))
    ));
}

/// Shapes touching or slightly overlapping a flat mesh slab at the start of
/// their motion get the slab's normal, not the direction of the round-off
/// between two closest points that coincide. The first pose is where the
/// projectile matrix (tumble's `scenes::projectile_cases`) met it: a hull of
/// an icosphere spinning at 190 rad/s along a slab turned by 60 degrees,
/// whose exact distance came out 0 with closest points 5e-16 m apart; the
/// normal of that difference put the body on the slab's far side and
/// continuous collision held it in place for good. The others are random
/// poses of every convex shape resting on the slab within 0.5 mm.
#[test]
fn shapes_touching_a_mesh_slab_at_the_start_get_its_normal() {
    let slab = Shape::Mesh(
        MeshShape::new(tumble_collide::mesh::box_mesh(DVec3::new(1.0, 1.0, 0.01)).unwrap()).unwrap(),
    );
    let turn = DQuat::from_rotation_y(60f64.to_radians());
    let slab_pose = Pose::new(DVec3::ZERO, turn).unwrap();
    let face = turn * DVec3::Z;
    let hull = Shape::ConvexHull(ConvexHull::from_mesh(&icosphere_mesh(0.05, 1).unwrap()).unwrap());
    let options = ToiOptions {
        target: 0.0025,
        tolerance: 0.00125,
        max_iterations: 64,
    };
    let normal_at_start = |shape: &Shape, start: Pose, end: Pose| {
        let hit = time_of_impact(
            shape,
            &Motion::new(start, end, DVec3::ZERO),
            &slab,
            &Motion::fixed(slab_pose),
            &options,
        )
        .unwrap()
        .expect("touching at the start");
        assert_eq!(hit.time, 0.0);
        hit.normal
    };
    // The pose the projectile matrix met (bits as traced), sliding off.
    let start = Pose::new(
        DVec3::new(0.4398560421521284, 6.155139569021796e-15, -0.6438872944553118),
        DQuat::from_xyzw(
            -5.572154496077951e-7,
            0.05712839809654763,
            4.645735657050637e-6,
            -0.99836683944782,
        ),
    )
    .unwrap();
    let end = Pose::new(
        DVec3::new(0.6689945138587156, -9.267128689810225e-11, -0.9950235973922759),
        DQuat::from_xyzw(
            -5.956699838882694e-6,
            -0.9986867652226836,
            2.1460406944395768e-5,
            -0.05123226008113505,
        ),
    )
    .unwrap();
    let n = normal_at_start(&hull, start, end);
    assert!(
        n.dot(face) > 0.99,
        "the traced hull: normal {n} against the face's {face}"
    );
    // Random resting poses of every convex shape, moving along the face.
    let mut r = rng(77);
    let convex: Vec<(&str, Shape)> = shapes().into_iter().filter(|(name, _)| *name != "mesh").collect();
    let along = turn * DVec3::X;
    for k in 0..200 {
        let (name, shape) = &convex[k % convex.len()];
        let q = random_rotation(&mut r);
        // Lowest point of the shape along -face at this orientation, by the
        // narrow phase against a half-space through the slab's top face.
        let probe = Pose::new(face * 5.0, q).unwrap();
        let plane = Shape::HalfSpace(HalfSpace::new(face, 0.0).unwrap());
        let mut out = Vec::new();
        contact_shapes(
            shape,
            &probe,
            &plane,
            &Pose::new(face * 0.01, DQuat::IDENTITY).unwrap(),
            10.0,
            &mut out,
        )
        .unwrap();
        let lowest = out.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min);
        let sink = 0.0005 * r();
        let offset = along * (r() - 0.5) + (turn * DVec3::Y) * (r() - 0.5);
        let start = Pose::new(face * (5.0 - lowest - sink) + offset, q).unwrap();
        let end = Pose::new(start.position + along * 0.3, q).unwrap();
        let n = normal_at_start(shape, start, end);
        assert!(
            n.dot(face) > 0.99,
            "{name} #{k}: normal {n} against the face's {face}"
        );
    }
}
