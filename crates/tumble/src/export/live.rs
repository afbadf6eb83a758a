//! The viewer's live-mode messages (`viewer/README.md`, "Live mode"): one
//! `scene` message with every body's mesh (its model frame, z up) and every
//! joint's anchor and axis in its body A's frame (drawn as the glTF draws
//! them, moving with A), then one
//! `frame` message per step with the poses and the plot data, and a
//! `bodies_added` message whenever bodies join a running session (their
//! poses then follow the others' in every later frame). `tumble view` sends
//! them over a WebSocket; they are built from a [`Recording`] or straight
//! from a [`World`], so that live and recorded sessions show the same thing.

use serde_json::{json, Value};

use super::recording::{FrameExtras, RecordedBody, RecordedJoint, Recording};
use super::world_recorder::{frame_extras, MAX_CONTACTS_DRAWN};
use crate::world::{BodyId, World};
use tumble_collide::Pose;

/// One body of a `scene` or `bodies_added` message.
fn body_json(b: &RecordedBody) -> Value {
    let vertices: Vec<f64> = b.mesh.vertices().iter().flat_map(|v| v.to_array()).collect();
    let triangles: Vec<u32> = b.mesh.triangles().iter().flatten().copied().collect();
    json!({
        "name": b.name,
        "color": b.color,
        "is_static": b.is_static,
        "vertices": vertices,
        "triangles": triangles,
    })
}

/// One joint of a `scene` message: its name (`joint<k>` when it has none),
/// kind, body A (index in the message's bodies) and its anchor and axis in
/// A's frame.
fn joint_json(k: usize, j: &RecordedJoint) -> Value {
    json!({
        "name": if j.name.is_empty() { format!("joint{k}") } else { j.name.clone() },
        "kind": j.kind,
        "body": j.body_a,
        "anchor": j.anchor.to_array(),
        "axis": j.axis.to_array(),
    })
}

/// The `scene` message: names, colours, static flags and meshes of the
/// bodies, and the joints to draw.
pub fn scene_message(rec: &Recording) -> String {
    let bodies: Vec<Value> = rec.bodies.iter().map(body_json).collect();
    let joints: Vec<Value> = rec
        .joints
        .iter()
        .enumerate()
        .map(|(k, j)| joint_json(k, j))
        .collect();
    json!({ "type": "scene", "bodies": bodies, "joints": joints }).to_string()
}

/// The `bodies_added` message: bodies appended to the session's list, in
/// order; every later frame carries their poses after the others'.
pub fn bodies_added_message(bodies: &[RecordedBody]) -> String {
    let bodies: Vec<Value> = bodies.iter().map(body_json).collect();
    json!({ "type": "bodies_added", "bodies": bodies }).to_string()
}

fn frame_json(t: f64, poses: &[Pose], extras: Option<&FrameExtras>) -> String {
    let poses: Vec<[f64; 7]> = poses
        .iter()
        .map(|p| {
            let (x, q) = (p.position, p.rotation);
            [x.x, x.y, x.z, q.x, q.y, q.z, q.w]
        })
        .collect();
    let mut msg = json!({ "type": "frame", "t": t, "poses": poses });
    if let Some(e) = extras {
        msg["kinetic_energy"] = json!(e.kinetic_energy);
        msg["potential_energy"] = json!(e.potential_energy);
        msg["contact_count"] = json!(e.contact_count);
        let contacts: Vec<[f64; 7]> = e
            .contacts
            .iter()
            .map(|c| {
                let (p, n) = (c.point, c.normal);
                [p.x, p.y, p.z, n.x, n.y, n.z, c.distance]
            })
            .collect();
        msg["contacts"] = json!(contacts);
    }
    msg.to_string()
}

/// The `frame` message of frame `f` (time, poses `[x, y, z, qx, qy, qz, qw]`,
/// and energies and contacts when the recording has them); `None` when
/// there is no such frame.
pub fn frame_message(rec: &Recording, f: usize) -> Option<String> {
    let t = *rec.frame_times.get(f)?;
    Some(frame_json(t, rec.frames.get(f)?, rec.extras.get(f)))
}

/// The `frame` message of the world's current state: the model-frame poses
/// of `ids` (in that order; a removed body keeps the identity pose), the
/// energies and the contacts, as [`WorldRecorder`](super::WorldRecorder)
/// would record them, without keeping any history.
pub fn world_frame_message(world: &World, ids: &[BodyId]) -> String {
    let poses: Vec<Pose> = ids
        .iter()
        .map(|&id| world.pose(id).unwrap_or(Pose::IDENTITY))
        .collect();
    frame_json(
        world.time(),
        &poses,
        Some(&frame_extras(world, MAX_CONTACTS_DRAWN)),
    )
}
