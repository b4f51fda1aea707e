//! Exporters: files for other tools, all written atomically.
//!
//! Single frames: [`write_obj`] (Wavefront OBJ), [`write_png`] and
//! [`GifWriter`] (rendered pictures). Animation: [`export_animation`] writes
//! the evaluated frames of a range as PC2 or MDD point caches (with the base
//! mesh as OBJ), glTF 2.0 with one morph target per frame, USD or an OBJ
//! sequence, streaming frame by frame with progress and cancel; see
//! [`animation`] for its guarantees and each format's module for its layout.
//! [`size`] estimates an export's size before it starts, and
//! [`check_export_size`] refuses one past [`MAX_EXPORT_BYTES`] or the free
//! space on its disk (the CLI's `--force` skips that check). [`check_output`]
//! refuses one that would write over a file it reads ([`InputFiles`]) or
//! leave an earlier sequence's frames mixed with its own ([`SequenceFiles`]).
//!
//! The files stack in one direction, none importing one that imports it
//! back: [`error`] at the bottom; [`job`] (the frames of an export, its
//! progress and cancel) and the output helpers (directories, side files
//! written atomically) on it; the formats ([`obj`], [`pc2`], [`mdd`],
//! [`gltf`], [`usd`], [`png`], [`gif`]) and [`sequence`] naming beside them;
//! the driver [`animation`] on top, with [`size`] reading its formats.
//!
//! The editor's File ▸ Export calls, for example:
//!
//! ```no_run
//! # use std::path::Path;
//! use drape::export::{AnimationFormat, ExportError, export_animation};
//! # let scene = drape::scene::load(Path::new("scenes/magic_carpet.ron")).unwrap();
//! let output = Path::new("carpet.glb");
//! let format = AnimationFormat::from_extension(output).expect("a known extension");
//! let timeline = &scene.timeline;
//! match export_animation(&scene, timeline.start..=timeline.end, output, format, &mut |done, total| {
//!     println!("{done}/{total}");
//!     true // false cancels
//! }) {
//!     Ok(summary) => println!("wrote {:?}", summary.files),
//!     Err(ExportError::Cancelled) => {}
//!     Err(error) => eprintln!("{error}"),
//! }
//! ```

pub mod animation;
pub mod error;
pub mod gif;
pub mod gltf;
pub mod job;
pub mod mdd;
pub mod obj;
mod output;
pub mod pc2;
pub mod png;
pub mod sequence;
pub mod size;
pub mod usd;

pub use crate::atomic_file::write_atomically;
pub use animation::{
    AnimationFormat, ExportOptions, ExportSummary, check_frames, check_output, export_animation,
    export_animation_using, export_animation_with,
};
pub use error::ExportError;
pub use gif::GifWriter;
pub use job::FrameSource;
pub use obj::write_obj;
pub use output::InputFiles;
pub use png::write_png;
pub use sequence::{OldFrames, SequenceFiles, check_sequence_dir, ensure_sequence_dir, sequence_file_name};
pub use size::{MAX_EXPORT_BYTES, SizeEstimate, check_export_size};
