//! `drape render`: pictures of a scene as a PNG, a numbered PNG sequence or an
//! animated GIF. This file turns the command line's options into a
//! [`RenderRequest`] (with the command line's own words for what is wrong)
//! and prints the result; [`drape::render_job`] renders and writes.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use anyhow::{Result, anyhow, bail};
use drape::picture::SceneOverlays;
use drape::render_job::{MAX_SIDE_PX, RenderJobError, RenderKind, RenderPlan, RenderSummary, default_size_px};
use drape::scene;

use crate::FrameRange;
use crate::terminal_progress;

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
    /// Remove an earlier sequence's frames that the new sequence does not write.
    pub replace_sequence: bool,
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
        (Some("gif"), _) => RenderKind::Gif,
        (Some("png"), false) => RenderKind::Png,
        (Some("png"), true) => bail!(
            "--frames writes a numbered PNG sequence into a directory, but {} names a PNG file: \
             give a directory, or a .gif for an animation",
            output.display()
        ),
        (None, true) => RenderKind::Sequence,
        (None, false) => {
            bail!("{} has no extension: name it .png or .gif (or give --frames for a sequence)", output.display())
        }
        (Some(other), _) => bail!("cannot render to .{other} ({}): use .png, .gif or a directory", output.display()),
    };
    // The options' own words for what the library would refuse too.
    if request.overlays.alpha && kind == RenderKind::Gif {
        bail!("--alpha writes PNGs (a GIF has no alpha channel): name a .png, or a directory with --frames");
    }
    if request.overlays.shadow_pass && kind == RenderKind::Gif {
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
    if request.replace_sequence && kind != RenderKind::Sequence {
        bail!("--replace-sequence applies to a PNG sequence (-o DIR --frames); {} is one file", output.display());
    }
    if request.shot && scene.camera.is_none() {
        bail!("--camera shot: the scene has no shot camera (`camera: (position: …, target: …)`)");
    }
    let size_px = request.size_px.unwrap_or_else(|| default_size_px(&scene, kind, request.overlays.view_camera));
    let start = scene.timeline.start;
    let range = match (request.frames, request.frame, kind) {
        (Some(range), _, _) => range,
        (None, frame, RenderKind::Png) => {
            let frame = frame.unwrap_or(start);
            FrameRange { first: frame, last: frame }
        }
        // A GIF without --frames shows the whole timeline.
        (None, _, _) => FrameRange { first: start, last: scene.timeline.end },
    };
    if kind == RenderKind::Sequence && output.exists() && !output.is_dir() {
        bail!("{} is not a directory: --frames writes a numbered sequence into a directory", output.display());
    }
    let through_shot = scene.camera.is_some() && !request.overlays.view_camera;
    let job = drape::render_job::RenderRequest {
        kind,
        output: output.to_path_buf(),
        frames: range.first..=range.last,
        size_px,
        overlays: request.overlays,
        plate: scene.plate.is_some() && request.plate.unwrap_or(through_shot),
        force: request.force,
        replace_sequence: request.replace_sequence,
    };
    let plan = RenderPlan::new(&scene, Some(path), job).map_err(with_force_hint)?;
    for warning in plan.warnings() {
        eprintln!("warning: {warning}");
    }
    let progress = match kind {
        RenderKind::Png => indicatif::ProgressBar::hidden(),
        RenderKind::Sequence | RenderKind::Gif => terminal_progress::frame_bar(range.frame_count(), "frames"),
    };
    // Ctrl+C ends the process (removing its temporaries): nothing cancels from here.
    let never = AtomicBool::new(false);
    let summary = plan.run(None, &mut |done, _| progress.set_position(done), &never).map_err(with_force_hint)?;
    progress.finish_and_clear();
    report(&summary);
    Ok(())
}

/// A refusal of the output's size says how to write it anyway, one of an
/// earlier sequence's frames how to replace them.
fn with_force_hint(error: RenderJobError) -> anyhow::Error {
    match error {
        RenderJobError::TooLarge(error) => crate::force_hint(error),
        RenderJobError::OldFrames(error) => crate::export_command::replace_hint(error),
        other => anyhow!(other),
    }
}

fn report(summary: &RenderSummary) {
    let (first, last) = (*summary.frames.start(), *summary.frames.end());
    let (width, height) = summary.size_px;
    let (output, adapter) = (summary.output.display(), &summary.adapter);
    let what = match summary.kind {
        RenderKind::Png => {
            say!("wrote {output} ({width}×{height}, frame {first}, {adapter})");
            return;
        }
        RenderKind::Gif => format!("GIF at {} fps", summary.fps),
        RenderKind::Sequence => "PNG sequence".to_owned(),
    };
    let count = summary.frame_count();
    say!(
        "wrote {output} ({what}, frames {first}..{last}, {count} frame{} at {width}×{height}) in {:.1} s: {:.1} frames/s on {adapter}",
        if count == 1 { "" } else { "s" },
        summary.elapsed.as_secs_f64(),
        summary.frames_per_sec(),
    );
    if let Some(line) = crate::export_command::removed_line(&summary.removed) {
        say!("{line}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_say_what_is_wrong() {
        assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        assert_eq!(parse_size("1280"), Err("`1280` is not a size: write it as WIDTHxHEIGHT, e.g. 1280x720".into()));
        assert_eq!(parse_size("0x10"), Err("`0` in `0x10` is not a side of 1 to 4096 pixels".into()));
        assert!(parse_size("99999x10").is_err());
        assert_eq!(parse_size("4096x4096"), Ok((4096, 4096)));
        assert_eq!(parse_size("8192x8192"), Err("`8192` in `8192x8192` is not a side of 1 to 4096 pixels".into()));
    }
}
