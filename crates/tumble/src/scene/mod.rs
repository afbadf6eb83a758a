//! Scene files: a TOML (or JSON, same schema) description of a world, read
//! with serde into a [`Scene`] and built into a [`World`], with errors that
//! name the file, line, column and field.
//!
//! - [`schema`]: the serde types (every key documented; unknown keys are errors);
//! - `parse`: text to schema types, syntax and schema errors located;
//! - `resolve` and `shapes`: named materials and shapes, grids, meshes from
//!   generators or files, every value checked with its field path;
//! - `joints`: the `[[joints]]`, bodies found by name;
//! - `locate`: field path to line and column in the source text;
//! - [`error`]: [`SceneError`], one line: `file:line:column: path: message`.
//!
//! A scene file in brief (the full reference is `docs/scenes.md`, the JSON
//! Schema `docs/scene.schema.json`, examples in `examples/scenes/`):
//!
//! ```toml
//! name = "two boxes"
//! duration = 2.0                  # s (or steps = N)
//!
//! [settings]                      # any WorldSettings field
//! dt = 0.004166666666666667
//!
//! [materials.default]
//! friction = 0.6
//!
//! [shapes.cube]
//! type = "box"
//! half_extents = [0.25, 0.25, 0.25]
//!
//! [[bodies]]
//! name = "ground"
//! kind = "static"
//! shapes = [{ type = "half_space" }]
//!
//! [[bodies]]
//! name = "cube{i}"
//! shape = "cube"
//! mass = 1.0
//! position = [0, 0, 0.25]
//! rotation = [{ z = 30 }]         # degrees; or orientation = [x, y, z, w]
//! grid = { count = [2, 1, 1], spacing = [1.0, 0, 0] }
//! ```
//!
//! ```
//! let text = r#"
//! [[bodies]]
//! kind = "static"
//! shapes = [{ type = "half_space" }]
//! [[bodies]]
//! shapes = [{ type = "sphere", radius = 0.1 }]
//! mass = -1
//! position = [0, 0, 1]
//! "#;
//! let err = tumble::scene::parse_scene(text, tumble::scene::Format::Toml, "drop.toml".as_ref())
//!     .err()
//!     .unwrap();
//! assert_eq!(err.to_string(), "drop.toml:7:8: bodies[1].mass: must be finite and > 0 kg, got -1");
//! ```

pub mod error;
mod joints;
mod locate;
mod no_contact;
pub mod params;
mod parse;
mod resolve;
pub mod schema;
mod shapes;
mod values;

pub use error::{FieldError, FieldPath, PathSeg, SceneError};
pub use params::{ParamPath, SceneDocument};
pub use resolve::DEFAULT_DURATION;
pub use schema::SceneFile;

use std::path::{Path, PathBuf};

use crate::joint::Gear;
use crate::scenes::Scene;
use crate::world::{BodyId, World};
use resolve::{world_error_message, world_error_path, BodyOrigin};
use tumble_collide::DVec3;

/// The text format of a scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// TOML 1.0 (`.toml`).
    Toml,
    /// JSON (`.json`), same schema.
    Json,
}

impl Format {
    /// The format for a file name's extension (case-insensitive), if known.
    pub fn from_path(path: &Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "toml" => Some(Format::Toml),
            "json" => Some(Format::Json),
            _ => None,
        }
    }
}

/// A force and torque applied to a body during the first step only.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialLoad {
    /// Index of the body in [`Scene::bodies`].
    pub body: usize,
    /// Force at the centre of mass (N, world frame).
    pub force: DVec3,
    /// Torque (N m, world frame).
    pub torque: DVec3,
}

/// A scene file, read and checked: the [`Scene`] plus what is needed to
/// build it and to point at the file when the world rejects something.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// Settings, bodies in insertion order, steps to run.
    pub scene: Scene,
    /// Initial forces and torques (first step only).
    pub initial_loads: Vec<InitialLoad>,
    /// The file the scene came from (as given).
    pub file: PathBuf,
    text: String,
    format: Format,
    origins: Vec<BodyOrigin>,
    joint_paths: Vec<FieldPath>,
}

/// Reads, parses and checks the scene file at `path` (format by extension;
/// mesh files relative to its directory).
///
/// ```
/// use tumble::scene::load_scene;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/scenes/domino.toml");
/// let loaded = load_scene(path)?;
/// assert_eq!(loaded.scene.name, "domino");
/// assert_eq!(loaded.scene.steps, 600);
/// let (mut world, ids) = loaded.build()?; // bodies in file order
/// assert_eq!(world.name(ids[1])?, "domino0");
/// world.step();
///
/// // Errors name the file, line, column and field.
/// let err = load_scene("no/such/scene.toml").unwrap_err();
/// assert!(err.to_string().contains("no/such/scene.toml"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn load_scene(path: impl AsRef<Path>) -> Result<LoadedScene, SceneError> {
    let path = path.as_ref();
    let format = Format::from_path(path).ok_or_else(|| SceneError::Format {
        file: path.to_path_buf(),
    })?;
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::Read {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    parse_scene(&text, format, path)
}

/// Parses and checks scene `text`; `file` names it in errors and its
/// directory is where mesh files are looked up.
pub fn parse_scene(text: &str, format: Format, file: &Path) -> Result<LoadedScene, SceneError> {
    let spec = parse::parse_scene_text(text, format, file)?;
    let base_dir = file.parent().unwrap_or(Path::new(""));
    let default_name = file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".to_string());
    let resolved = resolve::resolve(&spec, base_dir, &default_name)
        .map_err(|e| parse::locate_error(file, text, format, e))?;
    Ok(LoadedScene {
        scene: resolved.scene,
        initial_loads: resolved.loads,
        file: file.to_path_buf(),
        text: text.to_string(),
        format,
        origins: resolved.origins,
        joint_paths: resolved.joint_paths,
    })
}

impl LoadedScene {
    /// Builds the world (bodies in file order) and applies the initial
    /// forces and torques for the first step. A body the world rejects (an
    /// open mesh whose mass comes from density, a static body with a
    /// velocity, ...) is reported at its place in the file.
    pub fn build(&self) -> Result<(World, Vec<BodyId>), SceneError> {
        let locate = |e: &crate::world::WorldError, origin: Option<&BodyOrigin>| {
            let path = world_error_path(e, origin);
            parse::locate_error(
                &self.file,
                &self.text,
                self.format,
                FieldError::new(&path, world_error_message(e, origin)),
            )
        };
        let mut world = World::new(self.scene.settings.clone()).map_err(|e| locate(&e, None))?;
        let mut ids = Vec::with_capacity(self.scene.bodies.len());
        for (desc, origin) in self.scene.bodies.iter().zip(&self.origins) {
            ids.push(world.add_body(desc).map_err(|e| locate(&e, Some(origin)))?);
        }
        for load in &self.initial_loads {
            let origin = self.origins.get(load.body);
            let id = ids[load.body];
            world
                .apply_force(id, load.force)
                .map_err(|e| locate(&e, origin))?;
            world
                .apply_torque(id, load.torque)
                .map_err(|e| locate(&e, origin))?;
        }
        let mut joint_ids = Vec::with_capacity(self.scene.joints.len());
        for (joint, path) in self.scene.joints.iter().zip(&self.joint_paths) {
            let at = |e: crate::world::WorldError| {
                parse::locate_error(
                    &self.file,
                    &self.text,
                    self.format,
                    FieldError::new(
                        &joints::joint_error_path(&e, path),
                        joints::joint_error_message(&e),
                    ),
                )
            };
            let desc = self.scene.joint_desc(joint, &ids).map_err(at)?;
            joint_ids.push(world.add_joint(&desc).map_err(at)?);
        }
        self.scene
            .keep_apart(&mut world, &ids)
            .map_err(|e| locate(&e, None))?;
        // A gear is refused at its follower's `gear` (a robot's mimic
        // joints were checked in the robot's own file when it was read:
        // `read_urdf_parts` adds the robot to a scratch world).
        for g in &self.scene.gears {
            let path = self
                .joint_paths
                .get(g.follower)
                .cloned()
                .unwrap_or_else(FieldPath::root);
            let fail = |field: Option<&str>, message: String| {
                // (`gear.follower` is the joint itself: its `gear`.)
                let path = match field.and_then(|f| f.strip_prefix("gear.")) {
                    Some(rest) if rest != "follower" => path.key("gear").key(rest),
                    _ => path.key("gear"),
                };
                parse::locate_error(
                    &self.file,
                    &self.text,
                    self.format,
                    FieldError::new(&path, message),
                )
            };
            let (Some(&follower), Some(&leader)) = (joint_ids.get(g.follower), joint_ids.get(g.leader))
            else {
                return Err(fail(None, "its joints are not in the scene".into()));
            };
            let gear = Gear::new(leader, g.ratio).with_offset(g.offset);
            world.set_joint_gear(follower, Some(gear)).map_err(|e| match &e {
                crate::world::WorldError::BadValue { field, message } => fail(Some(field), message.clone()),
                other => fail(None, other.to_string()),
            })?;
        }
        Ok((world, ids))
    }
}

/// The JSON Schema of scene files (draft 2020-12), generated from
/// [`SceneFile`]; shipped as `docs/scene.schema.json`.
pub fn json_schema() -> String {
    let schema = schemars::schema_for!(SceneFile);
    // Serialising a schema (plain JSON values) cannot fail.
    let mut text = serde_json::to_string_pretty(&schema).unwrap_or_default();
    text.push('\n');
    text
}

#[cfg(test)]
mod tests;
