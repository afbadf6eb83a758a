//! Recording a running [`World`] for export: one triangle mesh per body from
//! its shapes (primitives tessellated, half-spaces drawn as a large slab), and
//! one pose per body per recorded frame, with energies and contacts for the
//! viewer's plots and overlays.

use super::{ContactMark, ExportError, FrameExtras, RecordedBody, Recording};
use crate::body::BodyKind;
use crate::world::{BodyId, World};
use tumble_collide::mesh::{self, TriMesh};
use tumble_collide::shape::Shape;
use tumble_collide::{DQuat, DVec3, Pose};

/// Half width (m) of the slab that stands for a half-space in exports.
pub const HALF_SPACE_DRAW_EXTENT: f64 = 20.0;

/// A display mesh of a shape in its own frame; `None` for shapes that have
/// no tessellation yet.
pub fn shape_mesh(shape: &Shape) -> Option<TriMesh> {
    match shape {
        Shape::Sphere(s) => mesh::icosphere_mesh(s.radius(), 3).ok(),
        Shape::Cuboid(c) => mesh::box_mesh(c.half_extents()).ok(),
        Shape::Capsule(c) => mesh::capsule_mesh(c.radius(), c.half_height(), 24, 6).ok(),
        Shape::ConvexHull(h) => h.surface_mesh().ok(),
        Shape::Mesh(m) => Some(m.mesh().clone()),
        Shape::HalfSpace(hs) => {
            let thickness = 0.05;
            let slab = mesh::box_mesh(DVec3::new(
                HALF_SPACE_DRAW_EXTENT,
                HALF_SPACE_DRAW_EXTENT,
                thickness,
            ))
            .ok()?;
            let rotation = DQuat::from_rotation_arc(DVec3::Z, hs.normal());
            let centre = hs.normal() * (hs.offset() - thickness);
            slab.map_vertices(|v| rotation * v + centre).ok()
        }
        _ => None,
    }
}

/// Appends `part` placed by `pose` to the vertex and triangle lists.
fn append(vertices: &mut Vec<DVec3>, triangles: &mut Vec<[u32; 3]>, part: &TriMesh, pose: &Pose) {
    let base = vertices.len() as u32;
    vertices.extend(part.vertices().iter().map(|&v| pose.transform_point(v)));
    triangles.extend(part.triangles().iter().map(|t| t.map(|i| i + base)));
}

// Colours, not geometry: alike only in shape to the cube-face tables of
// tumble-cli/tests/cli_queries.rs and tumble-collide/tests/query_oracle.rs.
const PALETTE: [[f32; 4]; 6] = [
    [0.90, 0.45, 0.30, 1.0],
    [0.30, 0.60, 0.90, 1.0],
    [0.45, 0.80, 0.45, 1.0],
    [0.95, 0.75, 0.30, 1.0],
    [0.70, 0.45, 0.85, 1.0],
    [0.35, 0.80, 0.80, 1.0],
];

/// Contacts drawn per frame at most (the count is always complete).
pub const MAX_CONTACTS_DRAWN: usize = 512;

/// How a body of `world` is drawn: one mesh of all its shapes in the body's
/// model frame (the frame its description placed the shapes in, whose pose
/// [`World::pose`] reports), its name (`body{k}` when it has none) and a
/// colour (grey for static bodies, else the palette entry of `k`, its index
/// in the recording).
pub fn recorded_body(world: &World, id: BodyId, k: usize) -> Result<RecordedBody, ExportError> {
    let missing = || ExportError::Empty { bodies: k, frames: 0 };
    // Colliders are posed in the body frame (centre of mass, principal
    // axes); the model frame is where the user placed them.
    let model = world.pose(id).map_err(|_| missing())?;
    let body = world.body(id).map_err(|_| missing())?.pose();
    let body_in_model = model.inverse().mul_pose(&body);
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for c in world.colliders(id).map_err(|_| missing())? {
        if let Some(m) = shape_mesh(&c.shape) {
            append(
                &mut vertices,
                &mut triangles,
                &m,
                &body_in_model.mul_pose(&c.local),
            );
        }
    }
    let mesh = TriMesh::new(vertices, triangles)
        .or_else(|_| mesh::box_mesh(DVec3::splat(0.01)).map_err(|e| e.to_string()))
        .map_err(|_| missing())?;
    let is_static = world.body(id).map_err(|_| missing())?.kind() == BodyKind::Static;
    let name = world.name(id).unwrap_or("").to_string();
    Ok(RecordedBody {
        name: if name.is_empty() { format!("body{k}") } else { name },
        mesh,
        color: if is_static {
            [0.75, 0.76, 0.80, 1.0]
        } else {
            PALETTE[k % PALETTE.len()]
        },
        is_static,
    })
}

/// The viewer data of the world's current state: energies, the contact
/// count, and up to `max_contacts` contacts that touch or pushed.
pub fn frame_extras(world: &World, max_contacts: usize) -> FrameExtras {
    let contacts = world.contacts();
    FrameExtras {
        kinetic_energy: world.kinetic_energy(),
        potential_energy: world.potential_energy(),
        contact_count: contacts.len(),
        contacts: contacts
            .iter()
            .filter(|c| c.contact.distance <= 0.0 || c.normal_impulse > 0.0)
            .take(max_contacts)
            .map(|c| ContactMark::from(&c.contact))
            .collect(),
    }
}

/// Samples a world into a [`Recording`]: create it before stepping, call
/// [`WorldRecorder::record`] after each step to keep, then [`finish`](Self::finish).
#[derive(Debug, Clone)]
pub struct WorldRecorder {
    ids: Vec<BodyId>,
    recording: Recording,
    max_contacts_drawn: usize,
}

/// The joints of `world` between recorded bodies `ids`, their anchor and
/// axis carried into body A's recorded frame at its present pose.
pub fn recorded_joints(world: &World, ids: &[BodyId]) -> Vec<super::recording::RecordedJoint> {
    let index = |id: BodyId| ids.iter().position(|&b| b == id);
    world
        .joint_ids()
        .into_iter()
        .filter_map(|j| {
            let desc = world.joint(j).ok()?;
            let state = world.joint_state(j).ok()?;
            let a = index(desc.body_a)?;
            let frame = world.pose(desc.body_a).ok()?;
            Some(super::recording::RecordedJoint {
                name: desc.name.clone(),
                kind: desc.kind.name().to_string(),
                body_a: a,
                body_b: desc.body_b.and_then(index),
                anchor: frame.inverse_transform_point(state.anchor_a),
                axis: frame.rotation.conjugate() * state.axis,
            })
        })
        .collect()
}

impl WorldRecorder {
    /// Takes the bodies of `world` (in slot order) and records its current
    /// state as the first frame. Bodies are recorded in their body frame
    /// (centre of mass, principal axes).
    pub fn new(world: &World) -> Result<WorldRecorder, ExportError> {
        let ids = world.body_ids();
        let bodies = ids
            .iter()
            .enumerate()
            .map(|(k, &id)| recorded_body(world, id, k))
            .collect::<Result<Vec<_>, _>>()?;
        let joints = recorded_joints(world, &ids);
        let mut recorder = WorldRecorder {
            ids,
            recording: Recording {
                bodies,
                joints,
                ..Recording::default()
            },
            max_contacts_drawn: MAX_CONTACTS_DRAWN,
        };
        recorder.record(world);
        Ok(recorder)
    }

    /// Records the world's current poses, energies and contacts as a frame.
    /// Bodies added after the recorder was created are not recorded.
    pub fn record(&mut self, world: &World) {
        let poses = self
            .ids
            .iter()
            .map(|&id| world.pose(id).unwrap_or(Pose::IDENTITY))
            .collect();
        self.recording.frame_times.push(world.time());
        self.recording.frames.push(poses);
        self.recording
            .extras
            .push(frame_extras(world, self.max_contacts_drawn));
    }

    /// Number of frames recorded.
    pub fn frames(&self) -> usize {
        self.recording.frames.len()
    }

    /// The recording so far (for streaming the newest frame while recording).
    pub fn recording(&self) -> &Recording {
        &self.recording
    }

    /// The finished recording.
    pub fn finish(self) -> Recording {
        self.recording
    }
}
