//! Trajectory table export: one row per (frame, body) with the pose in
//! tumble's world frame (z up), for plotting or regression diffs.

use std::fmt::Write as _;
use std::path::Path;

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
    Ok(out)
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
