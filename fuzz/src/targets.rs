//! The fuzz targets of tumble, written once and run two ways: by libFuzzer
//! (`fuzz/fuzz_targets/*.rs`, `scripts/fuzz.sh`, nightly) and by the stable
//! smoke test `crates/tumble/tests/fuzz_smoke.rs` (committed corpus plus
//! seeded mutations, in `make test`). Each target takes raw bytes, turns
//! them into an input for one public entry point, and asserts what must hold
//! for every input: no panic, and no non-finite number in what comes back
//! (states, distances, contacts). Errors are fine; they are the point.
//!
//! Structured targets (`collide`, `world_step`) read their input through
//! [`Input`], which turns bytes into numbers that are mostly in a useful
//! range and sometimes nasty (0, -0, NaN, +-inf, 1e300, subnormal), so that
//! both the geometry and the checks get exercised.

use std::path::Path;
use tumble::collide::mesh::{self, TriMesh};
use tumble::collide::query::{
    collide, collide_primitive, distance, distance_primitive, within_tolerance, CollideOptions,
    DistanceOptions, ReportMode,
};
use tumble::collide::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, Sphere};
use tumble::collide::{hull, mass, narrow, triangle, DQuat, DVec3, Pose};
use tumble::joint::urdf::{add_urdf, UrdfOptions};
use tumble::joint::{Gear, JointDesc, JointKind, Motor, Spring};
use tumble::scene::{parse_scene, Format, SceneDocument};
use tumble::sweep::{RunLength, Sweep};
use tumble::world::{BodyDesc, MassDesc, ShapeDesc, Snapshot, World, WorldSettings};
use tumble::BodyKind;

/// A fuzz target: any bytes in, a panic only on a bug.
pub type Target = fn(&[u8]);

/// The targets by name (the names of the libFuzzer binaries and of the
/// corpus directories `fuzz/corpus/<name>`).
pub const TARGETS: [(&str, Target); 11] = [
    ("scene_toml", scene_toml),
    ("scene_json", scene_json),
    ("obj", obj),
    ("stl", stl),
    ("collide", collide_target),
    ("world_step", world_step),
    ("snapshot", snapshot),
    ("narrow", narrow_pair),
    ("urdf", urdf),
    ("joints", joints),
    ("sweep", sweep),
];

/// Bytes read as numbers and choices; past the end everything reads as 0.
pub struct Input<'a> {
    data: &'a [u8],
    pos: usize,
}

/// Values that break careless arithmetic.
const NASTY: [f64; 11] = [
    0.0,
    -0.0,
    -1.0,
    1e-300,
    1e300,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    5e-324,
    f64::MAX,
    1e-9,
];

impl<'a> Input<'a> {
    /// Reads `data` from the start.
    pub fn new(data: &'a [u8]) -> Self {
        Input { data, pos: 0 }
    }

    /// The next byte (0 past the end).
    pub fn byte(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }

    /// A number in `0..n` (`n` >= 1).
    pub fn below(&mut self, n: usize) -> usize {
        self.byte() as usize % n.max(1)
    }

    /// A number mostly in `[lo, hi]` (16-bit resolution), one time in eight
    /// a nasty value.
    pub fn number(&mut self, lo: f64, hi: f64) -> f64 {
        let selector = self.byte();
        if selector >= 224 {
            return NASTY[selector as usize % NASTY.len()];
        }
        let t = u16::from_le_bytes([self.byte(), self.byte()]) as f64 / 65535.0;
        lo + (hi - lo) * t
    }

    /// Three numbers in `[lo, hi]`.
    pub fn vec3(&mut self, lo: f64, hi: f64) -> DVec3 {
        DVec3::new(self.number(lo, hi), self.number(lo, hi), self.number(lo, hi))
    }

    /// A quaternion: usually unit, sometimes only nearly, zero or nasty.
    pub fn quat(&mut self) -> DQuat {
        let raw = DQuat::from_xyzw(
            self.number(-1.0, 1.0),
            self.number(-1.0, 1.0),
            self.number(-1.0, 1.0),
            self.number(-1.0, 1.0),
        );
        match self.below(8) {
            0 => raw,
            1 => raw * 1.000_000_1,
            _ => {
                let n = raw.length();
                if n.is_finite() && n > 1e-6 {
                    raw / n
                } else {
                    DQuat::IDENTITY
                }
            }
        }
    }

    /// A pose, not validated (fields are public: the API must check).
    pub fn pose(&mut self, range: f64) -> Pose {
        Pose {
            position: self.vec3(-range, range),
            rotation: self.quat(),
        }
    }
}

fn assert_finite_world(world: &World) {
    for id in world.body_ids() {
        let state = world.body(id).expect("listed bodies are live").state();
        assert!(
            state.is_finite(),
            "body {id:?} has a non-finite state after a step: {state:?}"
        );
    }
}

fn step_and_check(world: &mut World, steps: usize) {
    for _ in 0..steps {
        let report = world.step();
        // Quarantined bodies are restored: every state stays finite.
        assert_finite_world(world);
        for q in &report.quarantined {
            assert!(world.body(q.body).is_ok(), "quarantined body {q:?} is not live");
        }
    }
}

/// Worlds from fuzzed scene files are stepped only when they are small.
const MAX_BODIES_STEPPED: usize = 32;
const MAX_TRIANGLES_STEPPED: usize = 4000;

/// `false` for scene text that asks for a lot: an integer above 64 (a grid
/// of a million bodies, a mesh of millions of triangles) or an icosphere of
/// more than 3 subdivisions (4^s growth). Such files are valid and limited by
/// the format itself; they are only slow, so the fuzzer skips them to keep
/// its executions per second.
fn within_fuzz_budget(text: &str, format: Format) -> bool {
    fn limit(key: &str) -> u64 {
        if key == "subdivisions" {
            3
        } else {
            64
        }
    }
    fn toml_small(key: &str, v: &toml::Value) -> bool {
        match v {
            toml::Value::Integer(i) => i.unsigned_abs() <= limit(key),
            toml::Value::Array(a) => a.iter().all(|x| toml_small(key, x)),
            toml::Value::Table(t) => t.iter().all(|(k, x)| toml_small(k, x)),
            _ => true,
        }
    }
    fn json_small(key: &str, v: &serde_json::Value) -> bool {
        match v {
            serde_json::Value::Number(n) => n
                .as_f64()
                .is_none_or(|x| x.abs() <= limit(key) as f64 || x.fract() != 0.0),
            serde_json::Value::Array(a) => a.iter().all(|x| json_small(key, x)),
            serde_json::Value::Object(o) => o.iter().all(|(k, x)| json_small(k, x)),
            _ => true,
        }
    }
    match format {
        Format::Toml => toml::from_str::<toml::Value>(text).map_or(true, |v| toml_small("", &v)),
        Format::Json => serde_json::from_str::<serde_json::Value>(text).map_or(true, |v| json_small("", &v)),
    }
}

fn scene_text(data: &[u8], format: Format) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if !within_fuzz_budget(text, format) {
        return;
    }
    let file = match format {
        Format::Toml => Path::new("fuzz-scene.toml"),
        Format::Json => Path::new("fuzz-scene.json"),
    };
    let loaded = match parse_scene(text, format, file) {
        Ok(l) => l,
        Err(e) => {
            // Every error is one located line.
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    let bodies = &loaded.scene.bodies;
    let triangles: usize = bodies
        .iter()
        .flat_map(|b| &b.shapes)
        .map(|s| match &s.shape {
            Shape::Mesh(m) => m.mesh().triangles().len(),
            _ => 12,
        })
        .sum();
    if bodies.len() > MAX_BODIES_STEPPED || triangles > MAX_TRIANGLES_STEPPED {
        return;
    }
    if let Ok((mut world, ids)) = loaded.build() {
        assert_eq!(ids.len(), world.body_count());
        step_and_check(&mut world, 3);
    }
}

/// Scene files in TOML: parse, check, build, step.
pub fn scene_toml(data: &[u8]) {
    scene_text(data, Format::Toml);
}

/// Scene files in JSON: parse, check, build, step.
pub fn scene_json(data: &[u8]) {
    scene_text(data, Format::Json);
}

/// URDF robots: parse and add to a world over a ground plane, which a
/// refused file leaves unchanged (its snapshot compared), then step a
/// robot that is not too large.
pub fn urdf(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // Mesh geometry is read from the disk, where a name such as /dev/zero
    // never ends: not fuzzed here (the mesh readers have their targets).
    if text.contains("mesh") {
        return;
    }
    let mut world = World::new(WorldSettings::default()).expect("the default settings are valid");
    let ground = HalfSpace::new(DVec3::Z, 0.0).expect("a unit normal");
    world
        .add_body(&BodyDesc::fixed(ground))
        .expect("a static half-space is a valid body");
    let before = world.snapshot();
    let options = UrdfOptions {
        position: DVec3::new(0.0, 0.0, 1.0),
        fixed_base: data.len().is_multiple_of(2),
        self_collision: data.len().is_multiple_of(3),
        balance_inertia: data.len().is_multiple_of(5),
        ..UrdfOptions::default()
    };
    match add_urdf(&mut world, text, Path::new("fuzz/robot.urdf"), options) {
        Ok(robot) => {
            assert!(!robot.bodies.is_empty(), "a robot without a body");
            assert_eq!(world.body_count(), 1 + robot.bodies.len());
            if robot.bodies.len() <= MAX_BODIES_STEPPED {
                step_and_check(&mut world, 3);
            }
        }
        Err(e) => {
            // Every error names the file (and, for the text, where in it).
            assert!(e.to_string().starts_with("fuzz/robot.urdf"), "{e}");
            assert!(
                world.snapshot() == before,
                "a refused URDF changed the world: {e}"
            );
        }
    }
}

/// Everything that accepts a mesh, on a mesh from a file.
fn exercise_mesh(m: &TriMesh) {
    let (lo, hi) = m.bounds();
    assert!(lo.is_finite() && hi.is_finite());
    let _ = m.check_solid();
    for fallback in [
        mass::MassFallback::ConvexHull,
        mass::MassFallback::Shell { thickness: 0.01 },
    ] {
        let _ = mass::mesh_mass_properties(m, mass::MassSpec::Density(1.0), fallback);
    }
    if let Ok((props, volume)) = mass::solid_mass_properties(m, mass::MassSpec::Density(1.0)) {
        assert!(props.mass.is_finite() && volume.is_finite());
    }
    let _ = ConvexHull::from_mesh(m);
    if m.vertices().len() <= 2000 {
        if let Ok(h) = hull::convex_hull(m.vertices()) {
            assert!(h.check_solid().is_ok(), "the hull of points is a closed solid");
        }
    }
    if m.triangles().len() > 2000 {
        return;
    }
    let Ok(shape) = MeshShape::new(m.clone()) else {
        return;
    };
    let offset = Pose::from_translation((hi - lo) * 0.3);
    let options = CollideOptions {
        report: ReportMode::Contacts,
        contact_margin: 0.01,
        ..CollideOptions::default()
    };
    for pose in [Pose::IDENTITY, offset] {
        if let Ok(r) = collide(&shape, &Pose::IDENTITY, &shape, &pose, &options) {
            check_report(&r, m.triangles().len(), m.triangles().len());
        }
        if let Ok(d) = distance(
            &shape,
            &Pose::IDENTITY,
            &shape,
            &pose,
            &DistanceOptions::default(),
        ) {
            assert!(d.distance.is_finite() && d.distance >= 0.0, "{d:?}");
        }
    }
}

/// Wavefront OBJ bytes: load, then everything that takes a mesh.
pub fn obj(data: &[u8]) {
    if let Ok(m) = mesh::obj_from_bytes(data) {
        exercise_mesh(&m);
    }
}

/// STL bytes (ASCII or binary): load, then everything that takes a mesh.
pub fn stl(data: &[u8]) {
    if let Ok(m) = mesh::stl_from_bytes(data) {
        exercise_mesh(&m);
    }
}

fn check_report(r: &tumble::collide::Report, na: usize, nb: usize) {
    for &(a, b) in &r.pairs {
        assert!(
            (a as usize) < na && (b as usize) < nb,
            "pair ({a}, {b}) out of range"
        );
    }
    for c in &r.contacts {
        assert!(
            c.point.is_finite() && c.normal.is_finite() && c.distance.is_finite(),
            "non-finite contact {c:?}"
        );
    }
}

/// `true` when some value is non-zero but below 1e-100 in magnitude.
fn has_tiny(values: &[f64]) -> bool {
    values.iter().any(|&x| x != 0.0 && x.abs() < 1e-100)
}

/// A small triangle soup (1 to 4 triangles) from the input.
fn soup(input: &mut Input, range: f64) -> Option<TriMesh> {
    let n = 1 + input.below(4);
    let mut vertices = Vec::with_capacity(3 * n);
    let mut triangles = Vec::with_capacity(n);
    for t in 0..n as u32 {
        for _ in 0..3 {
            vertices.push(input.vec3(-range, range));
        }
        triangles.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    TriMesh::new(vertices, triangles).ok()
}

/// Collision and distance queries on arbitrary small triangle soups and
/// primitives at arbitrary (unchecked) poses; cross-checks the boolean and
/// all-pairs answers against the triangle test on every pair.
pub fn collide_target(data: &[u8]) {
    let mut input = Input::new(data);
    let range = [1.0, 1e-3, 1e6][input.below(3)];
    let (Some(ma), Some(mb)) = (soup(&mut input, range), soup(&mut input, range)) else {
        return;
    };
    let (Ok(a), Ok(b)) = (MeshShape::new(ma.clone()), MeshShape::new(mb.clone())) else {
        return;
    };
    let pose_a = input.pose(range);
    let pose_b = input.pose(range);
    let margin = input.number(0.0, range);
    let all = CollideOptions {
        report: ReportMode::TrianglePairs,
        ..CollideOptions::default()
    };
    let boolean = CollideOptions {
        report: ReportMode::Boolean,
        ..CollideOptions::default()
    };
    let contacts = CollideOptions {
        report: ReportMode::Contacts,
        contact_margin: margin,
        ..CollideOptions::default()
    };
    let (na, nb) = (ma.triangles().len(), mb.triangles().len());
    match collide(&a, &pose_a, &b, &pose_b, &all) {
        Ok(r) => {
            check_report(&r, na, nb);
            assert_eq!(r.intersect, !r.pairs.is_empty(), "intersect without pairs");
            // Oracle: the exact triangle test on every pair, at the poses the
            // query used (valid poses are used as given when unit to
            // round-off, else normalised; compare only the former). Far from
            // the origin (beyond 100 mesh sizes) world coordinates round
            // coarser than the tree's relative frame: not compared there.
            // Nor where a coordinate is tiny but not zero (1e-300): products of
            // two such underflow, and the "exact" orientation predicates
            // report touching where the tree, in its relative frame, sees a
            // gap (found by libFuzzer; a limit of the predicates, documented
            // in docs/reliability.md).
            let usable = |p: &Pose| {
                (p.rotation.length_squared() - 1.0).abs() <= 8.0 * f64::EPSILON
                    && p.position.abs().max_element() <= 100.0 * range
                    && !has_tiny(&p.position.to_array())
                    && !has_tiny(&p.rotation.to_array())
            };
            let tiny_vertex = |m: &TriMesh| m.vertices().iter().any(|v| has_tiny(&v.to_array()));
            if usable(&pose_a) && usable(&pose_b) && !tiny_vertex(&ma) && !tiny_vertex(&mb) {
                let mut expected = Vec::new();
                for ta in 0..na {
                    for tb in 0..nb {
                        let wa = ma.triangle(ta).map(|p| pose_a.transform_point(p));
                        let wb = mb.triangle(tb).map(|p| pose_b.transform_point(p));
                        if triangle::tri_tri_overlap(&wa, &wb) {
                            expected.push((ta as u32, tb as u32));
                        }
                    }
                }
                assert_eq!(
                    r.pairs, expected,
                    "all-pairs query disagrees with the triangle test"
                );
            }
            let first = collide(&a, &pose_a, &b, &pose_b, &boolean).expect("same input");
            assert_eq!(
                first.intersect, r.intersect,
                "boolean and all-pairs answers differ"
            );
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
    if let Ok(r) = collide(&a, &pose_a, &b, &pose_b, &contacts) {
        check_report(&r, na, nb);
    }
    if let Ok(d) = distance(&a, &pose_a, &b, &pose_b, &DistanceOptions::default()) {
        assert!(d.distance.is_finite() && d.distance >= 0.0, "{d:?}");
        assert!(d.point_a.is_finite() && d.point_b.is_finite(), "{d:?}");
    }
    let _ = within_tolerance(&a, &pose_a, &b, &pose_b, margin);
    let prim = match input.below(4) {
        0 => Sphere::new(input.number(0.0, range)).map(Shape::Sphere),
        1 => Cuboid::new(input.vec3(0.0, range)).map(Shape::Cuboid),
        2 => Capsule::new(input.number(0.0, range), input.number(0.0, range)).map(Shape::Capsule),
        _ => HalfSpace::new(input.vec3(-1.0, 1.0), input.number(-range, range)).map(Shape::HalfSpace),
    };
    if let Ok(p) = prim {
        if let Ok(r) = collide_primitive(&p, &pose_a, &b, &pose_b, &contacts) {
            check_report(&r, 1, nb);
        }
        if let Ok(d) = distance_primitive(&p, &pose_a, &b, &pose_b, &DistanceOptions::default()) {
            assert!(d.distance.is_finite() && d.distance >= 0.0, "{d:?}");
        }
    }
    // The triangle-level routines directly, on the first two triangles.
    let ta = ma.triangle(0);
    let tb = mb.triangle(0);
    let d = triangle::triangle_distance(&ta, &tb);
    assert!(d.distance.is_nan() || d.distance >= 0.0, "{d:?}");
    let _ = triangle::tri_tri_overlap(&ta, &tb);
}

/// One shape from the input (about the size of `scale`), or why not.
fn fuzz_shape(input: &mut Input, scale: f64) -> Option<Shape> {
    let shape = match input.below(10) {
        0 | 1 => Shape::Sphere(Sphere::new(input.number(0.05, scale)).ok()?),
        2 | 3 => Shape::Cuboid(Cuboid::new(input.vec3(0.05, scale)).ok()?),
        4 => Shape::Capsule(Capsule::new(input.number(0.05, scale), input.number(0.0, scale)).ok()?),
        5 => {
            let n = 4 + input.below(6);
            let points: Vec<DVec3> = (0..n).map(|_| input.vec3(-scale, scale)).collect();
            Shape::ConvexHull(ConvexHull::from_points(&points).ok()?)
        }
        6 => {
            let m = match input.below(3) {
                0 => mesh::box_mesh(input.vec3(0.05, scale)).ok()?,
                1 => mesh::icosphere_mesh(input.number(0.05, scale), 1).ok()?,
                _ => {
                    mesh::torus_mesh(input.number(0.2, scale), input.number(0.02, scale * 0.3), 8, 6).ok()?
                }
            };
            Shape::Mesh(MeshShape::new(m).ok()?)
        }
        7 => Shape::HalfSpace(HalfSpace::new(input.vec3(-1.0, 1.0), input.number(-1.0, 1.0)).ok()?),
        8 => {
            // A thin slab, 0.2 mm to 2 cm thick, primitive or mesh.
            let half = DVec3::new(
                input.number(0.1, 1.0),
                input.number(0.1, 1.0),
                input.number(1e-4, 0.01),
            );
            if input.below(2) == 0 {
                Shape::Cuboid(Cuboid::new(half).ok()?)
            } else {
                Shape::Mesh(MeshShape::new(mesh::box_mesh(half).ok()?).ok()?)
            }
        }
        _ => {
            // A single-sided shell: an open sheet of triangles.
            let n = 1 + input.below(4);
            let sheet = mesh::grid_mesh(input.number(0.1, 1.0), input.number(0.1, 1.0), n, n).ok()?;
            Shape::Mesh(MeshShape::new(sheet).ok()?)
        }
    };
    Some(shape)
}

/// A small world from the input (settings, 1 to 6 bodies of random shapes
/// including thin slabs and open sheets, kinds, poses, velocities up to
/// 1,000 m/s, materials, the continuous-collision flag; a removal; forces),
/// stepped a few times: every rejected call leaves the body count alone,
/// every state stays finite, nothing panics.
pub fn world_step(data: &[u8]) {
    let mut input = Input::new(data);
    let mut settings = WorldSettings {
        dt: input.number(1e-4, 0.05),
        substeps: 1 + input.below(8) as u32,
        iterations: 1 + input.below(4) as u32,
        contact_margin: input.number(0.0, 0.05),
        sleeping: input.below(2) == 0,
        ..WorldSettings::default()
    };
    if input.below(4) == 0 {
        settings.gravity = input.vec3(-20.0, 20.0);
    }
    if input.below(8) == 0 {
        settings.solver = tumble::world::SolverKind::Lemke;
    }
    let Ok(mut world) = World::new(settings) else {
        return;
    };
    let n = 1 + input.below(6);
    let mut ids = Vec::new();
    for _ in 0..n {
        let kind = match input.below(6) {
            0 => BodyKind::Static,
            1 => BodyKind::Kinematic,
            _ => BodyKind::Dynamic,
        };
        let mut shapes = Vec::new();
        for _ in 0..1 + input.below(2) {
            if let Some(s) = fuzz_shape(&mut input, 0.6) {
                let local = if input.below(3) == 0 {
                    input.pose(0.5)
                } else {
                    Pose::IDENTITY
                };
                shapes.push(ShapeDesc {
                    shape: s,
                    local_pose: local,
                });
            }
        }
        // Bodies of two shapes share a non-colliding group, and a body
        // left without shapes gets its drawn mass as mass properties (a
        // body without shapes), both from what is drawn already, so that
        // kept inputs keep their meaning.
        let non_colliding_group = u32::from(shapes.len() == 2);
        let mut mass = if input.below(2) == 0 {
            MassDesc::Density(input.number(1.0, 3000.0))
        } else {
            MassDesc::Mass(input.number(0.01, 100.0))
        };
        if let (true, MassDesc::Mass(m)) = (shapes.is_empty(), mass) {
            let inertia = tumble::collide::DMat3::from_diagonal(DVec3::splat(0.1 * m));
            if let Ok(p) = tumble::collide::mass::MassProperties::new(m, DVec3::ZERO, inertia) {
                mass = MassDesc::Inertial(p);
            }
        }
        let desc = BodyDesc {
            kind,
            shapes,
            mass,
            pose: input.pose(2.0),
            // Rest, everyday speeds, or a projectile up to 1,000 m/s.
            linear_velocity: match input.below(3) {
                0 => input.vec3(-10.0, 10.0),
                1 => input.vec3(-1.0, 1.0).normalize_or_zero() * input.number(10.0, 1000.0),
                _ => DVec3::ZERO,
            },
            angular_velocity: if input.below(2) == 0 {
                input.vec3(-10.0, 10.0)
            } else {
                DVec3::ZERO
            },
            material: tumble::world::MaterialDesc {
                friction: input.number(0.0, 1.5),
                restitution: input.number(0.0, 1.0),
            },
            linear_damping: input.number(0.0, 1.0),
            angular_damping: input.number(0.0, 1.0),
            ccd: input.below(4) == 0,
            non_colliding_group,
            name: String::new(),
        };
        let count = world.body_count();
        match world.add_body(&desc) {
            Ok(id) => ids.push(id),
            Err(e) => {
                assert_eq!(
                    world.body_count(),
                    count,
                    "a rejected body changed the world: {e}"
                );
            }
        }
    }
    if !ids.is_empty() && input.below(4) == 0 {
        let id = ids.remove(input.below(ids.len()));
        world.remove_body(id).expect("live body");
        assert!(world.remove_body(id).is_err(), "removing twice");
    }
    let steps = 1 + input.below(4);
    for _ in 0..steps {
        for &id in &ids {
            match input.below(6) {
                0 => {
                    let _ = world.apply_force(id, input.vec3(-100.0, 100.0));
                }
                1 => {
                    let _ = world.apply_torque(id, input.vec3(-10.0, 10.0));
                }
                2 => {
                    let _ = world.set_velocity(id, input.vec3(-10.0, 10.0), input.vec3(-10.0, 10.0));
                }
                _ => {}
            }
        }
        step_and_check(&mut world, 1);
    }
}

/// Joints: 2-5 dynamic spheres and boxes over a ground, joined by up to six
/// fuzzed joints of every kind (anchors, axes, limits, swing limits,
/// motors, springs, lengths; some to the world, some of a body to itself);
/// a refused joint, motor change or removal leaves the world's whole
/// snapshot unchanged. Stepped with motors changed and joints or bodies
/// removed in between: every state finite, and every joint's state
/// (coordinate, rate, errors, reaction, anchors, axis) finite.
pub fn joints(data: &[u8]) {
    let mut input = Input::new(data);
    let settings = WorldSettings {
        dt: input.number(1e-3, 0.05),
        substeps: 1 + input.below(8) as u32,
        iterations: 1 + input.below(4) as u32,
        ..WorldSettings::default()
    };
    let Ok(mut world) = World::new(settings) else {
        return;
    };
    let ground = HalfSpace::new(DVec3::Z, 0.0).expect("a unit normal");
    world
        .add_body(&BodyDesc::fixed(ground))
        .expect("a static half-space is a valid body");
    let mut bodies = Vec::new();
    for i in 0..2 + input.below(4) {
        let shape = if input.below(2) == 0 {
            Sphere::new(input.number(0.05, 0.4)).map(Shape::Sphere)
        } else {
            Cuboid::new(input.vec3(0.05, 0.4)).map(Shape::Cuboid)
        };
        let Ok(shape) = shape else {
            continue;
        };
        let mut desc = BodyDesc::dynamic(shape);
        desc.pose = input.pose(1.0);
        desc.pose.position.z += 1.0 + 0.5 * i as f64;
        if input.below(2) == 0 {
            desc.mass = MassDesc::Mass(input.number(0.01, 100.0));
        }
        if let Ok(id) = world.add_body(&desc) {
            bodies.push(id);
        }
    }
    if bodies.is_empty() {
        return;
    }
    let mut joints = Vec::new();
    for _ in 0..1 + input.below(6) {
        let kind = JointKind::ALL[input.below(JointKind::ALL.len())];
        let ia = input.below(bodies.len());
        let a = bodies[ia];
        // Another body, or the world, or (refused) A itself.
        let b = match input.below(8) {
            7 => None,
            6 => Some(a),
            _ if bodies.len() > 1 => Some(bodies[(ia + 1 + input.below(bodies.len() - 1)) % bodies.len()]),
            _ => None,
        };
        let mut desc = JointDesc::new(kind, a, b, input.vec3(-2.0, 2.0), input.vec3(-1.0, 1.0));
        // Each option where the kind takes it, and one input in eight
        // anywhere (which the checks must refuse). A coin reads 1 for yes,
        // so that an input's zeros (and its end) ask for nothing.
        let wild = input.below(8) == 7;
        let (distance, ball) = (kind == JointKind::Distance, kind == JointKind::Ball);
        let coin = |input: &mut Input, allowed: bool| (allowed || wild) && input.below(2) == 1;
        if coin(&mut input, distance) {
            desc.anchor_b = Some(input.vec3(-2.0, 2.0));
        }
        if coin(&mut input, kind != JointKind::Fixed) {
            let lo = input.number(-3.2, 3.2);
            desc.limits = Some([lo, lo + input.number(-0.5, 4.0)]);
        }
        if coin(&mut input, ball) {
            desc.swing_limit = Some(input.number(0.0, 3.2));
        }
        if coin(
            &mut input,
            matches!(kind, JointKind::Hinge | JointKind::Slider) || ball,
        ) {
            desc.motor = fuzz_motor(&mut input);
        }
        if coin(&mut input, kind != JointKind::Fixed) {
            desc.spring = Some(Spring {
                stiffness: input.number(0.0, 1000.0),
                damping: input.number(0.0, 10.0),
            });
        }
        if coin(&mut input, distance) {
            desc.length = Some(input.number(0.0, 2.0));
        }
        if coin(&mut input, kind != JointKind::Fixed) {
            desc.friction = Some(input.number(0.0, 50.0));
        }
        desc.collide_connected = input.below(2) == 0;
        let before = world.snapshot();
        match world.add_joint(&desc) {
            Ok(id) => joints.push(id),
            Err(e) => assert!(
                world.snapshot() == before,
                "a refused joint changed the world: {e}"
            ),
        }
    }
    for _ in 0..1 + input.below(4) {
        if !joints.is_empty() {
            let j = joints[input.below(joints.len())];
            match input.below(7) {
                0 => {
                    let before = world.snapshot();
                    let motor = fuzz_motor(&mut input);
                    if let Err(e) = world.set_joint_motor(j, motor) {
                        assert!(
                            world.snapshot() == before,
                            "a refused motor changed the world: {e}"
                        );
                    }
                }
                1 => {
                    world.remove_joint(j).expect("a live joint");
                    joints.retain(|&k| k != j);
                    assert!(world.remove_joint(j).is_err(), "removing a joint twice");
                }
                3 | 4 => {
                    // A gear to another joint (or itself, or none: let go),
                    // any ratio and offset the input gives.
                    let before = world.snapshot();
                    let gear = match input.below(4) {
                        0 => None,
                        _ => Some(
                            Gear::new(joints[input.below(joints.len())], input.number(-100.0, 100.0))
                                .with_offset(input.number(-4.0, 4.0)),
                        ),
                    };
                    if let Err(e) = world.set_joint_gear(j, gear) {
                        assert!(
                            world.snapshot() == before,
                            "a refused gear changed the world: {e}"
                        );
                    }
                }
                2 => {
                    // Its joints go with it.
                    let body = bodies.remove(input.below(bodies.len()));
                    world.remove_body(body).expect("a live body");
                    let live = world.joint_ids();
                    joints.retain(|j| live.contains(j));
                    if bodies.is_empty() {
                        return;
                    }
                }
                _ => {}
            }
        }
        step_and_check(&mut world, 1);
        for id in world.joint_ids() {
            let s = world.joint_state(id).expect("a listed joint is live");
            let numbers = [s.position, s.rate, s.linear_error, s.angular_error];
            let vectors = [s.force, s.torque, s.anchor_a, s.anchor_b, s.axis];
            assert!(
                numbers.iter().all(|x| x.is_finite()) && vectors.iter().all(|v| v.is_finite()),
                "joint {id:?}: {s:?}"
            );
        }
        let (linear, angular) = world.max_joint_error();
        assert!(linear.is_finite() && angular.is_finite(), "{linear} {angular}");
    }
}

/// Parameter sweeps: the first line a JSON object `{"params": [[path,
/// [values...]], ...], "steps": n, "metrics": [names...]}`, the rest a
/// TOML scene file. Checked as `Sweep::new` checks it (a typed error is
/// fine), then up to 8 of its runs of at most 8 steps on two threads: each
/// run's row is its own, the same again on one thread, and a finished
/// run's metrics are numbers (finite, or NaN where a metric has no value).
pub fn sweep(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let (head, scene) = text.split_once('\n').unwrap_or((text, ""));
    if !within_fuzz_budget(scene, Format::Toml) {
        return;
    }
    let Ok(serde_json::Value::Object(spec)) = serde_json::from_str::<serde_json::Value>(head) else {
        return;
    };
    let Ok(doc) = SceneDocument::parse(scene, Format::Toml, Path::new("fuzz-sweep.toml")) else {
        return;
    };
    let params: Vec<(String, Vec<serde_json::Value>)> = match spec.get("params") {
        Some(serde_json::Value::Array(list)) => list
            .iter()
            .filter_map(|p| match p {
                serde_json::Value::Array(pair) => match (pair.first(), pair.get(1)) {
                    (Some(serde_json::Value::String(path)), Some(serde_json::Value::Array(values))) => {
                        Some((path.clone(), values.clone()))
                    }
                    _ => None,
                },
                _ => None,
            })
            .collect(),
        _ => Vec::new(),
    };
    let steps = spec
        .get("steps")
        .and_then(serde_json::Value::as_u64)
        .unwrap_or(1)
        .min(8);
    let metrics: Vec<String> = match spec.get("metrics") {
        Some(serde_json::Value::Array(m)) => m.iter().filter_map(|x| x.as_str().map(String::from)).collect(),
        _ => Vec::new(),
    };
    let sweep = match Sweep::new(doc, params, RunLength::Steps(steps), &metrics) {
        Ok(s) => s,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    let indices: Vec<usize> = (0..sweep.len().min(8)).collect();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let rows = sweep.run(&indices, 2, &cancel, &|_| {});
    let serial = sweep.run(&indices, 1, &cancel, &|_| {});
    assert_eq!(rows.len(), indices.len());
    for (row, again) in rows.iter().zip(&serial) {
        assert_eq!(
            format!("{row:?}"),
            format!("{again:?}"),
            "a run's row depends on the threads"
        );
        assert!(row.metrics.iter().all(|x| !x.is_infinite()), "{row:?}");
    }
}

/// No motor, or a velocity or position motor (a hinge's or slider's) or an
/// angular velocity or orientation motor (a ball joint's) of fuzzed
/// targets, gains and force bound (on any kind: the wrong ones are refused).
fn fuzz_motor(input: &mut Input) -> Option<Motor> {
    match input.below(5) {
        0 => Some(Motor::Velocity {
            target: input.number(-10.0, 10.0),
            max_force: input.number(0.0, 100.0),
        }),
        1 => Some(Motor::Position {
            target: input.number(-3.0, 3.0),
            stiffness: input.number(0.0, 1000.0),
            damping: input.number(0.0, 50.0),
            max_force: input.number(0.0, 100.0),
        }),
        2 => Some(Motor::AngularVelocity {
            target: input.vec3(-10.0, 10.0).to_array(),
            max_force: input.number(0.0, 100.0),
        }),
        3 => Some(Motor::Orientation {
            target: input.vec3(-4.0, 4.0).to_array(),
            stiffness: input.number(0.0, 1000.0),
            damping: input.number(0.0, 50.0),
            max_force: input.number(0.0, 100.0),
        }),
        _ => None,
    }
}

/// Snapshot bytes (binary, or JSON when the input is text): decode, restore
/// and step; corrupt input must give an error, never a panic or a world
/// holding NaN.
pub fn snapshot(data: &[u8]) {
    let snap = match std::str::from_utf8(data) {
        Ok(text) if text.trim_start().starts_with('{') => Snapshot::from_json(text),
        _ => Snapshot::from_bytes(data),
    };
    let Ok(snap) = snap else {
        return;
    };
    if snap.body_count() > MAX_BODIES_STEPPED {
        return;
    }
    if let Ok(mut world) = World::from_snapshot(&snap) {
        assert_finite_world(&world);
        step_and_check(&mut world, 2);
    }
}

/// The narrow phase (every shape pair of the dispatch table) on two fuzzed
/// shapes at fuzzed poses, normalised when possible.
pub fn narrow_pair(data: &[u8]) {
    let mut input = Input::new(data);
    let (Some(a), Some(b)) = (fuzz_shape(&mut input, 1.0), fuzz_shape(&mut input, 1.0)) else {
        return;
    };
    let (Ok(pa), Ok(pb)) = (
        Pose::new_normalized(input.vec3(-1.0, 1.0), input.quat()),
        Pose::new_normalized(input.vec3(-1.0, 1.0), input.quat()),
    ) else {
        return;
    };
    let mut out = Vec::new();
    if narrow::contact_shapes(&a, &pa, &b, &pb, input.number(0.0, 0.1), &mut out).is_ok() {
        for c in &out {
            assert!(
                c.point.is_finite() && c.normal.is_finite() && c.distance.is_finite(),
                "{c:?}"
            );
        }
    }
}

/// Debug helper: the triangle soups and poses `collide_target` reads.
pub fn describe_collide_input(data: &[u8]) -> String {
    let mut input = Input::new(data);
    let range = [1.0, 1e-3, 1e6][input.below(3)];
    let a = soup(&mut input, range);
    let b = soup(&mut input, range);
    let pa = input.pose(range);
    let pb = input.pose(range);
    format!("range {range}\nA {a:?}\nB {b:?}\npose_a {pa:?}\npose_b {pb:?}")
}

/// Debug helper: the shapes and poses `narrow_pair` reads.
pub fn describe_narrow_input(data: &[u8]) -> String {
    let mut input = Input::new(data);
    let a = fuzz_shape(&mut input, 1.0);
    let b = fuzz_shape(&mut input, 1.0);
    let pa = Pose::new_normalized(input.vec3(-1.0, 1.0), input.quat());
    let pb = Pose::new_normalized(input.vec3(-1.0, 1.0), input.quat());
    let margin = input.number(0.0, 0.1);
    format!("A {a:?}\nB {b:?}\npose_a {pa:?}\npose_b {pb:?}\nmargin {margin}")
}
