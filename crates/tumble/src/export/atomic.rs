//! Atomic file writes: the bytes go to a temporary file in the destination's
//! directory, are flushed to disk, and the file is renamed over the
//! destination. A rename within one directory is atomic on POSIX file systems,
//! so a viewer polling the file sees either the old or the new content.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::recording::ExportError;

/// Writes `bytes` to `path` atomically (temp file in the same directory, then
/// rename). The temporary file is removed if anything fails.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ExportError> {
    let io = |source| ExportError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file_name = path.file_name().ok_or_else(|| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "path has no file name",
        ))
    })?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    // The process id keeps two processes writing the same file from sharing a
    // temporary name.
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(file_name);
    tmp_name.push(format!(".tmp{}", std::process::id()));
    let tmp = dir.join(tmp_name);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io(e));
    }
    Ok(())
}
