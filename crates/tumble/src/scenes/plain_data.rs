//! A scene as plain data for other engines: the one description the
//! benchmark's peers (Rapier in Rust, PyBullet and MuJoCo in Python) build
//! their worlds from, so that each standard scene is defined once, here.
//!
//! Every body is given in its *body frame* (centre of mass, principal
//! axes), with the mass and principal inertia tumble computed for it and
//! its shapes posed in that frame: a peer then simulates exactly the
//! masses, inertias and geometry tumble does, whatever its own mass
//! properties code would make of a mesh. The JSON form is what
//! `tumble bench --scene S --export-scene FILE` writes (format
//! [`PLAIN_SCENE_FORMAT`]).

use super::Scene;
use crate::body::BodyKind;
use crate::world::WorldError;
use serde_json::{json, Value};
use tumble_collide::shape::Shape;
use tumble_collide::{DQuat, DVec3, Pose};

/// The `format` field of the JSON form; bumped when a field changes meaning.
pub const PLAIN_SCENE_FORMAT: &str = "tumble-plain-scene/1";

/// Largest |x| or |y| of a pile body's centre that still counts as inside
/// the container (m): the walls' inner faces stand at 3 m, and scenes.md
/// allows 1 cm.
pub const PILE_INSIDE_HALF_WIDTH: f64 = 3.01;

/// The chain holds while adjacent link centres stay within this distance
/// (m): 2R - 2r + 0.2 for the links of radii (1, 0.2) (scenes.md).
pub const CHAIN_MAX_CENTRE_DISTANCE: f64 = 1.8;

/// Centres outside the pile's container: beyond [`PILE_INSIDE_HALF_WIDTH`]
/// in x or y, below the floor's top (z < 0), or not finite.
pub fn pile_outside(centres: &[DVec3]) -> usize {
    centres
        .iter()
        .filter(|c| {
            !c.is_finite()
                || c.x.abs() > PILE_INSIDE_HALF_WIDTH
                || c.y.abs() > PILE_INSIDE_HALF_WIDTH
                || c.z < 0.0
        })
        .count()
}

/// One shape of a [`PlainBody`], posed in the body frame.
#[derive(Debug, Clone)]
pub struct PlainShape {
    /// The geometry (shared with tumble's own collider).
    pub shape: Shape,
    /// Pose in the body frame.
    pub local: Pose,
}

/// A body in its body frame, with tumble's mass properties.
#[derive(Debug, Clone)]
pub struct PlainBody {
    /// Name from the scene.
    pub name: String,
    /// Dynamic, static or kinematic.
    pub kind: BodyKind,
    /// Pose of the body frame (centre of mass, principal axes) in the world.
    pub pose: Pose,
    /// Linear velocity of the centre of mass (m/s).
    pub linear_velocity: DVec3,
    /// Angular velocity, world frame (rad/s).
    pub angular_velocity: DVec3,
    /// Mass (kg); 0 for static and kinematic bodies.
    pub mass: f64,
    /// Principal moments of inertia about the body axes (kg m^2); 0 for
    /// static and kinematic bodies.
    pub principal_inertia: DVec3,
    /// Coulomb friction (tumble combines a pair by the geometric mean).
    pub friction: f64,
    /// Restitution (tumble combines a pair by the maximum).
    pub restitution: f64,
    /// Shapes in the body frame.
    pub shapes: Vec<PlainShape>,
}

/// A scene resolved into [`PlainBody`]s: what another engine needs to run
/// the same work.
#[derive(Debug, Clone)]
pub struct PlainScene {
    /// The scene's name.
    pub name: String,
    /// Time step (s).
    pub dt: f64,
    /// Gravity (m/s^2).
    pub gravity: DVec3,
    /// Suggested number of steps.
    pub steps: usize,
    /// Bodies in the scene's order.
    pub bodies: Vec<PlainBody>,
}

impl Scene {
    /// The scene resolved into bodies in their body frames with tumble's
    /// mass properties (see the module documentation). Joints stay as the
    /// scene has them ([`Scene::joints`]: anchors and axes in the world).
    pub fn plain(&self) -> Result<PlainScene, WorldError> {
        // Only the bodies' resolved mass properties are read: one thread, no joints.
        let mut scene = self.clone();
        scene.settings.threads = 1;
        scene.joints.clear();
        scene.gears.clear();
        let (world, ids) = scene.build()?;
        let bodies = ids
            .iter()
            .zip(&self.bodies)
            .map(|(&id, desc)| {
                let body = world.body(id)?;
                let dynamic = body.kind() == BodyKind::Dynamic;
                Ok(PlainBody {
                    name: desc.name.clone(),
                    kind: body.kind(),
                    pose: body.pose(),
                    linear_velocity: world.linear_velocity(id)?,
                    angular_velocity: world.angular_velocity(id)?,
                    mass: if dynamic { body.mass() } else { 0.0 },
                    principal_inertia: if dynamic {
                        body.principal_inertia()
                    } else {
                        DVec3::ZERO
                    },
                    friction: desc.material.friction,
                    restitution: desc.material.restitution,
                    shapes: world
                        .colliders(id)?
                        .iter()
                        .map(|c| PlainShape {
                            shape: c.shape.clone(),
                            local: c.local,
                        })
                        .collect(),
                })
            })
            .collect::<Result<Vec<_>, WorldError>>()?;
        Ok(PlainScene {
            name: self.name.clone(),
            dt: self.settings.dt,
            gravity: self.settings.gravity,
            steps: self.steps,
            bodies,
        })
    }

    /// The JSON form of [`Scene::plain`]: `{format, name, dt, gravity,
    /// steps, limits, meshes, bodies, joints, gears, no_contact}`. Vectors are `[x, y, z]`,
    /// quaternions `[x, y, z, w]`; a mesh shape names its entry of
    /// `meshes` (each distinct mesh is written once); capsules lie along
    /// their local z axis; `limits` holds the scene's pass marks
    /// ([`PILE_INSIDE_HALF_WIDTH`], [`CHAIN_MAX_CENTRE_DISTANCE`]); `joints`
    /// are the scene's [`JointDesc`](crate::joint::JointDesc)s as written,
    /// their bodies named by index; `gears` the scene's
    /// [`SceneGear`](super::SceneGear)s (`{follower, leader, ratio,
    /// offset}`, joints by index) and `no_contact` its pairs of bodies kept
    /// apart (`[a, b]`, by index): a peer that has no twin for them must
    /// refuse the scene rather than run other work.
    pub fn to_plain_json(&self) -> Result<Value, WorldError> {
        let plain = self.plain()?;
        let mut meshes: Vec<Value> = Vec::new();
        let mut mesh_keys: Vec<*const tumble_collide::mesh::TriMesh> = Vec::new();
        let mut shape_json = |s: &PlainShape| -> Result<Value, WorldError> {
            let mut v = match &s.shape {
                Shape::Sphere(b) => json!({"type": "sphere", "radius": b.radius()}),
                Shape::Cuboid(c) => json!({"type": "box", "half_extents": vec3(c.half_extents())}),
                Shape::Capsule(c) => {
                    json!({"type": "capsule", "radius": c.radius(), "half_height": c.half_height()})
                }
                Shape::ConvexHull(h) => json!({
                    "type": "convex_hull",
                    "vertices": h.vertices().iter().map(|p| vec3(*p)).collect::<Vec<_>>(),
                }),
                Shape::HalfSpace(h) => {
                    json!({"type": "half_space", "normal": vec3(h.normal()), "offset": h.offset()})
                }
                Shape::Mesh(m) => {
                    let key = m.mesh() as *const _;
                    let index = match mesh_keys.iter().position(|&k| k == key) {
                        Some(i) => i,
                        None => {
                            mesh_keys.push(key);
                            meshes.push(json!({
                                "vertices": m.mesh().vertices().iter().map(|p| vec3(*p)).collect::<Vec<_>>(),
                                "triangles": m.mesh().triangles(),
                            }));
                            meshes.len() - 1
                        }
                    };
                    json!({"type": "mesh", "mesh": index})
                }
                other => {
                    return Err(WorldError::BadValue {
                        field: "shape",
                        message: format!("{} has no plain form yet", other.kind_name()),
                    })
                }
            };
            v["position"] = vec3(s.local.position);
            v["rotation"] = quat(s.local.rotation);
            Ok(v)
        };
        let bodies = plain
            .bodies
            .iter()
            .map(|b| {
                Ok(json!({
                    "name": b.name,
                    "kind": match b.kind {
                        BodyKind::Dynamic => "dynamic",
                        BodyKind::Static => "static",
                        BodyKind::Kinematic => "kinematic",
                    },
                    "position": vec3(b.pose.position),
                    "rotation": quat(b.pose.rotation),
                    "linear_velocity": vec3(b.linear_velocity),
                    "angular_velocity": vec3(b.angular_velocity),
                    "mass": b.mass,
                    "principal_inertia": vec3(b.principal_inertia),
                    "friction": b.friction,
                    "restitution": b.restitution,
                    "shapes": b.shapes.iter().map(&mut shape_json).collect::<Result<Vec<_>, _>>()?,
                }))
            })
            .collect::<Result<Vec<Value>, WorldError>>()?;
        let mut limits = serde_json::Map::new();
        if self.name.starts_with("pile") {
            limits.insert("inside_half_width".into(), json!(PILE_INSIDE_HALF_WIDTH));
        }
        if self.name == "concave_pile" {
            limits.insert(
                "inside_half_width".into(),
                json!(super::CONCAVE_BIN_INNER_HALF_WIDTH),
            );
        }
        if self.name.starts_with("chain") {
            limits.insert(
                "max_adjacent_centre_distance".into(),
                json!(CHAIN_MAX_CENTRE_DISTANCE),
            );
        }
        Ok(json!({
            "format": PLAIN_SCENE_FORMAT,
            "name": plain.name,
            "dt": plain.dt,
            "gravity": vec3(plain.gravity),
            "steps": plain.steps,
            "limits": limits,
            "meshes": meshes,
            "bodies": bodies,
            "joints": serde_json::to_value(&self.joints).map_err(|e| WorldError::BadValue {
                field: "joints",
                message: e.to_string(),
            })?,
            "gears": self.gears.iter().map(|g| json!({
                "follower": g.follower,
                "leader": g.leader,
                "ratio": g.ratio,
                "offset": g.offset,
            })).collect::<Vec<_>>(),
            "no_contact": self.no_contact.iter().map(|&(a, b)| json!([a, b])).collect::<Vec<_>>(),
        }))
    }
}

fn vec3(v: DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

fn quat(q: DQuat) -> Value {
    json!([q.x, q.y, q.z, q.w])
}
