//! `drape export`: the cloth at one frame as OBJ, or a frame range as a PC2 or
//! MDD point cache, glTF 2.0, USD or an OBJ sequence, through
//! [`drape::export::export_animation_with`].

use std::io::{self, IsTerminal};
use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use clap::ValueEnum;
use drape::export::animation::ExportStage;
use drape::export::{
    AnimationFormat, ExportError, ExportOptions, ExportSummary, FrameSource, check_frames, export_animation_with,
    write_atomically, write_obj,
};
use drape::scene::{self, Scene};

use crate::FrameRange;

/// `--format`: what to write when the output's extension does not say.
#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Format {
    /// Wavefront OBJ: one file for a frame, a numbered sequence for --frames.
    Obj,
    /// PC2 point cache (with the base mesh as OBJ beside it).
    Pc2,
    /// MDD point cache, big-endian (with the base mesh as OBJ beside it).
    Mdd,
    /// Binary glTF 2.0 with morph-target animation.
    Glb,
    /// glTF 2.0 JSON with NAME.bin (and the texture as NAME_texture.png) beside it.
    Gltf,
    /// USD text with time-sampled points and normals.
    Usda,
}

impl From<Format> for AnimationFormat {
    fn from(format: Format) -> AnimationFormat {
        match format {
            Format::Obj => AnimationFormat::ObjSequence,
            Format::Pc2 => AnimationFormat::Pc2,
            Format::Mdd => AnimationFormat::Mdd,
            Format::Glb => AnimationFormat::Glb,
            Format::Gltf => AnimationFormat::Gltf,
            Format::Usda => AnimationFormat::Usda,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
pub enum Stage {
    /// The surface approximated from the catenary network of the key in effect.
    Approx,
    /// The rest shape of the key in effect, after relaxation.
    Relaxed,
    /// The full animation: blended rest shapes and the layer stack.
    Animated,
}

impl From<Stage> for ExportStage {
    fn from(stage: Stage) -> ExportStage {
        match stage {
            Stage::Approx => ExportStage::Approx,
            Stage::Relaxed => ExportStage::Relaxed,
            Stage::Animated => ExportStage::Animated,
        }
    }
}

pub struct ExportRequest {
    pub frame: Option<i32>,
    pub frames: Option<FrameRange>,
    pub format: Option<Format>,
    pub stage: Stage,
    pub layers: bool,
}

pub fn export(path: &Path, output: &Path, request: ExportRequest) -> Result<()> {
    let scene = scene::load(path)?;
    if !request.layers && request.stage != Stage::Animated {
        bail!("--no-layers applies to the animated stage only; the {:?} stage has no layers", request.stage);
    }
    let format = match (request.format, AnimationFormat::from_extension(output)) {
        (Some(format), _) => AnimationFormat::from(format),
        (None, Some(format)) => format,
        // A range into a directory: the OBJ sequence, as before the other formats existed.
        (None, None) if request.frames.is_some() && output.extension().is_none() => AnimationFormat::ObjSequence,
        (None, None) => match output.extension() {
            Some(other) => bail!(
                "cannot tell the format from the extension .{} of {}: use .obj, .pc2, .mdd, .glb, .gltf or .usda, \
                 or --format",
                other.to_string_lossy(),
                output.display()
            ),
            None => bail!(
                "{} has no extension: name it .obj, .pc2, .mdd, .glb, .gltf or .usda, or pass --format \
                 (--frames into a directory writes an OBJ sequence)",
                output.display()
            ),
        },
    };
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("frame").to_string();
    let options = ExportOptions { stage: request.stage.into(), layers: request.layers, sequence_name: Some(stem) };

    if format == AnimationFormat::ObjSequence && request.frames.is_none() {
        let frame = request.frame.unwrap_or(scene.timeline.start);
        return export_one_obj(&scene, frame, output, &options);
    }
    let (first, last) = match (request.frames, request.frame) {
        (Some(range), _) => (range.first, range.last),
        (None, Some(frame)) => (frame, frame),
        // An animation format without a range: the whole timeline.
        (None, None) => (scene.timeline.start, scene.timeline.end),
    };
    let started = Instant::now();
    let mut bar: Option<indicatif::ProgressBar> = None;
    let mut progress = |done: usize, total: usize| {
        let bar = bar.get_or_insert_with(|| progress_bar(total as u64));
        bar.set_position(done as u64);
        true
    };
    let summary = export_animation_with(&scene, first..=last, output, format, &options, &mut progress);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    report(&summary?, output, &describe(&scene, &options, first), started);
    Ok(())
}

fn export_one_obj(scene: &Scene, frame: i32, output: &Path, options: &ExportOptions) -> Result<()> {
    check_frames(scene, frame, frame)?;
    let mut source = FrameSource::new(scene, options.stage, options.layers);
    let mesh = source.mesh(frame);
    write_atomically(output, |w| write_obj(mesh, &scene.name, w)).map_err(|e| ExportError::write(output, e))?;
    say!(
        "wrote {} ({} vertices, {} triangles; frame {frame}, {})",
        output.display(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        describe(scene, options, frame)
    );
    Ok(())
}

fn describe(scene: &Scene, options: &ExportOptions, frame: i32) -> String {
    let key_frame = || scene.key_in_effect(f64::from(frame)).frame;
    match options.stage {
        ExportStage::Animated if options.layers => "animated".to_string(),
        ExportStage::Animated => "animated, no layers".to_string(),
        ExportStage::Approx => format!("approximated key at frame {}", key_frame()),
        ExportStage::Relaxed => format!("relaxed key at frame {}", key_frame()),
    }
}

fn report(summary: &ExportSummary, output: &Path, what: &str, started: Instant) {
    let count = summary.frame_count;
    let frames = format!(
        "frames {}..{}, {count} frame{} at {} fps",
        summary.first_frame,
        summary.last_frame,
        if count == 1 { "" } else { "s" },
        summary.fps
    );
    let secs = started.elapsed().as_secs_f64();
    let name = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    if summary.format == AnimationFormat::ObjSequence {
        let (first, last) = (summary.files.first(), summary.files.last());
        let dir = first.and_then(|f| f.parent()).unwrap_or(output);
        say!(
            "wrote {count} file{} to {} ({frames}, {what}; {} … {}) in {secs:.1} s",
            if count == 1 { "" } else { "s" },
            dir.display(),
            first.map(|f| name(f)).unwrap_or_default(),
            last.map(|f| name(f)).unwrap_or_default(),
        );
        return;
    }
    let files: Vec<String> = summary.files.iter().map(|f| f.display().to_string()).collect();
    say!(
        "wrote {} ({}, {frames}, {} vertices, {} triangles, {what}) in {secs:.1} s",
        files.join(" + "),
        summary.format.description(),
        summary.vertex_count,
        summary.triangle_count
    );
}

fn progress_bar(total: u64) -> indicatif::ProgressBar {
    if !io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    let style = indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} frames evaluated  {per_sec}  eta {eta}")
        .expect("the progress template is valid");
    bar.set_style(style);
    bar
}
