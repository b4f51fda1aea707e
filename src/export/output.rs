//! Where an export's files go: the directory that must exist, the names of
//! side files, a side file written atomically around the main one, and the
//! files an export reads, which it never writes over.

use std::path::{Path, PathBuf};

use super::error::ExportError;
use crate::atomic_file::{FileIdentity, stage_companion, unstage_companions, write_pending};
use crate::scene::{Collider, Scene};

/// The files an export or a render reads — the scene file and the files
/// the scene names — by identity on disk, so that an output that is one of
/// them under another name, a hard link or a symlink is refused too.
#[derive(Clone, Debug, Default)]
pub struct InputFiles {
    files: Vec<(FileIdentity, PathBuf, &'static str)>,
}

impl InputFiles {
    /// The scene file `scene_path` (none for a scene never saved) and the
    /// files its mesh colliders, references and plate (a single picture)
    /// name, relative to its folder.
    pub fn of_scene(scene: &Scene, scene_path: Option<&Path>) -> InputFiles {
        let mut inputs = InputFiles::default();
        if let Some(path) = scene_path {
            inputs.add(path, "the scene file");
        }
        let folder = scene_path.and_then(Path::parent).unwrap_or(Path::new(""));
        let named = scene
            .colliders
            .iter()
            .filter_map(|collider| match collider {
                Collider::Mesh(mesh) => Some(&mesh.file),
                _ => None,
            })
            .chain(scene.references.iter().map(|reference| &reference.file))
            .chain(scene.plate.iter().map(|plate| &plate.file));
        for file in named {
            inputs.add(&folder.join(file), "a file the scene reads");
        }
        inputs
    }

    /// Adds `path` when it leads to a regular file; `role` says what it is
    /// (`a file the scene reads`).
    pub fn add(&mut self, path: &Path, role: &'static str) {
        if let Some(identity) = FileIdentity::of(path) {
            self.files.push((identity, path.to_path_buf(), role));
        }
    }

    /// Refuses writing over (or removing) `path` when it is one of the
    /// inputs; `what` says what `path` is to the output when it is not the
    /// output itself (`the base mesh beside x.pc2`).
    pub fn check(&self, path: &Path, what: Option<String>) -> Result<(), ExportError> {
        let Some(identity) = FileIdentity::of(path) else { return Ok(()) };
        match self.files.iter().find(|(input, _, _)| *input == identity) {
            Some((_, input, input_role)) => {
                Err(ExportError::OverwritesInput { path: path.to_path_buf(), what, input: input.clone(), input_role })
            }
            None => Ok(()),
        }
    }
}

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
