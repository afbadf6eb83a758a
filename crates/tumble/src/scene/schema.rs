//! The scene file schema: the serde types a TOML or JSON scene file
//! deserializes into, before any value is checked. Every struct denies
//! unknown keys, so a misspelt key is an error and never silently ignored.
//! The doc comments double as the descriptions of `docs/scene.schema.json`
//! (generated from these types by [`super::json_schema`]).
//!
//! Conventions: SI units (m, kg, s), z up, quaternions `[x, y, z, w]`, angular
//! velocity in the world frame, angles of `rotation` in degrees.
//! Fields are declared one by one (optional, with their unit in the doc,
//! which is the JSON schema's description): runs of them look alike by
//! design (as `BodySpec`'s `friction` to `ccd`): each key keeps its doc,
//! unit and `#[serde(default)]` beside it, where a reader of the format
//! looks the key up.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::Deserialize;

use crate::joint::{JointKind, Motor, Spring};
use crate::world::{MaterialDesc, WorldSettings};

/// A scene: world settings, named materials and shapes, and the bodies.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// JSON files may name their schema here (ignored).
    #[serde(rename = "$schema", default)]
    pub schema: Option<String>,
    /// Scene name (used for output files and reports). Default: the file name
    /// without extension.
    #[serde(default)]
    pub name: Option<String>,
    /// Free text for the reader of the file (not used by tumble).
    #[serde(default)]
    pub description: Option<String>,
    /// Number of steps `tumble run` takes. At most one of `steps` and
    /// `duration`; default 10 s of simulated time.
    #[serde(default)]
    pub steps: Option<u64>,
    /// Simulated time (s) `tumble run` covers: `round(duration / dt)` steps.
    #[serde(default)]
    pub duration: Option<f64>,
    /// World settings; every field optional, with the library's defaults.
    #[serde(default)]
    pub settings: WorldSettings,
    /// Named surface materials, referenced by bodies' `material`. A material
    /// named `default` applies to bodies that name none (otherwise friction
    /// 0.5, restitution 0).
    #[serde(default)]
    pub materials: BTreeMap<String, MaterialDesc>,
    /// Named shapes, referenced by bodies' `shape` and by `grid.alternate_shapes`.
    #[serde(default)]
    pub shapes: BTreeMap<String, ShapeSpec>,
    /// The bodies, added to the world in this order (a `grid` entry adds its
    /// copies in place).
    #[serde(default)]
    pub bodies: Vec<BodySpec>,
    /// Robots read from URDF files, added after the bodies in this order
    /// (their links' bodies named `ROBOT/LINK`, so that `joints` can name
    /// them).
    #[serde(default)]
    pub robots: Vec<RobotSpec>,
    /// Joints between bodies (or a body and the world), added after the
    /// bodies and the robots in this order.
    #[serde(default)]
    pub joints: Vec<JointSpec>,
    /// Pairs of bodies that never touch (`World::set_contacts_between`),
    /// named as `joints` names them.
    #[serde(default)]
    pub no_contact: Vec<NoContactSpec>,
}

/// Two bodies that never touch each other (they still touch the rest).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NoContactSpec {
    /// The names of the two bodies (after grid expansion, robots' links as
    /// `ROBOT/LINK`).
    pub bodies: [String; 2],
}

/// A robot from a URDF file (`tumble::joint::urdf`: what is read, and how
/// files written for other engines are read).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// The URDF file, relative to the scene file.
    pub file: String,
    /// Prefix of its bodies' names: `NAME/LINK` (links merged by fixed
    /// joints: `NAME/LINK+LINK`) and of its joints' names. Default: the
    /// robot's name in the file.
    #[serde(default)]
    pub name: Option<String>,
    /// World position of the root link's frame (m). Default [0, 0, 0].
    #[serde(default)]
    pub position: Option<[f64; 3]>,
    /// Orientation of the root link's frame as a unit quaternion [x, y, z,
    /// w]. At most one of `orientation` and `rotation`; default identity.
    #[serde(default)]
    pub orientation: Option<[f64; 4]>,
    /// Orientation as a product of rotations in degrees, as a body's.
    #[serde(default)]
    pub rotation: Option<Vec<RotationSpec>>,
    /// Weld the root link to the world. Default false.
    #[serde(default)]
    pub fixed_base: bool,
    /// Let the robot's links touch each other, except links that overlap
    /// in the file's pose. Default false (they share a non-colliding group
    /// of their own, as in PyBullet).
    #[serde(default)]
    pub self_collision: bool,
    /// Replace an inertia no body could have by the isotropic one of the
    /// same trace (MuJoCo's `balanceinertia`). Default false: refused.
    #[serde(default)]
    pub balance_inertia: bool,
    /// Each `<mesh>` link shape as its convex hull (as PyBullet and MuJoCo
    /// read them). Default false: the exact triangle mesh.
    #[serde(default)]
    pub convex_meshes: bool,
    /// Motors of the robot's joints by the file's joint names (`shoulder =
    /// { type = "position", target = 0.5, stiffness = 4000.0, damping =
    /// 200.0, max_force = 150.0 }`), beside the joint's `<dynamics damping>`
    /// (a damper) and `<dynamics friction>` (its Coulomb friction); a
    /// `spherical` joint's `angular_velocity` or `orientation` motor has its
    /// vector target in the file's axes (turned with the robot's placement).
    /// Default none.
    #[serde(default)]
    pub motors: BTreeMap<String, Motor>,
}

/// A joint: its anchor and axis in world coordinates as the bodies are
/// placed in the file; that pose is the joint's zero (angle 0, offset 0).
/// Angles in radians here (as in the Rust and Python APIs).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Name (reports, viewer). Default empty.
    #[serde(default)]
    pub name: String,
    /// `fixed`, `ball`, `hinge`, `slider` or `distance`.
    pub kind: JointKind,
    /// Name of the first body (after grid expansion, e.g. `link3`).
    pub body_a: String,
    /// Name of the second body; omit it to joint `body_a` to the world.
    #[serde(default)]
    pub body_b: Option<String>,
    /// Anchor point (m, world). On a distance joint, the anchor on body A.
    pub anchor: [f64; 3],
    /// Distance joint: the anchor on body B (m, world). Default `anchor`.
    #[serde(default)]
    pub anchor_b: Option<[f64; 3]>,
    /// Joint axis (world; any non-zero length): hinge rotation axis, slider
    /// direction, ball cone axis. Default [0, 0, 1].
    #[serde(default)]
    pub axis: Option<[f64; 3]>,
    /// Limits `[lower, upper]`: rad (hinge angle, ball twist, within
    /// [-pi, pi]) or m (slider offset, distance).
    #[serde(default)]
    pub limits: Option<[f64; 2]>,
    /// Ball joint: half-angle of the swing cone about the axis (rad).
    #[serde(default)]
    pub swing_limit: Option<f64>,
    /// Hinge or slider motor: `{ type = "velocity", target, max_force }` or
    /// `{ type = "position", target, stiffness, damping, max_force }`; ball
    /// joint: `{ type = "angular_velocity", target = [x, y, z], max_force }`
    /// (rad/s) or `{ type = "orientation", target = [x, y, z], stiffness,
    /// damping, max_force }` (a rotation vector, rad), world axes at
    /// creation, A turned relative to B.
    #[serde(default)]
    pub motor: Option<Motor>,
    /// Spring-damper: `{ stiffness, damping }`. Distance joint: N/m and
    /// N s/m, towards `length`; hinge: N m/rad and N m s/rad, slider: N/m
    /// and N s/m, towards the position at creation, beside the motor; ball
    /// joint: N m/rad and N m s/rad about every axis, towards the relative
    /// orientation at creation.
    #[serde(default)]
    pub spring: Option<Spring>,
    /// Distance joint rest length (m). Default: the anchors' distance.
    #[serde(default)]
    pub length: Option<f64>,
    /// Coulomb friction on the joint's coordinate (N m on a hinge or ball
    /// joint, whichever way a ball turns; N on a slider or distance joint;
    /// >= 0), beside the motor and spring. Not on a weld or a rod.
    #[serde(default)]
    pub friction: Option<f64>,
    /// Contacts between the two bodies (default false).
    #[serde(default)]
    pub collide_connected: bool,
    /// Hinge or slider: hold this joint's coordinate at a ratio of another
    /// joint's, `{ leader = "joint name", ratio, offset }` (a gear pair, a
    /// rack and pinion; a robot's joints are named `robot/joint`).
    #[serde(default)]
    pub gear: Option<GearSpec>,
}

/// A joint's gear: its coordinate (rad or m) held at `ratio` times the
/// leader's plus `offset`, both measured from the joints' creation.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GearSpec {
    /// Name of the joint followed (a hinge or slider of this scene).
    pub leader: String,
    /// Follower coordinate per unit of the leader's (rad/rad, m/rad, rad/m
    /// or m/m; negative turns the other way).
    pub ratio: f64,
    /// The follower's coordinate where the leader's is 0 (rad or m).
    /// Default 0.
    #[serde(default)]
    pub offset: f64,
}

/// How a body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum KindSpec {
    /// Finite mass: moved by gravity, forces and contacts.
    #[default]
    Dynamic,
    /// Never moves (infinite mass).
    Static,
    /// Moves with its constant `linear_velocity` / `angular_velocity`, pushes
    /// dynamic bodies, is never pushed.
    Kinematic,
}

/// A body's given inertia (kg m^2): its diagonal, or the whole matrix.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum InertiaSpec {
    /// `[Ixx, Iyy, Izz]`: principal moments along the model axes.
    Diagonal([f64; 3]),
    /// `[[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]]`: symmetric.
    Matrix([[f64; 3]; 3]),
}

/// One body (or, with `grid`, a block of identical bodies).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name (exports, reports). With `grid`, `{i}`, `{j}`, `{k}` (grid
    /// indices) and `{n}` (copy number) are replaced. Default empty.
    #[serde(default)]
    pub name: String,
    /// `dynamic` (default), `static` or `kinematic`.
    #[serde(default)]
    pub kind: KindSpec,
    /// Name of a shape in the top-level `shapes` table. At most one of
    /// `shape`, `shapes` and `grid.alternate_shapes`; none for a body
    /// without shapes, which touches nothing (a kinematic body, or a
    /// dynamic one with `mass` and `inertia`).
    #[serde(default)]
    pub shape: Option<String>,
    /// The body's shapes, each with its optional `local_pose`.
    #[serde(default)]
    pub shapes: Option<Vec<ShapeSpec>>,
    /// Total mass (kg, > 0), dynamic bodies only. At most one of `mass` and
    /// `density`; default density 1000 kg/m^3.
    #[serde(default)]
    pub mass: Option<f64>,
    /// Uniform density (kg/m^3, > 0), dynamic bodies only. Mass, centre of
    /// mass and inertia follow from the geometry (meshes must be closed).
    #[serde(default)]
    pub density: Option<f64>,
    /// Inertia about the centre of mass in the model frame (kg m^2), with
    /// `mass`: three numbers (a diagonal) or a symmetric 3x3 matrix (rows).
    /// The mass properties are then given outright (as a URDF `<inertial>`)
    /// and the shapes only collide. Dynamic bodies only.
    #[serde(default)]
    pub inertia: Option<InertiaSpec>,
    /// With `inertia`: the centre of mass in the model frame (m). Default
    /// [0, 0, 0].
    #[serde(default)]
    pub center_of_mass: Option<[f64; 3]>,
    /// Name of a material in the top-level `materials` table.
    #[serde(default)]
    pub material: Option<String>,
    /// Coulomb friction coefficient (>= 0), replacing the material's.
    #[serde(default)]
    pub friction: Option<f64>,
    /// Coefficient of restitution (in [0, 1]), replacing the material's.
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Position of the body's model frame (m). Default [0, 0, 0].
    #[serde(default)]
    pub position: Option<[f64; 3]>,
    /// Orientation as a unit quaternion [x, y, z, w]. At most one of
    /// `orientation` and `rotation`; default identity.
    #[serde(default)]
    pub orientation: Option<[f64; 4]>,
    /// Orientation as a product of rotations in degrees, written as in the
    /// formula `Ry(60) * Rx(90)`: `[{ y = 60 }, { x = 90 }]` (the last one is
    /// applied first).
    #[serde(default)]
    pub rotation: Option<Vec<RotationSpec>>,
    /// Linear velocity of the centre of mass (m/s). Default zero.
    #[serde(default)]
    pub linear_velocity: Option<[f64; 3]>,
    /// Angular velocity, world frame (rad/s). Default zero.
    #[serde(default)]
    pub angular_velocity: Option<[f64; 3]>,
    /// Linear damping (1/s, >= 0). Default 0.
    #[serde(default)]
    pub linear_damping: Option<f64>,
    /// Angular damping (1/s, >= 0). Default 0.
    #[serde(default)]
    pub angular_damping: Option<f64>,
    /// A bullet: always swept by continuous collision, against dynamic
    /// bodies too (fast bodies are swept against static and kinematic ones
    /// anyway). Default false.
    #[serde(default)]
    pub ccd: Option<bool>,
    /// Bodies that share a nonzero group never touch each other (they still
    /// touch every other body). Default 0: no group.
    #[serde(default)]
    pub non_colliding_group: Option<u32>,
    /// Force (N, world frame) at the centre of mass during the first step
    /// only: an initial push. Dynamic bodies only.
    #[serde(default)]
    pub initial_force: Option<[f64; 3]>,
    /// Torque (N m, world frame) during the first step only. Dynamic bodies only.
    #[serde(default)]
    pub initial_torque: Option<[f64; 3]>,
    /// Repeat this body on a regular grid.
    #[serde(default)]
    pub grid: Option<GridSpec>,
}

/// A block of copies of one body: copy (i, j, k) sits at
/// `position + (i dx, j dy, k dz)`, plus `odd_layer_offset` when k is odd.
/// Copies are added with k outermost, then j, then i.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Copies along x, y and z (each >= 1).
    pub count: [u32; 3],
    /// Distance between neighbouring copies along x, y and z (m).
    pub spacing: [f64; 3],
    /// Added to the position of copies in odd z layers (m), for staggered
    /// piles. Default zero.
    #[serde(default)]
    pub odd_layer_offset: Option<[f64; 3]>,
    /// Names of shapes (top-level `shapes`) used in turn: copy (i, j, k) gets
    /// `alternate_shapes[(i + j + k) % len]`. Replaces the body's `shape`.
    #[serde(default)]
    pub alternate_shapes: Option<Vec<String>>,
}

/// One rotation of a `rotation` product: exactly one of `x`, `y`, `z`
/// (degrees about that world axis) or `axis` with `angle`.
#[derive(Debug, Clone, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RotationSpec {
    /// Degrees about the x axis.
    #[serde(default)]
    pub x: Option<f64>,
    /// Degrees about the y axis.
    #[serde(default)]
    pub y: Option<f64>,
    /// Degrees about the z axis.
    #[serde(default)]
    pub z: Option<f64>,
    /// Axis (any length > 0) for `angle`.
    #[serde(default)]
    pub axis: Option<[f64; 3]>,
    /// Degrees about `axis`.
    #[serde(default)]
    pub angle: Option<f64>,
}

/// Pose of a shape in its body's model frame.
#[derive(Debug, Clone, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    /// Position (m). Default [0, 0, 0].
    #[serde(default)]
    pub position: Option<[f64; 3]>,
    /// Unit quaternion [x, y, z, w]. At most one of `orientation` and `rotation`.
    #[serde(default)]
    pub orientation: Option<[f64; 4]>,
    /// Product of rotations in degrees, as for bodies.
    #[serde(default)]
    pub rotation: Option<Vec<RotationSpec>>,
}

/// A shape, chosen by `type`.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A ball centred on the shape origin.
    Sphere {
        /// Radius (m, > 0).
        radius: f64,
        /// Pose in the body's model frame. Default identity.
        #[serde(default)]
        local_pose: PoseSpec,
    },
    /// A box centred on the shape origin (`cuboid` is accepted too).
    #[serde(alias = "cuboid")]
    Box {
        /// Half extents along x, y, z (m, each > 0).
        half_extents: [f64; 3],
        /// Pose in the body's model frame. Default identity.
        #[serde(default)]
        local_pose: PoseSpec,
    },
    /// A capsule along the z axis: a segment from -half_height to
    /// +half_height swept by a ball.
    Capsule {
        /// Radius (m, > 0).
        radius: f64,
        /// Half length of the inner segment (m, >= 0).
        half_height: f64,
        /// Pose in the body's model frame. Default identity.
        #[serde(default)]
        local_pose: PoseSpec,
    },
    /// The convex hull of `points` or of a mesh's vertices (exactly one).
    ConvexHull {
        /// Points (m).
        #[serde(default)]
        points: Option<Vec<[f64; 3]>>,
        /// A mesh whose vertices are hulled.
        #[serde(default)]
        mesh: Option<MeshSource>,
        /// Pose in the body's model frame. Default identity.
        #[serde(default)]
        local_pose: PoseSpec,
    },
    /// The solid below a plane: points p with `normal . p <= offset`.
    /// Static bodies only (infinite volume).
    HalfSpace {
        /// Outward normal (any length > 0). Default [0, 0, 1].
        #[serde(default)]
        normal: Option<[f64; 3]>,
        /// Plane offset along the unit normal (m). Default 0.
        #[serde(default)]
        offset: Option<f64>,
        /// Pose in the body's model frame. Default identity.
        #[serde(default)]
        local_pose: PoseSpec,
    },
    /// A triangle mesh (concave allowed) with exact mesh contact. For mass
    /// from density the mesh must be closed and wound outwards.
    Mesh {
        /// Where the triangles come from.
        mesh: MeshSource,
        /// Spheres and capsules touch the smooth surface the mesh
        /// tessellates instead of its facets, blended across every edge
        /// whose faces meet at no more than this (degrees, in (0, 180); 30
        /// blends a tessellated bowl and keeps a box's edges sharp). A ball
        /// then rolls in a faceted bowl as in a smooth one. Default: none,
        /// the facets as they are.
        #[serde(default)]
        crease_angle_deg: Option<f64>,
        /// Pose in the body's model frame. Default identity.
        #[serde(default)]
        local_pose: PoseSpec,
    },
}

/// A triangle mesh: exactly one of a file or a generator.
#[derive(Debug, Clone, Default, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MeshSource {
    /// OBJ or STL file, relative to the scene file's directory.
    #[serde(default)]
    pub file: Option<String>,
    /// A box with 12 triangles.
    #[serde(default, rename = "box")]
    pub box_: Option<BoxMesh>,
    /// A UV sphere.
    #[serde(default)]
    pub sphere: Option<SphereMesh>,
    /// A subdivided icosahedron.
    #[serde(default)]
    pub icosphere: Option<IcosphereMesh>,
    /// A closed cylinder along z.
    #[serde(default)]
    pub cylinder: Option<CylinderMesh>,
    /// A capsule along z.
    #[serde(default)]
    pub capsule: Option<CapsuleMesh>,
    /// A cone along z: base at z = -height/2, apex at +height/2.
    #[serde(default)]
    pub cone: Option<ConeMesh>,
    /// A torus around z (shared/scenes.md `torus_mesh`).
    #[serde(default)]
    pub torus: Option<TorusMesh>,
    /// A hemispherical bowl, open at the top, placed by its sphere's centre.
    #[serde(default)]
    pub bowl: Option<BowlMesh>,
    /// A half-pipe along x, open at the top, placed by its cylinder's axis.
    #[serde(default)]
    pub half_pipe: Option<HalfPipeMesh>,
}

/// Box mesh generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BoxMesh {
    /// Half extents (m, each > 0).
    pub half_extents: [f64; 3],
}

/// UV sphere generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SphereMesh {
    /// Radius (m, > 0).
    pub radius: f64,
    /// Segments around z. Default 32.
    #[serde(default)]
    pub segments: Option<usize>,
    /// Rings from pole to pole. Default segments / 2.
    #[serde(default)]
    pub rings: Option<usize>,
}

/// Icosphere generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IcosphereMesh {
    /// Radius (m, > 0).
    pub radius: f64,
    /// Subdivisions of the icosahedron (20 * 4^s triangles). Default 3.
    #[serde(default)]
    pub subdivisions: Option<usize>,
}

/// Cylinder generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CylinderMesh {
    /// Radius (m, > 0).
    pub radius: f64,
    /// Half height (m, > 0).
    pub half_height: f64,
    /// Segments around z. Default 32.
    #[serde(default)]
    pub segments: Option<usize>,
}

/// Capsule mesh generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CapsuleMesh {
    /// Radius (m, > 0).
    pub radius: f64,
    /// Half length of the inner segment (m, >= 0).
    pub half_height: f64,
    /// Segments around z. Default 32.
    #[serde(default)]
    pub segments: Option<usize>,
    /// Rings per hemisphere. Default segments / 4.
    #[serde(default)]
    pub rings: Option<usize>,
}

/// Cone generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConeMesh {
    /// Base radius (m, > 0).
    pub radius: f64,
    /// Height (m, > 0).
    pub height: f64,
    /// Segments around z. Default 32.
    #[serde(default)]
    pub segments: Option<usize>,
}

/// Bowl generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BowlMesh {
    /// Radius of the sphere its inside is half of (m, > 0).
    pub inner_radius: f64,
    /// Wall thickness (m, > 0).
    pub thickness: f64,
    /// Facets around z. Default 96.
    #[serde(default)]
    pub segments: Option<usize>,
    /// Facets from the rim to the bottom. Default segments / 2.
    #[serde(default)]
    pub rings: Option<usize>,
}

/// Half-pipe generator.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HalfPipeMesh {
    /// Radius of the cylinder its inside is half of (m, > 0).
    pub inner_radius: f64,
    /// Wall thickness (m, > 0).
    pub thickness: f64,
    /// Length along x (m, > 0).
    pub length: f64,
    /// Facets across the trough. Default 64.
    #[serde(default)]
    pub segments: Option<usize>,
}

/// Torus generator (vertex and triangle order as in shared/scenes.md).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TorusMesh {
    /// Major radius R: centre of the tube to the axis (m, > minor_radius).
    pub major_radius: f64,
    /// Minor radius r of the tube (m, > 0).
    pub minor_radius: f64,
    /// Segments around the axis. Default 50.
    #[serde(default)]
    pub n_major: Option<usize>,
    /// Segments around the tube. Default 50.
    #[serde(default)]
    pub n_minor: Option<usize>,
}
