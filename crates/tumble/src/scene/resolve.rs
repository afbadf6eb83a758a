//! From the schema types to a [`Scene`]: named materials and shapes looked
//! up, grids expanded, every value checked with the path of the field it came
//! from, so that the world never sees a value the file did not mean.

use std::collections::BTreeMap;
use std::path::Path;

use super::error::{FieldError, FieldPath};
use super::schema::{BodySpec, InertiaSpec, KindSpec, RobotSpec, SceneFile};
use super::shapes::build_shape;
use super::values::{non_negative, pose, positive, vec3_or_zero};
use super::InitialLoad;
use crate::body::BodyKind;
use crate::joint::urdf::{read_urdf_parts, UrdfOptions};
use crate::scenes::{Scene, SceneGear};
use crate::world::{
    unused_non_colliding_group, BodyDesc, MassDesc, MaterialDesc, ShapeDesc, World, WorldError,
};
use tumble_collide::mass::MassProperties;
use tumble_collide::{DMat3, DVec3};

/// Most bodies a scene file may describe (grids included).
const MAX_SCENE_BODIES: u64 = 1_000_000;

/// Simulated time (s) when a file gives neither `steps` nor `duration`.
pub const DEFAULT_DURATION: f64 = 10.0;

/// Where a body of the scene came from, for locating errors the world reports.
#[derive(Debug, Clone)]
pub(crate) struct BodyOrigin {
    /// `bodies[i]`.
    pub path: FieldPath,
    /// Copy number within the body's grid, if it has one.
    pub copy: Option<usize>,
    /// Path of each shape: `bodies[i].shapes[j]` or `shapes.NAME`.
    pub shapes: Vec<FieldPath>,
}

/// A resolved scene file.
pub(crate) struct Resolved {
    pub scene: Scene,
    pub loads: Vec<InitialLoad>,
    pub origins: Vec<BodyOrigin>,
    /// Path of each joint (`joints[k]`), in `scene.joints` order.
    pub joint_paths: Vec<FieldPath>,
}

/// The path of the field a [`WorldError`] is about: settings fields are
/// top-level, body fields are under the body that was being added.
pub(crate) fn world_error_path(e: &WorldError, origin: Option<&BodyOrigin>) -> FieldPath {
    let root = FieldPath::root();
    let body = origin.map_or(root.clone(), |o| o.path.clone());
    match e {
        WorldError::BadValue { field, .. } => {
            if let Some(setting) = field.strip_prefix("settings.") {
                return root.key("settings").key(setting);
            }
            let key = match *field {
                "body.linear_velocity" => "linear_velocity",
                "body.angular_velocity" => "angular_velocity",
                "body.pose" => "position",
                "mass.density" => "density",
                "mass.mass" => "mass",
                "body.damping" => "linear_damping",
                f if f.starts_with("body.material") => "material",
                _ => return body,
            };
            body.key(key)
        }
        WorldError::BadShape { index, .. } => {
            origin.and_then(|o| o.shapes.get(*index).cloned()).unwrap_or(body)
        }
        _ => body,
    }
}

/// The message of a [`WorldError`] without the field name (the path says it).
pub(crate) fn world_error_message(e: &WorldError, origin: Option<&BodyOrigin>) -> String {
    let message = match e {
        WorldError::BadValue { message, .. } | WorldError::BadShape { message, .. } => message.clone(),
        other => other.to_string(),
    };
    match origin.and_then(|o| o.copy) {
        Some(n) => format!("{message} (grid copy {n})"),
        None => message,
    }
}

fn check_material(path: &FieldPath, m: &MaterialDesc) -> Result<(), FieldError> {
    non_negative(&path.key("friction"), m.friction, "")?;
    let e = m.restitution;
    if !(e.is_finite() && (0.0..=1.0).contains(&e)) {
        return Err(FieldError::new(
            &path.key("restitution"),
            format!("must be in [0, 1], got {e}"),
        ));
    }
    Ok(())
}

fn kind(k: KindSpec) -> BodyKind {
    match k {
        KindSpec::Dynamic => BodyKind::Dynamic,
        KindSpec::Static => BodyKind::Static,
        KindSpec::Kinematic => BodyKind::Kinematic,
    }
}

/// Replaces `{i}`, `{j}`, `{k}` and `{n}` in a grid body's name.
fn copy_name(template: &str, ijk: [u32; 3], n: usize) -> String {
    template
        .replace("{i}", &ijk[0].to_string())
        .replace("{j}", &ijk[1].to_string())
        .replace("{k}", &ijk[2].to_string())
        .replace("{n}", &n.to_string())
}

/// Checks the settings (as `World::new` does) with their paths.
fn check_settings(file: &SceneFile) -> Result<(), FieldError> {
    World::new(file.settings.clone())
        .map(|_| ())
        .map_err(|e| FieldError::new(&world_error_path(&e, None), world_error_message(&e, None)))
}

fn steps(file: &SceneFile) -> Result<usize, FieldError> {
    let root = FieldPath::root();
    let dt = file.settings.dt;
    match (file.steps, file.duration) {
        (Some(_), Some(_)) => Err(FieldError::new(
            &root.key("duration"),
            "give either steps or duration, not both",
        )),
        (Some(0), None) => Err(FieldError::new(&root.key("steps"), "must be >= 1, got 0")),
        (Some(n), None) => {
            usize::try_from(n).map_err(|_| FieldError::new(&root.key("steps"), format!("too large: {n}")))
        }
        (None, Some(d)) => {
            let d = positive(&root.key("duration"), d, "s")?;
            Ok(((d / dt).round() as usize).max(1))
        }
        (None, None) => Ok(((DEFAULT_DURATION / dt).round() as usize).max(1)),
    }
}

/// Resolves `file`; mesh files are found relative to `base_dir`.
pub(crate) fn resolve(file: &SceneFile, base_dir: &Path, default_name: &str) -> Result<Resolved, FieldError> {
    let root = FieldPath::root();
    check_settings(file)?;
    let steps = steps(file)?;
    for (name, m) in &file.materials {
        check_material(&root.key("materials").key(name), m)?;
    }
    let default_material = file.materials.get("default").copied().unwrap_or_default();
    let mut named: BTreeMap<&str, ShapeDesc> = BTreeMap::new();
    for (name, spec) in &file.shapes {
        let path = root.key("shapes").key(name);
        named.insert(name, build_shape(spec, &path, base_dir)?);
    }
    let ctx = Context {
        base_dir,
        materials: &file.materials,
        default_material,
        named,
    };
    let mut out = Resolved {
        scene: Scene {
            name: file.name.clone().unwrap_or_else(|| default_name.to_string()),
            settings: file.settings.clone(),
            bodies: Vec::new(),
            steps,
            joints: Vec::new(),
            no_contact: Vec::new(),
            gears: Vec::new(),
        },
        loads: Vec::new(),
        origins: Vec::new(),
        joint_paths: Vec::new(),
    };
    for (i, spec) in file.bodies.iter().enumerate() {
        let path = root.key("bodies").index(i);
        resolve_body(spec, &path, &ctx, &mut out)?;
    }
    for (i, spec) in file.robots.iter().enumerate() {
        resolve_robot(spec, &root.key("robots").index(i), base_dir, &mut out)?;
    }
    // An empty file (or one with settings only) is almost surely the wrong
    // file: nothing would be simulated.
    if out.scene.bodies.is_empty() {
        return Err(FieldError::new(
            &root.key("bodies"),
            "a scene needs at least one body; this file describes none",
        ));
    }
    let first_file_joint = out.scene.joints.len();
    for (joint, path) in super::joints::resolve_joints(&file.joints, &out.scene.bodies)? {
        out.scene.joints.push(joint);
        out.joint_paths.push(path);
    }
    let gears = super::joints::resolve_gears(&file.joints, &out.scene.joints, first_file_joint)?;
    out.scene.gears.extend(gears);
    let pairs = super::no_contact::resolve_no_contact(&file.no_contact, &out.scene.bodies)?;
    out.scene.no_contact.extend(pairs);
    Ok(out)
}

/// A robot's bodies and joints, appended to the scene's: the bodies named
/// `PREFIX/LINK`, in a non-colliding group no body of the scene so far is
/// in (unless `self_collision`), its joints' bodies renumbered. A
/// refusal of the URDF file is located at `file`, with the URDF file's own
/// line and element in the message.
fn resolve_robot(
    spec: &RobotSpec,
    path: &FieldPath,
    base_dir: &Path,
    out: &mut Resolved,
) -> Result<(), FieldError> {
    let frame = pose(path, spec.position, spec.orientation, spec.rotation.as_deref())?;
    let options = UrdfOptions {
        position: frame.position,
        orientation: frame.rotation,
        fixed_base: spec.fixed_base,
        self_collision: spec.self_collision,
        balance_inertia: spec.balance_inertia,
        convex_meshes: spec.convex_meshes,
    };
    let group = unused_non_colliding_group(out.scene.bodies.iter().map(|b| b.non_colliding_group));
    let mut parts = read_urdf_parts(base_dir.join(&spec.file), options, group)
        .map_err(|e| FieldError::new(&path.key("file"), e.to_string()))?;
    for (name, motor) in &spec.motors {
        let mpath = path.key("motors").key(name);
        let Some(joint) = parts.joints.iter().position(|j| j.desc.name == *name) else {
            let known: Vec<&str> = parts.joints.iter().map(|j| j.desc.name.as_str()).collect();
            return Err(FieldError::new(
                &mpath,
                format!(
                    "the robot has no moving joint named `{name}` (it has: {})",
                    known.join(", ")
                ),
            ));
        };
        let joint = &mut parts.joints[joint];
        // (A ball joint's vector targets are in the file's axes: turned with
        // the robot's placement into the world's.)
        joint.desc.motor = Some(motor.turned(frame.rotation));
        joint.desc.validate().map_err(|e| {
            // `joints[k].motor.max_force` of a scene's own joint is
            // `robots[k].motors.NAME.max_force` here.
            let field = match &e {
                WorldError::BadValue { field, .. } => field.strip_prefix("joint.motor."),
                _ => None,
            };
            let at = field.map_or(mpath.clone(), |f| mpath.key(f));
            FieldError::new(&at, super::joints::joint_error_message(&e))
        })?;
    }
    let prefix = spec.name.clone().unwrap_or_else(|| parts.name.clone());
    let first = out.scene.bodies.len();
    for mut body in parts.bodies {
        body.name = format!("{prefix}/{}", body.name);
        out.origins.push(BodyOrigin {
            path: path.clone(),
            copy: None,
            shapes: vec![path.clone(); body.shapes.len()],
        });
        out.scene.bodies.push(body);
    }
    out.scene
        .no_contact
        .extend(parts.no_contact.iter().map(|&(a, b)| (first + a, first + b)));
    // A robot's mimic joints, as gears between its joints (numbered from
    // the first of them in the scene).
    let first_joint = out.scene.joints.len();
    out.scene
        .gears
        .extend(parts.joints.iter().enumerate().filter_map(|(k, j)| {
            j.gear.map(|g| SceneGear {
                follower: first_joint + k,
                leader: first_joint + g.leader,
                ratio: g.ratio,
                offset: g.offset,
            })
        }));
    let joints = parts.joints.into_iter().map(|j| j.desc).chain(parts.base_weld);
    for mut joint in joints {
        if !joint.name.is_empty() {
            joint.name = format!("{prefix}/{}", joint.name);
        }
        out.scene.joints.push(joint.with_bodies(|k| first + k));
        out.joint_paths.push(path.clone());
    }
    Ok(())
}

/// What the bodies of a file refer to.
struct Context<'a> {
    base_dir: &'a Path,
    materials: &'a BTreeMap<String, MaterialDesc>,
    default_material: MaterialDesc,
    named: BTreeMap<&'a str, ShapeDesc>,
}

impl Context<'_> {
    /// The named shape `name` and the path of its definition.
    fn lookup(&self, path: &FieldPath, name: &str) -> Result<(ShapeDesc, FieldPath), FieldError> {
        self.named
            .get(name)
            .map(|s| (s.clone(), FieldPath::root().key("shapes").key(name)))
            .ok_or_else(|| unknown_name(path, "shape", name, self.named.keys().copied()))
    }
}

/// The error for `name`, which the top-level table of `what`s does not
/// define: unknown shapes and materials, listing the names the table has.
fn unknown_name<'a>(
    path: &FieldPath,
    what: &str,
    name: &str,
    known: impl Iterator<Item = &'a str>,
) -> FieldError {
    let known: Vec<&str> = known.collect();
    FieldError::new(
        path,
        format!(
            "unknown {what} `{name}` (the top-level {what}s table defines: {})",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        ),
    )
}

/// `mass` with `inertia` (and `center_of_mass`): the mass properties given
/// outright, checked as a body's (finite, mass > 0, symmetric, physical).
fn given_mass_properties(
    path: &FieldPath,
    mass: f64,
    inertia: InertiaSpec,
    center_of_mass: Option<[f64; 3]>,
) -> Result<MassDesc, FieldError> {
    let mass = positive(&path.key("mass"), mass, "kg")?;
    let com = vec3_or_zero(&path.key("center_of_mass"), center_of_mass)?;
    let matrix = match inertia {
        InertiaSpec::Diagonal(d) => DMat3::from_diagonal(DVec3::from_array(d)),
        // Rows are columns: the matrix is symmetric (checked below).
        InertiaSpec::Matrix(rows) => DMat3::from_cols_array_2d(&rows),
    };
    MassProperties::new(mass, com, matrix)
        .map(MassDesc::Inertial)
        .map_err(|e| FieldError::new(&path.key("inertia"), e.to_string()))
}

fn resolve_body(
    spec: &BodySpec,
    path: &FieldPath,
    ctx: &Context,
    out: &mut Resolved,
) -> Result<(), FieldError> {
    let kind = kind(spec.kind);
    let alternate = spec.grid.as_ref().and_then(|g| g.alternate_shapes.as_ref());
    let given = [spec.shape.is_some(), spec.shapes.is_some(), alternate.is_some()];
    let n = given.iter().filter(|&&g| g).count();
    if n > 1 {
        return Err(FieldError::new(
            path,
            format!("give at most one of shape (a name), shapes (a list) or grid.alternate_shapes (got {n})"),
        ));
    }
    // The shape sets this body's copies cycle through (one set without a
    // grid; one empty set for a body without shapes).
    let mut shape_sets: Vec<(Vec<ShapeDesc>, Vec<FieldPath>)> = Vec::new();
    if !given.contains(&true) {
        shape_sets.push((Vec::new(), Vec::new()));
    } else if let Some(name) = &spec.shape {
        let (s, p) = ctx.lookup(&path.key("shape"), name)?;
        shape_sets.push((vec![s], vec![p]));
    } else if let Some(list) = &spec.shapes {
        if list.is_empty() {
            return Err(FieldError::new(&path.key("shapes"), "needs at least one shape"));
        }
        let mut set = (Vec::new(), Vec::new());
        for (j, s) in list.iter().enumerate() {
            let p = path.key("shapes").index(j);
            set.0.push(build_shape(s, &p, ctx.base_dir)?);
            set.1.push(p);
        }
        shape_sets.push(set);
    } else if let Some(names) = alternate {
        let apath = path.key("grid").key("alternate_shapes");
        if names.is_empty() {
            return Err(FieldError::new(&apath, "needs at least one shape name"));
        }
        for (j, name) in names.iter().enumerate() {
            let (s, p) = ctx.lookup(&apath.index(j), name)?;
            shape_sets.push((vec![s], vec![p]));
        }
    }

    if spec.center_of_mass.is_some() && spec.inertia.is_none() {
        return Err(FieldError::new(
            &path.key("center_of_mass"),
            "is given with inertia (else it follows from the shapes)",
        ));
    }
    let mass = match (spec.mass, spec.density, spec.inertia) {
        (_, Some(_), Some(_)) => {
            return Err(FieldError::new(
                &path.key("density"),
                "give inertia with mass, not density",
            ))
        }
        (None, None, Some(_)) => return Err(FieldError::new(&path.key("inertia"), "needs mass (kg)")),
        (Some(m), None, Some(i)) => Some(given_mass_properties(path, m, i, spec.center_of_mass)?),
        (Some(_), Some(_), None) => {
            return Err(FieldError::new(
                &path.key("density"),
                "give either mass or density, not both",
            ))
        }
        (Some(m), None, None) => Some(MassDesc::Mass(positive(&path.key("mass"), m, "kg")?)),
        (None, Some(d), None) => Some(MassDesc::Density(positive(&path.key("density"), d, "kg/m^3")?)),
        (None, None, None) => None,
    };
    if mass.is_some() && kind != BodyKind::Dynamic {
        let key = match (spec.inertia, spec.mass) {
            (Some(_), _) => "inertia",
            (None, Some(_)) => "mass",
            (None, None) => "density",
        };
        return Err(FieldError::new(
            &path.key(key),
            "only dynamic bodies have a mass (static and kinematic bodies are not pushed)",
        ));
    }
    let material = match &spec.material {
        None => ctx.default_material,
        Some(name) => *ctx.materials.get(name).ok_or_else(|| {
            unknown_name(
                &path.key("material"),
                "material",
                name,
                ctx.materials.keys().map(String::as_str),
            )
        })?,
    };
    let material = MaterialDesc {
        friction: spec.friction.unwrap_or(material.friction),
        restitution: spec.restitution.unwrap_or(material.restitution),
    };
    check_material(path, &material)?;
    let base_pose = pose(path, spec.position, spec.orientation, spec.rotation.as_deref())?;
    let linear_velocity = vec3_or_zero(&path.key("linear_velocity"), spec.linear_velocity)?;
    let angular_velocity = vec3_or_zero(&path.key("angular_velocity"), spec.angular_velocity)?;
    let linear_damping = non_negative(
        &path.key("linear_damping"),
        spec.linear_damping.unwrap_or(0.0),
        "1/s",
    )?;
    let angular_damping = non_negative(
        &path.key("angular_damping"),
        spec.angular_damping.unwrap_or(0.0),
        "1/s",
    )?;
    let force = vec3_or_zero(&path.key("initial_force"), spec.initial_force)?;
    let torque = vec3_or_zero(&path.key("initial_torque"), spec.initial_torque)?;
    if (spec.initial_force.is_some() || spec.initial_torque.is_some()) && kind != BodyKind::Dynamic {
        let key = if spec.initial_force.is_some() {
            "initial_force"
        } else {
            "initial_torque"
        };
        return Err(FieldError::new(
            &path.key(key),
            "forces act on dynamic bodies only",
        ));
    }

    let template = BodyDesc {
        kind,
        shapes: Vec::new(),
        mass: mass.unwrap_or_default(),
        pose: base_pose,
        linear_velocity,
        angular_velocity,
        material,
        linear_damping,
        angular_damping,
        ccd: spec.ccd.unwrap_or(false),
        non_colliding_group: spec.non_colliding_group.unwrap_or(0),
        name: spec.name.clone(),
    };
    let existing = out.scene.bodies.len() as u64;
    let mut push = |desc: BodyDesc, set: usize, copy: Option<usize>| {
        if force != DVec3::ZERO || torque != DVec3::ZERO {
            out.loads.push(InitialLoad {
                body: out.scene.bodies.len(),
                force,
                torque,
            });
        }
        out.origins.push(BodyOrigin {
            path: path.clone(),
            copy,
            shapes: shape_sets[set].1.clone(),
        });
        out.scene.bodies.push(desc);
    };
    let Some(grid) = &spec.grid else {
        push(
            BodyDesc {
                shapes: shape_sets[0].0.clone(),
                ..template
            },
            0,
            None,
        );
        return Ok(());
    };
    let gpath = path.key("grid");
    if grid.count.contains(&0) {
        return Err(FieldError::new(
            &gpath.key("count"),
            format!(
                "each count must be >= 1, got [{}, {}, {}]",
                grid.count[0], grid.count[1], grid.count[2]
            ),
        ));
    }
    let copies = grid.count.iter().map(|&c| c as u64).product::<u64>();
    if copies > 1_000_000 {
        return Err(FieldError::new(
            &gpath.key("count"),
            format!("at most 1,000,000 copies, got {copies}"),
        ));
    }
    // The same bound for the scene as a whole: many grids of a million each
    // would otherwise exhaust memory before any check runs.
    let total = existing + copies;
    if total > MAX_SCENE_BODIES {
        return Err(FieldError::new(
            &gpath.key("count"),
            format!("a scene holds at most 1,000,000 bodies; this grid brings it to {total}"),
        ));
    }
    let spacing = super::values::vec3(&gpath.key("spacing"), grid.spacing)?;
    let stagger = vec3_or_zero(&gpath.key("odd_layer_offset"), grid.odd_layer_offset)?;
    let mut n = 0usize;
    for k in 0..grid.count[2] {
        for j in 0..grid.count[1] {
            for i in 0..grid.count[0] {
                let mut offset = spacing * DVec3::new(i as f64, j as f64, k as f64);
                if k % 2 == 1 {
                    offset += stagger;
                }
                let set = (i + j + k) as usize % shape_sets.len();
                let mut desc = template.clone();
                desc.shapes = shape_sets[set].0.clone();
                desc.pose.position = base_pose.position + offset;
                desc.name = copy_name(&spec.name, [i, j, k], n);
                push(desc, set, Some(n));
                n += 1;
            }
        }
    }
    Ok(())
}

/// The index of the one body of `bodies` named `name`, which field `path`
/// gives (a joint's bodies, a `no_contact` pair).
pub(super) fn body_named(bodies: &[BodyDesc], path: &FieldPath, name: &str) -> Result<usize, FieldError> {
    let mut hits = bodies.iter().enumerate().filter(|(_, b)| b.name == name);
    match (hits.next(), hits.next()) {
        (Some((i, _)), None) => Ok(i),
        (None, _) => Err(FieldError::new(path, format!("no body is named `{name}`"))),
        (Some(_), Some(_)) => Err(FieldError::new(
            path,
            format!("more than one body is named `{name}`: give them distinct names"),
        )),
    }
}
