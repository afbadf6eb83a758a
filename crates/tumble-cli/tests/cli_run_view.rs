//! The `tumble` binary end to end: `run` writes outputs that reproduce the
//! simulation, bad input gives one located line, exit status 2 and no
//! output file; `view` serves the page, the recording and a live WebSocket
//! stream.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

fn tumble() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tumble"))
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn example(name: &str) -> PathBuf {
    repo().join("examples/scenes").join(name)
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tumble_cli_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn run_writes_a_glb_and_trajectories_that_match_the_simulation() {
    let dir = temp_dir("run");
    let (glb, csv, npz) = (dir.join("c.glb"), dir.join("c.csv"), dir.join("c.npz"));
    let steps = 40;
    // Not `assert_bad_input`'s command (below): this run must succeed and its
    // outputs are read back, so its arguments are written out here.
    let out = tumble()
        .args(["run", "--quiet", "--steps", &steps.to_string()])
        .arg(example("cradle.toml"))
        .arg("--out")
        .arg(&glb)
        .arg("--trajectory")
        .arg(&csv)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stdout.is_empty(), "--quiet prints nothing");
    let out = tumble()
        .args(["run", "--steps", &steps.to_string()])
        .arg(example("cradle.toml"))
        .arg("--trajectory")
        .arg(&npz)
        .output()
        .unwrap();
    assert!(out.status.success());
    let summary = String::from_utf8_lossy(&out.stdout);
    for word in ["40 steps", "steps/s", "max penetration", "energy drift", "wrote"] {
        assert!(summary.contains(word), "summary lacks {word:?}: {summary}");
    }

    // The same scene simulated here, in-process.
    let loaded = tumble::scene::load_scene(example("cradle.toml")).unwrap();
    let (mut world, ids) = loaded.build().unwrap();
    for _ in 0..steps {
        world.step();
    }
    let g = gltf::Gltf::open(&glb).unwrap();
    let blob = g.blob.as_deref().unwrap();
    assert_eq!(g.nodes().count(), ids.len() + 1);
    let anim = g.animations().next().unwrap();
    assert_eq!(anim.channels().count(), 2 * ids.len(), "six moving spheres");
    for channel in anim.channels() {
        let reader = channel.reader(|_| Some(blob));
        assert_eq!(reader.read_inputs().unwrap().count(), steps + 1);
        if let Some(gltf::animation::util::ReadOutputs::Translations(t)) = reader.read_outputs() {
            let b = channel.target().node().index() - 1;
            let last = t.last().unwrap();
            let x = world.center_of_mass(ids[b]).unwrap();
            for k in 0..3 {
                assert!((last[k] as f64 - x[k]).abs() < 1e-5, "body {b}: {last:?} vs {x}");
            }
        }
    }
    // CSV: header + one row per body per frame, last rows equal to the world.
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows[0], "t,body,x,y,z,qx,qy,qz,qw");
    assert_eq!(rows.len(), 1 + (steps + 1) * ids.len());
    let striker: Vec<f64> = rows
        .last()
        .unwrap()
        .split(',')
        .skip(2)
        .map(|v| v.parse().unwrap())
        .collect();
    let x = world.center_of_mass(ids[5]).unwrap();
    assert_eq!(striker[0], x.x, "CSV keeps the exact bits");
    // The .npz is a zip of .npy arrays.
    let bytes = std::fs::read(&npz).unwrap();
    assert_eq!(&bytes[..4], b"PK\x03\x04");
    for name in ["time.npy", "position.npy", "orientation.npy", "names.npy"] {
        assert!(
            bytes.windows(name.len()).any(|w| w == name.as_bytes()),
            "{name} missing"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs `tumble run FILE --out X.glb --trajectory X.csv` and checks exit 2,
/// one stderr line containing `expect`, and no output files.
fn assert_bad_input(dir: &Path, scene_name: &str, scene_text: &str, extra: &[&str], expect: &str) {
    let scene = dir.join(scene_name);
    std::fs::write(&scene, scene_text).unwrap();
    let (glb, csv) = (dir.join("bad.glb"), dir.join("bad.csv"));
    let out = tumble()
        .arg("run")
        .arg(&scene)
        .args(extra)
        .arg("--out")
        .arg(&glb)
        .arg("--trajectory")
        .arg(&csv)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{scene_name}: stderr {stderr}");
    assert_eq!(
        stderr.lines().count(),
        1,
        "{scene_name}: one line, got {stderr:?}"
    );
    assert!(
        stderr.contains(expect),
        "{scene_name}: {stderr:?} lacks {expect:?}"
    );
    assert!(
        !glb.exists() && !csv.exists(),
        "{scene_name}: an output was written"
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
}

#[test]
fn bad_input_is_one_located_line_exit_two_and_no_output() {
    let dir = temp_dir("bad");
    let ball = "[[bodies]]\nshapes = [{ type = \"sphere\", radius = 0.5 }]\nmass = 1.0\n";
    std::fs::write(
        dir.join("open.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n",
    )
    .unwrap();
    let cases: [(&str, String, &[&str], &str); 9] = [
        (
            "missing_mesh.toml",
            "[[bodies]]\nshapes = [{ type = \"mesh\", mesh = { file = \"gone.obj\" } }]\n".into(),
            &[],
            "missing_mesh.toml:2:",
        ),
        (
            "open_mesh.toml",
            "[[bodies]]\ndensity = 1000.0\nshapes = [{ type = \"mesh\", mesh = { file = \"open.obj\" } }]\n"
                .into(),
            &[],
            "open_mesh.toml:3:11: bodies[0].shapes[0]:",
        ),
        (
            "nan.toml",
            format!("{ball}position = [0, nan, 1]\n"),
            &[],
            "nan.toml:4:12: bodies[0].position: must be finite",
        ),
        (
            "shape_type.toml",
            ball.replace("sphere", "sphear"),
            &[],
            "shape_type.toml:2:",
        ),
        (
            "unknown_key.toml",
            format!("{ball}colour = \"red\"\n"),
            &[],
            "unknown_key.toml:4:1: bodies[0]",
        ),
        (
            "negative_dt.toml",
            format!("[settings]\ndt = -0.01\n{ball}"),
            &[],
            "negative_dt.toml:2:6: settings.dt: must be finite and > 0",
        ),
        (
            "negative_mass.toml",
            ball.replace("mass = 1.0", "mass = -1"),
            &[],
            "negative_mass.toml:3:8: bodies[0].mass: must be finite and > 0 kg, got -1",
        ),
        (
            "dt_flag.toml",
            ball.to_string(),
            &["--dt", "-0.5"],
            "--dt must be finite",
        ),
        (
            "json_nan.json",
            r#"{"bodies": [{"shapes": [{"type": "sphere", "radius": 1}], "position": [0, NaN, 0]}]}"#.into(),
            &[],
            "json_nan.json:1:",
        ),
    ];
    for (name, text, extra, expect) in cases {
        assert_bad_input(&dir, name, &text, extra, expect);
    }
    // An output path of the wrong kind is refused before anything runs.
    let out = tumble()
        .arg("run")
        .arg(example("cradle.toml"))
        .arg("--trajectory")
        .arg(dir.join("t.parquet"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    // A scene file that does not exist.
    let out = tumble().args(["run", "/no/such/scene.toml"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn help_reads_like_a_manual() {
    for verb in [&["--help"][..], &["run", "--help"], &["view", "--help"]] {
        let out = tumble().args(verb).output().unwrap();
        assert!(out.status.success());
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("Examples:"), "{verb:?} help has no examples");
    }
}

/// A `tumble view` process, killed when dropped.
struct Viewer {
    child: Child,
    port: u16,
    url: String,
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start_view(input: &Path, viewer_dir: &Path) -> Viewer {
    let mut child = tumble()
        .args(["view", "--no-open", "--port", "0", "--speed", "0"])
        .arg("--viewer-dir")
        .arg(viewer_dir)
        .arg(input)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    stdout.read_line(&mut line).unwrap();
    // Keep reading so that the server never writes to a closed pipe.
    std::thread::spawn(move || std::io::copy(&mut stdout, &mut std::io::sink()));
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap_or_else(|| panic!("no URL in {line:?}"))
        .to_string();
    let port = url["http://127.0.0.1:".len()..]
        .split('/')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    Viewer { child, port, url }
}

/// GET `path` over HTTP/1.0: (status code, body).
fn get(port: u16, path: &str) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(s, "GET {path} HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n").unwrap();
    let mut bytes = Vec::new();
    s.read_to_end(&mut bytes).unwrap();
    let split = bytes.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8_lossy(&bytes[..split]).to_string();
    let code = head.split_whitespace().nth(1).unwrap().parse().unwrap();
    (code, bytes[split + 4..].to_vec())
}

fn stub_viewer(dir: &Path) -> PathBuf {
    let dist = dir.join("dist");
    std::fs::create_dir_all(dist.join("assets")).unwrap();
    std::fs::write(dist.join("index.html"), "<title>tumble viewer</title>").unwrap();
    std::fs::write(dist.join("assets/main.js"), "console.log('hi')").unwrap();
    dist
}

#[test]
fn view_serves_a_recording() {
    let dir = temp_dir("view_glb");
    let dist = stub_viewer(&dir);
    let glb = dir.join("rec.glb");
    let status = tumble()
        .args(["run", "--quiet", "--steps", "10"])
        .arg(example("domino.toml"))
        .arg("--out")
        .arg(&glb)
        .status()
        .unwrap();
    assert!(status.success());
    let viewer = start_view(&glb, &dist);
    assert!(viewer.url.ends_with("/?file=/recording.glb"), "{}", viewer.url);
    let (code, page) = get(viewer.port, "/");
    assert_eq!(code, 200);
    assert!(String::from_utf8_lossy(&page).contains("tumble viewer"));
    assert_eq!(get(viewer.port, "/assets/main.js").0, 200);
    let (code, body) = get(viewer.port, "/recording.glb");
    assert_eq!(code, 200);
    assert_eq!(body, std::fs::read(&glb).unwrap());
    assert_eq!(
        get(viewer.port, "/../Cargo.toml").0,
        404,
        "no way out of the viewer dir"
    );
    assert_eq!(get(viewer.port, "/nothing.js").0, 404);
    drop(viewer);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn view_streams_a_scene_live_over_a_websocket() {
    let dir = temp_dir("view_live");
    let dist = stub_viewer(&dir);
    let viewer = start_view(&example("domino.toml"), &dist);
    // The WebSocket listens on its own port, named in the page's URL.
    let prefix = format!("http://127.0.0.1:{}/?live=", viewer.port);
    let ws_url = viewer
        .url
        .strip_prefix(&prefix)
        .unwrap_or_else(|| panic!("{}", viewer.url));
    assert!(
        ws_url.starts_with("ws://127.0.0.1:") && ws_url.ends_with("/live"),
        "{ws_url}"
    );
    let (code, body) = get(viewer.port, "/");
    assert_eq!(code, 200, "{}", String::from_utf8_lossy(&body));
    let (mut ws, _) = tungstenite::connect(ws_url).unwrap();
    let mut next = || -> serde_json::Value {
        loop {
            match ws.read().unwrap() {
                tungstenite::Message::Text(t) => return serde_json::from_str(t.as_str()).unwrap(),
                _ => continue,
            }
        }
    };
    let scene = next();
    assert_eq!(scene["type"], "scene");
    let bodies = scene["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 31, "ground and 30 dominoes");
    assert_eq!(bodies[1]["name"], "domino0");
    assert!(bodies[1]["triangles"].as_array().unwrap().len() >= 36);
    let mut last_t = -1.0;
    for _ in 0..3 {
        let frame = next();
        assert_eq!(frame["type"], "frame");
        let t = frame["t"].as_f64().unwrap();
        assert!(t > last_t, "time must increase: {t} after {last_t}");
        last_t = t;
        let poses = frame["poses"].as_array().unwrap();
        assert_eq!(poses.len(), 31);
        for p in poses {
            // JSON array to floats as in tumble/src/export/tests.rs
            // `extras_round_trip`: tumble-cli's tests cannot use tumble's test code.
            let p: Vec<f64> = p
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert_eq!(p.len(), 7);
            assert!(p.iter().all(|x| x.is_finite()));
            let qn = (p[3] * p[3] + p[4] * p[4] + p[5] * p[5] + p[6] * p[6]).sqrt();
            assert!((qn - 1.0).abs() < 1e-9);
        }
        assert!(frame["kinetic_energy"].as_f64().unwrap() >= 0.0);
    }
    // The first domino was tipped (angular velocity (0, 2, 0)): it turns.
    assert!(last_t > 0.0);
    drop(viewer);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn view_without_a_built_viewer_says_how_to_build_it() {
    let dir = temp_dir("view_missing");
    let out = tumble()
        .args(["view", "--no-open", "--port", "0"])
        .arg("--viewer-dir")
        .arg(dir.join("nowhere"))
        .arg(example("cradle.toml"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("npm run build"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn run_reports_the_largest_joint_error_of_a_jointed_scene() {
    let out = tumble()
        .args(["run", "--steps", "120"])
        .arg(example("rope.toml"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (line, mm) = summary_millimetres(&out.stdout, "largest joint error");
    assert!(line.contains("(21 joints)"), "{line}");
    // The rope holds within a centimetre.
    assert!(mm < 10.0, "{line}");
}

/// The line of `tumble run`'s summary that begins with `label`, and the
/// number of millimetres it gives ("max penetration X mm", "largest joint
/// error X mm, ...").
fn summary_millimetres(stdout: &[u8], label: &str) -> (String, f64) {
    let summary = String::from_utf8_lossy(stdout);
    let line = summary
        .lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no `{label}` line: {summary}"));
    let words = label.split_whitespace().count();
    let mm = line.split_whitespace().nth(words).unwrap().parse().unwrap();
    (line.to_string(), mm)
}

#[test]
fn run_simulates_a_urdf_robot_and_locates_a_bad_one() {
    let out = tumble()
        .args(["run", "--steps", "60", "--base-position", "0,0,0.4"])
        .arg(repo().join("examples/robots/quadruped.urdf"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(summary.contains("quadruped: 60 steps"), "{summary}");
    assert!(summary.contains("(12 joints)"), "{summary}");

    let dir = temp_dir("urdf");
    // Without --base-position the robot starts with its lowest point on
    // the ground: a box whose frame is its centre starts resting, not
    // 0.1 m deep in the ground (max penetration is the deepest overlap).
    let cube = dir.join("cube.urdf");
    std::fs::write(
        &cube,
        "<robot name=\"cube\"><link name=\"c\"><collision><geometry><box size=\"0.2 0.2 0.2\"/>\
         </geometry></collision></link></robot>\n",
    )
    .unwrap();
    for flags in [&[][..], &["--self-collision"][..]] {
        let out = tumble()
            .args(["run", "--steps", "30"])
            .args(flags)
            .arg(&cube)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let (line, mm) = summary_millimetres(&out.stdout, "max penetration");
        assert!(mm < 1.0, "{line}");
    }
    // Two links that overlap in the file's pose, linked by no joint (b is
    // carried by a massless frame on a hinge): with self-collision they are
    // said to be kept apart.
    let folded = dir.join("folded.urdf");
    std::fs::write(
        &folded,
        "<robot name=\"f\">\
         <link name=\"a\"><collision><geometry><box size=\"0.4 0.4 0.4\"/></geometry></collision></link>\
         <link name=\"m\"><collision><origin xyz=\"0 0 0.5\"/><geometry><sphere radius=\"0.05\"/></geometry></collision></link>\
         <link name=\"b\"><collision><origin xyz=\"0 0 -0.5\"/><geometry><sphere radius=\"0.1\"/></geometry></collision></link>\
         <joint name=\"j1\" type=\"continuous\"><parent link=\"a\"/><child link=\"m\"/></joint>\
         <joint name=\"j2\" type=\"continuous\"><parent link=\"m\"/><child link=\"b\"/><origin xyz=\"0 0 0.5\"/></joint>\
         </robot>\n",
    )
    .unwrap();
    for (flags, said) in [(&[][..], false), (&["--self-collision"][..], true)] {
        let out = tumble()
            .args(["run", "--steps", "5"])
            .args(flags)
            .arg(&folded)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let summary = String::from_utf8_lossy(&out.stdout);
        let line = "self-collision: links that overlap in the file's pose never touch (pairs kept apart: 1)";
        assert_eq!(summary.contains(line), said, "{summary}");
    }
    // A ring (a torus mesh) with a ball hinged in its hole: apart as
    // meshes, overlapping as convex hulls (the hull fills the hole), so
    // --convex-meshes has the pair kept apart.
    let mut obj = String::new();
    let (n, m) = (16, 8);
    for i in 0..n {
        let u = std::f64::consts::TAU * i as f64 / n as f64;
        for j in 0..m {
            let v = std::f64::consts::TAU * j as f64 / m as f64;
            let rho = 0.3 + 0.08 * v.cos();
            obj += &format!("v {} {} {}\n", rho * u.cos(), rho * u.sin(), 0.08 * v.sin());
        }
    }
    for i in 0..n {
        for j in 0..m {
            let at = |i: usize, j: usize| (i % n) * m + (j % m) + 1;
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
        }
    }
    std::fs::write(dir.join("ring.obj"), obj).unwrap();
    let ringed = dir.join("ringed.urdf");
    std::fs::write(
        &ringed,
        "<robot name=\"r\">\
         <link name=\"ring\"><collision><geometry><mesh filename=\"ring.obj\"/></geometry></collision></link>\
         <link name=\"m\"><collision><origin xyz=\"0 0 0.5\"/><geometry><sphere radius=\"0.05\"/></geometry></collision></link>\
         <link name=\"b\"><collision><origin xyz=\"0 0 -0.5\"/><geometry><sphere radius=\"0.1\"/></geometry></collision></link>\
         <joint name=\"j1\" type=\"continuous\"><parent link=\"ring\"/><child link=\"m\"/></joint>\
         <joint name=\"j2\" type=\"continuous\"><parent link=\"m\"/><child link=\"b\"/><origin xyz=\"0 0 0.5\"/></joint>\
         </robot>\n",
    )
    .unwrap();
    for (flags, said) in [
        (&["--self-collision"][..], false),
        (&["--self-collision", "--convex-meshes"][..], true),
    ] {
        let out = tumble()
            .args(["run", "--steps", "5", "--fixed-base"])
            .args(flags)
            .arg(&ringed)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let summary = String::from_utf8_lossy(&out.stdout);
        let line = "self-collision: links that overlap in the file's pose never touch (pairs kept apart: 1)";
        assert_eq!(summary.contains(line), said, "{flags:?}: {summary}");
    }
    let bad = dir.join("bad.urdf");
    std::fs::write(
        &bad,
        "<robot name=\"r\">\n  <link name=\"a\"/>\n  <joint name=\"j\" type=\"planar\"/>\n</robot>\n",
    )
    .unwrap();
    let out = tumble().arg("run").arg(&bad).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.urdf:3:3: <joint name=\"j\">: joint type `planar` is not supported"),
        "{err}"
    );
}
