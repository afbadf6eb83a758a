//! The request side of a live viewer session (`viewer/README.md`, "Live
//! mode"): a page may ask a running simulation for a new body (`spawn`: a
//! ball or box thrown from the camera); [`LiveSession`] checks the request
//! (every field, with the field named in the error), adds the body and
//! answers with a `bodies_added` message, or an `error` with the world
//! unchanged. The transport (`tumble view`'s WebSocket) only carries text.

use super::live::{bodies_added_message, scene_message, world_frame_message};
use super::{recorded_body, ExportError, WorldRecorder};
use crate::collide::{Cuboid, DVec3, Shape, Sphere};
use crate::world::{BodyDesc, BodyId, MassDesc, World};

/// Bodies a page may add to one session: bounds its cost.
pub const MAX_SPAWNED: usize = 200;
/// Largest radius or half extent of a spawned body (m).
pub const MAX_SPAWN_SIZE: f64 = 2.0;
/// Largest speed of a spawned body (m/s).
pub const MAX_SPAWN_SPEED: f64 = 100.0;

/// A page's request to add a body (`{"type": "spawn", ...}`).
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SpawnRequest {
    #[serde(rename = "type")]
    _type: String,
    /// `sphere` (with `radius`) or `box` (with `half_extents`).
    shape: String,
    radius: Option<f64>,
    half_extents: Option<[f64; 3]>,
    /// Centre (m, world frame, z up).
    position: [f64; 3],
    /// Initial velocity (m/s). Default zero.
    velocity: Option<[f64; 3]>,
    /// Density (kg/m^3). Default 1000; at most one of `density` and `mass`.
    density: Option<f64>,
    /// Total mass (kg).
    mass: Option<f64>,
    name: Option<String>,
}

fn size(field: &str, x: f64) -> Result<f64, String> {
    if x.is_finite() && x > 0.0 && x <= MAX_SPAWN_SIZE {
        Ok(x)
    } else {
        Err(format!(
            "spawn.{field}: must be in (0, {MAX_SPAWN_SIZE}] m, got {x}"
        ))
    }
}

/// The body a spawn request describes; every value checked, with the field
/// named in the error.
fn spawn_desc(req: &SpawnRequest, n: usize) -> Result<BodyDesc, String> {
    let shape: Shape = match req.shape.as_str() {
        "sphere" => {
            let r = size("radius", req.radius.ok_or("spawn.radius: required for a sphere")?)?;
            Sphere::new(r).map_err(|e| format!("spawn.radius: {e}"))?.into()
        }
        "box" => {
            let h = req.half_extents.ok_or("spawn.half_extents: required for a box")?;
            for (k, x) in h.iter().enumerate() {
                size(&format!("half_extents[{k}]"), *x)?;
            }
            Cuboid::new(DVec3::from_array(h))
                .map_err(|e| format!("spawn.half_extents: {e}"))?
                .into()
        }
        other => return Err(format!("spawn.shape: expected `sphere` or `box`, got `{other}`")),
    };
    let position = DVec3::from_array(req.position);
    if !position.is_finite() {
        return Err(format!("spawn.position: must be finite, got {:?}", req.position));
    }
    let velocity = DVec3::from_array(req.velocity.unwrap_or([0.0; 3]));
    if !(velocity.is_finite() && velocity.length() <= MAX_SPAWN_SPEED) {
        return Err(format!(
            "spawn.velocity: must be finite with speed <= {MAX_SPAWN_SPEED} m/s, got {:?}",
            req.velocity
        ));
    }
    let mass = match (req.density, req.mass) {
        (Some(_), Some(_)) => return Err("spawn: give `density` or `mass`, not both".into()),
        (None, Some(m)) => MassDesc::Mass(m),
        (Some(d), None) => MassDesc::Density(d),
        (None, None) => MassDesc::default(),
    };
    let mut desc = BodyDesc::dynamic(shape)
        .at(position)
        .with_velocity(velocity, DVec3::ZERO)
        .named(req.name.clone().unwrap_or_else(|| format!("spawned{n}")));
    desc.mass = mass;
    Ok(desc)
}

/// A live world and what the page has been told about it.
#[derive(Debug)]
pub struct LiveSession {
    /// The running world.
    pub world: World,
    /// Bodies in the order of the page's pose lists.
    ids: Vec<BodyId>,
    spawned: usize,
}

/// An `error` message to the page.
fn error_message(message: &str) -> String {
    serde_json::json!({ "type": "error", "message": message }).to_string()
}

impl LiveSession {
    /// A session over `world`; the page will be shown every body it has now.
    pub fn new(world: World) -> LiveSession {
        let ids = world.body_ids();
        LiveSession {
            world,
            ids,
            spawned: 0,
        }
    }

    /// The first messages of a session: the `scene` (every body's mesh) and
    /// the first `frame`.
    pub fn start_messages(&self) -> Result<Vec<String>, ExportError> {
        let scene = scene_message(WorldRecorder::new(&self.world)?.recording());
        Ok(vec![scene, self.frame_message()])
    }

    /// The `frame` message of the world's present state.
    pub fn frame_message(&self) -> String {
        world_frame_message(&self.world, &self.ids)
    }

    /// Bodies the page knows, in the order of its pose lists.
    pub fn bodies(&self) -> &[BodyId] {
        &self.ids
    }

    /// The reply to any request once the scene's steps are done.
    pub fn ended_message() -> String {
        error_message("the simulation has ended")
    }

    /// Handles one text message from the page (a `spawn` request); returns
    /// the messages to send back (`bodies_added`, or an `error` naming the
    /// field, the world unchanged).
    pub fn handle(&mut self, text: &str) -> Vec<String> {
        let reply_error = |message: String| vec![error_message(&message)];
        let value: serde_json::Value = match serde_json::from_str(text) {
            Ok(v) => v,
            Err(e) => return reply_error(format!("not JSON: {e}")),
        };
        match value.get("type").and_then(|t| t.as_str()) {
            Some("spawn") => {}
            Some(other) => return reply_error(format!("unknown message type `{other}` (expected `spawn`)")),
            None => return reply_error("a message needs a `type`".into()),
        }
        if self.spawned >= MAX_SPAWNED {
            return reply_error(format!("spawn: at most {MAX_SPAWNED} bodies per session"));
        }
        let result = serde_json::from_value::<SpawnRequest>(value)
            .map_err(|e| format!("spawn: {e}"))
            .and_then(|req| spawn_desc(&req, self.spawned))
            .and_then(|desc| self.world.add_body(&desc).map_err(|e| format!("spawn: {e}")));
        match result {
            Ok(id) => match recorded_body(&self.world, id, self.ids.len()) {
                Ok(body) => {
                    self.ids.push(id);
                    self.spawned += 1;
                    vec![bodies_added_message(&[body])]
                }
                Err(e) => {
                    // Cannot be drawn: take it out again so that page and world agree.
                    let _ = self.world.remove_body(id);
                    reply_error(format!("spawn: {e}"))
                }
            },
            Err(message) => reply_error(message),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::WorldSettings;

    fn session() -> LiveSession {
        LiveSession::new(World::new(WorldSettings::default()).unwrap())
    }

    #[test]
    fn spawn_adds_a_body_with_the_requested_mass_and_velocity() {
        let mut s = session();
        let replies = s.handle(
            r#"{"type":"spawn","shape":"sphere","radius":0.1,"position":[1,2,3],"velocity":[4,0,0],"mass":2}"#,
        );
        let msg: serde_json::Value = serde_json::from_str(&replies[0]).unwrap();
        assert_eq!(msg["type"], "bodies_added", "{msg}");
        assert_eq!(s.ids.len(), 1);
        let id = s.ids[0];
        assert_eq!(s.world.body(id).unwrap().mass(), 2.0);
        assert_eq!(s.world.center_of_mass(id).unwrap(), DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(s.world.linear_velocity(id).unwrap(), DVec3::new(4.0, 0.0, 0.0));
    }

    #[test]
    fn bad_requests_get_an_error_and_leave_the_world_unchanged() {
        let mut s = session();
        for (text, expect) in [
            ("nonsense", "not JSON"),
            (r#"{"type":"teleport"}"#, "unknown message type"),
            (
                r#"{"type":"spawn","shape":"cone","position":[0,0,0]}"#,
                "spawn.shape",
            ),
            (
                r#"{"type":"spawn","shape":"sphere","position":[0,0,0]}"#,
                "spawn.radius",
            ),
            (
                r#"{"type":"spawn","shape":"sphere","radius":-1,"position":[0,0,0]}"#,
                "spawn.radius",
            ),
            (
                r#"{"type":"spawn","shape":"sphere","radius":50,"position":[0,0,0]}"#,
                "spawn.radius",
            ),
            (
                r#"{"type":"spawn","shape":"box","half_extents":[1,0,1],"position":[0,0,0]}"#,
                "half_extents[1]",
            ),
            (
                r#"{"type":"spawn","shape":"sphere","radius":0.1,"position":[0,0,0],"velocity":[1e9,0,0]}"#,
                "spawn.velocity",
            ),
            (
                r#"{"type":"spawn","shape":"sphere","radius":0.1,"position":[0,0,0],"mass":-2}"#,
                "mass",
            ),
            (
                r#"{"type":"spawn","shape":"sphere","radius":0.1,"position":[0,0,0],"colour":1}"#,
                "unknown field",
            ),
        ] {
            let replies = s.handle(text);
            let msg: serde_json::Value = serde_json::from_str(&replies[0]).unwrap();
            assert_eq!(msg["type"], "error", "{text}");
            let m = msg["message"].as_str().unwrap();
            assert!(m.contains(expect), "{text}: {m}");
        }
        assert_eq!(s.world.body_count(), 0);
        assert!(s.ids.is_empty());
    }

    #[test]
    fn spawning_is_bounded_per_session() {
        let mut s = session();
        let text = r#"{"type":"spawn","shape":"sphere","radius":0.05,"position":[0,0,0]}"#;
        for _ in 0..MAX_SPAWNED {
            assert!(s.handle(text)[0].contains("bodies_added"));
        }
        assert!(s.handle(text)[0].contains("at most"));
        assert_eq!(s.world.body_count(), MAX_SPAWNED);
    }
}
