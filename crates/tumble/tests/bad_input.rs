//! Every bad input of docs/validation.md at the Rust API, each checked for
//! its typed error and, where there is state, for leaving it unchanged: the
//! world's full snapshot is compared before and after every rejected call
//! (settings, bodies, arena, contact cache, time), so a half-applied change
//! cannot hide. The section comments match the table's sections.
//!
//! Cases are written out one by one with their labels (in
//! `world_calls_reject_bad_input_and_leave_the_world_unchanged` the settings
//! table, the body descriptions and the `rejects` calls per handle, pose and
//! force; further down the mesh loaders' asserts and the scene-file cases):
//! runs of them look alike by design, and a failure names its case.

use std::path::Path;
use tumble::collide::mesh::{self, LoadError, MeshError, TriMesh};
use tumble::collide::query::{
    collide, distance, within_tolerance, CollideOptions, DistanceOptions, QueryError, ReportMode,
};
use tumble::collide::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, ShapeError, Sphere};
use tumble::collide::{DQuat, DVec3, Pose, PoseError};
use tumble::scene::{parse_scene, Format, SceneError};
use tumble::world::{
    BodyDesc, BodyId, MassDesc, ShapeDesc, Snapshot, SnapshotError, World, WorldError, WorldSettings,
};

const NAN: f64 = f64::NAN;
const INF: f64 = f64::INFINITY;

fn sphere(r: f64) -> Shape {
    Shape::Sphere(Sphere::new(r).unwrap())
}

fn cube_mesh() -> TriMesh {
    mesh::box_mesh(DVec3::splat(0.5)).unwrap()
}

/// A world with a ground, a resting ball that has been stepped (so the
/// contact cache and time are not empty), a kinematic plate and a removed
/// body (a stale handle with a bumped slot generation).
fn base_world() -> (World, BodyId, BodyId, BodyId, BodyId) {
    let mut w = World::new(WorldSettings::default()).unwrap();
    let ground = w.add_body(&BodyDesc::fixed(HalfSpace::ground())).unwrap();
    let ball = w
        .add_body(&BodyDesc::dynamic(sphere(0.1)).at(DVec3::new(0.0, 0.0, 0.1)))
        .unwrap();
    let plate = w
        .add_body(
            &BodyDesc::kinematic(Cuboid::new(DVec3::new(0.5, 0.5, 0.05)).unwrap())
                .at(DVec3::new(3.0, 0.0, 1.0)),
        )
        .unwrap();
    let gone = w
        .add_body(&BodyDesc::dynamic(sphere(0.1)).at(DVec3::new(5.0, 0.0, 1.0)))
        .unwrap();
    w.remove_body(gone).unwrap();
    for _ in 0..5 {
        w.step();
    }
    (w, ground, ball, plate, gone)
}

/// Runs `call` on the world; it must fail with an error `expected` accepts,
/// and the world's snapshot must be the same before and after.
fn rejects(
    count: &mut usize,
    world: &mut World,
    what: &str,
    call: impl FnOnce(&mut World) -> Result<(), WorldError>,
    expected: Expected,
) {
    let before = world.snapshot();
    match call(world) {
        Ok(()) => panic!("{what}: accepted"),
        Err(e) => {
            assert!(expected(&e), "{what}: unexpected error {e:?}");
            assert!(!e.to_string().is_empty());
        }
    }
    assert!(world.snapshot() == before, "{what}: the world changed");
    *count += 1;
}

/// Which errors a case accepts.
type Expected = fn(&WorldError) -> bool;

fn bad_value(e: &WorldError) -> bool {
    matches!(e, WorldError::BadValue { .. })
}
fn bad_shape(e: &WorldError) -> bool {
    matches!(e, WorldError::BadShape { .. })
}
fn stale(e: &WorldError) -> bool {
    matches!(e, WorldError::StaleBody(_))
}
fn wrong_kind(e: &WorldError) -> bool {
    matches!(e, WorldError::WrongKind { .. })
}
fn no_shapes(e: &WorldError) -> bool {
    matches!(e, WorldError::NoShapes)
}

#[test]
fn world_calls_reject_bad_input_and_leave_the_world_unchanged() {
    let (mut w, ground, ball, plate, gone) = base_world();
    let mut n = 0;
    let c = &mut n;

    // -- Settings (World::new and set_settings share the checks).
    let settings_cases: Vec<(&str, WorldSettings)> = vec![
        (
            "dt = 0",
            WorldSettings {
                dt: 0.0,
                ..Default::default()
            },
        ),
        (
            "dt < 0",
            WorldSettings {
                dt: -1.0 / 60.0,
                ..Default::default()
            },
        ),
        (
            "dt below MIN_DT (the smallest f64)",
            WorldSettings {
                dt: 5e-324,
                ..Default::default()
            },
        ),
        (
            "dt below MIN_DT",
            WorldSettings {
                dt: 1e-10,
                ..Default::default()
            },
        ),
        (
            "dt = NaN",
            WorldSettings {
                dt: NAN,
                ..Default::default()
            },
        ),
        (
            "dt = inf",
            WorldSettings {
                dt: INF,
                ..Default::default()
            },
        ),
        (
            "dt huge (> 1 s)",
            WorldSettings {
                dt: 1e9,
                ..Default::default()
            },
        ),
        (
            "gravity NaN",
            WorldSettings {
                gravity: DVec3::new(0.0, 0.0, NAN),
                ..Default::default()
            },
        ),
        (
            "substeps 0",
            WorldSettings {
                substeps: 0,
                ..Default::default()
            },
        ),
        (
            "substeps 65",
            WorldSettings {
                substeps: 65,
                ..Default::default()
            },
        ),
        (
            "iterations 0",
            WorldSettings {
                iterations: 0,
                ..Default::default()
            },
        ),
        (
            "iterations 1001",
            WorldSettings {
                iterations: 1001,
                ..Default::default()
            },
        ),
        (
            "push_out_iterations 1001",
            WorldSettings {
                push_out_iterations: 1001,
                ..Default::default()
            },
        ),
        (
            "push_out_fraction 0",
            WorldSettings {
                push_out_fraction: 0.0,
                ..Default::default()
            },
        ),
        (
            "push_out_fraction 1.5",
            WorldSettings {
                push_out_fraction: 1.5,
                ..Default::default()
            },
        ),
        (
            "contact_margin < 0",
            WorldSettings {
                contact_margin: -0.01,
                ..Default::default()
            },
        ),
        (
            "mesh_contact_margin NaN",
            WorldSettings {
                mesh_contact_margin: NAN,
                ..Default::default()
            },
        ),
        (
            "allowed_penetration NaN",
            WorldSettings {
                allowed_penetration: NAN,
                ..Default::default()
            },
        ),
        (
            "max_push_out_speed 0",
            WorldSettings {
                max_push_out_speed: 0.0,
                ..Default::default()
            },
        ),
        (
            "restitution_threshold < 0",
            WorldSettings {
                restitution_threshold: -1.0,
                ..Default::default()
            },
        ),
        (
            "sleep_linear_speed inf",
            WorldSettings {
                sleep_linear_speed: INF,
                ..Default::default()
            },
        ),
        (
            "sleep_angular_speed < 0",
            WorldSettings {
                sleep_angular_speed: -1.0,
                ..Default::default()
            },
        ),
        (
            "time_to_sleep NaN",
            WorldSettings {
                time_to_sleep: NAN,
                ..Default::default()
            },
        ),
    ];
    for (what, s) in settings_cases {
        assert!(
            matches!(World::new(s.clone()), Err(WorldError::BadValue { .. })),
            "new: {what}"
        );
        rejects(c, &mut w, what, |w| w.set_settings(s), bad_value);
    }

    // -- Body descriptions.
    let dynamic = || BodyDesc::dynamic(sphere(0.2)).at(DVec3::new(0.0, 2.0, 1.0));
    let descs: Vec<(&str, BodyDesc, Expected)> = vec![
        ("no shapes", BodyDesc::default(), no_shapes),
        (
            "no shapes on a static body",
            BodyDesc {
                kind: tumble::body::BodyKind::Static,
                ..BodyDesc::default()
            },
            no_shapes,
        ),
        ("mass 0", dynamic().with_mass(0.0), bad_value),
        ("mass < 0", dynamic().with_mass(-1.0), bad_value),
        ("mass NaN", dynamic().with_mass(NAN), bad_value),
        ("mass inf", dynamic().with_mass(INF), bad_value),
        (
            "mass subnormal (inverse overflows)",
            dynamic().with_mass(5e-324),
            bad_shape,
        ),
        ("density 0", dynamic().with_density(0.0), bad_value),
        ("density < 0", dynamic().with_density(-1000.0), bad_value),
        ("density NaN", dynamic().with_density(NAN), bad_value),
        ("position NaN", dynamic().at(DVec3::new(NAN, 0.0, 0.0)), bad_value),
        ("position inf", dynamic().at(DVec3::new(0.0, INF, 0.0)), bad_value),
        (
            "zero quaternion",
            dynamic().with_pose(Pose {
                position: DVec3::ZERO,
                rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            }),
            bad_value,
        ),
        (
            "non-unit quaternion (rejected, not normalised)",
            dynamic().with_pose(Pose {
                position: DVec3::ZERO,
                rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0),
            }),
            bad_value,
        ),
        (
            "NaN quaternion",
            dynamic().with_pose(Pose {
                position: DVec3::ZERO,
                rotation: DQuat::from_xyzw(NAN, 0.0, 0.0, 1.0),
            }),
            bad_value,
        ),
        (
            "linear velocity inf",
            dynamic().with_velocity(DVec3::new(INF, 0.0, 0.0), DVec3::ZERO),
            bad_value,
        ),
        (
            "angular velocity NaN",
            dynamic().with_velocity(DVec3::ZERO, DVec3::new(0.0, NAN, 0.0)),
            bad_value,
        ),
        ("friction < 0", dynamic().with_material(-0.5, 0.0), bad_value),
        ("friction NaN", dynamic().with_material(NAN, 0.0), bad_value),
        ("restitution > 1", dynamic().with_material(0.5, 1.5), bad_value),
        ("restitution < 0", dynamic().with_material(0.5, -0.1), bad_value),
        (
            "linear damping < 0",
            BodyDesc {
                linear_damping: -1.0,
                ..dynamic()
            },
            bad_value,
        ),
        (
            "angular damping inf",
            BodyDesc {
                angular_damping: INF,
                ..dynamic()
            },
            bad_value,
        ),
        (
            "dynamic half-space",
            BodyDesc::dynamic(HalfSpace::ground()),
            bad_shape,
        ),
        (
            "kinematic half-space",
            BodyDesc::kinematic(HalfSpace::ground()),
            bad_shape,
        ),
        (
            "static body with a velocity",
            BodyDesc::fixed(sphere(0.2)).with_velocity(DVec3::X, DVec3::ZERO),
            bad_value,
        ),
        (
            "shape local pose NaN",
            BodyDesc {
                shapes: vec![ShapeDesc::new(sphere(0.2)).at(Pose {
                    position: DVec3::new(NAN, 0.0, 0.0),
                    rotation: DQuat::IDENTITY,
                })],
                ..dynamic()
            },
            bad_shape,
        ),
        (
            "shape local quaternion non-unit",
            BodyDesc {
                shapes: vec![ShapeDesc::new(sphere(0.2)).at(Pose {
                    position: DVec3::ZERO,
                    rotation: DQuat::from_xyzw(0.1, 0.0, 0.0, 1.0),
                })],
                ..dynamic()
            },
            bad_shape,
        ),
        (
            "open mesh with a density (a closed one is needed for mass)",
            BodyDesc::dynamic(
                MeshShape::new(
                    TriMesh::new(
                        cube_mesh().vertices().to_vec(),
                        cube_mesh().triangles()[..10].to_vec(),
                    )
                    .unwrap(),
                )
                .unwrap(),
            ),
            bad_shape,
        ),
        (
            "mesh wound inside out",
            BodyDesc::dynamic(
                MeshShape::new(
                    TriMesh::new(
                        cube_mesh().vertices().to_vec(),
                        cube_mesh()
                            .triangles()
                            .iter()
                            .map(|t| [t[0], t[2], t[1]])
                            .collect(),
                    )
                    .unwrap(),
                )
                .unwrap(),
            ),
            bad_shape,
        ),
        (
            "flat (zero-volume) closed mesh",
            BodyDesc::dynamic(
                MeshShape::new(
                    TriMesh::new(
                        vec![DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::X * 3.0],
                        vec![[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]],
                    )
                    .unwrap(),
                )
                .unwrap(),
            ),
            bad_shape,
        ),
        (
            "mass given for a massless compound (mass spread over zero volume)",
            BodyDesc {
                mass: MassDesc::Mass(1.0),
                ..BodyDesc::dynamic(
                    MeshShape::new(
                        TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 2]]).unwrap(),
                    )
                    .unwrap(),
                )
            },
            bad_shape,
        ),
        (
            "body placed beyond MAX_POSITION (1e37 m)",
            BodyDesc::dynamic(sphere(0.1)).at(DVec3::new(0.0, 1e37, 0.0)),
            bad_value,
        ),
        (
            // libFuzzer: the body's centre of mass, 1.8e308 m off, overflowed
            // to infinity (fuzz/regressions/world_step/far_shape_offset).
            "shape placed 1.8e308 m from its body (finite, beyond MAX_POSITION)",
            BodyDesc {
                shapes: vec![ShapeDesc::new(sphere(0.1)).at(Pose::new(
                    DVec3::new(-1.0, f64::MAX, 0.5),
                    DQuat::IDENTITY,
                )
                .unwrap())],
                ..BodyDesc::dynamic(sphere(0.1))
            },
            bad_shape,
        ),
        (
            "centre of mass beyond MAX_POSITION (two shapes each within it)",
            BodyDesc {
                shapes: vec![
                    ShapeDesc::new(sphere(0.1))
                        .at(Pose::new(DVec3::new(1e36, 0.0, 0.0), DQuat::IDENTITY).unwrap()),
                    ShapeDesc::new(sphere(0.1))
                        .at(Pose::new(DVec3::new(1e36, 0.0, 0.0), DQuat::IDENTITY).unwrap()),
                ],
                ..BodyDesc::dynamic(sphere(0.1)).at(DVec3::new(1e36, 0.0, 0.0))
            },
            bad_value,
        ),
    ];
    for (what, desc, expected) in descs {
        rejects(c, &mut w, what, |w| w.add_body(&desc).map(|_| ()), expected);
    }

    // -- Handles: removing twice, stale handles everywhere, handles from nowhere.
    let nowhere = BodyId {
        index: 999,
        generation: 0,
    };
    for (label, id) in [("removed body", gone), ("never-added body", nowhere)] {
        rejects(
            c,
            &mut w,
            &format!("remove {label}"),
            |w| w.remove_body(id),
            stale,
        );
        rejects(
            c,
            &mut w,
            &format!("set_pose {label}"),
            |w| w.set_pose(id, Pose::IDENTITY),
            stale,
        );
        rejects(
            c,
            &mut w,
            &format!("set_velocity {label}"),
            |w| w.set_velocity(id, DVec3::X, DVec3::ZERO),
            stale,
        );
        rejects(
            c,
            &mut w,
            &format!("apply_force {label}"),
            |w| w.apply_force(id, DVec3::X),
            stale,
        );
        rejects(
            c,
            &mut w,
            &format!("apply_torque {label}"),
            |w| w.apply_torque(id, DVec3::X),
            stale,
        );
        rejects(
            c,
            &mut w,
            &format!("apply_impulse_at_point {label}"),
            |w| w.apply_impulse_at_point(id, DVec3::X, DVec3::ZERO),
            stale,
        );
        rejects(c, &mut w, &format!("wake {label}"), |w| w.wake(id), stale);
        rejects(
            c,
            &mut w,
            &format!("read pose of {label}"),
            |w| w.pose(id).map(|_| ()),
            stale,
        );
        rejects(
            c,
            &mut w,
            &format!("read body of {label}"),
            |w| w.body(id).map(|_| ()),
            stale,
        );
    }
    // A reused slot: the old handle stays stale (generation check).
    let mut w2 = w.clone();
    let reused = w2
        .add_body(&BodyDesc::dynamic(sphere(0.1)).at(DVec3::new(9.0, 0.0, 1.0)))
        .unwrap();
    assert_eq!(reused.index, gone.index, "slot reused");
    rejects(
        c,
        &mut w2,
        "stale handle to a reused slot",
        |w| w.apply_force(gone, DVec3::X),
        stale,
    );

    // -- Poses, velocities, forces on live bodies.
    let bad_poses = [
        (
            "set_pose NaN position",
            Pose {
                position: DVec3::new(NAN, 0.0, 0.0),
                rotation: DQuat::IDENTITY,
            },
        ),
        (
            "set_pose zero quaternion",
            Pose {
                position: DVec3::ZERO,
                rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            },
        ),
        (
            "set_pose non-unit quaternion",
            Pose {
                position: DVec3::ZERO,
                rotation: DQuat::from_xyzw(1.0, 1.0, 1.0, 1.0),
            },
        ),
        (
            "set_pose beyond MAX_POSITION",
            Pose {
                position: DVec3::new(-2e36, 0.0, 0.0),
                rotation: DQuat::IDENTITY,
            },
        ),
    ];
    for (what, pose) in bad_poses {
        rejects(c, &mut w, what, |w| w.set_pose(ball, pose), bad_value);
    }
    rejects(
        c,
        &mut w,
        "set_velocity NaN",
        |w| w.set_velocity(ball, DVec3::new(NAN, 0.0, 0.0), DVec3::ZERO),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "set_velocity angular inf",
        |w| w.set_velocity(ball, DVec3::ZERO, DVec3::splat(INF)),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "set_velocity kinematic NaN",
        |w| w.set_velocity(plate, DVec3::splat(NAN), DVec3::ZERO),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "set_velocity of a static body",
        |w| w.set_velocity(ground, DVec3::X, DVec3::ZERO),
        wrong_kind,
    );
    rejects(
        c,
        &mut w,
        "apply_force NaN",
        |w| w.apply_force(ball, DVec3::new(NAN, 0.0, 0.0)),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "apply_force inf",
        |w| w.apply_force(ball, DVec3::new(0.0, INF, 0.0)),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "apply_torque NaN",
        |w| w.apply_torque(ball, DVec3::splat(NAN)),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "apply_force_at_point NaN point",
        |w| w.apply_force_at_point(ball, DVec3::X, DVec3::new(NAN, 0.0, 0.0)),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "apply_force_at_point torque overflows",
        |w| w.apply_force_at_point(ball, DVec3::X * 1e300, DVec3::Y * 1e300),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "apply_impulse_at_point inf",
        |w| w.apply_impulse_at_point(ball, DVec3::splat(INF), DVec3::ZERO),
        bad_value,
    );
    rejects(
        c,
        &mut w,
        "force on a static body",
        |w| w.apply_force(ground, DVec3::X),
        wrong_kind,
    );
    rejects(
        c,
        &mut w,
        "force on a kinematic body",
        |w| w.apply_force(plate, DVec3::X),
        wrong_kind,
    );
    rejects(
        c,
        &mut w,
        "torque on a static body",
        |w| w.apply_torque(ground, DVec3::X),
        wrong_kind,
    );

    println!("world calls: {n} bad inputs rejected, world unchanged after each");
    assert!(n >= 80, "{n}");
}

#[test]
fn restoring_a_bad_snapshot_leaves_the_world_unchanged() {
    let (mut w, ..) = base_world();
    let before = w.snapshot();
    let mut other_version = before.clone();
    other_version.format_version = 0;
    let cases: Vec<(&str, Result<Snapshot, SnapshotError>)> = vec![
        ("older version", Ok(other_version)),
        ("empty bytes", Snapshot::from_bytes(&[])),
        ("truncated", Snapshot::from_bytes(&before.to_bytes()[..30])),
        ("not JSON", Snapshot::from_json("not json")),
        (
            "dt < 0 in JSON",
            Snapshot::from_json(
                &before
                    .to_json()
                    .replacen("\"dt\":0.016666666666666666", "\"dt\":-1.0", 1),
            ),
        ),
    ];
    for (what, snap) in cases {
        let result = snap.and_then(|s| w.restore(&s));
        assert!(result.is_err(), "{what}: accepted");
        assert!(w.snapshot() == before, "{what}: the world changed");
    }
}

#[test]
fn shape_constructors_reject_bad_dimensions() {
    let dims = [0.0, -1.0, NAN, INF, -INF];
    for d in dims {
        assert!(
            matches!(Sphere::new(d), Err(ShapeError::BadDimension { .. })),
            "sphere {d}"
        );
        assert!(
            matches!(
                Cuboid::new(DVec3::new(1.0, d, 1.0)),
                Err(ShapeError::BadDimension { .. })
            ),
            "box {d}"
        );
        assert!(
            matches!(Capsule::new(d, 1.0), Err(ShapeError::BadDimension { .. })),
            "capsule r {d}"
        );
        if d != 0.0 {
            assert!(
                matches!(Capsule::new(1.0, d), Err(ShapeError::BadDimension { .. })),
                "capsule h {d}"
            );
        }
    }
    for normal in [DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0), DVec3::new(NAN, 0.0, 1.0)] {
        assert!(
            matches!(HalfSpace::new(normal, 0.0), Err(ShapeError::NotUnit { .. })),
            "{normal:?}"
        );
    }
    assert!(matches!(
        HalfSpace::new(DVec3::Z, NAN),
        Err(ShapeError::BadDimension { .. })
    ));
    // Convex hulls: too few, coplanar, non-finite points; open, non-convex meshes.
    let collinear = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::X * 3.0];
    let coplanar = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE.with_z(0.0)];
    assert!(matches!(
        ConvexHull::from_points(&[DVec3::ZERO; 3]),
        Err(ShapeError::Hull(_))
    ));
    assert!(matches!(
        ConvexHull::from_points(&collinear),
        Err(ShapeError::Hull(_))
    ));
    assert!(matches!(
        ConvexHull::from_points(&coplanar),
        Err(ShapeError::Hull(_))
    ));
    let nan_points = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, NAN)];
    assert!(ConvexHull::from_points(&nan_points).is_err());
    let open = TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 2]]).unwrap();
    assert!(matches!(
        ConvexHull::from_mesh(&open),
        Err(ShapeError::Mesh(MeshError::Open { .. }))
    ));
    let torus = mesh::torus_mesh(1.0, 0.3, 12, 8).unwrap();
    assert!(matches!(
        ConvexHull::from_mesh(&torus),
        Err(ShapeError::NotConvex { .. })
    ));
    // Mesh shapes: coordinates beyond the OBBTree's range.
    let far = TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y * 1e300], vec![[0, 1, 2]]).unwrap();
    assert!(matches!(MeshShape::new(far), Err(ShapeError::Bvh(_))));
}

#[test]
fn meshes_generators_and_loaders_reject_bad_input() {
    let v = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    assert!(matches!(
        TriMesh::new(vec![], vec![]),
        Err(MeshError::Empty { .. })
    ));
    assert!(matches!(
        TriMesh::new(v.clone(), vec![]),
        Err(MeshError::Empty { .. })
    ));
    assert!(matches!(
        TriMesh::new(v.clone(), vec![[0, 1, 3]]),
        Err(MeshError::IndexOutOfRange { .. })
    ));
    assert!(matches!(
        TriMesh::from_indices(v.clone(), &[[0i64, -1, 2]]),
        Err(MeshError::IndexOutOfRange { .. })
    ));
    assert!(matches!(
        TriMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(0.0, NAN, 0.0)],
            vec![[0, 1, 2]]
        ),
        Err(MeshError::NonFiniteVertex { index: 2, .. })
    ));
    // Closedness where a solid is needed.
    let cube = cube_mesh();
    let open = TriMesh::new(cube.vertices().to_vec(), cube.triangles()[..11].to_vec()).unwrap();
    assert!(matches!(open.check_solid(), Err(MeshError::Open { .. })));
    let mut flipped = cube.triangles().to_vec();
    flipped[0] = [flipped[0][0], flipped[0][2], flipped[0][1]];
    let flipped = TriMesh::new(cube.vertices().to_vec(), flipped).unwrap();
    assert!(matches!(
        flipped.check_solid(),
        Err(MeshError::InconsistentWinding { .. })
    ));
    let mut doubled = cube.triangles().to_vec();
    doubled.push(doubled[0]);
    assert!(TriMesh::new(cube.vertices().to_vec(), doubled)
        .unwrap()
        .check_solid()
        .is_err());
    // Generators: dimensions, resolutions, sizes.
    assert!(mesh::box_mesh(DVec3::new(1.0, 0.0, 1.0)).is_err());
    assert!(mesh::uv_sphere_mesh(1.0, 2, 8).is_err());
    assert!(mesh::icosphere_mesh(1.0, 9).is_err());
    assert!(mesh::torus_mesh(1.0, 1.5, 8, 8).is_err(), "r >= R");
    assert!(
        mesh::torus_mesh(1.0, 0.2, 1 << 20, 1 << 20).is_err(),
        "2^41 triangles"
    );
    assert!(mesh::cylinder_mesh(NAN, 1.0, 8).is_err());
    // Loaders: empty, garbage, unknown, missing.
    assert!(matches!(
        mesh::obj_from_bytes(b""),
        Err(LoadError::EmptyFile { .. })
    ));
    assert!(matches!(
        mesh::obj_from_bytes(b"  \n\t"),
        Err(LoadError::EmptyFile { .. })
    ));
    assert!(
        mesh::obj_from_bytes(b"v 0 0 0\nf 1 2 3\n").is_err(),
        "face past the vertices"
    );
    assert!(mesh::obj_from_bytes(b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").is_err());
    assert!(mesh::stl_from_bytes(b"").is_err());
    assert!(mesh::stl_from_bytes(&[0u8; 10]).is_err(), "truncated binary STL");
    assert!(mesh::stl_from_bytes(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n").is_err());
    assert!(matches!(
        mesh::load_mesh("mesh.ply"),
        Err(LoadError::UnknownFormat { .. })
    ));
    assert!(matches!(
        mesh::load_mesh("/no/such/file.obj"),
        Err(LoadError::Io { .. })
    ));
}

#[test]
fn queries_reject_bad_poses_and_options() {
    let cube = MeshShape::new(cube_mesh()).unwrap();
    let id = Pose::IDENTITY;
    let bad_poses = [
        Pose {
            position: DVec3::new(NAN, 0.0, 0.0),
            rotation: DQuat::IDENTITY,
        },
        Pose {
            position: DVec3::new(INF, 0.0, 0.0),
            rotation: DQuat::IDENTITY,
        },
        Pose {
            position: DVec3::ZERO,
            rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
        },
        Pose {
            position: DVec3::ZERO,
            rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0),
        },
        Pose {
            position: DVec3::ZERO,
            rotation: DQuat::from_xyzw(NAN, 0.0, 0.0, 1.0),
        },
    ];
    // tumble-collide/tests/query_oracle.rs `bad_input_gets_typed_errors` checks
    // such poses on the query crate itself; here, the validation.md rows via tumble.
    for p in bad_poses {
        let opts = CollideOptions::default();
        assert!(matches!(
            collide(&cube, &p, &cube, &id, &opts),
            Err(QueryError::BadPose { which: "pose_a", .. })
        ));
        assert!(matches!(
            collide(&cube, &id, &cube, &p, &opts),
            Err(QueryError::BadPose { which: "pose_b", .. })
        ));
        assert!(matches!(
            distance(&cube, &p, &cube, &id, &DistanceOptions::default()),
            Err(QueryError::BadPose { .. })
        ));
        assert!(matches!(
            within_tolerance(&cube, &id, &cube, &p, 0.1),
            Err(QueryError::BadPose { .. })
        ));
    }
    let far = Pose::from_translation(DVec3::X * 3.0);
    for margin in [-1.0, NAN, INF] {
        let opts = CollideOptions {
            report: ReportMode::Contacts,
            contact_margin: margin,
            ..Default::default()
        };
        assert!(matches!(
            collide(&cube, &id, &cube, &far, &opts),
            Err(QueryError::BadOption { .. })
        ));
        let d = DistanceOptions {
            rel_err: margin,
            abs_err: 0.0,
        };
        assert!(matches!(
            distance(&cube, &id, &cube, &far, &d),
            Err(QueryError::BadOption { .. })
        ));
        assert!(matches!(
            within_tolerance(&cube, &id, &cube, &far, margin),
            Err(QueryError::BadOption { .. })
        ));
    }
    // Poses: zero and non-unit quaternions are rejected, near-unit ones
    // (within 1e-6) normalised; Pose::new_normalized opts into normalising.
    assert!(matches!(
        Pose::new(DVec3::ZERO, DQuat::from_xyzw(0.0, 0.0, 0.0, 1.5)),
        Err(PoseError::NonUnitRotation { .. })
    ));
    assert!(Pose::new(DVec3::ZERO, DQuat::from_xyzw(0.0, 0.0, 0.0, 1.0 + 1e-7)).is_ok());
    assert!(Pose::new_normalized(DVec3::ZERO, DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0)).is_err());
}

#[test]
fn scene_files_reject_bad_input_with_a_located_error() {
    let file = Path::new("bad.toml");
    let cases = [
        ("empty file", ""),
        ("syntax error", "[[bodies]\n"),
        ("unknown key", "[[bodies]]\nshape = \"x\"\nmasss = 1\n"),
        ("no bodies", "name = \"x\"\n"),
        ("dt < 0", "[settings]\ndt = -0.01\n[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.1 }]\n"),
        ("dt huge", "[settings]\ndt = 1e9\n[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.1 }]\n"),
        ("dt NaN", "[settings]\ndt = nan\n[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.1 }]\n"),
        ("mass 0", "[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.1 }]\nmass = 0\n"),
        ("radius < 0", "[[bodies]]\nshapes = [{ type = \"sphere\", radius = -0.1 }]\n"),
        ("position inf", "[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.1 }]\nposition = [inf, 0, 0]\n"),
        (
            "zero quaternion",
            "[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.1 }]\norientation = [0, 0, 0, 0]\n",
        ),
        ("grid too large", "[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.1 }]\ngrid = { count = [10000, 10000, 10000], spacing = [1, 1, 1] }\n"),
        ("missing mesh file", "[[bodies]]\nkind = \"static\"\nshapes = [{ type = \"mesh\", mesh = { file = \"no_such.obj\" } }]\n"),
        (
            "mesh too fine",
            "[[bodies]]\nkind = \"static\"\nshapes = [{ type = \"mesh\", mesh = { torus = { major_radius = 1, minor_radius = 0.2, n_major = 1000000, n_minor = 1000000 } } }]\n",
        ),
    ];
    for (what, text) in cases {
        match parse_scene(text, Format::Toml, file).and_then(|s| s.build().map(|_| ())) {
            Ok(()) => panic!("{what}: accepted"),
            Err(SceneError::At {
                file: f,
                line,
                column,
                path,
                message,
            }) => {
                assert_eq!(f, file, "{what}");
                assert!(line >= 1 && column >= 1, "{what}");
                let expect = match what {
                    "missing mesh file" => "cannot read",
                    "mesh too fine" => "triangles requested",
                    "empty file" | "no bodies" => "at least one body",
                    "unknown key" => "unknown field",
                    _ => "",
                };
                assert!(message.contains(expect), "{what}: {path}: {message}");
            }
            Err(e) => panic!("{what}: not located: {e}"),
        }
    }
    assert!(matches!(
        parse_scene("{", Format::Json, Path::new("bad.json")),
        Err(SceneError::At { .. })
    ));
    assert!(matches!(
        tumble::scene::load_scene("scene.yaml"),
        Err(SceneError::Format { .. })
    ));
    assert!(matches!(
        tumble::scene::load_scene("/no/such/scene.toml"),
        Err(SceneError::Read { .. })
    ));
}
