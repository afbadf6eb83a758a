//! A recorded world exports to a glTF whose animation reproduces the
//! simulated poses (read back with the `gltf` crate).

use tumble::collide::DVec3;
use tumble::export::{glb_bytes, WorldRecorder};
use tumble::scenes;

#[test]
fn recorded_ball_drop_round_trips_through_glb() {
    let (mut world, ids) = scenes::ball_drop(1.0, 0.5).build().unwrap();
    let mut recorder = WorldRecorder::new(&world).unwrap();
    for _ in 0..120 {
        world.step();
        recorder.record(&world);
    }
    let recording = recorder.finish();
    assert_eq!(recording.frames.len(), 121);
    assert_eq!(recording.bodies.len(), 2);
    assert!(recording.bodies[0].is_static && !recording.bodies[1].is_static);
    let bytes = glb_bytes(&recording).unwrap();
    let g = gltf::Gltf::from_slice(&bytes).unwrap();
    assert_eq!(g.nodes().count(), 3, "root + 2 bodies");
    let anim = g.animations().next().expect("the ball moves");
    let mut checked = false;
    for channel in anim.channels() {
        let reader = channel.reader(|_| g.blob.as_deref());
        let times: Vec<f32> = reader.read_inputs().unwrap().collect();
        assert_eq!(times.len(), 121);
        if let Some(gltf::animation::util::ReadOutputs::Translations(t)) = reader.read_outputs() {
            let last = t.last().unwrap();
            let x = world.center_of_mass(ids[1]).unwrap();
            assert!((last[0] as f64 - x.x).abs() < 1e-5 && (last[2] as f64 - x.z).abs() < 1e-5);
            checked = true;
        }
    }
    assert!(checked, "a translation channel was read back");
    // The ball fell: energy moved from potential to kinetic and back, and the
    // recorder kept a plot sample per frame.
    assert_eq!(recording.extras.len(), 121);
    assert!(
        recording.extras.iter().any(|e| e.contact_count > 0),
        "the bounce was recorded"
    );
}

/// Every shape kind (primitives, hulls, meshes from generators and from an
/// OBJ file, a half-space, a multi-shape body, a kinematic body) is drawn:
/// one node with a non-empty mesh and a material per body, translation and
/// rotation channels for each moving body, one key per frame, and the keys
/// equal the simulated poses.
#[test]
fn every_shape_kind_exports_with_its_animation() {
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/mixed_shapes.json");
    let loaded = tumble::scene::load_scene(&file).unwrap_or_else(|e| panic!("{e}"));
    let (mut world, ids) = loaded.build().unwrap();
    let mut recorder = WorldRecorder::new(&world).unwrap();
    let steps = 30;
    for _ in 0..steps {
        world.step();
        recorder.record(&world);
    }
    let recording = recorder.finish();
    let bytes = glb_bytes(&recording).unwrap();
    let g = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = g.blob.as_deref().unwrap();
    assert_eq!(g.nodes().count(), ids.len() + 1, "root + one node per body");
    assert_eq!(g.meshes().count(), ids.len());
    assert_eq!(g.materials().count(), ids.len());
    for mesh in g.meshes() {
        let prim = mesh.primitives().next().unwrap();
        let reader = prim.reader(|_| Some(blob));
        let n = reader.read_positions().unwrap().count();
        assert!(n >= 12 && n % 3 == 0, "mesh {:?} has {n} vertices", mesh.name());
    }
    let moving: Vec<usize> = (0..ids.len())
        .filter(|&b| world.body(ids[b]).unwrap().kind() != tumble::BodyKind::Static)
        .collect();
    let anim = g.animations().next().unwrap();
    assert_eq!(anim.channels().count(), 2 * moving.len());
    for channel in anim.channels() {
        let node = channel.target().node().index();
        let b = node - 1;
        assert!(moving.contains(&b), "channel on a static body's node {node}");
        let reader = channel.reader(|_| Some(blob));
        let times: Vec<f32> = reader.read_inputs().unwrap().collect();
        assert_eq!(times.len(), steps + 1);
        assert!((times[steps] as f64 - world.time()).abs() < 1e-6);
        let final_pose = world.pose(ids[b]).unwrap();
        match reader.read_outputs().unwrap() {
            gltf::animation::util::ReadOutputs::Translations(t) => {
                let last = t.last().unwrap();
                let x = final_pose.position;
                assert!((DVec3::new(last[0] as f64, last[1] as f64, last[2] as f64) - x).length() < 1e-5);
            }
            gltf::animation::util::ReadOutputs::Rotations(r) => {
                let last = r.into_f32().last().unwrap();
                let q = final_pose.rotation;
                let dot =
                    last[0] as f64 * q.x + last[1] as f64 * q.y + last[2] as f64 * q.z + last[3] as f64 * q.w;
                assert!(dot.abs() > 1.0 - 1e-6);
            }
            _ => panic!("unexpected channel"),
        }
    }
}

/// The live stream's frames built straight from the world are the frames the
/// recorder keeps (two ways to the same message), and a body added during a
/// session gets a `bodies_added` message and a pose after the others'.
#[test]
fn live_frames_from_the_world_equal_recorded_frames() {
    use tumble::collide::Sphere;
    use tumble::export::live::{bodies_added_message, frame_message, world_frame_message};
    use tumble::export::recorded_body;
    use tumble::world::BodyDesc;

    let (mut world, _) = scenes::tower(3).build().unwrap();
    let ids = world.body_ids();
    let mut recorder = WorldRecorder::new(&world).unwrap();
    for f in 1..=20 {
        world.step();
        recorder.record(&world);
        assert_eq!(
            world_frame_message(&world, &ids),
            frame_message(recorder.recording(), f).unwrap()
        );
    }
    let ball = world
        .add_body(&BodyDesc::dynamic(Sphere::new(0.2).unwrap()).at(DVec3::new(-3.0, 0.0, 1.0)))
        .unwrap();
    let added = recorded_body(&world, ball, ids.len()).unwrap();
    let msg: serde_json::Value = serde_json::from_str(&bodies_added_message(&[added])).unwrap();
    assert_eq!(msg["type"], "bodies_added");
    assert_eq!(msg["bodies"].as_array().unwrap().len(), 1);
    assert!(!msg["bodies"][0]["is_static"].as_bool().unwrap());
    let mut all = ids.clone();
    all.push(ball);
    world.step();
    let frame: serde_json::Value = serde_json::from_str(&world_frame_message(&world, &all)).unwrap();
    let poses = frame["poses"].as_array().unwrap();
    assert_eq!(poses.len(), ids.len() + 1);
    let x = world.center_of_mass(ball).unwrap();
    assert_eq!(poses[ids.len()][0].as_f64().unwrap(), x.x);
    assert_eq!(poses[ids.len()][2].as_f64().unwrap(), x.z);
}

/// Recordings are in the model frame the user placed the body in, as
/// `World::pose` reports it, not in the solver's body frame (centre of mass,
/// principal axes): a body whose box sits 1 m off its model origin keeps
/// that offset in the exported mesh, and the exported poses are the model
/// poses, so mesh and pose together put the box where the world has it.
#[test]
fn recordings_use_the_model_frame() {
    use tumble::collide::shape::{Cuboid, Shape};
    use tumble::collide::{DQuat, Pose};
    use tumble::world::{BodyDesc, ShapeDesc, World, WorldSettings};
    let mut world = World::new(WorldSettings {
        gravity: DVec3::ZERO,
        ..WorldSettings::default()
    })
    .unwrap();
    let offset = DVec3::new(1.0, 0.0, 0.0);
    let shape = ShapeDesc::new(Shape::Cuboid(Cuboid::new(DVec3::new(0.1, 0.2, 0.3)).unwrap()))
        .at(Pose::from_translation(offset));
    let id = world
        .add_body(&BodyDesc {
            shapes: vec![shape],
            pose: Pose::new(DVec3::new(0.0, 0.0, 2.0), DQuat::from_rotation_z(0.7)).unwrap(),
            angular_velocity: DVec3::new(0.3, -0.2, 1.0),
            ..BodyDesc::default()
        })
        .unwrap();
    let mut recorder = WorldRecorder::new(&world).unwrap();
    for _ in 0..30 {
        world.step();
        recorder.record(&world);
    }
    let rec = recorder.finish();
    let (lo, hi) = rec.bodies[0].mesh.bounds();
    assert!(
        ((lo + hi) * 0.5 - offset).length() < 1e-12,
        "mesh centre {:?}",
        (lo + hi) * 0.5
    );
    let last = rec.frames.last().unwrap()[0];
    let model = world.pose(id).unwrap();
    assert!((last.position - model.position).length() < 1e-12);
    assert!(last.rotation.dot(model.rotation).abs() > 1.0 - 1e-12);
    // Mesh centre placed by the exported pose = the world's centre of mass.
    let centre = last.transform_point((lo + hi) * 0.5);
    assert!((centre - world.center_of_mass(id).unwrap()).length() < 1e-9);
}
