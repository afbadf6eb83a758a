//! Text to [`SceneFile`]: TOML or JSON through serde, with the field path of
//! schema errors tracked by `serde_path_to_error` and their place taken from
//! the parser (`toml` spans, `serde_json` line and column) or, failing that,
//! from [`locate`](super::locate).

use std::path::Path;

use super::error::{FieldError, FieldPath, PathSeg, SceneError};
use super::locate::{line_column, locate};
use super::schema::SceneFile;
use super::Format;

/// A [`SceneError::At`] for `path` with `message`, at byte `offset` of `text`.
pub(crate) fn at_offset(
    file: &Path,
    text: &str,
    offset: usize,
    path: &FieldPath,
    message: String,
) -> SceneError {
    let (line, column) = line_column(text, offset);
    SceneError::At {
        file: file.to_path_buf(),
        line,
        column,
        path: path.to_string(),
        message,
    }
}

/// Locates a [`FieldError`] in the text.
pub(crate) fn locate_error(file: &Path, text: &str, format: Format, e: FieldError) -> SceneError {
    let offset = locate(text, format, &e.path);
    at_offset(file, text, offset, &e.path, e.message)
}

fn field_path(p: &serde_path_to_error::Path) -> FieldPath {
    use serde_path_to_error::Segment;
    FieldPath(
        p.iter()
            .filter_map(|s| match s {
                Segment::Seq { index } => Some(PathSeg::Index(*index)),
                Segment::Map { key } => Some(PathSeg::Key(key.clone())),
                Segment::Enum { .. } | Segment::Unknown => None,
            })
            .collect(),
    )
}

/// Deserializes `text` (in `format`) into the schema types.
pub(crate) fn parse_scene_text(text: &str, format: Format, file: &Path) -> Result<SceneFile, SceneError> {
    match format {
        Format::Toml => {
            let de = toml::Deserializer::parse(text).map_err(|e| {
                let offset = e.span().map_or(0, |s| s.start);
                at_offset(
                    file,
                    text,
                    offset,
                    &FieldPath::root(),
                    e.message().trim().to_string(),
                )
            })?;
            serde_path_to_error::deserialize::<_, SceneFile>(de).map_err(|e| {
                let path = field_path(e.path());
                let inner = e.into_inner();
                let offset = inner
                    .span()
                    .map_or_else(|| locate(text, format, &path), |s| s.start);
                at_offset(file, text, offset, &path, inner.message().trim().to_string())
            })
        }
        Format::Json => {
            let mut de = serde_json::Deserializer::from_str(text);
            let scene = serde_path_to_error::deserialize::<_, SceneFile>(&mut de).map_err(|e| {
                let path = field_path(e.path());
                json_error(file, text, &path, e.into_inner())
            })?;
            de.end()
                .map_err(|e| json_error(file, text, &FieldPath::root(), e))?;
            Ok(scene)
        }
    }
}

fn json_error(file: &Path, text: &str, path: &FieldPath, e: serde_json::Error) -> SceneError {
    let full = e.to_string();
    // serde_json appends " at line L column C"; the location goes in front instead.
    let message = match full.rsplit_once(" at line ") {
        Some((m, _)) if e.line() > 0 => m.to_string(),
        _ => full,
    };
    if e.line() > 0 {
        SceneError::At {
            file: file.to_path_buf(),
            line: e.line(),
            column: e.column().max(1),
            path: path.to_string(),
            message,
        }
    } else {
        let offset = locate(text, Format::Json, path);
        at_offset(file, text, offset, path, message)
    }
}
