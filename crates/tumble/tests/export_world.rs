//! A recorded world exports to a glTF whose animation reproduces the
//! simulated poses (read back with the `gltf` crate).

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
