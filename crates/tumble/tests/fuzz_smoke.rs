//! The fuzz targets of `fuzz/` on stable Rust, in seconds: each target
//! replays its committed corpus (`fuzz/corpus/<target>/`) and the inputs
//! that once crashed it (`fuzz/regressions/<target>/`), then runs seeded
//! mutations of the corpus (bit flips, byte and chunk edits, splices, and
//! number literals swapped for nasty ones). Deterministic: the same inputs
//! every run. `TUMBLE_FUZZ_ITERS=N` sets the mutations per target (default
//! 2000); `scripts/fuzz.sh` runs the same targets under libFuzzer (nightly).
//! A failing input is written to `target/fuzz-smoke-failures/` and named in
//! the panic message: copy it into `fuzz/regressions/<target>/`.

#[path = "../../../fuzz/src/targets.rs"]
#[allow(dead_code)]
mod targets;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

/// SplitMix64 (`tumble-testkit`): deterministic, the same on every machine.
use tumble_testkit::{RandomSource, SplitMix64 as Rng};

/// Number literals that break careless parsers and arithmetic.
const NASTY_LITERALS: [&str; 14] = [
    "0",
    "-0",
    "-1",
    "1e308",
    "1e999",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "18446744073709551616",
    "0.0000001",
    "1000000",
    "65",
];

fn mutate(rng: &mut Rng, seed: &[u8], corpus: &[Vec<u8>]) -> Vec<u8> {
    let mut v = seed.to_vec();
    for _ in 0..1 + rng.below(4) {
        let len = v.len();
        match rng.below(7) {
            0 if len > 0 => {
                let i = rng.below(len);
                v[i] ^= 1 << rng.below(8);
            }
            1 if len > 0 => {
                let i = rng.below(len);
                v[i] = [0x00, 0xff, 0x7f, 0x80, rng.next_u64() as u8][rng.below(5)];
            }
            2 => {
                let i = rng.below(len + 1);
                let chunk: Vec<u8> = (0..1 + rng.below(8)).map(|_| rng.next_u64() as u8).collect();
                v.splice(i..i, chunk);
            }
            3 if len > 0 => {
                let i = rng.below(len);
                let j = (i + 1 + rng.below(16)).min(len);
                v.drain(i..j);
            }
            4 if !corpus.is_empty() => {
                let other = &corpus[rng.below(corpus.len())];
                let cut = rng.below(len + 1);
                let from = rng.below(other.len() + 1);
                v.truncate(cut);
                v.extend_from_slice(&other[from..]);
            }
            5 => {
                // Replace a run of digits (a number in a text format).
                let starts: Vec<usize> = (0..len)
                    .filter(|&i| v[i].is_ascii_digit() && (i == 0 || !v[i - 1].is_ascii_digit()))
                    .collect();
                if !starts.is_empty() {
                    let i = starts[rng.below(starts.len())];
                    let j = (i..len).find(|&k| !v[k].is_ascii_digit()).unwrap_or(len);
                    let lit = NASTY_LITERALS[rng.below(NASTY_LITERALS.len())].as_bytes();
                    v.splice(i..j, lit.iter().copied());
                }
            }
            _ if len > 1 => {
                let i = rng.below(len);
                let j = (i + 1 + rng.below(32)).min(len);
                let chunk = v[i..j].to_vec();
                let at = rng.below(len + 1);
                v.splice(at..at, chunk);
            }
            _ => v.push(rng.next_u64() as u8),
        }
    }
    v.truncate(1 << 16);
    v
}

fn read_dir_files(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let data = std::fs::read(&p).unwrap();
            (p, data)
        })
        .collect()
}

fn run_one(name: &str, target: fn(&[u8]), data: &[u8], origin: &str) {
    if catch_unwind(AssertUnwindSafe(|| target(data))).is_err() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/fuzz-smoke-failures");
        std::fs::create_dir_all(&dir).ok();
        let hash = data.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
            (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
        });
        let path = dir.join(format!("{name}-{hash:016x}"));
        std::fs::write(&path, data).ok();
        panic!(
            "fuzz target {name} panicked on {origin}; input saved to {}",
            path.display()
        );
    }
}

fn smoke(name: &str) {
    let target = targets::TARGETS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, f)| f)
        .expect("known target");
    let corpus = read_dir_files(&fuzz_dir().join("corpus").join(name));
    assert!(!corpus.is_empty(), "fuzz/corpus/{name} is empty");
    let regressions = read_dir_files(&fuzz_dir().join("regressions").join(name));
    for (path, data) in corpus.iter().chain(&regressions) {
        run_one(name, target, data, &path.display().to_string());
    }
    let iters: usize = std::env::var("TUMBLE_FUZZ_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000);
    let seeds: Vec<Vec<u8>> = corpus.into_iter().map(|(_, d)| d).collect();
    let mut rng = Rng(0x7475_6d62_6c65 ^ name.len() as u64 ^ (name.as_bytes()[0] as u64) << 32);
    for k in 0..iters {
        let seed = &seeds[rng.below(seeds.len())];
        let input = mutate(&mut rng, seed, &seeds);
        run_one(name, target, &input, &format!("mutation {k}"));
    }
    println!(
        "fuzz smoke {name}: {} corpus + {} regression inputs, {iters} mutations",
        seeds.len(),
        regressions.len()
    );
}

#[test]
fn fuzz_smoke_scene_toml() {
    smoke("scene_toml");
}

#[test]
fn fuzz_smoke_scene_json() {
    smoke("scene_json");
}

#[test]
fn fuzz_smoke_obj() {
    smoke("obj");
}

#[test]
fn fuzz_smoke_stl() {
    smoke("stl");
}

#[test]
fn fuzz_smoke_collide() {
    smoke("collide");
}

#[test]
fn fuzz_smoke_world_step() {
    smoke("world_step");
}

#[test]
fn fuzz_smoke_snapshot() {
    // The seeds are snapshots of this build's format (regenerated with
    // `write_seed_corpus` when the format changes): seeds of an older one
    // would only reach the version check.
    for (path, data) in read_dir_files(&fuzz_dir().join("corpus").join("snapshot")) {
        let read = match path.extension().and_then(|e| e.to_str()) {
            Some("json") => tumble::world::Snapshot::from_json(std::str::from_utf8(&data).unwrap()),
            _ => tumble::world::Snapshot::from_bytes(&data),
        };
        let snapshot = read.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        tumble::world::World::from_snapshot(&snapshot).unwrap();
    }
    smoke("snapshot");
}

#[test]
fn fuzz_smoke_narrow() {
    smoke("narrow");
}

#[test]
fn fuzz_smoke_urdf() {
    smoke("urdf");
}

#[test]
fn fuzz_smoke_joints() {
    smoke("joints");
}

#[test]
fn fuzz_smoke_sweep() {
    smoke("sweep");
}

/// Writes the seed corpus of every target into `fuzz/corpus/` (run once by
/// hand with `--ignored`; the files are committed; rerun when a target is
/// added).
#[test]
#[ignore]
fn write_seed_corpus() {
    use tumble::collide::mesh::{box_mesh, torus_mesh};
    use tumble::collide::DVec3;
    let root = fuzz_dir().join("corpus");
    let write = |target: &str, name: &str, data: &[u8]| {
        let dir = root.join(target);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(name), data).unwrap();
    };
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes");
    for (path, data) in read_dir_files(&scenes) {
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        match path.extension().and_then(|e| e.to_str()) {
            Some("toml") => write("scene_toml", &file, &data),
            Some("json") => write("scene_json", &file, &data),
            _ => {}
        }
    }
    write(
        "scene_toml",
        "small.toml",
        b"[settings]\ndt = 0.01\n[[bodies]]\nkind = \"static\"\nshapes = [{ type = \"half_space\" }]\n\
          [[bodies]]\nshapes = [{ type = \"box\", half_extents = [0.5, 0.5, 0.5] }]\nmass = 2\n\
          position = [0, 0, 1]\nrotation = [{ z = 30 }]\nvelocity = [1, 0, 0]\n",
    );
    write(
        "scene_toml",
        "no_contact.toml",
        b"[[bodies]]\nname = \"a\"\nshapes = [{ type = \"sphere\", radius = 0.5 }]\n\
          [[bodies]]\nname = \"b\"\nshapes = [{ type = \"sphere\", radius = 0.5 }]\nposition = [0.5, 0, 0]\n\
          [[no_contact]]\nbodies = [\"a\", \"b\"]\n",
    );
    write(
        "scene_json",
        "small.json",
        br#"{"settings": {"dt": 0.01}, "bodies": [{"kind": "static", "shapes": [{"type": "half_space"}]},
            {"shapes": [{"type": "sphere", "radius": 0.5}], "mass": 1, "position": [0, 0, 1],
             "orientation": [0, 0, 0, 1], "grid": {"count": [2, 1, 1], "spacing": [1, 0, 0]}}]}"#,
    );
    let obj_of = |m: &tumble::collide::TriMesh| {
        let mut s = String::new();
        for v in m.vertices() {
            s += &format!("v {} {} {}\n", v.x, v.y, v.z);
        }
        for t in m.triangles() {
            s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    };
    write(
        "obj",
        "cube.obj",
        obj_of(&box_mesh(DVec3::new(0.5, 1.0, 0.25)).unwrap()).as_bytes(),
    );
    write(
        "obj",
        "torus.obj",
        obj_of(&torus_mesh(1.0, 0.3, 8, 6).unwrap()).as_bytes(),
    );
    write(
        "obj",
        "tetra.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    );
    write(
        "obj",
        "quad_normals.obj",
        b"# quad with normals and uvs\no q\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
          f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4 -2 -3\n",
    );
    let stl_binary = |m: &tumble::collide::TriMesh| {
        let mut out = vec![0u8; 80];
        out.extend((m.triangles().len() as u32).to_le_bytes());
        for t in 0..m.triangles().len() {
            out.extend([0f32; 3].iter().flat_map(|x| x.to_le_bytes()));
            for p in m.triangle(t) {
                out.extend(
                    [p.x as f32, p.y as f32, p.z as f32]
                        .iter()
                        .flat_map(|x| x.to_le_bytes()),
                );
            }
            out.extend([0u8, 0u8]);
        }
        out
    };
    write(
        "stl",
        "cube.stl",
        &stl_binary(&box_mesh(DVec3::splat(0.5)).unwrap()),
    );
    write(
        "stl",
        "torus.stl",
        &stl_binary(&torus_mesh(1.0, 0.3, 6, 4).unwrap()),
    );
    write(
        "stl",
        "tetra_ascii.stl",
        b"solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n\
          facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n\
          facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n\
          facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n",
    );
    // Structured targets: bytes from a fixed generator, plus plain patterns.
    let mut rng = Rng(2024);
    for target in ["collide", "world_step", "narrow", "joints"] {
        for k in 0..12 {
            let len = 32 + rng.below(224);
            let data: Vec<u8> = (0..len).map(|_| (rng.next_u64() % 224) as u8).collect();
            write(target, &format!("random_{k:02}"), &data);
        }
        write(target, "zeros", &[0u8; 128]);
        write(target, "mid", &[0x70u8; 160]);
    }
    // Snapshots of a small world of every shape kind, fresh and stepped.
    let mut world = tumble::world::World::new(Default::default()).unwrap();
    let descs = [
        tumble::world::BodyDesc::fixed(tumble::collide::HalfSpace::ground()),
        tumble::world::BodyDesc::dynamic(tumble::collide::Sphere::new(0.2).unwrap())
            .at(DVec3::new(0.0, 0.0, 0.5)),
        tumble::world::BodyDesc::dynamic(
            tumble::collide::MeshShape::new(box_mesh(DVec3::splat(0.2)).unwrap()).unwrap(),
        )
        .at(DVec3::new(1.0, 0.0, 0.3)),
        tumble::world::BodyDesc::dynamic(
            tumble::collide::ConvexHull::from_mesh(&box_mesh(DVec3::splat(0.2)).unwrap()).unwrap(),
        )
        .at(DVec3::new(-1.0, 0.0, 0.3)),
    ];
    let ids: Vec<_> = descs.iter().map(|d| world.add_body(d).unwrap()).collect();
    world.set_contacts_between(ids[2], ids[1], false).unwrap();
    write("snapshot", "fresh.snap", &world.snapshot().to_bytes());
    write("snapshot", "fresh.json", world.snapshot().to_json().as_bytes());
    for _ in 0..30 {
        world.step();
    }
    write("snapshot", "stepped.snap", &world.snapshot().to_bytes());
    write("snapshot", "stepped.json", world.snapshot().to_json().as_bytes());
    // Sweeps: a JSON line of parameters, steps and metrics, then a scene.
    let scene_text = |name: &str| std::fs::read_to_string(scenes.join(name)).unwrap();
    for (name, head, scene) in [
        (
            "bounce",
            r#"{"params": [["bodies[ball].restitution", [0.5, 0.9]], ["settings.dt", [0.004, 0.01]]], "steps": 8, "metrics": ["ball.rebound_z", "ball.max_z", "energy_drift", "max_penetration"]}"#,
            scene_text("bounce.toml"),
        ),
        (
            "door",
            r#"{"params": [["bodies[1].mass", [1, 5, 20]]], "steps": 4, "metrics": ["max_joint_error", "toppled", "time", "kinetic_energy_end"]}"#,
            scene_text("door.toml"),
        ),
        (
            "first",
            r#"{"params": [["settings.substeps", [1, 4]], ["settings.gravity", [[0, 0, -9.81], [0, 0, -1]]]], "steps": 3, "metrics": ["energy_start", "energy_end"]}"#,
            scene_text("first.toml"),
        ),
    ] {
        write(
            "sweep",
            &format!("{name}.txt"),
            format!("{head}\n{scene}").as_bytes(),
        );
    }
    // The shipped robots, and a small one of every joint type and geometry.
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/robots");
    for (path, data) in read_dir_files(&robots) {
        if path.extension().and_then(|e| e.to_str()) == Some("urdf") {
            write("urdf", &path.file_name().unwrap().to_string_lossy(), &data);
        }
    }
    write(
        "urdf",
        "small.urdf",
        br#"<robot name="r">
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><box size="0.4 0.4 0.2"/></geometry></collision></link>
  <link name="a"><inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0 0 0.1" rpy="0 0 0"/><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision></link>
  <link name="b"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="c"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/><dynamics damping="0.1"/></joint>
  <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/><origin xyz="0 0 0.2"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.1" effort="5" velocity="1"/></joint>
  <joint name="j3" type="continuous"><parent link="b"/><child link="c"/><axis xyz="0 1 0"/></joint>
  <joint name="j4" type="fixed"><parent link="base"/><child link="d"/></joint>
  <link name="d"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
</robot>
"#,
    );
}
