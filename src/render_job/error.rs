//! Why a render stopped. Every message names the file or the setting involved.

use std::io;
use std::path::{Path, PathBuf};

use crate::atomic_file::io_reason;
use crate::export::ExportError;
use crate::render::headless::RenderError;

#[derive(Debug, thiserror::Error)]
pub enum RenderJobError {
    #[error("no output was given: name a file, or a folder for a PNG sequence")]
    NoOutput,
    /// The cloth alone or its shadow pass was asked of a GIF.
    #[error("a GIF has no alpha channel: the cloth alone or its shadow is written as PNGs")]
    AlphaInGif,
    /// The plate was asked for but the scene has none.
    #[error("the scene has no background plate (`plate: (file: …)`)")]
    NoPlate,
    /// The plate's files are not there (the message names the scene and the file).
    #[error("{0}")]
    Plate(String),
    /// A side outside 1 to [`super::MAX_SIDE_PX`] pixels.
    #[error("a picture of {}×{} pixels cannot be rendered: each side must be 1 to {} pixels", .0.0, .0.1, super::MAX_SIDE_PX)]
    BadSize((u32, u32)),
    /// The output cannot be what the kind needs (frames outside the
    /// timeline, a sequence's directory whose parent is missing, …).
    #[error(transparent)]
    Output(ExportError),
    /// The size estimate is over the limit or the free space: held back
    /// unless the request forces it.
    #[error(transparent)]
    TooLarge(ExportError),
    /// The folder holds frames of an earlier sequence that the new one
    /// would leave mixed with its own: held back unless the request
    /// replaces the old sequence.
    #[error(transparent)]
    OldFrames(ExportError),
    #[error("{} is not a directory: a PNG sequence is written into a directory", .0.display())]
    NotADirectory(PathBuf),
    #[error(transparent)]
    Gpu(#[from] RenderError),
    #[error("cannot write {}: {reason}", path.display())]
    Write { path: PathBuf, reason: String },
    #[error("the PNG writer thread stopped unexpectedly")]
    WriterStopped,
    #[error("the render was cancelled; nothing was written")]
    Cancelled,
}

impl RenderJobError {
    /// An I/O error while writing `path`; a cancel carried out of a writer stays a cancel.
    pub(super) fn write(path: &Path, error: io::Error) -> RenderJobError {
        match ExportError::write(path, error) {
            ExportError::Cancelled => RenderJobError::Cancelled,
            ExportError::Write { reason, .. } => RenderJobError::Write { path: path.to_path_buf(), reason },
            other => RenderJobError::Output(other),
        }
    }

    /// A sequence's folder refused: [`RenderJobError::OldFrames`] for an
    /// earlier sequence's frames, else [`RenderJobError::Output`].
    pub(super) fn sequence(error: ExportError) -> RenderJobError {
        match error {
            ExportError::OldFrames { .. } => RenderJobError::OldFrames(error),
            other => RenderJobError::Output(other),
        }
    }

    /// An I/O error while moving files into `path` or making it.
    pub(super) fn into_dir(path: &Path, error: &io::Error) -> RenderJobError {
        RenderJobError::Write { path: path.to_path_buf(), reason: io_reason(error) }
    }
}
