//! `tumble.load_scene(path)`: a scene file (TOML or JSON, docs/scenes.md)
//! read and built by `tumble::scene`, wrapped as a `World` whose rows are the
//! bodies in the file's order (grid copies k, then j, then i), so that
//! `world.find(name)` and the arrays see what `tumble run` simulates.
//!
//! Errors: a file that cannot be read is a `FileError` (an `OSError`, as
//! for `open()`); everything else is a `SceneError` (a `ValueError`) with the
//! message of the command line (`file:line:column: field: reason`) and the
//! parts as attributes `file`, `line`, `column`, `field`, `reason`.

use crate::errors::{class, error, guard, Kind, OrRaise, ToPyErr};
use crate::world::World;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use tumble::scene::SceneError;

/// A `SceneError` with its attributes (`None` where the error has no place
/// in the file).
fn scene_error(
    py: Python<'_>,
    e: &SceneError,
    file: &Path,
    at: Option<(usize, usize, &str, &str)>,
) -> PyResult<PyErr> {
    let exc = class(py, Kind::Scene)?.call1((e.to_string(),))?;
    exc.setattr("file", file.display().to_string())?;
    let (line, column, field, reason) = match at {
        Some((l, c, f, r)) => (Some(l), Some(c), Some(f.to_string()), r.to_string()),
        None => (None, None, None, e.to_string()),
    };
    exc.setattr("line", line)?;
    exc.setattr("column", column)?;
    exc.setattr("field", field)?;
    exc.setattr("reason", reason)?;
    Ok(PyErr::from_value(exc))
}

impl ToPyErr for SceneError {
    fn to_py(&self) -> PyErr {
        Python::attach(|py| {
            let made = match self {
                SceneError::Read { .. } => return error(Kind::File, self.to_string()),
                SceneError::Format { file } => scene_error(py, self, file, None),
                SceneError::At {
                    file,
                    line,
                    column,
                    path,
                    message,
                } => scene_error(py, self, file, Some((*line, *column, path, message))),
                SceneError::Param { file, .. } => scene_error(py, self, file, None),
            };
            made.unwrap_or_else(|e| e)
        })
    }
}

/// Loads a scene file (``.toml`` or ``.json``, see docs/scenes.md) into a new
/// World: its settings, materials and bodies, with the initial forces and
/// torques applied for the first step.
///
/// Bodies are the rows of the world's arrays in the file's order (a ``grid``
/// entry adds its copies k outermost, then j, then i); find them by name with
/// ``world.find(name)``. Mesh files are looked up relative to the scene
/// file. The number of steps or duration of the file is for ``tumble run``;
/// step the world as long as you like.
///
/// Args:
///     path: the scene file (str or path-like).
///
/// Returns:
///     World: the built world at time 0.
///
/// Raises:
///     SceneError: syntax or schema error, bad value, or a body the world
///         refuses; the message is the command line's
///         (``file:line:column: field: reason``), the parts are the
///         attributes ``file``, ``line``, ``column``, ``field``, ``reason``.
///     FileError: the file cannot be read.
#[pyfunction]
#[pyo3(signature = (path))]
pub fn load_scene(py: Python<'_>, path: PathBuf) -> PyResult<World> {
    guard(|| {
        let built = py.detach(|| tumble::scene::load_scene(&path).and_then(|s| s.build()));
        let (world, ids) = built.or_raise()?;
        Ok(World::from_parts(world, ids))
    })
}
