//! The built `tumble` binary end to end: `collide` and `mass` give
//! physically right answers in their JSON (known overlap depth, gap,
//! closest points, the box mass formulas), `bench --scene tori` prints the
//! harness record, `bench --paired` times one run on one thread and on two,
//! `bench --export-scene` writes the scene the peers build from, and bad
//! input exits with status 2 and one line.

use serde_json::Value;
use std::process::{Command, Output};

fn tumble(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(args)
        .output()
        .expect("the tumble binary runs")
}

fn json_of(args: &[&str]) -> Value {
    let out = tumble(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn vec3(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("a 3-vector");
    [0, 1, 2].map(|i| a[i].as_f64().expect("a number"))
}

/// Bad input: exit status 2 and exactly one line `tumble: error: ...`
/// naming what was wrong.
fn assert_input_error(args: &[&str], mentions: &str) {
    let out = tumble(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("tumble: error: "), "{err}");
    assert!(
        err.contains(mentions),
        "{args:?}: '{err}' should mention '{mentions}'"
    );
}

const CUBE: &str = "box:hx=0.5,hy=0.5,hz=0.5";

#[test]
fn overlapping_cubes_report_the_overlap_depth() {
    // B 0.9 m above A: 0.1 m overlap, shifted so that no faces are coplanar.
    let v = json_of(&[
        "collide",
        CUBE,
        CUBE,
        "--pose-b",
        "0.3 0.2 0.9 0 0 0 1",
        "--report",
        "contacts",
        "--distance",
        "--tolerance",
        "0.01",
        "--json",
    ]);
    assert_eq!(v["intersect"], Value::Bool(true));
    let pairs = v["pairs"].as_array().unwrap();
    assert!(!pairs.is_empty());
    for p in pairs {
        let p = p.as_array().unwrap();
        assert!(p.len() == 2 && p.iter().all(|i| i.as_u64().unwrap() < 12));
    }
    let contacts = v["contacts"].as_array().unwrap();
    let deepest = contacts
        .iter()
        .max_by(|a, b| {
            a["depth"]
                .as_f64()
                .unwrap()
                .total_cmp(&b["depth"].as_f64().unwrap())
        })
        .unwrap();
    assert!(
        (deepest["depth"].as_f64().unwrap() - 0.1).abs() < 1e-9,
        "{deepest}"
    );
    let n = vec3(&deepest["normal"]);
    assert!(
        n[0].abs() < 1e-9 && n[1].abs() < 1e-9 && (n[2] + 1.0).abs() < 1e-9,
        "{deepest}"
    );
    for c in contacts {
        assert!(c["kind"].is_string() && c["point"].is_array());
        // Every contact point lies in the overlap slab of the two cubes.
        let p = vec3(&c["point"]);
        assert!(p[2] > 0.4 - 1e-9 && p[2] < 0.5 + 1e-9, "{c}");
    }
    assert_eq!(v["distance"]["distance"].as_f64(), Some(0.0));
    assert_eq!(v["within_tolerance"]["within"], Value::Bool(true));
}

#[test]
fn separated_cubes_give_the_gap_and_closest_points() {
    // B turned 90 degrees about z and lifted to 1.5 m: a 0.5 m gap.
    let s = std::f64::consts::FRAC_1_SQRT_2.to_string();
    let pose = format!("0.1 -0.2 1.5 0 0 {s} {s}");
    let v = json_of(&[
        "collide",
        CUBE,
        CUBE,
        "--pose-b",
        &pose,
        "--distance",
        "--tolerance",
        "0.4",
        "--json",
    ]);
    assert_eq!(v["intersect"], Value::Bool(false));
    assert_eq!(v["pairs"].as_array().map(|p| p.len()), Some(0));
    assert!(
        v.get("contacts").is_none(),
        "contacts only with --report contacts"
    );
    let d = &v["distance"];
    assert!((d["distance"].as_f64().unwrap() - 0.5).abs() < 1e-12, "{d}");
    let (pa, pb) = (vec3(&d["point_a"]), vec3(&d["point_b"]));
    assert!((pa[2] - 0.5).abs() < 1e-12 && (pb[2] - 1.0).abs() < 1e-12, "{d}");
    assert!((pa[0] - pb[0]).abs() < 1e-12 && (pa[1] - pb[1]).abs() < 1e-12);
    assert_eq!(v["within_tolerance"]["within"], Value::Bool(false));
    // The command above again, without --distance and at tolerance 0.5: the
    // whole argument list is the case, as a user would type it.
    let v = json_of(&[
        "collide",
        CUBE,
        CUBE,
        "--pose-b",
        &pose,
        "--tolerance",
        "0.5",
        "--json",
    ]);
    assert_eq!(v["within_tolerance"]["within"], Value::Bool(true));
}

#[test]
fn first_contact_returns_one_of_the_pairs() {
    let args = [
        "collide",
        "torus:R=1,r=0.3,n=24",
        "torus:R=1,r=0.3,n=24",
        "--pose-b",
    ];
    // B's ring in the xz plane through A's centre: it cuts A's tube twice.
    let pose = "0 0.05 0.02 0.70710678118654752 0 0 0.70710678118654752";
    let all = json_of(&[&args[..], &[pose, "--json"]].concat());
    let first = json_of(&[&args[..], &[pose, "--first", "--json"]].concat());
    let all_pairs = all["pairs"].as_array().unwrap();
    let first_pairs = first["pairs"].as_array().unwrap();
    assert!(all_pairs.len() > 1);
    assert_eq!(first_pairs.len(), 1);
    assert!(all_pairs.contains(&first_pairs[0]));
    assert!(first["stats"]["bv_tests"].as_u64() < all["stats"]["bv_tests"].as_u64());
    let boolean = json_of(&[&args[..], &[pose, "--report", "bool", "--json"]].concat());
    assert_eq!(boolean["intersect"], Value::Bool(true));
    assert!(boolean.get("pairs").is_none());
    // Text output for people.
    let out = tumble(&[&args[..], &[pose]].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("intersect: yes") && text.contains("triangle pairs:"));
}

/// A box mesh's mass properties equal the box formulas:
/// m = rho 8 hx hy hz, Ixx = m (b^2 + c^2) / 12 with full side lengths.
#[test]
fn mass_of_a_box_matches_the_formulas() {
    let v = json_of(&["mass", "box:hx=1,hy=0.5,hz=0.25", "--density", "2", "--json"]);
    let m = 2.0 * 8.0 * 1.0 * 0.5 * 0.25;
    assert!((v["volume"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert!((v["mass"].as_f64().unwrap() - m).abs() < 1e-12);
    let (a, b, c) = (2.0, 1.0, 0.5);
    let want = [
        m * (b * b + c * c) / 12.0,
        m * (a * a + c * c) / 12.0,
        m * (a * a + b * b) / 12.0,
    ];
    for (i, w) in want.iter().enumerate() {
        let row = vec3(&v["inertia"][i]);
        for (j, x) in row.iter().enumerate() {
            let expected = if i == j { *w } else { 0.0 };
            assert!((x - expected).abs() < 1e-12, "I[{i}][{j}] = {x}, want {expected}");
        }
    }
    assert!(vec3(&v["com"]).iter().all(|x| x.abs() < 1e-12));
}

/// A cube written as an OBJ file: `mass` finds its offset centre of mass and
/// `collide` reads it like a generated mesh.
#[test]
fn obj_files_work_in_mass_and_collide() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("cli_test_cube.obj");
    let mut obj = String::new();
    for i in 0..8 {
        let c = |bit: usize, off: f64| if i & bit != 0 { off + 0.5 } else { off - 0.5 };
        obj += &format!("v {} {} {}\n", c(1, 2.0), c(2, -1.0), c(4, 0.5));
    }
    // A hand-written OBJ on purpose (not mesh::box_mesh, nor the 0-based table
    // of query_oracle.rs `primitive_triangle_distance`): the reader is under test.
    // (world_recorder.rs `PALETTE` is six colours, alike to this table in shape only.)
    // Corner loops of the six faces (1-based), split into triangles wound
    // counter-clockwise seen from outside.
    for f in [
        [1, 3, 7, 5],
        [2, 6, 8, 4],
        [1, 5, 6, 2],
        [3, 4, 8, 7],
        [1, 2, 4, 3],
        [5, 7, 8, 6],
    ] {
        obj += &format!("f {} {} {}\nf {} {} {}\n", f[0], f[2], f[1], f[0], f[3], f[2]);
    }
    std::fs::write(&path, obj).unwrap();
    let p = path.to_str().unwrap();
    let v = json_of(&["mass", p, "--json"]);
    assert!((v["volume"].as_f64().unwrap() - 1.0).abs() < 1e-12, "{v}");
    let com = vec3(&v["com"]);
    assert!((com[0] - 2.0).abs() < 1e-12 && (com[1] + 1.0).abs() < 1e-12 && (com[2] - 0.5).abs() < 1e-12);
    // The file cube centred at (2, -1, 0.5) against a generated one at the
    // origin: 1 m gap along x.
    let v = json_of(&["collide", p, CUBE, "--distance", "--json"]);
    assert!(
        (v["distance"]["distance"].as_f64().unwrap() - 1.0).abs() < 1e-12,
        "{v}"
    );
}

#[test]
fn bench_tori_prints_the_harness_record() {
    let v = json_of(&["bench", "--scene", "tori", "--poses", "3"]);
    assert_eq!(v["engine"], "tumble");
    assert_eq!(v["scene"], "tori");
    assert_eq!(v["settings"]["poses"], 3);
    let f = &v["figures"];
    for key in ["first_contact", "all_pairs", "all_pairs_with_contacts"] {
        for part in ["all", "colliding", "separated"] {
            assert!(f[key].get(part).is_some(), "{key}.{part}");
        }
        assert_eq!(f[key]["all"]["unit"], "us");
    }
    for key in [
        "total_pairs",
        "truth_total_pairs",
        "colliding_poses",
        "truth_colliding_poses",
    ] {
        assert!(f["all_pairs_check"].get(key).is_some(), "{key}");
    }
    assert!(f["tree_memory_bytes"].as_u64().unwrap() > 0);
    // Poses 0, 100, 199: B far left, through A, far right.
    assert_eq!(f["all_pairs_check"]["colliding_poses"], 1);
    if v["settings"]["truth_file_found"] == Value::Bool(true) {
        assert_eq!(
            f["all_pairs_check"]["total_pairs"],
            f["all_pairs_check"]["truth_total_pairs"]
        );
    }
}

/// `bench --paired` times one run on one thread and on two in alternating
/// blocks of ten steps (1, 2, 2, 1): the trajectory is the one thread's to
/// the bit (every figure equal), and each count timed half the steps.
#[test]
fn bench_paired_times_the_same_run_on_one_thread_and_on_two() {
    let args = ["bench", "--scene", "pyramid", "--steps", "40"];
    let alone = json_of(&args);
    let paired = json_of(&[&args[..], &["--threads", "2", "--paired"]].concat());
    let (f, g) = (&alone["figures"], &paired["figures"]);
    for key in [
        "top_box_displacement_m",
        "largest_displacement_m",
        "deepest_penetration_m",
    ] {
        assert!(f[key].as_f64().is_some(), "{key}");
        assert_eq!(f[key], g[key], "{key}");
    }
    assert_eq!(g["step_time"]["count"], 20);
    assert_eq!(g["one_thread_step_time"]["count"], 20);
    assert!(g["steps_on_threads"].as_u64().unwrap() <= 20);
    let speedup = g["paired_speedup"].as_f64().unwrap();
    assert!(speedup.is_finite() && speedup > 0.0, "{speedup}");
    assert_eq!(paired["settings"]["paired"], true);
    // The threads it ran for, not those of its last block (one thread).
    assert_eq!(paired["settings"]["threads"], 2);
    assert_eq!(paired["settings"]["adaptive_threads"], false);
    assert_input_error(&[&args[..], &["--paired"]].concat(), "--paired");
    assert_input_error(
        &[
            "bench",
            "--scene",
            "pyramid",
            "--steps",
            "5",
            "--threads",
            "2",
            "--paired",
        ],
        "--steps 20 or more",
    );
}

#[test]
fn bad_input_exits_2_with_one_line() {
    assert_input_error(&["collide", "/no/such/mesh.obj", CUBE], "/no/such/mesh.obj");
    assert_input_error(&["collide", CUBE, CUBE, "--pose-b", "1 2"], "--pose-b");
    assert_input_error(
        &["collide", CUBE, CUBE, "--pose-a", "0 0 0 1 1 1 1"],
        "unit quaternion",
    );
    assert_input_error(&["collide", CUBE, CUBE, "--pose-a", "0 0 x"], "--pose-a");
    assert_input_error(&["collide", CUBE, CUBE, "--tolerance", "-1"], ">= 0");
    assert_input_error(
        &["collide", CUBE, CUBE, "--report", "contacts", "--margin", "-0.5"],
        "contact_margin",
    );
    assert_input_error(&["collide", CUBE, "torus:R=1,q=2"], "unknown parameter");
    assert_input_error(&["collide", CUBE, CUBE, "--no-such-flag"], "--no-such-flag");
    assert_input_error(&["collide", CUBE], "B");
    assert_input_error(&["mass", "/no/such/mesh.stl"], "/no/such/mesh.stl");
    assert_input_error(&["bench", "--scene", "tori", "--poses", "0"], "--poses");
}

#[test]
fn export_scene_writes_the_plain_scene_and_refuses_bad_requests() {
    // The pile of 100 as every peer receives it: 5 static boxes, then 100
    // bodies of density 1 (a cube of half extent 0.25: 0.125 kg).
    let v = json_of(&["bench", "--scene", "pile", "--n", "100", "--export-scene", "-"]);
    assert_eq!(v["format"], "tumble-plain-scene/1");
    let bodies = v["bodies"].as_array().expect("bodies");
    assert_eq!(bodies.len(), 105);
    assert_eq!(bodies[0]["kind"], "static");
    let cube = bodies
        .iter()
        .find(|b| b["shapes"][0]["type"] == "box" && b["kind"] == "dynamic")
        .expect("a dynamic cube");
    assert!((cube["mass"].as_f64().unwrap() - 0.125).abs() < 1e-12);
    // To a file, the same JSON.
    let dir = std::env::temp_dir().join(format!("tumble-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("tori.json");
    let out = tumble(&[
        "bench",
        "--scene",
        "tori",
        "--poses",
        "3",
        "--export-scene",
        file.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let tori: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(tori["poses"].as_array().unwrap().len(), 3);
    std::fs::remove_dir_all(&dir).ok();
    // Bad requests: a pile that is not a multiple of 100, an unwritable path.
    assert_input_error(
        &["bench", "--scene", "pile", "--n", "150", "--export-scene", "-"],
        "multiple of 100",
    );
    assert_input_error(
        &[
            "bench",
            "--scene",
            "cradle",
            "--export-scene",
            "/nonexistent-dir/cradle.json",
        ],
        "cannot write",
    );
}
