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
//! space on its disk (the CLI's `--force` skips that check).
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
pub mod gif;
pub mod gltf;
pub mod mdd;
pub mod obj;
pub mod pc2;
pub mod png;
pub mod size;
pub mod usd;

pub use crate::atomic_file::write_atomically;
pub use animation::{
    AnimationFormat, ExportError, ExportOptions, ExportSummary, FrameSource, check_frames, check_sequence_dir,
    ensure_sequence_dir, export_animation, export_animation_using, export_animation_with, sequence_file_name,
};
pub use gif::GifWriter;
pub use obj::write_obj;
pub use png::write_png;
pub use size::{MAX_EXPORT_BYTES, SizeEstimate, check_export_size};
