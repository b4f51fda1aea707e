//! Where an export's files go: the directory that must exist, the names of
//! side files, and a side file written atomically around the main one.

use std::io;
use std::path::{Path, PathBuf};

use super::error::ExportError;
use crate::atomic_file::write_atomically;

/// The directory `path` will be written into must exist.
pub(crate) fn check_directory(path: &Path) -> Result<(), ExportError> {
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    if dir.is_dir() {
        Ok(())
    } else {
        Err(ExportError::MissingDirectory { path: path.to_path_buf(), dir: dir.to_path_buf() })
    }
}

/// `path` with its extension replaced, e.g. the `.obj` beside a `.pc2`.
pub(crate) fn sibling(path: &Path, extension: &str) -> PathBuf {
    path.with_extension(extension)
}

/// Writes `bytes` to `path` atomically around `inner` (the write of the
/// streamed main file): `path` is renamed into place only when `inner`
/// succeeded, and abandoned (temporary file removed) when it failed, so the
/// two appear together or not at all. Returns `inner`'s error first.
pub(crate) fn write_around(
    path: &Path,
    bytes: &[u8],
    inner: impl FnOnce() -> Result<(), ExportError>,
) -> Result<(), ExportError> {
    let mut inner_result = Ok(());
    let outer = write_atomically(path, |w| {
        w.write_all(bytes)?;
        inner_result = inner();
        match inner_result {
            Ok(()) => Ok(()),
            Err(_) => Err(io::Error::other("abandoned: the file it belongs with failed")),
        }
    });
    inner_result?;
    outer.map_err(|e| ExportError::write(path, e))
}
