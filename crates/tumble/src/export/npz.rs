//! Trajectory export as a NumPy `.npz` archive (`numpy.load` reads it): a zip
//! of `.npy` arrays, stored uncompressed, written with `npyz` and `zip`.
//!
//! | array | dtype | shape | meaning |
//! | --- | --- | --- | --- |
//! | `time` | `<f8` | (F,) | frame times (s) |
//! | `position` | `<f8` | (F, N, 3) | origin of each body's model frame in the world (m, z up), as `World::pose` reports it |
//! | `orientation` | `<f8` | (F, N, 4) | model-frame orientation, unit quaternion (x, y, z, w) |
//! | `names` | `<U*` | (N,) | body names |
//!
//! F frames, N bodies, in the order of the [`Recording`].

use std::io::{Cursor, Write};
use std::path::Path;

use npyz::WriterBuilder;

use super::atomic::write_atomic;
use super::recording::{ExportError, Recording};

fn npy_f64(data: impl Iterator<Item = f64>, shape: &[u64]) -> std::io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(shape)
        .writer(&mut bytes)
        .begin_nd()?;
    w.extend(data)?;
    w.finish()?;
    Ok(bytes)
}

fn npy_names(names: &[&str]) -> std::io::Result<Vec<u8>> {
    // numpy's fixed-width unicode: as many code points as the longest name (>= 1).
    let width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0).max(1);
    let dtype = npyz::DType::Plain(
        format!("<U{width}")
            .parse::<npyz::TypeStr>()
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e.to_string()))?,
    );
    let mut bytes = Vec::new();
    let mut w = npyz::WriteOptions::<str>::new()
        .dtype(dtype)
        .shape(&[names.len() as u64])
        .writer(&mut bytes)
        .begin_nd()?;
    for n in names {
        w.push(n)?;
    }
    w.finish()?;
    Ok(bytes)
}

/// The `.npz` archive of `rec`'s trajectory, in memory.
pub fn trajectory_npz(rec: &Recording) -> Result<Vec<u8>, ExportError> {
    rec.validate()?;
    let io = |source: std::io::Error| ExportError::Io {
        path: "<npz archive>".into(),
        source,
    };
    let (f, n) = (rec.frames.len() as u64, rec.bodies.len() as u64);
    let names: Vec<&str> = rec.bodies.iter().map(|b| b.name.as_str()).collect();
    let arrays = [
        (
            "time.npy",
            npy_f64(rec.frame_times.iter().copied(), &[f]).map_err(io)?,
        ),
        (
            "position.npy",
            npy_f64(
                rec.frames.iter().flatten().flat_map(|p| p.position.to_array()),
                &[f, n, 3],
            )
            .map_err(io)?,
        ),
        (
            "orientation.npy",
            npy_f64(
                rec.frames.iter().flatten().flat_map(|p| p.rotation.to_array()),
                &[f, n, 4],
            )
            .map_err(io)?,
        ),
        ("names.npy", npy_names(&names).map_err(io)?),
    ];
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(arrays.iter().map(|a| a.1.len()).sum::<usize>() > u32::MAX as usize / 2);
    let zerr = |e: zip::result::ZipError| io(std::io::Error::other(e.to_string()));
    for (name, bytes) in &arrays {
        zip.start_file(*name, options).map_err(zerr)?;
        zip.write_all(bytes).map_err(io)?;
    }
    Ok(zip.finish().map_err(zerr)?.into_inner())
}

/// Writes [`trajectory_npz`] to `path` atomically.
pub fn write_trajectory_npz(rec: &Recording, path: impl AsRef<Path>) -> Result<(), ExportError> {
    let bytes = trajectory_npz(rec)?;
    write_atomic(path.as_ref(), &bytes)
}
