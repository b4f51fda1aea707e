//! Where an export's files go: the directory that must exist, the names of
//! side files, and a side file written atomically around the main one.

use std::path::{Path, PathBuf};

use super::error::ExportError;
use crate::atomic_file::{stage_companion, unstage_companions, write_pending};

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
/// streamed main file): `path` moves into place in the same step as the main
/// file (one hold of a signal's clean-up, see
/// [`crate::atomic_file::stage_companion`]) when `inner` succeeded, and is
/// abandoned (temporary file removed) when it failed, so the two appear
/// together or not at all, Ctrl+C included. Returns `inner`'s error first.
pub(crate) fn write_around(
    path: &Path,
    bytes: &[u8],
    inner: impl FnOnce() -> Result<(), ExportError>,
) -> Result<(), ExportError> {
    let pending = write_pending(path, |w| w.write_all(bytes)).map_err(|e| ExportError::write(path, e))?;
    let staged_at = stage_companion(pending);
    let inner_result = inner();
    // Still staged if `inner` failed, or wrote its file without `write_atomically`.
    let left = unstage_companions(staged_at);
    inner_result?;
    for file in left {
        file.commit().map_err(|e| ExportError::write(path, e))?;
    }
    Ok(())
}
