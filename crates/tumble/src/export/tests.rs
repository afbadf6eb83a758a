//! Round-trip tests: recordings with analytic motion are written, read back
//! with the independent `gltf` crate, and compared with the input.

use std::path::PathBuf;

use proptest::prelude::*;
use serde_json::Value;
use tumble_collide::mesh::{box_mesh, icosphere_mesh, torus_mesh};
use tumble_collide::{DQuat, DVec3, Pose, TriMesh};

use super::csv::{trajectory_csv, CSV_HEADER};
use super::*;

const G: f64 = 9.81;
const Z0: f64 = 2.0;
const SPIN_RATE: f64 = 3.0; // rad/s

fn spin_axis() -> DVec3 {
    DVec3::new(1.0, 2.0, 3.0).normalize()
}

fn falling_z(t: f64) -> f64 {
    Z0 - 0.5 * G * t * t
}

fn body(name: &str, mesh: TriMesh, is_static: bool) -> RecordedBody {
    RecordedBody {
        name: name.to_string(),
        mesh,
        color: [0.2, 0.5, 0.8, 1.0],
        is_static,
    }
}

/// A static ground slab, a box falling freely from rest and a torus spinning
/// at a constant rate about a tilted axis, sampled analytically.
fn scene(n_frames: usize) -> Recording {
    let bodies = vec![
        body("ground", box_mesh(DVec3::new(2.0, 2.0, 0.1)).unwrap(), true),
        body("faller", box_mesh(DVec3::new(0.1, 0.2, 0.3)).unwrap(), false),
        body("spinner", torus_mesh(0.3, 0.1, 12, 6).unwrap(), false),
    ];
    let frame_times: Vec<f64> = (0..n_frames).map(|f| f as f64 / 30.0).collect();
    let frames = frame_times
        .iter()
        .map(|&t| {
            vec![
                Pose::from_translation(DVec3::new(0.0, 0.0, -0.1)),
                Pose::from_translation(DVec3::new(0.5, 0.0, falling_z(t))),
                Pose::new(
                    DVec3::new(-1.0, 0.5, 1.0),
                    DQuat::from_axis_angle(spin_axis(), SPIN_RATE * t),
                )
                .unwrap(),
            ]
        })
        .collect();
    Recording {
        bodies,
        frame_times,
        frames,
        ..Default::default()
    }
}

fn read(bytes: &[u8]) -> gltf::Gltf {
    gltf::Gltf::from_slice(bytes).expect("gltf crate accepts the file")
}

/// The JSON chunk, parsed independently of the `gltf` crate.
fn json_chunk(bytes: &[u8]) -> Value {
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + len]).unwrap()
}

fn close3(a: [f32; 3], b: DVec3) -> bool {
    (DVec3::from(a.map(f64::from)) - b).abs().max_element() <= 1e-6 * (1.0 + b.abs().max_element())
}

fn temp_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tumble-export-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn nodes_meshes_and_root_rotation() {
    let rec = scene(31);
    let g = read(&glb_bytes(&rec).unwrap());
    let nodes: Vec<_> = g.nodes().collect();
    assert_eq!(nodes.len(), 1 + rec.bodies.len());
    let scene = g.default_scene().unwrap();
    let roots: Vec<_> = scene.nodes().collect();
    assert_eq!(roots.len(), 1, "one root node carries the axis change");
    let root = &roots[0];
    assert_eq!(root.children().count(), rec.bodies.len());

    // The root rotation must take tumble's up (z) to glTF's up (y), keep x,
    // and send y to -z (right-handed).
    let (_, r, _) = root.transform().decomposed();
    let q = DQuat::from_array(r.map(f64::from));
    assert!((q * DVec3::Z - DVec3::Y).length() < 1e-6);
    assert!((q * DVec3::X - DVec3::X).length() < 1e-6);
    assert!((q * DVec3::Y + DVec3::Z).length() < 1e-6);

    for (b, node) in root.children().enumerate() {
        let body = &rec.bodies[b];
        assert_eq!(node.name(), Some(body.name.as_str()));
        // Node-local rest transform = frame-0 pose, unchanged.
        let (t, r, s) = node.transform().decomposed();
        assert!(close3(t, rec.frames[0][b].position));
        assert_eq!(s, [1.0, 1.0, 1.0]);
        let q = DQuat::from_array(r.map(f64::from));
        assert!(q.dot(rec.frames[0][b].rotation).abs() > 1.0 - 1e-6);

        let prim = node.mesh().unwrap().primitives().next().unwrap();
        let color = prim.material().pbr_metallic_roughness().base_color_factor();
        assert_eq!(color, body.color);
        let reader = prim.reader(|_| g.blob.as_deref());
        let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let nrm: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
        assert_eq!(pos.len(), 3 * body.mesh.triangles().len());
        assert_eq!(nrm.len(), pos.len());
        // Non-indexed, in triangle order: vertex 3t + k is corner k of triangle t.
        assert!(prim.indices().is_none());
        for t in 0..body.mesh.triangles().len() {
            let tri = body.mesh.triangle(t);
            for k in 0..3 {
                assert!(close3(pos[3 * t + k], tri[k]));
            }
            // Flat shading: all three normals equal the unit face normal,
            // perpendicular to both edges and pointing along (b-a)x(c-a).
            let face = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
            for k in 0..3 {
                assert_eq!(nrm[3 * t + k], nrm[3 * t]);
            }
            let n = DVec3::from(nrm[3 * t].map(f64::from));
            assert!((n.length() - 1.0).abs() < 1e-6);
            assert!(n.dot(tri[1] - tri[0]).abs() < 1e-5);
            assert!(n.dot(tri[2] - tri[0]).abs() < 1e-5);
            assert!(n.dot(face) > 0.0);
        }
        // POSITION min/max are the mesh's bounds.
        let bb = prim.bounding_box();
        let (lo, hi) = body.mesh.bounds();
        assert!(close3(bb.min, lo) && close3(bb.max, hi));
    }
}

#[test]
fn animation_samples_equal_input_poses() {
    let rec = scene(31);
    let g = read(&glb_bytes(&rec).unwrap());
    assert_eq!(g.animations().count(), 1);
    let anim = g.animations().next().unwrap();
    // The static ground does not move, so only the two dynamic bodies animate.
    assert_eq!(anim.channels().count(), 4);
    for ch in anim.channels() {
        assert_eq!(
            ch.sampler().interpolation(),
            gltf::animation::Interpolation::Linear
        );
        let b = ch.target().node().index() - 1;
        assert!(b == 1 || b == 2);
        let reader = ch.reader(|_| g.blob.as_deref());
        let times: Vec<f32> = reader.read_inputs().unwrap().collect();
        assert_eq!(times.len(), rec.frame_times.len());
        for (t, &t_in) in times.iter().zip(&rec.frame_times) {
            assert_eq!(*t, t_in as f32);
        }
        use gltf::animation::util::{ReadOutputs, Rotations};
        match reader.read_outputs().unwrap() {
            ReadOutputs::Translations(it) => {
                let v: Vec<[f32; 3]> = it.collect();
                assert_eq!(v.len(), rec.frames.len());
                for (f, p) in v.iter().enumerate() {
                    assert!(close3(*p, rec.frames[f][b].position));
                    if b == 1 {
                        // The analytic free fall, not just whatever was passed in.
                        let t = rec.frame_times[f];
                        assert!((f64::from(p[2]) - falling_z(t)).abs() < 1e-5);
                    }
                }
            }
            ReadOutputs::Rotations(Rotations::F32(it)) => {
                let v: Vec<[f32; 4]> = it.collect();
                assert_eq!(v.len(), rec.frames.len());
                for (f, q) in v.iter().enumerate() {
                    let q = DQuat::from_array(q.map(f64::from));
                    let want = rec.frames[f][b].rotation;
                    assert!((q - want).length() < 1e-6, "frame {f}: {q:?} vs {want:?}");
                    if b == 2 {
                        // Rotation angle grows at the spin rate about the fixed axis.
                        let (axis, angle) = q.to_axis_angle();
                        let t = rec.frame_times[f];
                        if t > 0.0 {
                            assert!((axis - spin_axis()).length() < 1e-4);
                            assert!((angle - SPIN_RATE * t).abs() < 1e-5);
                        }
                    }
                }
            }
            other => panic!("unexpected output kind {:?}", std::mem::discriminant(&other)),
        }
    }
}

#[test]
fn moving_static_body_is_animated() {
    let mut rec = scene(5);
    rec.frames[3][0].position.z += 0.5;
    let g = read(&glb_bytes(&rec).unwrap());
    assert_eq!(g.animations().next().unwrap().channels().count(), 6);
    // And a recording where nothing moves has no animation at all.
    let mut still = scene(3);
    still.bodies.truncate(1);
    for f in &mut still.frames {
        f.truncate(1);
    }
    let g = read(&glb_bytes(&still).unwrap());
    assert_eq!(g.animations().count(), 0);
}

#[test]
fn glb_container_is_well_formed() {
    let rec = scene(7);
    let bytes = glb_bytes(&rec).unwrap();
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(u32::from_le_bytes(bytes[4..8].try_into().unwrap()), 2);
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
        bytes.len()
    );
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    assert_eq!(json_len % 4, 0);
    assert_eq!(&bytes[16..20], b"JSON");
    let bin_at = 20 + json_len;
    let bin_len = u32::from_le_bytes(bytes[bin_at..bin_at + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
    assert_eq!(bin_len % 4, 0);
    assert_eq!(bin_at + 8 + bin_len, bytes.len());
    let doc = json_chunk(&bytes);
    for view in doc["bufferViews"].as_array().unwrap() {
        let off = view["byteOffset"].as_u64().unwrap();
        let len = view["byteLength"].as_u64().unwrap();
        assert_eq!(off % 4, 0);
        assert!(off + len <= bin_len as u64);
    }
}

#[test]
fn extras_round_trip() {
    let mut rec = scene(4);
    rec.extras = (0..4)
        .map(|f| FrameExtras {
            kinetic_energy: f as f64 * 1.5,
            potential_energy: 10.0 - f as f64,
            contact_count: f,
            contacts: (0..f)
                .map(|k| ContactMark {
                    point: DVec3::new(k as f64, 0.25, -0.5),
                    normal: DVec3::Z,
                    distance: -1e-3 * k as f64,
                })
                .collect(),
        })
        .collect();
    rec.obb_boxes = vec![ObbBox {
        body: 1,
        depth: 0,
        center: DVec3::new(0.0, 0.0, 0.1),
        rotation: DQuat::from_rotation_z(0.3),
        half_extents: DVec3::new(0.1, 0.2, 0.3),
    }];
    let doc = json_chunk(&glb_bytes(&rec).unwrap());
    let x = &doc["extras"]["tumble"];
    assert_eq!(x["schema"], "tumble-recording/1");
    assert_eq!(x["up_axis"], "z");
    assert_eq!(x["bodies"].as_array().unwrap().len(), 3);
    assert_eq!(x["bodies"][0]["animated"], false);
    assert_eq!(x["bodies"][2]["node"], 3);
    for (f, e) in rec.extras.iter().enumerate() {
        assert_eq!(x["frame_times"][f].as_f64().unwrap(), rec.frame_times[f]);
        assert_eq!(x["kinetic_energy"][f].as_f64().unwrap(), e.kinetic_energy);
        assert_eq!(x["potential_energy"][f].as_f64().unwrap(), e.potential_energy);
        assert_eq!(x["contact_count"][f].as_u64().unwrap() as usize, e.contact_count);
        let cs = x["contacts"][f].as_array().unwrap();
        assert_eq!(cs.len(), e.contacts.len());
        for (c, want) in cs.iter().zip(&e.contacts) {
            // tumble-cli/tests/cli_run_view.rs (`view_streams_a_scene_live_over_a_websocket`)
            // reads its poses alike; test code is not shared across crates.
            let v: Vec<f64> = c
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            assert_eq!(v[0..3], want.point.to_array());
            assert_eq!(v[3..6], want.normal.to_array());
            assert_eq!(v[6], want.distance);
        }
    }
    let b = &x["obb_boxes"][0];
    assert_eq!(b["body"], 1);
    assert_eq!(b["half_extents"][2].as_f64().unwrap(), 0.3);
}

#[test]
fn rejects_bad_recordings() {
    // Each bad recording is made afresh from `scene(3)` with one fault and the
    // error fields it must give, so a failure points at one case.
    assert!(matches!(
        glb_bytes(&Recording::default()),
        Err(ExportError::Empty { .. })
    ));

    let mut r = scene(3);
    r.frames.pop();
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::FrameCountMismatch { what: "frames", .. })
    ));

    let mut r = scene(3);
    r.frames[1].pop();
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::BodyCountMismatch {
            frame: 1,
            found: 2,
            expected: 3
        })
    ));

    let mut r = scene(3);
    r.frames[2][1].position.y = f64::NAN;
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::BadPose {
            frame: 2,
            body: 1,
            ..
        })
    ));

    let mut r = scene(3);
    r.frames[0][2].rotation = DQuat::from_xyzw(1.0, 1.0, 1.0, 1.0);
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::BadPose {
            frame: 0,
            body: 2,
            ..
        })
    ));

    let mut r = scene(3);
    r.frame_times[2] = r.frame_times[1];
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::BadTime { frame: 2, .. })
    ));
    // Distinct in f64 but equal in f32: still rejected.
    r.frame_times[2] = r.frame_times[1] + 1e-12;
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::BadTime { frame: 2, .. })
    ));

    let mut r = scene(3);
    r.bodies[0].color[1] = 1.5;
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::BadColor { body: 0, .. })
    ));

    let mut r = scene(3);
    r.extras = vec![FrameExtras::default(); 2];
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::FrameCountMismatch { what: "extras", .. })
    ));
    r.extras.push(FrameExtras {
        kinetic_energy: f64::INFINITY,
        ..Default::default()
    });
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::NonFiniteExtra { frame: 2, .. })
    ));

    let mut r = scene(3);
    r.obb_boxes.push(ObbBox {
        body: 7,
        depth: 0,
        center: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
        half_extents: DVec3::ONE,
    });
    assert!(matches!(
        glb_bytes(&r),
        Err(ExportError::BadObbBox { index: 0, .. })
    ));
    // The CSV writer validates the same way.
    assert!(matches!(
        trajectory_csv(&Recording::default()),
        Err(ExportError::Empty { .. })
    ));
}

#[test]
fn write_glb_is_atomic_and_reports_io_errors() {
    let path = temp_path("scene.glb");
    write_glb(&scene(3), &path).unwrap();
    let first = std::fs::read(&path).unwrap();
    write_glb(&scene(9), &path).unwrap(); // overwrite in place
    let second = std::fs::read(&path).unwrap();
    assert_eq!(second, glb_bytes(&scene(9)).unwrap());
    assert_ne!(first, second);
    // No temporary file left beside it.
    let dir = path.parent().unwrap();
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    let missing = dir.join("no-such-dir").join("x.glb");
    assert!(matches!(
        write_glb(&scene(3), &missing),
        Err(ExportError::Io { .. })
    ));
    assert!(!missing.exists());
}

#[test]
fn output_is_deterministic() {
    assert_eq!(glb_bytes(&scene(12)).unwrap(), glb_bytes(&scene(12)).unwrap());
}

#[test]
fn csv_round_trips_exact_bits() {
    let mut rec = scene(6);
    rec.bodies[2].name = "spin, \"fast\"".to_string();
    let path = temp_path("traj.csv");
    write_trajectory_csv(&rec, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(CSV_HEADER));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), rec.frames.len() * rec.bodies.len());
    for (i, row) in rows.iter().enumerate() {
        let (f, b) = (i / rec.bodies.len(), i % rec.bodies.len());
        // Numbers are the last 7 fields; the name may contain a quoted comma.
        let fields: Vec<&str> = row.rsplitn(8, ',').collect();
        let nums: Vec<f64> = fields[..7].iter().rev().map(|s| s.parse().unwrap()).collect();
        let (t, name) = fields[7].split_once(',').unwrap();
        assert_eq!(t.parse::<f64>().unwrap(), rec.frame_times[f]);
        if b == 2 {
            assert_eq!(name, "\"spin, \"\"fast\"\"\"");
        } else {
            assert_eq!(name, rec.bodies[b].name);
        }
        let p = rec.frames[f][b];
        assert_eq!(nums[0..3], p.position.to_array());
        assert_eq!(nums[3..7], p.rotation.to_array());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any valid pose sequence comes back from the animation within f32
    /// precision, whatever the body mesh.
    #[test]
    fn random_poses_round_trip(
        raw in prop::collection::vec(
            (prop::array::uniform3(-50.0f64..50.0), prop::array::uniform4(-1.0f64..1.0)), 2..12),
    ) {
        let poses: Vec<Pose> = raw
            .iter()
            .filter_map(|(p, q)| Pose::new_normalized(DVec3::from(*p), DQuat::from_array(*q)).ok())
            .collect();
        prop_assume!(poses.len() >= 2);
        let rec = Recording {
            bodies: vec![body("b", icosphere_mesh(0.5, 1).unwrap(), false)],
            frame_times: (0..poses.len()).map(|f| 0.01 * f as f64).collect(),
            frames: poses.iter().map(|p| vec![*p]).collect(),
            ..Default::default()
        };
        let g = read(&glb_bytes(&rec).unwrap());
        let anim = g.animations().next().unwrap();
        for ch in anim.channels() {
            let reader = ch.reader(|_| g.blob.as_deref());
            use gltf::animation::util::{ReadOutputs, Rotations};
            match reader.read_outputs().unwrap() {
                ReadOutputs::Translations(it) => {
                    for (v, p) in it.zip(&poses) {
                        prop_assert!(close3(v, p.position));
                    }
                }
                ReadOutputs::Rotations(Rotations::F32(it)) => {
                    for (v, p) in it.zip(&poses) {
                        let q = DQuat::from_array(v.map(f64::from));
                        prop_assert!((q - p.rotation).length() < 1e-6);
                    }
                }
                _ => prop_assert!(false, "unexpected output kind"),
            }
        }
    }
}

/// Reads one `.npy` member of an `.npz` archive: (shape, f64 data or None for
/// non-float arrays, raw header dtype).
fn npz_member(archive: &[u8], name: &str) -> (Vec<u64>, npyz::DType, Vec<u8>) {
    use std::io::Read;
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(archive)).expect("a zip archive");
    let mut file = zip.by_name(name).expect("member present");
    assert_eq!(file.compression(), zip::CompressionMethod::Stored);
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).expect("a valid .npy");
    (npy.shape().to_vec(), npy.dtype(), bytes)
}

#[test]
fn npz_holds_time_positions_orientations_and_names() {
    let mut rec = scene(17);
    rec.bodies[2].name = "spinner_é".into(); // non-ASCII survives as numpy unicode
    let archive = trajectory_npz(&rec).unwrap();
    let (shape, _, bytes) = npz_member(&archive, "time.npy");
    assert_eq!(shape, vec![17]);
    let time: Vec<f64> = npyz::NpyFile::new(&bytes[..]).unwrap().into_vec().unwrap();
    assert_eq!(time, rec.frame_times);
    let (shape, _, bytes) = npz_member(&archive, "position.npy");
    assert_eq!(shape, vec![17, 3, 3]);
    let pos: Vec<f64> = npyz::NpyFile::new(&bytes[..]).unwrap().into_vec().unwrap();
    let (shape, _, bytes) = npz_member(&archive, "orientation.npy");
    assert_eq!(shape, vec![17, 3, 4]);
    let rot: Vec<f64> = npyz::NpyFile::new(&bytes[..]).unwrap().into_vec().unwrap();
    for (f, poses) in rec.frames.iter().enumerate() {
        for (b, p) in poses.iter().enumerate() {
            let i = f * 3 + b;
            assert_eq!(&pos[3 * i..3 * i + 3], &p.position.to_array()[..]);
            assert_eq!(&rot[4 * i..4 * i + 4], &p.rotation.to_array()[..]);
        }
    }
    // Frame f, body 1 falls freely: z = Z0 - g t^2 / 2 (the analytic input).
    assert!((pos[3 * (16 * 3 + 1) + 2] - falling_z(16.0 / 30.0)).abs() < 1e-12);
    let (shape, dtype, bytes) = npz_member(&archive, "names.npy");
    assert_eq!(shape, vec![3]);
    assert_eq!(dtype.descr(), "'<U9'");
    let names: Vec<String> = npyz::NpyFile::new(&bytes[..]).unwrap().into_vec().unwrap();
    assert_eq!(names, vec!["ground", "faller", "spinner_é"]);
    // Invalid recordings are refused before anything is written.
    let mut bad = scene(3);
    bad.frames[1].pop();
    assert!(trajectory_npz(&bad).is_err());
}

#[test]
fn live_messages_follow_the_viewer_protocol() {
    let rec = scene(4);
    let scene_msg: Value = serde_json::from_str(&live::scene_message(&rec)).unwrap();
    assert_eq!(scene_msg["type"], "scene");
    let bodies = scene_msg["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 3);
    for (b, body) in bodies.iter().zip(&rec.bodies) {
        assert_eq!(b["name"], body.name.as_str());
        assert_eq!(
            b["vertices"].as_array().unwrap().len(),
            3 * body.mesh.vertices().len()
        );
        assert_eq!(
            b["triangles"].as_array().unwrap().len(),
            3 * body.mesh.triangles().len()
        );
    }
    for f in 0..4 {
        let m: Value = serde_json::from_str(&live::frame_message(&rec, f).unwrap()).unwrap();
        assert_eq!(m["type"], "frame");
        assert_eq!(m["t"].as_f64().unwrap(), rec.frame_times[f]);
        let p = &m["poses"][1];
        assert_eq!(p[2].as_f64().unwrap(), falling_z(rec.frame_times[f]));
        assert_eq!(p[6].as_f64().unwrap(), 1.0);
    }
    assert!(live::frame_message(&rec, 4).is_none());
}
