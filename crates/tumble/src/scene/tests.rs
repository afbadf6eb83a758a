//! Scene file tests: values reach the world as written, and every kind of bad
//! input gives one line naming the file, line, column and field.
//!
//! The error tests repeat one pattern (edit `GROUND_AND_BALL`, parse, take
//! `at`'s line, column, path and message, assert them) case by case, so
//! that each edit stands beside the location and message it must produce.

use super::*;
use std::path::Path;
use tumble_collide::shape::Shape;
use tumble_collide::DQuat;

fn toml(text: &str) -> Result<LoadedScene, SceneError> {
    parse_scene(text, Format::Toml, Path::new("dir/test.toml"))
}

fn json(text: &str) -> Result<LoadedScene, SceneError> {
    parse_scene(text, Format::Json, Path::new("dir/test.json"))
}

/// The error's (line, column, path, message), asserting it is one line.
fn at(e: SceneError) -> (usize, usize, String, String) {
    let line = e.to_string();
    assert!(!line.contains('\n'), "error is not one line: {line:?}");
    match e {
        SceneError::At {
            line,
            column,
            path,
            message,
            ..
        } => (line, column, path, message),
        other => panic!("expected a located error, got {other}"),
    }
}

/// Line and column (1-based) of the first occurrence of `needle` in `text`.
fn position_of(text: &str, needle: &str) -> (usize, usize) {
    let offset = text.find(needle).expect("needle in text");
    locate::line_column(text, offset)
}

const GROUND_AND_BALL: &str = r#"
[[bodies]]
name = "ground"
kind = "static"
shapes = [{ type = "half_space" }]

[[bodies]]
name = "ball"
shapes = [{ type = "sphere", radius = 0.5 }]
mass = 2.0
position = [0, 0, 3]
"#;

#[test]
fn values_reach_the_world_as_written() {
    let text = r#"
name = "check"
steps = 7
[settings]
dt = 0.01
gravity = [0, 0, -1.62]
solver = "lemke"
integrator = "rk4"
[materials.rubber]
friction = 0.9
restitution = 0.8
[[bodies]]
name = "b"
material = "rubber"
shapes = [{ type = "box", half_extents = [1, 2, 3], local_pose = { position = [0, 0, 1] } }]
density = 2.0
position = [1, 2, 3]
rotation = [{ z = 90 }, { x = 90 }]
linear_velocity = [1, 0, 0]
angular_velocity = [0, 0, 0.5]
initial_force = [0, 0, 10]
"#;
    let s = toml(text).unwrap();
    assert_eq!(s.scene.name, "check");
    assert_eq!(s.scene.steps, 7);
    assert_eq!(s.scene.settings.dt, 0.01);
    assert_eq!(s.scene.settings.gravity, DVec3::new(0.0, 0.0, -1.62));
    assert_eq!(s.scene.settings.solver, crate::world::SolverKind::Lemke);
    assert_eq!(s.scene.settings.integrator, crate::integrate::Integrator::Rk4);
    let b = &s.scene.bodies[0];
    assert_eq!(b.material.friction, 0.9);
    assert_eq!(b.material.restitution, 0.8);
    assert_eq!(b.mass, crate::world::MassDesc::Density(2.0));
    assert_eq!(b.pose.position, DVec3::new(1.0, 2.0, 3.0));
    // Rz(90) * Rx(90): x -> y... applied to x: Rx keeps x, Rz turns it to y.
    let q = b.pose.rotation;
    let expected = DQuat::from_rotation_z(FRAC_PI_2) * DQuat::from_rotation_x(FRAC_PI_2);
    assert!(q.dot(expected).abs() > 1.0 - 1e-15);
    assert!((q * DVec3::X - DVec3::Y).length() < 1e-15);
    assert!((q * DVec3::Y - DVec3::Z).length() < 1e-15);
    assert_eq!(b.shapes[0].local_pose.position, DVec3::new(0.0, 0.0, 1.0));
    assert_eq!(
        s.initial_loads,
        vec![InitialLoad {
            body: 0,
            force: DVec3::new(0.0, 0.0, 10.0),
            torque: DVec3::ZERO
        }]
    );
    // Density 2 of a 2 x 4 x 6 box: 96 kg. The initial force acts in step 1
    // only (constant accelerations: exact for every integrator).
    let (mut world, ids) = s.build().unwrap();
    assert!((world.body(ids[0]).unwrap().mass() - 96.0).abs() < 1e-12);
    world.step();
    let v1 = world.linear_velocity(ids[0]).unwrap().z;
    assert!((v1 - (10.0 / 96.0 - 1.62) * 0.01).abs() < 1e-12, "v1 = {v1}");
    world.step();
    let v2 = world.linear_velocity(ids[0]).unwrap().z;
    assert!((v2 - v1 + 1.62 * 0.01).abs() < 1e-12, "v2 - v1 = {}", v2 - v1);
    let damped = toml(&GROUND_AND_BALL.replace(
        "mass = 2.0",
        "mass = 2.0\nlinear_damping = 0.1\nangular_damping = 0.2",
    ))
    .unwrap();
    let b = &damped.scene.bodies[1];
    assert_eq!((b.linear_damping, b.angular_damping), (0.1, 0.2));
    assert!(!b.ccd);
    let swept = toml(&GROUND_AND_BALL.replace("mass = 2.0", "mass = 2.0\nccd = true")).unwrap();
    assert!(swept.scene.bodies[1].ccd);
    let err = toml(&GROUND_AND_BALL.replace("mass = 2.0", "mass = 2.0\nccd = 1")).unwrap_err();
    assert!(err.to_string().contains("ccd"), "{err}");
}

use std::f64::consts::FRAC_PI_2;

#[test]
fn defaults_without_steps_give_ten_seconds() {
    let s = toml(GROUND_AND_BALL).unwrap();
    assert_eq!(s.scene.steps, 600);
    assert_eq!(s.scene.name, "test", "name from the file stem");
    assert_eq!(s.scene.settings, crate::world::WorldSettings::default());
    let d = toml(&format!("duration = 0.5\n{GROUND_AND_BALL}")).unwrap();
    assert_eq!(d.scene.steps, 30);
}

#[test]
fn grid_copies_in_order_with_names_offsets_and_alternating_shapes() {
    let text = r#"
[shapes.a]
type = "sphere"
radius = 0.1
[shapes.b]
type = "box"
half_extents = [0.1, 0.1, 0.1]
[[bodies]]
name = "c{i}_{j}_{k}_{n}"
mass = 1.0
position = [1, 2, 3]
grid = { count = [3, 2, 2], spacing = [0.5, 0.25, 1.0], odd_layer_offset = [0.01, 0.02, 0], alternate_shapes = ["a", "b"] }
"#;
    let s = toml(text).unwrap();
    assert_eq!(s.scene.bodies.len(), 12);
    let mut n = 0;
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..3 {
                let b = &s.scene.bodies[n];
                assert_eq!(b.name, format!("c{i}_{j}_{k}_{n}"));
                let odd = if k == 1 {
                    DVec3::new(0.01, 0.02, 0.0)
                } else {
                    DVec3::ZERO
                };
                let want = DVec3::new(1.0 + 0.5 * i as f64, 2.0 + 0.25 * j as f64, 3.0 + k as f64) + odd;
                assert!((b.pose.position - want).length() < 1e-14);
                let is_sphere = matches!(b.shapes[0].shape, Shape::Sphere(_));
                assert_eq!(is_sphere, (i + j + k) % 2 == 0);
                n += 1;
            }
        }
    }
}

#[test]
fn json_and_toml_read_the_same() {
    let t = toml(GROUND_AND_BALL).unwrap();
    let j = json(
        r#"{"bodies": [
        {"name": "ground", "kind": "static", "shapes": [{"type": "half_space"}]},
        {"name": "ball", "shapes": [{"type": "sphere", "radius": 0.5}], "mass": 2.0, "position": [0, 0, 3]}
    ]}"#,
    )
    .unwrap();
    assert_eq!(t.scene.bodies, j.scene.bodies);
    assert_eq!(t.scene.settings, j.scene.settings);
}

#[test]
fn negative_mass_is_located_at_its_value() {
    let text = GROUND_AND_BALL.replace("mass = 2.0", "mass = -1");
    let (line, column, path, message) = at(toml(&text).unwrap_err());
    assert_eq!((line, column), position_of(&text, "-1"));
    assert_eq!(path, "bodies[1].mass");
    assert_eq!(message, "must be finite and > 0 kg, got -1");
}

#[test]
fn a_mesh_crease_angle_outside_0_to_180_degrees_is_located() {
    let text = GROUND_AND_BALL.replace(
        r#"shapes = [{ type = "sphere", radius = 0.5 }]"#,
        r#"shapes = [{ type = "mesh", mesh = { icosphere = { radius = 0.5 } }, crease_angle_deg = 200.0 }]"#,
    );
    let (line, _, path, message) = at(toml(&text).unwrap_err());
    assert_eq!(line, position_of(&text, "crease_angle_deg").0);
    assert_eq!(path, "bodies[1].shapes[0].crease_angle_deg");
    assert_eq!(message, "must be an angle in (0, 180) degrees, got 200");
    let good = text.replace("200.0", "30.0");
    let loaded = toml(&good).unwrap();
    let tumble_collide::shape::Shape::Mesh(m) = &loaded.scene.bodies[1].shapes[0].shape else {
        panic!("not a mesh")
    };
    assert!((m.crease_angle().unwrap() - 30f64.to_radians()).abs() < 1e-15);
}

#[test]
fn a_body_replaces_its_materials_friction_and_restitution_within_bounds() {
    let text = GROUND_AND_BALL.replace("mass = 2.0", "mass = 2.0\nrestitution = 0.25\nfriction = 1.5");
    let b = &toml(&text).unwrap().scene.bodies[1];
    assert_eq!((b.material.restitution, b.material.friction), (0.25, 1.5));
    let text = GROUND_AND_BALL.replace("mass = 2.0", "mass = 2.0\nrestitution = 1.5");
    let (_, _, path, message) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[1].restitution");
    assert_eq!(message, "must be in [0, 1], got 1.5");
}

#[test]
fn unknown_key_is_an_error_not_ignored() {
    let text = GROUND_AND_BALL.replace("mass = 2.0", "masss = 2.0");
    let (line, column, path, message) = at(toml(&text).unwrap_err());
    assert_eq!((line, column), position_of(&text, "masss"));
    assert!(message.contains("unknown field `masss`"), "{message}");
    assert!(path.starts_with("bodies[1]"), "{path}");
    // In a settings table and in a shape too.
    let e = toml(&format!("[settings]\ndtt = 0.1\n{GROUND_AND_BALL}")).unwrap_err();
    assert!(e.to_string().starts_with("dir/test.toml:2:1: settings"), "{e}");
    let text = GROUND_AND_BALL.replace("radius = 0.5", "radius = 0.5, radus = 1");
    let (line, _, path, message) = at(toml(&text).unwrap_err());
    assert_eq!(line, position_of(&text, "radus").0);
    assert!(message.contains("unknown field `radus`"), "{message}");
    assert!(path.starts_with("bodies[1].shapes[0]"), "{path}");
}

#[test]
fn unknown_shape_type_names_the_choices() {
    let text = GROUND_AND_BALL.replace("type = \"sphere\"", "type = \"sphre\"");
    let (line, _, path, message) = at(toml(&text).unwrap_err());
    assert_eq!(line, position_of(&text, "sphre").0);
    assert_eq!(path, "bodies[1].shapes[0].type");
    assert!(message.contains("unknown variant `sphre`"), "{message}");
    assert!(
        message.contains("`sphere`") && message.contains("`mesh`"),
        "{message}"
    );
}

#[test]
fn nan_in_a_pose_is_rejected() {
    let text = GROUND_AND_BALL.replace("position = [0, 0, 3]", "position = [0, nan, 3]");
    let (line, column, path, message) = at(toml(&text).unwrap_err());
    assert_eq!((line, column), position_of(&text, "[0, nan"));
    assert_eq!(path, "bodies[1].position");
    assert!(message.contains("must be finite"), "{message}");
    let text = GROUND_AND_BALL.replace("position = [0, 0, 3]", "orientation = [0, 0, inf, 1]");
    let (_, _, path, _) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[1].orientation");
    // JSON has no NaN literal: a syntax error at the token.
    let e = json(r#"{"bodies": [{"shapes": [{"type": "sphere", "radius": 1}], "position": [0, NaN, 0]}]}"#)
        .unwrap_err();
    let (line, column, _, _) = at(e);
    assert_eq!(line, 1);
    assert!(column > 60, "column {column}");
}

#[test]
fn non_unit_quaternion_and_ambiguous_orientation() {
    let text = GROUND_AND_BALL.replace("position = [0, 0, 3]", "orientation = [0, 0, 0, 2]");
    let (_, _, path, message) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[1].orientation");
    assert!(message.contains("unit quaternion"), "{message}");
    // Rounded unit quaternions are accepted and normalised.
    let text = GROUND_AND_BALL.replace("position = [0, 0, 3]", "orientation = [0, 0, 0.7071, 0.7071]");
    let q = toml(&text).unwrap().scene.bodies[1].pose.rotation;
    assert!((q.length() - 1.0).abs() < 1e-15);
    let text = GROUND_AND_BALL.replace(
        "position = [0, 0, 3]",
        "orientation = [0, 0, 0, 1]\nrotation = [{ x = 10 }]",
    );
    let (_, _, path, _) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[1].rotation");
    let text = GROUND_AND_BALL.replace("position = [0, 0, 3]", "rotation = [{ x = 10, y = 5 }]");
    let (_, _, path, message) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[1].rotation[0]");
    assert!(message.contains("exactly one"), "{message}");
}

#[test]
fn negative_timestep_is_a_settings_error() {
    let text = format!("[settings]\ndt = -0.01\n{GROUND_AND_BALL}");
    let (line, column, path, message) = at(toml(&text).unwrap_err());
    assert_eq!((line, column), (2, 6));
    assert_eq!(path, "settings.dt");
    assert!(message.contains("> 0") && message.contains("-0.01"), "{message}");
    let e = json(r#"{"settings": {"dt": -1}, "bodies": []}"#).unwrap_err();
    assert_eq!(
        e.to_string(),
        "dir/test.json:1:21: settings.dt: must be finite and > 0, got -1"
    );
}

#[test]
fn missing_mesh_file_names_the_path() {
    let text = r#"
[[bodies]]
shapes = [{ type = "mesh", mesh = { file = "no/such/mesh.obj" } }]
"#;
    let (line, _, path, message) = at(toml(text).unwrap_err());
    assert_eq!(line, 3);
    assert_eq!(path, "bodies[0].shapes[0].mesh.file");
    assert!(message.contains("no/such/mesh.obj"), "{message}");
}

#[test]
fn open_mesh_with_mass_from_density_is_located_at_the_shape() {
    let dir = std::env::temp_dir().join(format!("tumble_scene_test_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A tetrahedron with one face missing: not closed, so it has no volume.
    std::fs::write(
        dir.join("open.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n",
    )
    .unwrap();
    let text =
        "[[bodies]]\ndensity = 1000.0\nshapes = [{ type = \"mesh\", mesh = { file = \"open.obj\" } }]\n";
    let scene_path = dir.join("open.toml");
    std::fs::write(&scene_path, text).unwrap();
    let loaded = load_scene(&scene_path).expect("the mesh itself loads");
    let (line, column, path, message) = at(loaded.build().unwrap_err());
    assert_eq!((line, column), (3, 11));
    assert_eq!(path, "bodies[0].shapes[0]");
    assert!(!message.is_empty());
    // As a static body the open mesh needs no mass and is accepted.
    let text =
        "[[bodies]]\nkind = \"static\"\nshapes = [{ type = \"mesh\", mesh = { file = \"open.obj\" } }]\n";
    std::fs::write(&scene_path, text).unwrap();
    assert!(load_scene(&scene_path).unwrap().build().is_ok());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn world_rejections_point_at_the_body() {
    // A static body with a velocity is refused by World::add_body.
    let text = GROUND_AND_BALL.replace(
        "kind = \"static\"",
        "kind = \"static\"\nlinear_velocity = [1, 0, 0]",
    );
    let loaded = toml(&text).unwrap();
    let (line, _, path, _) = at(loaded.build().unwrap_err());
    assert_eq!(path, "bodies[0].linear_velocity");
    assert_eq!(line, position_of(&text, "linear_velocity").0);
    // A half-space on a dynamic body.
    let text = GROUND_AND_BALL.replace("kind = \"static\"\n", "");
    let (_, _, path, message) = at(toml(&text).unwrap().build().unwrap_err());
    assert_eq!(path, "bodies[0].shapes[0]");
    assert!(message.contains("half-space"), "{message}");
}

#[test]
fn references_and_exclusive_keys() {
    // Edit, parse, check path and message, as in
    // non_unit_quaternion_and_ambiguous_orientation: each edit stays beside
    // the field it must name, so a failure shows which key.
    let text = GROUND_AND_BALL.replace("mass = 2.0", "mass = 2.0\nmaterial = \"ice\"");
    let (_, _, path, message) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[1].material");
    assert!(message.contains("unknown material `ice`"), "{message}");
    let text = GROUND_AND_BALL.replace("mass = 2.0", "mass = 2.0\ndensity = 3.0");
    let (_, _, path, _) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[1].density");
    let text = "[[bodies]]\nshape = \"nothing\"\n";
    let (_, _, path, message) = at(toml(text).unwrap_err());
    assert_eq!(path, "bodies[0].shape");
    assert!(message.contains("unknown shape `nothing`"), "{message}");
    let text = GROUND_AND_BALL.replace("kind = \"static\"", "kind = \"static\"\nmass = 1.0");
    let (_, _, path, _) = at(toml(&text).unwrap_err());
    assert_eq!(path, "bodies[0].mass");
    let text = format!("steps = 5\nduration = 1.0\n{GROUND_AND_BALL}");
    let (_, _, path, _) = at(toml(&text).unwrap_err());
    assert_eq!(path, "duration");
}

#[test]
fn syntax_errors_are_located() {
    let (line, _, path, _) = at(toml("[[bodies]]\nmass = = 1\n").unwrap_err());
    assert_eq!((line, path.as_str()), (2, ""));
    let (line, column, _, _) = at(json("{\n  \"bodies\": [\n    {\"mass\": 1,}\n  ]\n}").unwrap_err());
    assert_eq!(line, 3);
    assert!(column > 10);
    assert!(matches!(
        load_scene("scene.yaml").unwrap_err(),
        SceneError::Format { .. }
    ));
    assert!(matches!(
        load_scene("/no/such/scene.toml").unwrap_err(),
        SceneError::Read { .. }
    ));
}

#[test]
fn field_paths_print_like_the_file() {
    let p = FieldPath::root()
        .key("bodies")
        .index(3)
        .key("shapes")
        .index(0)
        .key("radius");
    assert_eq!(p.to_string(), "bodies[3].shapes[0].radius");
}

/// `docs/scene.schema.json` is generated from the schema types; this fails
/// when they drift apart. Regenerate with
/// `TUMBLE_UPDATE_SCHEMA=1 cargo test -p tumble --release scene::tests::json_schema`.
#[test]
fn json_schema_file_is_in_sync() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene.schema.json");
    let generated = json_schema();
    if std::env::var_os("TUMBLE_UPDATE_SCHEMA").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let shipped = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        shipped == generated,
        "docs/scene.schema.json is out of date: regenerate it with \
         TUMBLE_UPDATE_SCHEMA=1 cargo test -p tumble --release scene::tests::json_schema"
    );
    // It describes what the parser accepts: closed objects and the shape kinds.
    let v: serde_json::Value = serde_json::from_str(&generated).unwrap();
    assert_eq!(v["additionalProperties"], serde_json::json!(false));
    for kind in ["sphere", "box", "capsule", "convex_hull", "half_space", "mesh"] {
        assert!(generated.contains(&format!("\"{kind}\"")), "schema lacks {kind}");
    }
}

/// The schema's integer bounds on the solver settings are the ones the
/// world enforces: the bound itself is accepted, one past it refused.
#[test]
fn json_schema_integer_bounds_are_the_worlds() {
    let v: serde_json::Value = serde_json::from_str(&json_schema()).unwrap();
    let settings = &v["$defs"]["WorldSettings"]["properties"];
    let accepted = |field: &str, value: u64| {
        let mut s = crate::world::WorldSettings::default();
        let n = value as u32;
        match field {
            "substeps" => s.substeps = n,
            "iterations" => s.iterations = n,
            "push_out_iterations" => s.push_out_iterations = n,
            "threads" => s.threads = n,
            _ => unreachable!(),
        }
        // The settings check of `World::new` (a world of 1,024 threads
        // would start them).
        crate::world::check_settings(&s).is_ok()
    };
    for field in ["substeps", "iterations", "push_out_iterations", "threads"] {
        let bound = |key: &str| settings[field][key].as_u64();
        let (lo, hi) = (bound("minimum").unwrap(), bound("maximum"));
        let hi = hi.unwrap_or_else(|| panic!("{field}: no maximum in the schema"));
        assert!(
            accepted(field, lo) && accepted(field, hi),
            "{field}: {lo}..={hi} refused"
        );
        if lo > 0 {
            assert!(!accepted(field, lo - 1), "{field}: {} accepted", lo - 1);
        }
        assert!(!accepted(field, hi + 1), "{field}: {} accepted", hi + 1);
    }
}

const PENDULUM: &str = r#"
[[bodies]]
name = "post"
kind = "static"
shapes = [{ type = "box", half_extents = [0.05, 0.05, 0.05] }]
position = [0, 0, 1]

[[bodies]]
name = "bob"
shapes = [{ type = "sphere", radius = 0.05 }]
mass = 1.0
position = [0.5, 0, 1]

[[joints]]
kind = "hinge"
body_a = "bob"
body_b = "post"
anchor = [0, 0, 1]
axis = [0, 1, 0]
limits = [-1.0, 2.0]
motor = { type = "velocity", target = 0.5, max_force = 0.1 }
"#;

#[test]
fn joints_reach_the_world_as_written() {
    let loaded = toml(PENDULUM).unwrap();
    let (mut world, ids) = loaded.build().unwrap();
    assert_eq!(world.joint_count(), 1);
    let j = world.joint_ids()[0];
    let desc = world.joint(j).unwrap();
    assert_eq!(desc.kind, crate::joint::JointKind::Hinge);
    assert_eq!((desc.body_a, desc.body_b), (ids[1], Some(ids[0])));
    assert_eq!(desc.limits, Some([-1.0, 2.0]));
    assert_eq!(
        desc.motor,
        Some(crate::joint::Motor::Velocity {
            target: 0.5,
            max_force: 0.1
        })
    );
    for _ in 0..30 {
        world.step();
    }
    // The bob swings down on its hinge: its distance to the anchor stays.
    let p = world.center_of_mass(ids[1]).unwrap();
    assert!(((p - DVec3::new(0.0, 0.0, 1.0)).length() - 0.5).abs() < 1e-3);
    assert!(p.z < 0.9);
}

const GEARED: &str = r#"
[[bodies]]
name = "wheel_a"
shapes = [{ type = "sphere", radius = 0.1 }]
mass = 1.0

[[bodies]]
name = "wheel_b"
shapes = [{ type = "sphere", radius = 0.1 }]
mass = 1.0
position = [0.3, 0, 0]

[[joints]]
name = "drive"
kind = "hinge"
body_a = "wheel_a"
anchor = [0, 0, 0]
motor = { type = "velocity", target = 2.0, max_force = 100.0 }

[[joints]]
name = "driven"
kind = "hinge"
body_a = "wheel_b"
anchor = [0.3, 0, 0]
gear = { leader = "drive", ratio = -2.0 }
"#;

#[test]
fn a_gear_reaches_the_world_and_bad_gears_are_located() {
    let loaded = toml(GEARED).unwrap();
    let (mut world, ids) = loaded.build().unwrap();
    let [drive, driven] = [world.joint_ids()[0], world.joint_ids()[1]];
    assert_eq!(
        world.joint_gear(driven).unwrap(),
        Some(crate::joint::Gear::new(drive, -2.0))
    );
    for _ in 0..30 {
        world.step();
    }
    let spin = |k: usize| world.angular_velocity(ids[k]).unwrap().z;
    assert!(
        (spin(0) - 2.0).abs() < 1e-6 && (spin(1) + 4.0).abs() < 1e-6,
        "{} {}",
        spin(0),
        spin(1)
    );

    let unknown = GEARED.replace("leader = \"drive\"", "leader = \"drvie\"");
    let (line, column, path, message) = at(toml(&unknown).err().unwrap());
    assert_eq!(path, "joints[1].gear.leader");
    assert_eq!((line, column), position_of(&unknown, "\"drvie\""));
    assert!(
        message.contains("no joint is named `drvie`") && message.contains("drive"),
        "{message}"
    );

    let twice = GEARED.replace("name = \"driven\"", "name = \"drive\"");
    let (_, _, path, message) = at(toml(&twice).err().unwrap());
    assert_eq!(path, "joints[1].gear.leader");
    assert!(message.contains("2 joints are named"), "{message}");

    let nan = GEARED.replace("ratio = -2.0", "ratio = nan");
    let (line, column, path, _) = at(toml(&nan).unwrap().build().err().unwrap());
    assert_eq!(path, "joints[1].gear.ratio");
    assert_eq!((line, column), position_of(&nan, "nan"));

    let itself = GEARED.replace("leader = \"drive\"", "leader = \"driven\"");
    let (_, _, path, message) = at(toml(&itself).unwrap().build().err().unwrap());
    assert_eq!(path, "joints[1].gear.leader");
    assert!(message.contains("itself"), "{message}");

    let ball = GEARED.replace(
        "kind = \"hinge\"\nbody_a = \"wheel_b\"",
        "kind = \"ball\"\nbody_a = \"wheel_b\"",
    );
    let (_, _, path, message) = at(toml(&ball).unwrap().build().err().unwrap());
    assert_eq!(path, "joints[1].gear");
    assert!(message.contains("hinges and sliders"), "{message}");
}

#[test]
fn bad_joints_are_located_at_their_field() {
    let swapped = PENDULUM.replace("limits = [-1.0, 2.0]", "limits = [2.0, -1.0]");
    let (line, column, path, message) = at(toml(&swapped).err().unwrap());
    assert_eq!(path, "joints[0].limits");
    assert_eq!((line, column), position_of(&swapped, "[2.0, -1.0]"));
    assert!(message.contains("lower <= upper"), "{message}");

    let unknown = PENDULUM.replace("body_b = \"post\"", "body_b = \"pots\"");
    let (_, _, path, message) = at(toml(&unknown).err().unwrap());
    assert_eq!(path, "joints[0].body_b");
    assert!(message.contains("no body is named `pots`"), "{message}");

    let bad_motor = PENDULUM.replace("max_force = 0.1", "max_force = -2");
    let (_, _, path, _) = at(toml(&bad_motor).err().unwrap());
    assert_eq!(path, "joints[0].motor.max_force");

    // A spring on a hinge or a ball joint is read; on a weld it is refused
    // at its field.
    let sprung = PENDULUM.replace(
        "axis = [0, 1, 0]",
        "axis = [0, 1, 0]\nspring = { stiffness = 2.0, damping = 0.5 }",
    );
    let (world, _) = toml(&sprung).unwrap().build().unwrap();
    let spring = world.joint(world.joint_ids()[0]).unwrap().spring;
    assert_eq!(
        spring,
        Some(crate::joint::Spring {
            stiffness: 2.0,
            damping: 0.5
        })
    );
    let ball = sprung.replace("kind = \"hinge\"", "kind = \"ball\"").replace(
        "limits = [-1.0, 2.0]\nmotor = { type = \"velocity\", target = 0.5, max_force = 0.1 }\n",
        "",
    );
    let (world, _) = toml(&ball).unwrap().build().unwrap();
    let joint = world.joint(world.joint_ids()[0]).unwrap();
    assert_eq!(
        (joint.kind, joint.spring),
        (crate::joint::JointKind::Ball, spring)
    );
    // A ball joint's motor takes a vector target; a hinge's motor on it is
    // refused at its field.
    let driven = ball.replace(
        "kind = \"ball\"",
        "kind = \"ball\"\nmotor = { type = \"orientation\", target = [0, 0, 0.5], stiffness = 3.0, damping = 0.2, max_force = 1.5 }",
    );
    let (world, _) = toml(&driven).unwrap().build().unwrap();
    assert_eq!(
        world.joint(world.joint_ids()[0]).unwrap().motor,
        Some(crate::joint::Motor::Orientation {
            target: [0.0, 0.0, 0.5],
            stiffness: 3.0,
            damping: 0.2,
            max_force: 1.5
        })
    );
    let scalar = ball.replace(
        "kind = \"ball\"",
        "kind = \"ball\"\nmotor = { type = \"velocity\", target = 0.5, max_force = 0.1 }",
    );
    let (_, _, path, message) = at(toml(&scalar).err().unwrap());
    assert_eq!(path, "joints[0].motor");
    assert!(message.contains("angular_velocity"), "{message}");
    let weld = ball.replace("kind = \"ball\"", "kind = \"fixed\"");
    let (_, _, path, message) = at(toml(&weld).err().unwrap());
    assert_eq!(path, "joints[0].spring");
    assert!(
        message.contains("distance, ball, hinge and slider joints, not fixed"),
        "{message}"
    );
    // A joint's friction is read, and a bad one located.
    let rubbing = PENDULUM.replace("axis = [0, 1, 0]", "axis = [0, 1, 0]\nfriction = 0.25");
    let (world, _) = toml(&rubbing).unwrap().build().unwrap();
    assert_eq!(world.joint(world.joint_ids()[0]).unwrap().friction, Some(0.25));
    let (_, _, path, message) = at(toml(&rubbing.replace("0.25", "-0.25")).err().unwrap());
    assert_eq!(path, "joints[0].friction");
    assert!(message.contains(">= 0"), "{message}");

    let bad_kind = PENDULUM.replace("kind = \"hinge\"", "kind = \"hing\"");
    let e = toml(&bad_kind).err().unwrap().to_string();
    assert!(e.contains("joints[0].kind") || e.contains("hing"), "{e}");

    // Two static bodies cannot be jointed: the world says so, located.
    let both_static = PENDULUM.replace("name = \"bob\"", "name = \"bob\"\nkind = \"static\"");
    let both_static = both_static.replace("mass = 1.0\n", "");
    let e = toml(&both_static).unwrap().build().err().unwrap();
    let (_, _, path, message) = at(e);
    assert_eq!(path, "joints[0].body_a");
    assert!(message.contains("dynamic"), "{message}");
}

#[test]
fn given_inertia_and_bodies_without_shapes() {
    // A shapeless body given its mass properties, a box given an inertia
    // other than its own, a kinematic body without shapes.
    let text = r#"
[[bodies]]
name = "weight"
mass = 2.0
inertia = [1.0, 1.5, 2.0]
center_of_mass = [0.1, 0, 0]

[[bodies]]
name = "box"
shapes = [{ type = "box", half_extents = [0.1, 0.1, 0.1] }]
mass = 1.0
inertia = [[0.3, 0, 0], [0, 0.3, 0], [0, 0, 0.3]]
position = [3, 0, 0]

[[bodies]]
name = "marker"
kind = "kinematic"
linear_velocity = [1, 0, 0]
"#;
    let (mut w, ids) = toml(text).unwrap().build().unwrap();
    let weight = w.body(ids[0]).unwrap();
    assert_eq!(weight.mass(), 2.0);
    let mut moments = weight.principal_inertia().to_array();
    moments.sort_by(f64::total_cmp);
    assert_eq!(moments, [1.0, 1.5, 2.0]);
    assert!((w.center_of_mass(ids[0]).unwrap() - DVec3::new(0.1, 0.0, 0.0)).length() < 1e-15);
    assert_eq!(w.body(ids[1]).unwrap().principal_inertia(), DVec3::splat(0.3));
    w.step();
    assert!(
        w.pose(ids[2]).unwrap().position.x > 0.0,
        "the kinematic marker moves"
    );

    // Each bad combination at its field.
    for (edit, field, wanted) in [
        ("mass = 2.0\n", "inertia", "needs mass"),
        ("mass = 2.0\n", "center_of_mass", "is given with inertia"),
        ("mass = 2.0\n", "density", "not density"),
        ("inertia = [1.0, 1.5, 2.0]\n", "inertia", "triangle inequality"),
        ("inertia = [1.0, 1.5, 2.0]\n", "inertia", "only dynamic bodies"),
    ] {
        let replaced = match (field, wanted) {
            ("inertia", "needs mass") => text.replacen(edit, "", 1),
            ("center_of_mass", _) => text.replacen("inertia = [1.0, 1.5, 2.0]\n", "", 1),
            ("density", _) => text.replacen(edit, "density = 5.0\n", 1),
            (_, "triangle inequality") => text.replacen(edit, "inertia = [1.0, 1.0, 3.0]\n", 1),
            _ => text.replacen(edit, "inertia = [1.0, 1.5, 2.0]\nkind = \"static\"\n", 1),
        };
        let (line, _, path, message) = at(toml(&replaced).unwrap_err());
        assert_eq!(path, format!("bodies[0].{field}"), "{message}");
        assert!(message.contains(wanted), "{message}");
        assert_eq!(line, position_of(&replaced, field).0, "{message}");
    }
    // Without shapes and without inertia: the world refuses, at the body.
    let bare = text.replacen("inertia = [1.0, 1.5, 2.0]\ncenter_of_mass = [0.1, 0, 0]\n", "", 1);
    let (_, _, path, message) = at(toml(&bare).unwrap().build().unwrap_err());
    assert_eq!(path, "bodies[0]");
    assert!(message.contains("no shapes"), "{message}");
    let both = text.replacen("mass = 2.0\n", "mass = 2.0\nshape = \"a\"\nshapes = []\n", 1);
    let (_, _, path, message) = at(toml(&both).unwrap_err());
    assert_eq!(path, "bodies[0]");
    assert!(message.contains("at most one of"), "{message}");
}

#[test]
fn a_no_contact_pair_passes_through_itself_and_bad_pairs_are_located() {
    // Two balls overlapping by half, without gravity: kept apart they do
    // not push each other; without the entry they are pushed apart.
    let text = r#"
[settings]
gravity = [0, 0, 0]
sleeping = false
[[bodies]]
name = "left"
shapes = [{ type = "sphere", radius = 0.1 }]
position = [0, 0, 0]
[[bodies]]
name = "right"
shapes = [{ type = "sphere", radius = 0.1 }]
position = [0.1, 0, 0]
[[no_contact]]
bodies = ["right", "left"]
"#;
    let moved = |text: &str| {
        let loaded = toml(text).unwrap();
        let (mut world, ids) = loaded.build().unwrap();
        for _ in 0..10 {
            world.step();
        }
        let gap = world.center_of_mass(ids[1]).unwrap() - world.center_of_mass(ids[0]).unwrap();
        gap.x - 0.1
    };
    let loaded = toml(text).unwrap();
    assert_eq!(loaded.scene.no_contact, vec![(0, 1)]);
    assert_eq!(moved(text), 0.0);
    let without = &text[..text.find("[[no_contact]]").unwrap()];
    assert!(moved(without) > 0.05, "overlapping balls push apart");

    let unknown = text.replace("[\"right\", \"left\"]", "[\"right\", \"lfet\"]");
    let (line, column, path, message) = at(toml(&unknown).err().unwrap());
    assert_eq!(path, "no_contact[0].bodies[1]");
    assert_eq!((line, column), position_of(&unknown, "\"lfet\""));
    assert!(message.contains("no body is named `lfet`"), "{message}");
    let twice = text.replace("[\"right\", \"left\"]", "[\"left\", \"left\"]");
    let (_, _, path, message) = at(toml(&twice).err().unwrap());
    assert_eq!(path, "no_contact[0].bodies[1]");
    assert!(message.contains("never touches itself"), "{message}");
    let one = text.replace("[\"right\", \"left\"]", "[\"right\"]");
    assert!(toml(&one).is_err(), "a pair has two bodies");
}
