//! The viewer's live-mode messages (`viewer/README.md`, "Live mode"): one
//! `scene` message with every body's mesh (body frame, z up), then one
//! `frame` message per step with the poses and the plot data. `tumble view`
//! sends them over a WebSocket; they are built from a [`Recording`] so that
//! live and recorded sessions show the same thing.

use serde_json::{json, Value};

use super::recording::Recording;

/// The `scene` message: names, colours, static flags and meshes of the bodies.
pub fn scene_message(rec: &Recording) -> String {
    let bodies: Vec<Value> = rec
        .bodies
        .iter()
        .map(|b| {
            let vertices: Vec<f64> = b.mesh.vertices().iter().flat_map(|v| v.to_array()).collect();
            let triangles: Vec<u32> = b.mesh.triangles().iter().flatten().copied().collect();
            json!({
                "name": b.name,
                "color": b.color,
                "is_static": b.is_static,
                "vertices": vertices,
                "triangles": triangles,
            })
        })
        .collect();
    json!({ "type": "scene", "bodies": bodies }).to_string()
}

/// The `frame` message of frame `f` (time, poses `[x, y, z, qx, qy, qz, qw]`,
/// and energies and contacts when the recording has them); `None` when
/// there is no such frame.
pub fn frame_message(rec: &Recording, f: usize) -> Option<String> {
    let t = *rec.frame_times.get(f)?;
    let poses: Vec<[f64; 7]> = rec
        .frames
        .get(f)?
        .iter()
        .map(|p| {
            let (x, q) = (p.position, p.rotation);
            [x.x, x.y, x.z, q.x, q.y, q.z, q.w]
        })
        .collect();
    let mut msg = json!({ "type": "frame", "t": t, "poses": poses });
    if let Some(e) = rec.extras.get(f) {
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
    Some(msg.to_string())
}
