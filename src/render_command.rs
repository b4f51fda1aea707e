//! `drape render`: pictures of a scene as a PNG, a numbered PNG sequence or an animated GIF.

use std::io;
use std::path::Path;
use std::sync::mpsc;
use std::time::Instant;

use anyhow::{Context as _, Result, anyhow, bail};
use drape::atomic_file::StagedFiles;
use drape::atomic_file::io_reason;
use drape::export::{
    GifWriter, SizeEstimate, check_frames, check_sequence_dir, ensure_sequence_dir, write_atomically, write_png,
};
use drape::image::RgbaImage;
use drape::picture::{SceneOverlays, SceneRenderer};
use drape::render::GpuContext;
use drape::scene::{self, PlateFiles, Scene, frame_list, group_thousands, readable_bytes};

use crate::terminal_progress;
use crate::{FrameRange, frame_number_width, padded_frame};

/// Sizes used when `--size` is not given: a full-HD-ish still, a lighter GIF.
pub const DEFAULT_PNG_SIZE: (u32, u32) = (1280, 720);
pub const DEFAULT_GIF_SIZE: (u32, u32) = (640, 360);
/// How to make a sequence or GIF smaller, for a refusal of its size.
const RENDER_REMEDY: &str = "render fewer frames or smaller pictures";
/// Largest side accepted by `--size`.
pub const MAX_SIDE_PX: u32 = 8192;

pub struct RenderRequest {
    pub frame: Option<i32>,
    pub frames: Option<FrameRange>,
    pub size_px: Option<(u32, u32)>,
    pub overlays: SceneOverlays,
    /// `--camera shot`: the scene must have a shot camera.
    pub shot: bool,
    /// `--plate` (`Some(true)`: the scene must have a plate), `--no-plate`
    /// (`Some(false)`), or neither: the plate when looking through the shot camera.
    pub plate: Option<bool>,
    /// Write a sequence or GIF even when its size estimate is over the limit or the free space.
    pub force: bool,
}

/// How a render draws the cloth (`--style`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum StyleChoice {
    /// Lit: key, fill, sky and rim lights.
    Lit,
    /// Flat tone bands and ink lines, in the scene's toon settings.
    Toon,
}

/// Which camera a render looks through (`--camera`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CameraChoice {
    /// The framing view: the scene's saved view, or one that frames every key.
    View,
    /// The scene's shot camera.
    Shot,
}

/// What a render draws (`--pass`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Pass {
    /// The cloth, its surroundings and the plate, as the options say.
    Cloth,
    /// The cloth's shadow on the ground alone, black with alpha.
    Shadow,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Output {
    Png,
    Gif,
    Sequence,
}

/// Parses `WxH`, e.g. `1280x720`.
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X', '×'])
        .ok_or_else(|| format!("`{text}` is not a size: write it as WIDTHxHEIGHT, e.g. 1280x720"))?;
    let side = |s: &str| match s.trim().parse::<u32>() {
        Ok(v) if (1..=MAX_SIDE_PX).contains(&v) => Ok(v),
        _ => Err(format!("`{s}` in `{text}` is not a side of 1 to {MAX_SIDE_PX} pixels")),
    };
    Ok((side(w)?, side(h)?))
}

pub fn render(path: &Path, output: &Path, request: RenderRequest) -> Result<()> {
    let scene = scene::load(path)?;
    let extension = output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let kind = match (extension.as_deref(), request.frames.is_some()) {
        (Some("gif"), _) => Output::Gif,
        (Some("png"), false) => Output::Png,
        (Some("png"), true) => bail!(
            "--frames writes a numbered PNG sequence into a directory, but {} names a PNG file: \
             give a directory, or a .gif for an animation",
            output.display()
        ),
        (None, true) => Output::Sequence,
        (None, false) => {
            bail!("{} has no extension: name it .png or .gif (or give --frames for a sequence)", output.display())
        }
        (Some(other), _) => bail!("cannot render to .{other} ({}): use .png, .gif or a directory", output.display()),
    };
    if request.overlays.alpha && kind == Output::Gif {
        bail!("--alpha writes PNGs (a GIF has no alpha channel): name a .png, or a directory with --frames");
    }
    if request.overlays.shadow_pass && kind == Output::Gif {
        bail!("--pass shadow writes PNGs with alpha (a GIF has none): name a .png, or a directory with --frames");
    }
    if request.plate == Some(true) {
        if scene.plate.is_none() {
            bail!("--plate: the scene has no background plate (`plate: (file: …)`)");
        }
        if request.overlays.alpha || request.overlays.shadow_pass {
            bail!(
                "--plate with --alpha or --pass shadow: those are the cloth or its shadow alone, to composite \
                 over the plate; leave out --plate"
            );
        }
    }
    if request.shot && scene.camera.is_none() {
        bail!("--camera shot: the scene has no shot camera (`camera: (position: …, target: …)`)");
    }
    let shot_size = scene.camera.as_ref().filter(|_| !request.overlays.view_camera).map(|c| c.image_size);
    let default_size = match shot_size {
        Some(size) => size,
        None if kind == Output::Gif => DEFAULT_GIF_SIZE,
        None => DEFAULT_PNG_SIZE,
    };
    let size_px = request.size_px.unwrap_or(default_size);
    let start = scene.timeline.start;
    let range = match (request.frames, request.frame, kind) {
        (Some(range), _, _) => range,
        (None, frame, Output::Png) => {
            let frame = frame.unwrap_or(start);
            FrameRange { first: frame, last: frame }
        }
        // A GIF without --frames shows the whole timeline.
        (None, _, _) => FrameRange { first: start, last: scene.timeline.end },
    };
    // The frames and the directory `drape export` would accept, refused with its messages.
    check_frames(&scene, range.first, range.last)?;
    if kind == Output::Sequence {
        if output.exists() && !output.is_dir() {
            bail!("{} is not a directory: --frames writes a numbered sequence into a directory", output.display());
        }
        check_sequence_dir(output)?;
    }

    let frame_count = range.frame_count();
    if kind == Output::Gif {
        // A GIF frame is at most a palette and one LZW-coded byte a pixel; cloth compresses far better.
        let frame_bytes = u64::from(size_px.0) * u64::from(size_px.1) + 1024;
        let estimate = SizeEstimate::new(
            frame_count * frame_bytes,
            format!(
                "the render (a GIF of {} frames at {}×{}, counted at a byte a pixel)",
                group_thousands(frame_count),
                size_px.0,
                size_px.1
            ),
            RENDER_REMEDY,
        );
        crate::check_size(&estimate, output, request.force)?;
    }

    let through_shot = scene.camera.is_some() && !request.overlays.view_camera;
    let separate_pass = request.overlays.alpha || request.overlays.shadow_pass;
    let use_plate = scene.plate.is_some() && !separate_pass && request.plate.unwrap_or(through_shot);
    let plate = match (&scene.plate, use_plate) {
        (Some(plate), true) => Some(plate_files(plate, path, range)?),
        _ => None,
    };

    let context = GpuContext::headless()?;
    let adapter = context.describe();
    let mut renderer = SceneRenderer::new(context, &scene, size_px, request.overlays);
    renderer.set_plate(plate.zip(scene.plate.as_ref().map(|p| p.opacity.clone())));
    let started = Instant::now();
    match kind {
        Output::Png => {
            let image = renderer.render_frame(&scene, range.first as f64)?;
            write_atomically(output, |w| write_png(&image, w))
                .map_err(|e| anyhow!("cannot write {}: {}", output.display(), io_reason(&e)))?;
            say!("wrote {} ({}×{}, frame {}, {adapter})", output.display(), size_px.0, size_px.1, range.first);
        }
        Output::Gif => {
            let progress = terminal_progress::frame_bar(range.frame_count(), "frames");
            write_atomically(output, |w| {
                let mut gif = GifWriter::new(w, size_px, scene.timeline.fps)?;
                for frame in range.first..=range.last {
                    let image = renderer.render_frame(&scene, frame as f64).map_err(io::Error::other)?;
                    gif.write_frame(&image)?;
                    progress.inc(1);
                }
                gif.finish().map(|_| ())
            })
            .map_err(|e| anyhow!("cannot write {}: {}", output.display(), io_reason(&e)))?;
            progress.finish_and_clear();
            report(output, range, size_px, started, &adapter, &format!("GIF at {} fps", scene.timeline.fps));
        }
        Output::Sequence => {
            render_sequence(&mut renderer, &scene, path, output, range, request.force)?;
            report(output, range, size_px, started, &adapter, "PNG sequence");
        }
    }
    Ok(())
}

/// Renders on this thread while a second thread encodes and writes the PNGs;
/// at most two finished frames wait between them, so memory stays bounded.
/// The frames are staged in a hidden directory inside `dir` and moved into
/// place together once all are written, like an OBJ sequence: an error or an
/// interrupt leaves the directory as it was, never old and new frames mixed.
/// `dir` is created when missing, but not its parents (as `drape export`).
///
/// Before anything is written the size of the sequence is estimated as the
/// first frame's PNG size times the frame count, and refused past the limit
/// or the free space on the disk unless `force`.
fn render_sequence(
    renderer: &mut SceneRenderer,
    scene: &Scene,
    path: &Path,
    dir: &Path,
    range: FrameRange,
    force: bool,
) -> Result<()> {
    let first_image = renderer.render_frame(scene, range.first as f64)?;
    let mut first_png = Vec::new();
    write_png(&first_image, &mut first_png).map_err(|e| anyhow!("cannot encode a PNG: {}", io_reason(&e)))?;
    let frame_count = range.frame_count();
    let estimate = SizeEstimate::new(
        frame_count.saturating_mul(first_png.len() as u64),
        format!(
            "the render (a PNG sequence of {} frames at {}×{}, {} each as the first frame is)",
            group_thousands(frame_count),
            first_image.width,
            first_image.height,
            readable_bytes(first_png.len() as u64)
        ),
        RENDER_REMEDY,
    );
    crate::check_size(&estimate, dir, force)?;
    let created_dir = ensure_sequence_dir(dir)?;
    let rendered = render_staged(renderer, scene, path, dir, range, first_image);
    if rendered.is_err() && created_dir {
        let _ = std::fs::remove_dir(dir);
    }
    rendered
}

fn render_staged(
    renderer: &mut SceneRenderer,
    scene: &Scene,
    path: &Path,
    dir: &Path,
    range: FrameRange,
    first_image: RgbaImage,
) -> Result<()> {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("frame").to_string();
    let mut staged =
        StagedFiles::new(dir, &stem).map_err(|e| anyhow!("cannot write into {}: {}", dir.display(), io_reason(&e)))?;
    let width = frame_number_width(range);
    let progress = terminal_progress::frame_bar(range.frame_count(), "frames");
    let (sender, receiver) = mpsc::sync_channel::<(String, RgbaImage)>(2);
    let target_dir = dir.to_path_buf();
    let writer = std::thread::spawn(move || -> Result<StagedFiles> {
        for (file_name, image) in receiver {
            staged
                .write(&file_name, |w| write_png(&image, w))
                .map_err(|e| anyhow!("cannot write {}: {}", target_dir.join(&file_name).display(), io_reason(&e)))?;
        }
        Ok(staged)
    });
    let mut rendered = Ok(());
    let mut first_image = Some(first_image);
    for frame in range.first..=range.last {
        let image = match first_image.take().map_or_else(|| renderer.render_frame(scene, frame as f64), Ok) {
            Ok(image) => image,
            Err(error) => {
                rendered = Err(anyhow!(error));
                break;
            }
        };
        let file_name = format!("{stem}_{}.png", padded_frame(frame, width));
        // A send fails only when the writer stopped on an error, which join reports.
        if sender.send((file_name, image)).is_err() {
            break;
        }
        progress.inc(1);
    }
    drop(sender);
    let written = writer.join().map_err(|_| anyhow!("the PNG writer thread panicked"))?;
    progress.finish_and_clear();
    let staged = rendered.and(written).context("rendering the sequence stopped")?;
    staged.commit().map_err(|e| anyhow!("cannot move the frames into {}: {}", dir.display(), io_reason(&e)))?;
    Ok(())
}

/// The plate's files beside the scene at `path`, refused when there are none;
/// frames of `range` without their own file are named in one warning.
fn plate_files(plate: &scene::Plate, path: &Path, range: FrameRange) -> Result<PlateFiles> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let files = PlateFiles::scan(plate, folder).map_err(|why| anyhow!("{}: {why}", path.display()))?;
    let missing = files.missing(range.first, range.last);
    if !missing.is_empty() {
        eprintln!(
            "warning: the plate {:?} has no file for frame{} {} (of {}..{}): {} the nearest file's picture",
            plate.file,
            if missing.len() == 1 { "" } else { "s" },
            frame_list(&missing),
            range.first,
            range.last,
            if missing.len() == 1 { "it shows" } else { "each shows" },
        );
    }
    Ok(files)
}

fn report(output: &Path, range: FrameRange, size_px: (u32, u32), started: Instant, adapter: &str, what: &str) {
    let count = range.frame_count();
    let secs = started.elapsed().as_secs_f64();
    say!(
        "wrote {} ({what}, frames {}..{}, {count} frame{} at {}×{}) in {secs:.1} s: {:.1} frames/s on {adapter}",
        output.display(),
        range.first,
        range.last,
        if count == 1 { "" } else { "s" },
        size_px.0,
        size_px.1,
        count as f64 / secs.max(1e-9),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_say_what_is_wrong() {
        assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        assert_eq!(parse_size("1280"), Err("`1280` is not a size: write it as WIDTHxHEIGHT, e.g. 1280x720".into()));
        assert_eq!(parse_size("0x10"), Err("`0` in `0x10` is not a side of 1 to 8192 pixels".into()));
        assert!(parse_size("99999x10").is_err());
    }
}
