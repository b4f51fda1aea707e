//! A numbered PNG sequence `DIR/STEM_0000.png …`: rendered on the calling
//! thread while a second thread encodes and writes the PNGs, staged in a
//! hidden directory and moved into place together at the end.

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

use super::error::RenderJobError;
use super::request::{RENDER_REMEDY, frame_count};
use crate::atomic_file::StagedFiles;
use crate::export::sequence::{frame_number_width, padded_frame};
use crate::export::{MAX_EXPORT_BYTES, SizeEstimate, check_export_size, ensure_sequence_dir, write_png};
use crate::image::RgbaImage;
use crate::picture::SceneRenderer;
use crate::scene::{Scene, group_thousands, readable_bytes};

/// Renders `frames` of `scene` into `dir` as `STEM_NNNN.png` and returns the
/// files written. At most two finished frames wait between the renderer and
/// the writer, so memory stays bounded however long the range.
///
/// Before anything is written the sequence's size is estimated as the first
/// frame's PNG size times the frame count, and refused past 8 GiB or the
/// free space on the disk unless `force`. `dir` is created when missing (not
/// its parents). An error or a cancel leaves `dir` as it was — no new
/// frames, no staging directory, and `dir` itself removed again when this
/// call made it; never old and new frames mixed.
#[allow(clippy::too_many_arguments)]
pub fn render_sequence(
    renderer: &mut SceneRenderer,
    scene: &Scene,
    stem: &str,
    dir: &Path,
    frames: RangeInclusive<i32>,
    force: bool,
    progress: &mut dyn FnMut(u64, u64),
    cancel: &AtomicBool,
) -> Result<Vec<PathBuf>, RenderJobError> {
    let first_image = renderer.render_frame(scene, f64::from(*frames.start()))?;
    let mut first_png = Vec::new();
    write_png(&first_image, &mut first_png).map_err(|e| RenderJobError::write(dir, e))?;
    let count = frame_count(&frames);
    if !force {
        let what = format!(
            "the render (a PNG sequence of {} frames at {}×{}, {} each as the first frame is)",
            group_thousands(count),
            first_image.width,
            first_image.height,
            readable_bytes(first_png.len() as u64)
        );
        let estimate = SizeEstimate::new(count.saturating_mul(first_png.len() as u64), what, RENDER_REMEDY);
        check_export_size(&estimate, dir, MAX_EXPORT_BYTES).map_err(RenderJobError::TooLarge)?;
    }
    let created_dir = ensure_sequence_dir(dir).map_err(RenderJobError::Output)?;
    let written = render_staged(renderer, scene, stem, dir, frames, first_image, progress, cancel);
    if written.is_err() && created_dir {
        let _ = std::fs::remove_dir(dir);
    }
    written
}

#[allow(clippy::too_many_arguments)]
fn render_staged(
    renderer: &mut SceneRenderer,
    scene: &Scene,
    stem: &str,
    dir: &Path,
    frames: RangeInclusive<i32>,
    first_image: RgbaImage,
    progress: &mut dyn FnMut(u64, u64),
    cancel: &AtomicBool,
) -> Result<Vec<PathBuf>, RenderJobError> {
    let mut staged = StagedFiles::new(dir, stem).map_err(|e| RenderJobError::into_dir(dir, &e))?;
    let width = frame_number_width(*frames.start(), *frames.end());
    let total = frame_count(&frames);
    let (sender, receiver) = mpsc::sync_channel::<(String, RgbaImage)>(2);
    let target_dir = dir.to_path_buf();
    let writer = std::thread::spawn(move || -> Result<StagedFiles, RenderJobError> {
        for (file_name, image) in receiver {
            staged
                .write(&file_name, |w| write_png(&image, w))
                .map_err(|e| RenderJobError::write(&target_dir.join(&file_name), e))?;
        }
        Ok(staged)
    });
    let mut rendered = Ok(());
    let mut first_image = Some(first_image);
    for (done, frame) in frames.enumerate() {
        if cancel.load(Ordering::Relaxed) {
            rendered = Err(RenderJobError::Cancelled);
            break;
        }
        let image = match first_image.take().map_or_else(|| renderer.render_frame(scene, f64::from(frame)), Ok) {
            Ok(image) => image,
            Err(error) => {
                rendered = Err(error.into());
                break;
            }
        };
        let file_name = format!("{stem}_{}.png", padded_frame(frame, width));
        // A send fails only when the writer stopped on an error, which join reports.
        if sender.send((file_name, image)).is_err() {
            break;
        }
        progress(done as u64 + 1, total);
    }
    drop(sender);
    let written = writer.join().map_err(|_| RenderJobError::WriterStopped)?;
    // Dropped uncommitted on an error or a cancel, the staging directory goes with its frames.
    let staged = rendered.and(written)?;
    staged.commit().map_err(|e| RenderJobError::into_dir(dir, &e))
}
