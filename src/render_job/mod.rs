//! A scene rendered to files — one PNG, a numbered PNG sequence or an
//! animated GIF — frame by frame, with progress and cancel: the one
//! implementation behind `drape render` and the editor's File ▸ Render….
//!
//! It sits above [`crate::picture`] (a scene at a frame to an image) and
//! [`crate::export`] (PNG and GIF encoders, sequence naming, size checks),
//! which may not import each other:
//!
//! - [`request`]: what to render ([`RenderRequest`], [`RenderKind`]) and the
//!   default picture sizes;
//! - [`error`]: why a render stopped ([`RenderJobError`]);
//! - [`plan`]: the checks made before any GPU work ([`RenderPlan::new`]) and
//!   the render itself ([`RenderPlan::run`], [`render_to_files`]);
//! - [`sequence`]: the PNG sequence, staged and written on a second thread.
//!
//! Nothing is left half written: a single PNG or GIF goes through
//! [`crate::atomic_file::write_atomically`], a sequence through
//! [`crate::atomic_file::StagedFiles`]; an error or a cancel leaves the
//! output as it was.
//!
//! ```no_run
//! # use std::path::Path;
//! # use std::sync::atomic::AtomicBool;
//! use drape::render_job::{RenderKind, RenderRequest, render_to_files};
//! # let path = Path::new("scenes/flag.ron");
//! # let scene = drape::scene::load(path).unwrap();
//! let request = RenderRequest::new(RenderKind::Sequence, "frames".into(), 0..=23, (640, 360));
//! let cancel = AtomicBool::new(false);
//! let summary = render_to_files(&scene, Some(path), &request, None, &mut |done, total| {
//!     println!("{done}/{total}");
//! }, &cancel);
//! ```

pub mod error;
pub mod plan;
pub mod request;
pub mod sequence;

pub use error::RenderJobError;
pub use plan::{RenderPlan, RenderSummary, render_to_files};
pub use request::{DEFAULT_GIF_SIZE, DEFAULT_PNG_SIZE, MAX_SIDE_PX, RenderKind, RenderRequest, default_size_px};
