//! Animated binary glTF 2.0 export (Khronos glTF 2.0 specification: 3.6
//! buffers/accessors, 3.7 meshes, 3.8 materials, 3.11 animations, 4.4 GLB).
//!
//! Layout of the written file:
//! - node 0, `tumble_world`: the only scene root. Its rotation of -90 degrees
//!   about x maps tumble's z-up world to glTF's y-up (x stays x, z becomes y,
//!   y becomes -z). The physics data below it is written unchanged.
//! - node `1 + b` for body `b`: child of the root, with mesh `b` (flat normals,
//!   see `mesh_data`) and material `b` (PBR, base colour = body colour,
//!   metallic 0, roughness 0.8). Its translation/rotation are the frame-0 pose.
//! - after the bodies, two nodes per joint, children of body A's node (so
//!   they move with it): `joint:NAME` (a small octahedron at the anchor) and
//!   `joint:NAME:axis` (a thin bar along the axis, 0.15 m each way), with
//!   the shared material `joint` (orange).
//! - one animation, `recording`, with a LINEAR translation and rotation channel
//!   per animated body (dynamic, or static but moving), sampled at every frame
//!   time (s). Bodies that never move get no channels.
//!
//! ## `extras` schema (root object `extras.tumble`, read by `viewer/`)
//! ```text
//! schema:           "tumble-recording/1"
//! up_axis:          "z"           physics frame of every vector below
//! root_node:        0             node holding the z-up -> y-up rotation
//! frame_times:      [f64; F]      s, same as the animation input
//! bodies:           [{name, node, is_static, animated}; B]
//! kinetic_energy:   [f64; F]      J        (present only with frame extras)
//! potential_energy: [f64; F]      J        (present only with frame extras)
//! contact_count:    [u64; F]               (present only with frame extras)
//! contacts:         [[[px,py,pz, nx,ny,nz, d]; C_f]; F]
//!                   world point (m), unit normal B->A, signed distance (m)
//! obb_boxes:        [{body, depth, center:[3], rotation:[x,y,z,w],
//!                     half_extents:[3]}]   body frame, m (may be empty)
//! joints:           [{name, kind, body_a, body_b, anchor:[3], axis:[3],
//!                     node}]   anchor and axis in body A's frame (m);
//!                     body_b null for the world; node: the marker node
//! ```
//! World-frame data (contacts) is meant to be drawn under the root node;
//! body-frame data (OBB boxes) under the body's node.

use std::f64::consts::FRAC_1_SQRT_2;
use std::path::Path;

use serde_json::{json, Value};
use tumble_collide::{DVec3, Pose};

use super::atomic::write_atomic;
use super::mesh_data::flat_mesh;
use super::recording::{ExportError, Recording};

/// Rotation (x, y, z, w) of the root node: -90 degrees about x, z-up to y-up.
pub const ROOT_ROTATION_XYZW: [f64; 4] = [-FRAC_1_SQRT_2, 0.0, 0.0, FRAC_1_SQRT_2];

/// The value of `extras.tumble.schema` written by this version.
pub const EXTRAS_SCHEMA: &str = "tumble-recording/1";

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const ARRAY_BUFFER: u32 = 34962;
const FLOAT: u32 = 5126;

/// Writes `rec` as a binary glTF file at `path`, atomically.
pub fn write_glb(rec: &Recording, path: impl AsRef<Path>) -> Result<(), ExportError> {
    let bytes = glb_bytes(rec)?;
    write_atomic(path.as_ref(), &bytes)
}

/// The complete `.glb` file for `rec`, in memory.
pub fn glb_bytes(rec: &Recording) -> Result<Vec<u8>, ExportError> {
    rec.validate()?;
    let mut buf = BinBuilder::default();

    let mut meshes = Vec::with_capacity(rec.bodies.len());
    let mut materials = Vec::with_capacity(rec.bodies.len());
    let mut nodes = vec![json!({
        "name": "tumble_world",
        "rotation": ROOT_ROTATION_XYZW,
        "children": (1..=rec.bodies.len()).collect::<Vec<_>>(),
    })];
    for (b, body) in rec.bodies.iter().enumerate() {
        meshes.push(mesh_json(&mut buf, &body.mesh, &body.name, b));
        let mut material = json!({
            "name": body.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": body.color,
                "metallicFactor": 0.0,
                "roughnessFactor": 0.8,
            },
        });
        if body.color[3] < 1.0 {
            material["alphaMode"] = json!("BLEND");
        }
        materials.push(material);
        let p0 = rec.frames[0][b];
        nodes.push(json!({
            "name": body.name,
            "mesh": b,
            "translation": p0.position.to_array(),
            "rotation": p0.rotation.to_array(),
        }));
    }

    add_joint_markers(rec, &mut buf, &mut nodes, &mut meshes, &mut materials);

    let animated: Vec<usize> = (0..rec.bodies.len()).filter(|&b| rec.is_animated(b)).collect();
    let mut animations = Vec::new();
    if !animated.is_empty() {
        let times: Vec<f32> = rec.frame_times.iter().map(|&t| t as f32).collect();
        let (t0, t1) = (times[0], times[times.len() - 1]);
        let input = buf.accessor(
            times,
            rec.frame_times.len(),
            "SCALAR",
            None,
            Some((vec![t0], vec![t1])),
        );
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        for &b in &animated {
            let poses: Vec<Pose> = rec.frames.iter().map(|f| f[b]).collect();
            let translation: Vec<f32> = poses
                .iter()
                .flat_map(|p| p.position.as_vec3().to_array())
                .collect();
            let rotation: Vec<f32> = poses
                .iter()
                .flat_map(|p| p.rotation.as_quat().to_array())
                .collect();
            for (data, kind, path) in [
                (translation, "VEC3", "translation"),
                (rotation, "VEC4", "rotation"),
            ] {
                let output = buf.accessor(data, poses.len(), kind, None, None);
                channels
                    .push(json!({ "sampler": samplers.len(), "target": { "node": 1 + b, "path": path } }));
                samplers.push(json!({ "input": input, "output": output, "interpolation": "LINEAR" }));
            }
        }
        animations.push(json!({ "name": "recording", "samplers": samplers, "channels": channels }));
    }

    let mut doc = json!({
        "asset": { "version": "2.0", "generator": concat!("tumble ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "name": "recording", "nodes": [0] }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "buffers": [{ "byteLength": buf.bin.len() }],
        "bufferViews": buf.views,
        "accessors": buf.accessors,
        "extras": { "tumble": extras_json(rec, &animated) },
    });
    if !animations.is_empty() {
        doc["animations"] = Value::Array(animations);
    }
    // Serialising a `Value` built from finite numbers cannot fail.
    let json_text = serde_json::to_vec(&doc).unwrap_or_default();
    assemble_glb(json_text, buf.bin)
}

/// Joint markers: an octahedron at each anchor and a bar along each axis,
/// as children of body A's node (layout in the module docs).
fn add_joint_markers(
    rec: &Recording,
    buf: &mut BinBuilder,
    nodes: &mut Vec<Value>,
    meshes: &mut Vec<Value>,
    materials: &mut Vec<Value>,
) {
    if rec.joints.is_empty() {
        return;
    }
    let material = materials.len();
    materials.push(json!({
        "name": "joint",
        "pbrMetallicRoughness": { "baseColorFactor": [1.0, 0.45, 0.05, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5 },
    }));
    let mut mesh_of = |mesh: &tumble_collide::mesh::TriMesh, name: &str| {
        meshes.push(mesh_json(buf, mesh, name, material));
        meshes.len() - 1
    };
    let r = 0.02;
    let octahedron = tumble_collide::mesh::TriMesh::new(
        vec![
            DVec3::X * r,
            -DVec3::X * r,
            DVec3::Y * r,
            -DVec3::Y * r,
            DVec3::Z * r,
            -DVec3::Z * r,
        ],
        vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
    )
    .expect("a closed octahedron");
    // A thin box along x (the joint's axis once turned).
    let bar = tumble_collide::mesh::box_mesh(DVec3::new(0.15, 0.004, 0.004)).expect("a closed bar");
    let marker = mesh_of(&octahedron, "joint_anchor");
    let axis_bar = mesh_of(&bar, "joint_axis");
    for (k, j) in rec.joints.iter().enumerate() {
        let name = if j.name.is_empty() {
            format!("joint{k}")
        } else {
            j.name.clone()
        };
        // The bar lies along x: turned onto the axis.
        let turn = tumble_collide::DQuat::from_rotation_arc(DVec3::X, j.axis.normalize_or(DVec3::X));
        for (node_name, mesh, rotation) in [
            (format!("joint:{name}"), marker, tumble_collide::DQuat::IDENTITY),
            (format!("joint:{name}:axis"), axis_bar, turn),
        ] {
            let index = nodes.len();
            nodes.push(json!({
                "name": node_name,
                "mesh": mesh,
                "translation": j.anchor.to_array(),
                "rotation": rotation.to_array(),
            }));
            let parent = &mut nodes[1 + j.body_a];
            match parent.get_mut("children").and_then(Value::as_array_mut) {
                Some(children) => children.push(json!(index)),
                None => parent["children"] = json!([index]),
            }
        }
    }
}

/// A glTF mesh of `mesh` (flat normals) with `material`, its data in `buf`.
fn mesh_json(
    buf: &mut BinBuilder,
    mesh: &tumble_collide::mesh::TriMesh,
    name: &str,
    material: usize,
) -> Value {
    let flat = flat_mesh(mesh);
    let count = flat.positions.len();
    let pos = buf.accessor(
        flatten(&flat.positions),
        count,
        "VEC3",
        Some(ARRAY_BUFFER),
        Some((flat.min.to_vec(), flat.max.to_vec())),
    );
    let nrm = buf.accessor(flatten(&flat.normals), count, "VEC3", Some(ARRAY_BUFFER), None);
    json!({
        "name": name,
        "primitives": [{ "attributes": { "POSITION": pos, "NORMAL": nrm }, "material": material, "mode": 4 }],
    })
}

/// The `extras.tumble` object (schema in the module docs).
///
/// Bodies, boxes and joints are each mapped to their JSON object key by key,
/// as the schema lists them: the `iter().map(json!)` chains read alike, but
/// each builds a different record's object.
fn extras_json(rec: &Recording, animated: &[usize]) -> Value {
    let bodies: Vec<Value> = rec
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            json!({
                "name": body.name,
                "node": 1 + b,
                "is_static": body.is_static,
                "animated": animated.contains(&b),
            })
        })
        .collect();
    let boxes: Vec<Value> = rec
        .obb_boxes
        .iter()
        .map(|o| {
            json!({
                "body": o.body,
                "depth": o.depth,
                "center": o.center.to_array(),
                "rotation": o.rotation.to_array(),
                "half_extents": o.half_extents.to_array(),
            })
        })
        .collect();
    let mut extras = json!({
        "schema": EXTRAS_SCHEMA,
        "up_axis": "z",
        "root_node": 0,
        "frame_times": rec.frame_times,
        "bodies": bodies,
        "obb_boxes": boxes,
    });
    if !rec.joints.is_empty() {
        let first_marker = 1 + rec.bodies.len();
        let joints: Vec<Value> = rec
            .joints
            .iter()
            .enumerate()
            .map(|(k, j)| {
                json!({
                    "name": j.name,
                    "kind": j.kind,
                    "body_a": j.body_a,
                    "body_b": j.body_b,
                    "anchor": j.anchor.to_array(),
                    "axis": j.axis.to_array(),
                    "node": first_marker + 2 * k,
                })
            })
            .collect();
        extras["joints"] = json!(joints);
    }
    if !rec.extras.is_empty() {
        let e = &rec.extras;
        extras["kinetic_energy"] = json!(e.iter().map(|x| x.kinetic_energy).collect::<Vec<_>>());
        extras["potential_energy"] = json!(e.iter().map(|x| x.potential_energy).collect::<Vec<_>>());
        extras["contact_count"] = json!(e.iter().map(|x| x.contact_count).collect::<Vec<_>>());
        let contacts: Vec<Vec<[f64; 7]>> = e
            .iter()
            .map(|x| {
                x.contacts
                    .iter()
                    .map(|c| {
                        let (p, n) = (c.point, c.normal);
                        [p.x, p.y, p.z, n.x, n.y, n.z, c.distance]
                    })
                    .collect()
            })
            .collect();
        extras["contacts"] = json!(contacts);
    }
    extras
}

fn flatten(v: &[[f32; 3]]) -> Vec<f32> {
    v.iter().flatten().copied().collect()
}

/// Accumulates the binary chunk with one buffer view per accessor. All data is
/// `f32`, so every view starts at a multiple of 4 bytes as glTF requires.
#[derive(Default)]
struct BinBuilder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl BinBuilder {
    /// Appends `data` (`count` elements of glTF type `kind`) and returns the
    /// accessor index.
    fn accessor(
        &mut self,
        data: Vec<f32>,
        count: usize,
        kind: &str,
        target: Option<u32>,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> usize {
        let offset = self.bin.len();
        for x in &data {
            self.bin.extend_from_slice(&x.to_le_bytes());
        }
        let mut view = json!({ "buffer": 0, "byteOffset": offset, "byteLength": 4 * data.len() });
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.views.push(view);
        let mut acc = json!({
            "bufferView": self.views.len() - 1,
            "componentType": FLOAT,
            "count": count,
            "type": kind,
        });
        if let Some((min, max)) = min_max {
            acc["min"] = json!(min);
            acc["max"] = json!(max);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }
}

/// GLB container (spec 4.4): 12-byte header, JSON chunk padded with spaces,
/// BIN chunk padded with zeros, both to 4-byte boundaries.
fn assemble_glb(mut json_text: Vec<u8>, mut bin: Vec<u8>) -> Result<Vec<u8>, ExportError> {
    json_text.resize(json_text.len().next_multiple_of(4), b' ');
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json_text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let total32 = u32::try_from(total).map_err(|_| ExportError::TooLarge(total))?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&GLB_MAGIC.to_le_bytes());
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total32.to_le_bytes());
    out.extend_from_slice(&(json_text.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&json_text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    Ok(out)
}
