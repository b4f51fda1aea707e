//! Why an export failed, and the marker that carries a cancel out through
//! the writers' I/O errors.

use std::io;
use std::path::{Path, PathBuf};

use crate::animate::Stage;
use crate::atomic_file::io_reason;
use crate::scene::readable_bytes;

/// Why an export failed. Messages name the file or the ranges involved.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error(
        "{} outside the scene's timeline {start}..{end}: choose frames within it (or lengthen the timeline)",
        if first == last { format!("frame {first} is") } else { format!("frames {first}..{last} reach") }
    )]
    FramesOutsideTimeline { first: i32, last: i32, start: i32, end: i32 },
    #[error("the frame range {first}..{last} ends before it starts: give the smaller frame first")]
    EmptyRange { first: i32, last: i32 },
    #[error("the layer stack can only be left out of the animated stage; the {stage:?} stage has no layers")]
    LayersWithoutAnimation { stage: Stage },
    #[error("cannot write {path}: the directory {} does not exist", dir.display(), path = path.display())]
    MissingDirectory { path: PathBuf, dir: PathBuf },
    #[error(
        "{} is not a directory: an OBJ sequence is written into a directory (or name the files with OUT.obj)",
        path.display()
    )]
    NotADirectory { path: PathBuf },
    #[error("cannot write {}: {reason}", path.display())]
    Write {
        path: PathBuf,
        reason: String,
        #[source]
        source: io::Error,
    },
    #[error(
        "{} would take at least {} ({size_bytes} bytes), more than a GLB can hold (4 GiB): export to .gltf instead",
        path.display(),
        readable_bytes(*size_bytes)
    )]
    TooLarge { path: PathBuf, size_bytes: u64 },
    #[error(
        "{what} would take about {}, more than the {} limit: {remedy}",
        readable_bytes(*estimate_bytes),
        readable_bytes(*limit_bytes)
    )]
    OverSizeLimit { what: String, estimate_bytes: u64, limit_bytes: u64, remedy: String },
    #[error(
        "{what} would take about {} but the disk holding {} has only {} free: free some space or write elsewhere",
        readable_bytes(*estimate_bytes),
        dir.display(),
        readable_bytes(*free_bytes)
    )]
    NotEnoughSpace { what: String, estimate_bytes: u64, free_bytes: u64, dir: PathBuf },
    #[error(
        "{} is not a regular file (a device or a FIFO): a .gltf needs its .bin beside it, which Drape does not \
         make next to a special file; write a .glb, which holds everything, instead",
        path.display()
    )]
    SideFilesBesideSpecialFile { path: PathBuf },
    #[error(
        "{} already holds {count} frame{} of a {pattern} sequence that the new one does not replace ({} {frames}: \
         {files}): a loader would play them mixed with the new frames; write the sequence into another folder, \
         or replace the old one",
        dir.display(),
        if *count == 1 { "" } else { "s" },
        if *count == 1 { "frame" } else { "frames" }
    )]
    OldFrames {
        dir: PathBuf,
        /// The sequence's names, e.g. `curtain_####.obj`.
        pattern: String,
        count: usize,
        /// The old frames' numbers, e.g. `4–9`.
        frames: String,
        /// The first and last old file, e.g. `curtain_0004.obj … curtain_0009.obj`.
        files: String,
    },
    #[error(
        "cannot write {}{}: it is the same file on disk as {}, {input_role}, which would be lost: choose another \
         output",
        path.display(),
        what.as_deref().map(|what| format!(" ({what})")).unwrap_or_default(),
        input.display()
    )]
    OverwritesInput {
        path: PathBuf,
        /// What `path` is to the output, when it is not the output itself:
        /// `the base mesh beside x.pc2`.
        what: Option<String>,
        input: PathBuf,
        /// `the scene file`, `a file the scene reads`.
        input_role: &'static str,
    },
    #[error("the export was cancelled; nothing was written")]
    Cancelled,
}

impl ExportError {
    /// An I/O error while writing `path`; a cancel passed up through the writers stays a cancel.
    pub fn write(path: &Path, source: io::Error) -> ExportError {
        if is_cancel(&source) {
            return ExportError::Cancelled;
        }
        ExportError::Write { path: path.to_path_buf(), reason: io_reason(&source), source }
    }
}

/// The I/O error that carries a cancel out of a writer closure.
#[derive(Debug)]
struct CancelMarker;

impl std::fmt::Display for CancelMarker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the export was cancelled")
    }
}

impl std::error::Error for CancelMarker {}

pub(crate) fn cancel_error() -> io::Error {
    io::Error::new(io::ErrorKind::Interrupted, CancelMarker)
}

fn is_cancel(error: &io::Error) -> bool {
    error.get_ref().is_some_and(|inner| inner.is::<CancelMarker>())
}
