//! The Python exception tree and the mapping of every Rust error onto it.
//!
//! ```text
//! TumbleError(Exception)                    base of everything tumble raises
//! ├── InvalidArgument(TumbleError, ValueError)   a bad value, shape, dtype or mesh
//! │   └── StaleBodyError(InvalidArgument, LookupError)  handle of a removed body
//! ├── SceneError(TumbleError, ValueError)    a bad scene file (file, line, column, field)
//! ├── FileError(TumbleError, OSError)        a file could not be read or written
//! └── InternalError(TumbleError)             a bug inside tumble (a caught panic)
//! ```
//!
//! Messages are the Rust errors' `Display` text, unchanged, so that the Rust
//! documentation of an error applies word for word in Python. Multiple
//! inheritance (`ValueError`, `OSError`) is why the classes are made with
//! `type(...)` at module initialisation instead of `create_exception!`.

use pyo3::exceptions::{PyException, PyLookupError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use std::panic::{catch_unwind, AssertUnwindSafe};
use tumble::export::ExportError;
use tumble::world::WorldError;
use tumble_collide::mass::MassError;
use tumble_collide::mesh::{GeneratorError, LoadError, MeshError};
use tumble_collide::ShapeError;

/// One of the exception classes of the module.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// `TumbleError`.
    Tumble,
    /// `InvalidArgument`.
    Invalid,
    /// `StaleBodyError`.
    Stale,
    /// `FileError`.
    File,
    /// `SceneError` (raised with its attributes by [`crate::scene`]).
    Scene,
    /// `InternalError`.
    Internal,
}

struct Classes {
    tumble: Py<PyType>,
    invalid: Py<PyType>,
    stale: Py<PyType>,
    file: Py<PyType>,
    scene: Py<PyType>,
    internal: Py<PyType>,
}

static CLASSES: PyOnceLock<Classes> = PyOnceLock::new();

fn make_class<'py>(
    py: Python<'py>,
    name: &str,
    bases: Vec<Bound<'py, PyType>>,
    doc: &str,
) -> PyResult<Bound<'py, PyType>> {
    let ns = PyDict::new(py);
    ns.set_item("__doc__", doc)?;
    ns.set_item("__module__", "tumble")?;
    let bases = PyTuple::new(py, bases)?;
    let class = py.get_type::<PyType>().call1((name, bases, ns))?;
    Ok(class.cast_into::<PyType>()?)
}

fn classes(py: Python<'_>) -> PyResult<&Classes> {
    CLASSES.get_or_try_init(py, || {
        // One call per class of the tree above: each names its own bases
        // (made just before it) and its Python docstring.
        let tumble = make_class(
            py,
            "TumbleError",
            vec![py.get_type::<PyException>()],
            "Base class of every error raised by tumble.",
        )?;
        let invalid = make_class(
            py,
            "InvalidArgument",
            vec![tumble.clone(), py.get_type::<PyValueError>()],
            "A bad argument: a value out of range or not finite, a wrong array shape or\n\
             dtype, an invalid mesh or shape. Also a ValueError.",
        )?;
        let stale = make_class(
            py,
            "StaleBodyError",
            vec![invalid.clone(), py.get_type::<PyLookupError>()],
            "A Body handle whose body was removed (or that belongs to no world).",
        )?;
        let file = make_class(
            py,
            "FileError",
            vec![tumble.clone(), py.get_type::<PyOSError>()],
            "A file could not be read or written. Also an OSError.",
        )?;
        let scene = make_class(
            py,
            "SceneError",
            vec![tumble.clone(), py.get_type::<PyValueError>()],
            "A scene file that cannot be loaded: a syntax or schema error, a bad value,\n\
             or a body the world refuses. The message is the command line's\n\
             (`file:line:column: field: reason`). Also a ValueError.\n\
             \n\
             Attributes:\n\
             \x20   file: the scene file, as given (str).\n\
             \x20   line: 1-based line of the offending value, or None.\n\
             \x20   column: 1-based column (in characters), or None.\n\
             \x20   field: the field path, e.g. \"bodies[3].mass\" (\"\" for syntax\n\
             \x20       errors, None when the error has no place in the file).\n\
             \x20   reason: what is wrong and what was expected, without the location.",
        )?;
        let internal = make_class(
            py,
            "InternalError",
            vec![tumble.clone()],
            "A bug inside tumble (an internal panic, caught). A World that raised it\n\
             during step() refuses further calls.",
        )?;
        Ok::<_, PyErr>(Classes {
            tumble: tumble.unbind(),
            invalid: invalid.unbind(),
            stale: stale.unbind(),
            file: file.unbind(),
            scene: scene.unbind(),
            internal: internal.unbind(),
        })
    })
}

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    let c = classes(py)?;
    m.add("TumbleError", c.tumble.bind(py))?;
    m.add("InvalidArgument", c.invalid.bind(py))?;
    m.add("StaleBodyError", c.stale.bind(py))?;
    m.add("FileError", c.file.bind(py))?;
    m.add("SceneError", c.scene.bind(py))?;
    m.add("InternalError", c.internal.bind(py))?;
    Ok(())
}

/// The exception class of `kind`.
pub fn class(py: Python<'_>, kind: Kind) -> PyResult<Bound<'_, PyType>> {
    let c = classes(py)?;
    let class = match kind {
        Kind::Tumble => &c.tumble,
        Kind::Invalid => &c.invalid,
        Kind::Stale => &c.stale,
        Kind::File => &c.file,
        Kind::Scene => &c.scene,
        Kind::Internal => &c.internal,
    };
    Ok(class.bind(py).clone())
}

/// A Python exception of `kind` with `message`.
pub fn error(kind: Kind, message: impl Into<String>) -> PyErr {
    let message = message.into();
    Python::attach(|py| match class(py, kind) {
        Ok(class) => PyErr::from_type(class, message),
        Err(e) => e,
    })
}

/// `InvalidArgument(message)`.
pub fn invalid(message: impl Into<String>) -> PyErr {
    error(Kind::Invalid, message)
}

/// Maps a Rust error to its Python exception (same message).
pub trait ToPyErr {
    /// The exception.
    fn to_py(&self) -> PyErr;
}

impl ToPyErr for WorldError {
    fn to_py(&self) -> PyErr {
        match self {
            WorldError::StaleBody(_) | WorldError::StaleJoint(_) => error(Kind::Stale, self.to_string()),
            _ => invalid(self.to_string()),
        }
    }
}

impl ToPyErr for tumble::joint::urdf::UrdfError {
    fn to_py(&self) -> PyErr {
        match self {
            tumble::joint::urdf::UrdfError::Read { .. } => error(Kind::File, self.to_string()),
            tumble::joint::urdf::UrdfError::At { .. } => invalid(self.to_string()),
        }
    }
}

impl ToPyErr for ShapeError {
    fn to_py(&self) -> PyErr {
        invalid(self.to_string())
    }
}

impl ToPyErr for MeshError {
    fn to_py(&self) -> PyErr {
        invalid(self.to_string())
    }
}

impl ToPyErr for GeneratorError {
    fn to_py(&self) -> PyErr {
        invalid(self.to_string())
    }
}

impl ToPyErr for MassError {
    fn to_py(&self) -> PyErr {
        match self {
            MassError::NonFiniteResult { .. } => error(Kind::Tumble, self.to_string()),
            _ => invalid(self.to_string()),
        }
    }
}

impl ToPyErr for LoadError {
    fn to_py(&self) -> PyErr {
        match self {
            LoadError::Io { .. } => error(Kind::File, self.to_string()),
            _ => invalid(self.to_string()),
        }
    }
}

impl ToPyErr for ExportError {
    fn to_py(&self) -> PyErr {
        match self {
            ExportError::Io { .. } => error(Kind::File, self.to_string()),
            _ => error(Kind::Tumble, self.to_string()),
        }
    }
}

/// `result.map_err(ToPyErr::to_py)` in one word.
pub trait OrRaise<T> {
    /// The value, or the error as a Python exception.
    fn or_raise(self) -> PyResult<T>;
}

impl<T, E: ToPyErr> OrRaise<T> for Result<T, E> {
    fn or_raise(self) -> PyResult<T> {
        self.map_err(|e| e.to_py())
    }
}

/// The text of a panic payload.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

/// The error for a world another thread holds (stepping with the GIL
/// released).
pub fn busy() -> PyErr {
    error(
        Kind::Tumble,
        "the world is in use by another thread (stepping); try again when step() returns",
    )
}

/// Runs `f`, turning a panic inside it into `InternalError` so that no
/// panic reaches Python as pyo3's `PanicException` (a `BaseException`).
pub fn guard<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => Err(error(
            Kind::Internal,
            format!("internal error in tumble: {}", panic_message(payload.as_ref())),
        )),
    }
}
