//! URDF robots: a `<robot>` file read into bodies and joints of a world.
//!
//! What is read (the ROS URDF specification): `<link>` with `<inertial>`
//! (origin, mass, inertia), `<collision>` geometry (box, cylinder, sphere,
//! mesh STL/OBJ relative to the file, with scale; `<visual>` geometry when a
//! link has no collision), and `<joint>` of type revolute, continuous,
//! prismatic and fixed with origin, axis, `<limit lower upper effort
//! velocity>` and `<dynamics damping>`. Links joined by fixed joints are
//! merged into one body (their shapes and inertia combined, as PyBullet and
//! MuJoCo do); every other joint becomes a hinge (revolute, continuous) or
//! slider (prismatic) from the parent link to the child link, its angle 0
//! at the file's zero configuration. Joint `damping` becomes a damping
//! motor (`Motor::Position` with stiffness 0) until another motor is set;
//! `effort` is kept as the joint's largest motor force for the caller.
//!
//! Errors name the file, line, column and element (`arm.urdf:12:5: <joint
//! name="elbow">: ...`). Nothing is added to the world unless the whole
//! robot is.

use crate::joint::{JointDesc, JointId, JointKind, Motor};
use crate::world::{BodyDesc, BodyId, MassDesc, ShapeDesc, World, WorldError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tumble_collide::mass::MassProperties;
use tumble_collide::mesh::load_mesh;
use tumble_collide::shape::{ConvexHull, Cuboid, MeshShape, Shape, Sphere};
use tumble_collide::{DMat3, DQuat, DVec3, Pose};

/// Segments of the convex hull that stands for a URDF cylinder.
pub const CYLINDER_SEGMENTS: usize = 24;

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
}

impl Default for UrdfOptions {
    fn default() -> Self {
        UrdfOptions {
            position: DVec3::ZERO,
            orientation: DQuat::IDENTITY,
            fixed_base: false,
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
    /// Every link's body (links merged by fixed joints share one).
    pub links: BTreeMap<String, BodyId>,
    /// The robot's bodies in the order they were added (root first).
    pub bodies: Vec<BodyId>,
    /// Every non-fixed joint, by name.
    pub joints: BTreeMap<String, UrdfJoint>,
    /// The root link.
    pub root: String,
    /// What was read but not used (limits beyond what a hinge measures, ...).
    pub warnings: Vec<String>,
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
    let text = std::fs::read_to_string(path).map_err(|e| UrdfError::Read {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    add_urdf(world, &text, path, options)
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
    let reader = Reader { doc: &doc, file };
    let model = reader.model()?;
    model.add_to(world, options, &reader)
}

/// The parsed file.
struct Reader<'a, 'input> {
    doc: &'a roxmltree::Document<'input>,
    file: &'a Path,
}

struct Link<'a, 'input> {
    node: roxmltree::Node<'a, 'input>,
    name: String,
    inertial: Option<MassProperties>,
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
}

struct Model<'a, 'input> {
    name: String,
    links: Vec<Link<'a, 'input>>,
    joints: Vec<Joint<'a, 'input>>,
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

    /// The shape of a `<geometry>` element.
    fn geometry(&self, g: roxmltree::Node) -> Result<Shape, UrdfError> {
        let Some(shape) = g.children().find(|c| c.is_element()) else {
            return Err(self.err(g, "needs one of <box>, <cylinder>, <sphere>, <mesh>"));
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
                let relative = name.strip_prefix("file://").unwrap_or(name);
                if relative.contains("://") {
                    return Err(self.err(
                        shape,
                        format!("`{name}`: only files relative to the URDF (or file://) can be found, not ROS packages"),
                    ));
                }
                let path = self.file.parent().unwrap_or(Path::new("")).join(relative);
                let mut mesh =
                    load_mesh(&path).map_err(|e| self.err(shape, format!("{}: {e}", path.display())))?;
                if shape.attribute("scale").is_some() {
                    let s = self.numbers(shape, "scale", 3)?;
                    let scale = DVec3::new(s[0], s[1], s[2]);
                    let vertices: Vec<DVec3> = mesh.vertices().iter().map(|&v| v * scale).collect();
                    mesh = tumble_collide::mesh::TriMesh::new(vertices, mesh.triangles().to_vec())
                        .map_err(|e| bad(&e))?;
                }
                Ok(MeshShape::new(mesh).map_err(|e| bad(&e))?.into())
            }
            other => Err(self.err(
                shape,
                format!("unknown geometry <{other}> (box, cylinder, sphere or mesh)"),
            )),
        }
    }

    fn link(&self, node: roxmltree::Node<'a, 'input>) -> Result<Link<'a, 'input>, UrdfError> {
        let name = self.attr(node, "name")?.to_string();
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
                let [ixx, ixy, ixz, iyy, iyz, izz] =
                    ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"].map(|k| self.optional_number(t, k, f64::NAN));
                let (ixx, ixy, ixz, iyy, iyz, izz) = (ixx?, ixy?, ixz?, iyy?, iyz?, izz?);
                let inertia = DMat3::from_cols(
                    DVec3::new(ixx, ixy, ixz),
                    DVec3::new(ixy, iyy, iyz),
                    DVec3::new(ixz, iyz, izz),
                );
                // The tensor is given in the inertial origin's frame.
                let r = DMat3::from_quat(origin.rotation);
                let p = MassProperties::new(mass, origin.position, r * inertia * r.transpose())
                    .map_err(|e| self.err(i, format!("mass {mass} kg, inertia: {e}")))?;
                Some(p)
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
                other => {
                    return Err(self.err(
                        node,
                        format!(
                            "joint type `{other}` is not supported (revolute, continuous, prismatic, fixed)"
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
            let axis = match self.child(node, "axis") {
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
                    if lo > hi {
                        return Err(self.err(l, format!("lower {lo} > upper {hi}")));
                    }
                    limits = Some([lo, hi]);
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
            let damping = match self.child(node, "dynamics") {
                Some(d) => self.optional_number(d, "damping", 0.0)?,
                None => 0.0,
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
            });
        }
        Ok(Model { name, links, joints })
    }
}

impl Model<'_, '_> {
    fn add_to(&self, world: &mut World, options: UrdfOptions, r: &Reader) -> Result<UrdfRobot, UrdfError> {
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
        let mut descs = Vec::with_capacity(groups.len());
        for (g, &head_link) in groups.iter().enumerate() {
            let frame = pose[head_link].expect("placed");
            let inv = frame.inverse();
            let mut shapes = Vec::new();
            let mut parts = Vec::new();
            let mut names = Vec::new();
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
            }
            let link = &self.links[head_link];
            if shapes.is_empty() {
                return Err(r.err(
                    link.node,
                    "has no collision or visual geometry (a body needs a shape; join it with a fixed joint to one that has)",
                ));
            }
            let mass = if parts.is_empty() {
                MassDesc::default()
            } else {
                MassDesc::Inertial(
                    MassProperties::combine(&parts).map_err(|e| r.err(link.node, format!("inertia: {e}")))?,
                )
            };
            descs.push(BodyDesc {
                shapes,
                mass,
                pose: frame,
                name: names.join("+"),
                ..BodyDesc::default()
            });
        }
        let mut warnings = Vec::new();
        let mut joint_descs = Vec::new();
        for j in self.joints.iter().filter(|j| j.kind != "fixed") {
            let frame = pose[j.child].expect("placed");
            let axis = frame.rotation * j.axis;
            let (kind, mut limits) = match j.kind {
                "prismatic" => (JointKind::Slider, j.limits),
                "revolute" => (JointKind::Hinge, j.limits),
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
            let mut desc = JointDesc::new(
                kind,
                body_of[j.child],
                Some(body_of[j.parent]),
                frame.position,
                axis,
            )
            .named(j.name.clone());
            desc.limits = limits;
            if j.damping > 0.0 {
                desc.motor = Some(Motor::Position {
                    target: 0.0,
                    stiffness: 0.0,
                    damping: j.damping,
                    max_force: j.effort,
                });
            }
            desc.validate().map_err(|e| r.err(j.node, e.to_string()))?;
            joint_descs.push((j, desc));
        }
        // Everything checked: added to a copy of the world, which replaces
        // it only once the whole robot is in. Removing what was added
        // before a refusal would not give the world back as it was: the
        // freed slots' generations and the free list would differ
        // (the `urdf` fuzz target, a box 1e-320 m thick).
        let mut trial = world.clone();
        let mut ids: Vec<BodyId> = Vec::with_capacity(descs.len());
        for (g, desc) in descs.iter().enumerate() {
            let id = trial
                .add_body(desc)
                .map_err(|e| r.err(self.links[groups[g]].node, world_message(&e)))?;
            ids.push(id);
        }
        let mut joints = BTreeMap::new();
        for (j, desc) in &joint_descs {
            let id = trial
                .add_joint(&desc.clone().with_bodies(|g| ids[g]))
                .map_err(|e| r.err(j.node, world_message(&e)))?;
            joints.insert(
                j.name.clone(),
                UrdfJoint {
                    id,
                    effort: j.effort,
                    velocity: j.velocity,
                },
            );
        }
        if options.fixed_base {
            let frame = pose[root].expect("placed");
            trial
                .add_joint(&JointDesc::fixed(ids[body_of[root]], None, frame.position))
                .map_err(|e| r.err(self.links[root].node, world_message(&e)))?;
        }
        *world = trial;
        Ok(UrdfRobot {
            name: self.name.clone(),
            links: self
                .links
                .iter()
                .enumerate()
                .map(|(l, link)| (link.name.clone(), ids[body_of[l]]))
                .collect(),
            joints,
            bodies: ids.clone(),
            root: self.links[root].name.clone(),
            warnings,
        })
    }
}

fn world_message(e: &WorldError) -> String {
    e.to_string()
}
