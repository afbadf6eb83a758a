//! Errors of scene files: every one names the file, the line and column of
//! the offending value, and the field path (`bodies[3].mass`), in one line:
//!
//! ```text
//! scenes/pile.toml:12:8: bodies[3].mass: must be finite and > 0 kg, got -1
//! ```

use std::fmt;
use std::path::PathBuf;

/// One step of a field path: a table key or an array index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PathSeg {
    /// A key of a table / object.
    Key(String),
    /// An index into an array.
    Index(usize),
}

/// A field path such as `bodies[3].shapes[0].radius`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FieldPath(pub Vec<PathSeg>);

impl FieldPath {
    /// The empty path (the whole document).
    pub fn root() -> FieldPath {
        FieldPath(Vec::new())
    }

    /// This path extended by a key.
    pub fn key(&self, key: &str) -> FieldPath {
        let mut p = self.clone();
        p.0.push(PathSeg::Key(key.to_string()));
        p
    }

    /// This path extended by an index.
    pub fn index(&self, index: usize) -> FieldPath {
        let mut p = self.clone();
        p.0.push(PathSeg::Index(index));
        p
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, seg) in self.0.iter().enumerate() {
            match seg {
                PathSeg::Key(k) if i == 0 => write!(f, "{k}")?,
                PathSeg::Key(k) => write!(f, ".{k}")?,
                PathSeg::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// An error at a field, before it is located in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldError {
    /// Where.
    pub path: FieldPath,
    /// What is wrong and what was expected.
    pub message: String,
}

impl FieldError {
    /// An error at `path`.
    pub fn new(path: &FieldPath, message: impl Into<String>) -> FieldError {
        FieldError {
            path: path.clone(),
            message: message.into(),
        }
    }
}

/// Why a scene file could not be loaded or built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{file}: cannot read: {message}")]
    Read {
        /// The scene file.
        file: PathBuf,
        /// The operating system's reason.
        message: String,
    },
    /// The extension is neither `.toml` nor `.json`.
    #[error("{file}: unknown scene format (expected a .toml or .json file)")]
    Format {
        /// The scene file.
        file: PathBuf,
    },
    /// Syntax, schema or value error at a place in the file.
    #[error("{}", located(file, *line, *column, path, message))]
    At {
        /// The scene file.
        file: PathBuf,
        /// Line, 1-based.
        line: usize,
        /// Column in characters, 1-based.
        column: usize,
        /// Field path (`bodies[3].mass`); empty for syntax errors.
        path: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A scene parameter (a sweep's `bodies[ball].restitution = 2`) that
    /// cannot be set, or makes the scene invalid.
    #[error("{file}: {param}: {message}")]
    Param {
        /// The scene file.
        file: PathBuf,
        /// The parameter path, or the assignments of the run.
        param: String,
        /// What is wrong and what was expected.
        message: String,
    },
}

fn located(file: &std::path::Path, line: usize, column: usize, path: &str, message: &str) -> String {
    if path.is_empty() {
        format!("{}:{line}:{column}: {message}", file.display())
    } else {
        format!("{}:{line}:{column}: {path}: {message}", file.display())
    }
}
