//! A render from request to files: [`RenderPlan::new`] checks everything it
//! can before the GPU starts (the frames, the output, the plate, a GIF's
//! size), [`RenderPlan::run`] renders and writes, reporting progress and
//! stopping at a cancel between frames.

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::error::RenderJobError;
use super::request::{MAX_SIDE_PX, RENDER_REMEDY, RenderKind, RenderRequest, frame_count};
use super::sequence::{SequenceTarget, render_sequence};
use crate::atomic_file::write_atomically;
use crate::export::error::cancel_error;
use crate::export::sequence::file_stem_for;
use crate::export::{
    GifWriter, InputFiles, MAX_EXPORT_BYTES, SequenceFiles, SizeEstimate, check_export_size, check_frames,
    check_sequence_dir, write_png,
};
use crate::picture::SceneRenderer;
use crate::render::GpuContext;
use crate::render::headless::RenderError;
use crate::scene::{PlateFiles, Scene, frame_list, group_thousands};

/// A checked render, ready to run.
pub struct RenderPlan<'a> {
    scene: &'a Scene,
    request: RenderRequest,
    /// File names of a sequence: `STEM_0000.png`.
    stem: String,
    /// The plate's files when the pictures are laid over it.
    plate: Option<PlateFiles>,
    /// The files the render reads, which it never writes over.
    inputs: InputFiles,
    warnings: Vec<String>,
}

/// What a finished render wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSummary {
    pub kind: RenderKind,
    /// The file, or the directory of a sequence.
    pub output: PathBuf,
    /// Every file written, in frame order.
    pub files: Vec<PathBuf>,
    pub frames: RangeInclusive<i32>,
    pub size_px: (u32, u32),
    /// The scene's frame rate (a GIF plays at it).
    pub fps: f64,
    /// From the first frame's start to the last file in place.
    pub elapsed: Duration,
    /// The GPU that drew, e.g. `llvmpipe (LLVM 15.0.7, 256 bits) on Vulkan`.
    pub adapter: String,
    /// What the render did that the user may not expect (plate frames shown
    /// from the nearest file), each a sentence without a `warning:` prefix.
    pub warnings: Vec<String>,
    /// Frames of an earlier sequence removed as the new one moved in
    /// ([`RenderRequest::replace_sequence`]), in frame order.
    pub removed: Vec<PathBuf>,
}

impl RenderSummary {
    pub fn frame_count(&self) -> u64 {
        frame_count(&self.frames)
    }

    pub fn frames_per_sec(&self) -> f64 {
        self.frame_count() as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

/// Checks `request` and renders `scene` to files, as [`RenderPlan::new`]
/// then [`RenderPlan::run`]; the warnings come back in the summary.
pub fn render_to_files(
    scene: &Scene,
    scene_path: Option<&Path>,
    request: &RenderRequest,
    context: Option<&GpuContext>,
    progress: &mut dyn FnMut(u64, u64),
    cancel: &AtomicBool,
) -> Result<RenderSummary, RenderJobError> {
    RenderPlan::new(scene, scene_path, request.clone())?.run(context, progress, cancel)
}

impl<'a> RenderPlan<'a> {
    /// Checks `request` against `scene` (loaded from `scene_path`, whose
    /// folder holds the plate and whose name names a sequence's files; an
    /// unsaved scene's plate is looked for in the working directory and its
    /// files named after the scene). Nothing is written and no GPU is
    /// opened. Refused: no output; a side of 0 or over [`MAX_SIDE_PX`];
    /// alpha or the shadow pass in a GIF; the plate asked of a scene without
    /// one, or whose files are not there; frames outside the timeline; a
    /// file whose folder, or a sequence whose parent folder, is missing; a
    /// sequence into something that is not a directory; a GIF whose size
    /// estimate (a byte a pixel) is over 8 GiB or the free disk space,
    /// unless the request forces it (a sequence's is checked once its first
    /// frame is drawn, in [`RenderPlan::run`]); an output that is a file the
    /// render reads (the scene file, a file it names, a plate picture shown),
    /// by identity on disk; a sequence into a folder holding frames of an
    /// earlier sequence of its name that it does not write, unless the
    /// request replaces them ([`RenderJobError::OldFrames`]).
    pub fn new(
        scene: &'a Scene,
        scene_path: Option<&Path>,
        request: RenderRequest,
    ) -> Result<RenderPlan<'a>, RenderJobError> {
        let output = request.output.as_path();
        if output.as_os_str().is_empty() {
            return Err(RenderJobError::NoOutput);
        }
        let (width, height) = request.size_px;
        if !(1..=MAX_SIDE_PX).contains(&width) || !(1..=MAX_SIDE_PX).contains(&height) {
            return Err(RenderJobError::BadSize(request.size_px));
        }
        let separate_pass = request.overlays.alpha || request.overlays.shadow_pass;
        if separate_pass && request.kind == RenderKind::Gif {
            return Err(RenderJobError::AlphaInGif);
        }
        if request.plate && scene.plate.is_none() {
            return Err(RenderJobError::NoPlate);
        }
        let frames = request.written_frames();
        check_frames(scene, *frames.start(), *frames.end()).map_err(RenderJobError::Output)?;
        match request.kind {
            RenderKind::Sequence => {
                if output.exists() && !output.is_dir() {
                    return Err(RenderJobError::NotADirectory(output.to_path_buf()));
                }
                check_sequence_dir(output).map_err(RenderJobError::Output)?;
            }
            RenderKind::Png | RenderKind::Gif => {
                if let Some(dir) = output.parent().filter(|d| !d.as_os_str().is_empty() && !d.is_dir()) {
                    let missing = crate::export::ExportError::MissingDirectory {
                        path: output.to_path_buf(),
                        dir: dir.to_path_buf(),
                    };
                    return Err(RenderJobError::Output(missing));
                }
            }
        }
        if request.kind == RenderKind::Gif && !request.force {
            // A GIF frame is at most a palette and one LZW-coded byte a pixel; cloth compresses far better.
            let frame_bytes = u64::from(width) * u64::from(height) + 1024;
            let count = frame_count(&frames);
            let what = format!(
                "the render (a GIF of {} frames at {width}×{height}, counted at a byte a pixel)",
                group_thousands(count)
            );
            let estimate = SizeEstimate::new(count.saturating_mul(frame_bytes), what, RENDER_REMEDY);
            check_export_size(&estimate, output, MAX_EXPORT_BYTES).map_err(RenderJobError::TooLarge)?;
        }
        let mut warnings = Vec::new();
        let plate = match (&scene.plate, request.plate && !separate_pass) {
            (Some(plate), true) => {
                let folder = scene_path.and_then(Path::parent).unwrap_or(Path::new(""));
                let files = PlateFiles::scan(plate, folder).map_err(|why| match scene_path {
                    Some(path) => RenderJobError::Plate(format!("{}: {why}", path.display())),
                    None => RenderJobError::Plate(format!("the plate: {why}")),
                })?;
                warnings.extend(missing_plate_frames(plate, &files, &frames));
                Some(files)
            }
            _ => None,
        };
        let stem = match scene_path.and_then(Path::file_stem).and_then(|s| s.to_str()) {
            Some(stem) => stem.to_owned(),
            None => file_stem_for(&scene.name),
        };
        let inputs = render_inputs(scene, scene_path, plate.as_ref(), &frames);
        match request.kind {
            RenderKind::Sequence => {
                let sequence = SequenceFiles::new(output, &stem, "png", frames);
                sequence.check_directory(&inputs, request.replace_sequence).map_err(RenderJobError::sequence)?;
            }
            RenderKind::Png | RenderKind::Gif => inputs.check(output, None).map_err(RenderJobError::Output)?,
        }
        Ok(RenderPlan { scene, request, stem, plate, inputs, warnings })
    }

    /// What the user should know before the render runs (see [`RenderSummary::warnings`]).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Renders on `context` (a headless device of its own when `None`) and
    /// writes the files. `progress(done, total)` is called as frames are
    /// drawn; `cancel`, checked between frames, stops the render with
    /// [`RenderJobError::Cancelled`] and nothing written (building the
    /// scene's rest shapes before the first frame is not interrupted).
    pub fn run(
        self,
        context: Option<&GpuContext>,
        progress: &mut dyn FnMut(u64, u64),
        cancel: &AtomicBool,
    ) -> Result<RenderSummary, RenderJobError> {
        let RenderPlan { scene, request, stem, plate, inputs, warnings } = self;
        let context = match context {
            Some(context) => context.clone(),
            None => GpuContext::headless().map_err(RenderError::from)?,
        };
        let adapter = context.describe();
        let mut renderer = SceneRenderer::new(context, scene, request.size_px, request.overlays);
        renderer.set_plate(plate.zip(scene.plate.as_ref().map(|p| p.opacity.clone())));
        let frames = request.written_frames();
        let total = frame_count(&frames);
        let cancelled = || cancel.load(Ordering::Relaxed);
        if cancelled() {
            return Err(RenderJobError::Cancelled);
        }
        progress(0, total);
        let started = Instant::now();
        let output = request.output.as_path();
        let mut removed = Vec::new();
        let files = match request.kind {
            RenderKind::Png => {
                let image = renderer.render_frame(scene, f64::from(*frames.start()))?;
                if cancelled() {
                    return Err(RenderJobError::Cancelled);
                }
                write_atomically(output, |w| write_png(&image, w)).map_err(|e| RenderJobError::write(output, e))?;
                progress(1, 1);
                vec![output.to_path_buf()]
            }
            RenderKind::Gif => {
                write_atomically(output, |w| {
                    let mut gif = GifWriter::new(w, request.size_px, scene.timeline.fps)?;
                    for (done, frame) in frames.clone().enumerate() {
                        if cancelled() {
                            return Err(cancel_error());
                        }
                        let image = renderer.render_frame(scene, f64::from(frame)).map_err(std::io::Error::other)?;
                        gif.write_frame(&image)?;
                        progress(done as u64 + 1, total);
                    }
                    gif.finish().map(|_| ())
                })
                .map_err(|e| RenderJobError::write(output, e))?;
                vec![output.to_path_buf()]
            }
            RenderKind::Sequence => {
                let target = SequenceTarget {
                    files: SequenceFiles::new(output, &stem, "png", frames.clone()),
                    inputs: &inputs,
                    replace: request.replace_sequence,
                    force: request.force,
                };
                let committed = render_sequence(&mut renderer, scene, &target, progress, cancel)?;
                removed = committed.removed;
                committed.files
            }
        };
        Ok(RenderSummary {
            kind: request.kind,
            output: output.to_path_buf(),
            files,
            frames,
            size_px: request.size_px,
            fps: scene.timeline.fps,
            elapsed: started.elapsed(),
            adapter,
            warnings,
            removed,
        })
    }
}

/// The files a render of `frames` reads: the scene's (see
/// [`InputFiles::of_scene`]) and the plate pictures those frames show.
fn render_inputs(
    scene: &Scene,
    scene_path: Option<&Path>,
    plate: Option<&PlateFiles>,
    frames: &RangeInclusive<i32>,
) -> InputFiles {
    let mut inputs = InputFiles::of_scene(scene, scene_path);
    if let Some(plate) = plate {
        let mut last_number = None;
        for frame in frames.clone() {
            let shown = plate.frame(frame);
            // Runs of frames holding one picture add it once.
            if last_number.replace(shown.number) != Some(shown.number) {
                inputs.add(&shown.path, "a plate picture the render reads");
            }
        }
    }
    inputs
}

/// The warning for the frames of `frames` whose plate file is missing (each
/// shows the nearest file's picture), or `None` when every one has its own.
fn missing_plate_frames(
    plate: &crate::scene::Plate,
    files: &PlateFiles,
    frames: &RangeInclusive<i32>,
) -> Option<String> {
    let (first, last) = (*frames.start(), *frames.end());
    let missing = files.missing(first, last);
    if missing.is_empty() {
        return None;
    }
    let one = missing.len() == 1;
    Some(format!(
        "the plate {:?} has no file for frame{} {} (of {first}..{last}): {} the nearest file's picture",
        plate.file,
        if one { "" } else { "s" },
        frame_list(&missing),
        if one { "it shows" } else { "each shows" },
    ))
}
