//! URDF robots: a `<robot>` file read into bodies and joints of a world.
//!
//! What is read (the ROS URDF specification): `<link>` with `<inertial>`
//! (origin, mass, inertia), `<collision>` geometry (box, cylinder, sphere,
//! mesh STL/OBJ relative to the file or in a ROS `package://`, with scale;
//! `<visual>` geometry when a link has no collision), and `<joint>` of type
//! revolute, continuous, prismatic and fixed with origin, axis, `<limit
//! lower upper effort velocity>` and `<dynamics damping friction>`. Links joined by
//! fixed joints are merged into one body (their shapes and inertia
//! combined, as PyBullet and MuJoCo do); every other joint becomes a hinge
//! (revolute, continuous) or slider (prismatic) from the parent link to the
//! child link, its angle 0 at the file's zero configuration. Joint
//! `damping` becomes a damper on the joint (a `Spring` of stiffness 0,
//! which stays when a motor is set; on a `spherical` joint it damps the
//! turn about every axis), and `friction` the joint's Coulomb friction
//! (`JointDesc::friction`, beside any motor); `effort` is kept as the
//! joint's largest motor force for the caller.
//!
//! Files written for other engines load as those engines read them (the
//! URDFs of PyBullet's data set, `bulletphysics/bullet3` `data/`, were the
//! test): `<capsule radius length>` (Bullet's extension, `length` between
//! the caps' centres) is a capsule, `<plane normal>` a half-space (a static
//! link's), joint type `spherical` a ball joint and `floating` no joint, and
//! a `<limit>` with lower > upper no limit; a mass of 0 means no mass was
//! given, and a root body without mass is static, as in PyBullet (a ground
//! plane, a table, the base of a fixed arm); a root link with neither
//! geometry nor mass stands for the world (ROS's `world` link), so the
//! joints from it attach their links to the world; a leaf link with
//! neither, on a moving joint (a frame for a tool or a sensor), is left out
//! with its joint, and one between moving joints (a frame through which
//! joints are composed: a hip of three hinges) becomes a light body
//! ([`STAND_IN_FRACTION`]); a fixed joint's axis is not read; off-diagonal inertia
//! entries default to 0. Each such reading is reported in
//! `UrdfRobot::warnings`. A link with an `<inertial>` but no geometry is a
//! body without shapes: it carries its mass and its joints and touches
//! nothing. The robot's links do not touch each other unless
//! `UrdfOptions::self_collision`, and then not where they overlap in the
//! file's pose (`UrdfParts::no_contact`); an inertia no body could have is
//! refused unless `UrdfOptions::balance_inertia`. Meshes are exact triangle
//! meshes, or their convex hulls with `UrdfOptions::convex_meshes` (as
//! PyBullet and MuJoCo read them).
//!
//! Errors name the file, line, column and element (`arm.urdf:12:5: <joint
//! name="elbow">: ...`). Nothing is added to the world unless the whole
//! robot is.

use crate::body::BodyKind;
use crate::joint::{Gear, JointDesc, JointId, JointKind, Spring};
use crate::world::{BodyDesc, BodyId, MassDesc, ShapeDesc, World, WorldError, WorldSettings};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tumble_collide::mass::MassProperties;
use tumble_collide::mesh::load_mesh;
use tumble_collide::narrow::contact_shapes;
use tumble_collide::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, Sphere};
use tumble_collide::{DMat3, DQuat, DVec3, Pose};

/// Segments of the convex hull that stands for a URDF cylinder.
pub const CYLINDER_SEGMENTS: usize = 24;

/// A link with neither geometry nor mass that carries other links through
/// moving joints (a frame that composes joints: MuJoCo's humanoid exported
/// to URDF makes its hips of three hinges this way) gets this fraction of
/// the robot's lightest body's mass, and an isotropic inertia of this
/// fraction of the smallest principal moment of any of its bodies. Small
/// enough to leave the motion of the links it joins as it would be without
/// it (a part in a thousand of the lightest mass), large enough for the
/// joint island's direct solve, which is exact whatever the mass ratio
/// (`solver::contact_solver::joint_island`).
pub const STAND_IN_FRACTION: f64 = 1e-3;

/// For a point or line mass `point` (an `<inertial>` with a moment of 0) whose link
/// has the geometry `shapes`: the file's mass at the file's centre of mass,
/// with the inertia the geometry has about its own centre for that mass
/// (PyBullet's default reading of every link: the shapes' inertia, the
/// file's mass and frame). `None` when the geometry has no volume.
fn geometry_inertia(shapes: &[ShapeDesc], point: &MassProperties) -> Option<MassProperties> {
    let frame = crate::world::body_mass::body_mass(shapes, MassDesc::Mass(point.mass)).ok()?;
    let axes = DMat3::from_quat(frame.rotation);
    let inertia = axes * DMat3::from_diagonal(frame.moments) * axes.transpose();
    MassProperties::new(point.mass, point.com, inertia).ok()
}

/// Gives the stand-in bodies `stand_ins` (indices into `descs`) their mass
/// ([`STAND_IN_FRACTION`]), from the other dynamic bodies of `descs`; `Err`
/// when none has a mass.
fn stand_in_masses(descs: &mut [BodyDesc], stand_ins: &[usize]) -> Result<(), ()> {
    let (mut lightest, mut smallest) = (f64::INFINITY, f64::INFINITY);
    for (k, d) in descs.iter().enumerate() {
        if d.kind != BodyKind::Dynamic || stand_ins.contains(&k) {
            continue;
        }
        // A body whose mass cannot be found is refused by the world later,
        // with its own message.
        if let Ok(frame) = crate::world::body_mass::body_mass(&d.shapes, d.mass) {
            lightest = lightest.min(frame.mass);
            smallest = smallest.min(frame.moments.min_element());
        }
    }
    if !(lightest.is_finite() && smallest.is_finite() && smallest > 0.0) {
        return Err(());
    }
    for &k in stand_ins {
        let inertia = DMat3::from_diagonal(DVec3::splat(STAND_IN_FRACTION * smallest));
        let p = MassProperties::new(STAND_IN_FRACTION * lightest, DVec3::ZERO, inertia).map_err(|_| ())?;
        descs[k].mass = MassDesc::Inertial(p);
    }
    Ok(())
}

/// Why a URDF file could not be loaded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UrdfError {
    /// The file could not be read.
    #[error("{file}: {message}")]
    Read {
        /// The file.
        file: PathBuf,
        /// The reason.
        message: String,
    },
    /// Something in the file is wrong.
    #[error("{file}:{line}:{column}: <{element}>: {message}")]
    At {
        /// The file.
        file: PathBuf,
        /// Line (from 1).
        line: u32,
        /// Column (from 1).
        column: u32,
        /// The element, e.g. `joint name="elbow"`.
        element: String,
        /// What is wrong and what was expected.
        message: String,
    },
}

/// Where to put the robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UrdfOptions {
    /// World position of the root link's frame (m).
    pub position: DVec3,
    /// World orientation of the root link's frame.
    pub orientation: DQuat,
    /// Weld the root link to the world.
    pub fixed_base: bool,
    /// Let the robot's links touch each other (jointed links still do not,
    /// as a joint's `collide_connected` is off, nor do links that overlap
    /// where the file places them: `UrdfParts::no_contact`). Off by
    /// default, as in PyBullet. Off, the robot's bodies share a
    /// non-colliding group of their own (`BodyDesc::non_colliding_group`).
    pub self_collision: bool,
    /// Replace an inertia that no body could have (a principal moment
    /// below 0, or two that sum to less than the third, as some files
    /// give) by the same mass's isotropic inertia of equal trace, with a
    /// warning, as MuJoCo's `balanceinertia` does; off, such a file is
    /// refused at its `<inertial>`.
    pub balance_inertia: bool,
    /// Give each `<mesh>` link shape as its convex hull instead of the
    /// triangle mesh itself, as PyBullet and MuJoCo take a moving link's
    /// mesh: a concave link (a hand, a head with its cameras' recesses)
    /// then touches with a few points a pair instead of every piece of its
    /// surface, at the cost of the hollows, which the hull fills. The hull
    /// is the link's shape for everything: its contacts and, where the file
    /// gives no `<inertial>`, its mass properties. Off by default: meshes
    /// are exact.
    pub convex_meshes: bool,
}

impl Default for UrdfOptions {
    fn default() -> Self {
        UrdfOptions {
            position: DVec3::ZERO,
            orientation: DQuat::IDENTITY,
            fixed_base: false,
            self_collision: false,
            balance_inertia: false,
            convex_meshes: false,
        }
    }
}

/// A movable joint of a loaded robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UrdfJoint {
    /// The joint in the world.
    pub id: JointId,
    /// Largest effort of the URDF `<limit>` (N m or N; infinite when not given).
    pub effort: f64,
    /// Largest speed of the URDF `<limit>` (rad/s or m/s; infinite when not given).
    pub velocity: f64,
}

/// A robot added to a world.
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfRobot {
    /// The robot's name.
    pub name: String,
    /// Every link's body (links merged by fixed joints share one); a link
    /// that stands for the world, or was left out, has none.
    pub links: BTreeMap<String, BodyId>,
    /// The robot's bodies in the order they were added (the root's first,
    /// unless the root stands for the world).
    pub bodies: Vec<BodyId>,
    /// Every non-fixed joint, by name.
    pub joints: BTreeMap<String, UrdfJoint>,
    /// With `UrdfOptions::self_collision`: the pairs of bodies that overlap
    /// in the file's pose and so never touch (`UrdfParts::no_contact`).
    pub no_contact: Vec<(BodyId, BodyId)>,
    /// The root link.
    pub root: String,
    /// What was read but not used (limits beyond what a hinge measures, ...).
    pub warnings: Vec<String>,
}

/// A robot read from URDF before it is added anywhere: its bodies, and its
/// joints with their bodies as indices into `bodies` (`None`: the world).
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfParts {
    /// The robot's name.
    pub name: String,
    /// One body per group of links joined by fixed joints, the root's first
    /// (unless the root stands for the world).
    pub bodies: Vec<BodyDesc>,
    /// Every joint of the file that becomes one, in the file's order.
    pub joints: Vec<UrdfPartJoint>,
    /// With `UrdfOptions::fixed_base` and a dynamic root: its weld to the world.
    pub base_weld: Option<JointDesc<usize>>,
    /// With `UrdfOptions::self_collision`: the pairs of bodies (indices
    /// into `bodies`, the lower first) that overlap where the file places
    /// them and that no joint links; they never touch
    /// (`World::set_contacts_between`).
    pub no_contact: Vec<(usize, usize)>,
    /// Every link's body (an index into `bodies`); a link that stands for
    /// the world, or was left out, has none.
    pub links: BTreeMap<String, usize>,
    /// The root link.
    pub root: String,
    /// How the file was read where it departs from the URDF specification,
    /// and what it asks for that is not simulated.
    pub warnings: Vec<String>,
}

/// A joint of [`UrdfParts`].
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfPartJoint {
    /// The joint, named as in the file.
    pub desc: JointDesc<usize>,
    /// Largest effort of its `<limit>` (N m or N; infinite when not given).
    pub effort: f64,
    /// Largest speed of its `<limit>` (rad/s or m/s; infinite when not given).
    pub velocity: f64,
    /// Its `<mimic>`: the gear that holds it to another joint's coordinate.
    pub gear: Option<UrdfGear>,
}

/// A `<mimic joint multiplier offset>`: the joint's coordinate held at
/// `ratio` times `leader`'s plus `offset` ([`Gear`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UrdfGear {
    /// The joint followed, an index into [`UrdfParts::joints`].
    pub leader: usize,
    /// `multiplier` (default 1).
    pub ratio: f64,
    /// `offset` (rad or m, default 0).
    pub offset: f64,
}

/// Reads the URDF file at `path` and adds the robot to `world`.
///
/// ```
/// use tumble::joint::urdf::{load_urdf, UrdfOptions};
/// use tumble::world::{World, WorldSettings};
///
/// let mut world = World::new(WorldSettings::default())?;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/robots/arm6.urdf");
/// let arm = load_urdf(&mut world, path, UrdfOptions { fixed_base: true, ..UrdfOptions::default() })?;
/// assert_eq!(arm.joints.len(), 6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn load_urdf(
    world: &mut World,
    path: impl AsRef<Path>,
    options: UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    let path = path.as_ref();
    let text = read_file(path)?;
    add_urdf(world, &text, path, options)
}

/// Largest URDF file read (bytes): robot descriptions are kilobytes; a
/// path to something else (a device that never ends, a mesh named by
/// mistake) is refused before it is read.
pub const MAX_URDF_BYTES: u64 = 64 << 20;

/// The text of the URDF file at `path`.
fn read_file(path: &Path) -> Result<String, UrdfError> {
    let refuse = |message: String| UrdfError::Read {
        file: path.to_path_buf(),
        message,
    };
    let meta = std::fs::metadata(path).map_err(|e| refuse(e.to_string()))?;
    if !meta.is_file() {
        return Err(refuse("not a regular file".into()));
    }
    if meta.len() > MAX_URDF_BYTES {
        return Err(refuse(format!(
            "{} bytes: larger than any robot description (at most {MAX_URDF_BYTES})",
            meta.len()
        )));
    }
    std::fs::read_to_string(path).map_err(|e| refuse(e.to_string()))
}

/// Adds the robot described by URDF `text` to `world`; `file` names it in
/// errors and is where mesh files are looked up from. On error the world
/// is unchanged (the robot goes into a copy of the world first, so a call
/// costs a copy of what the world holds).
pub fn add_urdf(
    world: &mut World,
    text: &str,
    file: &Path,
    options: UrdfOptions,
) -> Result<UrdfRobot, UrdfError> {
    read(text, file, options, |model, reader| {
        model.add_to(world, options, reader)
    })
}

/// Reads the URDF file at `path` into [`UrdfParts`], the robot's bodies in
/// non-colliding group `group` unless `options.self_collision` (a scene
/// file's robots: `tumble::scene`). Checked as a world would check them
/// when they are added, the refusals located in the file.
pub fn read_urdf_parts(
    path: impl AsRef<Path>,
    options: UrdfOptions,
    group: u32,
) -> Result<UrdfParts, UrdfError> {
    let path = path.as_ref();
    let text = read_file(path)?;
    read(&text, path, options, |model, reader| {
        let Located {
            parts,
            body_nodes,
            joint_nodes,
        } = model.parts(options, group, reader)?;
        let mut scratch = World::new(WorldSettings::default()).expect("the default settings are valid");
        add_parts(&mut scratch, &parts, &body_nodes, &joint_nodes, reader)?;
        Ok(parts)
    })
}

/// Parses URDF `text` (errors naming `file`) and hands its model to `then`.
fn read<T>(
    text: &str,
    file: &Path,
    options: UrdfOptions,
    then: impl for<'a, 'i> FnOnce(&Model<'a, 'i>, &Reader<'a, 'i>) -> Result<T, UrdfError>,
) -> Result<T, UrdfError> {
    // An XML declaration after a blank line (files of PyBullet's data set)
    // is refused by the XML parser; it says nothing a URDF needs, so it is
    // blanked out, in place, keeping every line and column.
    let blanked;
    let text = match text.find("<?xml") {
        Some(at) if at > 0 && text[..at].trim().is_empty() => {
            let end = text[at..].find("?>").map_or(text.len(), |e| at + e + 2);
            blanked = format!("{}{}{}", &text[..at], " ".repeat(end - at), &text[end..]);
            blanked.as_str()
        }
        _ => text,
    };
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        let pos = e.pos();
        UrdfError::At {
            file: file.to_path_buf(),
            line: pos.row,
            column: pos.col,
            element: "xml".into(),
            message: e.to_string(),
        }
    })?;
    let reader = Reader {
        doc: &doc,
        file,
        balance_inertia: options.balance_inertia,
        convex_meshes: options.convex_meshes,
    };
    let model = reader.model()?;
    then(&model, &reader)
}

/// The parsed file.
struct Reader<'a, 'input> {
    doc: &'a roxmltree::Document<'input>,
    file: &'a Path,
    /// `UrdfOptions::balance_inertia`.
    balance_inertia: bool,
    /// `UrdfOptions::convex_meshes`.
    convex_meshes: bool,
}

struct Link<'a, 'input> {
    node: roxmltree::Node<'a, 'input>,
    name: String,
    /// The `<inertial>`, if it gives a mass (> 0).
    inertial: Option<MassProperties>,
    /// An `<inertial>` with a mass of 0 (PyBullet: static, if the root).
    zero_mass: bool,
    /// Its inertia was not physical and was balanced (`balance_inertia`).
    balanced: bool,
    shapes: Vec<ShapeDesc>,
}

struct Joint<'a, 'input> {
    node: roxmltree::Node<'a, 'input>,
    name: String,
    kind: &'static str,
    parent: usize,
    child: usize,
    origin: Pose,
    axis: DVec3,
    limits: Option<[f64; 2]>,
    effort: f64,
    velocity: f64,
    damping: f64,
    /// `<dynamics friction>` (N m or N, Coulomb).
    friction: f64,
    /// `<mimic joint multiplier offset>`: the leader's name, the ratio and
    /// the offset, and the element.
    mimic: Option<(String, f64, f64, roxmltree::Node<'a, 'input>)>,
}

struct Model<'a, 'input> {
    name: String,
    links: Vec<Link<'a, 'input>>,
    joints: Vec<Joint<'a, 'input>>,
    /// Joints whose `<limit>` has lower > upper: no limit.
    reversed_limits: Vec<String>,
}

impl<'a, 'input> Reader<'a, 'input> {
    fn err(&self, node: roxmltree::Node, message: impl Into<String>) -> UrdfError {
        let pos = self.doc.text_pos_at(node.range().start);
        let tag = node.tag_name().name();
        let element = match node.attribute("name") {
            Some(n) => format!("{tag} name=\"{n}\""),
            None => tag.to_string(),
        };
        UrdfError::At {
            file: self.file.to_path_buf(),
            line: pos.row,
            column: pos.col,
            element,
            message: message.into(),
        }
    }

    fn attr<'n>(&self, node: roxmltree::Node<'n, 'input>, name: &str) -> Result<&'n str, UrdfError> {
        node.attribute(name)
            .ok_or_else(|| self.err(node, format!("the attribute `{name}` is missing")))
    }

    fn numbers(&self, node: roxmltree::Node, name: &str, n: usize) -> Result<Vec<f64>, UrdfError> {
        let text = self.attr(node, name)?;
        let values: Vec<f64> = text
            .split_whitespace()
            .map(|t| t.parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| self.err(node, format!("`{name}` must be {n} numbers, got \"{text}\"")))?;
        if values.len() != n || values.iter().any(|v| !v.is_finite()) {
            return Err(self.err(
                node,
                format!("`{name}` must be {n} finite numbers, got \"{text}\""),
            ));
        }
        Ok(values)
    }

    fn number(&self, node: roxmltree::Node, name: &str) -> Result<f64, UrdfError> {
        Ok(self.numbers(node, name, 1)?[0])
    }

    fn optional_number(&self, node: roxmltree::Node, name: &str, default: f64) -> Result<f64, UrdfError> {
        if node.attribute(name).is_some() {
            self.number(node, name)
        } else {
            Ok(default)
        }
    }

    fn child<'n>(&self, node: roxmltree::Node<'n, 'input>, tag: &str) -> Option<roxmltree::Node<'n, 'input>> {
        node.children()
            .find(|c| c.is_element() && c.tag_name().name() == tag)
    }

    /// `<origin xyz rpy>` of `node` (identity when absent). URDF's rpy is
    /// roll about x, then pitch about y, then yaw about z, all fixed axes.
    fn origin(&self, node: roxmltree::Node) -> Result<Pose, UrdfError> {
        let Some(o) = self.child(node, "origin") else {
            return Ok(Pose::IDENTITY);
        };
        let xyz = if o.attribute("xyz").is_some() {
            self.numbers(o, "xyz", 3)?
        } else {
            vec![0.0; 3]
        };
        let rpy = if o.attribute("rpy").is_some() {
            self.numbers(o, "rpy", 3)?
        } else {
            vec![0.0; 3]
        };
        let rotation =
            DQuat::from_rotation_z(rpy[2]) * DQuat::from_rotation_y(rpy[1]) * DQuat::from_rotation_x(rpy[0]);
        Ok(Pose {
            position: DVec3::new(xyz[0], xyz[1], xyz[2]),
            rotation: rotation.normalize(),
        })
    }

    /// Where the mesh file `name` of element `node` is: relative to the
    /// URDF file, `file://` (absolute, or relative to the file), or a ROS
    /// `package://PKG/PATH`: `PATH` inside the first directory named `PKG`
    /// found among the URDF's own directory and its ancestors (a package
    /// holding its `urdf/` and `meshes/` folders, as ROS lays them out),
    /// their subdirectories named `PKG`, and the directories of
    /// `ROS_PACKAGE_PATH` (and their subdirectories named `PKG`).
    fn mesh_path(&self, node: roxmltree::Node, name: &str) -> Result<PathBuf, UrdfError> {
        let here = self.file.parent().unwrap_or(Path::new(""));
        if let Some(rest) = name.strip_prefix("package://") {
            let (package, inside) = rest.split_once('/').unwrap_or((rest, ""));
            let env = std::env::var_os("ROS_PACKAGE_PATH").unwrap_or_default();
            let roots: Vec<PathBuf> = here
                .ancestors()
                .map(Path::to_path_buf)
                .chain(std::env::split_paths(&env))
                .collect();
            let found = roots.iter().find_map(|root| {
                let named = |dir: &Path| dir.file_name().is_some_and(|n| n == package);
                [root.clone(), root.join(package)]
                    .into_iter()
                    .filter(|dir| named(dir))
                    .map(|dir| dir.join(inside))
                    .find(|candidate| candidate.is_file())
            });
            return found.ok_or_else(|| {
                self.err(
                    node,
                    format!(
                        "`{name}`: no directory named `{package}` holding `{inside}` among the URDF's \
                         directory, its ancestors and ROS_PACKAGE_PATH"
                    ),
                )
            });
        }
        let relative = name.strip_prefix("file://").unwrap_or(name);
        if relative.contains("://") {
            return Err(self.err(
                node,
                format!("`{name}`: only files, file:// and package:// can be found"),
            ));
        }
        Ok(here.join(relative))
    }

    /// The shape of a `<geometry>` element.
    fn geometry(&self, g: roxmltree::Node) -> Result<Shape, UrdfError> {
        let Some(shape) = g.children().find(|c| c.is_element()) else {
            return Err(self.err(
                g,
                "needs one of <box>, <cylinder>, <capsule>, <sphere>, <plane>, <mesh>",
            ));
        };
        let bad = |e: &dyn std::fmt::Display| self.err(shape, e.to_string());
        match shape.tag_name().name() {
            "box" => {
                let s = self.numbers(shape, "size", 3)?;
                Ok(Cuboid::new(DVec3::new(s[0], s[1], s[2]) * 0.5)
                    .map_err(|e| bad(&e))?
                    .into())
            }
            "sphere" => Ok(Sphere::new(self.number(shape, "radius")?)
                .map_err(|e| bad(&e))?
                .into()),
            // Bullet's extension: the half-space below the plane through
            // the collision origin with this normal (a static link's).
            "plane" => {
                let n = match shape.attribute("normal") {
                    Some(_) => self.numbers(shape, "normal", 3)?,
                    None => vec![0.0, 0.0, 1.0],
                };
                Ok(HalfSpace::new(DVec3::new(n[0], n[1], n[2]), 0.0)
                    .map_err(|e| bad(&e))?
                    .into())
            }
            // Bullet's extension: `length` between the two caps' centres, along z.
            "capsule" => {
                let (r, l) = (self.number(shape, "radius")?, self.number(shape, "length")?);
                Ok(Capsule::new(r, 0.5 * l).map_err(|e| bad(&e))?.into())
            }
            "cylinder" => {
                // A convex hull of two rings: tumble has no cylinder
                // primitive; the hull's flat sides are within r (1 - cos(pi/24)),
                // 0.9 % of the radius.
                let (r, l) = (self.number(shape, "radius")?, self.number(shape, "length")?);
                if !(r > 0.0 && l > 0.0) {
                    return Err(self.err(shape, format!("radius and length must be > 0 m, got {r} and {l}")));
                }
                let points: Vec<DVec3> = (0..CYLINDER_SEGMENTS)
                    .flat_map(|k| {
                        let a = std::f64::consts::TAU * k as f64 / CYLINDER_SEGMENTS as f64;
                        let (s, c) = a.sin_cos();
                        [
                            DVec3::new(r * c, r * s, -l / 2.0),
                            DVec3::new(r * c, r * s, l / 2.0),
                        ]
                    })
                    .collect();
                Ok(ConvexHull::from_points(&points).map_err(|e| bad(&e))?.into())
            }
            "mesh" => {
                let name = self.attr(shape, "filename")?;
                let path = self.mesh_path(shape, name)?;
                let mut mesh =
                    load_mesh(&path).map_err(|e| self.err(shape, format!("{}: {e}", path.display())))?;
                if shape.attribute("scale").is_some() {
                    let s = self.numbers(shape, "scale", 3)?;
                    let scale = DVec3::new(s[0], s[1], s[2]);
                    let vertices: Vec<DVec3> = mesh.vertices().iter().map(|&v| v * scale).collect();
                    mesh = tumble_collide::mesh::TriMesh::new(vertices, mesh.triangles().to_vec())
                        .map_err(|e| bad(&e))?;
                }
                if self.convex_meshes {
                    return Ok(ConvexHull::from_points(mesh.vertices())
                        .map_err(|e| self.err(shape, format!("{}: its convex hull: {e}", path.display())))?
                        .into());
                }
                Ok(MeshShape::new(mesh).map_err(|e| bad(&e))?.into())
            }
            other => Err(self.err(
                shape,
                format!("unknown geometry <{other}> (box, cylinder, capsule, sphere, plane or mesh)"),
            )),
        }
    }

    fn link(&self, node: roxmltree::Node<'a, 'input>) -> Result<Link<'a, 'input>, UrdfError> {
        let name = self.attr(node, "name")?.to_string();
        let mut zero_mass = false;
        let mut balanced = false;
        let inertial = match self.child(node, "inertial") {
            None => None,
            Some(i) => {
                let origin = self.origin(i)?;
                let mass_node = self
                    .child(i, "mass")
                    .ok_or_else(|| self.err(i, "needs <mass value=...>"))?;
                let mass = self.number(mass_node, "value")?;
                let t = self
                    .child(i, "inertia")
                    .ok_or_else(|| self.err(i, "needs <inertia ixx ixy ixz iyy iyz izz>"))?;
                // The moments are needed; the products default to 0.
                let [ixx, iyy, izz] = ["ixx", "iyy", "izz"].map(|k| self.number(t, k));
                let [ixy, ixz, iyz] = ["ixy", "ixz", "iyz"].map(|k| self.optional_number(t, k, 0.0));
                let (ixx, ixy, ixz, iyy, iyz, izz) = (ixx?, ixy?, ixz?, iyy?, iyz?, izz?);
                zero_mass = mass == 0.0;
                let inertia = DMat3::from_cols(
                    DVec3::new(ixx, ixy, ixz),
                    DVec3::new(ixy, iyy, iyz),
                    DVec3::new(ixz, iyz, izz),
                );
                // The tensor is given in the inertial origin's frame.
                let r = DMat3::from_quat(origin.rotation);
                let mean = (ixx + iyy + izz) / 3.0;
                match (
                    zero_mass,
                    MassProperties::new(mass, origin.position, r * inertia * r.transpose()),
                ) {
                    (true, _) => None,
                    (false, Ok(p)) => Some(p),
                    (false, Err(_)) if self.balance_inertia && mean > 0.0 && mass > 0.0 => {
                        balanced = true;
                        let isotropic = DMat3::from_diagonal(DVec3::splat(mean));
                        Some(
                            MassProperties::new(mass, origin.position, isotropic)
                                .map_err(|e| self.err(i, format!("mass {mass} kg, inertia: {e}")))?,
                        )
                    }
                    (false, Err(e)) => {
                        let hint = if mass > 0.0 && mean > 0.0 {
                            " (balance_inertia, CLI --balance-inertia, replaces it by the isotropic \
                             inertia of the same trace, as MuJoCo's balanceinertia does)"
                        } else {
                            ""
                        };
                        return Err(self.err(i, format!("mass {mass} kg, inertia: {e}{hint}")));
                    }
                }
            }
        };
        let mut shapes = Vec::new();
        for tag in ["collision", "visual"] {
            for c in node
                .children()
                .filter(|c| c.is_element() && c.tag_name().name() == tag)
            {
                let g = self
                    .child(c, "geometry")
                    .ok_or_else(|| self.err(c, "needs a <geometry>"))?;
                shapes.push(ShapeDesc::new(self.geometry(g)?).at(self.origin(c)?));
            }
            // Visual geometry stands in only for links with no collision.
            if !shapes.is_empty() {
                break;
            }
        }
        Ok(Link {
            node,
            name,
            inertial,
            zero_mass,
            balanced,
            shapes,
        })
    }

    fn model(&self) -> Result<Model<'a, 'input>, UrdfError> {
        let root = self.doc.root_element();
        if root.tag_name().name() != "robot" {
            return Err(self.err(root, "a URDF file's root element is <robot>"));
        }
        let name = root.attribute("name").unwrap_or("robot").to_string();
        let mut links = Vec::new();
        for node in root
            .children()
            .filter(|c| c.is_element() && c.tag_name().name() == "link")
        {
            let link = self.link(node)?;
            if links.iter().any(|l: &Link| l.name == link.name) {
                return Err(self.err(node, format!("a second link named `{}`", link.name)));
            }
            links.push(link);
        }
        if links.is_empty() {
            return Err(self.err(root, "the robot has no <link>"));
        }
        let find = |node: roxmltree::Node, tag: &str| -> Result<usize, UrdfError> {
            let el = self
                .child(node, tag)
                .ok_or_else(|| self.err(node, format!("needs <{tag} link=...>")))?;
            let name = self.attr(el, "link")?;
            links
                .iter()
                .position(|l| l.name == name)
                .ok_or_else(|| self.err(el, format!("no link is named `{name}`")))
        };
        let mut joints: Vec<Joint> = Vec::new();
        let mut reversed_limits = Vec::new();
        for node in root
            .children()
            .filter(|c| c.is_element() && c.tag_name().name() == "joint")
        {
            let name = self.attr(node, "name")?.to_string();
            let kind = match self.attr(node, "type")? {
                "revolute" => "revolute",
                "continuous" => "continuous",
                "prismatic" => "prismatic",
                "fixed" => "fixed",
                // Bullet's extension: a ball joint.
                "spherical" => "spherical",
                // No constraint: the child moves freely.
                "floating" => "floating",
                other => {
                    return Err(self.err(
                        node,
                        format!(
                            "joint type `{other}` is not supported (revolute, continuous, prismatic, fixed, \
                             spherical, floating)"
                        ),
                    ))
                }
            };
            let (parent, child) = (find(node, "parent")?, find(node, "child")?);
            if parent == child {
                return Err(self.err(node, "parent and child are the same link"));
            }
            if joints.iter().any(|j| j.child == child) {
                return Err(self.err(
                    node,
                    format!(
                        "link `{}` is the child of two joints (URDF is a tree)",
                        links[child].name
                    ),
                ));
            }
            // A fixed joint's axis means nothing (files give "0 0 0").
            let axis = match self.child(node, "axis").filter(|_| kind != "fixed") {
                Some(a) => {
                    let v = self.numbers(a, "xyz", 3)?;
                    let v = DVec3::new(v[0], v[1], v[2]);
                    if v.length() < 1e-9 {
                        return Err(self.err(a, "the axis must not be zero"));
                    }
                    v.normalize()
                }
                None => DVec3::X,
            };
            let (mut limits, mut effort, mut velocity) = (None, f64::INFINITY, f64::INFINITY);
            if let Some(l) = self.child(node, "limit") {
                effort = self.optional_number(l, "effort", f64::INFINITY)?;
                velocity = self.optional_number(l, "velocity", f64::INFINITY)?;
                if matches!(kind, "revolute" | "prismatic") {
                    let (lo, hi) = (
                        self.optional_number(l, "lower", 0.0)?,
                        self.optional_number(l, "upper", 0.0)?,
                    );
                    // Bullet reads lower > upper as no limit (files of
                    // PyBullet's data set rely on it).
                    if lo <= hi {
                        limits = Some([lo, hi]);
                    } else {
                        reversed_limits.push(name.clone());
                    }
                }
                if effort < 0.0 || velocity < 0.0 {
                    return Err(self.err(l, "effort and velocity must be >= 0"));
                }
            } else if kind == "revolute" || kind == "prismatic" {
                return Err(self.err(
                    node,
                    format!("a {kind} joint needs a <limit> (lower, upper, effort, velocity)"),
                ));
            }
            let (damping, friction) = match self.child(node, "dynamics") {
                Some(d) => (
                    self.optional_number(d, "damping", 0.0)?,
                    self.optional_number(d, "friction", 0.0)?,
                ),
                None => (0.0, 0.0),
            };
            if friction < 0.0 {
                return Err(self.err(node, "dynamics friction must be >= 0"));
            }
            // A mimic joint follows its leader by a gear (`joint::Gear`).
            let mimic = match self.child(node, "mimic") {
                Some(m) => {
                    let leader = m
                        .attribute("joint")
                        .ok_or_else(|| self.err(m, "<mimic> needs joint=\"the joint it follows\""))?;
                    let (ratio, offset) = (
                        self.optional_number(m, "multiplier", 1.0)?,
                        self.optional_number(m, "offset", 0.0)?,
                    );
                    // The numbers checked here, at the element.
                    Gear::check_numbers(ratio, offset).map_err(|e| self.err(m, world_message(&e)))?;
                    Some((leader.to_string(), ratio, offset, m))
                }
                None => None,
            };
            if damping < 0.0 {
                return Err(self.err(node, "dynamics damping must be >= 0"));
            }
            joints.push(Joint {
                node,
                name,
                kind,
                parent,
                child,
                origin: self.origin(node)?,
                axis,
                limits,
                effort,
                velocity,
                damping,
                friction,
                mimic,
            });
        }
        Ok(Model {
            name,
            links,
            joints,
            reversed_limits,
        })
    }
}

impl<'a, 'input> Model<'a, 'input> {
    /// The robot's bodies and joints, with the elements they come from
    /// (for errors the world raises when they are added), the robot's
    /// bodies in non-colliding group `group` unless `options.self_collision`.
    fn parts(
        &self,
        options: UrdfOptions,
        group: u32,
        r: &Reader<'a, 'input>,
    ) -> Result<Located<'a, 'input>, UrdfError> {
        let n = self.links.len();
        let mut parent_joint = vec![None; n];
        for (k, j) in self.joints.iter().enumerate() {
            parent_joint[j.child] = Some(k);
        }
        let roots: Vec<usize> = (0..n).filter(|&l| parent_joint[l].is_none()).collect();
        let root = match roots.as_slice() {
            [one] => *one,
            _ => {
                let names: Vec<&str> = roots.iter().map(|&l| self.links[l].name.as_str()).collect();
                return Err(r.err(
                    r.doc.root_element(),
                    format!("the links must form one tree with one root; roots: {names:?}"),
                ));
            }
        };
        // World pose of every link frame at the zero configuration, parents
        // first (a depth-first walk from the root; a loop leaves links unset).
        let mut pose: Vec<Option<Pose>> = vec![None; n];
        pose[root] = Some(Pose {
            position: options.position,
            rotation: options.orientation.normalize(),
        });
        let mut order = vec![root];
        let mut head = 0;
        while head < order.len() {
            let l = order[head];
            for j in self.joints.iter().filter(|j| j.parent == l) {
                pose[j.child] = Some(pose[l].expect("parent placed").mul_pose(&j.origin));
                order.push(j.child);
            }
            head += 1;
        }
        if order.len() != n {
            return Err(r.err(r.doc.root_element(), "the joints form a loop (URDF is a tree)"));
        }
        // Bodies: each link joins its parent's body across a fixed joint.
        let mut body_of = vec![usize::MAX; n];
        let mut groups: Vec<usize> = Vec::new(); // group -> its root link
        for &l in &order {
            match parent_joint[l].map(|k| &self.joints[k]) {
                Some(j) if j.kind == "fixed" => body_of[l] = body_of[j.parent],
                _ => {
                    body_of[l] = groups.len();
                    groups.push(l);
                }
            }
        }
        let mut warnings: Vec<String> = self
            .reversed_limits
            .iter()
            .map(|j| {
                format!("joint `{j}`: lower > upper in its <limit>, read as no limit (as Bullet reads it)")
            })
            .collect();
        warnings.extend(self.links.iter().filter(|l| l.balanced).map(|l| {
            format!(
                "link `{}`: its inertia is not physical; replaced by the isotropic inertia of the same \
                 trace (balance_inertia)",
                l.name
            )
        }));
        // A group of its own for the robot's bodies, unless they may touch.
        let group = match options.self_collision {
            true => 0,
            false => group,
        };
        // Whether a group carries another through a moving joint.
        let carries = |g: usize| {
            self.joints
                .iter()
                .any(|j| j.kind != "fixed" && body_of[j.parent] == g)
        };
        // Each group's body (an index into `descs`), or none: the root
        // with neither geometry nor mass is the world, a leaf with neither
        // is left out (module docs).
        let mut group_body: Vec<Option<usize>> = Vec::with_capacity(groups.len());
        let mut descs = Vec::with_capacity(groups.len());
        // The massless frames between moving joints (indices into `descs`)
        // and their links.
        let (mut stand_ins, mut stand_in_links) = (Vec::new(), Vec::new());
        for (g, &head_link) in groups.iter().enumerate() {
            let frame = pose[head_link].expect("placed");
            let inv = frame.inverse();
            let mut shapes = Vec::new();
            let mut parts = Vec::new();
            let mut names = Vec::new();
            let mut zero_mass = false;
            for l in (0..n).filter(|&l| body_of[l] == g) {
                let local = inv.mul_pose(&pose[l].expect("placed"));
                let link = &self.links[l];
                names.push(link.name.as_str());
                shapes.extend(
                    link.shapes
                        .iter()
                        .map(|s| s.clone().at(local.mul_pose(&s.local_pose))),
                );
                if let Some(p) = link.inertial {
                    parts.push(p.transformed(&local));
                }
                zero_mass |= link.zero_mass;
            }
            let link = &self.links[head_link];
            if shapes.is_empty() && parts.is_empty() {
                if g == 0 {
                    warnings.push(format!(
                        "link `{}` has neither geometry nor mass: it stands for the world, and the joints \
                         from it attach their links to the world",
                        link.name
                    ));
                    group_body.push(None);
                    continue;
                }
                if !carries(g) {
                    let joint = parent_joint[head_link].map_or("", |k| self.joints[k].name.as_str());
                    warnings.push(format!(
                        "link `{}` has neither geometry nor mass and carries no other link: left out, \
                         with its joint `{joint}`",
                        link.name
                    ));
                    group_body.push(None);
                    continue;
                }
            }
            if shapes.is_empty() && parts.is_empty() {
                // A frame between two moving joints (joints composed
                // through massless links: a hip of three hinges). A body
                // with no mass cannot move in maximal coordinates; it gets
                // a small one once the robot's masses are known (below).
                stand_ins.push(descs.len());
                group_body.push(Some(descs.len()));
                descs.push(BodyDesc {
                    kind: BodyKind::Dynamic,
                    pose: frame,
                    non_colliding_group: group,
                    name: names.join("+"),
                    ..BodyDesc::default()
                });
                stand_in_links.push(head_link);
                continue;
            }
            let (kind, mass) = if !parts.is_empty() {
                let combined =
                    MassProperties::combine(&parts).map_err(|e| r.err(link.node, format!("inertia: {e}")))?;
                // A point mass (all moments 0, as some files give) or a
                // line mass (a rod's moment about its axis 0) is valid mass
                // properties but no rigid body: it could not turn about
                // some axis. With geometry, the geometry gives the moments;
                // without, refused.
                let moments = combined.principal().moments;
                let from_geometry = match moments.x <= 0.0 && !shapes.is_empty() {
                    true => geometry_inertia(&shapes, &combined),
                    false => None,
                };
                if let Some(p) = from_geometry {
                    warnings.push(format!(
                        "link `{}`: its <inertial> has a principal moment of 0 (moments {:?} kg m^2: a point \
                         or a line mass, which no solid is): its inertia follows from its geometry and the \
                         file's mass, as PyBullet computes it",
                        link.name,
                        moments.to_array()
                    ));
                    (BodyKind::Dynamic, MassDesc::Inertial(p))
                } else if moments.x <= 0.0 || moments.x.is_nan() {
                    let at = r.child(link.node, "inertial").unwrap_or(link.node);
                    return Err(r.err(
                        at,
                        format!(
                            "the body's principal moments of inertia must all be > 0 kg m^2, got {:?} \
                             (a point mass cannot turn)",
                            moments.to_array()
                        ),
                    ));
                } else {
                    (BodyKind::Dynamic, MassDesc::Inertial(combined))
                }
            } else if zero_mass && g == 0 {
                warnings.push(format!(
                    "link `{}` has a mass of 0: the robot's root is static, as in PyBullet",
                    link.name
                ));
                (BodyKind::Static, MassDesc::default())
            } else {
                if zero_mass {
                    warnings.push(format!(
                        "link `{}` has a mass of 0 but moves: its mass follows from its geometry \
                         (as for a link without <inertial>)",
                        link.name
                    ));
                }
                (BodyKind::Dynamic, MassDesc::default())
            };
            group_body.push(Some(descs.len()));
            descs.push(BodyDesc {
                kind,
                shapes,
                mass,
                pose: frame,
                non_colliding_group: group,
                name: names.join("+"),
                ..BodyDesc::default()
            });
        }
        if descs.is_empty() {
            return Err(r.err(
                r.doc.root_element(),
                "no link of the robot is a body (each has neither geometry nor mass)",
            ));
        }
        if !stand_ins.is_empty() {
            stand_in_masses(&mut descs, &stand_ins).map_err(|()| {
                r.err(
                    self.links[stand_in_links[0]].node,
                    "has neither geometry nor mass, and carries other links, and no link of the robot \
                     has a mass to size a stand-in from (give it an <inertial>)",
                )
            })?;
            let names: Vec<String> = stand_in_links
                .iter()
                .map(|&l| format!("`{}`", self.links[l].name))
                .collect();
            warnings.push(format!(
                "link{s} {}: neither geometry nor mass, but carrying other links: given {STAND_IN_FRACTION} \
                 of the lightest body's mass and smallest moment of inertia (a massless frame between \
                 joints cannot move in maximal coordinates)",
                names.join(", "),
                s = if names.len() > 1 { "s" } else { "" },
            ));
        }
        let mut joint_descs = Vec::new();
        for j in self
            .joints
            .iter()
            .filter(|j| !matches!(j.kind, "fixed" | "floating"))
        {
            // A left-out link's joint goes with it.
            let Some(child) = group_body[body_of[j.child]] else {
                continue;
            };
            let parent = group_body[body_of[j.parent]];
            let frame = pose[j.child].expect("placed");
            let axis = frame.rotation * j.axis;
            let (kind, mut limits) = match j.kind {
                "prismatic" => (JointKind::Slider, j.limits),
                "revolute" => (JointKind::Hinge, j.limits),
                "spherical" => (JointKind::Ball, None),
                _ => (JointKind::Hinge, None),
            };
            let pi = std::f64::consts::PI;
            if let (JointKind::Hinge, Some([lo, hi])) = (kind, limits) {
                if lo < -pi || hi > pi {
                    warnings.push(format!(
                        "joint `{}`: limits [{lo}, {hi}] reach beyond +-pi, which a hinge angle cannot measure; \
                         the joint turns freely",
                        j.name
                    ));
                    limits = None;
                }
            }
            let mut desc = JointDesc::new(kind, child, parent, frame.position, axis).named(j.name.clone());
            desc.limits = limits;
            // Damping is passive, a damper beside whatever motor drives
            // the joint (a spring of stiffness 0), never bounded by the
            // effort; on a ball joint it damps the turn about every axis.
            if j.damping > 0.0 {
                desc.spring = Some(Spring {
                    stiffness: 0.0,
                    damping: j.damping,
                });
            }
            // Coulomb friction on the joint (MuJoCo's `frictionloss`),
            // beside whatever motor is set later.
            if j.friction > 0.0 {
                desc.friction = Some(j.friction);
            }
            desc.validate().map_err(|e| r.err(j.node, e.to_string()))?;
            joint_descs.push((j, desc));
        }
        // (A static root, or one that stands for the world, is fixed already.)
        let base_weld = match (options.fixed_base, group_body[body_of[root]]) {
            (true, Some(k)) if descs[k].kind == BodyKind::Dynamic => {
                let frame = pose[root].expect("placed");
                Some(JointDesc::fixed(k, None, frame.position))
            }
            _ => None,
        };
        let mut body_nodes = vec![self.links[root].node; descs.len()];
        for (g, body) in group_body.iter().enumerate() {
            if let Some(k) = body {
                body_nodes[*k] = self.links[groups[g]].node;
            }
        }
        let joint_nodes = joint_descs.iter().map(|(j, _)| j.node).collect();
        let no_contact = match options.self_collision {
            true => {
                let linked: Vec<(usize, usize)> = joint_descs
                    .iter()
                    .filter_map(|(_, d)| d.body_b.map(|b| (d.body_a.min(b), d.body_a.max(b))))
                    .collect();
                overlapping_pairs(&descs, &linked)
            }
            false => Vec::new(),
        };
        // Mimic joints: each follows a moving joint of this robot by name.
        let mut gears = Vec::with_capacity(joint_descs.len());
        for (j, _) in &joint_descs {
            gears.push(match &j.mimic {
                None => None,
                Some((leader, ratio, offset, node)) => {
                    let Some(k) = joint_descs.iter().position(|(l, _)| l.name == *leader) else {
                        return Err(r.err(
                            *node,
                            format!(
                                "joint `{}` mimics `{leader}`, which is not a moving joint of this robot \
                                 (no such joint, or a fixed one)",
                                j.name
                            ),
                        ));
                    };
                    Some(UrdfGear {
                        leader: k,
                        ratio: *ratio,
                        offset: *offset,
                    })
                }
            });
        }
        let parts = UrdfParts {
            name: self.name.clone(),
            bodies: descs,
            joints: joint_descs
                .into_iter()
                .zip(gears)
                .map(|((j, desc), gear)| UrdfPartJoint {
                    desc,
                    effort: j.effort,
                    velocity: j.velocity,
                    gear,
                })
                .collect(),
            base_weld,
            no_contact,
            links: self
                .links
                .iter()
                .enumerate()
                .filter_map(|(l, link)| Some((link.name.clone(), group_body[body_of[l]]?)))
                .collect(),
            root: self.links[root].name.clone(),
            warnings,
        };
        Ok(Located {
            parts,
            body_nodes,
            joint_nodes,
        })
    }

    /// Adds the robot to `world`; on error the world is unchanged.
    fn add_to(
        &self,
        world: &mut World,
        options: UrdfOptions,
        r: &Reader<'a, 'input>,
    ) -> Result<UrdfRobot, UrdfError> {
        let Located {
            parts,
            body_nodes,
            joint_nodes,
        } = self.parts(options, world.unused_non_colliding_group(), r)?;
        // Added to a copy of the world, which replaces it only once the
        // whole robot is in. Removing what was added before a refusal would
        // not give the world back as it was: the freed slots' generations
        // and the free list would differ (the `urdf` fuzz target, a box
        // 1e-320 m thick).
        let mut trial = world.clone();
        let (ids, joint_ids) = add_parts(&mut trial, &parts, &body_nodes, &joint_nodes, r)?;
        *world = trial;
        Ok(UrdfRobot {
            name: parts.name.clone(),
            links: parts
                .links
                .iter()
                .map(|(name, &k)| (name.clone(), ids[k]))
                .collect(),
            joints: parts
                .joints
                .iter()
                .zip(&joint_ids)
                .map(|(j, &id)| {
                    (
                        j.desc.name.clone(),
                        UrdfJoint {
                            id,
                            effort: j.effort,
                            velocity: j.velocity,
                        },
                    )
                })
                .collect(),
            no_contact: parts.no_contact.iter().map(|&(a, b)| (ids[a], ids[b])).collect(),
            bodies: ids,
            root: parts.root,
            warnings: parts.warnings,
        })
    }
}

/// [`UrdfParts`] with the link element of each body and the joint element
/// of each joint.
struct Located<'a, 'input> {
    parts: UrdfParts,
    body_nodes: Vec<roxmltree::Node<'a, 'input>>,
    joint_nodes: Vec<roxmltree::Node<'a, 'input>>,
}

/// Adds `parts` to `world` (bodies, joints, the base's weld, the pairs kept
/// apart), the world's
/// refusals located at the link or joint element; the bodies' and the
/// joints' handles. On error, part of the robot may be in `world`.
fn add_parts(
    world: &mut World,
    parts: &UrdfParts,
    body_nodes: &[roxmltree::Node],
    joint_nodes: &[roxmltree::Node],
    r: &Reader,
) -> Result<(Vec<BodyId>, Vec<JointId>), UrdfError> {
    let mut ids: Vec<BodyId> = Vec::with_capacity(parts.bodies.len());
    for (desc, node) in parts.bodies.iter().zip(body_nodes) {
        ids.push(
            world
                .add_body(desc)
                .map_err(|e| r.err(*node, world_message(&e)))?,
        );
    }
    let mut joint_ids = Vec::with_capacity(parts.joints.len());
    for (j, node) in parts.joints.iter().zip(joint_nodes) {
        let id = world
            .add_joint(&j.desc.clone().with_bodies(|k| ids[k]))
            .map_err(|e| r.err(*node, world_message(&e)))?;
        joint_ids.push(id);
    }
    for ((j, node), &id) in parts.joints.iter().zip(joint_nodes).zip(&joint_ids) {
        if let Some(g) = j.gear {
            let gear = Gear::new(joint_ids[g.leader], g.ratio).with_offset(g.offset);
            world
                .set_joint_gear(id, Some(gear))
                .map_err(|e| r.err(*node, world_message(&e)))?;
        }
    }
    if let Some(weld) = &parts.base_weld {
        world
            .add_joint(&weld.clone().with_bodies(|k| ids[k]))
            .map_err(|e| r.err(body_nodes[weld.body_a], world_message(&e)))?;
    }
    for &(a, b) in &parts.no_contact {
        world
            .set_contacts_between(ids[a], ids[b], false)
            .map_err(|e| r.err(body_nodes[a], world_message(&e)))?;
    }
    Ok((ids, joint_ids))
}

/// The pairs of `bodies` (indices, the lower first, in order) that no pair
/// of `linked` names and whose shapes overlap where their descriptions
/// place them. A robot's links that overlap in the file's pose were never
/// meant to touch (the links of files written for other engines overlap
/// beyond their joints: a KUKA LWR's fifth and seventh links); held
/// together by the joints between them, their contacts squeeze against rows
/// that lock every way out, and such robots blew apart (KUKA's LWR, Vision
/// 60 and MuJoCo's humanoid in PyBullet's data set). MoveIt's setup
/// assistant switches off the pairs "in collision by default" the same way.
/// A pair with a triangle mesh counts as overlapping within the skin the
/// world keeps meshes apart by (twice the default allowed penetration, as
/// the narrow stage offsets them): nearer, it would be pushed apart at the
/// first step. (A mesh is a surface: a link wholly inside another's mesh
/// makes no contact here, and is not kept apart.)
fn overlapping_pairs(bodies: &[BodyDesc], linked: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let skin = 2.0 * WorldSettings::default().allowed_penetration;
    let shapes: Vec<Vec<(&Shape, Pose)>> = bodies
        .iter()
        .map(|b| {
            b.shapes
                .iter()
                .filter(|s| !matches!(s.shape, Shape::HalfSpace(_)))
                .map(|s| (&s.shape, b.pose.mul_pose(&s.local_pose)))
                .collect()
        })
        .collect();
    let mut buffer = Vec::new();
    let mut pairs = Vec::new();
    for a in 0..bodies.len() {
        for b in a + 1..bodies.len() {
            if linked.contains(&(a, b)) {
                continue;
            }
            let overlap = shapes[a].iter().any(|(sa, pa)| {
                shapes[b].iter().any(|(sb, pb)| {
                    let mesh = matches!(sa, Shape::Mesh(_)) || matches!(sb, Shape::Mesh(_));
                    let within = if mesh { skin } else { 0.0 };
                    buffer.clear();
                    // (A pair the narrow phase cannot answer is left to touch.)
                    contact_shapes(sa, pa, sb, pb, within, &mut buffer).is_ok()
                        && buffer.iter().any(|c| c.distance < within)
                })
            });
            if overlap {
                pairs.push((a, b));
            }
        }
    }
    pairs
}

fn world_message(e: &WorldError) -> String {
    e.to_string()
}
