//! Scene parameters by path, for sweeps: `settings.dt`,
//! `bodies[ball].restitution`, `bodies[0].position[2]`. A path names a value
//! of the scene *file* (the document, before defaults and grids are
//! resolved), so every field a file can hold can be swept, under the name
//! the file gives it.
//!
//! Grammar: keys separated by dots, each followed by any number of
//! selectors in brackets: an index (`[2]`) or, in an array of tables, the
//! `name` of an element (`[ball]`). A missing last key (or a missing table
//! on the way) is created, so a value left to its default can be swept; a
//! missing element or an index past the end is an error naming the path and
//! the file. The scene with its values replaced is checked as a file is
//! (schema and values), and its errors name the parameters.

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::{parse_scene, Format, LoadedScene, SceneError};

/// One step of a [`ParamPath`].
#[derive(Debug, Clone, PartialEq)]
enum Segment {
    Key(String),
    Index(usize),
    Named(String),
}

/// A parsed parameter path.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamPath {
    text: String,
    segments: Vec<Segment>,
}

impl std::fmt::Display for ParamPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

impl std::str::FromStr for ParamPath {
    type Err = String;

    /// Parses `a.b[name].c[0]`; the error says what is wrong with the text.
    fn from_str(text: &str) -> Result<ParamPath, String> {
        let bad = |why: &str| {
            format!("parameter path {text:?}: {why} (expected keys and [index] or [name], e.g. bodies[ball].restitution)")
        };
        let mut segments = Vec::new();
        for part in text.split('.') {
            let key_end = part.find('[').unwrap_or(part.len());
            let key = &part[..key_end];
            if key.is_empty()
                || !key
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                return Err(bad(&format!("bad key {key:?}")));
            }
            segments.push(Segment::Key(key.to_string()));
            let mut rest = &part[key_end..];
            while !rest.is_empty() {
                let Some(close) = rest.find(']').filter(|_| rest.starts_with('[')) else {
                    return Err(bad(&format!("bad selector {rest:?}")));
                };
                let sel = rest[1..close].trim();
                if sel.is_empty() {
                    return Err(bad("empty []"));
                }
                segments.push(match sel.parse::<usize>() {
                    Ok(i) => Segment::Index(i),
                    Err(_) => Segment::Named(sel.trim_matches('"').to_string()),
                });
                rest = &rest[close + 1..];
            }
        }
        Ok(ParamPath {
            text: text.to_string(),
            segments,
        })
    }
}

impl ParamPath {
    /// Puts `value` at this path in `doc`.
    fn apply(&self, doc: &mut Value, value: Value) -> Result<(), String> {
        let mut here = doc;
        let mut walked = String::new();
        for (k, seg) in self.segments.iter().enumerate() {
            let last = k + 1 == self.segments.len();
            here = match seg {
                Segment::Key(key) => {
                    if !walked.is_empty() {
                        walked.push('.');
                    }
                    walked.push_str(key);
                    let Value::Object(map) = here else {
                        return Err(format!("{walked}: the scene has no table here"));
                    };
                    // Missing keys are created: a default value can be swept.
                    let next_is_selector = matches!(
                        self.segments.get(k + 1),
                        Some(Segment::Index(_) | Segment::Named(_))
                    );
                    if !map.contains_key(key) && next_is_selector {
                        return Err(format!("{walked}: the scene has no {key:?}"));
                    }
                    map.entry(key.clone()).or_insert_with(|| {
                        if last {
                            Value::Null
                        } else {
                            Value::Object(Default::default())
                        }
                    })
                }
                Segment::Index(i) => {
                    walked.push_str(&format!("[{i}]"));
                    let Value::Array(items) = here else {
                        return Err(format!("{walked}: not a list"));
                    };
                    let len = items.len();
                    items
                        .get_mut(*i)
                        .ok_or_else(|| format!("{walked}: index past the end (the list has {len} items)"))?
                }
                Segment::Named(name) => {
                    walked.push_str(&format!("[{name}]"));
                    let Value::Array(items) = here else {
                        return Err(format!("{walked}: not a list"));
                    };
                    let names: Vec<String> = items
                        .iter()
                        .filter_map(|v| v.get("name").and_then(Value::as_str).map(str::to_string))
                        .collect();
                    let found = items
                        .iter_mut()
                        .find(|v| v.get("name").and_then(Value::as_str) == Some(name.as_str()));
                    found.ok_or_else(|| {
                        format!(
                            "{walked}: no element named {name:?} (names: {})",
                            names.join(", ")
                        )
                    })?
                }
            };
        }
        *here = value;
        Ok(())
    }
}

/// A scene file held as its document, to be built with parameters replaced.
#[derive(Debug, Clone)]
pub struct SceneDocument {
    file: PathBuf,
    doc: Value,
}

impl SceneDocument {
    /// Reads the scene file and checks it as [`super::load_scene`] does
    /// (errors located in the file).
    pub fn load(path: impl AsRef<Path>) -> Result<SceneDocument, SceneError> {
        Self::from_loaded(super::load_scene(path.as_ref())?)
    }

    /// A scene given as text (as read from `file`, which names it in errors
    /// and whose directory is where mesh files are looked up): for a sweep's
    /// runs on another machine, which gets the text, not the file.
    pub fn parse(text: &str, format: Format, file: &Path) -> Result<SceneDocument, SceneError> {
        let loaded = parse_scene(text, format, file)?;
        Self::from_loaded(loaded)
    }

    fn from_loaded(loaded: LoadedScene) -> Result<SceneDocument, SceneError> {
        let file = loaded.file.clone();
        let doc: Result<Value, String> = match loaded.format {
            Format::Json => serde_json::from_str(&loaded.text).map_err(|e| e.to_string()),
            Format::Toml => toml::from_str(&loaded.text).map_err(|e| e.to_string()),
        };
        let doc = doc.map_err(|message| SceneError::Read {
            file: file.clone(),
            message,
        })?;
        Ok(SceneDocument { file, doc })
    }

    /// The scene file.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// The document (JSON data model) with `assignments` made, checked.
    pub fn document_with(&self, assignments: &[(ParamPath, Value)]) -> Result<Value, SceneError> {
        let mut doc = self.doc.clone();
        for (path, value) in assignments {
            path.apply(&mut doc, value.clone())
                .map_err(|message| SceneError::Param {
                    file: self.file.clone(),
                    param: path.to_string(),
                    message,
                })?;
        }
        Ok(doc)
    }

    /// The scene with `assignments` made, read and checked as a file. Its
    /// errors name the file and the assignments (a replaced value has no
    /// line in the file).
    pub fn with(&self, assignments: &[(ParamPath, Value)]) -> Result<LoadedScene, SceneError> {
        let doc = self.document_with(assignments)?;
        let text = serde_json::to_string_pretty(&doc).map_err(|e| SceneError::Read {
            file: self.file.clone(),
            message: e.to_string(),
        })?;
        parse_scene(&text, Format::Json, &self.file).map_err(|e| match e {
            SceneError::At { path, message, .. } => SceneError::Param {
                file: self.file.clone(),
                param: describe(assignments),
                message: if path.is_empty() {
                    message
                } else {
                    format!("{path}: {message}")
                },
            },
            other => other,
        })
    }
}

/// `a=1, b=[0, 0, 1]`.
pub fn describe(assignments: &[(ParamPath, Value)]) -> String {
    assignments
        .iter()
        .map(|(p, v)| format!("{p}={v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A value given on a command line: JSON where it parses (`0.5`, `true`,
/// `[0, 0, 1]`, `"text"`), a string otherwise (`box`).
pub fn value_from_text(text: &str) -> Value {
    serde_json::from_str(text.trim()).unwrap_or_else(|_| Value::String(text.trim().to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc() -> Value {
        serde_json::json!({
            "settings": {"dt": 0.01},
            "bodies": [{"name": "ground"}, {"name": "ball", "position": [0, 0, 1]}],
        })
    }

    fn set(path: &str, v: Value) -> Result<Value, String> {
        let mut d = doc();
        path.parse::<ParamPath>()?.apply(&mut d, v)?;
        Ok(d)
    }

    #[test]
    fn paths_reach_keys_indices_and_names_and_create_missing_keys() {
        assert_eq!(set("settings.dt", 0.02.into()).unwrap()["settings"]["dt"], 0.02);
        assert_eq!(
            set("bodies[ball].restitution", 0.5.into()).unwrap()["bodies"][1]["restitution"],
            0.5
        );
        assert_eq!(
            set("bodies[1].position[2]", 3.into()).unwrap()["bodies"][1]["position"][2],
            3
        );
        assert_eq!(
            set("settings.gravity", serde_json::json!([0, 0, -1])).unwrap()["settings"]["gravity"][2],
            -1
        );
        assert_eq!(set("steps", 7.into()).unwrap()["steps"], 7);
        assert_eq!(
            set("materials.rubber.friction", 1.into()).unwrap()["materials"]["rubber"]["friction"],
            1
        );
    }

    #[test]
    fn bad_paths_say_where_they_fail() {
        // One assertion per failing path with the message it must give, so a
        // failure names the path.
        assert!(set("bodies[rock].mass", 1.into())
            .unwrap_err()
            .contains("no element named \"rock\" (names: ground, ball)"));
        assert!(set("bodies[5].mass", 1.into())
            .unwrap_err()
            .contains("bodies[5]: index past the end"));
        assert!(set("joints[0].kind", 1.into())
            .unwrap_err()
            .contains("joints: the scene has no \"joints\""));
        assert!(set("settings.dt.x", 1.into())
            .unwrap_err()
            .contains("settings.dt.x: the scene has no table here"));
        for bad in ["", "a..b", "a[", "a[]", "a]", "bo dies.x"] {
            assert!(bad.parse::<ParamPath>().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn command_line_values_are_json_or_text() {
        assert_eq!(value_from_text("0.5"), serde_json::json!(0.5));
        assert_eq!(value_from_text("[0, 0, 1]"), serde_json::json!([0, 0, 1]));
        assert_eq!(value_from_text("box"), serde_json::json!("box"));
        assert_eq!(value_from_text("true"), serde_json::json!(true));
    }
}
