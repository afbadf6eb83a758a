//! Trajectory table export: one row per (frame, body) with the pose in
//! tumble's world frame (z up), for plotting or regression diffs; written
//! whole ([`write_trajectory_csv`]) or streamed frame by frame while a run
//! goes ([`CsvStream`]), so that a killed process leaves every flushed chunk.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use super::atomic::write_atomic;
use super::recording::{ExportError, Recording};

/// Header line of [`trajectory_csv`].
pub const CSV_HEADER: &str = "t,body,x,y,z,qx,qy,qz,qw";

/// The trajectory as CSV text: header [`CSV_HEADER`], then frame-major rows
/// `t,body,x,y,z,qx,qy,qz,qw` (s, body name, m, unit quaternion). Numbers use
/// Rust's shortest round-trip formatting, so parsing gives back the same bits.
/// Body names containing a comma, quote or newline are quoted (RFC 4180).
pub fn trajectory_csv(rec: &Recording) -> Result<String, ExportError> {
    rec.validate()?;
    let names: Vec<String> = rec.bodies.iter().map(|b| quote(&b.name)).collect();
    let mut out = String::with_capacity(64 * rec.frames.len() * rec.bodies.len() + 32);
    out.push_str(CSV_HEADER);
    out.push('\n');
    for (t, poses) in rec.frame_times.iter().zip(&rec.frames) {
        frame_rows(&mut out, &names, *t, poses);
    }
    Ok(out)
}

/// Appends the rows of one frame.
fn frame_rows(out: &mut String, names: &[String], t: f64, poses: &[crate::collide::Pose]) {
    for (name, p) in names.iter().zip(poses) {
        let (x, q) = (p.position, p.rotation);
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "{t},{name},{},{},{},{},{},{},{}",
            x.x, x.y, x.z, q.x, q.y, q.z, q.w
        );
    }
}

/// A trajectory table written while the run goes: [`CsvStream::append`]
/// adds the frames recorded since the last call and flushes them, so the
/// file holds every appended frame whole even if the process is killed
/// (the rows are those of [`trajectory_csv`], in the same order).
#[derive(Debug)]
pub struct CsvStream {
    path: PathBuf,
    // Unbuffered: each chunk goes to the file in one write, so a killed
    // process leaves whole rows.
    file: std::fs::File,
    names: Vec<String>,
    frames_written: usize,
}

impl CsvStream {
    /// Creates (or truncates) `path` and writes the header.
    pub fn create(path: impl AsRef<Path>, rec: &Recording) -> Result<CsvStream, ExportError> {
        let path = path.as_ref().to_path_buf();
        let file = std::fs::File::create(&path).map_err(|source| ExportError::Io {
            path: path.clone(),
            source,
        })?;
        let mut stream = CsvStream {
            path,
            file,
            names: rec.bodies.iter().map(|b| quote(&b.name)).collect(),
            frames_written: 0,
        };
        stream.write(format!("{CSV_HEADER}\n").as_bytes())?;
        Ok(stream)
    }

    /// Appends the frames of `rec` not written yet and flushes them to the
    /// file (the bodies must be those `create` saw).
    pub fn append(&mut self, rec: &Recording) -> Result<(), ExportError> {
        let mut text = String::new();
        for f in self.frames_written..rec.frames.len() {
            frame_rows(&mut text, &self.names, rec.frame_times[f], &rec.frames[f]);
        }
        self.frames_written = rec.frames.len();
        self.write(text.as_bytes())?;
        self.file.flush().map_err(|source| ExportError::Io {
            path: self.path.clone(),
            source,
        })
    }

    /// Frames in the file so far.
    pub fn frames_written(&self) -> usize {
        self.frames_written
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn write(&mut self, bytes: &[u8]) -> Result<(), ExportError> {
        self.file.write_all(bytes).map_err(|source| ExportError::Io {
            path: self.path.clone(),
            source,
        })
    }
}

/// Writes [`trajectory_csv`] to `path` atomically.
pub fn write_trajectory_csv(rec: &Recording, path: impl AsRef<Path>) -> Result<(), ExportError> {
    let text = trajectory_csv(rec)?;
    write_atomic(path.as_ref(), text.as_bytes())
}

fn quote(name: &str) -> String {
    if name.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", name.replace('"', "\"\""))
    } else {
        name.to_string()
    }
}
