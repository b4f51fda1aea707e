//! A numbered PNG sequence `DIR/STEM_0000.png …`: rendered on the calling
//! thread while a second thread encodes and writes the PNGs, staged in a
//! hidden directory and moved into place together at the end.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

use super::error::RenderJobError;
use super::request::{RENDER_REMEDY, frame_count};
use crate::atomic_file::{Committed, StagedFiles};
use crate::export::{
    InputFiles, MAX_EXPORT_BYTES, SequenceFiles, SizeEstimate, check_export_size, ensure_sequence_dir, write_png,
};
use crate::image::RgbaImage;
use crate::picture::SceneRenderer;
use crate::scene::{Scene, group_thousands, readable_bytes};

/// Where a PNG sequence goes and what it may do there.
pub struct SequenceTarget<'a> {
    /// `DIR/STEM_0000.png …` over the frames rendered.
    pub files: SequenceFiles,
    /// Files the render reads, never written over.
    pub inputs: &'a InputFiles,
    /// Removes an earlier sequence's frames that the new one does not write.
    pub replace: bool,
    /// Writes even past the size limit or the free space.
    pub force: bool,
}

/// Renders the frames of `target` and returns the files written (and the
/// earlier frames removed, when replacing). At most two finished frames
/// wait between the renderer and the writer, so memory stays bounded
/// however long the range.
///
/// Before anything is written the sequence's size is estimated as the first
/// frame's PNG size times the frame count, and refused past 8 GiB or the
/// free space on the disk unless `force`. The directory is created when
/// missing (not its parents). An error or a cancel leaves it as it was — no
/// new frames, no staging directory, and the directory itself removed
/// again when this call made it; never old and new frames mixed.
pub fn render_sequence(
    renderer: &mut SceneRenderer,
    scene: &Scene,
    target: &SequenceTarget,
    progress: &mut dyn FnMut(u64, u64),
    cancel: &AtomicBool,
) -> Result<Committed, RenderJobError> {
    let (dir, frames) = (target.files.dir.as_path(), target.files.frames.clone());
    let first_image = renderer.render_frame(scene, f64::from(*frames.start()))?;
    let mut first_png = Vec::new();
    write_png(&first_image, &mut first_png).map_err(|e| RenderJobError::write(dir, e))?;
    let count = frame_count(&frames);
    if !target.force {
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
    let written = render_staged(renderer, scene, target, first_image, progress, cancel);
    if written.is_err() && created_dir {
        let _ = std::fs::remove_dir(dir);
    }
    written
}

fn render_staged(
    renderer: &mut SceneRenderer,
    scene: &Scene,
    target: &SequenceTarget,
    first_image: RgbaImage,
    progress: &mut dyn FnMut(u64, u64),
    cancel: &AtomicBool,
) -> Result<Committed, RenderJobError> {
    let files = &target.files;
    let dir = files.dir.as_path();
    let mut staged = StagedFiles::new(dir, &files.name).map_err(|e| RenderJobError::into_dir(dir, &e))?;
    let frames = files.frames.clone();
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
    let rendered = render_frames(
        renderer,
        scene,
        files,
        first_image,
        &sender,
        &mut |done| {
            progress(done, total);
        },
        cancel,
    );
    drop(sender);
    let written = writer.join().map_err(|_| RenderJobError::WriterStopped)?;
    // Dropped uncommitted on an error or a cancel, the staging directory goes with its frames.
    let staged = rendered.and(written)?;
    // The folder may have changed while the frames were drawn.
    let old = files.check_directory(target.inputs, target.replace).map_err(RenderJobError::sequence)?;
    staged.commit_replacing(&old.names()).map_err(|e| RenderJobError::into_dir(dir, &e))
}

/// Draws each frame (the first is drawn already) and sends it to the writer
/// with its file name, stopping at a cancel, an error, or a writer that
/// stopped (whose error its join reports).
fn render_frames(
    renderer: &mut SceneRenderer,
    scene: &Scene,
    files: &SequenceFiles,
    first_image: RgbaImage,
    sender: &mpsc::SyncSender<(String, RgbaImage)>,
    progress: &mut dyn FnMut(u64),
    cancel: &AtomicBool,
) -> Result<(), RenderJobError> {
    let mut first_image = Some(first_image);
    for (done, frame) in files.frames.clone().enumerate() {
        if cancel.load(Ordering::Relaxed) {
            return Err(RenderJobError::Cancelled);
        }
        let image = match first_image.take() {
            Some(image) => image,
            None => renderer.render_frame(scene, f64::from(frame))?,
        };
        if sender.send((files.file_name(frame), image)).is_err() {
            return Ok(());
        }
        progress(done as u64 + 1);
    }
    Ok(())
}
